//! What the config and checkpoint targets share: building each engine from a parsed
//! config exactly as `emdstar run` does ([`AnyEngine::build`] with the default options:
//! the default time step, the default MoR table with the exact fallback, automatic broad
//! phase, friction where the material has it), and running it a bounded amount.

use emdstar_dem::DEFAULT_DT_FRACTION;
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::{Config, Simulation, System};

/// Particles above which an input is skipped, so that each input runs in well under a
/// second (a gas's `count` is checked before it is generated).
pub const MAX_PARTICLES: u64 = 64;

/// Whether the config describes few enough particles to be set up quickly.
pub fn small_enough(config: &Config) -> bool {
    config.particles.len() as u64 <= MAX_PARTICLES
        && config
            .gas
            .as_ref()
            .is_none_or(|g| (g.count as u64) <= MAX_PARTICLES)
}

/// Frictional eMD\* collisions after which an event run stops: each is a DOP853 solve
/// (0.2 ms for physical parameters, up to 0.1 s for odd ones such as a tangential spring
/// far stiffer than the normal one), and one exercises the whole frictional path.
pub const MAX_FRICTIONAL_SOLVES: u64 = 1;

/// The engines `emdstar run --engine` offers (the checkpoint target picks among the
/// first three).
pub const KINDS: [EngineKind; 4] = [
    EngineKind::Md,
    EngineKind::EmdStar,
    EngineKind::Hybrid,
    EngineKind::Emd,
];

/// The engine of `kind` for the system of `config`, or `None` where set-up refuses it
/// (a refusal must be an error, never a panic).
pub fn build(kind: EngineKind, config: &Config, system: System) -> Option<AnyEngine> {
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    AnyEngine::build(&options, config, system, DEFAULT_DT_FRACTION).ok()
}

/// Runs `n` time steps (MD, the hybrid) or events (the event engines), stopping at the
/// first error or after [`MAX_FRICTIONAL_SOLVES`], then reads the state out and saves it.
pub fn run_bounded(engine: &mut AnyEngine, n: u32) {
    match engine {
        AnyEngine::Md(e) => {
            let dt = e.options().dt;
            let _ = e.advance_to(e.time() + f64::from(n) * dt);
        }
        AnyEngine::Event(e) => {
            for _ in 0..n {
                if e.step().is_err() || e.stats().frictional_solves >= MAX_FRICTIONAL_SOLVES {
                    break;
                }
            }
        }
        AnyEngine::Hybrid(e) => {
            let _ = e.advance(u64::from(n));
        }
    }
    let sim = engine.sim_mut();
    let _ = sim.thermo();
    let _ = sim.particles();
    let _ = sim.save_state();
}
