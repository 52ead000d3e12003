//! `emdstar pair`: a few particles to t_end, printing the final state.

use super::any_engine::EngineReport;
use super::engine::load;
use anyhow::Result;
use clap::Args;
use emdstar_engines::{AnyEngine, EngineOptions};
use serde_json::json;
use std::path::PathBuf;

/// The default time step of `pair`, as a fraction of the shortest expected contact
/// time: fine enough that two-sphere collisions end within 1e-4 of the exact solution
/// (in units of l and |v_rel|), also after long free flights (a velocity error grows
/// into a position error); checked by the tests in tests/md. The engine converges at
/// second order for the linear dashpot and at about 1.6 for damped Hertz contacts.
pub const PAIR_DT_FRACTION: f64 = 1.0 / 2000.0;

/// A few particles (typically one collision) to t_end; prints the final state.
///
/// Simulates the particles of CONFIG (typically two) up to t_end and prints their final
/// positions, velocities and angular velocities, in config order.
///
/// Example:
///   emdstar pair tests/md/configs/oblique_linear.toml --engine md --json
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct PairArgs {
    /// The TOML config.
    pub config: PathBuf,
    #[command(flatten)]
    pub engine: EngineOptions,
    /// Print JSON: {"engine", "t", "particles": [{"position", "velocity",
    /// "angular_velocity"}, ...], and for
    /// the event-driven engines "stats"}.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &PairArgs) -> Result<()> {
    let (config, system) = load(&args.config, false)?;
    let mut engine = AnyEngine::build(&args.engine, &config, system, PAIR_DT_FRACTION)?;
    engine
        .sim_mut()
        .advance_to(config.t_end)
        .map_err(|e| anyhow::anyhow!(e))?;
    let sim = engine.sim();
    let p = sim.particles();
    if args.json {
        let particles: Vec<_> = (0..p.len())
            .map(|i| {
                json!({
                    "position": p.position[i],
                    "velocity": p.velocity[i],
                    "angular_velocity": p.angular_velocity[i],
                })
            })
            .collect();
        let mut out = json!({"engine": sim.engine(), "t": sim.time(), "particles": particles});
        if let Some(stats) = engine.summary_fields(1.0, 0, 1).get("stats") {
            out["stats"] = stats.clone();
        }
        println!("{out}");
    } else {
        match sim.time_step() {
            Some(dt) => println!(
                "engine {}, t = {} s, dt = {dt:e} s, {} steps",
                sim.engine(),
                sim.time(),
                sim.steps_done()
            ),
            None => println!("engine {}, t = {} s", sim.engine(), sim.time()),
        }
        for i in 0..p.len() {
            println!(
                "particle {i}: position {:?} m, velocity {:?} m/s, angular velocity {:?} rad/s",
                p.position[i], p.velocity[i], p.angular_velocity[i]
            );
        }
    }
    let fallbacks = engine.mor_fallbacks();
    if fallbacks > 0 {
        eprintln!(
            "note: {fallbacks} impacts lay outside the MoR table's box and were solved exactly \
             (`--mor table` makes them errors)"
        );
    }
    Ok(())
}
