//! One type for every engine, built from a config and the options, driven through the
//! simulation interface.

use crate::options::{BroadPhaseChoice, EngineKind, EngineOptions};
use crate::setup::{event_engine, interference, md_options, mor_source};
use anyhow::{Result, bail};
use emdstar_dem::{ContactEnd, Md};
use emdstar_hybrid::{Hybrid, HybridOptions};
use emdstar_system::{Config, Drive, DriveKind, Simulation, System};

/// MD, an event engine (eMD or eMD*) or the hybrid.
pub enum AnyEngine {
    Md(Box<Md>),
    Event(Box<emdstar_edmd::Engine>),
    Hybrid(Box<Hybrid>),
}

/// Refuses the engines and broad phases that do not run Lees–Edwards boundaries, and
/// picks cell crossings for the event engines.
fn shear_engine(config: &Config, options: &mut EngineOptions) -> Result<()> {
    let refuse = |why: &str| -> Result<()> {
        bail!(
            "config: {}",
            config.keys.locate(&format!("box.shear_rate: {why}"))
        )
    };
    match (options.engine, options.edmd.broad_phase) {
        (EngineKind::Hybrid, _) => refuse(
            "the hybrid engine does not run Lees–Edwards boundaries; use --engine md, emd \
                 or emdstar",
        ),
        (EngineKind::Emd | EngineKind::EmdStar, BroadPhaseChoice::Auto) => {
            options.edmd.broad_phase = BroadPhaseChoice::Crossings;
            Ok(())
        }
        (EngineKind::Emd | EngineKind::EmdStar, BroadPhaseChoice::Crossings)
        | (EngineKind::Md, _) => Ok(()),
        (EngineKind::Emd | EngineKind::EmdStar, other) => refuse(&format!(
            "Lees–Edwards boundaries run on the crossings broad phase only, not on \
             {other:?}; use --broad-phase crossings or auto"
        )),
    }
}

impl AnyEngine {
    /// The engine `options` choose for `system` (built from `config`). Step engines
    /// take steps of `dt_fraction` × the shortest contact time unless told otherwise
    /// (`emdstar pair` uses 1/2000, `emdstar run` 1/50).
    pub fn build(
        options: &EngineOptions,
        config: &Config,
        system: System,
        dt_fraction: f64,
    ) -> Result<Self> {
        // A bad value is refused whatever the engine (the config checks its numbers).
        if let Some(end) = config.md.as_ref().and_then(|m| m.contact_end.as_ref()) {
            end.parse::<ContactEnd>().map_err(|e| {
                anyhow::anyhow!(
                    "config: {}",
                    config.keys.locate(&format!("md.contact_end: {e}"))
                )
            })?;
        }
        let driving = config.driving.as_ref().map(|d| d.drive()).transpose()?;
        if let Some(Drive {
            kind: DriveKind::Andersen { .. },
            ..
        }) = driving
            && system.domain.shear_rate != 0.0
        {
            bail!(
                "config: {}",
                config.keys.locate(
                    "driving.kind: an Andersen thermostat draws velocities about rest, not \
                     about the shear flow of box.shear_rate (it would stop the flow at every \
                     tick); use kind = \"white_noise\" (its kicks keep the flow) or drop the \
                     shear rate"
                )
            );
        }
        let mut options = options.clone();
        if driving.is_some() {
            match (options.engine, options.edmd.broad_phase) {
                (EngineKind::Emd | EngineKind::EmdStar, BroadPhaseChoice::Auto) => {
                    options.edmd.broad_phase = BroadPhaseChoice::Crossings;
                }
                (EngineKind::Emd | EngineKind::EmdStar, BroadPhaseChoice::Crossings) => {}
                (EngineKind::Emd | EngineKind::EmdStar, other) => bail!(
                    "[driving] runs on the crossings broad phase (kicks change the speeds \
                     that {other:?} bounds its predictions by): use --broad-phase crossings \
                     or auto"
                ),
                (EngineKind::Md | EngineKind::Hybrid, _) => {}
            }
        }
        if system.domain.shear_rate != 0.0 {
            shear_engine(config, &mut options)?;
        }
        let options = &options;
        Ok(match options.engine {
            EngineKind::Md => {
                let md = md_options(config, &system, &options.md, dt_fraction)?;
                Self::Md(Box::new(Md::new(system, md, config.t_end)?))
            }
            EngineKind::Emd | EngineKind::EmdStar => {
                let mut engine = event_engine(options.engine, &system, &options.edmd)?;
                engine.set_tc(config.events.as_ref().and_then(|e| e.tc))?;
                Self::Event(Box::new(engine))
            }
            EngineKind::Hybrid => {
                let md = md_options(config, &system, &options.md, dt_fraction)?;
                if md.contact_end != ContactEnd::ForceZero {
                    bail!(
                        "the hybrid engine needs contact_end = \"force\" (F = max(0, …)): its \
                         mode switches rely on the force staying zero at the end of an eMD* \
                         contact"
                    );
                }
                let h = &options.hybrid;
                let hybrid = HybridOptions {
                    skin: md.skin,
                    phi_time: h.phi_time,
                    phi_event: h.phi_event,
                    max_events_per_step: h.max_events_per_step,
                    events: h.events.into(),
                    interference: interference(options.edmd.interference),
                    ..HybridOptions::with_dt(md.dt)
                };
                let mor = mor_source(&system, &options.edmd)?;
                Self::Hybrid(Box::new(Hybrid::new(system, hybrid, mor, config.t_end)?))
            }
        })
    }

    /// The engine behind the simulation interface.
    pub fn sim(&self) -> &dyn Simulation {
        match self {
            Self::Md(e) => e.as_ref(),
            Self::Event(e) => e.as_ref(),
            Self::Hybrid(e) => e.as_ref(),
        }
    }

    /// The engine behind the simulation interface, to advance it.
    pub fn sim_mut(&mut self) -> &mut dyn Simulation {
        match self {
            Self::Md(e) => e.as_mut(),
            Self::Event(e) => e.as_mut(),
            Self::Hybrid(e) => e.as_mut(),
        }
    }

    /// What a resumed run must share with the run that wrote its checkpoint, besides
    /// the config: the source of the matrix of restitution.
    pub fn options_tag(&self) -> String {
        match self {
            Self::Md(_) => String::new(),
            Self::Event(e) => e.rules().mor_name().to_string(),
            Self::Hybrid(e) => e.mor_name().to_string(),
        }
    }

    /// Impacts whose MoR came from the exact solver because the table did not cover
    /// them (eMD* and the hybrid).
    pub fn mor_fallbacks(&self) -> u64 {
        match self {
            Self::Md(_) => 0,
            Self::Event(e) => e.stats().mor_fallbacks,
            Self::Hybrid(e) => e.stats().ed.mor_fallbacks,
        }
    }
}
