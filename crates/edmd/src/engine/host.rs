//! The event engine as a host of the shared collision rules: its state and broad
//! phase, apart from the rules that act on them, with the hooks of the engine that
//! runs the loop.

use super::hooks::EventHooks;
use crate::broad_phase::BroadPhase;
use crate::collision::{Host, LastContact, NONE, RotationProbe};
use crate::queue::EventQueue;
use crate::state::{Saved, State};
use crate::stats::Stats;
use emdstar_contact::vec3::{add, norm, sub};
use emdstar_system::Wall;

/// The parts of an [`super::EventEngine`] the collision rules act on.
pub(crate) struct EngineHost<'a, B, Q: EventQueue, H> {
    pub(crate) state: &'a mut State<Q>,
    pub(crate) broad: &'a mut B,
    pub(crate) hooks: &'a mut H,
}

impl<B: BroadPhase, Q: EventQueue, H: EventHooks> Host for EngineHost<'_, B, Q, H> {
    type Saved = Saved;

    #[inline]
    fn now(&self) -> f64 {
        self.state.time
    }

    #[inline]
    fn particles(&self) -> usize {
        self.state.len()
    }

    #[inline]
    fn sync(&mut self, i: usize) {
        let now = self.state.time;
        self.state.advance(i, now);
    }

    #[inline]
    fn position(&self, i: usize) -> [f64; 3] {
        self.state.slot[i].kin.pos
    }

    #[inline]
    fn velocity(&self, i: usize) -> [f64; 3] {
        self.state.slot[i].kin.vel
    }

    #[inline]
    fn set_velocity(&mut self, i: usize, v: [f64; 3]) {
        self.state.slot[i].kin.vel = v;
        self.hooks.velocity_set(v);
    }

    /// Spins are kept by original particle number, out of the slots.
    #[inline]
    fn spin(&self, i: usize) -> [f64; 3] {
        self.state.spin[self.state.id[i] as usize]
    }

    #[inline]
    fn set_spin(&mut self, i: usize, w: [f64; 3]) {
        self.state.spin[self.state.id[i] as usize] = w;
    }

    #[inline]
    fn radius(&self, i: usize) -> f64 {
        self.state.slot[i].kin.radius
    }

    #[inline]
    fn mass(&self, i: usize) -> f64 {
        self.state.mass[i]
    }

    #[inline]
    fn species(&self, i: usize) -> u32 {
        self.state.species[i]
    }

    #[inline]
    fn min_image(&self, d: [f64; 3]) -> [f64; 3] {
        self.state.min_image(d)
    }

    #[inline]
    fn image(&self, d: [f64; 3]) -> ([f64; 3], f64) {
        match self.state.lees_edwards() {
            Some(le) => {
                let (r, up) = le.image(d, self.state.time);
                (r, le.image_velocity(up))
            }
            None => (self.state.min_image(d), 0.0),
        }
    }

    #[inline]
    fn gravity(&self) -> [f64; 3] {
        self.state.domain.gravity
    }

    #[inline]
    fn walls(&self) -> &[Wall] {
        &self.state.domain.walls
    }

    #[inline]
    fn pending_time(&self, i: usize) -> f64 {
        self.state.slot[i].ev.pending_time
    }

    #[inline]
    fn pending_velocity(&self, i: usize) -> [f64; 3] {
        self.state.pending_vel[i]
    }

    #[inline]
    fn partner(&self, i: usize) -> u32 {
        self.state.slot[i].ev.partner
    }

    #[inline]
    fn begin_transient(&mut self, i: usize, end: f64, after: [f64; 3], partner: u32) {
        self.state.pending_vel[i] = after;
        self.state.slot[i].ev.pending_time = end;
        self.state.slot[i].ev.partner = partner;
        self.hooks.velocity_set(after);
    }

    #[inline]
    fn clear_transient(&mut self, i: usize) {
        self.state.slot[i].ev.pending_time = f64::INFINITY;
        self.state.slot[i].ev.partner = NONE;
    }

    #[inline]
    fn changed(&mut self, i: usize) {
        let ev = &mut self.state.slot[i].ev;
        ev.counter = ev.counter.wrapping_add(1);
    }

    #[inline]
    fn last_contact(&self, i: usize) -> LastContact {
        self.state.last_contact[i]
    }

    #[inline]
    fn set_last_contact(&mut self, i: usize, c: LastContact) {
        self.state.last_contact[i] = c;
    }

    /// Puts particle `p` at position `x` now (wrapped, re-filed).
    #[inline]
    fn place(&mut self, p: usize, x: [f64; 3]) {
        if let Some(le) = self.state.lees_edwards() {
            let d = le
                .image(sub(x, self.state.slot[p].kin.pos), self.state.time)
                .0;
            self.hooks.jumped(p, norm(d));
            let x = self.state.place_sheared(&le, p, x);
            self.broad.placed(p, x);
            return;
        }
        let d = self.state.min_image(sub(x, self.state.slot[p].kin.pos));
        self.hooks.jumped(p, norm(d));
        // `x` may come from a partner across a periodic face (in its image): the
        // particle moved by the minimum image of the jump from where it is now, and its
        // image flags follow that, not the face `x` lies beyond.
        let now = self.state.state_at(p, self.state.time).0;
        let moved = add(now, self.state.min_image(sub(x, now)));
        self.state.image[p] = self.state.image_of(p, moved, self.state.wrap(moved));
        let x = self.state.wrap(x);
        self.state.slot[p].kin.pos = x;
        self.state.slot[p].kin.stamp = self.state.time;
        self.broad.placed(p, x);
    }

    #[inline]
    fn save(&self, i: usize) -> Saved {
        Saved {
            kin: self.state.slot[i].kin,
            cell: self.broad.cell_of(i),
            image: self.state.image[i],
        }
    }

    #[inline]
    fn restore(&mut self, i: usize, saved: Saved) {
        self.state.slot[i].kin = saved.kin;
        self.state.image[i] = saved.image;
        self.broad.return_to(i, saved.cell);
    }

    #[inline]
    fn predict(&mut self, i: usize) {
        self.broad.predict(self.state, i);
        if H::BODIES_OUTSIDE
            && let Some((probe, slot)) = self.state.probe_slot(i)
            && self
                .hooks
                .blocks_rotation(i, self.state.slot[i].kin.pos, probe.old_position[slot])
        {
            self.state.block_probe();
        }
    }

    #[inline]
    fn probe(&mut self) -> &mut Option<RotationProbe<Saved>> {
        &mut self.state.probe
    }

    #[inline]
    fn stats(&mut self) -> &mut Stats {
        &mut self.state.stats
    }
}
