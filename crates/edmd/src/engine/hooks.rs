//! What an engine built on the event core adds to its events: optional hooks with
//! do-nothing defaults ([`NoHooks`], the event engine's own), called by the event loop
//! and the collision rules' host.

/// Hooks into the event loop. The event engine runs without any ([`NoHooks`]); the
/// hybrid engine uses them to budget the events of its event-driven particles per time
/// step, to keep the bounds its neighbour list relies on, and to show eMD*'s exception
/// (a) the time-driven particles, which live outside the event core.
pub trait EventHooks {
    /// Whether [`EventHooks::blocks_rotation`] can ever block (checked at compile time:
    /// the event engine pays nothing for it).
    const BODIES_OUTSIDE: bool = false;

    /// Called before an event of particle `i` at time `t` that is not a cell crossing
    /// (a collision, an E^v, a stale prediction). Returning false vetoes it: the
    /// particle keeps its records, and its next event in the queue becomes its next
    /// cell crossing (where it is filed anew and may be vetoed again).
    #[inline(always)]
    fn admit(&mut self, _i: usize, _t: f64) -> bool {
        true
    }

    /// A particle's velocity was set to `v`, now or (an eMD* E^v) later.
    #[inline(always)]
    fn velocity_set(&mut self, _v: [f64; 3]) {}

    /// Particle `i` jumped by the distance `d` (an eMD* E^φ).
    #[inline(always)]
    fn jumped(&mut self, _i: usize, _d: f64) {}

    /// Whether a body outside the core blocks the rotation of party `i` of an eMD* E^φ
    /// from `old` to `x` (now): within contact of the new position and closer to it than
    /// to the old one (eMD*'s exception (a), `collision::pushes_deeper`).
    #[inline(always)]
    fn blocks_rotation(&self, _i: usize, _x: [f64; 3], _old: [f64; 3]) -> bool {
        false
    }
}

/// No hooks: the event engine's own loop.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoHooks;

impl EventHooks for NoHooks {}
