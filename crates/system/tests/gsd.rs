//! The GSD writer against a reader written here from the GSD file-layer specification
//! (version 2: header, name list, index, data chunks) and the HOOMD schema, independent
//! of the writer's code.

use emdstar_system::gsd::GsdWriter;
use emdstar_system::{Particles, SimBox, Species};
use std::collections::BTreeMap;

/// One decoded chunk: its shape, type id and raw bytes.
#[derive(Debug)]
struct Chunk {
    n: u64,
    m: u32,
    kind: u8,
    bytes: Vec<u8>,
}

/// Frames by number, each a map from chunk name to chunk.
struct GsdFile {
    application: String,
    schema: String,
    schema_version: u32,
    gsd_version: u32,
    frames: Vec<BTreeMap<String, Chunk>>,
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().unwrap())
}

fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

fn text(b: &[u8]) -> String {
    let end = b.iter().position(|&c| c == 0).unwrap_or(b.len());
    String::from_utf8(b[..end].to_vec()).unwrap()
}

/// Size in bytes of a GSD element type (gsd.h: 1-4 unsigned 8-64 bit, 5-8 signed,
/// 9 float, 10 double).
fn type_size(kind: u8) -> usize {
    match kind {
        1 | 5 => 1,
        2 | 6 => 2,
        3 | 7 | 9 => 4,
        4 | 8 | 10 => 8,
        other => panic!("unknown GSD type {other}"),
    }
}

fn read(path: &std::path::Path) -> GsdFile {
    let b = std::fs::read(path).unwrap();
    assert!(b.len() >= 256, "shorter than a header");
    assert_eq!(u64_at(&b, 0), 0x65DF_65DF_65DF_65DF, "magic");
    let (index_at, index_entries) = (u64_at(&b, 8) as usize, u64_at(&b, 16) as usize);
    let (names_at, name_blocks) = (u64_at(&b, 24) as usize, u64_at(&b, 32) as usize);
    let names: Vec<String> = b[names_at..names_at + 64 * name_blocks]
        .split(|&c| c == 0)
        .map(|s| String::from_utf8(s.to_vec()).unwrap())
        .take_while(|s| !s.is_empty())
        .collect();
    let mut frames: Vec<BTreeMap<String, Chunk>> = Vec::new();
    let mut last = (0u64, 0u16);
    for k in 0..index_entries {
        let e = &b[index_at + 32 * k..index_at + 32 * (k + 1)];
        let location = i64::from_le_bytes(e[16..24].try_into().unwrap());
        if location == 0 {
            break;
        }
        let (frame, n, m) = (u64_at(e, 0), u64_at(e, 8), u32_at(e, 24));
        let id = u16::from_le_bytes(e[28..30].try_into().unwrap());
        let kind = e[30];
        assert!(
            k == 0 || (frame, id) > last,
            "index not sorted by frame, then id"
        );
        last = (frame, id);
        let len = n as usize * m as usize * type_size(kind);
        let at = location as usize;
        assert!(at + len <= b.len(), "chunk past the end of the file");
        while frames.len() <= frame as usize {
            frames.push(BTreeMap::new());
        }
        let chunk = Chunk {
            n,
            m,
            kind,
            bytes: b[at..at + len].to_vec(),
        };
        frames[frame as usize].insert(names[id as usize].clone(), chunk);
    }
    GsdFile {
        application: text(&b[48..112]),
        schema: text(&b[112..176]),
        schema_version: u32_at(&b, 40),
        gsd_version: u32_at(&b, 44),
        frames,
    }
}

