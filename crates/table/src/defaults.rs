//! The shipped default tables of `tables/`, embedded in the binary so that `default`
//! works from any working directory and from an installed program.

use crate::{Table, TableError};
use emdstar_contact::Model;
use std::sync::OnceLock;

static LINEAR: &[u8] = include_bytes!("../../../tables/linear.npz");
static HERTZ: &[u8] = include_bytes!("../../../tables/hertz.npz");

/// The bytes of the default table of `model` (tables/linear.npz or tables/hertz.npz).
pub fn default_table_bytes(model: Model) -> &'static [u8] {
    match model {
        Model::Linear => LINEAR,
        Model::Hertz => HERTZ,
    }
}

/// The default table of `model`, parsed and validated once.
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
