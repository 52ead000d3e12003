//! Reading and writing the table file (see the crate documentation for the layout).

use crate::error::TableError;
use crate::interp::{Axis, NQ, Stretch};
use crate::npz::{Array, Data, read_npz, write_npz};
use crate::table::Table;
use emdstar_contact::{Model, Range, RectBounds};

/// The file format version this crate reads and writes.
pub const FORMAT_VERSION: i64 = 2;

/// Names of the four stored quantities of the main grid, in storage order.
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

impl Table {
    /// Serialises the table (deterministic: equal tables give equal bytes).
    pub fn to_bytes(&self) -> Vec<u8> {
        let [a, b, c] = self.axes;
        let (na, nb, nc) = (a.n, b.n, c.n);
        let axis = |ax: &Axis| Array::f64(vec![ax.n], (0..ax.n).map(|i| ax.node(i)).collect());
        let stretch: Vec<f64> = self
            .axes
            .iter()
            .flat_map(|x| [x.stretch.amount, x.stretch.knee])
            .collect();
        let g = &self.bounds;
        let mut members: Vec<(&str, Array)> = vec![
            ("format_version", Array::i64(vec![], vec![FORMAT_VERSION])),
            ("model", Array::str_scalar(self.model.name())),
            ("generator", Array::str_scalar(&self.info.generator)),
            ("spec", Array::str_scalar(&self.info.spec)),
            (
                "quantities",
                Array::str_list(QUANTITIES.iter().map(|s| s.to_string()).collect()),
            ),
            ("box_names", Array::str_list(self.info.box_names.clone())),
            (
                "box_ranges",
                Array::f64(
                    vec![self.info.box_ranges.len(), 2],
                    self.info.box_ranges.iter().flatten().copied().collect(),
                ),
            ),
            (
                "bounds",
                Array::f64(
                    vec![3, 2],
                    vec![g.g.min, g.g.max, g.m.min, g.m.max, g.c.min, g.c.max],
                ),
            ),
            ("axis_a", axis(&a)),
            ("axis_b", axis(&b)),
            ("axis_c", axis(&c)),
            (
                "order",
                Array::i64(vec![3], self.axes.iter().map(|x| x.order as i64).collect()),
            ),
            ("axis_stretch", Array::f64(vec![3, 2], stretch)),
            (
                "values",
                Array::f64(vec![na, nb, nc, NQ], self.main.clone()),
            ),
            (
                "elastic",
                Array::f64(vec![na, nb, NQ], self.elastic.clone()),
            ),
            (
                "central",
                Array::f64(vec![nb, nc, NQ], self.central.clone()),
            ),
            (
                "central_elastic",
                Array::f64(vec![nb, NQ], self.central_elastic.clone()),
            ),
        ];
        let npys: Vec<Vec<u8>> = members.iter().map(|(_, a)| a.to_npy()).collect();
        let refs: Vec<&[u8]> = npys.iter().map(Vec::as_slice).collect();
        members.push(("checksum", Array::u64_scalar(fnv1a64(&refs))));
        write_npz(&members)
    }

