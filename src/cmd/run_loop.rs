//! The one run loop of `emdstar run`, for every engine: advance through the
//! simulation interface to the next output time, write the thermo log, trajectory
//! frames and checkpoints when they are due, keep the progress bar going, and stop
//! cleanly when asked to.

use super::any_engine::EngineReport;
use super::stop::{Stop, StopFlags};
use anyhow::{Context, Result};
use emdstar_engines::AnyEngine;
use emdstar_system::gsd::GsdWriter;
use emdstar_system::{Checkpoint, Particles, SimBox, Thermo, ThermoLog, XyzWriter};
use indicatif::ProgressBar;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Output times k·interval (k = 0, 1, …), on whole steps for an engine that takes
/// steps of `step`.
#[derive(Debug, Clone, Copy)]
pub struct Ticks {
    interval: f64,
    next: u64,
}

impl Ticks {
    /// Ticks every `interval` (at least one step of `step`), the first one after `t`
    /// (or at `t` itself if `inclusive`).
    pub fn new(interval: f64, step: Option<f64>, t: f64, inclusive: bool) -> Self {
        let interval = match step {
            Some(dt) => (interval / dt).round().max(1.0) * dt,
            None => interval,
        };
        let mut ticks = Self {
            interval,
            next: (t / interval).floor().max(0.0) as u64,
        };
        while ticks.time() < t || (!inclusive && ticks.time() <= t) {
            ticks.next += 1;
        }
        ticks
    }

    /// The time between ticks (a whole number of steps for a step engine).
    pub fn interval(&self) -> f64 {
        self.interval
    }

    /// The time of the next tick.
    pub fn time(&self) -> f64 {
        self.next as f64 * self.interval
    }

    /// Whether the next tick has come at time `t` (within `tolerance`); moves on past
    /// it if so.
    fn take(&mut self, t: f64, tolerance: f64) -> bool {
        let due = t >= self.time() - tolerance;
        if due {
            while self.time() <= t + tolerance {
                self.next += 1;
            }
        }
        due
    }
}

/// A trajectory file: extended XYZ (text), or GSD (binary, chosen by the extension
/// `.gsd`); OVITO reads both.
pub enum Trajectory {
    Xyz(XyzWriter),
    Gsd { writer: GsdWriter, species: usize },
}

impl Trajectory {
    /// Bytes one frame of `n` particles of `species` kinds takes, about.
    pub fn frame_bytes(gsd: bool, n: usize, species: usize) -> u64 {
        if gsd {
            GsdWriter::frame_bytes(n, species)
        } else {
            // Nine columns in shortest round-trip notation.
            200 * n as u64
        }
    }

    fn write_frame(&mut self, t: f64, p: &Particles, sim_box: Option<&SimBox>) -> Result<()> {
        match self {
            Self::Xyz(w) => w.write_frame(t, p, sim_box),
            Self::Gsd { writer, species } => writer.write_frame(t, p, *species, sim_box),
        }
        .with_context(|| format!("stopped at t = {t} s: writing the trajectory frame"))
    }

    fn flush(&mut self) -> Result<()> {
        match self {
            Self::Xyz(w) => w.flush()?,
            Self::Gsd { writer, .. } => writer.flush()?,
        }
        Ok(())
    }
}

/// The files of a run and when they are written.
pub struct Plan {
    /// The time the run stops at (the nearest step for step engines).
    pub t_end: f64,
    pub trajectory: Option<(PathBuf, Trajectory, Ticks)>,
    pub log: (PathBuf, ThermoLog, Ticks),
    /// Where checkpoints go, and (with `[output] restart_interval`) when.
    pub checkpoint: Option<(PathBuf, Option<Ticks>)>,
    /// The config digest and options a checkpoint records.
    pub config_digest: u64,
    /// Whether the run starts afresh (its first frame and log line are at the start).
    pub fresh: bool,
}

/// What a run did.
pub struct Outcome {
    pub first: Thermo,
    pub last: Thermo,
    /// Steps or events done by this run (a resumed run counts from its checkpoint).
    pub work: u64,
    pub wall_seconds: f64,
    pub interrupted: Option<Stop>,
    /// The hybrid's mode counts at every log line.
    pub mode_counts: Vec<Value>,
    pub checkpoint_written: Option<PathBuf>,
}

/// Writes the checkpoint of the engine's state now.
pub fn write_checkpoint(engine: &AnyEngine, path: &Path, config_digest: u64) -> Result<()> {
    let sim = engine.sim();
    Checkpoint {
        engine: sim.engine().to_string(),
        options: engine.options_tag(),
        config_digest,
        time: sim.time(),
        state: sim.save_state(),
    }
    .write(path)
    .context("writing the checkpoint")
}

