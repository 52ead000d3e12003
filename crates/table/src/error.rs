//! The one error type of the table reader.

use emdstar_contact::{ContactError, Model};
use std::fmt;

/// Why a table could not be read or could not answer a lookup.
///
/// Each message says what was wrong and how to fix it.
#[derive(Debug, Clone, PartialEq)]
pub enum TableError {
    /// The file could not be read.
    Io(String),
    /// The file is not an `.npz` table at all.
    NotATable(String),
    /// The file ends early.
    Truncated(String),
    /// The file is a readable archive but its content is inconsistent.
    Corrupt(String),
    /// A stored checksum differs from the data.
    ChecksumMismatch(String),
    /// The format version is not one this reader understands.
    UnknownVersion { found: i64, supported: i64 },
    /// The table was built for another force model.
    WrongModel { table: Model, requested: Model },
    /// The point lies outside the table's rectangle.
    OutOfBox {
        axis: &'static str,
        value: f64,
        min: f64,
        max: f64,
    },
    /// The point lies in a limit region that the table does not cover (near-central
    /// impacts whose c_φ → 0 limit does not exist there).
    NotTabulated(String),
    /// The scaled or physical input itself is invalid.
    Input(String),
    /// A caller-supplied exact-solve fallback failed.
    Fallback(String),
}

impl fmt::Display for TableError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Io(why) => write!(f, "cannot read the table file: {why}"),
            Self::NotATable(why) => write!(
                f,
                "not an emdstar MoR table: {why}; build one with `emdstar table build SPEC`"
            ),
            Self::Truncated(what) => write!(
                f,
                "the table file is truncated: {what} is missing or cut short (an interrupted \
                 copy or download?); copy the file again or regenerate it with `emdstar table \
                 build SPEC`"
            ),
            Self::Corrupt(why) => write!(
                f,
                "corrupt table data: {why}; regenerate it with `emdstar table build SPEC`"
            ),
            Self::ChecksumMismatch(why) => write!(
                f,
                "checksum mismatch, the table file was altered or damaged: {why}; regenerate it"
            ),
            Self::UnknownVersion { found, supported } => write!(
                f,
                "unknown table format version {found} (this reader supports version {supported}); \
                 use a matching emdstar release or rebuild the table"
            ),
            Self::WrongModel { table, requested } => write!(
                f,
                "wrong model: the table is for the {table} model but the {requested} model was \
                 requested; load a {requested} table"
            ),
            Self::OutOfBox {
                axis,
                value,
                min,
                max,
            } => write!(
                f,
                "point outside the table's box: {axis} = {value} is not in [{min}, {max}]; \
                 use a table built for a larger box (see tables/README.md) or an exact-solve fallback"
            ),
            Self::NotTabulated(why) => write!(
                f,
                "not tabulated: {why}; use an exact-solve fallback for such impacts"
            ),
            Self::Input(why) => write!(f, "invalid lookup input: {why}"),
            Self::Fallback(why) => write!(f, "the exact-solve fallback failed: {why}"),
        }
    }
}

impl std::error::Error for TableError {}

impl From<ContactError> for TableError {
    fn from(e: ContactError) -> Self {
        Self::Input(e.to_string())
    }
}
