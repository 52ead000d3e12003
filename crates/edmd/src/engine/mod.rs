//! The event loop: per-particle next events in a swappable queue, stale events found
//! by collision counters, a broad phase chosen at compile time, and delayed (lazy)
//! particle updates — each particle's state is stored at the time of its last event
//! and moved on only when it is touched (Lubachevsky 1991; DynamO's delayed states).

pub(crate) mod build;
mod host;
mod readout;
mod snapshot;
#[cfg(test)]
mod tests;

use crate::broad_phase::BroadPhase;
use crate::calendar::CalendarQueue;
use crate::collision;
use crate::error::{EngineError, Result};
use crate::queue::EventQueue;
use crate::state::State;
use crate::stats::Stats;
use emdstar_contact::{Friction, TangentialModel, Walton};

/// What [`EventEngine::step`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// A pair collision (for eMD*: its E^φ event, or the eMD fallback).
    Collision(u32, u32),
    /// A collision with wall `w`.
    Wall(u32, u32),
    /// An eMD* E^v event: the particle took its post-collision velocity.
    Velocity(u32),
    /// A particle moved into another cell (with epochs: renewed its swept box early).
    Crossing(u32),
    /// A new epoch of the epoch broad phase began (no particle changed).
    Epoch,
    /// A stale prediction was discarded and the particle re-predicted.
    Stale(u32),
    /// An interfering collision whose pair stopped approaching once the pending E^v
    /// events ran (eMD* exception b); nothing else happened.
    Resolved(u32, u32),
}

