//! `emdstar pair|run --engine emd|emdstar`: the event-driven engine behind the commands
//! MD uses, on the same config, state and writers.

use super::engine::Engine as EngineKind;
use super::engine::{drift_fields, progress_bar, with_fields};
use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{BroadPhaseKind, Engine, Interference, Materials, Physics, Stats};
use emdstar_system::{Config, System, Thermo, ThermoLog, XyzWriter};
use emdstar_table::Table;
use serde_json::{Value, json};
use std::path::PathBuf;
use std::time::Instant;

/// Where eMD* takes the matrix of restitution from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MorChoice {
    /// The lookup table (--table, or the default table embedded in the program);
    /// impacts outside its box are an error.
    Table,
    /// The table, with impacts outside its box solved exactly (and counted).
    TableOrExact,
    /// The exact solver for every collision (slow, exact).
    Exact,
}

/// Which pending E^v events run early when a third particle interferes (exception b).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InterferenceChoice {
    /// Only the particle that is hit (Müller & Pöschel's default).
    Hit,
    /// Both partners of the interrupted collision.
    Both,
}

/// How the event engine finds the pairs it tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum BroadPhaseChoice {
    /// Epochs in dilute gases without gravity (packing fraction below 0.02) that are
    /// periodic or held by walls along every axis, cell crossings otherwise.
    Auto,
    /// A cell grid with a crossing event whenever a particle changes cell.
    Crossings,
    /// Swept boxes filed once per epoch (no gravity; along periodic axes a box at
    /// least four times the sum of the largest contact distance and a cell width). A
    /// gas that spreads into free space runs far slower on epochs than on crossings.
    Epochs,
}

/// Options of the event-driven engines (emd, emdstar).
#[derive(Args, Debug, Clone)]
pub struct EdmdArgs {
    /// eMD*: source of the matrix of restitution.
    #[arg(long, value_enum, default_value_t = MorChoice::Table)]
    pub mor: MorChoice,
    /// eMD*: a MoR table file instead of the default one.
    #[arg(long, value_name = "FILE")]
    pub table: Option<PathBuf>,
    /// eMD*: exception (b) variant.
    #[arg(long, value_enum, default_value_t = InterferenceChoice::Hit)]
    pub interference: InterferenceChoice,
    /// How candidate pairs are found (the same collisions either way; epochs are
    /// about 2.8 times faster at packing fraction 0.001, crossings win above about
    /// 0.02).
    #[arg(long, value_enum, default_value_t = BroadPhaseChoice::Auto)]
    pub broad_phase: BroadPhaseChoice,
}

impl From<BroadPhaseChoice> for BroadPhaseKind {
    fn from(choice: BroadPhaseChoice) -> Self {
        match choice {
            BroadPhaseChoice::Auto => BroadPhaseKind::Auto,
            BroadPhaseChoice::Crossings => BroadPhaseKind::Crossings,
            BroadPhaseChoice::Epochs => BroadPhaseKind::Epochs,
        }
    }
}

/// The event engine for `system` with the options of `args`.
fn build_engine(kind: EngineKind, system: &System, args: &EdmdArgs) -> Result<Engine> {
    let physics = physics(kind, system, args)?;
    Ok(Engine::with_broad_phase(
        &system.particles,
        &system.domain,
        physics,
        args.broad_phase.into(),
    )?)
}

/// The source of the matrix of restitution chosen by `args` (eMD* and the hybrid).
pub fn mor_source(system: &System, args: &EdmdArgs) -> Result<Box<dyn MorSource>> {
    let model = system.material.model();
    let fallback = args.mor == MorChoice::TableOrExact;
    Ok(match (args.mor, &args.table) {
        (MorChoice::Exact, _) => Box::new(ExactMor),
        (_, Some(path)) => {
            let table = Table::open(path)
                .with_context(|| format!("reading the MoR table {}", path.display()))?;
            Box::new(TableMorSource::from_table(table, fallback))
        }
        (_, None) => Box::new(TableMorSource::default_for(model, fallback)?),
    })
}

fn physics(kind: EngineKind, system: &System, args: &EdmdArgs) -> Result<Physics> {
    let materials = Materials::from_system(system)?;
    Ok(match kind {
        EngineKind::Emd => Physics::Emd(materials),
        EngineKind::EmdStar => Physics::EmdStar {
            materials,
            mor: mor_source(system, args)?,
            interference: match args.interference {
                InterferenceChoice::Hit => Interference::HitOnly,
                InterferenceChoice::Both => Interference::BothPartners,
            },
        },
        EngineKind::Md | EngineKind::Hybrid => bail!("this engine is not purely event-driven"),
    })
}

fn engine_name(kind: EngineKind) -> &'static str {
    match kind {
        EngineKind::Emd => "emd",
        EngineKind::EmdStar => "emdstar",
        EngineKind::Md => "md",
        EngineKind::Hybrid => "hybrid",
    }
}

/// Runs the particles of `system` to t_end and prints them in config order, in the
/// format of the MD `pair` command.
pub fn pair(
    config: &Config,
    mut system: System,
    kind: EngineKind,
    args: &EdmdArgs,
    as_json: bool,
) -> Result<()> {
    let mut engine = build_engine(kind, &system, args)?;
    engine.run_until(config.t_end)?;
    engine.write_state(&mut system.particles);
    let p = &system.particles;
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.id[i]);
    if as_json {
        let particles: Vec<_> = order
            .iter()
            .map(|&i| json!({"position": p.position[i], "velocity": p.velocity[i]}))
            .collect();
        let out = json!({
            "engine": engine_name(kind),
            "t": engine.time(),
            "particles": particles,
            "stats": stats_json(engine.stats()),
        });
        println!("{out}");
    } else {
        println!("engine {}, t = {} s", engine_name(kind), engine.time());
        for (k, &i) in order.iter().enumerate() {
            println!(
                "particle {k}: position {:?} m, velocity {:?} m/s",
                p.position[i], p.velocity[i]
            );
        }
    }
    Ok(())
}

