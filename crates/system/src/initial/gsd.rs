//! A frame of a GSD file (file layers 1 and 2; HOOMD schema): what this project's
//! [`crate::gsd::GsdWriter`] writes and what HOOMD-blue writes. A chunk a frame lacks
//! is taken from frame 0, else the schema's default (HOOMD's rule).

use super::{FileState, Row, file_box, frame_index};
use crate::error::{Result, SystemError, invalid};
use std::collections::HashMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::Path;

struct Entry {
    frame: u64,
    rows: u64,
    location: u64,
    cols: u32,
    kind: u8,
}

struct Gsd {
    file: File,
    len: u64,
    path: String,
    /// (frame, name) → index entry.
    chunks: HashMap<(u64, String), Entry>,
    frames: u64,
}

fn io(path: &str) -> impl Fn(std::io::Error) -> SystemError + '_ {
    move |io| SystemError::Io {
        path: path.to_string(),
        io,
    }
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

impl Gsd {
    fn open(path: &Path) -> Result<Self> {
        let (file, len) = crate::files::open_input(path, "initial state")?;
        let mut g = Self {
            file,
            len,
            path: path.display().to_string(),
            chunks: HashMap::new(),
            frames: 0,
        };
        if len < crate::gsd::HEADER_BYTES {
            return invalid!("it is shorter than a GSD header: is it a GSD file?");
        }
        let header = g.bytes(0, crate::gsd::HEADER_BYTES)?;
        if u64_at(&header, 0) != crate::gsd::MAGIC {
            return invalid!("it is not a GSD file (no GSD magic number at its start)");
        }
        let (index_at, index_entries) = (u64_at(&header, 8), u64_at(&header, 16));
        let (names_at, name_blocks) = (u64_at(&header, 24), u64_at(&header, 32));
        let major = u32::from_le_bytes(header[44..48].try_into().expect("4 bytes")) >> 16;
        let names = g.bytes(names_at, name_blocks.saturating_mul(64))?;
        let names: Vec<String> = if major >= 2 {
            // Names one after the other, each ended by a 0; an empty one ends the list.
            names
                .split(|&b| b == 0)
                .take_while(|n| !n.is_empty())
                .map(|n| String::from_utf8_lossy(n).into_owned())
                .collect()
        } else {
            // Layer 1: 64 bytes per name.
            names
                .chunks(64)
                .map(|n| n.split(|&b| b == 0).next().unwrap_or_default())
                .take_while(|n| !n.is_empty())
                .map(|n| String::from_utf8_lossy(n).into_owned())
                .collect()
        };
        let index = g.bytes(
            index_at,
            index_entries.saturating_mul(crate::gsd::ENTRY_BYTES),
        )?;
        for e in index.chunks_exact(crate::gsd::ENTRY_BYTES as usize) {
            let location = u64_at(e, 16);
            if location == 0 {
                break;
            }
            let id = usize::from(u16::from_le_bytes([e[28], e[29]]));
            let Some(name) = names.get(id) else {
                return invalid!("an index entry names chunk {id}, beyond the name list");
            };
            let entry = Entry {
                frame: u64_at(e, 0),
                rows: u64_at(e, 8),
                location,
                cols: u32::from_le_bytes(e[24..28].try_into().expect("4 bytes")),
                kind: e[30],
            };
            g.frames = g.frames.max(entry.frame + 1);
            g.chunks.insert((entry.frame, name.clone()), entry);
        }
        Ok(g)
    }

    fn bytes(&mut self, at: u64, len: u64) -> Result<Vec<u8>> {
        if at.checked_add(len).is_none_or(|end| end > self.len) {
            return invalid!("it ends before the data its index points to (cut short?)");
        }
        let mut b = vec![0; len as usize];
        let err = io(&self.path);
        self.file.seek(SeekFrom::Start(at)).map_err(&err)?;
        self.file.read_exact(&mut b).map_err(&err)?;
        Ok(b)
    }

    /// The chunk `name` of `frame` (else of frame 0) as f64s with its row count and
    /// column count, if either frame has it.
    fn numbers(&mut self, frame: u64, name: &str) -> Result<Option<(Vec<f64>, u32)>> {
        let Some(e) = self
            .chunks
            .get(&(frame, name.to_string()))
            .or_else(|| self.chunks.get(&(0, name.to_string())))
        else {
            return Ok(None);
        };
        let (location, rows, cols, kind) = (e.location, e.rows, e.cols, e.kind);
        let size: u64 = match kind {
            1 | 5 => 1,
            2 | 6 => 2,
            3 | 7 | 9 => 4,
            4 | 8 | 10 => 8,
            _ => return invalid!("chunk {name} has an unknown element type {kind}"),
        };
        let count = rows.saturating_mul(u64::from(cols));
        let b = self.bytes(location, count.saturating_mul(size))?;
        let s = size as usize;
        let values = b
            .chunks_exact(s)
            .map(|c| match kind {
                1 => f64::from(c[0]),
                2 => f64::from(u16::from_le_bytes([c[0], c[1]])),
                3 => f64::from(u32::from_le_bytes(c.try_into().expect("4"))),
                4 => u64::from_le_bytes(c.try_into().expect("8")) as f64,
                5 => f64::from(c[0] as i8),
                6 => f64::from(i16::from_le_bytes([c[0], c[1]])),
                7 => f64::from(i32::from_le_bytes(c.try_into().expect("4"))),
                8 => i64::from_le_bytes(c.try_into().expect("8")) as f64,
                9 => f64::from(f32::from_le_bytes(c.try_into().expect("4"))),
                _ => f64::from_le_bytes(c.try_into().expect("8")),
            })
            .collect();
        Ok(Some((values, cols)))
    }

