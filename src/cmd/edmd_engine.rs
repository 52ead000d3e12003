//! The event-driven engines (`--engine emd|emdstar`) behind `pair` and `run`: their
//! options, the source of the matrix of restitution, and their counters.

use super::engine::EngineKind;
use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{BroadPhaseKind, Engine, Interference, Materials, Physics, Stats};
use emdstar_system::System;
use emdstar_table::{Table, TableError};
use serde_json::{Value, json};
use std::path::PathBuf;

/// Where eMD* takes the matrix of restitution from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MorChoice {
    /// The lookup table (--table, or the default table embedded in the program), with
    /// impacts outside its box solved exactly; the summary counts them.
    TableOrExact,
    /// The table only: an impact outside its box stops the run with an error.
    Table,
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
    #[arg(long, value_enum, default_value_t = MorChoice::TableOrExact)]
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
pub fn build(kind: EngineKind, system: &System, args: &EdmdArgs) -> Result<Engine> {
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

/// The name of the MoR source of eMD* physics (empty for the other rules).
pub fn mor_name(physics: &Physics) -> &'static str {
    match physics {
        Physics::EmdStar { mor, .. } => mor.name(),
        _ => "",
    }
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

/// The counters of an event-driven run, as `pair` and `run` print them.
pub fn stats_json(s: &Stats) -> Value {
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
