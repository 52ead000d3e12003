//! Each engine's set-up from a config and the options: MD's time step, the source of
//! the matrix of restitution, the event engine's physics.

use crate::options::{EngineKind, EventChoice, InterferenceChoice, MdChoice, MorChoice};
use anyhow::{Result, bail};
use emdstar_dem::{ContactEnd, MdOptions, shortest_contact_time};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{Engine, Interference, Materials, Physics};
use emdstar_system::{Config, System};
use emdstar_table::{Table, TableError};

/// Refuses Walton's rule (`tangential_restitution`) for MD and for the hybrid, whose
/// time-driven part is MD (`engine`: how the message names the engine).
pub fn refuse_walton_for_md(system: &System, engine: &str) -> Result<()> {
    if system.friction.is_active() && system.friction.tangential_restitution.is_some() {
        bail!(
            "material.tangential_restitution is Walton's rule of the event-driven engines \
             (--engine emd); {engine} a tangential spring: replace it by \
             tangential_stiffness (and tangential_damping), or by tangential = \"coulomb\""
        );
    }
    Ok(())
}

/// The MD options (`md` over the config's `[md]`). Without an explicit dt the step is
/// `default_fraction` × the shortest contact time expected up to the config's `t_end`,
/// shortened so that the config's `t_end` is a whole number of steps (a run stopped
/// earlier or resumed later keeps this step).
pub fn md_options(
    config: &Config,
    system: &System,
    md: &MdChoice,
    default_fraction: f64,
) -> Result<MdOptions> {
    let section = config.md.clone().unwrap_or_default();
    let contact_end: ContactEnd = match md.contact_end.as_ref().or(section.contact_end.as_ref()) {
        Some(s) => s.parse().map_err(anyhow::Error::msg)?,
        None => ContactEnd::ForceZero,
    };
    let t_end = config.t_end;
    let dt = match md.dt.or(section.dt) {
        Some(dt) => {
            if !(dt.is_finite() && dt > 0.0) {
                bail!("dt = {dt} must be a finite number greater than zero");
            }
            dt
        }
        None => match shortest_contact_time(system, t_end)? {
            Some(tc) => default_fraction * tc,
            None => t_end,
        },
    };
    let steps = (t_end / dt).ceil().max(1.0);
    if steps > 1e13 {
        bail!("t_end / dt = {steps:e} steps is too many; raise dt or lower t_end");
    }
    Ok(MdOptions {
        dt: t_end / steps,
        contact_end,
        skin: md.skin.or(section.skin),
    })
}

/// The source of the matrix of restitution that `choice` names (eMD* and the hybrid).
pub fn mor_source(system: &System, choice: &EventChoice) -> Result<Box<dyn MorSource>> {
    let model = system.material.model();
    let fallback = choice.mor == MorChoice::TableOrExact;
    Ok(match (choice.mor, &choice.table) {
        (MorChoice::Exact, _) => Box::new(ExactMor),
        (_, Some(path)) => {
            let table = Table::open(path).map_err(|e| match e {
                // Names the path already.
                TableError::Io(_) => anyhow::Error::new(e),
                e => anyhow::Error::new(e)
                    .context(format!("reading the MoR table {}", path.display())),
            })?;
            Box::new(TableMorSource::from_table(table, fallback))
        }
        (_, None) => Box::new(TableMorSource::new(
            emdstar_table::default_table(model)?,
            fallback,
        )),
    })
}

/// The event engine (`kind` emd or emdstar) for `system`: with friction, emd runs
/// Walton's rule (the material needs `tangential_restitution`) and eMD* the exact
/// contact with the history spring (the material needs `tangential_stiffness`).
pub fn event_engine(kind: EngineKind, system: &System, choice: &EventChoice) -> Result<Engine> {
    let friction = &system.friction;
    let walton = match kind {
        _ if !friction.is_active() => None,
        EngineKind::EmdStar => None,
        _ => match friction.walton_rule() {
            Some(w) => Some(w),
            None => bail!(
                "friction = {} with --engine {} needs material.tangential_restitution, the \
                 tangential restitution β₀ ∈ [-1, 1] of sticking impacts in Walton's rule \
                 (-1 smooth, 1 perfectly rough) instead of MD's tangential_stiffness, \
                 tangential_damping and tangential; or run --engine md",
                friction.friction,
                kind.name()
            ),
        },
    };
    let materials = Materials::from_system(system)?;
    let physics = match kind {
        EngineKind::Emd => Physics::Emd(materials),
        EngineKind::EmdStar => Physics::EmdStar {
            materials,
            mor: mor_source(system, choice)?,
            interference: match choice.interference {
                InterferenceChoice::Hit => Interference::HitOnly,
                InterferenceChoice::Both => Interference::BothPartners,
            },
        },
        EngineKind::Md | EngineKind::Hybrid => bail!("this engine is not purely event-driven"),
    };
    let engine = Engine::with_broad_phase(
        &system.particles,
        &system.domain,
        physics,
        choice.broad_phase.into(),
    )?;
    Ok(match (walton, kind) {
        (Some(w), _) => engine.with_friction(w)?,
        (None, EngineKind::EmdStar) if friction.is_active() => {
            engine.with_exact_friction(*friction)?
        }
        (None, _) => engine,
    })
}

/// The name of the MoR source of eMD* physics (empty for the other rules).
pub fn mor_name(physics: &Physics) -> &'static str {
    match physics {
        Physics::EmdStar { mor, .. } => mor.name(),
        _ => "",
    }
}
