//! `emdstar run`: simulate a gas, writing a trajectory and a thermo log.

use super::engine::{
    Engine, MdArgs, drift_fields, load, md_options, parse_engine, progress_bar, with_fields,
};
use anyhow::{Context, Result, bail};
use clap::Args;
use emdstar_dem::{DEFAULT_DT_FRACTION, Md};
use emdstar_system::{Thermo, ThermoLog, XyzWriter};
use serde_json::json;
use std::path::PathBuf;
use std::time::Instant;

/// Simulate a gas: progress bar, trajectory, thermo log and a summary JSON.
///
/// Simulates the system of CONFIG up to t_end. Writes an extended-XYZ trajectory (for
/// OVITO) and a thermo log, shows a progress bar on a terminal, and prints a summary
/// JSON: wall time, particle-steps per second, energy and momentum drift.
///
/// Files default to CONFIG's stem + .xyz / .log in the current directory ([output] in
/// the config or --trajectory/--log override them); frames are written every t_end/20
/// and log lines every t_end/100 unless [output] says otherwise.
#[derive(Args, Debug)]
pub struct RunArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// The engine: md, emd, emdstar or hybrid.
    #[arg(long, value_parser = parse_engine, default_value = "md")]
    pub engine: Engine,
    #[command(flatten)]
    pub md: MdArgs,
    #[command(flatten)]
    pub edmd: super::edmd_engine::EdmdArgs,
    #[command(flatten)]
    pub hybrid: super::hybrid_engine::HybridArgs,
    /// Trajectory file (extended XYZ).
    #[arg(long, value_name = "PATH")]
    pub trajectory: Option<PathBuf>,
    /// Thermo log file.
    #[arg(long, value_name = "PATH")]
    pub log: Option<PathBuf>,
    /// Worker threads [default: all cores]; results do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

pub fn run(args: &RunArgs) -> Result<()> {
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = args.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        pool = pool.num_threads(n);
    }
    let pool = pool.build().context("starting the worker threads")?;
    pool.install(|| match args.engine {
        Engine::Md => run_md(args, pool.current_num_threads()),
        Engine::Emd | Engine::EmdStar => run_edmd(args),
        Engine::Hybrid => super::hybrid_engine::run(args),
    })
}

fn run_edmd(args: &RunArgs) -> Result<()> {
    let (config, system) = load(&args.config)?;
    let outputs = run_outputs(args, &config);
    super::edmd_engine::run(&config, system, args.engine, &args.edmd, &outputs)
}

/// The output paths and intervals of a run (the command line over [output] over the
/// defaults).
pub(super) fn run_outputs(
    args: &RunArgs,
    config: &emdstar_system::Config,
) -> super::edmd_engine::RunOutputs {
    let output = config.output.clone().unwrap_or_default();
    let stem = args
        .config
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    super::edmd_engine::RunOutputs {
        trajectory: args
            .trajectory
            .clone()
            .or(output.trajectory.map(PathBuf::from))
            .unwrap_or_else(|| format!("{stem}.xyz").into()),
        log: args
            .log
            .clone()
            .or(output.log.map(PathBuf::from))
            .unwrap_or_else(|| format!("{stem}.log").into()),
        trajectory_interval: output.trajectory_interval.unwrap_or(config.t_end / 20.0),
        log_interval: output.log_interval.unwrap_or(config.t_end / 100.0),
        quiet: args.quiet,
    }
}

fn run_md(args: &RunArgs, threads: usize) -> Result<()> {
    let (config, system) = load(&args.config)?;
    let (opts, steps) = md_options(&config, &system, &args.md, DEFAULT_DT_FRACTION)?;
    let output = config.output.clone().unwrap_or_default();
    let stem = args
        .config
        .file_stem()
        .map_or("run".into(), |s| s.to_string_lossy().into_owned());
    let traj_path = args
        .trajectory
        .clone()
        .or(output.trajectory.map(PathBuf::from))
        .unwrap_or_else(|| format!("{stem}.xyz").into());
    let log_path = args
        .log
        .clone()
        .or(output.log.map(PathBuf::from))
        .unwrap_or_else(|| format!("{stem}.log").into());
    let every = |interval: Option<f64>, parts: f64, name: &str| -> Result<u64> {
        let interval = interval.unwrap_or(config.t_end / parts);
        if !(interval.is_finite() && interval > 0.0) {
            bail!("output.{name} = {interval} must be a finite number greater than zero");
        }
        Ok(((interval / opts.dt).round() as u64).clamp(1, steps))
    };
    let traj_every = every(output.trajectory_interval, 20.0, "trajectory_interval")?;
    let log_every = every(output.log_interval, 100.0, "log_interval")?;

    let n = system.particles.len();
    let mut md = Md::new(system, opts, config.t_end)?;
    let mut traj = XyzWriter::create(&traj_path)?;
    let mut log = ThermoLog::create(&log_path)?;
    let first = md.thermo();
    write_outputs(&md, &first, (&mut traj, true), (&mut log, true))?;

    let bar = progress_bar(
        args.quiet,
        steps,
        "{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta} {msg}",
    );
    let progress_every = (steps / 200).max(1);
    let start = Instant::now();
    let mut last = first;
    while md.steps() < steps {
        let done = md.steps();
        let next = [
            next_multiple(done, traj_every),
            next_multiple(done, log_every),
            next_multiple(done, progress_every),
            steps,
        ]
        .into_iter()
        .min()
        .expect("non-empty");
        md.advance(next - done)?;
        bar.set_position(md.steps());
        let at_traj = md.steps() % traj_every == 0 || md.steps() == steps;
        let at_log = md.steps() % log_every == 0 || md.steps() == steps;
        if at_traj || at_log {
            last = md.thermo();
            bar.set_message(format!(
                "T = {:.3e} J, contacts {}",
                last.granular_temperature, last.contacts
            ));
            write_outputs(&md, &last, (&mut traj, at_traj), (&mut log, at_log))?;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    traj.flush()?;
    log.flush()?;

    let total_mass = md.system().particles.total_mass();
    let summary = with_fields(
        json!({
            "engine": "md",
            "particles": n,
            "t": md.time(),
            "steps": md.steps(),
            "dt": opts.dt,
            "skin": md.skin(),
            "neighbour_rebuilds": md.rebuilds(),
            "threads": threads,
            "wall_time_s": wall,
            "particle_steps_per_s": n as f64 * steps as f64 / wall,
            "trajectory": traj_path,
            "log": log_path,
        }),
        drift_fields(&first, &last, total_mass),
    );
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}

fn next_multiple(done: u64, every: u64) -> u64 {
    (done / every + 1) * every
}

fn write_outputs(
    md: &Md,
    th: &Thermo,
    (traj, frame): (&mut XyzWriter, bool),
    (log, line): (&mut ThermoLog, bool),
) -> Result<()> {
    if line {
        log.write(th)?;
    }
    if frame {
        let s = md.system();
        traj.write_frame(th.t, &s.particles, s.domain.sim_box.as_ref())?;
    }
    Ok(())
}
