//! Binary trajectories in GSD (General Simulation Data, the HOOMD-blue format), which
//! OVITO reads directly with positions, velocities, radii, masses and species mapped.
//!
//! Layout (GSD file layer 2.0, little-endian): a 256-byte header; the name list (names
//! separated by 0 bytes, padded to a multiple of 64 bytes); an index of 32-byte entries
//! (frame, N, location, M, name id, type, flags), sorted by frame and then name id, its
//! end marked by the first entry at location 0; and the data chunks, each an N × M
//! array in row-major order. Data is written before the index entries that point to it,
//! so a run cut short leaves a readable file with the frames completed. When the index
//! is full, a twice as large one is written at the end of the file and the header
//! pointed to it. A resumed run ([`GsdWriter::resume`]) reads the index back and cuts
//! the frames written after its checkpoint.
//!
//! Per frame (HOOMD schema 1.4): `configuration/step` (the frame number),
//! `configuration/dimensions` (3), `configuration/box` [Lx, Ly, Lz, 0, 0, 0],
//! `particles/N`, `particles/types` (the species numbers as names), and per particle
//! `particles/typeid`, `position`, `velocity`, `diameter` and `mass` in single
//! precision and `particles/image` (the periodic image flags, int32), rows in the order
//! of the particles' config number (`Particles::id`), plus `log/time` (s, double),
//! `log/box_centre` (m, double) and `log/particles/angular_velocity` (rad/s, single
//! precision; HOOMD keeps angular momenta of oriented bodies instead).
//!
//! HOOMD boxes are centred at the origin, so positions are written relative to the box
//! centre (`log/box_centre`). In free space the box is the smallest one about the first
//! frame's centre that holds every sphere of the frame.

use crate::error::{Result, SystemError};
use crate::files::OutputFile;
use crate::geometry::{SimBox, bounding_box};
use crate::state::Particles;
use crate::tail::{Cut, KeepUntil};
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

pub(crate) const MAGIC: u64 = 0x65DF_65DF_65DF_65DF;
pub(crate) const HEADER_BYTES: u64 = 256;
pub(crate) const ENTRY_BYTES: u64 = 32;
/// Index entries allocated at first (9 chunks per frame: about 110 frames).
const FIRST_INDEX_ENTRIES: u64 = 1024;

/// GSD element types (gsd.h, `enum gsd_type`).
#[derive(Clone, Copy)]
#[repr(u8)]
enum Type {
    U8 = 1,
    U32 = 3,
    U64 = 4,
    I8 = 5,
    I32 = 7,
    F32 = 9,
    F64 = 10,
}

/// The chunk names, in name-id order (alphabetical, so each frame's index is sorted).
pub(crate) const NAMES: [&str; 14] = [
    "configuration/box",
    "configuration/dimensions",
    "configuration/step",
    "log/box_centre",
    "log/particles/angular_velocity",
    "log/time",
    "particles/N",
    "particles/diameter",
    "particles/image",
    "particles/mass",
    "particles/position",
    "particles/typeid",
    "particles/types",
    "particles/velocity",
];

pub(crate) fn name_id(name: &str) -> u16 {
    NAMES
        .iter()
        .position(|n| *n == name)
        .expect("a chunk name of the list") as u16
}

/// One data chunk of a frame before it is written.
struct Chunk {
    id: u16,
    rows: u64,
    cols: u32,
    kind: Type,
    bytes: Vec<u8>,
}

/// Writes frames in GSD; see the module documentation for what a frame holds.
pub struct GsdWriter {
    file: File,
    path: String,
    /// Where the next data chunk goes (the end of the file).
    end: u64,
    index_location: u64,
    index_capacity: u64,
    /// Every index entry written so far, in file order.
    entries: Vec<[u8; 32]>,
    frames: u64,
    /// Size of the name list in 64-byte blocks.
    namelist_blocks: u64,
    /// The centre of free-space boxes, fixed at the first frame.
    free_centre: Option<[f64; 3]>,
}

impl GsdWriter {
    /// Claims the file at `path`, empties it and writes the header, name list and an
    /// empty index.
    pub fn create(path: &Path) -> Result<Self> {
        Self::start(OutputFile::claim(path)?)
    }

