//! `emdstar pair`: a few particles to t_end, printing the final state.

use super::engine::{Engine, MdArgs, load, md_options, parse_engine};
use anyhow::Result;
use clap::Args;
use emdstar_dem::Md;
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
/// positions and velocities, in config order.
///
/// Example:
///   emdstar pair tests/md/configs/oblique_linear.toml --engine md --json
#[derive(Args, Debug)]
#[command(verbatim_doc_comment)]
pub struct PairArgs {
    /// The TOML config.
    pub config: PathBuf,
    /// The engine: md, emd or emdstar.
    #[arg(long, value_parser = parse_engine, default_value = "md")]
    pub engine: Engine,
    #[command(flatten)]
    pub md: MdArgs,
    #[command(flatten)]
    pub edmd: super::edmd_engine::EdmdArgs,
    /// Print JSON: {"engine", "t", "particles": [{"position", "velocity"}, ...]}.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &PairArgs) -> Result<()> {
    let (config, system) = load(&args.config)?;
    match args.engine {
        Engine::Emd | Engine::EmdStar => {
            super::edmd_engine::pair(&config, system, args.engine, &args.edmd, args.json)?;
        }
        Engine::Hybrid => {
            anyhow::bail!("the hybrid engine runs gases: use `emdstar run CONFIG --engine hybrid`")
        }
        Engine::Md => {
            let (opts, steps) = md_options(&config, &system, &args.md, PAIR_DT_FRACTION)?;
            let mut md = Md::new(system, opts, config.t_end)?;
            md.advance(steps)?;
            let p = md.particles_in_config_order();
            if args.json {
                let particles: Vec<_> = (0..p.len())
                    .map(|i| json!({"position": p.position[i], "velocity": p.velocity[i]}))
                    .collect();
                let out = json!({"engine": "md", "t": md.time(), "particles": particles});
                println!("{out}");
            } else {
                println!(
                    "engine md, t = {} s, dt = {:e} s, {} steps",
                    md.time(),
                    opts.dt,
                    steps
                );
                for i in 0..p.len() {
                    println!(
                        "particle {i}: position {:?} m, velocity {:?} m/s",
                        p.position[i], p.velocity[i]
                    );
                }
            }
        }
    }
    Ok(())
}
