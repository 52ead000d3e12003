//! The engine's side of solving frictional contacts ahead (`collision::SolveAhead`):
//! the collisions predicted since the last event, handed to the worker as the rules
//! will meet them.

use super::EventEngine;
use super::hooks::NoHooks;
use super::host::EngineHost;
use crate::broad_phase::BroadPhase;
use crate::collision::{self, Predicted};
use crate::queue::EventQueue;
use emdstar_contact::vec3::sub;

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// Drops the worker's jobs that time has passed and hands it the frictional
    /// collisions predicted since the last event: each particle's earliest event, if it
    /// is a collision with a particle that flies freely until then. Across a
    /// Lees–Edwards face the image depends on the time: nothing is handed on there.
    pub(super) fn anticipate(&mut self) {
        let Some(ahead) = self.rules.solves_ahead() else {
            return;
        };
        let s = &mut self.state;
        if !s.anticipating {
            s.anticipating = s.domain.shear_rate == 0.0;
        }
        let mut scheduled = std::mem::take(&mut s.scheduled);
        scheduled.sort_unstable();
        scheduled.dedup();
        let changed = scheduled.iter().map(|&i| {
            let i = i as usize;
            (s.id[i], s.slot[i].ev.counter)
        });
        let mut again = Vec::new();
        ahead.note(s.time, changed, &mut again);
        if !again.is_empty() {
            scheduled.extend(again.into_iter().filter(|&i| (i as usize) < s.len()));
            scheduled.sort_unstable();
            scheduled.dedup();
        }
        let host = EngineHost {
            state: &mut self.state,
            broad: &mut self.broad,
            hooks: &mut NoHooks,
        };
        let s = &*host.state;
        let n = s.len();
        for &i in &scheduled {
            let i = i as usize;
            let ev = &s.slot[i].ev;
            let (t, j) = (ev.coll_time, ev.coll_partner as usize);
            let next = j < n && t.is_finite() && s.queue.key(i) == t;
            if !next
                || s.slot[j].ev.counter != ev.coll_counter
                || s.slot[i].ev.pending_time <= t
                || s.slot[j].ev.pending_time <= t
            {
                continue;
            }
            // As `collision::pair_collision` meets them, both synced to t.
            let (xi, vi) = s.state_at(i, t);
            let (xj, vj) = s.state_at(j, t);
            let r = s.min_image(sub(xi, xj));
            let parties = collision::meeting(&host, [i, j], xj, [vi, vj], (r, 0.0));
            let predicted = Predicted {
                time: t,
                parties: [i, j].map(|p| (s.id[p], s.slot[p].ev.counter)),
                slot: i as u32,
            };
            self.rules
                .solve_ahead(predicted, (s.species[i], s.species[j]), &parties);
        }
        scheduled.clear();
        self.state.scheduled = scheduled;
    }
}
