//! Resume sequences through the library's run loop (`emdstar_engines::run`): a small
//! gas run by any engine with an XYZ or GSD trajectory, a log and periodic checkpoints,
//! cut into up to four pieces, each ended by a kill (the files as they were at some
//! point of the loop, the last write perhaps torn), a stop request (what SIGINT does)
//! or an early stop time (`--t-end`), and resumed from its checkpoint. The log and the
//! trajectory must end byte for byte as those of the run that went through.
#![no_main]

#[allow(dead_code)] // each target uses part of it
mod common;

use emdstar_engines::run::{Observer, Run, RunFiles};
use emdstar_engines::{AnyEngine, EngineKind};
use emdstar_system::{Config, stop};
use libfuzzer_sys::arbitrary::{self, Arbitrary};
use libfuzzer_sys::fuzz_target;
use std::path::{Path, PathBuf};

/// How a piece of the run ends.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum End {
    /// The process is killed after this many stretches of the loop (once a checkpoint
    /// exists), its last writes torn by up to this many bytes of what it wrote after
    /// that checkpoint.
    Kill { after: u8, tear: u16 },
    /// A stop is requested after this many stretches.
    Interrupt { after: u8 },
    /// The piece stops at this fraction (/256) of the run.
    StopAt { fraction: u8 },
}

#[derive(Arbitrary, Debug)]
struct Case {
    engine: u8,
    gsd: bool,
    /// Indices into the interval choices.
    log: u8,
    trajectory: u8,
    restart: u8,
    pieces: Vec<End>,
}

const T_END: f64 = 0.02;
const LOG: [f64; 3] = [0.001, 0.0013, 0.0002];
const TRAJECTORY: [f64; 3] = [0.0025, 0.004, 0.0007];
const RESTART: [f64; 3] = [0.0037, 0.001, 0.005];

fn config(case: &Case) -> Config {
    let pick = |choices: &[f64; 3], k: u8| choices[usize::from(k) % 3];
    let text = format!(
        "t_end = {T_END}\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
         dissipation = 1e-4\ndensity = 1140.0\n[gas]\ncount = 27\nradius = 0.1\n\
         arrangement = \"random\"\npacking_fraction = 0.2\nrms_speed = 1.0\nseed = 42\n\
         [output]\nlog_interval = {}\ntrajectory_interval = {}\nrestart_interval = {}\n",
        pick(&LOG, case.log),
        pick(&TRAJECTORY, case.trajectory),
        pick(&RESTART, case.restart)
    );
    Config::from_toml(&text).expect("a valid config")
}

/// The files of the run in `dir`.
fn files(dir: &Path, gsd: bool) -> RunFiles {
    let ckpt = dir.join("run.ckpt");
    RunFiles {
        trajectory: Some(dir.join(if gsd { "run.gsd" } else { "run.xyz" })),
        log: Some(dir.join("run.log")),
        checkpoint: Some(ckpt.clone()),
        stop_checkpoint: ckpt,
    }
}

/// Ends a piece of the run: copies its files (as a kill would leave them) once it has
/// gone `after` stretches past its first checkpoint, or requests a stop.
struct Ender {
    files: RunFiles,
    end: End,
    stretches: u32,
    /// The log and trajectory sizes when the checkpoint was last replaced.
    at_checkpoint: Option<(u64, u64)>,
    inode: Option<u64>,
    /// The killed files, once copied.
    killed: Option<Vec<(PathBuf, Vec<u8>)>>,
}

fn size(path: &Path) -> u64 {
    std::fs::metadata(path).map_or(0, |m| m.len())
}

