//! State and input shared by the emdstar engines (force-based MD and event-driven eMD*):
//!
//! - [`Particles`] (structure of arrays) and [`Species`];
//! - [`SimBox`] (periodic or closed axes; `None` = free space), plane [`Wall`]s, gravity;
//! - [`Config`], the TOML schema (unknown keys are errors), and [`System`], what it
//!   builds after validation (no overlaps, everything inside the box and in front of
//!   the walls);
//! - generated gases (lattice or random placement, Maxwell velocities);
//! - [`CellGrid`] for neighbour searches;
//! - writers: extended XYZ trajectories for OVITO and a thermo log.

// Component loops `for k in 0..3` over several arrays read best as they are.
#![allow(clippy::needless_range_loop)]

mod config;
mod error;
mod geometry;
pub mod gsd;
mod init;
mod state;
mod system;
mod writers;

pub use config::{
    Arrangement, BoxConfig, Config, GasConfig, MaterialConfig, MdConfig, OutputConfig,
    ParticleConfig, WallConfig,
};
pub use error::{Result, SystemError};
pub use geometry::{CellGrid, SimBox, Stencil, Wall, bounding_box};
pub use init::cubic_box;
pub use state::{Particles, Species, permute};
pub use system::System;
pub use writers::{Thermo, ThermoLog, XyzWriter};
