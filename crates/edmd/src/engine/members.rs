//! The event core over a membership: an engine on cell crossings whose particles join
//! and leave one by one (the event-driven particles of the hybrid engine), with
//! everything else of the event engine unchanged. A particle outside is filed in no
//! cell, has no events (+∞ in the queue) and is met by no prediction; its records
//! are kept, but hold nothing.

use super::EventEngine;
use super::build::Prepared;
use crate::broad_phase::{BroadPhase, Crossings};
use crate::cells::{NONE, OUTSIDE};
use crate::collision::{self, LastContact};
use crate::error::Result;
use crate::physics::Physics;
use crate::queue::EventQueue;
use crate::state::EventRec;
use emdstar_system::{Domain, Particles};

impl<Q: EventQueue> EventEngine<Crossings, Q> {
    /// The event core of `particles` in `domain`: cell crossings on the grid the event
    /// engine would choose (the same checks as [`crate::Engine::new`]), with the
    /// particles `member` names filed and predicted in increasing number, as the event
    /// engine starts, and the others outside until they [`EventEngine::join`]. Particle
    /// numbers are the indices of `particles` and stay the caller's: the core never
    /// re-sorts them itself (see [`EventEngine::renumber`]).
    pub fn over_members(
        particles: &Particles,
        domain: &Domain,
        physics: Physics,
        member: impl Fn(usize) -> bool,
    ) -> Result<Self> {
        let mut p = Prepared::<Q>::new(particles, domain, physics, 0.0)?;
        p.state.resort_every = 0;
        // The time-driven part of a hybrid keeps the cores busy: no contacts ahead.
        p.rules.solve_on_one_thread();
        p.state.anticipating = false;
        let n = p.state.len();
        let mut broad = Crossings::new(&p.state.region, p.cell_width, n);
        let mut state = p.state;
        state.queue = Q::new(n);
        let members: Vec<usize> = (0..n).filter(|&i| member(i)).collect();
        broad.grid.coords.iter_mut().for_each(|c| *c = OUTSIDE);
        for &i in &members {
            let c = broad.grid.coords_of(state.slot[i].kin.pos);
            broad.grid.insert(i, c);
        }
        for &i in &members {
            broad.predict(&mut state, i);
        }
        Ok(Self {
            state,
            broad,
            rules: p.rules,
        })
    }

    /// Whether particle `i` is a member.
    #[inline]
    pub fn is_member(&self, i: usize) -> bool {
        self.broad.grid.is_filed(i)
    }

    /// Particles `ids` (outside) join now, with the positions, velocities and spins of
    /// `particles` (indexed as the core): all are filed first, then each is predicted
    /// in the order given.
    pub fn join(&mut self, ids: &[u32], particles: &Particles) {
        let s = &mut self.state;
        let now = s.time;
        for &i in ids {
            let i = i as usize;
            debug_assert!(!self.broad.grid.is_filed(i), "particle {i} is a member");
            debug_assert_eq!(s.id[i], particles.id[i], "numbered as the core");
            s.image[i] = particles.image[i];
            let x = s.wrap_slot(i, particles.position[i]);
            let slot = &mut s.slot[i];
            slot.kin.pos = x;
            slot.kin.vel = particles.velocity[i];
            slot.kin.stamp = now;
            slot.ev = EventRec {
                counter: slot.ev.counter.wrapping_add(1),
                ..EventRec::default()
            };
            s.last_contact[i] = LastContact::NONE;
            let id = s.id[i] as usize;
            s.spin[id] = particles
                .angular_velocity
                .get(i)
                .copied()
                .unwrap_or([0.0; 3]);
            let c = self.broad.grid.coords_of(x);
            self.broad.grid.insert(i, c);
        }
        for &i in ids {
            self.broad.predict(s, i as usize);
        }
    }

    /// Member `i`, outside any eMD* transient ([`EventEngine::end_transient`] first),
    /// leaves now: its position, velocity and spin now. Predictions of others that
    /// name it become stale.
    pub fn leave(&mut self, i: usize) -> ([f64; 3], [f64; 3], [f64; 3]) {
        debug_assert!(self.broad.grid.is_filed(i), "particle {i} is no member");
        let s = &mut self.state;
        debug_assert!(!s.slot[i].ev.pending_time.is_finite(), "in a transient");
        s.advance(i, s.time);
        self.broad.grid.take_out(i);
        let slot = &mut s.slot[i];
        slot.ev = EventRec {
            counter: slot.ev.counter.wrapping_add(1),
            ..EventRec::default()
        };
        s.last_contact[i] = LastContact::NONE;
        s.queue.set(i, f64::INFINITY);
        let kin = s.slot[i].kin;
        (kin.pos, kin.vel, s.spin[s.id[i] as usize])
    }

