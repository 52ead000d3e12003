//! State and input shared by the emdstar engines (force-based MD and event-driven eMD*):
//!
//! - [`Particles`] (structure of arrays) and [`Species`];
//! - the [`Domain`]: a [`SimBox`] (periodic or closed axes; `None` = free space), plane
//!   [`Wall`]s, gravity; and [`Domain::check`], the checks of a state every engine
//!   relies on (no overlaps, everything inside the box and in front of the walls);
//! - [`Interactions`]: the contact model (normal law and tangential sub-model) and
//!   properties of every kind of contact, from the materials and their pairs
//!   ([`MaterialTable`]); [`Method`] and [`Interactions::check_runs_on`], which method
//!   runs which model;
//! - [`Config`], the TOML schema (unknown keys are errors), and [`System`], what it
//!   builds after validation;
//! - generated gases ([`GasConfig`]: simple cubic, fcc or random placement, Maxwell
//!   velocities);
//! - [`CellGrid`] for neighbour searches;
//! - [`Simulation`], the one interface of every engine, and [`Checkpoint`] files of
//!   their saved states;
//! - writers: extended XYZ trajectories for OVITO and a thermo log, with the pressure
//!   tensor, collision rate and Sonine coefficient ([`StressSums`], [`Observables`]);
//! - [`stop`]: the request to stop a run that every engine reads at each event or step.

// Component loops `for k in 0..3` over several arrays read best as they are.
#![allow(clippy::needless_range_loop)]

mod cell_grid;
mod checkpoint;
mod config;
mod contact_check;
mod domain;
mod domain_config;
mod driving;
mod error;
mod files;
mod gas;
mod geometry;
pub mod gsd;
mod gsd_tail;
mod initial;
mod interactions;
mod key_lines;
mod material_config;
mod materials;
mod methods;
mod parse;
mod shear;
mod simulation;
mod state;
pub mod stop;
mod stress;
mod system;
mod tail;
mod vibration;
mod writers;

pub use checkpoint::{CHECKPOINT_VERSION, Checkpoint, CheckpointFile, write_atomically};
pub use config::{
    BoxConfig, Config, EventsConfig, MdConfig, OutputConfig, ParticleConfig, WallConfig,
};
pub use domain::Domain;
pub use driving::{Drive, DriveKind, DrivingConfig};
pub use error::{Result, SystemError};
pub use files::{FileIdentity, OutputFile, check_writable, open_input, read_input};
pub use gas::{Arrangement, GasConfig, GasKind, GasSpeciesConfig, cubic_box, fcc_gas};
pub use geometry::{
    CellGrid, SimBox, Stencil, Wall, bounded_cell_width, bounding_box, cell_along, cells_per_axis,
    sparse_cell_limit, sparse_cell_width,
};
pub use initial::{InitialConfig, InitialFormat};
pub use interactions::{Interaction, Interactions};
pub use key_lines::KeyLines;
pub use material_config::{InteractionConfig, MaterialConfig};
pub use materials::{Dissipation, Elastic, Material, MaterialTable, PairEntry, Reference};
pub use methods::Method;
pub use shear::LeesEdwards;
pub use simulation::{Simulation, SimulationError, VelocityChange};
pub use state::{Particles, Species, permute};
pub use stress::{
    Observables, StressMark, StressSums, Sym3, add_kinetic, add_scaled, sonine_a2, sym_outer,
};
pub use system::System;
pub use tail::{Cut, KeepUntil};
pub use vibration::Vibration;
pub use writers::{Thermo, ThermoLog, XyzWriter};
