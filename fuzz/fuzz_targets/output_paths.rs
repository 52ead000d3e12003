//! Output paths through a run's preparation (`emdstar_engines::run::Run::prepare`): the
//! trajectory, the log, the checkpoint and the checkpoint resumed from each drawn from
//! paths that are new, the config, a table, each other, a directory, a device, a pipe, a
//! symbolic or hard link to the config, "none", in a missing directory. A preparation
//! either refuses with an error, or its outputs are regular files or new paths, none is
//! an input or another output (the checkpoint may be the one resumed from), and it
//! changes no input; it never panics.
#![no_main]

#[allow(dead_code)] // each target uses part of it
mod common;

use emdstar_engines::EngineKind;
use emdstar_engines::run::{Run, RunFiles};
use emdstar_system::{CheckpointFile, Config, FileIdentity};
use libfuzzer_sys::fuzz_target;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

const CONFIG: &str = "t_end = 0.01
[material]
model = \"linear\"
stiffness = 1e4
damping = 0.05
density = 2500.0
[gas]
count = 8
radius = 0.01
arrangement = \"lattice\"
packing_fraction = 0.01
rms_speed = 1.0
seed = 3
";

/// The scratch directory with its fixed files: the config, a table (any regular file
/// read as an input), a checkpoint of the config's run, a directory, a pipe and links.
fn dir() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("emdstar-fuzz-paths-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("a_directory")).unwrap();
        std::fs::write(dir.join("gas.toml"), CONFIG).unwrap();
        std::fs::write(dir.join("table.npz"), b"a table").unwrap();
        std::os::unix::fs::symlink(dir.join("gas.toml"), dir.join("symlink.toml")).unwrap();
        std::fs::hard_link(dir.join("gas.toml"), dir.join("hardlink.toml")).unwrap();
        use std::os::unix::ffi::OsStrExt;
        let fifo = std::ffi::CString::new(dir.join("fifo").as_os_str().as_bytes()).unwrap();
        // SAFETY: a NUL-terminated path.
        assert_eq!(unsafe { libc_mkfifo(fifo.as_ptr(), 0o600) }, 0);
        let config = Config::from_toml(CONFIG).unwrap();
        let engine = common::build(EngineKind::Md, &config, config.build().unwrap()).unwrap();
        let files = RunFiles {
            trajectory: None,
            log: None,
            checkpoint: Some(dir.join("start.ckpt")),
            stop_checkpoint: dir.join("start.ckpt"),
        };
        let mut run = Run::prepare(engine, &config, &files, &[], None, Some(1e-4)).unwrap();
        run.start().unwrap();
        run.drive(&mut ()).unwrap();
        dir
    })
}

unsafe extern "C" {
    #[link_name = "mkfifo"]
    fn libc_mkfifo(path: *const std::ffi::c_char, mode: u32) -> i32;
}

/// The candidate paths a byte picks from.
const NAMES: [&str; 16] = [
    "out.xyz",
    "out.gsd",
    "out.log",
    "out.ckpt",
    "gas.toml",
    "table.npz",
    "start.ckpt",
    "symlink.toml",
    "hardlink.toml",
    "a_directory",
    "fifo",
    "/dev/null",
    "/dev/full",
    "no/such/dir/x.log",
    "out.ckpt.partial",
    "./out.log",
];

fn path(byte: u8) -> Option<PathBuf> {
    let name = NAMES[usize::from(byte) % NAMES.len()];
    (byte < 240).then(|| {
        if name.starts_with('/') {
            PathBuf::from(name)
        } else {
            dir().join(name)
        }
    })
}

fuzz_target!(|data: [u8; 5]| {
    let dir = dir();
    let config_path = dir.join("gas.toml");
    let table = dir.join("table.npz");
    let before = [
        std::fs::read(&config_path).unwrap(),
        std::fs::read(&table).unwrap(),
        std::fs::read(dir.join("start.ckpt")).unwrap(),
    ];
    let checkpoint = path(data[2]);
    let files = RunFiles {
        trajectory: path(data[0]),
        log: path(data[1]),
        stop_checkpoint: checkpoint.clone().unwrap_or_else(|| dir.join("stop.ckpt")),
        checkpoint,
    };
    let resume = path(data[3]).filter(|_| data[4] & 1 == 1);
    let config = Config::from_toml(CONFIG).unwrap();
    let engine = common::build(EngineKind::Md, &config, config.build().unwrap()).unwrap();
    let inputs = [
        ("the config", config_path.as_path()),
        ("the MoR table (--table)", table.as_path()),
    ];
    let prepared = Run::prepare(engine, &config, &files, &inputs, resume.as_deref(), Some(0.02));
    if let Ok(run) = prepared {
        // Accepted: every output a regular file or new, distinct, and no input.
        let ckpt = files.checkpoint_path().to_path_buf();
        let mut outputs: Vec<PathBuf> = [files.trajectory.clone(), files.log.clone()]
            .into_iter()
            .flatten()
            .collect();
        outputs.push(ckpt.clone());
        outputs.push(CheckpointFile::partial_path(&ckpt));
        let ids: Vec<FileIdentity> = outputs
            .iter()
            .map(|p| FileIdentity::of(p).expect("an accepted output has an identity"))
            .collect();
        for (k, p) in outputs.iter().enumerate() {
            // The checkpoint itself exists only once written.
            let meta = std::fs::metadata(p);
            assert!(meta.map_or(*p == ckpt, |m| m.is_file()), "{} accepted", p.display());
            assert!(!ids[..k].contains(&ids[k]), "{} accepted twice", p.display());
            for input in [&config_path, &table] {
                assert!(FileIdentity::of(input).unwrap() != ids[k], "{} is an input", p.display());
            }
            if let Some(r) = &resume
                && *p != ckpt
            {
                assert!(FileIdentity::of(r).unwrap() != ids[k], "{} is resumed", p.display());
            }
        }
        drop(run);
    }
    let after = [
        std::fs::read(&config_path).unwrap(),
        std::fs::read(&table).unwrap(),
        std::fs::read(dir.join("start.ckpt")).unwrap(),
    ];
    assert!(before == after, "an input changed ({data:?})");
    for device in ["/dev/null", "/dev/full"] {
        assert!(!std::fs::metadata(device).unwrap().is_file(), "{device} replaced");
    }
    // Leave the scratch directory as it was for the next input.
    for name in ["out.xyz", "out.gsd", "out.log", "out.ckpt", "out.ckpt.partial", "stop.ckpt"] {
        let _ = std::fs::remove_file(dir.join(name));
    }
});