fn stats_json(s: &Stats) -> Value {
    json!({
        "events": s.events,
        "collisions": s.pair_collisions,
        "wall_collisions": s.wall_collisions,
        "stabilising_collisions": s.stabilising,
        "cell_crossings": s.crossings,
        "epochs": s.epochs,
        "stale_events": s.stale,
        "velocity_events": s.velocity_events,
        "exceptions": {
            "rotation_impossible": s.exception_rotation,
            "interference": s.exception_interference,
            "interference_partner_updates": s.early_partner_updates,
            "interference_no_longer_approaching": s.interference_resolved,
        },
        "fallbacks": {
            "emd_rule": s.exception_rotation,
            "exact_mor": s.mor_fallbacks,
        },
        "max_impact_overlap": s.max_impact_overlap,
    })
}

fn thermo(engine: &mut Engine, system: &System) -> Thermo {
    engine.sync();
    let v = engine.settled_velocities();
    let x = engine.positions();
    let p = &system.particles;
    let mut momentum = [0.0; 3];
    let mut kinetic = 0.0;
    let mut potential = 0.0;
    for i in 0..p.len() {
        let m = p.mass[i];
        for k in 0..3 {
            momentum[k] += m * v[i][k];
            potential -= m * system.domain.gravity[k] * x[i][k];
        }
        kinetic += 0.5 * m * (v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
    }
    let total: f64 = p.mass.iter().sum();
    let vcm: [f64; 3] = std::array::from_fn(|k| momentum[k] / total);
    let peculiar: f64 = (0..p.len())
        .map(|i| {
            let d: [f64; 3] = std::array::from_fn(|k| v[i][k] - vcm[k]);
            p.mass[i] * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        })
        .sum();
    Thermo {
        t: engine.time(),
        step: engine.stats().events,
        kinetic_energy: kinetic,
        potential_energy: potential,
        granular_temperature: if p.is_empty() {
            0.0
        } else {
            peculiar / (3.0 * p.len() as f64)
        },
        momentum,
        contacts: 0,
    }
}

/// Paths and intervals of `run`'s outputs.
pub struct RunOutputs {
    pub trajectory: PathBuf,
    pub log: PathBuf,
    pub trajectory_interval: f64,
    pub log_interval: f64,
    pub quiet: bool,
}

/// `run` with an event-driven engine: progress bar, trajectory and thermo log at fixed
/// simulation times, and a summary JSON.
pub fn run(
    config: &Config,
    mut system: System,
    kind: EngineKind,
    args: &EdmdArgs,
    out: &RunOutputs,
) -> Result<()> {
    for (name, x) in [
        ("trajectory_interval", out.trajectory_interval),
        ("log_interval", out.log_interval),
    ] {
        if !(x.is_finite() && x > 0.0) {
            bail!("output.{name} = {x} must be a finite number greater than zero");
        }
    }
    let n = system.particles.len();
    let mut engine = build_engine(kind, &system, args)?;
    let mut traj = XyzWriter::create(&out.trajectory)?;
    let mut log = ThermoLog::create(&out.log)?;
    let first = thermo(&mut engine, &system);
    log.write(&first)?;
    engine.write_state(&mut system.particles);
    traj.write_frame(0.0, &system.particles, system.domain.sim_box.as_ref())?;
    let t_end = config.t_end;
    let bar = progress_bar(
        out.quiet,
        1000,
        "{bar:40} {percent}% of t_end, {elapsed} elapsed, eta {eta} {msg}",
    );
    let start = Instant::now();
    let (mut next_traj, mut next_log) = (out.trajectory_interval, out.log_interval);
    let mut last = first;
    loop {
        let target = next_traj
            .min(next_log)
            .min(t_end)
            .min(engine.time() + t_end / 1000.0);
        engine.run_until(target)?;
        bar.set_position((1000.0 * engine.time() / t_end) as u64);
        let done = engine.time() >= t_end;
        if engine.time() >= next_log || done {
            last = thermo(&mut engine, &system);
            log.write(&last)?;
            next_log += out.log_interval;
            bar.set_message(format!(
                "T = {:.3e} J, {} collisions",
                last.granular_temperature,
                engine.stats().collisions()
            ));
        }
        if engine.time() >= next_traj || done {
            engine.write_state(&mut system.particles);
            traj.write_frame(
                engine.time(),
                &system.particles,
                system.domain.sim_box.as_ref(),
            )?;
            next_traj += out.trajectory_interval;
        }
        if done {
            break;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    bar.finish_and_clear();
    traj.flush()?;
    log.flush()?;
    let total_mass: f64 = system.particles.mass.iter().sum();
    let s = engine.stats();
    let summary = with_fields(
        json!({
            "engine": engine_name(kind),
            "particles": n,
            "t": engine.time(),
            "wall_time_s": wall,
            "collisions_per_s": s.collisions() as f64 / wall,
            "stats": stats_json(s),
            "trajectory": out.trajectory,
            "log": out.log,
        }),
        drift_fields(&first, &last, total_mass),
    );
    println!("{}", serde_json::to_string_pretty(&summary)?);
    Ok(())
}