impl Observer for Ender {
    fn progress(&mut self, _engine: &AnyEngine, _fraction: f64) {
        use std::os::unix::fs::MetadataExt;
        let (log, traj) = (
            self.files.log.clone().unwrap(),
            self.files.trajectory.clone().unwrap(),
        );
        let ckpt = self.files.checkpoint_path().to_path_buf();
        let inode = std::fs::metadata(&ckpt).ok().map(|m| m.ino());
        if inode.is_some() && inode != self.inode {
            self.inode = inode;
            self.at_checkpoint = Some((size(&log), size(&traj)));
        }
        if self.at_checkpoint.is_none() || self.killed.is_some() {
            return;
        }
        self.stretches += 1;
        match self.end {
            End::Kill { after, tear } if self.stretches == u32::from(after) + 1 => {
                let (log0, traj0) = self.at_checkpoint.unwrap();
                let mut copies = Vec::new();
                for (path, from) in [(log, log0), (traj, traj0)] {
                    let mut bytes = std::fs::read(&path).unwrap();
                    // Only what was written after the checkpoint can be torn.
                    let written = bytes.len() as u64 - from;
                    let cut = u64::from(tear).min(written);
                    bytes.truncate((bytes.len() as u64 - cut) as usize);
                    copies.push((path, bytes));
                }
                copies.push((ckpt.clone(), std::fs::read(&ckpt).unwrap()));
                self.killed = Some(copies);
            }
            End::Interrupt { after } if self.stretches == u32::from(after) + 1 => {
                stop::request(2);
            }
            _ => {}
        }
    }
}

/// Runs one piece in `dir` (resuming its checkpoint if `resume`) to `t_end`; returns
/// the time it ended at, `None` if the engine failed.
fn piece(
    dir: &Path,
    case: &Case,
    kind: EngineKind,
    resume: bool,
    t_end: Option<f64>,
    observer: &mut dyn Observer,
) -> Option<f64> {
    let config = config(case);
    let engine = common::build(kind, &config, config.build().ok()?)?;
    let files = files(dir, case.gsd);
    let ckpt = files.checkpoint_path().to_path_buf();
    let resume = resume.then_some(ckpt.as_path());
    let mut run = Run::prepare(engine, &config, &files, &[], resume, t_end)
        .expect("a run of a fixed config prepares");
    run.start().expect("its outputs open");
    run.drive(observer).ok()?;
    Some(run.engine().sim().time())
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("emdstar-fuzz-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fuzz_target!(|case: Case| {
    let kind = common::KINDS[usize::from(case.engine) % 4];
    let (one, dir) = (scratch("one"), scratch("pieces"));
    stop::clear();
    let Some(t_last) = piece(&one, &case, kind, false, None, &mut ()) else {
        return; // the engine stopped with an error: nothing to compare
    };
    let mut resume = false;
    for &end in case.pieces.iter().take(4) {
        let ckpt = files(&dir, case.gsd).checkpoint_path().to_path_buf();
        let now = if resume {
            emdstar_system::Checkpoint::read(&ckpt).unwrap().time
        } else {
            0.0
        };
        let t_end = match end {
            End::StopAt { fraction } => {
                Some(now + (T_END - now) * (f64::from(fraction) + 1.0) / 258.0)
            }
            _ => None,
        };
        let mut ender = Ender {
            files: files(&dir, case.gsd),
            end,
            stretches: 0,
            at_checkpoint: None,
            inode: None,
            killed: None,
        };
        let reached = piece(&dir, &case, kind, resume, t_end, &mut ender);
        let stopped = stop::requested().is_some();
        stop::clear();
        let reached = reached.expect("a piece ran where the whole run did");
        match ender.killed {
            Some(copies) => {
                for (path, bytes) in copies {
                    std::fs::write(path, bytes).unwrap();
                }
            }
            // Neither killed nor stopped early: the run is done.
            None if !stopped && t_end.is_none() => {
                resume = false;
                break;
            }
            // A step engine's stop time rounds to its nearest step, which may be the
            // end: resuming a run that is over is refused, and there is nothing left.
            None if reached >= t_last => {
                resume = false;
                break;
            }
            None => {}
        }
        resume = true;
    }
    if resume || case.pieces.is_empty() {
        piece(&dir, &case, kind, resume, None, &mut ()).expect("the last piece runs");
    }
    let f = files(&dir, case.gsd);
    let g = files(&one, case.gsd);
    for (a, b) in [(f.log, g.log), (f.trajectory, g.trajectory)] {
        let (a, b) = (a.unwrap(), b.unwrap());
        assert!(
            std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
            "{} differs from the run that went through ({case:?})",
            a.display()
        );
    }
});
