//! A whole run of any engine with its outputs: the one run loop of `emdstar run` and of
//! the Python package.
//!
//! [`Run::prepare`] restores a checkpoint if the run resumes one, checks the stop time
//! and the output intervals, estimates what the run will write, and claims its files
//! (see [`RunFiles::check`]; nothing is written yet). [`Run::start`] opens the outputs,
//! or takes them up where the resumed run left them. [`Run::drive`] advances the engine
//! from one due output to the next ([`crate::output`]) until the stop time, or until a
//! stop is requested ([`emdstar_system::stop`]), which every engine sees at its next
//! event or step.

mod budget;
mod files;
mod restore;

pub use budget::{Estimate, MAX_CHECKPOINTS, gigabytes, size};
pub use files::RunFiles;

use crate::AnyEngine;
use crate::output::{
    Cadence, CheckpointOutput, End, LogOutput, ModeCounts, ModePoint, Output, Recorder,
    TrajectoryOutput,
};
use crate::{drive, observe};
use anyhow::{Context, Result};
use emdstar_system::{CheckpointFile, Config, Cut, Drive, Observables, OutputFile, Thermo, stop};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What a caller hears of a run while it goes on (every hook does nothing unless
/// implemented).
pub trait Observer {
    /// After each stretch of the run (a thousandth of it, or up to the next output):
    /// the engine, and the fraction of the run done.
    fn progress(&mut self, _engine: &AnyEngine, _fraction: f64) {}
    /// Something the user should know (e.g. that checkpoints take most of the time).
    fn note(&mut self, _message: &str) {}
}

/// An observer that hears nothing.
impl Observer for () {}

/// The outputs of a run, the records first and the checkpoint last.
struct Outputs {
    log: Option<LogOutput>,
    trajectory: Option<TrajectoryOutput>,
    modes: ModeCounts,
    recorders: Vec<Recorder>,
    checkpoint: CheckpointOutput,
}

impl Outputs {
    fn all(&mut self) -> Vec<&mut dyn Output> {
        let mut all: Vec<&mut dyn Output> = Vec::with_capacity(4);
        if let Some(o) = &mut self.log {
            all.push(o);
        }
        if let Some(o) = &mut self.trajectory {
            all.push(o);
        }
        all.push(&mut self.modes);
        for r in &mut self.recorders {
            all.push(r);
        }
        all.push(&mut self.checkpoint);
        all
    }
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The thermo quantities when the run started and when it ended.
    pub first: Thermo,
    pub last: Thermo,
    /// The run's means: pressure tensor and collision rate over the whole run (this
    /// piece of it, if resumed), a₂ over the log's lines (NaN without a log).
    pub means: Observables,
    /// Steps or events done by this run (a resumed run counts from its checkpoint).
    pub work: u64,
    pub wall_seconds: f64,
    /// The signal that stopped the run early, if one did.
    pub stopped_by: Option<i32>,
}

/// A run being prepared, started and driven (see the module documentation).
pub struct Run {
    engine: AnyEngine,
    /// The config's thermostat, if any.
    drive: Option<Drive>,
    t_end: f64,
    resumed_at: Option<f64>,
    outputs: Outputs,
    estimates: Vec<Estimate>,
    notes: Vec<String>,
    cuts: Vec<(&'static str, PathBuf, Cut)>,
}

impl Run {
    /// Prepares a run of `engine` (built from `config`) writing `files`: resumes the
    /// checkpoint `resume` if given, stops at `t_end` (else the config's), and checks
    /// the files against each other and against `inputs` (what each is, for messages,
    /// and its path: the config, a table). The config's `t_end` sets the default output
    /// intervals.
    pub fn prepare(
        mut engine: AnyEngine,
        config: &Config,
        files: &RunFiles,
        inputs: &[(&str, &Path)],
        resume: Option<&Path>,
        t_end: Option<f64>,
    ) -> Result<Self> {
        let resumed_at = match resume {
            Some(path) => Some(restore::restore(&mut engine, path, config)?),
            None => None,
        };
        let (now, step) = (engine.sim().time(), engine.sim().time_step());
        let stop_at = t_end.unwrap_or(config.t_end);
        let source = if t_end.is_some() { "--t-end" } else { "t_end" };
        budget::check_stop_time(stop_at, now, step, source, resumed_at.is_some())?;
        let output = config.output.clone().unwrap_or_default();
        let mut notes = Vec::new();
        let mut estimates = Vec::new();
        let cadence = |value: Option<f64>, default: f64, name: &str, what: &str| {
            let asked = budget::interval(value, default, name)?;
            let c = Cadence::new(asked, step);
            Ok::<_, anyhow::Error>((c, budget::every_step_note(&c, name, asked, what)))
        };
        let (log_cadence, note) = cadence(
            output.log_interval,
            config.t_end / 100.0,
            "log_interval",
            "a log line",
        )?;
        notes.extend(note);
        let (traj_cadence, note) = cadence(
            output.trajectory_interval,
            config.t_end / 20.0,
            "trajectory_interval",
            "a frame",
        )?;
        if files.trajectory.is_some() {
            notes.extend(note);
        }
        let restart = match output.restart_interval {
            Some(x) => {
                let (c, note) = cadence(Some(x), x, "restart_interval", "a checkpoint")?;
                notes.extend(note);
                Some(c)
            }
            None => None,
        };
        let particles = engine.sim().particles();
        let species = particles
            .species
            .iter()
            .max()
            .map_or(0, |&s| s as usize + 1);
        if let Some(path) = &files.trajectory {
            estimates.push(budget::trajectory(
                path,
                &traj_cadence,
                now,
                stop_at,
                particles.len(),
                species,
            ));
        }
        if let Some(path) = &files.log {
            estimates.push(budget::log(path, &log_cadence, now, stop_at));
        }
        if let Some(c) = &restart {
            let state = engine.sim().save_state().len();
            let e = budget::checkpoints(files.checkpoint_path(), c, now, stop_at, state);
            notes.extend(budget::checkpoints_note(c, &e));
            estimates.push(e);
        }
        // The file of the initial state is an input too.
        let initial = config
            .initial
            .as_ref()
            .map(|i| i.path(config.dir.as_deref()));
        let mut inputs = inputs.to_vec();
        if let Some(path) = &initial {
            inputs.push(("the initial state ([initial] file)", path.as_path()));
        }
        files.check(&inputs, resume)?;
        let claim = |path: &Path| {
            OutputFile::claim(path)
                .with_context(|| format!("claiming the output {}", path.display()))
        };
        let log = match &files.log {
            Some(p) => Some(LogOutput::new(claim(p)?, log_cadence)),
            None => None,
        };
        let trajectory = match &files.trajectory {
            Some(p) => Some(TrajectoryOutput::new(claim(p)?, traj_cadence)),
            None => None,
        };
        let checkpoint = CheckpointOutput::new(
            CheckpointFile::claim(files.checkpoint_path())?,
            restart,
            files.checkpoint.is_some(),
            config.digest(),
        );
        let drive = config.driving.as_ref().map(|d| d.drive()).transpose()?;
        Ok(Self {
            engine,
            drive,
            t_end: stop_at,
            resumed_at,
            outputs: Outputs {
                log,
                trajectory,
                modes: ModeCounts::new(log_cadence),
                recorders: Vec::new(),
                checkpoint,
            },
            estimates,
            notes,
            cuts: Vec::new(),
        })
    }

    /// The engine.
    pub fn engine(&self) -> &AnyEngine {
        &self.engine
    }

    /// The time the run stops at.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// The time of the checkpoint the run resumed from, if it did.
    pub fn resumed_at(&self) -> Option<f64> {
        self.resumed_at
    }

    /// The sizes of the files the run will write.
    pub fn estimates(&self) -> &[Estimate] {
        &self.estimates
    }

    /// What the user should know before the run starts.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// What resuming cut off the end of each output (after [`Run::start`]).
    pub fn cuts(&self) -> &[(&'static str, PathBuf, Cut)] {
        &self.cuts
    }

    /// The hybrid's mode counts at every log tick and at the end.
    pub fn mode_points(&self) -> &[ModePoint] {
        self.outputs.modes.points()
    }

    /// Adds a record kept in memory every `interval` s of simulated time (on whole
    /// steps of a step engine), with the particles if `keep_particles`; returns its
    /// number for [`Run::recorder`]. Before [`Run::start`].
    pub fn record(&mut self, interval: f64, keep_particles: bool) -> Result<usize> {
        let interval = budget::interval(Some(interval), interval, "interval")?;
        let cadence = Cadence::new(interval, self.engine.sim().time_step());
        self.outputs
            .recorders
            .push(Recorder::new(cadence, keep_particles));
        Ok(self.outputs.recorders.len() - 1)
    }

    /// The records of [`Run::record`]'s number `k`.
    pub fn recorder(&self, k: usize) -> &Recorder {
        &self.outputs.recorders[k]
    }

    /// The checkpoint written last, if any.
    pub fn checkpoint_written(&self) -> Option<&Path> {
        self.outputs.checkpoint.written()
    }

    /// Opens the outputs of a fresh run, or takes up those of a resumed one (see
    /// [`Output::resume`]); what resuming cut is then in [`Run::cuts`].
    pub fn start(&mut self) -> Result<()> {
        let resumed = self.resumed_at.is_some();
        for o in self.outputs.all() {
            if resumed {
                let cut = o.resume(&self.engine)?;
                if let Some(path) = o.path().filter(|_| !o.saves_state()) {
                    self.cuts.push((o.name(), path.to_path_buf(), cut));
                }
            } else {
                o.open(&self.engine)?;
            }
        }
        Ok(())
    }

    /// Runs to the stop time, or until a stop is requested, writing every output when
    /// it is due (see the module documentation).
    pub fn drive(&mut self, observer: &mut dyn Observer) -> Result<Outcome> {
        let step = self.engine.sim().time_step();
        let tolerance = step.map_or(0.0, |dt| 0.5 * dt);
        let t_start = self.engine.sim().time();
        let work_start = self.engine.sim().steps_done();
        let span = (self.t_end - t_start).max(f64::MIN_POSITIVE);
        // How far one call advances at most: progress is reported in between.
        let quantum = (span / 1000.0).max(step.unwrap_or(0.0));
        let first = self.engine.sim().thermo();
        let start = observe::reading(self.engine.sim());
        let clock = Instant::now();
        let mut cost_noted = false;
        self.write_due(tolerance)?;
        let mut end = End::Complete;
        loop {
            let now = self.engine.sim().time();
            if now >= self.t_end - tolerance {
                break;
            }
            if stop::is_requested() {
                end = End::Stopped;
                break;
            }
            let due = self
                .outputs
                .all()
                .iter()
                .map(|o| o.next_due())
                .fold(f64::INFINITY, f64::min);
            let target = self.t_end.min(now + quantum).min(due);
            if let Err(e) = drive::advance(self.engine.sim_mut(), self.drive.as_ref(), target) {
                // What was written stays readable; no checkpoint of a failed state.
                for o in self.outputs.all() {
                    o.sync()?;
                }
                return Err(anyhow::anyhow!(e))
                    .with_context(|| format!("stopped at t = {:e} s", self.engine.sim().time()));
            }
            self.write_due(tolerance)?;
            let t = self.engine.sim().time();
            observer.progress(&self.engine, (t - t_start) / span);
            if !cost_noted && let Some(note) = self.checkpoint_cost(clock) {
                observer.note(&note);
                cost_noted = true;
            }
        }
        let wall_seconds = clock.elapsed().as_secs_f64();
        for o in self.outputs.all() {
            o.finish(&self.engine, end)?;
        }
        let mut means = observe::since(self.engine.sim(), Some(&start));
        means.sonine_a2 = self
            .outputs
            .log
            .as_ref()
            .map_or(f64::NAN, |l| l.mean_sonine_a2());
        Ok(Outcome {
            first,
            means,
            last: self.engine.sim().thermo(),
            work: self.engine.sim().steps_done() - work_start,
            wall_seconds,
            stopped_by: match end {
                End::Stopped => stop::requested(),
                End::Complete => None,
            },
        })
    }

    /// Lets every output due now write: the records first, then (after syncing them)
    /// a checkpoint.
    fn write_due(&mut self, tolerance: f64) -> Result<()> {
        let t = self.engine.sim().time();
        let mut outputs = self.outputs.all();
        let (mut saves, mut logged) = (false, false);
        for o in outputs.iter_mut() {
            if o.next_due() <= t + tolerance {
                if o.saves_state() {
                    saves = true;
                } else {
                    o.write(&self.engine)?;
                    logged |= o.name() == "log";
                }
            }
        }
        if logged {
            // The log's next interval starts here (the mark goes into checkpoints; a
            // last line that was not due leaves it, as a resumed run cuts that line).
            self.engine.sim_mut().mark_stress();
        }
        if saves {
            for o in outputs.iter_mut() {
                o.sync()?;
            }
            for o in outputs.iter_mut() {
                if o.saves_state() && o.next_due() <= t + tolerance {
                    o.write(&self.engine)?;
                }
            }
        }
        Ok(())
    }

    /// A note if checkpoints have taken more than half of the run's time so far (after
    /// ten of them and two seconds).
    fn checkpoint_cost(&self, clock: Instant) -> Option<String> {
        let (count, seconds) = self.outputs.checkpoint.cost();
        let elapsed = clock.elapsed().as_secs_f64();
        (count >= 10 && elapsed >= 2.0 && seconds > 0.5 * elapsed).then(|| {
            format!(
                "checkpoints took {:.0} % of the run's {elapsed:.1} s so far ({count} written): \
                 raise output.restart_interval",
                100.0 * seconds / elapsed
            )
        })
    }
}
