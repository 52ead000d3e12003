//! Force-based DEM (MD) of soft spheres: the reference that eMD* must reproduce
//! (Müller & Pöschel 2013, Sec. V), with friction and rotation where the contacts have
//! them ([`Frictional`]: Cundall–Strack springs or Coulomb sliding in LAMMPS's
//! conventions, see docs/physics.md, "Friction and rotation").
//!
//! # Integrator
//! Velocity Verlet: v(t+dt/2) = v(t) + (dt/2)·a(t); x(t+dt) = x(t) + dt·v(t+dt/2);
//! a(t+dt) = F(x(t+dt), v*)/m; v(t+dt) = v(t+dt/2) + (dt/2)·a(t+dt). Consecutive
//! half-kicks are fused into one, so a step streams over the particles twice (kick +
//! drift, then forces).
//!
//! **Velocity-dependent damping.** The dashpot needs v(t+dt), which depends on the
//! force being computed. The force uses the explicit predictor
//! v* = v(t+dt/2) + (dt/2)·a(t) = v(t) + dt·a(t), which differs from v(t+dt) by O(dt²),
//! so the scheme stays second order for smooth forces (the plain choice v(t+dt/2),
//! used by LAMMPS's `fix nve/sphere`, is off by O(dt) and makes damped runs first
//! order). At t = 0 the initial velocities are used.
//!
//! **Contact start.** The linear dashpot's force jumps to γ·ξ̇ at first touch; the
//! trapezoidal weighting of velocity Verlet then misplaces an impulse of order
//! γ·ξ̇·dt per collision. The first step of every contact corrects it from the touch
//! time interpolated between the last two steps (see [`touch_correction`]), which
//! restores second order. Observed orders against the exact eMD* solution
//! (tests/collisions.rs, 25 to 800 steps per contact): 2.0 for the linear dashpot,
//! damped or not; about 1.6 for damped and 2.5 for elastic Hertz contacts, whose
//! √ξ-dependence at touch is not smooth.
//!
//! # Contacts
//! The normal forces come from [`emdstar_contact::PairLaw`]: clipped to F ≥ 0, so a
//! contact ends when the force reaches zero ([`ContactEnd::ForceZero`]), or unclipped
//! until the overlap vanishes ([`ContactEnd::OverlapZero`], LAMMPS's convention).
//! Walls are infinitely heavy flat partners ([`emdstar_contact::PairProperties::sphere_wall`]),
//! each with its own contact model per species.
//! The one force kernel ([`ForceKernel`]) is generic over its tangential slot
//! ([`TangentialSlot`]): [`Smooth`], a zero-sized slot that gives the normal force alone,
//! where every contact is frictionless; [`Frictional`] otherwise, which adds each
//! contact's tangential force and torques, while spins are kicked like the velocities
//! and each contact's spring is kept between steps ([`Springs`], keyed by config ids).
//! A frictionless run never touches a spin.
//!
//! # Neighbours
//! A half Verlet list with a skin, built from a cell grid, and rebuilt only when the
//! particles may have moved by more than half the skin: the bound Σ_steps max|v|·dt,
//! no per-particle displacement bookkeeping. On every rebuild the particles are sorted
//! by cell, for locality. [`NeighbourList`] lists each pair once, under its higher
//! index; on demand its upper part lists them under the lower one too (every
//! neighbour of every particle, for the hybrid engine's bookkeeping).
//!
//! # One driver, for all particles or a subset
//! [`Verlet`] is MD's one driver: the steps above, the list and its rebuilds, over the
//! particles of a [`Members`] set. [`Md`] is the driver over [`All`] particles, whose
//! tests compile away. The hybrid engine's time-driven part is the same driver over
//! its time-driven particles (a mask): pairs with a particle outside are left out (the
//! hybrid has no mixed contacts), particles join with their forces at their velocities
//! then ([`Verlet::add_forces_of`], as a run's first step) and leave without contacts
//! ([`Verlet::release`]). With every particle a member, the hybrid runs the very
//! arithmetic of MD.
//!
//! Other building blocks: [`ForceKernel::particle`], the force kernel (walls, then the
//! partners it is given, with predictor and touch correction), writing its contacts to
//! any [`ForceSink`], applied in order by [`apply_contacts`]; [`ForceModel::add_elastic`]
//! and [`elastic_energy`] for the thermo output.
//!
//! # Determinism
//! The force loop runs on rayon over fixed chunks of particles. Each chunk sets its
//! particles' gravity and wall forces and records its pair forces; the pair forces
//! are then added in chunk order. The sums therefore run in the same order whatever
//! the number of threads, and results are bitwise identical.

// Component loops `for k in 0..3` over several arrays read best as they are.
#![allow(clippy::needless_range_loop)]

mod driver;
mod engine;
mod forces;
mod frictional;
mod neighbour;
mod options;
mod simulation;
mod sliding;
mod verlet;

pub use driver::{All, Members, Verlet, check_and_wrap};
pub use engine::Md;
pub use forces::{
    Accelerations, ContactKey, ContactRecord, ForceKernel, ForceModel, ForceSink, PairForce,
    Smooth, TangentialSlot, Touch, WALL, apply_contacts, elastic_energy, normal_force,
    touch_correction, unclipped_force,
};
pub use frictional::{ContactForce, Frictional, Rotation, Springs};
pub use neighbour::NeighbourList;
pub use options::{
    ContactEnd, DEFAULT_DT_FRACTION, MAX_DT_FRACTION, MdError, MdOptions, default_skin,
    prepare_system, shortest_contact_time,
};
pub use verlet::{kick_contacts, kick_drift};