    /// [`GsdWriter::create`] on the claimed file `out`.
    pub fn start(out: OutputFile) -> Result<Self> {
        let name = out.path().display().to_string();
        let file = out.into_file();
        file.set_len(0).map_err(io_error(&name))?;
        let names = name_list();
        let namelist_location = HEADER_BYTES;
        let index_location = namelist_location + names.len() as u64;
        let mut w = Self {
            file,
            path: name,
            end: index_location + FIRST_INDEX_ENTRIES * ENTRY_BYTES,
            index_location,
            index_capacity: FIRST_INDEX_ENTRIES,
            entries: Vec::new(),
            frames: 0,
            namelist_blocks: names.len() as u64 / 64,
            free_centre: None,
        };
        let header = w.header();
        w.write_at(0, &header)?;
        w.write_at(namelist_location, &names)?;
        w.write_at(
            index_location,
            &vec![0; (FIRST_INDEX_ENTRIES * ENTRY_BYTES) as usize],
        )?;
        Ok(w)
    }

    /// Opens the GSD trajectory of a run resumed from a checkpoint at time `t`, to add
    /// frames at its end, after cutting off what the run wrote after `t`: whole frames,
    /// and a last frame left unfinished. The file must be one this writer wrote for
    /// `particles` spheres of `species` kinds; a missing file is created.
    pub fn resume(path: &Path, t: f64, particles: usize, species: usize) -> Result<(Self, Cut)> {
        let keep = KeepUntil { t, at_t: true };
        Self::resume_in(OutputFile::claim(path)?, keep, particles, species)
    }

    /// [`GsdWriter::resume`] on the claimed file `out`, keeping the frames `keep`
    /// keeps; an empty file is started afresh.
    pub fn resume_in(
        out: OutputFile,
        keep: KeepUntil,
        particles: usize,
        species: usize,
    ) -> Result<(Self, Cut)> {
        let name = out.path().display().to_string();
        let err = io_error(&name);
        if out.file().metadata().map_err(&err)?.len() == 0 {
            return Ok((Self::start(out)?, Cut::default()));
        }
        let mut file = out.into_file();
        let names = name_list();
        let kept =
            crate::gsd_tail::keep_until(&mut file, &names, keep, particles as u64, species as u64)
                .map_err(&err)?;
        let mut w = Self {
            file,
            path: name.clone(),
            end: kept.end,
            index_location: kept.index_location,
            index_capacity: kept.index_capacity,
            entries: kept.entries,
            frames: kept.frames,
            namelist_blocks: names.len() as u64 / 64,
            free_centre: kept.first_centre,
        };
        // The index ends at the kept entries; the file at the kept data and the index.
        let from = w.entries.len() as u64;
        let zeros = vec![0u8; ((w.index_capacity - from) * ENTRY_BYTES) as usize];
        w.write_at(w.index_location + from * ENTRY_BYTES, &zeros)?;
        w.file.set_len(w.end).map_err(&err)?;
        crate::writers::sync_data(&w.file).map_err(&err)?;
        let cut = Cut {
            records: kept.cut_frames,
            partial_bytes: kept.partial_bytes,
        };
        Ok((w, cut))
    }

    /// Bytes one frame of `particles` spheres of `species` kinds adds to the file.
    pub fn frame_bytes(particles: usize, species: usize) -> u64 {
        let n = particles as u64;
        // 3 + 3 + 3 floats, diameter, mass, typeid, 3 image flags: 60 bytes per
        // particle; type names;
        // box, dimensions, step, N, time, centre; and one index entry per chunk.
        60 * n
            + species as u64 * type_name_width(species) as u64
            + 24
            + 1
            + 8
            + 4
            + 8
            + 24
            + NAMES.len() as u64 * ENTRY_BYTES
    }

