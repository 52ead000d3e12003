//! Restarts and clean stops of `emdstar run`, for every engine: a run stopped at t/2
//! with a checkpoint and resumed ends in bitwise the state of a run that went through;
//! SIGINT and SIGTERM stop a run with whole files, a checkpoint and a summary; wrong
//! checkpoints are refused with a message that says why.

use crate::{error_in, stdout_in};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

const GAS: &str = "tests/md/configs/gas_small.toml";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-restart-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn config() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(GAS)
        .display()
        .to_string()
}

/// The last frame of an extended-XYZ file (its header line and particle lines).
fn last_frame(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let n: usize = lines[0].trim().parse().unwrap();
    lines[lines.len() - n - 1..].join("\n")
}

/// Runs `run` to `t_half` with a checkpoint and resumes it to the end: its trajectory
/// and log are those of the one run in `dir` (`one.xyz`, `one.log`), byte for byte.
fn assert_split_run_writes_one_run<T>(
    dir: &Path,
    run: impl Fn(&[&str]) -> T,
    tag: &str,
    t_half: &str,
) {
    let name = |ext: &str| format!("split-{t_half}.{ext}");
    let (traj, log, ckpt) = (name("xyz"), name("log"), name("ckpt"));
    let files = ["--trajectory", &traj, "--log", &log, "--checkpoint", &ckpt];
    let mut first = files.to_vec();
    first.extend(["--t-end", t_half]);
    run(&first);
    let mut second = files.to_vec();
    second.extend(["--resume", &ckpt]);
    run(&second);
    for (a, b) in [(&traj, "one.xyz"), (&log, "one.log")] {
        let x = std::fs::read(dir.join(a)).unwrap();
        let y = std::fs::read(dir.join(b)).unwrap();
        assert!(x == y, "{tag}: {a} differs from {b} of one run");
    }
}

