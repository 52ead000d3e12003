//! `emdstar bench edmd`: collisions per second of the event-driven engine.

use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use emdstar_contact::{ForceLaw, Model, Sphere, ViscoelasticHertz};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{Engine, Interference, Materials, Physics, Setup, gas};
use serde_json::{Value, json};
use std::f64::consts::PI;
use std::time::Instant;

/// Where the eMD* benchmark takes its MoR from.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MorArg {
    /// The default table (embedded), out-of-box impacts solved exactly and counted.
    Table,
    /// The exact solver, one ODE solve per collision.
    Exact,
}

#[derive(Args, Debug)]
pub struct BenchEdmdArgs {
    /// Collisions per particle to time (after as many to equilibrate).
    #[arg(long, default_value_t = 20.0)]
    pub per_particle: f64,
    /// Packing fraction of the hard-sphere benchmark.
    #[arg(long, default_value_t = 0.10)]
    pub hs_eta: f64,
    /// Also measure the hard-sphere rate for N = 864 … 1 000 188.
    #[arg(long)]
    pub scaling: bool,
    /// Skip the eMD* gas.
    #[arg(long)]
    pub hard_spheres_only: bool,
    /// MoR source of the eMD* gas.
    #[arg(long, value_enum, default_value_t = MorArg::Table)]
    pub mor: MorArg,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Number density ρσ³ of packing fraction η.
fn density(eta: f64) -> f64 {
    6.0 * eta / PI
}

/// Runs `collisions` after `warmup` and returns (collisions/s, stats JSON).
fn time_run(mut engine: Engine, warmup: u64, collisions: u64) -> Result<(f64, Value)> {
    engine.run_collisions(warmup)?;
    let before = *engine.stats();
    let start = Instant::now();
    engine.run_collisions(collisions)?;
    let seconds = start.elapsed().as_secs_f64();
    let s = engine.stats();
    let done = s.collisions() - before.collisions();
    let events = s.events - before.events;
    Ok((
        done as f64 / seconds,
        json!({
            "particles": engine.len(),
            "collisions": done,
            "events": events,
            "seconds": seconds,
            "collisions_per_second": done as f64 / seconds,
            "events_per_second": events as f64 / seconds,
            "exceptions_rotation": s.exception_rotation - before.exception_rotation,
            "exceptions_interference": s.exception_interference - before.exception_interference,
            "mor_fallbacks": s.mor_fallbacks - before.mor_fallbacks,
        }),
    ))
}

fn hard_spheres(cells: usize, eta: f64, per_particle: f64) -> Result<(f64, Value)> {
    let setup = gas::fcc(cells, density(eta), 1.0, 1.0, 1.0, 1);
    let n = setup.position.len() as f64;
    let engine = Engine::new(setup, Physics::HardSpheres { restitution: 1.0 })?;
    let count = (per_particle * n * 0.5) as u64;
    time_run(engine, count, count)
}

/// Müller & Pöschel 2013, Sec. VI B 6: elastic Hertz spheres, R = 0.1 m,
/// ρ = 1140 kg/m³, ν = 0.4, thermal speed ≈ 2 m/s; here Y = 1 GPa and η = 0.01.
fn emdstar_gas(per_particle: f64, mor: Box<dyn MorSource>) -> Result<(f64, Value)> {
    let sphere = Sphere::from_density(0.1, 1140.0)?;
    let eta = 0.01;
    let setup: Setup = gas::fcc(
        14,
        eta / (4.0 / 3.0 * PI * 0.1f64.powi(3)),
        0.2,
        sphere.mass,
        sphere.mass * 4.0 / 3.0,
        1,
    );
    let n = setup.position.len() as f64;
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 0.0)?);
    let physics = Physics::EmdStar {
        materials: Materials::of_spheres(&law, &[sphere])?,
        mor,
        interference: Interference::HitOnly,
    };
    let engine = Engine::new(setup, physics)?;
    let count = (per_particle * n * 0.5) as u64;
    time_run(engine, count / 4, count)
}

pub fn run(a: &BenchEdmdArgs) -> Result<()> {
    if a.per_particle.is_nan() || a.per_particle <= 0.0 {
        bail!("--per-particle must be positive");
    }
    let (hs_rate, hs) = hard_spheres(20, a.hs_eta, a.per_particle)?;
    if !a.json {
        println!(
            "elastic hard spheres, N = 32000, η = {}: {hs_rate:.3e} collisions/s",
            a.hs_eta
        );
    }
    let mut out = json!({ "hard_spheres": hs });
    if !a.hard_spheres_only {
        let mor: Box<dyn MorSource> = match a.mor {
            MorArg::Exact => Box::new(ExactMor),
            MorArg::Table => Box::new(TableMorSource::default_for(Model::Hertz, true)?),
        };
        let (rate, v) = emdstar_gas(a.per_particle, mor)?;
        if !a.json {
            println!(
                "eMD* Hertz gas, N = {}, η = 0.01, Y = 1 GPa ({} MoR): {rate:.3e} collisions/s \
                 ({:.2}× slower than hard spheres)",
                v["particles"],
                format!("{:?}", a.mor).to_lowercase(),
                hs_rate / rate
            );
        }
        out["emdstar_hertz"] = v;
        out["emdstar_slowdown"] = json!(hs_rate / rate);
    }
    if a.scaling {
        let mut rows = vec![];
        for cells in [6, 10, 22, 46, 63] {
            let (rate, v) = hard_spheres(cells, a.hs_eta, a.per_particle.min(10.0))?;
            if !a.json {
                println!("  N = {:>8}: {rate:.3e} collisions/s", v["particles"]);
            }
            rows.push(v);
        }
        out["scaling"] = json!(rows);
    }
    if a.json {
        println!("{out}");
    }
    Ok(())
}
