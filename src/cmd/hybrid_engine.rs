//! `emdstar run --engine hybrid`: MD where the gas is dense, eMD* where it is dilute
//! (crate emdstar-hybrid), on the same config, state and writers as the other engines.

use super::engine::{drift_fields, md_options, progress_bar, with_fields};
use super::run::RunArgs;
use anyhow::{Result, bail};
use clap::Args;
use emdstar_dem::{ContactEnd, DEFAULT_DT_FRACTION};
use emdstar_hybrid::{Hybrid, HybridOptions, HybridStats, Mode};
use emdstar_system::{ThermoLog, XyzWriter};
use serde_json::{Value, json};
use std::time::Instant;

/// Options of the hybrid engine.
#[derive(Args, Debug, Clone)]
pub struct HybridArgs {
    /// Hybrid: local volume fraction from which a particle is time-driven.
    #[arg(long, value_name = "PHI", default_value_t = 0.2)]
    pub phi_time: f64,
    /// Hybrid: local volume fraction below which a contact-free particle returns to
    /// event-driven (≤ --phi-time; 0 and 0 make every particle time-driven, i.e. MD).
    #[arg(long, value_name = "PHI", default_value_t = 0.1)]
    pub phi_event: f64,
    /// Hybrid: events of one particle within one time step above which it becomes
    /// time-driven (inelastic collapse, resting contacts).
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub max_events_per_step: u32,
    /// Hybrid: keep the Verlet list and its rebuilds even while no particle is
    /// time-driven, instead of event-driven cell crossings (the same physics; slower in
    /// dilute phases; for comparisons).
    #[arg(long)]
    pub no_cells: bool,
}

fn stats_json(s: &HybridStats) -> Value {
    json!({
        "steps": s.steps,
        "neighbour_rebuilds": s.rebuilds,
        "cell_mode_checks": s.cell_passes,
        "cell_crossings": s.crossings,
        "events": s.events,
        "collisions": s.pair_collisions,
        "wall_collisions": s.wall_collisions,
        "velocity_events": s.velocity_events,
        "exceptions": {
            "rotation_impossible": s.exception_rotation,
            "interference": s.exception_interference,
        },
        "mor_fallbacks": s.mor_fallbacks,
        "switches": {
            "to_time_driven": s.to_time,
            "to_event_driven": s.to_event,
            "guard": s.guard_conversions,
            "guard_late": s.late_conversions,
            "guard_late_max_overlap": s.max_late_overlap,
            "event_budget": s.budget_conversions,
            "transients_ended_early": s.early_transient_ends,
        },
        "time_driven_particle_steps": s.td_particle_steps,
    })
}

/// Runs the config of `args` with the hybrid engine: progress bar, trajectory and
/// thermo log, and a summary JSON with the mode counts over time.
pub fn run(args: &RunArgs) -> Result<()> {
    let (config, system) = super::engine::load(&args.config)?;
    let out = super::run::run_outputs(args, &config);
    let (md, steps) = md_options(&config, &system, &args.md, DEFAULT_DT_FRACTION)?;
    if md.contact_end != ContactEnd::ForceZero {
        bail!(
            "the hybrid engine needs contact_end = \"force\" (F = max(0, …)): its mode switches \
             rely on the force staying zero at the end of an eMD* contact"
        );
    }
    let every = |interval: f64, name: &str| -> Result<u64> {
        if !(interval.is_finite() && interval > 0.0) {
            bail!("output.{name} = {interval} must be a finite number greater than zero");
        }
        Ok(((interval / md.dt).round() as u64).clamp(1, steps))
    };
    let traj_every = every(out.trajectory_interval, "trajectory_interval")?;
    let log_every = every(out.log_interval, "log_interval")?;
    let opts = HybridOptions {
        skin: md.skin,
        phi_time: args.hybrid.phi_time,
        phi_event: args.hybrid.phi_event,
        max_events_per_step: args.hybrid.max_events_per_step,
        cells: !args.hybrid.no_cells,
        ..HybridOptions::with_dt(md.dt)
    };
    let mor = super::edmd_engine::mor_source(&system, &args.edmd)?;
    let n = system.particles.len();
    let sim_box = system.domain.sim_box;
    let mut engine = Hybrid::new(system, opts, mor, config.t_end)?;
    let mut traj = XyzWriter::create(&out.trajectory)?;
    let mut log = ThermoLog::create(&out.log)?;
    let first = engine.thermo();
    log.write(&first)?;
    traj.write_frame(0.0, &engine.particles(), sim_box.as_ref())?;
    let bar = progress_bar(
        out.quiet,
        steps,
        "{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta} {msg}",
    );
    let start = Instant::now();
    let mode_point = |e: &Hybrid, wall: f64| {
        json!({"t": e.time(), "event_driven": e.count(Mode::Event),
               "time_driven": e.count(Mode::Time), "wall_time_s": wall})
    };
    let mut modes = vec![mode_point(&engine, 0.0)];
    let mut last = first;
    while engine.steps() < steps {
        let done = engine.steps();
        let next = [traj_every, log_every]
            .map(|k| (done / k + 1) * k)
            .into_iter()
            .chain([steps])
            .min()
            .expect("non-empty");
        engine.advance(next - done)?;
        bar.set_position(engine.steps());
        let at_end = engine.steps() == steps;
        if engine.steps() % log_every == 0 || at_end {
            last = engine.thermo();
            log.write(&last)?;
            modes.push(mode_point(&engine, start.elapsed().as_secs_f64()));
            bar.set_message(format!(
                "{} event-driven, {} time-driven",
                engine.count(Mode::Event),
                engine.count(Mode::Time)
            ));
        }
        if engine.steps() % traj_every == 0 || at_end {
            traj.write_frame(engine.time(), &engine.particles(), sim_box.as_ref())?;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    traj.flush()?;
    log.flush()?;
    let total_mass = engine.system().particles.total_mass();
    let summary = with_fields(
        json!({
            "engine": "hybrid",
            "particles": n,
            "t": engine.time(),
            "steps": engine.steps(),
            "dt": md.dt,
            "skin": engine.skin(),
            "neighbour_rebuilds": engine.stats().rebuilds,
            "threads": 1,
            "wall_time_s": wall,
            "particle_steps_per_s": n as f64 * steps as f64 / wall,
            "collisions_per_s": engine.stats().pair_collisions as f64 / wall,
            "stats": stats_json(engine.stats()),
            "mode_counts": modes,
            "trajectory": out.trajectory,
            "log": out.log,
        }),
        drift_fields(&first, &last, total_mass),
    );
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