#[test]
fn a_run_resumed_from_half_way_ends_bitwise_as_one_run() {
    let cfg = config();
    for engine in ["md", "emd", "emdstar", "hybrid"] {
        let dir = scratch(engine);
        let run = |extra: &[&str]| {
            let mut args = vec!["run", cfg.as_str(), "--engine", engine, "--quiet"];
            args.extend_from_slice(extra);
            let out = stdout_in(&dir, &args);
            serde_json::from_str::<serde_json::Value>(&out).unwrap()
        };
        run(&["--trajectory", "one.xyz", "--log", "one.log"]);
        let first = run(&[
            "--trajectory",
            "two.xyz",
            "--log",
            "two.log",
            "--t-end",
            "0.01",
            "--checkpoint",
            "half.ckpt",
        ]);
        let t_half = first["t"].as_f64().unwrap();
        assert!((t_half - 0.01).abs() < 1e-12, "{engine}: {first}");
        let second = run(&[
            "--trajectory",
            "two.xyz",
            "--log",
            "two.log",
            "--resume",
            "half.ckpt",
        ]);
        assert_eq!(second["resumed_from"], t_half, "{engine}");
        assert_eq!(
            last_frame(&dir.join("one.xyz")),
            last_frame(&dir.join("two.xyz")),
            "{engine}: the resumed run ends elsewhere"
        );
        // The files of the two parts are those of the one run, byte for byte, also when
        // the first part stopped between two log lines and two frames (it wrote a last
        // line and frame there, which resuming cut).
        for t_half in ["0.01", "0.0123"] {
            assert_split_run_writes_one_run(&dir, run, engine, t_half);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// Lees–Edwards boundaries keep no state of their own (the offset is γ̇ L_y t; MD's list
/// carries its images' shifts; eMD*'s pending E^v velocities are kept in the frame of
/// the particle's box): a sheared eMD*, eMD or MD run resumed half-way writes the files
/// of the one run, byte for byte, and so does a run on one thread.
#[test]
fn a_sheared_run_resumed_from_half_way_writes_the_files_of_one_run() {
    let dir = scratch("sheared");
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/configs/sheared_gas.toml");
    let text = std::fs::read_to_string(example).unwrap();
    let text = text.replace("t_end = 2.0 ", "t_end = 0.2 ");
    assert!(text.contains("t_end = 0.2 "));
    std::fs::write(dir.join("sheared.toml"), text).unwrap();
    for engine in ["emdstar", "emd", "md"] {
        let run = |extra: &[&str]| {
            let mut args = vec!["run", "sheared.toml", "--engine", engine, "--quiet"];
            args.extend_from_slice(extra);
            stdout_in(&dir, &args);
        };
        run(&["--trajectory", "one.xyz", "--log", "one.log"]);
        for t_half in ["0.1", "0.123"] {
            assert_split_run_writes_one_run(&dir, run, engine, t_half);
        }
        let files = ["--trajectory", "serial.xyz", "--log", "serial.log"];
        run(&[&files[..], &["--threads", "1"]].concat());
        for (a, b) in [("serial.xyz", "one.xyz"), ("serial.log", "one.log")] {
            let same = std::fs::read(dir.join(a)).unwrap() == std::fs::read(dir.join(b)).unwrap();
            assert!(same, "{engine}: {a} on one thread differs from {b}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn wrong_checkpoints_are_refused_with_reasons() {
    let cfg = config();
    let dir = scratch("wrong");
    stdout_in(
        &dir,
        &[
            "run",
            &cfg,
            "--engine",
            "md",
            "--quiet",
            "--t-end",
            "0.005",
            "--checkpoint",
            "md.ckpt",
        ],
    );
    let err = error_in(
        &dir,
        &["run", &cfg, "--engine", "emdstar", "--resume", "md.ckpt"],
    );
    assert!(err.contains("--engine md"), "{err}");
    let elastic = dir.join("elastic.toml");
    let text = std::fs::read_to_string(&cfg).unwrap();
    std::fs::write(
        &elastic,
        text.replace("dissipation = 1e-4", "dissipation = 2e-4"),
    )
    .unwrap();
    let err = error_in(
        &dir,
        &[
            "run",
            elastic.to_str().unwrap(),
            "--engine",
            "md",
            "--resume",
            "md.ckpt",
        ],
    );
    assert!(err.contains("another system"), "{err}");
    let bytes = std::fs::read(dir.join("md.ckpt")).unwrap();
    std::fs::write(dir.join("cut.ckpt"), &bytes[..bytes.len() / 2]).unwrap();
    let err = error_in(
        &dir,
        &["run", &cfg, "--engine", "md", "--resume", "cut.ckpt"],
    );
    assert!(
        err.contains("truncated") || err.contains("not a valid"),
        "{err}"
    );
    std::fs::write(dir.join("none.ckpt"), b"not a checkpoint at all").unwrap();
    let err = error_in(
        &dir,
        &["run", &cfg, "--engine", "md", "--resume", "none.ckpt"],
    );
    assert!(err.contains("not a valid emdstar checkpoint"), "{err}");
    let err = error_in(
        &dir,
        &[
            "run", &cfg, "--engine", "md", "--resume", "md.ckpt", "--t-end", "0.001",
        ],
    );
    assert!(err.contains("--t-end"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// SIGKILL gives a run no chance to finish what it writes: it may leave frames and log
/// lines from after its last checkpoint, and a last one cut in the middle of a write.
/// Resumed from that checkpoint, the run must end with the files of a run that went
/// through.
#[test]
fn a_killed_run_resumed_from_its_checkpoint_leaves_the_files_of_one_run() {
    let dir = scratch("kill");
    let cfg = long_config(&dir);
    let text = std::fs::read_to_string(&cfg).unwrap();
    std::fs::write(
        &cfg,
        text.replace(
            "log_interval = 0.001",
            "log_interval = 0.001\nrestart_interval = 0.0073",
        ),
    )
    .unwrap();
    let cfg = cfg.to_str().unwrap();
    // Every engine with an extended-XYZ trajectory, and one with a GSD file.
    for (engine, format) in [
        ("md", "xyz"),
        ("emdstar", "xyz"),
        ("hybrid", "xyz"),
        ("md", "gsd"),
    ] {
        let name = format!("{engine}-{format}");
        let (traj, log, ckpt) = (
            format!("{name}.{format}"),
            format!("{name}.log"),
            format!("{name}.ckpt"),
        );
        let mut child = Command::new(env!("CARGO_BIN_EXE_emdstar"))
            .current_dir(&dir)
            .args(["run", cfg, "--engine", engine, "--quiet"])
            .args(["--trajectory", &traj, "--log", &log])
            .stdout(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Kill it once it has written a checkpoint and gone on past it (log lines up to
        // t = 0.015 s; the checkpoints fall every 0.0073 s).
        let start = Instant::now();
        while !dir.join(&ckpt).exists()
            || std::fs::read_to_string(dir.join(&log)).map_or(0, |t| t.lines().count()) < 17
        {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "{name}: no checkpoint written"
            );
            std::thread::sleep(Duration::from_millis(5));
        }
        child.kill().unwrap();
        child.wait().unwrap();
        // Resume to a little after the last time the killed run logged.
        let frames = std::fs::read(dir.join(&traj)).unwrap();
        let log_text = std::fs::read_to_string(dir.join(&log)).unwrap();
        let t_last = log_text
            .lines()
            .filter_map(|l| l.split_whitespace().next()?.parse::<f64>().ok())
            .fold(0.0, f64::max);
        let t_end = format!("{}", t_last + 0.0125);
        // The same run, its files and the extra arguments.
        let run = |traj: &str, log: &str, extra: &[&str]| {
            let mut args = vec!["run", cfg, "--engine", engine, "--quiet"];
            args.extend(["--trajectory", traj, "--log", log, "--t-end", &t_end]);
            args.extend_from_slice(extra);
            stdout_in(&dir, &args)
        };
        let resumed = run(&traj, &log, &["--resume", &ckpt]);
        let resumed: serde_json::Value = serde_json::from_str(&resumed).unwrap();
        let t_ckpt = resumed["resumed_from"].as_f64().unwrap();
        let cut = &resumed["cut_at_resume"];
        if format == "xyz" {
            let frames = String::from_utf8(frames).unwrap();
            assert_eq!(
                cut["trajectory"],
                serde_json::json!(after(&frames, 502, "Time=", t_ckpt)),
                "{name}: frames after t = {t_ckpt}"
            );
        }
        assert_eq!(
            cut["log"],
            serde_json::json!(after(&log_text, 1, "", t_ckpt)),
            "{name}: log lines after t = {t_ckpt}"
        );
        let one = |ext: &str| format!("{name}-one.{ext}");
        run(&one(format), &one("log"), &[]);
        for (killed, through) in [(&traj, one(format)), (&log, one("log"))] {
            let a = std::fs::read(dir.join(killed)).unwrap();
            let b = std::fs::read(dir.join(&through)).unwrap();
            assert!(
                a == b,
                "{killed}, killed and resumed, differs from {through} of one run ({} against \
                 {} bytes)",
                a.len(),
                b.len()
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// What resuming at `t` must cut off `text`, records of `lines` lines whose time is the
/// field after `prefix`: whole records stamped after `t`, and the bytes of an unfinished
/// last one.
fn after(text: &str, lines: usize, prefix: &str, t: f64) -> serde_json::Value {
    let all: Vec<&str> = text.split_inclusive('\n').collect();
    let whole: Vec<&[&str]> = all
        .chunks(lines)
        .filter(|r| r.len() == lines && r[lines - 1].ends_with('\n'))
        .collect();
    let whole_bytes: usize = whole.iter().flat_map(|r| r.iter()).map(|l| l.len()).sum();
    let records = whole
        .iter()
        .filter(|r| !r[0].starts_with('#'))
        .filter(|r| {
            let time = r
                .iter()
                .flat_map(|l| l.split_whitespace())
                .find_map(|f| f.strip_prefix(prefix)?.parse::<f64>().ok());
            time.unwrap() > t
        })
        .count();
    serde_json::json!({ "records": records, "partial_bytes": text.len() - whole_bytes })
}

/// A run long enough to be stopped in the middle.
fn long_config(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(config()).unwrap();
    let path = dir.join("long.toml");
    std::fs::write(&path, text.replace("t_end = 0.02", "t_end = 100.0")).unwrap();
    path
}

#[test]
fn signals_stop_every_engine_with_whole_files_and_a_checkpoint() {
    let dir = scratch("signals");
    let cfg = long_config(&dir);
    for (engine, signal, code) in ["md", "emd", "emdstar", "hybrid"]
        .into_iter()
        .flat_map(|e| [(e, "INT", 130), (e, "TERM", 143)])
    {
        let traj = format!("{engine}-{signal}.xyz");
        let log = format!("{engine}-{signal}.log");
        let child = Command::new(env!("CARGO_BIN_EXE_emdstar"))
            .current_dir(&dir)
            .args(["run", cfg.to_str().unwrap(), "--engine", engine, "--quiet"])
            .args(["--trajectory", &traj, "--log", &log])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        // Wait until the run has written a few log lines.
        let start = Instant::now();
        while std::fs::read_to_string(dir.join(&log)).map_or(0, |t| t.lines().count()) < 4 {
            assert!(
                start.elapsed() < Duration::from_secs(60),
                "{engine} wrote no log"
            );
            std::thread::sleep(Duration::from_millis(20));
        }
        let sent = Command::new("kill")
            .args([&format!("-{signal}"), &child.id().to_string()])
            .status()
            .unwrap();
        assert!(sent.success());
        let t_sent = Instant::now();
        let out = child.wait_with_output().unwrap();
        assert!(
            t_sent.elapsed() < Duration::from_secs(10),
            "{engine} took long to stop"
        );
        assert_eq!(out.status.code(), Some(code), "{engine}");
        let summary: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(summary["interrupted"], true, "{engine}");
        let t = summary["t"].as_f64().unwrap();
        assert!(t > 0.0 && t < 100.0, "{engine}: {t}");
        // Whole files: every log line has its 21 columns, every frame its particles.
        let text = std::fs::read_to_string(dir.join(&log)).unwrap();
        assert!(text.ends_with('\n'));
        assert!(
            text.lines()
                .skip(1)
                .all(|l| l.split_whitespace().count() == 21)
        );
        let frames = std::fs::read_to_string(dir.join(&traj)).unwrap();
        assert_eq!(
            frames.lines().count() % 502,
            0,
            "{engine}: a frame cut short"
        );
        // The checkpoint next to the trajectory resumes the run.
        let ckpt = format!("{engine}-{signal}.ckpt");
        assert!(dir.join(&ckpt).exists(), "{engine}");
        let t_end = format!("{}", t + 1e-3);
        let run = |traj: &str, log: &str, extra: &[&str]| {
            let mut args = vec!["run", cfg.to_str().unwrap(), "--engine", engine, "--quiet"];
            args.extend(["--trajectory", traj, "--log", log, "--t-end", &t_end]);
            args.extend_from_slice(extra);
            stdout_in(&dir, &args)
        };
        run(&traj, &log, &["--resume", &ckpt]);
        // It ends with the files of a run that went through, byte for byte: the log
        // line written at the stop time (off every log tick) was cut when it resumed.
        let (one_traj, one_log) = (
            format!("{engine}-{signal}-one.xyz"),
            format!("{engine}-{signal}-one.log"),
        );
        run(&one_traj, &one_log, &[]);
        for (stopped, through) in [(&traj, &one_traj), (&log, &one_log)] {
            let a = std::fs::read(dir.join(stopped)).unwrap();
            let b = std::fs::read(dir.join(through)).unwrap();
            assert!(
                a == b,
                "{stopped}, stopped by SIG{signal} and resumed, differs from {through} of one \
                 run ({} against {} bytes)",
                a.len(),
                b.len()
            );
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A vibrated floor moves with time alone: a run resumed from half way ends in the
/// state of one run, bitwise, on every engine.
#[test]
fn a_run_on_a_vibrated_wall_resumed_from_half_way_ends_bitwise_as_one_run() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/configs/vibrated_bed.toml"),
    )
    .unwrap()
    .replace("t_end = 1.0", "t_end = 0.04")
    .replace("count = 300", "count = 60");
    for engine in ["md", "emd", "emdstar", "hybrid"] {
        let dir = scratch(&format!("vibrated-{engine}"));
        std::fs::write(dir.join("bed.toml"), &text).unwrap();
        let run = |extra: &[&str]| {
            let mut args = vec!["run", "bed.toml", "--engine", engine, "--quiet"];
            args.extend_from_slice(extra);
            stdout_in(&dir, &args)
        };
        run(&["--trajectory", "one.xyz", "--log", "one.log"]);
        assert_split_run_writes_one_run(&dir, run, engine, "0.0213");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
