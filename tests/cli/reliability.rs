//! Input that `emdstar run` must refuse quickly, with a message that names what was
//! wrong: extreme speeds in every engine, configs of the wrong shape, truncated tables,
//! full disks, runs too large for the memory or the disk.

use crate::{emdstar_in, error_in};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-reliable-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const MATERIAL: &str = "[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.3\n\
                        density = 2500.0\n";

/// A gas of 64 spheres in a periodic box with `rms_speed` and `count`.
fn gas(rms_speed: &str, count: u64, extra: &str) -> String {
    format!(
        "t_end = 1.0\n{extra}{MATERIAL}[gas]\ncount = {count}\nradius = 0.01\n\
         arrangement = \"lattice\"\npacking_fraction = 0.01\nrms_speed = {rms_speed}\n"
    )
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    std::fs::write(dir.join(name), text).unwrap();
    name.to_string()
}

#[test]
fn extreme_speeds_are_refused_by_every_engine_within_a_second_naming_the_key() {
    let dir = scratch("extreme");
    let hot = write(&dir, "hot.toml", &gas("1e300", 64, ""));
    let fast = write(
        &dir,
        "fast.toml",
        &format!(
            "t_end = 1.0\n{MATERIAL}[[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n\
             velocity = [1e308, 0.0, 0.0]\n"
        ),
    );
    for (config, key) in [(&hot, "gas.rms_speed"), (&fast, "particles[0].velocity")] {
        for engine in ["md", "emdstar", "hybrid"] {
            let start = Instant::now();
            let err = error_in(&dir, &["run", config, "--engine", engine, "--quiet"]);
            let took = start.elapsed();
            assert!(
                err.contains(key) && err.contains("too large"),
                "{engine}, {config}: {err}"
            );
            assert!(took < Duration::from_secs(1), "{engine}: {took:?}");
        }
    }
    // Refused before any file is written.
    assert!(!dir.join("hot.xyz").exists() && !dir.join("fast.log").exists());
}

#[test]
fn extreme_spins_are_refused_by_every_engine_within_a_second_naming_the_key() {
    let dir = scratch("spin");
    let spinning = |w: &str| {
        format!(
            "t_end = 1.0\n{MATERIAL}[[particles]]\nradius = 0.01\nposition = [0.0, 0.0, 0.0]\n\
             angular_velocity = [{w}, 0.0, 0.0]\n"
        )
    };
    let fast = write(&dir, "fast.toml", &spinning("1e308"));
    let nan = write(&dir, "nan.toml", &spinning("nan"));
    for (config, why) in [(&fast, "too large"), (&nan, "finite")] {
        for engine in ["md", "emdstar", "hybrid"] {
            let start = Instant::now();
            let err = error_in(&dir, &["run", config, "--engine", engine, "--quiet"]);
            let took = start.elapsed();
            assert!(
                err.contains("particles[0].angular_velocity") && err.contains(why),
                "{engine}, {config}: {err}"
            );
            assert!(took < Duration::from_secs(1), "{engine}: {took:?}");
        }
    }
    assert!(!dir.join("fast.xyz").exists() && !dir.join("fast.log").exists());
}

#[test]
fn a_position_of_two_numbers_is_named_with_its_line() {
    let dir = scratch("shape");
    let config = write(
        &dir,
        "short.toml",
        &format!("t_end = 1.0\n{MATERIAL}[[particles]]\nradius = 0.01\nposition = [0.0, 0.0]\n"),
    );
    let err = error_in(&dir, &["run", &config, "--quiet"]);
    assert!(
        err.contains("particles[0].position: expected 3 numbers, got 2 (line 9, column 12)"),
        "{err}"
    );
    assert!(!err.contains("invalid length"), "{err}");
}

#[test]
fn a_truncated_table_says_what_is_missing_and_what_to_do() {
    let dir = scratch("table");
    let full =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/hertz.npz")).unwrap();
    std::fs::write(dir.join("cut.npz"), &full[..full.len() / 3]).unwrap();
    let config = write(&dir, "gas.toml", &gas("1.0", 64, ""));
    let err = error_in(
        &dir,
        &[
            "run", &config, "--engine", "emdstar", "--table", "cut.npz", "--quiet",
        ],
    );
    assert!(
        err.contains("cut.npz")
            && err
                .contains("the table file is truncated: the zip end-of-archive record is missing")
            && err.contains("regenerate it"),
        "{err}"
    );
}