    /// Renumbers the particles, members or not, so that new number k is old number
    /// `order[k]` (the caller renumbers its own records alike). Only the numbering
    /// changes: states and predicted events move with their particles, nothing is
    /// predicted again.
    pub fn renumber(&mut self, order: &[u32]) {
        self.state.permute(order);
        self.broad.grid.renumber(order);
        // Without any event every key is +∞, whatever the numbering.
        if self.state.queue.peek().1.is_finite() {
            self.state.refile();
        }
    }

    /// Swaps the collision rules with `other`'s (a core decoded from a checkpoint takes
    /// those of the core the config built: rules are not saved).
    pub fn swap_rules(&mut self, other: &mut Self) {
        std::mem::swap(&mut self.rules, &mut other.rules);
    }

    /// Errors unless `self`, decoded from a checkpoint, fits `built`, the core the same
    /// config builds: see `State::check_restored`; cells may hold any particles.
    pub fn check_restored_members(&self, built: &Self) -> std::result::Result<(), String> {
        let n = built.len();
        self.state.check_restored(&built.state, n)?;
        if !crate::state::same_encoding(&self.broad.grid.shape, &built.broad.grid.shape) {
            return Err("another cell grid than the config's".into());
        }
        self.broad.grid.check_restored(n, false)
    }
}

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// Ends the eMD* transient of particle `i` now: its pending E^v runs early (as in
    /// exception (b), exact in momentum and energy), and predictions that name it
    /// become stale; `i` itself is not predicted again.
    pub fn end_transient(&mut self, i: usize) {
        let mut host = super::EngineHost {
            state: &mut self.state,
            broad: &mut self.broad,
            hooks: &mut super::NoHooks,
        };
        collision::finish_transient(&mut host, i);
    }

    /// Who shares the eMD* transient of `i`: a particle, `n + w` for wall w, or `None`
    /// outside a transient.
    #[inline]
    pub fn transient_partner(&self, i: usize) -> Option<u32> {
        let ev = &self.state.slot[i].ev;
        (ev.pending_time.is_finite() && ev.partner != NONE).then_some(ev.partner)
    }

    /// The velocity the pending E^v of `i` applies, if it is in a transient.
    #[inline]
    pub fn pending_velocity(&self, i: usize) -> Option<[f64; 3]> {
        let ev = &self.state.slot[i].ev;
        ev.pending_time
            .is_finite()
            .then(|| self.state.pending_vel[i])
    }

    /// Position and velocity of particle `i` at time `t` (not before its last event),
    /// without moving its stored state (a position in the box along periodic axes at
    /// its last event, not wrapped since).
    #[inline]
    pub fn motion_at(&self, i: usize, t: f64) -> ([f64; 3], [f64; 3]) {
        self.state.state_at(i, t)
    }

    /// Particle `i` now: its position (wrapped into the box) and its velocity with a
    /// pending E^v applied (what it will have once its collision is over).
    pub fn settled(&self, i: usize) -> ([f64; 3], [f64; 3]) {
        let s = &self.state;
        (s.wrap(s.state_at(i, s.time).0), self.settled_velocity(i))
    }

    /// The image flags of particle `i` (slot number) at its [`EventEngine::settled`]
    /// position; after [`EventEngine::leave`], at the position it left with.
    pub fn image(&self, i: usize) -> [i32; 3] {
        let s = &self.state;
        let p = s.state_at(i, s.time).0;
        s.image_of(i, p, s.wrap(p))
    }

    /// The image flags of the stored position of particle `i` (slot number): of the
    /// position [`EventEngine::leave`] gives.
    pub fn stored_image(&self, i: usize) -> [i32; 3] {
        self.state.image[i]
    }

    /// The angular velocity of particle `i` (slot number) in rad/s.
    #[inline]
    pub fn spin(&self, i: usize) -> [f64; 3] {
        self.state.spin[self.state.id[i] as usize]
    }
}
