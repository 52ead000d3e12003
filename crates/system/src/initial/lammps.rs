//! A LAMMPS data file of `atom_style sphere` (as `write_data` writes it): the header's
//! atom count and box, `Atoms` rows `id type diameter density x y z [ix iy iz]` and
//! `Velocities` rows `id vx vy vz wx wy wz`. The box is periodic along every axis
//! (a data file does not say; give [box] in the config for another).

use super::{FileState, Row, file_box};
use crate::error::{Result, invalid};
use emdstar_contact::Sphere;
use std::collections::HashMap;

/// The section names of a data file (LAMMPS `read_data`), which end the one before.
const SECTIONS: [&str; 18] = [
    "Atoms",
    "Velocities",
    "Masses",
    "Ellipsoids",
    "Lines",
    "Triangles",
    "Bodies",
    "Bonds",
    "Angles",
    "Dihedrals",
    "Impropers",
    "Pair Coeffs",
    "PairIJ Coeffs",
    "Bond Coeffs",
    "Angle Coeffs",
    "Dihedral Coeffs",
    "Improper Coeffs",
    "Extras",
];

fn section_of(line: &str) -> Option<&'static str> {
    let word = line.split('#').next().unwrap_or_default().trim();
    SECTIONS.iter().copied().find(|s| *s == word)
}

fn parse<T: std::str::FromStr>(word: &str, what: &str, line: usize) -> Result<T> {
    match word.parse() {
        Ok(v) => Ok(v),
        Err(_) => invalid!("line {line}: {what} '{word}' is not a number"),
    }
}

/// The LAMMPS data file `text`.
pub(super) fn read(text: &str) -> Result<FileState> {
    let mut atoms = None;
    let mut lo = [f64::NAN; 3];
    let mut hi = [f64::NAN; 3];
    let mut sections: HashMap<&str, Vec<(usize, Vec<&str>)>> = HashMap::new();
    let mut current: Option<&str> = None;
    // The first line is a title.
    for (no, raw) in text.lines().enumerate().skip(1) {
        let no = no + 1;
        if let Some(s) = section_of(raw) {
            current = Some(s);
            sections.entry(s).or_default();
            continue;
        }
        let line = raw.split('#').next().unwrap_or_default().trim();
        if line.is_empty() {
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        match current {
            Some(s) => sections.get_mut(s).expect("started").push((no, words)),
            None => {
                // Header keywords.
                let tail = &words[words.len().min(2)..].join(" ");
                if words.len() == 2 && words[1] == "atoms" {
                    atoms = Some(parse::<usize>(words[0], "the atom count", no)?);
                } else if words.len() == 4
                    && ["xlo xhi", "ylo yhi", "zlo zhi"].contains(&tail.as_str())
                {
                    let k = usize::from(words[2].as_bytes()[0] - b'x');
                    lo[k] = parse(words[0], "a box bound", no)?;
                    hi[k] = parse(words[1], "a box bound", no)?;
                } else if words.ends_with(&["xy", "xz", "yz"]) {
                    let tilts: Vec<f64> =
                        words[..3].iter().filter_map(|w| w.parse().ok()).collect();
                    if tilts.iter().any(|&t| t != 0.0) {
                        return invalid!(
                            "line {no}: a triclinic box (tilts {tilts:?}); only orthogonal \
                             boxes are simulated here"
                        );
                    }
                }
            }
        }
    }
    let Some(n) = atoms else {
        return invalid!("the header has no 'N atoms' line: is it a LAMMPS data file?");
    };
    if lo.iter().chain(&hi).any(|c| c.is_nan()) {
        return invalid!("the header lacks one of the xlo xhi, ylo yhi, zlo zhi lines");
    }
    let Some(atom_rows) = sections.get("Atoms") else {
        return invalid!("it has no Atoms section");
    };
    if atom_rows.len() != n {
        return invalid!(
            "the Atoms section has {} rows for the header's {n} atoms",
            atom_rows.len()
        );
    }
    let mut index = HashMap::with_capacity(n);
    let mut rows = Vec::with_capacity(n);
    let mut ids = Vec::with_capacity(n);
    for (no, w) in atom_rows {
        let no = *no;
        if w.len() != 7 && w.len() != 10 {
            return invalid!(
                "line {no}: an Atoms row of atom_style sphere is 'id type diameter density x y \
                 z' with optional image flags 'ix iy iz' (7 or 10 entries); this one has {} \
                 (another atom style? write the file with atom_style sphere)",
                w.len()
            );
        }
        let id: u64 = parse(w[0], "the atom id", no)?;
        let diameter: f64 = parse(w[2], "the diameter", no)?;
        let density: f64 = parse(w[3], "the density", no)?;
        if diameter.is_nan() || diameter <= 0.0 {
            return invalid!(
                "line {no}: atom {id} has diameter {diameter}; spheres need a positive one"
            );
        }
        let mass = Sphere::from_density(0.5 * diameter, density)
            .map_err(|e| crate::SystemError::Invalid(format!("line {no}: atom {id}: {e}")))?
            .mass;
        let x = [
            parse(w[4], "x", no)?,
            parse(w[5], "y", no)?,
            parse(w[6], "z", no)?,
        ];
        let image = if w.len() == 10 {
            [
                parse(w[7], "ix", no)?,
                parse(w[8], "iy", no)?,
                parse(w[9], "iz", no)?,
            ]
        } else {
            [0; 3]
        };
        if index.insert(id, rows.len()).is_some() {
            return invalid!("line {no}: atom id {id} is given twice");
        }
        ids.push(id);
        rows.push(Row {
            type_name: w[1].to_string(),
            radius: 0.5 * diameter,
            mass: Some(mass),
            position: x,
            velocity: [0.0; 3],
            angular_velocity: [0.0; 3],
            image,
        });
    }
    for (no, w) in sections
        .get("Velocities")
        .map(Vec::as_slice)
        .unwrap_or_default()
    {
        let no = *no;
        if w.len() != 7 {
            return invalid!(
                "line {no}: a Velocities row of atom_style sphere is 'id vx vy vz wx wy wz'; \
                 this one has {} entries",
                w.len()
            );
        }
        let id: u64 = parse(w[0], "the atom id", no)?;
        let Some(&i) = index.get(&id) else {
            return invalid!("line {no}: Velocities names atom {id}, which Atoms does not hold");
        };
        let v: Vec<f64> = w[1..]
            .iter()
            .map(|s| parse::<f64>(s, "a velocity", no))
            .collect::<Result<_>>()?;
        rows[i].velocity = [v[0], v[1], v[2]];
        rows[i].angular_velocity = [v[3], v[4], v[5]];
    }
    // Particles numbered in the order of their atom ids.
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| ids[i]);
    let rows = order.into_iter().map(|i| rows[i].clone()).collect();
    let size = std::array::from_fn(|k| hi[k] - lo[k]);
    Ok(FileState {
        rows,
        sim_box: Some(file_box(lo, size, [true; 3])?),
    })
}