/// The event-driven engine for hard spheres, eMD and eMD* on one broad phase `B`.
/// The default queue is the calendar queue (O(1) per event); [`crate::IndexedHeap`]
/// gives the same event order. [`crate::Engine`] chooses the broad phase at run time.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct EventEngine<B, Q: EventQueue = CalendarQueue> {
    state: State<Q>,
    broad: B,
}

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    const MAX_ZERO_TIME_EVENTS: u64 = 10_000_000;

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.state.len()
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        self.state.slot.is_empty()
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// Event and exception counters.
    pub fn stats(&self) -> &Stats {
        &self.state.stats
    }

    /// The collision rule.
    pub fn physics(&self) -> &crate::physics::Physics {
        &self.state.physics
    }

    /// Friction by Walton's rule, if collisions are frictional.
    pub fn friction(&self) -> Option<Walton> {
        self.state.walton
    }

    /// Makes collisions of spheres and with walls frictional by Walton's rule
    /// (`emdstar_contact::Walton`; docs/physics.md): spins change at collisions. For
    /// hard spheres and eMD; eMD* refuses (it solves the history spring exactly:
    /// [`EventEngine::with_exact_friction`]). µ = 0 is
    /// frictionless and keeps the frictionless rule, bit for bit.
    pub fn with_friction(mut self, walton: Walton) -> Result<Self> {
        if let crate::physics::Physics::EmdStar { .. } = self.state.physics {
            return Err(EngineError::Invalid(
                "eMD* does not run Walton's rule: its frictional collisions are the exact \
                 contact with the history spring (tangential_stiffness); Walton's rule runs on \
                 hard spheres and eMD"
                    .into(),
            ));
        }
        Walton::new(walton.friction, walton.tangential_restitution)?;
        self.state.walton = (walton.friction > 0.0).then_some(walton);
        Ok(self)
    }

    /// eMD*'s frictional spheres, if collisions are frictional.
    pub fn exact_friction(&self) -> Option<Friction> {
        self.state.exact_friction
    }

    /// Makes eMD*'s pair collisions frictional: each is the exact contact of the
    /// normal law with the history spring of `friction` and both spins
    /// (`emdstar_mor::frictional`; docs/physics.md, "eMD* with friction"). For eMD* only,
    /// spheres without walls (a wall's frictional contact is not solved yet), and the
    /// history spring (pure Coulomb sliding has no exact solve). µ = 0 keeps the
    /// frictionless rule, bit for bit.
    pub fn with_exact_friction(mut self, friction: Friction) -> Result<Self> {
        let crate::physics::Physics::EmdStar { .. } = self.state.physics else {
            return Err(EngineError::Invalid(
                "the exact frictional contact is eMD*'s rule; hard spheres and eMD run \
                 friction by Walton's rule (tangential_restitution)"
                    .into(),
            ));
        };
        if !friction.is_active() {
            return Ok(self);
        }
        if friction.model != TangentialModel::History || friction.tangential_restitution.is_some() {
            return Err(EngineError::Invalid(
                "eMD* with friction solves the history spring exactly: give the material \
                 tangential_stiffness (and tangential_damping) with tangential = \"history\", \
                 not tangential_restitution (Walton's rule, run by --engine emd) or tangential = \
                 \"coulomb\""
                    .into(),
            ));
        }
        if !self.state.domain.walls.is_empty() {
            return Err(EngineError::Invalid(
                "eMD* with friction has no frictional wall contact yet: remove the walls \
                 (periodic box or free space), or run friction with walls on --engine md"
                    .into(),
            ));
        }
        let checked = Friction::new(
            friction.friction,
            friction.stiffness,
            friction.damping,
            friction.model,
        )?;
        self.state.exact_friction = Some(checked);
        Ok(self)
    }

    /// Full prediction for particle `i` at the current time: all neighbours, walls and
    /// the next cell crossing.
    #[inline]
    pub(crate) fn predict(&mut self, i: usize) {
        self.broad.predict(&mut self.state, i);
    }

    /// Processes the next event.
    pub fn step(&mut self) -> Result<Event> {
        let s = &mut self.state;
        let (i, t) = s.queue.peek();
        if !t.is_finite() {
            return Err(EngineError::Invalid(
                "no event is left: every particle flies freely for ever (an empty or \
                 fully separating system); run for a fixed time instead"
                    .into(),
            ));
        }
        // Time that advances by round-off only (at most four ulps: eMD*'s events pile up
        // at one instant, eMD's wall bounces shrink to one ulp each) counts as standing.
        if t - s.time <= 2.0 * f64::EPSILON * t.abs() {
            s.zero_streak += 1;
            if s.zero_streak > Self::MAX_ZERO_TIME_EVENTS {
                return Err(EngineError::Invalid(format!(
                    "more than {} events at t = {t:e} s without time advancing beyond \
                     round-off: an inelastic collapse (Bannerman et al. 2014, Sec. 5), such \
                     as spheres coming to rest on a wall or on each other; event-driven \
                     dynamics cannot go on. For a bed that settles run --engine hybrid (MD \
                     where the gas is dense, eMD* where it is dilute), else --engine md or \
                     less dissipation",
                    Self::MAX_ZERO_TIME_EVENTS
                )));
            }
        } else {
            s.zero_streak = 0;
        }
        s.time = t;
        s.stats.events += 1;
        s.since_resort += 1;
        s.prefetch_upcoming(|id| self.broad.prefetch(id));
        if i >= s.len() {
            self.broad.own_event(s);
            return Ok(Event::Epoch);
        }
        if self.broad.resorts_between_events()
            && s.resort_every > 0
            && s.since_resort >= s.resort_every
        {
            s.since_resort = 0;
            self.broad.resort(s);
            s.stats.events -= 1;
            return self.step();
        }
        if s.slot[i].ev.pending_time <= t {
            collision::velocity_event(self, i);
            return Ok(Event::Velocity(self.state.id[i]));
        }
        let (cross_time, axis, dir) = s.next_crossing(i);
        if cross_time < s.slot[i].ev.coll_time {
            s.stats.crossings += 1;
            self.broad.crossing(s, i, axis, dir);
            return Ok(Event::Crossing(self.state.id[i]));
        }
        let j = s.slot[i].ev.coll_partner as usize;
        let n = s.len();
        if j >= n {
            collision::wall_collision(self, i, j - n)?;
            return Ok(Event::Wall(self.state.id[i], (j - n) as u32));
        }
        if s.slot[j].ev.counter != s.slot[i].ev.coll_counter {
            s.stats.stale += 1;
            self.predict(i);
            return Ok(Event::Stale(self.state.id[i]));
        }
        if s.slot[i].ev.coll_now {
            s.stats.stabilising += 1;
        }
        let (id_i, id_j) = (s.id[i], s.id[j]);
        if collision::pair_collision(self, i, j)? {
            Ok(Event::Collision(id_i, id_j))
        } else {
            Ok(Event::Resolved(id_i, id_j))
        }
    }

    /// Runs until time `t_end` (all events before it), leaving every particle's
    /// stored state at its last event. Returns early, at the time of the last event,
    /// when a stop is requested ([`emdstar_system::stop`]).
    pub fn run_until(&mut self, t_end: f64) -> Result<()> {
        while self.state.queue.peek().1 <= t_end {
            if emdstar_system::stop::is_requested() {
                return Ok(());
            }
            self.step()?;
        }
        self.state.time = self.state.time.max(t_end);
        Ok(())
    }

    /// Runs until `count` more pair and wall collisions have been executed.
    pub fn run_collisions(&mut self, count: u64) -> Result<()> {
        let target = self.state.stats.collisions() + count;
        while self.state.stats.collisions() < target && !emdstar_system::stop::is_requested() {
            self.step()?;
        }
        Ok(())
    }

    /// Sets how many events pass between spatial re-sorts of the particle order
    /// (0 switches re-sorting off).
    pub fn set_resort_interval(&mut self, events: u64) {
        self.state.resort_every = events;
    }
}
