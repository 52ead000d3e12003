//! Byte-identical resumption, driven through the library's run loop: a run killed at
//! any point of its loop (right after a periodic checkpoint, or in the middle of a
//! write, which leaves a record cut short), or ended early by a stop time, and resumed
//! from its checkpoint, ends with the log and trajectory of a run that went through,
//! byte for byte, for every engine and both trajectory formats.
//!
//! A kill is a panic raised by the run's observer and caught here: the files are then
//! as a SIGKILL would leave them (every record goes to the file in one write, nothing
//! waits in a buffer of the process).

use emdstar_engines::run::{Observer, Run, RunFiles};
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::Config;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

const CONFIG: &str = "t_end = 0.02
[material]
model = \"hertz\"
young = 1e9
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 120
radius = 0.1
arrangement = \"random\"
packing_fraction = 0.2
rms_speed = 1.0
seed = 42
[md]
dt = 3.4246575342465754e-5
[output]
trajectory_interval = 0.0025
log_interval = 0.001
";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-resume-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Kills the run (a panic) once the checkpoint at `path` has been replaced `after`
/// times, or once it has reached the time `at`.
struct Killer {
    path: PathBuf,
    inode: Option<u64>,
    replaced: u32,
    after: Option<u32>,
    at: Option<f64>,
}

impl Observer for Killer {
    fn progress(&mut self, engine: &AnyEngine, _fraction: f64) {
        use std::os::unix::fs::MetadataExt;
        let inode = std::fs::metadata(&self.path).ok().map(|m| m.ino());
        if inode.is_some() && inode != self.inode {
            self.inode = inode;
            self.replaced += 1;
            if Some(self.replaced) == self.after {
                panic!("kill: right after checkpoint {}", self.replaced);
            }
        }
        if self.at.is_some_and(|t| engine.sim().time() >= t) {
            panic!("kill: at t = {}", engine.sim().time());
        }
    }
}

/// How a run is made.
#[derive(Clone, Copy)]
struct Setup<'a> {
    kind: EngineKind,
    format: &'a str,
    /// `[output] restart_interval`.
    restart: f64,
    /// Driven by white noise (`[driving]`, a tick every 0.4 ms).
    driven: bool,
}

const DRIVING: &str =
    "[driving]\nkind = \"white_noise\"\nstrength = 50.0\nrate = 2500.0\nseed = 3\n";

/// Runs the config in `dir` as `setup` says, writing `name`.log and `name`.`format`,
/// resuming `name`.ckpt if `resume`, to `t_end` (else the config's), under `observer`.
fn run(
    dir: &Path,
    setup: Setup,
    name: &str,
    resume: bool,
    t_end: Option<f64>,
    observer: &mut dyn Observer,
) {
    let (kind, format) = (setup.kind, setup.format);
    let mut text = format!("{CONFIG}restart_interval = {}\n", setup.restart);
    if setup.driven {
        text.push_str(DRIVING);
    }
    let config = Config::from_toml(&text).unwrap();
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    let engine = AnyEngine::build(&options, &config, config.build().unwrap(), 1.0 / 50.0).unwrap();
    let files = RunFiles {
        trajectory: Some(dir.join(format!("{name}.{format}"))),
        log: Some(dir.join(format!("{name}.log"))),
        checkpoint: Some(dir.join(format!("{name}.ckpt"))),
        stop_checkpoint: dir.join(format!("{name}.ckpt")),
    };
    let ckpt = dir.join(format!("{name}.ckpt"));
    let resume = resume.then_some(ckpt.as_path());
    let mut run = Run::prepare(engine, &config, &files, &[], resume, t_end).unwrap();
    run.start().unwrap();
    run.drive(observer).unwrap();
}

fn assert_same_files(dir: &Path, a: &str, b: &str, format: &str, what: &str) {
    for ext in ["log", format] {
        let x = std::fs::read(dir.join(format!("{a}.{ext}"))).unwrap();
        let y = std::fs::read(dir.join(format!("{b}.{ext}"))).unwrap();
        assert!(
            x == y,
            "{what}: {a}.{ext} ({} bytes) differs from {b}.{ext} of a run that went through \
             ({} bytes)",
            x.len(),
            y.len()
        );
    }
}

