//! Each engine's set-up from a config and the options: MD's time step, the source of
//! the matrix of restitution, the event engine's physics.

use crate::options::{EngineKind, EventChoice, InterferenceChoice, MdChoice, MorChoice};
use anyhow::{Result, bail};
use emdstar_contact::Model;
use emdstar_dem::{ContactEnd, MdOptions, shortest_contact_time};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource, TableRef};
use emdstar_edmd::{Engine, Interference, Physics};
use emdstar_system::{Config, System};
use emdstar_table::{Table, TableError};

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

/// The force models of the contacts of `system`, each once.
fn models(system: &System) -> Vec<Model> {
    let mut models: Vec<Model> = Vec::new();
    for i in system.interactions().distinct() {
        if !models.contains(&i.law().model()) {
            models.push(i.law().model());
        }
    }
    models
}

/// The source of the matrix of restitution that `choice` names (eMD* and the hybrid):
/// a table per force model of the system (the default ones, or the file given), with
/// the exact solver as the counted fallback where `choice` allows it.
pub fn mor_source(system: &System, choice: &EventChoice) -> Result<Box<dyn MorSource>> {
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
            let source = TableMorSource::from_table(table, fallback);
            if !fallback && let Some(m) = models(system).into_iter().find(|&m| !source.covers(m)) {
                bail!(
                    "the MoR table {} does not cover the {m} contacts of this config; give a \
                     {m} table, or --mor table+exact to solve them exactly",
                    path.display()
                );
            }
            Box::new(source)
        }
        (_, None) => {
            let tables = models(system)
                .into_iter()
                .map(|m| Ok(TableRef::Static(emdstar_table::default_table(m)?)))
                .collect::<Result<Vec<_>>>()?;
            Box::new(TableMorSource::with_tables(tables, fallback))
        }
    })
}

/// The event engine (`kind` emd or emdstar) for `system`: with friction, emd runs
/// Walton's rule (contacts with `tangential_restitution`) and eMD* the exact contact
/// with the history spring (contacts with `tangential_stiffness`); each contact's model
/// is checked against the method (`emdstar_system::Method`).
pub fn event_engine(kind: EngineKind, system: &System, choice: &EventChoice) -> Result<Engine> {
    let interactions = system.interactions().clone();
    let physics = match kind {
        EngineKind::Emd => Physics::Emd(interactions),
        EngineKind::EmdStar => Physics::EmdStar {
            interactions,
            mor: mor_source(system, choice)?,
            interference: match choice.interference {
                InterferenceChoice::Hit => Interference::HitOnly,
                InterferenceChoice::Both => Interference::BothPartners,
            },
        },
        EngineKind::Md | EngineKind::Hybrid => bail!("this engine is not purely event-driven"),
    };
    Ok(Engine::with_broad_phase(
        &system.particles,
        &system.domain,
        physics,
        choice.broad_phase.into(),
    )?)
}