    /// Reads a table file from disk.
    pub fn open(path: impl AsRef<std::path::Path>) -> Result<Self, TableError> {
        let path = path.as_ref();
        let bytes =
            std::fs::read(path).map_err(|e| TableError::Io(format!("{}: {e}", path.display())))?;
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
        let floats = |name: &str, shape: &[usize]| -> Result<Vec<f64>, TableError> {
            let a = get(name)?;
            match &a.data {
                Data::F64(v) if a.shape == shape => Ok(v.clone()),
                _ => Err(TableError::Corrupt(format!(
                    "{name} should be a float64 array of shape {shape:?}, found shape {:?}",
                    a.shape
                ))),
            }
        };
        let model: Model = text("model")?
            .parse()
            .map_err(|_| TableError::Corrupt("unknown model name".into()))?;
        let bounds_v = floats("bounds", &[3, 2])?;
        let bounds = RectBounds {
            model,
            g: Range::new(bounds_v[0], bounds_v[1]),
            m: Range::new(bounds_v[2], bounds_v[3]),
            c: Range::new(bounds_v[4], bounds_v[5]),
        };
        let order = match &get("order")?.data {
            Data::I64(v) if v.len() == 3 && v.iter().all(|&o| o > 0) => v.clone(),
            _ => {
                return Err(TableError::Corrupt(
                    "order must hold three positive integers".into(),
                ));
            }
        };
        let stretch_v = floats("axis_stretch", &[3, 2])?;
        let mut axes = [Axis::uniform(0.0, 1.0, 2, 2); 3];
        for (k, (name, range)) in ["axis_a", "axis_b", "axis_c"]
            .into_iter()
            .zip(bounds.axes())
            .enumerate()
        {
            let a = get(name)?;
            let nodes = match &a.data {
                Data::F64(v) if a.shape.len() == 1 && v.len() >= 2 => v,
                _ => {
                    return Err(TableError::Corrupt(format!(
                        "{name} is not a 1-d float array"
                    )));
                }
            };
            let stretch = Stretch {
                amount: stretch_v[2 * k],
                knee: stretch_v[2 * k + 1],
            };
            let ax = Axis::new(
                nodes[0],
                nodes[nodes.len() - 1],
                nodes.len(),
                order[k] as usize,
                stretch,
            );
            ax.check()
                .map_err(|why| TableError::Corrupt(format!("{name}: {why}")))?;
            let tol = 1e-9 * range.width().abs().max(1.0);
            if (ax.min - range.min).abs() > tol || (ax.max - range.max).abs() > tol {
                return Err(TableError::Corrupt(format!(
                    "{name} spans [{}, {}] but the bounds give [{}, {}]",
                    ax.min, ax.max, range.min, range.max
                )));
            }
            // Node positions come from ln_1p and Newton steps: allow the last digits to
            // differ between platforms.
            let tol = 1e-12 * (ax.max - ax.min);
            if nodes
                .iter()
                .enumerate()
                .any(|(i, &x)| (x - ax.node(i)).abs() > tol || x.is_nan())
            {
                return Err(TableError::Corrupt(format!(
                    "{name} does not hold the nodes of its grid (uniform in w of axis_stretch)"
                )));
            }
            axes[k] = ax;
        }
        let [na, nb, nc] = axes.map(|a| a.n);
        let main = floats("values", &[na, nb, nc, NQ])?;
        let elastic = floats("elastic", &[na, nb, NQ])?;
        let central = floats("central", &[nb, nc, NQ])?;
        let central_elastic = floats("central_elastic", &[nb, NQ])?;
        // NaN marks central-limit nodes without a limit (see `Table`); nothing else may
        // be non-finite.
        for (name, v, nan_ok) in [
            ("values", &main, false),
            ("elastic", &elastic, false),
            ("central", &central, true),
            ("central_elastic", &central_elastic, true),
        ] {
            if let Some(i) = v
                .iter()
                .position(|x| !(x.is_finite() || (nan_ok && x.is_nan())))
            {
                return Err(TableError::Corrupt(format!(
                    "{name} holds a non-finite value at flat index {i}"
                )));
            }
        }
        let box_names = match &get("box_names")?.data {
            Data::Str(v) => v.clone(),
            _ => return Err(TableError::Corrupt("box_names is not a string list".into())),
        };
        let ranges = floats("box_ranges", &[box_names.len(), 2])?;
        let info = crate::TableInfo {
            generator: text("generator")?,
            spec: text("spec")?,
            box_names,
            box_ranges: ranges.chunks_exact(2).map(|r| [r[0], r[1]]).collect(),
        };
        Ok(Self {
            model,
            bounds,
            axes,
            main,
            elastic,
            central,
            central_elastic,
            info,
        })
    }
}
