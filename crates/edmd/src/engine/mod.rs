//! The event loop: per-particle next events in a swappable queue, stale events found
//! by collision counters, a broad phase chosen at compile time, and delayed (lazy)
//! particle updates — each particle's state is stored at the time of its last event
//! and moved on only when it is touched (Lubachevsky 1991; DynamO's delayed states).

mod anticipate;
pub(crate) mod build;
mod drive;
mod hooks;
mod host;
mod members;
mod readout;
mod snapshot;
#[cfg(test)]
mod tests;

use crate::broad_phase::BroadPhase;
use crate::calendar::CalendarQueue;
use crate::collision::{self, Rules};
use crate::error::{EngineError, Result};
use crate::queue::EventQueue;
use crate::state::State;
use crate::stats::Stats;
pub use hooks::{EventHooks, NoHooks};
use host::EngineHost;

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
    /// The hooks vetoed the particle's event ([`EventHooks::admit`]).
    Vetoed(u32),
}

/// The event-driven engine for hard spheres, eMD and eMD* on one broad phase `B`.
/// The default queue is the calendar queue (O(1) per event); [`crate::IndexedHeap`]
/// gives the same event order. [`crate::Engine`] chooses the broad phase at run time.
#[derive(serde::Serialize, serde::Deserialize)]
pub struct EventEngine<B, Q: EventQueue = CalendarQueue> {
    state: State<Q>,
    broad: B,
    /// Not saved: a restored engine keeps the rules it was built with.
    #[serde(skip)]
    rules: Rules,
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

    /// The collision rules.
    pub fn rules(&self) -> &Rules {
        &self.rules
    }

    /// Turns the TC model on with duration `tc` in s, or off ([`Rules::set_tc`]).
    pub fn set_tc(&mut self, tc: Option<f64>) -> Result<()> {
        self.rules.set_tc(tc)
    }

    /// Full prediction for particle `i` at the current time: all neighbours, walls and
    /// the next cell crossing.
    #[cfg(test)]
    pub(crate) fn predict(&mut self, i: usize) {
        self.broad.predict(&mut self.state, i);
    }

    /// Processes the next event.
    pub fn step(&mut self) -> Result<Event> {
        self.step_with(&mut NoHooks)
    }

    /// Processes the next event, with `hooks` (see [`EventHooks`]).
    pub fn step_with<H: EventHooks>(&mut self, hooks: &mut H) -> Result<Event> {
        self.anticipate();
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
                     where the gas is dense, eMD* where it is dilute), or --engine emd with \
                     the TC model ([events] tc = t_c in s, e.g. the contact duration: \
                     collisions within t_c of a particle's previous one are elastic), else \
                     --engine md or less dissipation",
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
            return self.step_with(hooks);
        }
        if s.slot[i].ev.pending_time > t {
            let (cross_time, axis, dir) = s.next_crossing(i);
            if cross_time < s.slot[i].ev.coll_time {
                s.stats.crossings += 1;
                self.broad.crossing(s, i, axis, dir);
                return Ok(Event::Crossing(self.state.id[i]));
            }
        }
        if !hooks.admit(i, t) {
            let next = s.next_crossing(i).0;
            s.queue.set(i, next);
            return Ok(Event::Vetoed(s.id[i]));
        }
        let mut host = EngineHost {
            state: &mut self.state,
            broad: &mut self.broad,
            hooks,
        };
        let s = &mut *host.state;
        if s.slot[i].ev.pending_time <= t {
            collision::velocity_event(&mut host, i);
            return Ok(Event::Velocity(self.state.id[i]));
        }
        let j = s.slot[i].ev.coll_partner as usize;
        let n = s.len();
        if j >= n {
            collision::wall_collision(&mut host, &mut self.rules, i, j - n)?;
            return Ok(Event::Wall(self.state.id[i], (j - n) as u32));
        }
        if s.slot[j].ev.counter != s.slot[i].ev.coll_counter {
            s.stats.stale += 1;
            host.broad.predict(host.state, i);
            return Ok(Event::Stale(self.state.id[i]));
        }
        if s.slot[i].ev.coll_now {
            s.stats.stabilising += 1;
        }
        let (id_i, id_j) = (s.id[i], s.id[j]);
        if collision::pair_collision(&mut host, &mut self.rules, i, j)? {
            Ok(Event::Collision(id_i, id_j))
        } else {
            Ok(Event::Resolved(id_i, id_j))
        }
    }

    /// Runs until time `t_end` (all events before it), leaving every particle's
    /// stored state at its last event. Returns early, at the time of the last event,
    /// when a stop is requested ([`emdstar_system::stop`]).
    pub fn run_until(&mut self, t_end: f64) -> Result<()> {
        self.run_until_with(t_end, &mut NoHooks)
    }

    /// [`EventEngine::run_until`] with `hooks` (see [`EventHooks`]).
    pub fn run_until_with<H: EventHooks>(&mut self, t_end: f64, hooks: &mut H) -> Result<()> {
        while self.state.queue.peek().1 <= t_end {
            if emdstar_system::stop::is_requested() {
                return Ok(());
            }
            self.step_with(hooks)?;
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
