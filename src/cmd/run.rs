//! `emdstar run`: simulate a gas with any engine, writing a trajectory, a thermo log
//! and checkpoints, and printing a summary.

use super::any_engine::EngineReport;
use super::engine::{drift_fields, load, progress_bar, with_fields};
use anyhow::{Context, Result, bail};
use clap::Args;
use emdstar_dem::DEFAULT_DT_FRACTION;
use emdstar_engines::output::TrajectoryFormat;
use emdstar_engines::run::{Observer, Run, RunFiles};
use emdstar_engines::{AnyEngine, EngineOptions};
use emdstar_system::Cut;
use indicatif::ProgressBar;
use serde_json::{Map, Value, json};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Simulate a gas: progress bar, trajectory, thermo log, checkpoints and a summary JSON.
///
/// Simulates the system of CONFIG up to t_end with the chosen engine. Writes an
/// extended-XYZ trajectory (for OVITO) and a thermo log, shows a progress bar on a
/// terminal, and prints a summary JSON: wall time, rates, energy and momentum drift,
/// the engine's counters, and the run's means of the pressure tensor, collision rate
/// and Sonine coefficient a2 ("means"). Each log line ends with those of the interval
/// since the line before: pressure[Pa], pxx..pyz[Pa] (kinetic plus collisional;
/// walls and gravity are external and left out), collision_rate[1/s] (per particle)
/// and sonine_a2 (now); the first line has no interval (nan).
///
/// Files default to CONFIG's stem + .xyz / .log in the current directory ([output] in
/// the config or --trajectory/--log override them; a trajectory ending in .gsd is
/// written in the binary GSD format, which OVITO also reads and which takes a fifth of
/// the space; "none" writes no trajectory or no log); frames are written every
/// t_end/20 and log lines every t_end/100 of the config's t_end unless [output] says
/// otherwise, and a last frame and line when the run ends between two. The log is
/// written line by line, so it is readable while the run goes on.
///
/// Outputs are written only to regular files or new paths, never over an input (the
/// config, --table, the --resume file) or over another output of the run, and each is
/// locked while the run writes it, so that a second run writing the same files is
/// refused; --force does not override these rules.
///
/// Restarts: --checkpoint FILE writes the whole state when the run ends (and every
/// [output] restart_interval; that alone writes them next to the trajectory, .ckpt);
/// --resume FILE continues a run from its checkpoint, with the same config and engine
/// options, appending to its trajectory and log after cutting off what the run wrote
/// after the checkpoint (frames and log lines, and a last one left unfinished by a
/// kill) and a last frame or line written only because it stopped there. A run
/// stopped (Ctrl-C, SIGTERM, --t-end) or killed (SIGKILL), and resumed, ends in bitwise
/// the same state, with byte for byte the same log and trajectory, as one that ran
/// through. With --t-end a run stops earlier or goes on later than the config's t_end.
/// The checkpoint may be the --resume file, which it then replaces.
///
/// Before it starts, a run is refused if its particles seem not to fit into the free
/// memory (about 500 bytes each) or its trajectory and log not onto their disks;
/// --force starts it anyway. It says when an output interval is shorter than the time
/// step (one record per step) or when checkpoints may take longer than the
/// simulation. A full disk during the run stops it with the file named; what was
/// written is kept.
///
/// Ctrl-C (SIGINT) or SIGTERM stop the run at the next step or event, whatever the
/// output intervals: the log and trajectory are closed whole, a checkpoint is written
/// (to --checkpoint, or next to the trajectory), and the summary says "interrupted";
/// the exit code is 130 or 143. A second signal ends the process at once.
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
    /// Thermo log file, or "none".
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
    /// Worker threads [default: all cores; at most 4 per core]; results do not depend
    /// on it. MD splits its force loop over them; frictional eMD* solves the exact
    /// contacts of predicted collisions ahead on a second thread.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Start even if the particles seem not to fit into the free memory or the
    /// trajectory and log into the free disk space (both are checked before the run
    /// starts).
    #[arg(long)]
    pub force: bool,
}

pub fn run(args: &RunArgs) -> Result<ExitCode> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        check_threads(n)?;
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("starting the worker threads")?;
    let threads = pool.current_num_threads();
    pool.install(|| simulate(args, threads))
}

/// Worker threads beyond this many per core are refused.
const THREADS_PER_CORE: usize = 4;

/// Refuses `--threads n` below 1 or beyond [`THREADS_PER_CORE`] × the cores.
fn check_threads(n: usize) -> Result<()> {
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    if n == 0 {
        bail!("--threads must be at least 1");
    }
    if n > THREADS_PER_CORE * cores {
        bail!(
            "--threads {n} is more than {THREADS_PER_CORE} per core ({cores} cores here): more \
             threads than cores only share them, and starting that many takes long; give \
             --threads {cores} or fewer"
        );
    }
    Ok(())
}

/// The progress bar of a run, and its notes on stderr.
struct Progress {
    bar: ProgressBar,
    /// When the bar's note was last renewed.
    noted: Instant,
}

