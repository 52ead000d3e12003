//! `emdstar run`: simulate a gas with any engine, writing a trajectory, a thermo log
//! and checkpoints, and printing a summary.

use super::any_engine::EngineReport;
use super::engine::{drift_fields, load, progress_bar, with_fields};
use super::run_loop::{Plan, Ticks, Trajectory, drive};
use super::stop::StopFlags;
use anyhow::{Context, Result, bail};
use clap::Args;
use emdstar_dem::DEFAULT_DT_FRACTION;
use emdstar_engines::{AnyEngine, EngineOptions};
use emdstar_system::gsd::GsdWriter;
use emdstar_system::{Checkpoint, Config, Cut, ThermoLog, XyzWriter};
use serde_json::{Map, Value, json};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Simulate a gas: progress bar, trajectory, thermo log, checkpoints and a summary JSON.
///
/// Simulates the system of CONFIG up to t_end with the chosen engine. Writes an
/// extended-XYZ trajectory (for OVITO) and a thermo log, shows a progress bar on a
/// terminal, and prints a summary JSON: wall time, rates, energy and momentum drift,
/// the engine's counters.
///
/// Files default to CONFIG's stem + .xyz / .log in the current directory ([output] in
/// the config or --trajectory/--log override them; a trajectory ending in .gsd is
/// written in the binary GSD format, which OVITO also reads and which takes a fifth of
/// the space; --trajectory none writes none);
/// frames are written every t_end/20 and log lines every t_end/100 of the config's
/// t_end unless [output] says otherwise. The log is written line by line, so it is
/// readable while the run goes on.
///
/// Restarts: --checkpoint FILE writes the whole state when the run ends (and every
/// [output] restart_interval); --resume FILE continues a run from its checkpoint, with
/// the same config and engine options, appending to its trajectory and log after
/// cutting off what the run wrote after the checkpoint (if it was killed: frames, log
/// lines, and a last one left unfinished). A run stopped, or killed, and resumed ends in
/// bitwise the same state, with the same files, as one that ran through. With
/// --t-end a run stops earlier or goes on later than the config's t_end.
///
/// Before it starts, a run is refused if its particles seem not to fit into the free
/// memory (about 500 bytes each) or its trajectory not onto its disk; --force starts
/// it anyway. A full disk during the run stops it with the file named; what was
/// written is kept.
///
/// Ctrl-C (SIGINT) or SIGTERM stop the run at the next step or event: the log and
/// trajectory are closed whole, a checkpoint is written (to --checkpoint, or next to
/// the trajectory), and the summary says "interrupted"; the exit code is 130 or 143.
///
/// Example:
///   emdstar run examples/configs/cooling_hertz_gas.toml --engine emdstar
///   emdstar run gas.toml --engine md --t-end 0.5 --checkpoint half.ckpt
///   emdstar run gas.toml --engine md --resume half.ckpt
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct RunArgs {
    /// The TOML config.
    pub config: PathBuf,
    #[command(flatten)]
    pub engine: EngineOptions,
    /// Trajectory file: extended XYZ, or GSD for a name ending in .gsd, or "none".
    #[arg(long, value_name = "PATH")]
    pub trajectory: Option<PathBuf>,
    /// Thermo log file.
    #[arg(long, value_name = "PATH")]
    pub log: Option<PathBuf>,
    /// Stop at this time (s) instead of the config's t_end (which still sets the
    /// default output intervals and the time step).
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// Write a checkpoint here when the run ends (and every [output] restart_interval).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Continue the run saved in this checkpoint.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Worker threads [default: all cores]; results do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Start even if the particles seem not to fit into the free memory or the
    /// trajectory into the free disk space (both are checked before the run starts).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: &RunArgs) -> Result<ExitCode> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("starting the worker threads")?;
    let threads = pool.current_num_threads();
    pool.install(|| simulate(args, threads))
}

/// A positive, finite interval of `[output]`, or the default.
fn interval(value: Option<f64>, default: f64, name: &str) -> Result<f64> {
    let x = value.unwrap_or(default);
    if !(x.is_finite() && x > 0.0) {
        bail!("output.{name} = {x} must be a finite number greater than zero");
    }
    Ok(x)
}

/// `--path` over the config's `[output]` over CONFIG's stem with `extension`.
fn output_path(
    arg: &Option<PathBuf>,
    config_value: &Option<String>,
    config: &Path,
    extension: &str,
) -> PathBuf {
    let stem = config
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    arg.clone()
        .or(config_value.as_ref().map(PathBuf::from))
        .unwrap_or_else(|| format!("{stem}.{extension}").into())
}

