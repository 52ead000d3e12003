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
        let n = self.len();
        let now = self.state.time;
        let mut host = EngineHost {
            state: &mut self.state,
            broad: &mut self.broad,
            hooks: &mut NoHooks,
        };
        for i in 0..n {
            if host.state.slot[i].ev.pending_time.is_finite() {
                collision::finish_transient(&mut host, i);
            }
        }
        for i in 0..n {
            self.state.advance(i, now);
        }
        let mut v = self.in_original_order(|i| self.state.slot[i].kin.vel);
        let m = self.in_original_order(|i| self.state.mass[i]);
        change(&mut v, &m);
        for i in 0..n {
            let slot = &mut self.state.slot[i];
            slot.kin.vel = v[self.state.id[i] as usize];
            slot.ev.counter = slot.ev.counter.wrapping_add(1);
        }
        for i in 0..n {
            self.broad.predict(&mut self.state, i);
        }
    }
}
