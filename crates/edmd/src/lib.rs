//! The event-driven engine of emdstar: hard spheres, eMD and eMD* (Müller & Pöschel
//! 2013, Sec. VI) on top of the stable event detection of Bannerman et al. 2014.
//!
//! - [`detect`]: stable event detection, Bannerman 2014, Algorithms 1 and 2;
//! - [`bouncing`]: their bouncing-ball stability test (Sec. 5);
//! - [`queue`]: the event queue behind the [`EventQueue`] trait;
//! - [`cells`]: the cell grid with crossing events;
//! - [`rules`]: collision rules and the source of the matrix of restitution;
//! - [`Engine`]: the event loop with delayed updates, built from a [`Setup`] and a
//!   [`Physics`].

pub mod bouncing;
mod build;
pub mod cells;
mod collide;
pub mod detect;
mod engine;
mod error;
pub mod gas;
pub mod queue;
mod reorder;
pub mod rules;
mod setup;
mod stats;
mod system;

pub use engine::{Engine, Event};
pub use error::{EngineError, Result};
pub use queue::{EventQueue, IndexedHeap};
pub use setup::{Interference, Materials, PairEntry, Physics, Region, Setup, Wall};
pub use stats::Stats;
#[cfg(test)]
mod engine_tests;
