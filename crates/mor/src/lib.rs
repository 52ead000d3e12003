//! The matrix of restitution (MoR) of Müller & Pöschel 2013 and the eMD* collision rule.
//!
//! - [`solve`] integrates the scaled two-body collision ODE, Eqs. (42) and (54), and
//!   returns the [`Mor`] {ε_r, 1−ε_r, ε_ṙ, ε_φ, ε_t} of Eqs. (16)-(21).
//! - [`rule`] applies a MoR to two spheres in the laboratory frame, Sec. IV,
//!   Eqs. (25)-(39), and splits it into the E^φ and E^v events of Sec. VI B.
//! - [`inverse`] gives the dissipation (γ or A) of a material from the coefficient of
//!   normal restitution of a central impact: restitution as input.
//!
//! - [`frictional`] solves the exact contact of frictional spheres (history spring, both
//!   spins, 3-D) from touch to the same end.
//!
//! All are pure functions: no tables, no engines, no I/O.

mod dop853;
pub mod frictional;
pub mod inverse;
mod roots;
pub mod rule;
mod solver;

pub use emdstar_contact::Mor;
pub use inverse::{InverseError, central_c_dis, with_restitution};
pub use solver::{SolveError, SolveStats, SolverOptions, solve, solve_with};
