//! The files of `emdstar run`: outputs never replace an input, a device or another
//! output, and are locked against a second run (`--force` changes none of it); inputs
//! are read only from regular files; what a run will write is estimated and bounded
//! before it starts.

use crate::{emdstar_in, error_in, stdout_in};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small gas of 64 spheres, with `extra` appended (e.g. an `[output]` section).
fn gas(dir: &Path, extra: &str) -> String {
    let text = format!(
        "t_end = 0.01\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
         dissipation = 1e-4\ndensity = 1140.0\n[gas]\ncount = 64\nradius = 0.1\n\
         arrangement = \"random\"\npacking_fraction = 0.1\nrms_speed = 1.0\nseed = 3\n{extra}"
    );
    let path = dir.join("gas.toml");
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

fn mkfifo(path: &Path) {
    use std::os::unix::ffi::OsStrExt;
    let name = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
    // SAFETY: a NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
}

#[test]
fn outputs_never_replace_an_input_a_device_or_each_other() {
    let dir = scratch("paths");
    let cfg = gas(&dir, "");
    let original = std::fs::read(&cfg).unwrap();
    stdout_in(&dir, &["run", &cfg, "--quiet", "--checkpoint", "a.ckpt"]);
    std::fs::create_dir(dir.join("a_directory")).unwrap();
    mkfifo(&dir.join("a_fifo"));
    let table = Path::new(env!("CARGO_MANIFEST_DIR")).join("tables/hertz.npz");
    let table = table.to_str().unwrap();
    let cases: [(&[&str], &str); 11] = [
        (&["--checkpoint", &cfg], "is the config"),
        (&["--log", &cfg], "is the config"),
        (&["--trajectory", &cfg], "is the config"),
        (&["--trajectory", "gas.toml"], "is the config"),
        (
            &["--trajectory", "t.xyz", "--log", "t.xyz"],
            "the same file",
        ),
        (&["--checkpoint", "gas.log"], "the same file"),
        (&["--checkpoint", "/dev/full"], "a device"),
        (&["--log", "/dev/null"], "a device"),
        (&["--trajectory", "a_fifo"], "a pipe"),
        (&["--log", "a_directory"], "a directory"),
        (
            &["--engine", "emdstar", "--table", table, "--log", table],
            "is the MoR table",
        ),
    ];
    for (extra, why) in cases {
        for force in [false, true] {
            let mut args = vec!["run", cfg.as_str(), "--quiet"];
            args.extend_from_slice(extra);
            if force {
                args.push("--force");
            }
            let err = error_in(&dir, &args);
            assert!(err.contains(why), "{extra:?}: {err}");
            assert_eq!(std::fs::read(&cfg).unwrap(), original, "{extra:?}");
        }
    }
    // The trajectory or log over the checkpoint resumed from is refused; the checkpoint
    // itself may replace it (it continues that run).
    let err = error_in(
        &dir,
        &[
            "run", &cfg, "--quiet", "--resume", "a.ckpt", "--log", "a.ckpt", "--t-end", "0.02",
        ],
    );
    assert!(err.contains("resumed from"), "{err}");
    stdout_in(
        &dir,
        &[
            "run",
            &cfg,
            "--quiet",
            "--resume",
            "a.ckpt",
            "--t-end",
            "0.02",
            "--checkpoint",
            "a.ckpt",
        ],
    );
    // /dev/null and /dev/full are still devices; nothing was left behind.
    for device in ["/dev/null", "/dev/full"] {
        let meta = std::fs::metadata(device).unwrap();
        assert!(!meta.is_file(), "{device} was replaced");
    }
    assert!(!dir.join("t.xyz").exists() && !dir.join("a.ckpt.partial").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_second_run_writing_the_same_files_is_refused_while_the_first_goes_on() {
    let dir = scratch("lock");
    let cfg = gas(&dir, "[output]\nlog_interval = 1e-4\n");
    let long = ["--t-end", "1e3", "--trajectory", "none", "--quiet"];
    let first = Command::new(env!("CARGO_BIN_EXE_emdstar"))
        .current_dir(&dir)
        .args(["run", &cfg])
        .args(long)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while std::fs::read_to_string(dir.join("gas.log")).map_or(0, |t| t.lines().count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(60), "no log");
        std::thread::sleep(Duration::from_millis(20));
    }
    for extra in [&["--force"][..], &[][..]] {
        let mut args = vec!["run", cfg.as_str()];
        args.extend(long);
        args.extend_from_slice(extra);
        let err = error_in(&dir, &args);
        assert!(err.contains("another emdstar run"), "{err}");
    }
    // Its checkpoint is locked too, whatever the other files.
    let err = error_in(
        &dir,
        &[
            "run",
            &cfg,
            "--quiet",
            "--log",
            "other.log",
            "--trajectory",
            "none",
            "--checkpoint",
            "gas.ckpt",
        ],
    );
    assert!(
        err.contains("another emdstar run") && err.contains("gas.ckpt"),
        "{err}"
    );
    assert!(
        !dir.join("other.log").exists(),
        "a refused run left its log"
    );
    let sent = Command::new("kill")
        .args(["-INT", &first.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let out = first.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130));
    let log = std::fs::read_to_string(dir.join("gas.log")).unwrap();
    assert!(
        log.ends_with('\n')
            && log
                .lines()
                .skip(1)
                .all(|l| l.split_whitespace().count() == 21)
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn inputs_are_read_only_from_regular_files() {
    let dir = scratch("inputs");
    let cfg = gas(&dir, "");
    mkfifo(&dir.join("fifo"));
    let fifo = dir.join("fifo").display().to_string();
    let cases: [(&[&str], &str); 5] = [
        (
            &["run", &cfg, "--engine", "emdstar", "--table", "/dev/zero"],
            "regular file",
        ),
        (
            &["run", &cfg, "--engine", "emdstar", "--table", &fifo],
            "regular file",
        ),
        (&["run", &cfg, "--resume", "/dev/zero"], "regular file"),
        (&["run", &cfg, "--resume", &fifo], "regular file"),
        (&["run", "/dev/zero"], "regular file"),
    ];
    for (args, why) in cases {
        let start = Instant::now();
        let mut args = args.to_vec();
        args.extend(["--quiet", "--trajectory", "none", "--log", "none"]);
        let err = error_in(&dir, &args);
        assert!(err.contains(why), "{args:?}: {err}");
        assert!(
            start.elapsed() < Duration::from_secs(5),
            "{args:?} took long"
        );
    }
    // A checkpoint longer than its header declares is refused before it is read whole.
    stdout_in(
        &dir,
        &[
            "run",
            &cfg,
            "--quiet",
            "--checkpoint",
            "c.ckpt",
            "--t-end",
            "0.005",
        ],
    );
    let mut bytes = std::fs::read(dir.join("c.ckpt")).unwrap();
    bytes.extend([0u8; 100]);
    std::fs::write(dir.join("long.ckpt"), bytes).unwrap();
    let err = error_in(&dir, &["run", &cfg, "--quiet", "--resume", "long.ckpt"]);
    assert!(err.contains("declares"), "{err}");
    // Threads beyond four per core are refused with the reason, at once.
    let start = Instant::now();
    let err = error_in(&dir, &["run", &cfg, "--threads", "100000"]);
    assert!(
        err.contains("per core") && err.contains("--threads"),
        "{err}"
    );
    assert!(start.elapsed() < Duration::from_secs(2));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_a_run_writes_is_estimated_and_bounded_before_it_starts() {
    let dir = scratch("bounded");
    // A log line every 1e-30 s: no disk holds it, for an event engine or a stepping
    // one asked to go on for long.
    let cfg = gas(&dir, "[output]\nlog_interval = 1e-30\n");
    for engine in ["emd", "emdstar"] {
        let err = error_in(&dir, &["run", &cfg, "--engine", engine, "--quiet"]);
        assert!(
            err.contains("the log") && err.contains("output.log_interval"),
            "{err}"
        );
    }
    assert!(!dir.join("gas.log").exists(), "a refused run left its log");
    // MD and the hybrid write a line per step, and say so.
    for engine in ["md", "hybrid"] {
        let out = emdstar_in(&dir, &["run", &cfg, "--engine", engine, "--quiet"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert!(
            err.contains("shorter than the time step") && err.contains("every step"),
            "{err}"
        );
        let steps = std::fs::read_to_string(dir.join("gas.log"))
            .unwrap()
            .lines()
            .count();
        assert!(steps > 100, "{engine}: {steps} lines");
    }
    // --t-end is checked as t_end is: too many steps, or a log no disk holds.
    let cfg = gas(&dir, "");
    let err = error_in(&dir, &["run", &cfg, "--engine", "md", "--t-end", "1e300"]);
    assert!(err.contains("--t-end") && err.contains("steps"), "{err}");
    let err = error_in(
        &dir,
        &["run", &cfg, "--engine", "emdstar", "--t-end", "1e300"],
    );
    assert!(err.contains("would take about"), "{err}");
    for bad in ["inf", "nan", "-1"] {
        let err = error_in(&dir, &["run", &cfg, &format!("--t-end={bad}")]);
        assert!(err.contains("--t-end"), "{bad}: {err}");
    }
    // Checkpoints every step: said before the start.
    let cfg = gas(&dir, "[output]\nrestart_interval = 1e-30\n");
    let out = emdstar_in(
        &dir,
        &["run", &cfg, "--engine", "md", "--quiet", "--t-end", "0.001"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("restart_interval") && err.contains("every step"),
        "{err}"
    );
    let err = error_in(
        &dir,
        &["run", &cfg, "--engine", "emdstar", "--t-end", "0.001"],
    );
    assert!(
        err.contains("checkpoints") && err.contains("restart_interval"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