/// Counts the occurrences of `what` in `text`.
fn count(text: &str, what: &str) -> usize {
    text.matches(what).count()
}

/// Runs `emdstar` in `dir` where no file may grow beyond `max_bytes` (RLIMIT_FSIZE, as
/// `ulimit -f` sets it): a write beyond fails as on a full disk. Returns its stderr.
fn error_with_file_limit(dir: &Path, args: &[&str], max_bytes: u64) -> String {
    use std::os::unix::process::CommandExt;
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_emdstar"));
    command.current_dir(dir).args(args);
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        command.pre_exec(move || {
            let limit = libc::rlimit {
                rlim_cur: max_bytes,
                rlim_max: max_bytes,
            };
            libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
            if libc::setrlimit(libc::RLIMIT_FSIZE, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let out = command.output().unwrap();
    assert!(!out.status.success(), "{args:?} should fail");
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    err
}

#[test]
fn a_full_disk_is_reported_once_with_the_path_and_the_log_is_kept() {
    let dir = scratch("full");
    let config = write(&dir, "gas.toml", &gas("1.0", 64, ""));
    // Frames of 64 spheres take about 10 kB: the second one does not fit into 16 kB.
    for engine in ["md", "emdstar", "hybrid"] {
        let err = error_with_file_limit(
            &dir,
            &[
                "run",
                &config,
                "--engine",
                engine,
                "--trajectory",
                "big.xyz",
                "--log",
                "kept.log",
                "--quiet",
            ],
            16_000,
        );
        assert_eq!(count(&err, "big.xyz"), 1, "{engine}: {err}");
        assert_eq!(count(&err, "File too large"), 1, "{engine}: {err}");
        assert!(
            err.contains("trajectory") && err.contains("largest size"),
            "{err}"
        );
        // The log's line at t = 0 was written before the second frame failed.
        let log = std::fs::read_to_string(dir.join("kept.log")).unwrap();
        assert!(log.lines().count() >= 2, "{engine}: {log}");
    }
    // An unwritable path: named once, with what to do.
    let err = error_in(
        &dir,
        &[
            "run",
            &config,
            "--trajectory",
            "no/such/dir/t.xyz",
            "--quiet",
        ],
    );
    assert_eq!(count(&err, "no/such/dir/t.xyz"), 1, "{err}");
    assert!(err.contains("check the path"), "{err}");
}

#[test]
fn a_gas_too_large_for_the_memory_is_refused_at_once() {
    let dir = scratch("memory");
    let config = write(&dir, "huge.toml", &gas("1.0", 100_000_000, ""));
    for engine in ["md", "emdstar", "hybrid"] {
        let start = Instant::now();
        let err = error_in(&dir, &["run", &config, "--engine", engine, "--quiet"]);
        assert!(
            err.contains("100000000 particles need about") && err.contains("--force"),
            "{engine}: {err}"
        );
        assert!(start.elapsed() < Duration::from_secs(1));
    }
}

#[test]
fn a_trajectory_larger_than_the_disk_is_refused_before_the_run() {
    let dir = scratch("disk");
    // 10^10 frames of 64 particles: far beyond any disk.
    let config = write(
        &dir,
        "often.toml",
        &gas("1.0", 64, "[output]\ntrajectory_interval = 1e-10\n"),
    );
    let err = error_in(&dir, &["run", &config, "--engine", "emdstar", "--quiet"]);
    assert!(
        err.contains("often.xyz would take about")
            && err.contains("free")
            && err.contains("--force"),
        "{err}"
    );
    // Refused before the run: neither file was opened.
    assert!(!dir.join("often.xyz").exists() && !dir.join("often.log").exists());
    // Without a trajectory the same config runs.
    let out = emdstar_in(
        &dir,
        &[
            "run",
            &config,
            "--engine",
            "emdstar",
            "--trajectory",
            "none",
            "--t-end",
            "0.01",
            "--quiet",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Found by fuzzing: eMD* with friction on a linear law of subnormal stiffness hung in
/// the exact frictional contact (an infinite step; the solver now ends with an error,
/// `a_contact_too_soft_for_a_finite_step_ends_with_an_error` in crates/mor). The
/// up-front check of contacts refuses it before the run, naming the key once.
#[test]
fn a_frictional_contact_too_soft_to_solve_stops_with_what_to_check() {
    let dir = scratch("soft-friction");
    let config = write(
        &dir,
        "soft.toml",
        "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 1.17e-310\n\
         density = 5.5e8\nfriction = 56.0\ntangential_stiffness = 119.0\n\
         [[particles]]\nposition = [0.0, 0.0, 0.0]\nradius = 55.0\n\
         [[particles]]\nposition = [2e5, 0.0, 0.0]\nradius = 5.1e4\n\
         velocity = [-5.7e6, 5.7e5, 0.0]\nangular_velocity = [0.0, 5.7e4, 5.7e4]\n",
    );
    let start = Instant::now();
    let stderr = error_in(&dir, &["pair", &config, "--engine", "emdstar"]);
    assert!(start.elapsed() < Duration::from_secs(10));
    assert!(
        stderr.contains("line 4: material.stiffness") && stderr.contains("not a finite number"),
        "{stderr}"
    );
    assert_eq!(stderr.matches("material.stiffness").count(), 1, "{stderr}");
}

/// A contact that needed more solver steps than the bound (found by fuzzing: spins of
/// 3·10¹⁰ rad/s, µ = 10⁵, speeds of 6·10¹⁰ m/s) is refused before the run in terms of
/// the config, not of solver options: at those speeds the spheres would pass through
/// each other.
#[test]
fn a_frictional_contact_too_long_to_solve_names_the_material_and_spins() {
    let dir = scratch("long-friction");
    let config = write(
        &dir,
        "long.toml",
        "t_end = 5.3e6\n[material]\nmodel = \"linear\"\nstiffness = 51000.0\n\
         density = 33000.0\nfriction = 123000.0\ntangential_stiffness = 123000.0\n\
         tangential_damping = 5.2e8\n\
         [[particles]]\nposition = [6.72e9, 6.72e9, 6.72e9]\nradius = 5.6e8\nmass = 7e7\n\
         velocity = [7e7, 7e7, 7e7]\nangular_velocity = [7e7, 7e7, 7e7]\n\
         [[particles]]\nposition = [8.4000013e8, 8.4000013e8, 8.4e8]\nradius = 7e7\n\
         mass = 3.3e10\nvelocity = [3.3e10, 3.3e10, 3.3e10]\n\
         angular_velocity = [3.3e10, 3.3e10, 3.3e10]\n",
    );
    let start = Instant::now();
    let stderr = error_in(&dir, &["pair", &config, "--engine", "emdstar"]);
    assert!(start.elapsed() < Duration::from_secs(10));
    assert!(
        stderr.contains("line 4: material.stiffness")
            && stderr.contains("centres pass through each other"),
        "{stderr}"
    );
    assert!(!stderr.contains("max_steps"), "{stderr}");
}

#[test]
fn a_reader_that_leaves_early_ends_the_output_without_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_emdstar"))
        .args(["table", "check", "default:linear", "--samples", "20000"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the emdstar binary runs");
    // The reader leaves before the first line (the check takes a tenth of a second),
    // as `| head -0` would.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
}

/// Runs the config at `path` with `engine` and `extra` arguments in `dir`, expects a
/// clean failure and returns its message.
fn refused(dir: &Path, path: &Path, engine: &str, extra: &[&str]) -> String {
    let mut args = vec!["run", path.to_str().unwrap(), "--engine", engine, "--quiet"];
    args.extend_from_slice(extra);
    error_in(dir, &args)
}

/// A bed that settles on a floor is an inelastic collapse for the event engines: eMD
/// (which ran for ever, its flights shrinking to one ulp) and eMD* stop with the same
/// error, which names the hybrid.
#[test]
fn a_bed_settling_on_a_floor_stops_every_event_engine_naming_the_hybrid() {
    let config = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/configs/walls_gravity.toml");
    let dir = scratch("settles");
    for engine in ["emd", "emdstar"] {
        let start = Instant::now();
        let none = ["--trajectory", "none", "--log", "none"];
        let err = refused(&dir, &config, engine, &none);
        assert!(
            err.contains("inelastic collapse") && err.contains("--engine hybrid"),
            "{engine}: {err}"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "{engine} took {:?}",
            start.elapsed()
        );
    }
}

/// The TC model keeps eMD going where the bed settles: walls_gravity.toml with
/// [events] tc = 1 ms (about the contact duration of its spheres, π√(m_eff/k) = 0.8
/// ms) runs to t_end, its total energy never rising from one log line to the next
/// and its granular temperature falling fiftyfold at least, with the collisions TC made
/// elastic counted; without tc it stops with the collapse error, which names the
/// hybrid and TC.
#[test]
fn the_tc_model_runs_the_settling_bed_to_its_end_on_emd() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/configs/walls_gravity.toml");
    let dir = scratch("tc");
    let text = std::fs::read_to_string(&example).unwrap() + "[events]\ntc = 1e-3\n";
    std::fs::write(dir.join("tc.toml"), text).unwrap();
    let out = emdstar_in(
        &dir,
        &[
            "run",
            "tc.toml",
            "--engine",
            "emd",
            "--quiet",
            "--trajectory",
            "none",
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(summary["t"], 1.0, "{summary}");
    let elastic = summary["stats"]["tc_elastic_collisions"].as_u64().unwrap();
    let collisions = summary["stats"]["collisions"].as_u64().unwrap()
        + summary["stats"]["wall_collisions"].as_u64().unwrap();
    assert!(elastic > 0 && elastic < collisions, "{summary}");
    let log = std::fs::read_to_string(dir.join("tc.log")).unwrap();
    let rows: Vec<Vec<f64>> = log
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| l.split_whitespace().map(|w| w.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 201);
    // Columns: t, step, kinetic, potential, total, granular temperature.
    for w in rows.windows(2) {
        assert!(
            w[1][4] <= w[0][4] * (1.0 + 1e-12),
            "energy rose: {:?} -> {:?}",
            w[0],
            w[1]
        );
    }
    let (t0, t1) = (rows[0][5], rows[rows.len() - 1][5]);
    assert!(t1 < t0 / 50.0, "T from {t0:e} to {t1:e}");
    let err = refused(
        &dir,
        &example,
        "emd",
        &["--trajectory", "none", "--log", "none"],
    );
    assert!(
        err.contains("inelastic collapse")
            && err.contains("--engine hybrid")
            && err.contains("[events] tc"),
        "{err}"
    );
}

/// A stop request is seen at the next event or step, not at the next output: with no
/// output due for the whole run, SIGINT still ends every engine within a second.
#[test]
fn a_signal_stops_every_engine_within_a_second_whatever_the_output_intervals() {
    let dir = scratch("prompt");
    let config = write(
        &dir,
        "gas.toml",
        &gas(
            "1.0",
            500,
            "[output]\ntrajectory_interval = 1e4\nlog_interval = 1e4\n",
        )
        .replace("t_end = 1.0", "t_end = 1e4"),
    );
    for engine in ["md", "emd", "emdstar", "hybrid"] {
        let child = std::process::Command::new(env!("CARGO_BIN_EXE_emdstar"))
            .current_dir(&dir)
            .args(["run", &config, "--engine", engine, "--quiet"])
            .args(["--trajectory", "none", "--log", &format!("{engine}.log")])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // The run has started once its log holds the line of t = 0.
        let start = Instant::now();
        while std::fs::read_to_string(dir.join(format!("{engine}.log")))
            .map_or(0, |t| t.lines().count())
            < 2
        {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "{engine} did not start"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
        std::thread::sleep(Duration::from_millis(500));
        let sent = Instant::now();
        // SAFETY: a signal to the child started above.
        assert_eq!(unsafe { libc::kill(child.id() as i32, libc::SIGINT) }, 0);
        let out = child.wait_with_output().unwrap();
        let took = sent.elapsed();
        assert_eq!(
            out.status.code(),
            Some(130),
            "{engine}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            took < Duration::from_secs(1),
            "{engine} took {took:?} to stop"
        );
        eprintln!("{engine}: stopped {took:?} after SIGINT");
    }
}

/// A box axis that is closed without a wall at each end lets particles out: every
/// engine refuses it before the start, and writes nothing.
#[test]
fn a_closed_axis_without_walls_is_refused_by_every_engine_before_the_start() {
    let dir = scratch("closed");
    let config = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/md/configs/bad/closed_axis_without_walls.toml");
    for engine in ["md", "emd", "emdstar", "hybrid"] {
        let start = Instant::now();
        let err = refused(&dir, &config, engine, &[]);
        assert!(
            err.contains("no wall holds the particles at its high end")
                && err.contains("normal = [0.0, 0.0, -1.0]"),
            "{engine}: {err}"
        );
        assert!(start.elapsed() < Duration::from_secs(2), "{engine}");
    }
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "files were written"
    );
}