    /// Per-particle chunk `name` of `cols` columns for `n` particles, or `default`.
    fn column(
        &mut self,
        frame: u64,
        name: &str,
        n: usize,
        cols: u32,
        default: f64,
    ) -> Result<Vec<f64>> {
        match self.numbers(frame, name)? {
            None => Ok(vec![default; n * cols as usize]),
            Some((v, c)) if c == cols && v.len() == n * cols as usize => Ok(v),
            Some((v, c)) => invalid!(
                "chunk {name} holds {} rows of {c} where {n} rows of {cols} were expected",
                v.len() / (c.max(1) as usize)
            ),
        }
    }

    /// The type names (`particles/types`, default "A").
    fn types(&mut self, frame: u64) -> Result<Vec<String>> {
        let key = |f: u64| (f, "particles/types".to_string());
        let Some(e) = self
            .chunks
            .get(&key(frame))
            .or_else(|| self.chunks.get(&key(0)))
        else {
            return Ok(vec!["A".into()]);
        };
        let (location, rows, cols) = (e.location, e.rows, e.cols as u64);
        let b = self.bytes(location, rows.saturating_mul(cols))?;
        Ok(b.chunks(cols.max(1) as usize)
            .map(|n| {
                String::from_utf8_lossy(n.split(|&c| c == 0).next().unwrap_or_default())
                    .into_owned()
            })
            .collect())
    }
}

/// Frame `frame` (negative from the end) of the GSD file at `path`.
pub(super) fn read(path: &Path, frame: i64) -> Result<FileState> {
    let mut g = Gsd::open(path)?;
    let f = frame_index(frame, g.frames as usize)? as u64;
    let n = match g.numbers(f, "particles/N")? {
        Some((v, _)) if v.len() == 1 => v[0] as usize,
        _ => 0,
    };
    let size = match g.numbers(f, "configuration/box")? {
        Some((b, _)) if b.len() == 6 => {
            if b[3..].iter().any(|&t| t != 0.0) {
                return invalid!(
                    "frame {f} has a triclinic box (tilts {:?}); only orthogonal boxes are \
                     simulated here",
                    &b[3..]
                );
            }
            [b[0], b[1], b[2]]
        }
        _ => [1.0; 3],
    };
    let centre = match g.numbers(f, "log/box_centre")? {
        Some((c, _)) if c.len() == 3 => [c[0], c[1], c[2]],
        _ => [0.0; 3],
    };
    let position = match g.numbers(f, "particles/position")? {
        Some((v, 3)) if v.len() == 3 * n => v,
        Some(_) => return invalid!("chunk particles/position does not hold {n} rows of 3"),
        None => return invalid!("frame {f} has no particles/position chunk (missing column)"),
    };
    let velocity = g.column(f, "particles/velocity", n, 3, 0.0)?;
    let diameter = g.column(f, "particles/diameter", n, 1, 1.0)?;
    let image = g.column(f, "particles/image", n, 3, 0.0)?;
    let spin = g.column(f, "log/particles/angular_velocity", n, 3, 0.0)?;
    let has_mass = g.chunks.contains_key(&(f, "particles/mass".into()))
        || g.chunks.contains_key(&(0, "particles/mass".into()));
    let mass = g.column(f, "particles/mass", n, 1, 1.0)?;
    let typeid = g.column(f, "particles/typeid", n, 1, 0.0)?;
    let types = g.types(f)?;
    let v3 = |v: &[f64], i: usize| [v[3 * i], v[3 * i + 1], v[3 * i + 2]];
    let mut rows = Vec::with_capacity(n);
    for i in 0..n {
        let t = typeid[i] as usize;
        let Some(type_name) = types.get(t) else {
            return invalid!(
                "particle {i} has type id {t}, beyond the {} names of particles/types",
                types.len()
            );
        };
        let x = v3(&position, i);
        rows.push(Row {
            type_name: type_name.clone(),
            radius: 0.5 * diameter[i],
            mass: has_mass.then_some(mass[i]),
            position: std::array::from_fn(|k| x[k] + centre[k]),
            velocity: v3(&velocity, i),
            angular_velocity: v3(&spin, i),
            image: v3(&image, i).map(|c| c as i32),
        });
    }
    let lo = std::array::from_fn(|k| centre[k] - 0.5 * size[k]);
    Ok(FileState {
        rows,
        sim_box: Some(file_box(lo, size, [true; 3])?),
    })
}