    /// Frames written so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Appends one frame at time `t` (s); `species` is the number of species.
    pub fn write_frame(
        &mut self,
        t: f64,
        particles: &Particles,
        species: usize,
        sim_box: Option<&SimBox>,
    ) -> Result<()> {
        let (centre, size) = match sim_box {
            Some(b) => (std::array::from_fn(|k| b.lo[k] + 0.5 * b.size[k]), b.size),
            None => self.free_box(particles),
        };
        let mut order: Vec<usize> = (0..particles.len()).collect();
        order.sort_by_key(|&i| particles.id[i]);
        let n = order.len() as u64;
        let vectors = |field: &[[f64; 3]], shift: [f64; 3]| {
            let mut b = Vec::with_capacity(order.len() * 12);
            for &i in &order {
                for k in 0..3 {
                    b.extend_from_slice(&((field[i][k] - shift[k]) as f32).to_le_bytes());
                }
            }
            b
        };
        let scalars = |f: &dyn Fn(usize) -> f32| -> Vec<u8> {
            order.iter().flat_map(|&i| f(i).to_le_bytes()).collect()
        };
        let width = type_name_width(species);
        let mut types = vec![0u8; species * width];
        for s in 0..species {
            let label = s.to_string();
            types[s * width..s * width + label.len()].copy_from_slice(label.as_bytes());
        }
        let f64s = |v: &[f64]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
        let box6 = [size[0], size[1], size[2], 0.0, 0.0, 0.0];
        let chunks = [
            rows(
                "configuration/box",
                6,
                1,
                Type::F32,
                box6.iter()
                    .flat_map(|x| (*x as f32).to_le_bytes())
                    .collect(),
            ),
            chunk("configuration/dimensions", Type::U8, vec![3]),
            chunk(
                "configuration/step",
                Type::U64,
                self.frames.to_le_bytes().to_vec(),
            ),
            rows("log/box_centre", 3, 1, Type::F64, f64s(&centre)),
            rows(
                "log/particles/angular_velocity",
                n,
                3,
                Type::F32,
                vectors(&particles.angular_velocity, [0.0; 3]),
            ),
            chunk("log/time", Type::F64, t.to_le_bytes().to_vec()),
            chunk("particles/N", Type::U32, (n as u32).to_le_bytes().to_vec()),
            rows(
                "particles/diameter",
                n,
                1,
                Type::F32,
                scalars(&|i| (2.0 * particles.radius[i]) as f32),
            ),
            rows(
                "particles/image",
                n,
                3,
                Type::I32,
                order
                    .iter()
                    .flat_map(|&i| particles.image[i])
                    .flat_map(i32::to_le_bytes)
                    .collect(),
            ),
            rows(
                "particles/mass",
                n,
                1,
                Type::F32,
                scalars(&|i| particles.mass[i] as f32),
            ),
            rows(
                "particles/position",
                n,
                3,
                Type::F32,
                vectors(&particles.position, centre),
            ),
            rows(
                "particles/typeid",
                n,
                1,
                Type::U32,
                order
                    .iter()
                    .flat_map(|&i| particles.species[i].to_le_bytes())
                    .collect(),
            ),
            rows(
                "particles/types",
                species as u64,
                width as u32,
                Type::I8,
                types,
            ),
            rows(
                "particles/velocity",
                n,
                3,
                Type::F32,
                vectors(&particles.velocity, [0.0; 3]),
            ),
        ];
        // Data first, then the index entries that point to it.
        let mut data = Vec::new();
        let mut new_entries = Vec::new();
        for c in chunks.iter().filter(|c| c.rows > 0) {
            new_entries.push(self.entry(c, self.end + data.len() as u64));
            data.extend_from_slice(&c.bytes);
        }
        self.write_at(self.end, &data)?;
        self.end += data.len() as u64;
        let first = self.entries.len() as u64;
        self.entries.extend(new_entries);
        if self.entries.len() as u64 >= self.index_capacity {
            // Keep one entry at location 0 to end the index: move it, twice as large.
            self.index_capacity = 2 * (self.entries.len() as u64).max(self.index_capacity);
            self.index_location = self.end;
            let mut block = self.entries.concat();
            block.resize((self.index_capacity * ENTRY_BYTES) as usize, 0);
            self.write_at(self.index_location, &block)?;
            self.end += block.len() as u64;
            crate::writers::sync_data(&self.file).map_err(io_error(&self.path))?;
            let header = self.header();
            self.write_at(0, &header)?;
        } else {
            let block = self.entries[first as usize..].concat();
            self.write_at(self.index_location + first * ENTRY_BYTES, &block)?;
        }
        self.frames += 1;
        Ok(())
    }