/// Writes one log line, naming the time in the error.
fn write_log(log: &mut ThermoLog, thermo: &Thermo) -> Result<()> {
    log.write(thermo)
        .with_context(|| format!("stopped at t = {} s: writing the thermo log", thermo.t))
}

/// Runs `engine` to `plan.t_end` (see the module docs).
pub fn drive(
    engine: &mut AnyEngine,
    plan: &mut Plan,
    bar: &ProgressBar,
    stop: &StopFlags,
) -> Result<Outcome> {
    let step = engine.sim().time_step();
    let tolerance = step.map_or(0.0, |dt| 0.5 * dt);
    let t_start = engine.sim().time();
    let work_start = engine.sim().steps_done();
    let span = (plan.t_end - t_start).max(f64::MIN_POSITIVE);
    // How far one call advances at most: progress and stop requests are looked at in
    // between (a thousandth of the run, at least one step).
    let quantum = (span / 1000.0).max(step.unwrap_or(0.0));
    let start = Instant::now();
    let mut mode_counts = Vec::new();
    let first = engine.sim().thermo();
    let mut last = first;
    let mut logged_at = f64::NAN;
    if plan.fresh {
        write_log(&mut plan.log.1, &first)?;
        logged_at = t_start;
        mode_counts.extend(engine.mode_point(0.0));
        if let Some((_, traj, ticks)) = &mut plan.trajectory {
            traj.write_frame(
                t_start,
                &engine.sim().particles(),
                engine.sim().domain().sim_box.as_ref(),
            )?;
            ticks.take(t_start, tolerance);
        }
        plan.log.2.take(t_start, tolerance);
    }
    let mut interrupted = None;
    loop {
        let now = engine.sim().time();
        if now >= plan.t_end - tolerance {
            break;
        }
        if let Some(signal) = stop.requested() {
            interrupted = Some(signal);
            break;
        }
        let mut target = plan.t_end.min(now + quantum).min(plan.log.2.time());
        if let Some((_, _, ticks)) = &plan.trajectory {
            target = target.min(ticks.time());
        }
        if let Some((_, Some(ticks))) = &plan.checkpoint {
            target = target.min(ticks.time());
        }
        engine
            .sim_mut()
            .advance_to(target)
            .map_err(|e| anyhow::anyhow!(e))?;
        let t = engine.sim().time();
        if plan.log.2.take(t, tolerance) {
            last = engine.sim().thermo();
            write_log(&mut plan.log.1, &last)?;
            logged_at = t;
            mode_counts.extend(engine.mode_point(start.elapsed().as_secs_f64()));
            bar.set_message(engine.status());
        }
        if let Some((_, traj, ticks)) = &mut plan.trajectory
            && ticks.take(t, tolerance)
        {
            traj.write_frame(
                t,
                &engine.sim().particles(),
                engine.sim().domain().sim_box.as_ref(),
            )?;
        }
        if let Some((path, Some(ticks))) = &mut plan.checkpoint
            && ticks.take(t, tolerance)
        {
            write_checkpoint(engine, path, plan.config_digest)?;
        }
        bar.set_position((1000.0 * (t - t_start) / span) as u64);
    }
    let wall_seconds = start.elapsed().as_secs_f64();
    let t = engine.sim().time();
    if logged_at != t {
        last = engine.sim().thermo();
        write_log(&mut plan.log.1, &last)?;
        mode_counts.extend(engine.mode_point(wall_seconds));
    }
    if interrupted.is_none()
        && let Some((_, traj, ticks)) = &mut plan.trajectory
    {
        // The last frame, unless the run ended on a frame time.
        let ended_on_frame = (ticks.time() - ticks.interval - t).abs() <= tolerance;
        if !ended_on_frame {
            traj.write_frame(
                t,
                &engine.sim().particles(),
                engine.sim().domain().sim_box.as_ref(),
            )?;
        }
    }
    plan.log.1.flush()?;
    if let Some((_, traj, _)) = &mut plan.trajectory {
        traj.flush()?;
    }
    let mut checkpoint_written = None;
    if let Some((path, _)) = &plan.checkpoint {
        write_checkpoint(engine, path, plan.config_digest)?;
        checkpoint_written = Some(path.clone());
    }
    Ok(Outcome {
        first,
        last,
        work: engine.sim().steps_done() - work_start,
        wall_seconds,
        interrupted,
        mode_counts,
        checkpoint_written,
    })
}
