//! emdstar's engines built from a config.
//!
//! A config ([`emdstar_system::Config`]) describes the physical system; the options
//! here choose and tune the engine that simulates it: MD (`emdstar-dem`), classic eMD
//! or eMD* (`emdstar-edmd`), or the hybrid (`emdstar-hybrid`). [`AnyEngine`] holds
//! whichever was chosen and hands it out behind the one simulation interface
//! ([`emdstar_system::Simulation`]). [`run`] drives it through a whole run with its
//! [`output`]s: the thermo log, the trajectory, checkpoints, resumption and clean
//! stops. The command line, the Python package and anyone who embeds a whole run use
//! this crate; it links the default MoR tables.
//!
//! ```no_run
//! use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
//! use emdstar_system::Config;
//!
//! let config = Config::from_file("gas.toml".as_ref())?;
//! let system = config.build()?;
//! let options = EngineOptions { engine: EngineKind::EmdStar, ..Default::default() };
//! let mut engine = AnyEngine::build(&options, &config, system, 1.0 / 50.0)?;
//! engine.sim_mut().advance_to(config.t_end)?;
//! engine.sim_mut().synchronise()?;
//! println!("T = {}", engine.sim().thermo().granular_temperature);
//! # Ok::<(), Box<dyn std::error::Error + Send + Sync>>(())
//! ```

pub mod drive;
mod engine;
mod keys;
pub mod observe;
mod options;
pub mod output;
pub mod run;
mod setup;
mod vibrated;

pub use engine::AnyEngine;
pub use keys::{unused_keys, unwritten_intervals};
pub use options::{
    BroadPhaseChoice, EngineKind, EngineOptions, EventChoice, EventsChoice, HybridChoice,
    InterferenceChoice, MdChoice, MorChoice, parse_engine,
};
pub use setup::{event_engine, md_options, mor_source};
pub use vibrated::{VIBRATED_CONTACT_LIMIT, vibrated_wall_warnings};
