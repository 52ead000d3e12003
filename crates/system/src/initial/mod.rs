//! Initial states from files: `[initial]` reads a frame of a GSD file (this project's
//! or HOOMD-blue's), of an extended XYZ file (this project's or OVITO's) or a LAMMPS
//! data file (`atom_style sphere`), instead of `[[particles]]` or `[gas]`.
//!
//! ```toml
//! [initial]
//! file = "packing.gsd"             # relative to the config file's directory
//! format = "gsd"                   # or "xyz", "lammps" (default: from the extension;
//!                                  # .data, .lmp and .lammps are LAMMPS data files)
//! frame = -1                       # GSD and XYZ: 0 the first, -1 the last (default)
//! types = { 1 = "glass", 2 = "steel" } # the material of each type in the file
//!                                  # (required with several materials)
//! ```
//!
//! Each reader gives rows (type, radius, mass if the file has it, position, velocity,
//! spin, image flags) and the file's box; [`crate::Config::build`] checks them as it
//! checks `[[particles]]` entries.

mod gsd;
mod lammps;
mod xyz;

use crate::error::{Result, SystemError, invalid};
use crate::geometry::SimBox;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// `[initial]`: the initial state read from a file.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialConfig {
    /// The file, relative to the config file's directory.
    pub file: String,
    /// "gsd", "xyz" or "lammps" (default: from the extension).
    pub format: Option<String>,
    /// The frame of a GSD or XYZ file: 0 the first, negative from the end (default -1,
    /// the last).
    pub frame: Option<i64>,
    /// The material of each particle type of the file, by type name (GSD
    /// `particles/types`, the XYZ species column, the LAMMPS type number).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub types: BTreeMap<String, String>,
}

/// The formats read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InitialFormat {
    Gsd,
    Xyz,
    Lammps,
}

/// One particle as a file gives it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Row {
    pub type_name: String,
    pub radius: f64,
    /// The file's mass, if it has one (else the material's density gives it).
    pub mass: Option<f64>,
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    pub angular_velocity: [f64; 3],
    pub image: [i32; 3],
}

/// What a reader gives: the rows (in particle order) and the file's box, if it has one.
pub(crate) struct FileState {
    pub rows: Vec<Row>,
    pub sim_box: Option<SimBox>,
}

impl InitialConfig {
    /// The material of the particle `what` of type `type_name`: `types` maps it, else
    /// the material of that name, else with one material and no `types` that one.
    pub(crate) fn material_of(
        &self,
        table: &crate::MaterialTable,
        what: &str,
        type_name: &str,
    ) -> Result<u32> {
        let names = crate::material_config::names(table);
        let Some(name) = self.types.get(type_name) else {
            if self.types.is_empty() && table.materials.len() == 1 {
                return Ok(0);
            }
            // A type named after a material (as an OVITO file may name them).
            if let Some(i) = table.materials.iter().position(|m| m.name == type_name) {
                return Ok(i as u32);
            }
            let known: Vec<String> = self.types.keys().map(|k| format!("\"{k}\"")).collect();
            return invalid!(
                "{what} is of type \"{type_name}\", which initial.types does not map to a \
                 material (it maps {}); add it, e.g. initial.types = {{ \"{type_name}\" = \
                 \"{}\" }} (the materials are {names})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                },
                table.materials[0].name
            );
        };
        match table.materials.iter().position(|m| &m.name == name) {
            Some(i) => Ok(i as u32),
            None => invalid!(
                "initial.types maps type \"{type_name}\" to \"{name}\", which is no material \
                 of this config; the materials are {names}"
            ),
        }
    }
}

/// The largest text file read (16 GiB).
const MAX_TEXT_BYTES: u64 = 1 << 34;

impl InitialConfig {
    /// The file's path: relative to `dir` (the config's directory), if given.
    pub fn path(&self, dir: Option<&Path>) -> PathBuf {
        let file = Path::new(&self.file);
        match dir {
            Some(d) if file.is_relative() => d.join(file),
            _ => file.to_path_buf(),
        }
    }

    /// The format: `format`, else the file's extension.
    pub fn format(&self) -> Result<InitialFormat> {
        if let Some(f) = &self.format {
            return match f.to_ascii_lowercase().as_str() {
                "gsd" => Ok(InitialFormat::Gsd),
                "xyz" | "extxyz" => Ok(InitialFormat::Xyz),
                "lammps" | "lammps-data" | "data" => Ok(InitialFormat::Lammps),
                _ => invalid!(
                    "initial.format = \"{f}\" is no format read here; give \"gsd\", \"xyz\" \
                     or \"lammps\" (a LAMMPS data file)"
                ),
            };
        }
        let ext = Path::new(&self.file)
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("gsd") => Ok(InitialFormat::Gsd),
            Some("xyz" | "extxyz") => Ok(InitialFormat::Xyz),
            Some("data" | "lmp" | "lammps") => Ok(InitialFormat::Lammps),
            _ => invalid!(
                "initial.file = \"{}\": its extension names no format; add initial.format = \
                 \"gsd\", \"xyz\" or \"lammps\"",
                self.file
            ),
        }
    }

    /// Reads the file (relative to `dir`).
    pub(crate) fn read(&self, dir: Option<&Path>) -> Result<FileState> {
        let format = self.format()?;
        let path = self.path(dir);
        if self.frame.is_some() && format == InitialFormat::Lammps {
            return invalid!(
                "initial.frame is given, but a LAMMPS data file holds one state; drop \
                 initial.frame"
            );
        }
        let frame = self.frame.unwrap_or(-1);
        let state = match format {
            InitialFormat::Gsd => gsd::read(&path, frame),
            InitialFormat::Xyz => {
                let text = text(&path)?;
                xyz::read(&text, frame)
            }
            InitialFormat::Lammps => lammps::read(&text(&path)?),
        };
        state.map_err(|e| match e {
            SystemError::Invalid(m) => SystemError::Invalid(format!("{}: {m}", path.display())),
            other => other,
        })
    }
}

fn text(path: &Path) -> Result<String> {
    let bytes = crate::files::read_input(path, "initial state", MAX_TEXT_BYTES)?;
    String::from_utf8(bytes).map_err(|_| {
        SystemError::Invalid(format!(
            "{}: an XYZ or LAMMPS data file is text; this file is not (a GSD file? then \
             set initial.format = \"gsd\")",
            path.display()
        ))
    })
}

/// Index of frame `frame` (negative from the end) of `count`, or an error naming the
/// range.
pub(crate) fn frame_index(frame: i64, count: usize) -> Result<usize> {
    let n = count as i64;
    let index = if frame < 0 { n + frame } else { frame };
    if count == 0 {
        return invalid!("the file holds no frame");
    }
    if !(0..n).contains(&index) {
        return invalid!(
            "initial.frame = {frame} is out of range: the file holds {count} frames (0 to {}, \
             or -{count} to -1 from the end)",
            n - 1
        );
    }
    Ok(index as usize)
}

/// An orthogonal box from `lo`, `size` and `periodic`, or an error naming where it was
/// read.
pub(crate) fn file_box(lo: [f64; 3], size: [f64; 3], periodic: [bool; 3]) -> Result<SimBox> {
    for k in 0..3 {
        if !(size[k].is_finite() && size[k] > 0.0 && lo[k].is_finite()) {
            return invalid!(
                "the file's box has lower corner {lo:?} and size {size:?}: each size must be \
                 positive and finite (or give [box] in the config)"
            );
        }
    }
    Ok(SimBox { lo, size, periodic })
}