    /// Writes what the operating system still buffers to the disk.
    pub fn flush(&mut self) -> Result<()> {
        crate::writers::sync_data(&self.file).map_err(io_error(&self.path))
    }

    fn free_box(&mut self, particles: &Particles) -> ([f64; 3], [f64; 3]) {
        let r = particles.radius.iter().copied().fold(0.0, f64::max);
        let (lo, extent) = bounding_box(&particles.position);
        let centre = *self.free_centre.get_or_insert_with(|| {
            std::array::from_fn(|k| {
                let c = lo[k] + 0.5 * extent[k];
                if c.is_finite() { c } else { 0.0 }
            })
        });
        let mut half = [r; 3];
        for x in &particles.position {
            for k in 0..3 {
                half[k] = half[k].max((x[k] - centre[k]).abs() + r);
            }
        }
        (centre, half.map(|h| 2.0 * h.max(f64::MIN_POSITIVE)))
    }

    /// The header; the name list follows it.
    fn header(&self) -> Vec<u8> {
        let mut h = Vec::with_capacity(HEADER_BYTES as usize);
        for v in [
            MAGIC,
            self.index_location,
            self.index_capacity,
            HEADER_BYTES,
            self.namelist_blocks,
        ] {
            h.extend_from_slice(&v.to_le_bytes());
        }
        h.extend_from_slice(&((1u32 << 16) | 4).to_le_bytes()); // schema hoomd 1.4
        h.extend_from_slice(&(2u32 << 16).to_le_bytes()); // file layer 2.0
        for text in [concat!("emdstar ", env!("CARGO_PKG_VERSION")), "hoomd"] {
            let mut field = [0u8; 64];
            field[..text.len()].copy_from_slice(text.as_bytes());
            h.extend_from_slice(&field);
        }
        h.resize(HEADER_BYTES as usize, 0);
        h
    }

    fn entry(&self, c: &Chunk, location: u64) -> [u8; 32] {
        let mut e = [0u8; 32];
        e[0..8].copy_from_slice(&self.frames.to_le_bytes());
        e[8..16].copy_from_slice(&c.rows.to_le_bytes());
        e[16..24].copy_from_slice(&(location as i64).to_le_bytes());
        e[24..28].copy_from_slice(&c.cols.to_le_bytes());
        e[28..30].copy_from_slice(&c.id.to_le_bytes());
        e[30] = c.kind as u8;
        e
    }

    fn write_at(&mut self, at: u64, bytes: &[u8]) -> Result<()> {
        let err = io_error(&self.path);
        self.file.seek(SeekFrom::Start(at)).map_err(&err)?;
        self.file.write_all(bytes).map_err(&err)
    }
}

/// The name list: the names, each ended by a 0, one more 0, padded to 64-byte blocks.
fn name_list() -> Vec<u8> {
    let mut names = Vec::new();
    for n in NAMES {
        names.extend_from_slice(n.as_bytes());
        names.push(0);
    }
    names.push(0);
    names.resize(names.len().div_ceil(64) * 64, 0);
    names
}

/// Bytes per species name: the longest number plus a terminating 0.
fn type_name_width(species: usize) -> usize {
    species.saturating_sub(1).to_string().len() + 1
}

/// A chunk of one value.
fn chunk(name: &str, kind: Type, bytes: Vec<u8>) -> Chunk {
    rows(name, 1, 1, kind, bytes)
}

fn rows(name: &str, rows: u64, cols: u32, kind: Type, bytes: Vec<u8>) -> Chunk {
    Chunk {
        id: name_id(name),
        rows,
        cols,
        kind,
        bytes,
    }
}

fn io_error(path: &str) -> impl Fn(std::io::Error) -> SystemError + '_ {
    move |io| SystemError::Io {
        path: path.to_string(),
        io,
    }
}
