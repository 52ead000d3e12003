//! The event-driven part's step: the event core runs every ED event up to the step's
//! end with the hybrid's hooks (emdstar-edmd's `EventHooks`): each event is counted
//! against its particle's budget, speeds and jumps are noted for the list and the guard,
//! and eMD*'s exception (a) also sees the TD particles.

use super::Hybrid;
use crate::options::{HybridError, Mode};
use emdstar_contact::vec3::{norm, sub};
use emdstar_dem::NeighbourList;
use emdstar_edmd::EventHooks;
use emdstar_edmd::collision::pushes_deeper;
use emdstar_system::Domain;

/// What the events of a step report to the rest of the engine.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct EventBook {
    /// A bound on the speed of every ED particle, pending E^v velocities included.
    pub v_max: f64,
    /// The eMD* position jumps of each particle since the last rebuild or mode check,
    /// and their largest sum (both count against the list's skin).
    jump: Vec<f64>,
    pub max_jump: f64,
    /// Each particle's events in the step it last had one: (step, events).
    budget: Vec<(u64, u32)>,
    /// Particles over their budget, switched to TD at the end of the step.
    pub deferred: Vec<u32>,
    /// Events held back over budget.
    pub vetoed: u64,
}

impl EventBook {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            v_max: 0.0,
            jump: vec![0.0; n],
            max_jump: 0.0,
            budget: vec![(u64::MAX, 0); n],
            deferred: Vec::new(),
            vetoed: 0,
        }
    }

    /// After a rebuild or mode check (between steps; particles may have been
    /// renumbered): no jumps, no events counted.
    pub(crate) fn restart(&mut self) {
        self.jump.iter_mut().for_each(|j| *j = 0.0);
        self.max_jump = 0.0;
        self.budget.iter_mut().for_each(|b| *b = (u64::MAX, 0));
    }

    #[inline]
    pub(crate) fn note_speed(&mut self, v: [f64; 3]) {
        self.v_max = self.v_max.max(norm(v));
    }

    /// Whether a decoded book (a checkpoint's) is whole for `n` particles.
    pub(crate) fn is_whole(&self, n: usize) -> bool {
        self.jump.len() == n
            && self.budget.len() == n
            && self.deferred.iter().all(|&i| (i as usize) < n)
    }
}

/// The TD particles as exception (a) sees them: where they are at the step's start,
/// within a margin of one step's reach.
struct TimeDriven<'a> {
    list: &'a NeighbourList,
    mask: &'a [bool],
    position: &'a [[f64; 3]],
    radius: &'a [f64],
    domain: &'a Domain,
    margin: f64,
}

/// The hybrid's hooks into the event core for one step.
struct Hooks<'a> {
    book: &'a mut EventBook,
    step: u64,
    max_events: u32,
    td: Option<TimeDriven<'a>>,
}

impl EventHooks for Hooks<'_> {
    const BODIES_OUTSIDE: bool = true;

    /// Counts the event; over the budget the particle only crosses cells until the
    /// end of the step, where it becomes TD (crate docs).
    fn admit(&mut self, i: usize, _t: f64) -> bool {
        let (step, events) = &mut self.book.budget[i];
        if *step != self.step {
            *step = self.step;
            *events = 0;
        }
        *events += 1;
        if *events <= self.max_events {
            return true;
        }
        if *events == self.max_events + 1 {
            self.book.deferred.push(i as u32);
        }
        self.book.vetoed += 1;
        false
    }

    #[inline]
    fn velocity_set(&mut self, v: [f64; 3]) {
        self.book.note_speed(v);
    }

    #[inline]
    fn jumped(&mut self, i: usize, d: f64) {
        let book = &mut *self.book;
        book.jump[i] += d;
        book.max_jump = book.max_jump.max(book.jump[i]);
    }

    /// A TD particle within contact (plus the margin) of the party's new position,
    /// closer to it than to the old one, blocks the rotation.
    fn blocks_rotation(&self, i: usize, x: [f64; 3], old: [f64; 3]) -> bool {
        let Some(td) = &self.td else {
            return false;
        };
        let min_image = |d| td.domain.min_image(d);
        td.list.neighbours(i).any(|e| {
            let j = td.list.split(e).0;
            td.mask[j] && {
                let xj = td.position[j];
                let contact = td.radius[i] + td.radius[j] + td.margin;
                pushes_deeper(min_image(sub(x, xj)), old, xj, contact, min_image)
            }
        })
    }
}

impl Hybrid {
    /// Runs every ED event up to `t_end` (the end of the step), in time order.
    pub(super) fn run_events(&mut self, t_end: f64) -> Result<(), HybridError> {
        let mixed = self.modes.any(Mode::Time) && self.modes.any(Mode::Event);
        if mixed {
            self.td.complete_list();
        }
        let margin = self.td_probe_margin();
        let td = mixed.then(|| TimeDriven {
            list: self.td.list(),
            mask: self.modes.time_driven(),
            position: &self.system.particles.position,
            radius: &self.system.particles.radius,
            domain: &self.system.domain,
            margin,
        });
        let mut hooks = Hooks {
            book: &mut self.book,
            step: self.steps,
            max_events: self.opts.max_events_per_step,
            td,
        };
        self.ed.run_until_with(t_end, &mut hooks)?;
        self.stats.ed = *self.ed.stats();
        self.stats.vetoed_events = self.book.vetoed;
        Ok(())
    }

    /// How close a jump may bring an ED particle to a TD one: within one step's reach,
    /// the guard (which runs at step boundaries) would find the pair in contact.
    fn td_probe_margin(&self) -> f64 {
        2.0 * (self.td.v_max() + self.book.v_max) * self.opts.dt
    }

    /// At the end of a step: the ED particles over their event budget become TD.
    pub(super) fn switch_deferred(&mut self) -> Result<(), HybridError> {
        if self.book.deferred.is_empty() {
            return Ok(());
        }
        let t = self.time();
        self.in_step(t)?;
        for i in std::mem::take(&mut self.book.deferred) {
            let i = i as usize;
            if self.modes.of(i) == Mode::Event {
                self.switch_to_time(i);
                self.stats.budget_conversions += 1;
            }
        }
        if !self.upkeep.list {
            // Leave the phase without TD particles: the list comes back.
            self.rebuild(false)?;
        } else {
            self.td.complete_list();
        }
        self.add_fresh_forces();
        Ok(())
    }

    /// Adds the forces of the particles switched to TD at this boundary, as MD's first
    /// step has them (their velocities now), to theirs and their TD partners'.
    pub(super) fn add_fresh_forces(&mut self) {
        if self.scratch.fresh.is_empty() {
            return;
        }
        self.td.complete_list();
        let fresh = std::mem::take(&mut self.scratch.fresh);
        self.td
            .add_forces_of(&self.system, self.modes.time_driven(), &fresh);
        self.scratch.fresh = fresh;
        self.scratch.fresh.clear();
    }
}