/// Tells on stderr what resuming cut off the end of `path` (`record` names one record),
/// and notes it in `cuts` under `key` for the summary.
fn report_cut(cuts: &mut Map<String, Value>, key: &str, path: &Path, record: &str, cut: Cut) {
    cuts.insert(key.into(), json!(cut));
    if cut.records > 0 {
        eprintln!(
            "{}: cut {} {record}{} written after the checkpoint (the run went on after it)",
            path.display(),
            cut.records,
            if cut.records == 1 { "" } else { "s" }
        );
    }
    if cut.partial_bytes > 0 {
        eprintln!(
            "{}: cut an unfinished last {record} of {} bytes (the run was killed while \
             writing it)",
            path.display(),
            cut.partial_bytes
        );
    }
}

/// Restores `engine` from the checkpoint at `path`, refusing one of another engine,
/// options or config.
fn resume(engine: &mut AnyEngine, path: &Path, config: &Config) -> Result<f64> {
    let ckpt = Checkpoint::read(path)?;
    let sim = engine.sim();
    if ckpt.engine != sim.engine() {
        bail!(
            "{} was written by the {} engine; resume it with --engine {} (this run uses {})",
            path.display(),
            ckpt.engine,
            ckpt.engine,
            sim.engine()
        );
    }
    if ckpt.options != engine.options_tag() {
        bail!(
            "{} was written with the MoR source '{}', this run uses '{}'; give the same --mor \
             and --table as the run that wrote it",
            path.display(),
            ckpt.options,
            engine.options_tag()
        );
    }
    if ckpt.config_digest != config.digest() {
        bail!(
            "{} belongs to another system than this config describes (the particles, \
             material, box, walls, gravity or [md] differ); resume it with the config it was \
             written from (only t_end and [output] may change)",
            path.display()
        );
    }
    engine
        .sim_mut()
        .restore_state(&ckpt.state)
        .map_err(|e| anyhow::anyhow!("restoring {}: {e}", path.display()))?;
    Ok(ckpt.time)
}

