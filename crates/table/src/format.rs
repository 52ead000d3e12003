//! Reading and writing the table file (see the crate documentation for the layout).

use crate::error::TableError;
use crate::npz::{Array, Data, read_npz};
use crate::piece::{LEAF, PieceParts};
use crate::poly::{NQ, Terms};
use crate::table::{PIECES, Table, TableParts};
use emdstar_contact::{Model, Range, RectBounds};

/// The file format version this crate reads and writes.
pub const FORMAT_VERSION: i64 = 4;

/// Names of the four stored quantities, in storage order.
pub const QUANTITIES: [&str; NQ] = ["ln(1-eps_r)", "ln(-eps_rdot)", "ln(eps_phi)", "ln(eps_t)"];

/// Descriptive metadata carried by a table file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TableInfo {
    /// Name and version of the program that generated the table.
    pub generator: String,
    /// The TOML spec the table was generated from.
    pub spec: String,
    /// Names of the physical parameters of the box (e.g. "stiffness").
    pub box_names: Vec<String>,
    /// Their [min, max] ranges, in SI units.
    pub box_ranges: Vec<[f64; 2]>,
    /// The generator's goal for the error of each stored log (= relative error of each
    /// MoR component) in every patch.
    pub tolerance: f64,
    /// The largest error estimate of any patch, per stored quantity (from the decay of
    /// its Chebyshev coefficients); `emdstar table check` measures the actual error.
    pub estimated_error: [f64; NQ],
}