impl Observer for Progress {
    fn progress(&mut self, engine: &AnyEngine, fraction: f64) {
        self.bar.set_position((1000.0 * fraction) as u64);
        if self.noted.elapsed().as_secs_f64() > 0.5 {
            self.bar.set_message(engine.status());
            self.noted = Instant::now();
        }
    }

    fn note(&mut self, message: &str) {
        self.bar.suspend(|| eprintln!("note: {message}"));
    }
}

/// Tells on stderr what resuming cut off the end of `path` (`record` names one record).
fn report_cut(path: &Path, record: &str, cut: Cut) {
    if cut.records > 0 {
        eprintln!(
            "{}: cut {} {record}{} written after the checkpoint, or at it by a run that \
             stopped there (the resumed run writes them again)",
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

fn simulate(args: &RunArgs, threads: usize) -> Result<ExitCode> {
    let (config, system) = load(&args.config, args.force)?;
    let n = system.particles.len();
    let total_mass = system.particles.total_mass();
    for warning in emdstar_engines::unused_keys(&config, &args.engine) {
        eprintln!("warning: {warning}");
    }
    let engine = args.engine.engine;
    for warning in emdstar_engines::vibrated_wall_warnings(&config, &system, engine) {
        eprintln!("warning: {warning}");
    }
    let engine = AnyEngine::build(&args.engine, &config, system, DEFAULT_DT_FRACTION)?;
    let output = config.output.clone().unwrap_or_default();
    let files = RunFiles::resolve(
        &args.config,
        &output,
        args.trajectory.as_deref(),
        args.log.as_deref(),
        args.checkpoint.as_deref(),
    );
    for warning in emdstar_engines::unwritten_intervals(&config, &files) {
        eprintln!("warning: {warning}");
    }
    let mut inputs = vec![("the config", args.config.as_path())];
    if let Some(table) = &args.engine.edmd.table {
        inputs.push(("the MoR table (--table)", table.as_path()));
    }
    // From here on a signal stops the run cleanly (before, it ends the process: nothing
    // is written yet).
    super::stop::install()?;
    let mut run = Run::prepare(
        engine,
        &config,
        &files,
        &inputs,
        args.resume.as_deref(),
        args.t_end,
    )?;
    for note in run.notes() {
        eprintln!("note: {note}");
    }
    super::resources::check_outputs(run.estimates(), args.force)?;
    for e in run.estimates().iter().filter(|e| e.what != "checkpoint") {
        if n >= 100_000 || e.bytes > 1e8 {
            let advice = match e.what {
                "trajectory" if TrajectoryFormat::of(&e.path) == TrajectoryFormat::Xyz => {
                    "; a .gsd file takes a fifth of that (OVITO reads both), --trajectory none \
                     writes none"
                }
                _ => "",
            };
            eprintln!("{} of {n} particles{advice}", e.describe());
        }
    }
    run.start()?;
    let mut cuts = Map::new();
    for (name, path, cut) in run.cuts() {
        report_cut(path, if *name == "log" { "line" } else { "frame" }, *cut);
        cuts.insert((*name).into(), json!(cut));
    }
    let mut progress = Progress {
        bar: progress_bar(
            args.quiet,
            1000,
            "{bar:40} {percent}% of the run, {elapsed} elapsed, eta {eta} {msg}",
        ),
        noted: Instant::now(),
    };
    let outcome = run.drive(&mut progress)?;
    progress.bar.finish_and_clear();
    let engine = run.engine();
    if let Some(signal) = outcome.stopped_by {
        eprintln!(
            "{}: stopped at t = {:e} s; resume with `--resume {}`",
            super::stop::name(signal),
            engine.sim().time(),
            files.checkpoint_path().display()
        );
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
        "trajectory": files.trajectory,
        "log": files.log,
        "interrupted": outcome.stopped_by.is_some(),
        "resumed_from": run.resumed_at(),
        "cut_at_resume": run.resumed_at().map(|_| cuts),
        "checkpoint": run.checkpoint_written(),
    });
    summary = with_fields(
        summary,
        engine.summary_fields(outcome.wall_seconds, outcome.work, threads),
    );
    let modes: Vec<Value> = run
        .mode_points()
        .iter()
        .map(|p| {
            json!({
                "t": p.t,
                "event_driven": p.event_driven,
                "time_driven": p.time_driven,
                "wall_time_s": p.wall_seconds,
            })
        })
        .collect();
    if !modes.is_empty() {
        summary = with_fields(summary, json!({ "mode_counts": modes }));
    }
    summary = with_fields(summary, json!({ "mor_fallbacks": fallbacks }));
    let m = &outcome.means;
    summary = with_fields(
        summary,
        json!({ "means": {
            "pressure_pa": finite(m.pressure),
            "pressure_tensor_pa": m.tensor.map(finite),
            "collision_rate_per_s": finite(m.collision_rate),
            "sonine_a2": finite(m.sonine_a2),
        }}),
    );
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
    Ok(match outcome.stopped_by {
        Some(signal) => ExitCode::from(super::stop::exit_code(signal)),
        None => ExitCode::SUCCESS,
    })
}

/// A number for JSON: null where it is not finite (no interval, no box, no log).
fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}