/// Cuts the last `bytes` off the file, as a kill in the middle of its last write does.
fn tear(path: &Path, bytes: u64) {
    let file = std::fs::OpenOptions::new().write(true).open(path).unwrap();
    let len = file.metadata().unwrap().len();
    file.set_len(len.saturating_sub(bytes)).unwrap();
}

/// The kills are expected: no messages for them.
fn quiet_kills() {
    let report = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let kill = info
            .payload()
            .downcast_ref::<String>()
            .is_some_and(|m| m.starts_with("kill: "));
        if !kill {
            report(info);
        }
    }));
}

#[test]
fn killed_or_stopped_early_and_resumed_every_engine_writes_the_files_of_one_run() {
    let dir = scratch("kills");
    quiet_kills();
    for kind in [
        EngineKind::Md,
        EngineKind::Emd,
        EngineKind::EmdStar,
        EngineKind::Hybrid,
    ] {
        for format in ["xyz", "gsd"] {
            kills_and_stops(&dir, kind, format, false);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn driven_runs_killed_or_stopped_and_resumed_write_the_files_of_one_run() {
    // The kicks of a resumed run are those of the run that went through (the tick
    // numbers follow from the checkpoint's time, the numbers from the seed).
    let dir = scratch("driven");
    quiet_kills();
    for kind in [
        EngineKind::Md,
        EngineKind::Emd,
        EngineKind::EmdStar,
        EngineKind::Hybrid,
    ] {
        kills_and_stops(&dir, kind, "xyz", true);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs of `kind` writing `format` (driven or not) killed at several points of the
/// loop or stopped at a stop time, and resumed: the files of a run that went through.
fn kills_and_stops(dir: &Path, kind: EngineKind, format: &str, driven: bool) {
    let dir = dir.to_path_buf();
    let tag = format!("{}-{format}-{driven}", kind.name());
    let setup = |restart| Setup {
        kind,
        format,
        restart,
        driven,
    };
    let one = format!("{tag}-one");
    run(&dir, setup(0.0037), &one, false, None, &mut ());
    // Killed right after the first and the second periodic checkpoint (at
    // 0.0037 and 0.0074 s), right after one of the same time as a log line
    // (MD and the hybrid: 145 steps of dt = 0.02 s / 584, which ends 1 ulp
    // before 5 log intervals of 29 steps), and in the middle of writing the log
    // line and the frame of 0.005 s (torn: their last bytes never reached the
    // files); and right after the checkpoint at the stop time, before the last
    // records (MD's last log line is off its ticks), which resuming completes.
    let cases = [
        (0.0037, Some(1), None, 0),
        (0.0037, Some(2), None, 0),
        (0.001, Some(5), None, 0),
        (0.005, Some(4), None, 0),
        (0.0037, None, Some(0.0051), 37),
    ];
    for (k, (restart, after, at, torn)) in cases.into_iter().enumerate() {
        let name = format!("{tag}-kill{k}");
        let mut killer = Killer {
            path: dir.join(format!("{name}.ckpt")),
            inode: None,
            replaced: 0,
            after,
            at,
        };
        let killed = catch_unwind(AssertUnwindSafe(|| {
            run(&dir, setup(restart), &name, false, None, &mut killer)
        }));
        assert!(killed.is_err(), "{name} was not killed");
        if torn > 0 {
            tear(&dir.join(format!("{name}.log")), torn);
            tear(&dir.join(format!("{name}.{format}")), torn);
        }
        run(&dir, setup(restart), &name, true, None, &mut ());
        assert_same_files(&dir, &name, &one, format, &format!("killed ({k})"));
    }
    // Stopped by a stop time off every cadence, and resumed.
    let name = format!("{tag}-t-end");
    run(&dir, setup(0.0037), &name, false, Some(0.01234), &mut ());
    run(&dir, setup(0.0037), &name, true, None, &mut ());
    assert_same_files(&dir, &name, &one, format, "stopped at --t-end");
}
