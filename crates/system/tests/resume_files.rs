//! Resuming a trajectory or thermo log after a killed run: the file must come back to
//! exactly the bytes it held when the checkpoint was written, whatever the killed run
//! added after it (whole records, and a last record cut at any byte).

use emdstar_system::{Cut, Observables, Particles, Thermo, ThermoLog, XyzWriter};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "emdstar-resume-files-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// `n` particles whose coordinates depend on `t`, so that frames differ.
fn particles(n: usize, t: f64) -> Particles {
    let position = (0..n)
        .map(|i| [i as f64 * 0.1 + t, (i % 7) as f64 / 3.0, -t / 9.0])
        .collect();
    let velocity = (0..n).map(|i| [t / 7.0, i as f64 / 11.0, 1.0]).collect();
    Particles::from_columns(position, velocity, vec![0.01; n], vec![1e-3; n], vec![0; n]).unwrap()
}

/// The bytes of a frame at time `t`, written on its own.
fn frame_bytes(dir: &Path, n: usize, t: f64) -> Vec<u8> {
    let path = dir.join("one-frame.xyz");
    let mut w = XyzWriter::create(&path).unwrap();
    w.write_frame(t, &particles(n, t), None).unwrap();
    std::fs::read(&path).unwrap()
}

fn append(path: &Path, bytes: &[u8]) {
    use std::io::Write;
    let mut f = std::fs::OpenOptions::new().append(true).open(path).unwrap();
    f.write_all(bytes).unwrap();
}

/// Frames at t = 0, 1, 2, 3 and the start of a frame at t = 4, resumed at `t_ckpt`:
/// the file holds the frames up to `t_ckpt`, as it did when they were written.
#[test]
fn a_trajectory_is_cut_back_to_its_checkpoint() {
    let dir = scratch("xyz");
    // 800 particles: a frame spans more than one of the scan's 64 KiB chunks.
    let n = 800;
    let last = frame_bytes(&dir, n, 4.0);
    let path = dir.join("run.xyz");
    for (t_ckpt, kept_frames) in [(1.0, 2), (1.5, 2), (3.0, 4), (-1.0, 0)] {
        for partial in [0, 1, 4, 5, 60, last.len() / 2, last.len() - 1] {
            let mut w = XyzWriter::create(&path).unwrap();
            let mut at_checkpoint = Vec::new();
            for k in 0..4 {
                if k == kept_frames {
                    at_checkpoint = std::fs::read(&path).unwrap();
                }
                let t = k as f64;
                w.write_frame(t, &particles(n, t), None).unwrap();
            }
            if kept_frames == 4 {
                at_checkpoint = std::fs::read(&path).unwrap();
            }
            drop(w);
            append(&path, &last[..partial]);
            let (mut w, cut) = XyzWriter::resume(&path, t_ckpt, n).unwrap();
            let expected = Cut {
                records: 4 - kept_frames as u64,
                partial_bytes: partial as u64,
            };
            assert_eq!(cut, expected, "t = {t_ckpt}, partial {partial}");
            assert!(
                std::fs::read(&path).unwrap() == at_checkpoint,
                "t = {t_ckpt}, partial {partial}: not the file at the checkpoint"
            );
            // Frames go on at the end.
            w.write_frame(9.0, &particles(n, 9.0), None).unwrap();
            let mut expected = at_checkpoint.clone();
            expected.extend(frame_bytes(&dir, n, 9.0));
            assert!(std::fs::read(&path).unwrap() == expected, "t = {t_ckpt}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

fn thermo(t: f64) -> Thermo {
    Thermo {
        t,
        step: (t * 10.0) as u64,
        kinetic_energy: 1.0 + t,
        rotational_energy: 0.0,
        potential_energy: t / 3.0,
        granular_temperature: 2.0,
        rotational_temperature: 0.0,
        momentum: [t, 0.0, -t],
        contacts: 3,
    }
}

#[test]
fn a_log_is_cut_back_to_its_checkpoint() {
    let dir = scratch("log");
    let path = dir.join("run.log");
    let line = {
        let mut log = ThermoLog::create(&path).unwrap();
        let header = std::fs::read(&path).unwrap().len();
        log.write(&thermo(7.0), &Observables::UNKNOWN).unwrap();
        std::fs::read(&path).unwrap()[header..].to_vec()
    };
    for (t_ckpt, kept_lines) in [(2.0, 3), (2.5, 3), (-1.0, 0), (4.0, 5)] {
        for partial in [0, 1, line.len() / 2, line.len() - 1] {
            let mut log = ThermoLog::create(&path).unwrap();
            let mut at_checkpoint = std::fs::read(&path).unwrap();
            for k in 0..5 {
                log.write(&thermo(k as f64), &Observables::UNKNOWN).unwrap();
                if k + 1 == kept_lines {
                    at_checkpoint = std::fs::read(&path).unwrap();
                }
            }
            drop(log);
            append(&path, &line[..partial]);
            let (_, cut) = ThermoLog::resume(&path, t_ckpt).unwrap();
            let expected = Cut {
                records: 5 - kept_lines as u64,
                partial_bytes: partial as u64,
            };
            assert_eq!(cut, expected, "t = {t_ckpt}, partial {partial}");
            assert!(std::fs::read(&path).unwrap() == at_checkpoint);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn foreign_files_are_refused_and_missing_ones_created() {
    let dir = scratch("foreign");
    let path = dir.join("other.xyz");
    std::fs::write(&path, frame_bytes(&dir, 10, 0.0)).unwrap();
    let err = XyzWriter::resume(&path, 1.0, 11).err().unwrap().to_string();
    assert!(
        err.contains("11 particles") && err.contains("--trajectory"),
        "{err}"
    );
    std::fs::write(&path, "not a trajectory\n").unwrap();
    let err = XyzWriter::resume(&path, 1.0, 11).err().unwrap().to_string();
    assert!(err.contains("--trajectory"), "{err}");
    let log = dir.join("other.log");
    std::fs::write(&log, "# t\nzero 1 2\n").unwrap();
    let err = ThermoLog::resume(&log, 1.0).err().unwrap().to_string();
    assert!(err.contains("--log"), "{err}");
    // Nothing to cut in a file that is not there: it is created.
    let fresh = dir.join("new.xyz");
    let (_, cut) = XyzWriter::resume(&fresh, 1.0, 11).unwrap();
    assert!(cut.is_empty() && fresh.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
