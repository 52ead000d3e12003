//! Generation of matrix-of-restitution tables (Müller & Pöschel 2013, Sec. V) with the
//! exact solver of `emdstar-mor`: grid sweeps over the rectangle of a parameter box in
//! parallel (rayon) with a progress bar, shards and their merge, accuracy checks
//! against exact solves, and heatmap plots.
//!
//! Everything is deterministic: the same spec gives the same bytes for any thread count,
//! and the shards of a run merge into exactly the bytes of a single run.

pub mod check;
pub mod generate;
pub mod plot;
pub mod shard;
pub mod spec;

pub use check::{CheckReport, Region, check};
pub use generate::{Solver, build, exact_solver, unit_count};
pub use shard::{build_shard, merge};
pub use spec::Spec;