impl Chunk {
    fn f32s(&self) -> Vec<f64> {
        assert_eq!(self.kind, 9);
        self.bytes
            .chunks(4)
            .map(|c| f32::from_le_bytes(c.try_into().unwrap()) as f64)
            .collect()
    }
    fn f64s(&self) -> Vec<f64> {
        assert_eq!(self.kind, 10);
        self.bytes
            .chunks(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }
    fn u32s(&self) -> Vec<u32> {
        assert_eq!(self.kind, 3);
        self.bytes
            .chunks(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    }
}

const SPECIES: [Species; 2] = [Species::new(0.1, 4.5), Species::new(0.05, 0.6)];

/// `n` particles of both species, stored out of config order (as engines re-sort them).
fn particles(n: usize, t: f64) -> Particles {
    let mut p = Particles::default();
    for i in 0..n {
        let s = (i % 3 == 0) as u32;
        let x = [
            -1.0 + 0.37 * i as f64 + t,
            2.0 + 0.11 * (i * i % 7) as f64,
            0.5 - 0.05 * i as f64,
        ];
        p.push(&SPECIES, s, x, [1.0 + i as f64, -0.5 * t, 0.25]);
        p.image[i] = [i as i32 - 3, 2 * i as i32, -((i % 2) as i32)];
    }
    p.image.reverse();
    p.position.reverse();
    p.velocity.reverse();
    p.species.reverse();
    p.radius.reverse();
    p.mass.reverse();
    p.id.reverse();
    p
}

/// Asserts that `frame` holds `p` at time `t`, in config order, relative to `centre`.
fn check_frame(frame: &BTreeMap<String, Chunk>, p: &Particles, t: f64, centre: [f64; 3]) {
    let n = p.len();
    assert_eq!(frame["particles/N"].u32s(), vec![n as u32]);
    assert_eq!(frame["configuration/dimensions"].bytes, vec![3]);
    assert_eq!(frame["log/time"].f64s(), vec![t]);
    assert_eq!(frame["log/box_centre"].f64s(), centre.to_vec());
    let types = &frame["particles/types"];
    assert_eq!(types.n, 2);
    let names: Vec<String> = types.bytes.chunks(types.m as usize).map(text).collect();
    assert_eq!(names, ["0", "1"]);
    let pos = frame["particles/position"].f32s();
    let vel = frame["particles/velocity"].f32s();
    let diameter = frame["particles/diameter"].f32s();
    let mass = frame["particles/mass"].f32s();
    let typeid = frame["particles/typeid"].u32s();
    assert_eq!(
        (frame["particles/position"].n, frame["particles/position"].m),
        (n as u64, 3)
    );
    for i in 0..n {
        let row = p.id.iter().position(|&id| id as usize == i).unwrap();
        for k in 0..3 {
            let x = p.position[row][k] - centre[k];
            assert!(
                (pos[3 * i + k] - x).abs() <= 1e-6 * x.abs().max(1.0),
                "x of {i}"
            );
            let v = p.velocity[row][k];
            assert!(
                (vel[3 * i + k] - v).abs() <= 1e-6 * v.abs().max(1.0),
                "v of {i}"
            );
        }
        assert_eq!(diameter[i], (2.0 * p.radius[row]) as f32 as f64);
        assert_eq!(mass[i], p.mass[row] as f32 as f64);
        assert_eq!(typeid[i], p.species[row]);
        let image = &frame["particles/image"];
        assert_eq!((image.n, image.m, image.kind), (n as u64, 3, 7));
        for k in 0..3 {
            let at = 4 * (3 * i + k);
            let flag = i32::from_le_bytes(image.bytes[at..at + 4].try_into().unwrap());
            assert_eq!(flag, p.image[row][k], "image of {i}");
        }
    }
}

#[test]
fn periodic_frames_read_back_through_index_growth() {
    let dir = std::env::temp_dir().join(format!("emdstar-gsd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("periodic.gsd");
    let b = SimBox {
        lo: [-2.0, 1.0, -5.0],
        size: [10.0, 4.0, 12.0],
        periodic: [true, true, false],
    };
    let centre = [3.0, 3.0, 1.0];
    let mut w = GsdWriter::create(&path).unwrap();
    // 14 chunks a frame: 300 frames outgrow the first index (1024 entries) twice.
    let frames = 300;
    let mut sizes = Vec::new();
    for f in 0..frames {
        let t = 0.01 * f as f64;
        w.write_frame(t, &particles(10, t), 2, Some(&b)).unwrap();
        sizes.push(std::fs::metadata(&path).unwrap().len());
        if f == 2 {
            // A run cut short here leaves three readable frames.
            assert_eq!(read(&path).frames.len(), 3);
        }
    }
    w.flush().unwrap();
    assert_eq!(w.frames(), frames);
    let file = read(&path);
    assert_eq!(file.schema, "hoomd");
    assert_eq!(file.schema_version, (1 << 16) | 4);
    assert_eq!(file.gsd_version, 2 << 16);
    assert!(
        file.application.starts_with("emdstar"),
        "{}",
        file.application
    );
    assert_eq!(file.frames.len(), frames as usize);
    for (f, frame) in file.frames.iter().enumerate() {
        let t = 0.01 * f as f64;
        check_frame(frame, &particles(10, t), t, centre);
        assert_eq!(
            frame["configuration/box"].f32s(),
            [10.0, 4.0, 12.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(u64_at(&frame["configuration/step"].bytes, 0), f as u64);
    }
    // Between index moves a frame adds its data; its index entries fill the room
    // already allocated. GsdWriter::frame_bytes counts both.
    let data = sizes[4] - sizes[3];
    assert_eq!(data + 14 * 32, GsdWriter::frame_bytes(10, 2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn free_space_box_holds_every_sphere_about_a_fixed_centre() {
    let dir = std::env::temp_dir().join(format!("emdstar-gsd-free-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("free.gsd");
    let mut w = GsdWriter::create(&path).unwrap();
    let first = particles(7, 0.0);
    w.write_frame(0.0, &first, 2, None).unwrap();
    w.write_frame(2.0, &particles(7, 2.0), 2, None).unwrap();
    let file = read(&path);
    let centre = file.frames[0]["log/box_centre"].f64s();
    assert_eq!(file.frames[1]["log/box_centre"].f64s(), centre);
    for (frame, t) in file.frames.iter().zip([0.0, 2.0]) {
        let p = particles(7, t);
        let c: [f64; 3] = centre.clone().try_into().unwrap();
        check_frame(frame, &p, t, c);
        let size = frame["configuration/box"].f32s();
        for i in 0..p.len() {
            for k in 0..3 {
                let reach = (p.position[i][k] - c[k]).abs() + p.radius[i];
                assert!(
                    reach <= 0.5 * size[k] * (1.0 + 1e-6),
                    "sphere {i} outside the box"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run killed after its checkpoint and resumed: the file comes back to the bytes it
/// held at the checkpoint (before the index first grows), whatever was added after it,
/// and goes on from there; across index growth the frames read back in order.
#[test]
fn a_resumed_file_is_cut_back_to_its_checkpoint() {
    let dir = std::env::temp_dir().join(format!("emdstar-gsd-resume-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("run.gsd");
    let b = SimBox {
        lo: [-2.0, 1.0, -5.0],
        size: [10.0, 4.0, 12.0],
        periodic: [true, true, true],
    };
    let centre = [3.0, 3.0, 1.0];
    // (frames written, time of the checkpoint, frames before it, bytes of the frame
    // after the last to leave unfinished): 300 frames outgrow the first index twice.
    for (written, t_ckpt, kept, unfinished) in [
        (4, 1.5, 2, 0),
        (4, 1.5, 2, 500),
        (4, -1.0, 0, 100),
        (300, 100.5, 101, 0),
        (300, 2.9, 3, 333),
    ] {
        let mut w = GsdWriter::create(&path).unwrap();
        let mut at_checkpoint = std::fs::read(&path).unwrap();
        for f in 0..written {
            let t = f as f64;
            w.write_frame(t, &particles(10, t), 2, Some(&b)).unwrap();
            if f + 1 == kept {
                at_checkpoint = std::fs::read(&path).unwrap();
            }
        }
        // An unfinished frame: its data (part of it), no index entries.
        w.write_frame(written as f64, &particles(10, 1e3), 2, Some(&b))
            .unwrap();
        drop(w);
        let full = std::fs::read(&path).unwrap();
        let before = full.len() - GsdWriter::frame_bytes(10, 2) as usize + 14 * 32;
        let mut bytes = full[..before].to_vec();
        bytes.extend(vec![7u8; unfinished]);
        // Take the unfinished frame's index entries out again.
        let (index_at, entries) = (u64_at(&bytes, 8) as usize, 14 * written);
        bytes[index_at + 32 * entries..index_at + 32 * (entries + 14)].fill(0);
        std::fs::write(&path, &bytes).unwrap();

        let (mut w, cut) = GsdWriter::resume(&path, t_ckpt, 10, 2).unwrap();
        assert_eq!(
            (cut.records, cut.partial_bytes),
            ((written - kept) as u64, unfinished as u64),
            "{written} frames, checkpoint at {t_ckpt}"
        );
        if written < 80 {
            assert!(std::fs::read(&path).unwrap() == at_checkpoint, "{t_ckpt}");
        }
        w.write_frame(500.0, &particles(10, 500.0), 2, Some(&b))
            .unwrap();
        let file = read(&path);
        assert_eq!(file.frames.len(), kept + 1, "{t_ckpt}");
        for (f, frame) in file.frames.iter().enumerate() {
            let t = if f == kept { 500.0 } else { f as f64 };
            check_frame(frame, &particles(10, t), t, centre);
            assert_eq!(u64_at(&frame["configuration/step"].bytes, 0), f as u64);
        }
    }
    // Not a trajectory of this run: refused with what to do.
    let err = GsdWriter::resume(&path, 1.0, 11, 2)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("11 of 2") && err.contains("--trajectory"),
        "{err}"
    );
    std::fs::write(&path, vec![1u8; 4000]).unwrap();
    let err = GsdWriter::resume(&path, 1.0, 10, 2)
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("not a GSD trajectory written by emdstar"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