fn simulate(args: &RunArgs, threads: usize) -> Result<ExitCode> {
    let (config, system) = load(&args.config, args.force)?;
    let n = system.particles.len();
    let species = system.species.len();
    let total_mass = system.particles.total_mass();
    let mut engine = AnyEngine::build(&args.engine, &config, system, DEFAULT_DT_FRACTION)?;
    let resumed_at = match &args.resume {
        Some(path) => Some(resume(&mut engine, path, &config)?),
        None => None,
    };
    let t_end = args.t_end.unwrap_or(config.t_end);
    let t_now = engine.sim().time();
    if !(t_end.is_finite() && t_end > t_now) {
        bail!(
            "t_end = {t_end} s must lie after the start of the run (t = {t_now} s){}",
            if resumed_at.is_some() {
                "; give a later --t-end"
            } else {
                ""
            }
        );
    }
    let output = config.output.clone().unwrap_or_default();
    let step = engine.sim().time_step();
    let fresh = resumed_at.is_none();
    // What resuming cut off the files' ends (written after the checkpoint).
    let mut cuts = Map::new();
    let traj_path = output_path(&args.trajectory, &output.trajectory, &args.config, "xyz");
    let trajectory = if traj_path == Path::new("none") {
        None
    } else {
        let every = interval(
            output.trajectory_interval,
            config.t_end / 20.0,
            "trajectory_interval",
        )?;
        let gsd = traj_path.extension().is_some_and(|e| e == "gsd");
        let ticks = Ticks::new(every, step, t_now, fresh);
        let frames = ((t_end - t_now) / ticks.interval()).floor() + 2.0;
        let bytes = frames * Trajectory::frame_bytes(gsd, n, species) as f64;
        super::resources::check_disk(&traj_path, bytes, args.force)?;
        if n >= 100_000 || bytes > 1e8 {
            eprintln!(
                "trajectory {}: about {frames:.0} frames of {n} particles, {:.1} GB{}",
                traj_path.display(),
                bytes / 1e9,
                if gsd {
                    ""
                } else {
                    " of text; a .gsd file takes a fifth of that (OVITO reads both), \
                     --trajectory none writes none"
                }
            );
        }
        let writer = match (gsd, fresh) {
            (false, true) => Trajectory::Xyz(XyzWriter::create(&traj_path)?),
            (false, false) => {
                let (writer, cut) = XyzWriter::resume(&traj_path, t_now, n)?;
                report_cut(&mut cuts, "trajectory", &traj_path, "frame", cut);
                Trajectory::Xyz(writer)
            }
            (true, true) => Trajectory::Gsd {
                writer: GsdWriter::create(&traj_path)?,
                species,
            },
            (true, false) => {
                let (writer, cut) = GsdWriter::resume(&traj_path, t_now, n, species)?;
                report_cut(&mut cuts, "trajectory", &traj_path, "frame", cut);
                Trajectory::Gsd { writer, species }
            }
        };
        Some((traj_path.clone(), writer, ticks))
    };
    let log_path = output_path(&args.log, &output.log, &args.config, "log");
    let log_every = interval(output.log_interval, config.t_end / 100.0, "log_interval")?;
    let log = if fresh {
        ThermoLog::create(&log_path)?
    } else {
        let (log, cut) = ThermoLog::resume(&log_path, t_now)?;
        report_cut(&mut cuts, "log", &log_path, "line", cut);
        log
    };
    let restart_every = output
        .restart_interval
        .map(|x| interval(Some(x), x, "restart_interval"))
        .transpose()?;
    let checkpoint_path = args
        .checkpoint
        .clone()
        .or_else(|| restart_every.map(|_| traj_path.with_extension("ckpt")));
    let mut plan = Plan {
        t_end,
        trajectory,
        log: (
            log_path.clone(),
            log,
            Ticks::new(log_every, step, t_now, fresh),
        ),
        checkpoint: checkpoint_path.clone().map(|p| {
            (
                p,
                restart_every.map(|every| Ticks::new(every, step, t_now, false)),
            )
        }),
        config_digest: config.digest(),
        fresh,
    };
    let bar = progress_bar(
        args.quiet,
        1000,
        "{bar:40} {percent}% of the run, {elapsed} elapsed, eta {eta} {msg}",
    );
    let stop = StopFlags::install()?;
    let outcome = drive(&mut engine, &mut plan, &bar, &stop)?;
    bar.finish_and_clear();
    let mut outcome = outcome;
    if let Some(signal) = outcome.interrupted
        && outcome.checkpoint_written.is_none()
    {
        // Stopped without --checkpoint: save next to the trajectory (or the log).
        let base = if traj_path == Path::new("none") {
            &log_path
        } else {
            &traj_path
        };
        let path = base.with_extension("ckpt");
        super::run_loop::write_checkpoint(&engine, &path, plan.config_digest)?;
        eprintln!(
            "{}: stopped at t = {} s; resume with `--resume {}`",
            signal.name(),
            engine.sim().time(),
            path.display()
        );
        outcome.checkpoint_written = Some(path);
    }
    let fallbacks = engine.mor_fallbacks();
    if fallbacks > 0 {
        eprintln!(
            "note: {fallbacks} impacts lay outside the MoR table's box and were solved exactly \
             (`--mor table` makes them errors)"
        );
    }
    let mut summary = json!({
        "engine": engine.sim().engine(),
        "particles": n,
        "t": engine.sim().time(),
        "wall_time_s": outcome.wall_seconds,
        "trajectory": plan.trajectory.as_ref().map(|(p, _, _)| p.clone()),
        "log": log_path,
        "interrupted": outcome.interrupted.is_some(),
        "resumed_from": resumed_at,
        "cut_at_resume": resumed_at.map(|_| cuts),
        "checkpoint": outcome.checkpoint_written,
    });
    summary = with_fields(
        summary,
        engine.summary_fields(outcome.wall_seconds, outcome.work, threads),
    );
    if !outcome.mode_counts.is_empty() {
        summary = with_fields(summary, json!({ "mode_counts": outcome.mode_counts }));
    }
    summary = with_fields(summary, json!({ "mor_fallbacks": fallbacks }));
    summary = with_fields(
        summary,
        drift_fields(&outcome.first, &outcome.last, total_mass),
    );
    let text = serde_json::to_string_pretty(&summary)?;
    // The files are complete by now: a reader of stdout that has left misses only this.
    if let Err(e) = writeln!(std::io::stdout().lock(), "{text}") {
        if e.kind() != std::io::ErrorKind::BrokenPipe {
            return Err(e.into());
        }
    }
    Ok(match outcome.interrupted {
        Some(signal) => ExitCode::from(signal.exit_code()),
        None => ExitCode::SUCCESS,
    })
}
