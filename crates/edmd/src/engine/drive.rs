//! Velocities changed from outside the events (a thermostat's tick): every particle
//! brought to now, every eMD* transient ended, the new velocities set and every
//! prediction made again.

use super::EventEngine;
use super::hooks::NoHooks;
use super::host::EngineHost;
use crate::broad_phase::BroadPhase;
use crate::collision;
use crate::queue::EventQueue;
use emdstar_system::VelocityChange;

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// Changes the velocities now: pending E^v events run first (as when a third party
    /// hits a particle in its transient, [MP13] Sec. VI B 5 (b)), then `change` gets
    /// the velocities and masses in config order, and every particle is predicted
    /// again. Predictions of broad phases that bound speeds (epochs, neighbour lists)
    /// are not renewed: run such changes on cell crossings.
    pub fn change_velocities(&mut self, change: &mut VelocityChange<'_>) {
        self.bring_to_now(|_| true);
        let mut v = self.in_original_order(|i| self.state.slot[i].kin.vel);
        let m = self.in_original_order(|i| self.state.mass[i]);
        change(&mut v, &m);
        let id = self.state.id.clone();
        self.set_velocities_now(|_| true, |i| v[id[i] as usize]);
    }

    /// The first half of a change of velocities from outside, for the particles
    /// `member` accepts (slot numbers; a membership's members, or all): their pending
    /// E^v events run now ([MP13] Sec. VI B 5 (b)), then each is moved to now, its
    /// motion up to now in the kinetic sums. Their velocities now are then their
    /// [`EventEngine::motion_at`] now.
    pub fn bring_to_now(&mut self, member: impl Fn(usize) -> bool) {
        let n = self.len();
        let now = self.state.time;
        let mut host = EngineHost {
            state: &mut self.state,
            broad: &mut self.broad,
            hooks: &mut NoHooks,
        };
        for i in (0..n).filter(|&i| member(i)) {
            if host.state.slot[i].ev.pending_time.is_finite() {
                collision::finish_transient(&mut host, i);
            }
        }
        for i in (0..n).filter(|&i| member(i)) {
            self.state.advance(i, now);
        }
    }

    /// The second half (after [`EventEngine::bring_to_now`] of the same particles):
    /// each particle `member` accepts takes the velocity `v(slot)` now, its predictions
    /// become stale, and each is predicted again, in increasing slot number.
    pub fn set_velocities_now(
        &mut self,
        member: impl Fn(usize) -> bool,
        v: impl Fn(usize) -> [f64; 3],
    ) {
        let n = self.len();
        for i in (0..n).filter(|&i| member(i)) {
            let slot = &mut self.state.slot[i];
            slot.kin.vel = v(i);
            slot.ev.counter = slot.ev.counter.wrapping_add(1);
        }
        for i in (0..n).filter(|&i| member(i)) {
            self.broad.predict(&mut self.state, i);
        }
    }
}
