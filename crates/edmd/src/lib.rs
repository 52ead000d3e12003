//! The event-driven engine of emdstar: hard spheres, eMD and eMD* (Müller & Pöschel
//! 2013, Sec. VI) on top of the stable event detection of Bannerman et al. 2014.
//!
//! - [`detect`]: stable event detection, Bannerman 2014, Algorithms 1 and 2;
//! - [`bouncing`]: their bouncing-ball stability test (Sec. 5);
//! - [`queue`]: the event queue behind the [`EventQueue`] trait;
//! - [`cells`]: the cell grid with crossing events, and (private) `sweep`: the swept
//!   boxes of the epoch broad phase ([`BroadPhase`]);
//! - [`rules`]: collision rules and the source of the matrix of restitution;
//! - [`Engine`]: the event loop with delayed updates, built from particles and their
//!   domain (`emdstar_system`'s [`Particles`](emdstar_system::Particles) and
//!   [`Domain`](emdstar_system::Domain)) and a [`Physics`].
//!
//! How the engine works:
//! - every particle keeps its own earliest events (a collision with a particle or
//!   wall, a cell crossing, an eMD* E^v) in one record; the queue orders particles by
//!   the earliest of them. A predicted collision stores the partner's collision
//!   counter; if the partner has changed since, the event is stale and the particle is
//!   re-predicted (no deletions from the queue, no allocation per event);
//! - particles are moved on only when touched (delayed updates);
//! - candidate pairs come from one of three broad phases. With cell crossings, cells are
//!   at least one contact distance wide, with explicit periodic image shifts per
//!   neighbour cell, and each crossing tests only the layer of cells that became
//!   neighbours. With epochs (the default below η = 0.02, without gravity, in a
//!   gas periodic or held by walls along every axis), time is
//!   cut into epochs of about one cell width of flight; each particle's swept box is
//!   filed once per epoch, one pass over the cells tests every pair that can meet
//!   before the epoch ends, and a particle that changes course files its new box; a
//!   particle that meets nobody costs no event at all. With neighbour lists (the
//!   default for hard spheres and eMD from η = 0.38, without gravity), each particle
//!   lists the particles whose shell centres lie within 1.6 contact distances of its
//!   own, and leaving its shell (0.3 contact distances) rebuilds its list.
//!   All give the same collisions;
//! - detection is Bannerman's Algorithm 1 (pairs) and 2 (walls under gravity): an
//!   overlapping, approaching pair collides at once (a stabilising collision);
//! - eMD*: E^φ rotates the pair and gives both the centre-of-mass velocity, the two
//!   E^v events apply the stored post-collision velocities τ later. Partners sharing a
//!   transient are never tested against each other (they overlap by l(1 − ε_r) and
//!   move together; round-off must not make them collide again). A third particle
//!   hitting one of them runs the pending E^v early (exception b: the hit particle or
//!   both partners, [`Interference`]); a rotation that would push into a third
//!   particle or a wall falls back to the eMD rule (exception a). All are counted in
//!   [`Stats`].
//! - the collision rules are values chosen once per kind of contact
//!   ([`collision::Rules`]): hard spheres, eMD and eMD*, Walton's rule
//!   (`emdstar_contact::rough_pair`) instead of the central kick where an instantaneous
//!   contact has friction, the exact frictional contact where an eMD* contact has the
//!   history spring; spins are kept per particle outside the slots and change only at
//!   collisions.

/// `$body` with `$e` bound to the engine of whichever broad phase runs.
macro_rules! on_engine {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            $crate::Engine::Crossings($e) => $body,
            $crate::Engine::Epochs($e) => $body,
            $crate::Engine::Neighbours($e) => $body,
        }
    };
}

mod auto;
pub mod bouncing;
pub mod broad_phase;
mod calendar;
pub mod cells;
pub mod collision;
pub mod detect;
mod engine;
mod error;
mod physics;
pub mod queue;
pub mod rules;
mod simulation;
mod state;
mod stats;
mod sweep;
pub mod vibrated;

pub use auto::Engine;
pub use broad_phase::{BroadPhase, Crossings, Epochs, Neighbours};
pub use calendar::CalendarQueue;
pub use engine::{Event, EventEngine, EventHooks, NoHooks};
pub use error::{EngineError, Result};
pub use physics::{BroadPhaseKind, Interference, Physics};
pub use queue::{EventQueue, IndexedHeap};
pub use state::State;
pub use stats::Stats;
