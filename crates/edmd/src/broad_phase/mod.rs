//! How the event engine finds the pairs it tests, behind one trait with three
//! implementations: [`Crossings`] (a cell grid and a crossing event whenever a
//! particle changes cell; Alder & Wainwright 1959, Rapaport 1980), [`Epochs`]
//! (swept boxes filed once per epoch, see [`crate::sweep`]) and [`Neighbours`]
//! (a neighbour list per particle, rebuilt when it leaves its shell). All give the
//! same collisions; the engine is generic over the broad phase, so each runs its own
//! monomorphised event loop.

mod centre_cells;
mod crossings;
mod epoch_pairs;
mod epochs;
mod neighbours;
mod sheared;

pub use crossings::Crossings;
pub use epochs::Epochs;
pub use neighbours::Neighbours;

use crate::queue::EventQueue;
use crate::state::State;
use emdstar_system::SimBox;

/// A broad phase of the event engine.
///
/// # Contract
/// - **No candidate missed.** [`BroadPhase::predict_pairs`] for particle `i` (synced
///   to now) tests `i` with Bannerman et al. 2014, Algorithm 1, against every
///   particle that it could meet before its next crossing or horizon (the next own
///   event of `i` that this broad phase schedules through `EventRec::cross`), and
///   keeps the earliest collision through [`State::keep_earliest`]. Collisions
///   beyond that event need not be found: `i` is predicted again there.
/// - **Probe.** While `State::probe` names `i` as a party, the same scan passes every
///   particle that could be within contact of `i`'s position to
///   [`State::blocks_rotation`] and blocks the probe if one blocks (eMD*'s exception
///   (a)).
/// - **Filing.** After [`BroadPhase::placed`] (a jump of `i` by an E^φ, or its undo)
///   `i` is found at its new position.
/// - **Determinism.** Candidates are visited in an order fixed by the state alone, so
///   equal inputs give equal event sequences.
pub trait BroadPhase: Sized {
    /// Queue ids this broad phase uses after the particles' (for its own events).
    const OWN_EVENTS: usize;
    /// Whether the broad phase fits `region` for `n` particles whose largest contact
    /// distance is `max_contact`.
    fn fits(region: &SimBox, max_contact: f64, n: usize) -> bool;

    /// Errors unless `self`, decoded from a checkpoint, fits `built` (what the same
    /// config builds) for `n` particles: the geometry the config determines, one entry
    /// per particle in every array and no index out of range.
    fn check_restored(&self, built: &Self, n: usize) -> Result<(), String>;

    /// Files every particle of `state` at its stored position (already wrapped).
    fn file<Q: EventQueue>(&mut self, state: &State<Q>);

    /// Predicts the first events of every particle, once filed (and re-sorted).
    fn start<Q: EventQueue>(&mut self, state: &mut State<Q>);

    /// The full prediction of `i` at the current time: its pairs, the walls, its next
    /// crossing, and its place in the queue.
    #[inline]
    fn predict<Q: EventQueue>(&mut self, state: &mut State<Q>, i: usize) {
        let now = state.time;
        state.advance(i, now);
        let ev = &mut state.slot[i].ev;
        ev.coll_time = f64::INFINITY;
        ev.coll_partner = crate::collision::NONE;
        ev.coll_now = false;
        self.predict_pairs(state, i);
        state.predict_walls(i);
        self.predict_crossing(state, i);
        state.schedule(i);
    }

    /// The pair part of a full prediction of `i` (see the contract).
    fn predict_pairs<Q: EventQueue>(&mut self, state: &mut State<Q>, i: usize);

    /// After the pair and wall predictions of `i`: its next crossing, if any.
    fn predict_crossing<Q: EventQueue>(&mut self, state: &mut State<Q>, i: usize);

    /// `i` reached its next crossing along `axis` in direction `dir`.
    fn crossing<Q: EventQueue>(&mut self, state: &mut State<Q>, i: usize, axis: usize, dir: i64);

    /// One of the broad phase's own events came due.
    fn own_event<Q: EventQueue>(&mut self, state: &mut State<Q>);

    /// `i` now stands at its stored position after a jump.
    fn placed(&mut self, i: usize, x: [f64; 3]);

    /// The cell `i` is filed under (restored with [`BroadPhase::return_to`]).
    fn cell_of(&self, i: usize) -> [u32; 3];

    /// Puts `i` back into `cell` (undoing a jump).
    fn return_to(&mut self, i: usize, cell: [u32; 3]);

    /// Whether the engine re-sorts the particles between events (else the broad
    /// phase does so at its own events).
    fn resorts_between_events(&self) -> bool;

    /// Asks for what an event of `i` will read of this broad phase's own records
    /// (a hint for a large gas: see [`State::prefetch_upcoming`]).
    #[inline(always)]
    fn prefetch(&self, _i: usize) {}

    /// Renumbers the particles in space (Morton order of their cells); see
    /// [`State::permute`].
    fn resort<Q: EventQueue>(&mut self, state: &mut State<Q>);
}
