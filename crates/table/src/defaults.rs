//! The shipped default tables (crate `emdstar-table-defaults`), embedded in the binary
//! so that `default` works from any working directory and from an installed program.

use crate::{Table, TableError};
use emdstar_contact::Model;
use std::sync::OnceLock;

/// The bytes of the default table of `model` (tables/linear.npz or tables/hertz.npz).
pub fn default_table_bytes(model: Model) -> &'static [u8] {
    match model {
        Model::Linear => emdstar_table_defaults::LINEAR,
        Model::Hertz => emdstar_table_defaults::HERTZ,
    }
}

/// The default table of `model`, parsed and validated once per process; every later
/// call returns the same table (no copy).
pub fn default_table(model: Model) -> Result<&'static Table, TableError> {
    static CACHE: [OnceLock<Result<Table, TableError>>; 2] = [OnceLock::new(), OnceLock::new()];
    let slot = match model {
        Model::Linear => &CACHE[0],
        Model::Hertz => &CACHE[1],
    };
    slot.get_or_init(|| Table::from_bytes(default_table_bytes(model)))
        .as_ref()
        .map_err(Clone::clone)
}
