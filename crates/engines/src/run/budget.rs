//! What a run will write, checked before it starts: the stop time against the engine's
//! step, each output interval, the sizes of the trajectory and the log, and how many
//! checkpoints it will write.

use crate::output::{Cadence, TrajectoryFormat};
use anyhow::{Result, bail};
use std::path::{Path, PathBuf};

/// Steps a run may take at most (as for the config's t_end).
pub const MAX_STEPS: f64 = 1e13;

/// Checkpoints above which a run is told they may cost more than the simulation.
pub const MANY_CHECKPOINTS: f64 = 1e4;

/// Checkpoints above which a run is refused (unless forced): each is synced to the
/// disk, about a millisecond at best, so that these take a day.
pub const MAX_CHECKPOINTS: f64 = 1e8;

/// A file a run will write and its size, about.
#[derive(Debug, Clone, PartialEq)]
pub struct Estimate {
    /// "trajectory", "log" or "checkpoint".
    pub what: &'static str,
    pub path: PathBuf,
    /// Frames, lines or checkpoints.
    pub records: f64,
    /// The bytes on the disk at the end (a checkpoint replaces the one before, through
    /// a temporary file: twice its size).
    pub bytes: f64,
}

impl Estimate {
    /// A line for the user.
    pub fn describe(&self) -> String {
        let unit = match self.what {
            "log" => "lines",
            "checkpoint" => "checkpoints",
            _ => "frames",
        };
        format!(
            "{} {}: about {:.0} {unit}, {}",
            self.what,
            self.path.display(),
            self.records,
            gigabytes(self.bytes)
        )
    }
}

/// A size in GB, in scientific notation beyond 10⁴ GB.
pub fn gigabytes(bytes: f64) -> String {
    let gb = bytes / 1e9;
    if gb >= 1e4 {
        format!("{gb:.1e} GB")
    } else {
        format!("{gb:.1} GB")
    }
}

/// Refuses a stop time `t_end` (from `source`: "t_end" or "--t-end") that is not a finite
/// time after `now`, or that an engine stepping by `step` would need more than
/// [`MAX_STEPS`] steps to reach. A run `resumed` from a checkpoint may stop where it
/// starts (within half a step): a run killed right after its last checkpoint then
/// only completes its files.
pub fn check_stop_time(
    t_end: f64,
    now: f64,
    step: Option<f64>,
    source: &str,
    resumed: bool,
) -> Result<()> {
    let slack = step.map_or(0.0, |dt| 0.5 * dt);
    let later = t_end > now || (resumed && t_end >= now - slack);
    if !(t_end.is_finite() && later) {
        if resumed {
            bail!(
                "{source} = {t_end:e} s must be a finite time no earlier than the checkpoint's \
                 (t = {now:e} s); give a later --t-end"
            );
        }
        bail!(
            "{source} = {t_end:e} s must be a finite time after the start of the run (t = \
             {now:e} s)"
        );
    }
    if let Some(dt) = step {
        let steps = ((t_end - now) / dt).ceil();
        if steps > MAX_STEPS {
            bail!(
                "{source} = {t_end:e} s takes {steps:e} steps of dt = {dt:e} s, more than \
                 {MAX_STEPS:e}; lower {source} or raise dt"
            );
        }
    }
    Ok(())
}

/// An interval of `[output]` (`name`), positive and finite, or `default`.
pub fn interval(value: Option<f64>, default: f64, name: &str) -> Result<f64> {
    let x = value.unwrap_or(default);
    if !(x.is_finite() && x > 0.0) {
        bail!("output.{name} = {x:e} s must be a finite number greater than zero");
    }
    Ok(x)
}

/// The note for an output whose interval (`name`, `asked`) is shorter than the step.
pub fn every_step_note(cadence: &Cadence, name: &str, asked: f64, what: &str) -> Option<String> {
    cadence.every_step().then(|| {
        format!(
            "output.{name} = {asked:e} s is shorter than the time step dt = {:e} s: {what} \
             every step",
            cadence.interval()
        )
    })
}

/// The trajectory's size from `now` to `t_end`: a frame per tick and a last one.
pub fn trajectory(
    path: &Path,
    cadence: &Cadence,
    now: f64,
    t_end: f64,
    particles: usize,
    species: usize,
) -> Estimate {
    let records = cadence.ticks_between(now, t_end) + 1.0;
    let frame = TrajectoryFormat::of(path).frame_bytes(particles, species) as f64;
    Estimate {
        what: "trajectory",
        path: path.to_path_buf(),
        records,
        bytes: records * frame,
    }
}

/// The log's size from `now` to `t_end`: a line per tick and a last one.
pub fn log(path: &Path, cadence: &Cadence, now: f64, t_end: f64) -> Estimate {
    let records = cadence.ticks_between(now, t_end) + 1.0;
    Estimate {
        what: "log",
        path: path.to_path_buf(),
        records,
        bytes: records * emdstar_system::ThermoLog::LINE_BYTES as f64,
    }
}

/// A size in bytes as kB, MB or GB.
pub fn size(bytes: f64) -> String {
    match bytes {
        b if b < 1e6 => format!("{:.0} kB", (b / 1e3).max(1.0)),
        b if b < 1e9 => format!("{:.1} MB", b / 1e6),
        b => gigabytes(b),
    }
}

/// The checkpoints every `cadence` from `now` to `t_end`, each of `state_bytes`, at
/// `path`.
pub fn checkpoints(
    path: &Path,
    cadence: &Cadence,
    now: f64,
    t_end: f64,
    state_bytes: usize,
) -> Estimate {
    Estimate {
        what: "checkpoint",
        path: path.to_path_buf(),
        records: cadence.ticks_between(now, t_end),
        bytes: 2.0 * state_bytes as f64,
    }
}

/// The note for checkpoints every `cadence` (the estimate `e`), if there are more than
/// [`MANY_CHECKPOINTS`].
pub fn checkpoints_note(cadence: &Cadence, e: &Estimate) -> Option<String> {
    (e.records > MANY_CHECKPOINTS).then(|| {
        format!(
            "output.restart_interval = {:e} s writes about {:.1e} checkpoints of {} each, \
             every one synced to the disk: writing them may take longer than the simulation; \
             raise restart_interval",
            cadence.interval(),
            e.records,
            size(e.bytes / 2.0)
        )
    })
}