/// 64-bit FNV-1a hash, the content checksum of a table file.
pub fn fnv1a64(chunks: &[&[u8]]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for c in chunks {
        for &b in *c {
            h ^= b as u64;
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

/// The `.npy` members of a piece, named `{piece}_…`.
#[cfg(feature = "write")]
fn piece_members(name: &str, p: &PieceParts, terms: &Terms, quantum: f64) -> Vec<(String, Array)> {
    let bits = crate::pack::pack(&p.cheb, terms, quantum);
    vec![
        (
            format!("{name}_cells"),
            Array::i64(vec![3], p.cells.iter().map(|&c| c as i64).collect()),
        ),
        (
            format!("{name}_roots"),
            Array::i64(
                vec![p.roots.len()],
                p.roots.iter().map(|&r| r as i64).collect(),
            ),
        ),
        (
            format!("{name}_tree"),
            Array::i64(
                vec![p.tree.len(), 2],
                p.tree.iter().flatten().copied().collect(),
            ),
        ),
        (
            format!("{name}_split"),
            Array::f64(vec![p.split.len()], p.split.clone()),
        ),
        (
            format!("{name}_patches"),
            Array::i64(vec![], vec![(p.cheb.len() / terms.len()) as i64]),
        ),
        (
            format!("{name}_coef_bits"),
            Array::u64(vec![bits.len()], bits),
        ),
    ]
}

impl Table {
    /// Serialises the table (deterministic: equal tables give equal bytes).
    #[cfg(feature = "write")]
    pub fn to_bytes(&self) -> Vec<u8> {
        let g = &self.bounds;
        let info = &self.info;
        let mut members: Vec<(String, Array)> = vec![
            (
                "format_version".into(),
                Array::i64(vec![], vec![FORMAT_VERSION]),
            ),
            ("model".into(), Array::str_scalar(self.model.name())),
            ("generator".into(), Array::str_scalar(&info.generator)),
            ("spec".into(), Array::str_scalar(&info.spec)),
            (
                "quantities".into(),
                Array::str_list(QUANTITIES.iter().map(|s| s.to_string()).collect()),
            ),
            ("box_names".into(), Array::str_list(info.box_names.clone())),
            (
                "box_ranges".into(),
                Array::f64(
                    vec![info.box_ranges.len(), 2],
                    info.box_ranges.iter().flatten().copied().collect(),
                ),
            ),
            (
                "bounds".into(),
                Array::f64(
                    vec![3, 2],
                    vec![g.g.min, g.g.max, g.m.min, g.m.max, g.c.min, g.c.max],
                ),
            ),
            ("b_knee".into(), Array::f64(vec![], vec![self.b_map.knee])),
            (
                "degree".into(),
                Array::i64(vec![], vec![self.degree as i64]),
            ),
            ("tolerance".into(), Array::f64(vec![], vec![info.tolerance])),
            (
                "quantum".into(),
                Array::f64(vec![], vec![crate::pack::quantum(info.tolerance)]),
            ),
            (
                "estimated_error".into(),
                Array::f64(vec![NQ], info.estimated_error.to_vec()),
            ),
        ];
        for ((name, _), piece) in PIECES.iter().zip(self.pieces()) {
            members.extend(piece_members(
                name,
                piece.parts(),
                piece.terms(),
                crate::pack::quantum(info.tolerance),
            ));
        }
        let npys: Vec<Vec<u8>> = members.iter().map(|(_, a)| a.to_npy()).collect();
        let refs: Vec<&[u8]> = npys.iter().map(Vec::as_slice).collect();
        members.push(("checksum".into(), Array::u64_scalar(fnv1a64(&refs))));
        crate::npz::write_npz(&members)
    }

    /// The largest table file read (the default tables take about 2 MB).
    pub const MAX_FILE_BYTES: u64 = 4 << 30;

    /// Reads a table file from disk: only a regular file (a device or a pipe could be
    /// endless or block), of at most [`Table::MAX_FILE_BYTES`], and no more than the
    /// size it had when opened.
    pub fn open(path: impl AsRef<std::path::Path>) -> Result<Self, TableError> {
        use std::io::Read;
        let path = path.as_ref();
        let io = |e: std::io::Error| TableError::Io(format!("{}: {e}", path.display()));
        let irregular = || {
            TableError::Io(format!(
                "{} is not a regular file (a directory, a device or a pipe); a table is read \
                 only from a regular file",
                path.display()
            ))
        };
        // Looked at before it is opened too: opening a pipe blocks until someone writes.
        if !std::fs::metadata(path).map_err(io)?.is_file() {
            return Err(irregular());
        }
        let file = std::fs::File::open(path).map_err(io)?;
        let meta = file.metadata().map_err(io)?;
        if !meta.is_file() {
            return Err(irregular());
        }
        if meta.len() > Self::MAX_FILE_BYTES {
            return Err(TableError::Io(format!(
                "{} has {} bytes, more than a table file can have ({}); is it a table?",
                path.display(),
                meta.len(),
                Self::MAX_FILE_BYTES
            )));
        }
        let mut bytes = Vec::with_capacity(meta.len() as usize);
        file.take(meta.len()).read_to_end(&mut bytes).map_err(io)?;
        Self::from_bytes(&bytes)
    }

    /// Parses and validates a table file.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, TableError> {
        let members = read_npz(bytes)?;
        let get = |name: &str| -> Result<&Array, TableError> {
            members
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, a)| a)
                .ok_or_else(|| TableError::Corrupt(format!("member {name} is missing")))
        };
        let version = match &get("format_version")?.data {
            Data::I64(v) if v.len() == 1 => v[0],
            _ => {
                return Err(TableError::Corrupt(
                    "format_version is not one integer".into(),
                ));
            }
        };
        if version != FORMAT_VERSION {
            return Err(TableError::UnknownVersion {
                found: version,
                supported: FORMAT_VERSION,
            });
        }
        // Content checksum over every member before `checksum`, in file order.
        let stored = match members.last() {
            Some((
                n,
                Array {
                    data: Data::U64(v), ..
                },
            )) if n == "checksum" && v.len() == 1 => v[0],
            _ => return Err(TableError::Corrupt("the checksum member is missing".into())),
        };
        let npys: Vec<Vec<u8>> = members[..members.len() - 1]
            .iter()
            .map(|(_, a)| a.to_npy())
            .collect();
        let refs: Vec<&[u8]> = npys.iter().map(Vec::as_slice).collect();
        let computed = fnv1a64(&refs);
        if computed != stored {
            return Err(TableError::ChecksumMismatch(format!(
                "content checksum stored {stored:016x}, computed {computed:016x}"
            )));
        }
        let text = |name: &str| -> Result<String, TableError> {
            match &get(name)?.data {
                Data::Str(v) if v.len() == 1 => Ok(v[0].clone()),
                _ => Err(TableError::Corrupt(format!("{name} is not one string"))),
            }
        };
        let floats = |name: &str, shape: Option<&[usize]>| -> Result<Vec<f64>, TableError> {
            let a = get(name)?;
            match &a.data {
                Data::F64(v) if shape.is_none_or(|s| a.shape == s) => Ok(v.clone()),
                _ => Err(TableError::Corrupt(format!(
                    "{name} should be a float64 array{}, found shape {:?}",
                    shape
                        .map(|s| format!(" of shape {s:?}"))
                        .unwrap_or_default(),
                    a.shape
                ))),
            }
        };
        let ints = |name: &str| -> Result<(Vec<i64>, Vec<usize>), TableError> {
            let a = get(name)?;
            match &a.data {
                Data::I64(v) => Ok((v.clone(), a.shape.clone())),
                _ => Err(TableError::Corrupt(format!("{name} is not an int64 array"))),
            }
        };
        let model: Model = text("model")?
            .parse()
            .map_err(|_| TableError::Corrupt("unknown model name".into()))?;
        let b = floats("bounds", Some(&[3, 2]))?;
        let bounds = RectBounds {
            model,
            g: Range::new(b[0], b[1]),
            m: Range::new(b[2], b[3]),
            c: Range::new(b[4], b[5]),
        };
        if let Some(r) = bounds
            .axes()
            .iter()
            .find(|r| !(r.min.is_finite() && r.max.is_finite() && r.min < r.max))
        {
            return Err(TableError::Corrupt(format!(
                "the bounds give an empty or infinite axis [{}, {}]",
                r.min, r.max
            )));
        }
        let degree = match ints("degree")? {
            (v, s) if s.is_empty() && (1..=16).contains(&v[0]) => v[0] as usize,
            _ => {
                return Err(TableError::Corrupt(
                    "degree must be one integer in 1..=16".into(),
                ));
            }
        };
        let tolerance = floats("tolerance", Some(&[]))?[0];
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(TableError::Corrupt(format!(
                "the tolerance {tolerance} is not finite and > 0"
            )));
        }
        let quantum = crate::pack::quantum(tolerance);
        if floats("quantum", Some(&[]))?[0] != quantum {
            return Err(TableError::Corrupt(format!(
                "quantum is not {quantum}, the power of two of the tolerance {tolerance}"
            )));
        }
        let mut pieces = Vec::with_capacity(4);
        for (name, active) in PIECES {
            let corrupt = |what: &str| TableError::Corrupt(format!("{name}_{what}"));
            let (cells, s) = ints(&format!("{name}_cells"))?;
            if s != [3] || cells.iter().any(|&c| !(1..=1 << 16).contains(&c)) {
                return Err(corrupt("cells must hold three counts in 1..=65536"));
            }
            let (roots, _) = ints(&format!("{name}_roots"))?;
            let (tree, s) = ints(&format!("{name}_tree"))?;
            if s.len() != 2 || s[1] != 2 {
                return Err(corrupt("tree must have shape (n, 2)"));
            }
            let split = floats(&format!("{name}_split"), Some(&[s[0]]))?;
            let max = std::array::from_fn(|k| if active[k] { degree } else { 0 });
            let terms = Terms::new(degree, max);
            let patches = match ints(&format!("{name}_patches"))? {
                (v, s) if s.is_empty() && (0..=1 << 28).contains(&v[0]) => v[0] as usize,
                _ => return Err(corrupt("patches must be one count in 0..=2^28")),
            };
            let bits = match &get(&format!("{name}_coef_bits"))?.data {
                Data::U64(v) => v,
                _ => return Err(corrupt("coef_bits is not a uint64 array")),
            };
            if tree.chunks_exact(2).filter(|n| n[0] == LEAF).count() != patches {
                return Err(corrupt("patches differs from the number of leaves of tree"));
            }
            let cheb = crate::pack::unpack(bits, &terms, patches, quantum)
                .map_err(|e| corrupt(&format!("coef_bits: {e}")))?;
            if roots.iter().any(|&r| r < 0) {
                return Err(corrupt("roots must not be negative"));
            }
            pieces.push(PieceParts {
                cells: std::array::from_fn(|k| cells[k] as usize),
                roots: roots.iter().map(|&r| r as usize).collect(),
                tree: tree.chunks_exact(2).map(|c| [c[0], c[1]]).collect(),
                split,
                cheb,
            });
        }
        let box_names = match &get("box_names")?.data {
            Data::Str(v) => v.clone(),
            _ => return Err(TableError::Corrupt("box_names is not a string list".into())),
        };
        let ranges = floats("box_ranges", Some(&[box_names.len(), 2]))?;
        let estimated = floats("estimated_error", Some(&[NQ]))?;
        let info = TableInfo {
            generator: text("generator")?,
            spec: text("spec")?,
            box_names,
            box_ranges: ranges.chunks_exact(2).map(|r| [r[0], r[1]]).collect(),
            tolerance,
            estimated_error: [estimated[0], estimated[1], estimated[2], estimated[3]],
        };
        let mut it = pieces.into_iter();
        let mut next = || it.next().expect("four pieces");
        Table::from_parts(TableParts {
            bounds,
            b_map: crate::BMap {
                b_min: bounds.axes()[1].min,
                knee: floats("b_knee", Some(&[]))?[0],
            },
            degree,
            main: next(),
            elastic: next(),
            central: next(),
            central_elastic: next(),
            info,
        })
    }
}
