//! The guard (crate docs, "Mixed pairs: no mixed contacts"): at every step boundary,
//! ED particles that could reach a TD particle within the step become TD before the
//! contact starts, and so on from them.

use super::Hybrid;
use crate::options::{HybridError, Mode};
use emdstar_contact::vec3::{dot, norm, sub};

impl Hybrid {
    /// Switches to TD every ED particle that could reach a TD particle within the next
    /// step (gap < 2·(|v_ij|·dt + |a_i|·dt² + v_ED,max·dt)). Only TD particles with ED
    /// list neighbours can meet one; their list only grows (by switches to TD) until
    /// the next rebuild.
    pub(super) fn guard(&mut self) -> Result<(), HybridError> {
        if !(self.modes.any(Mode::Time) && self.modes.any(Mode::Event)) {
            return Ok(());
        }
        self.td.complete_list();
        let (t, dt) = (self.time(), self.opts.dt);
        let mut in_step = false;
        let mut stack = self.boundary.clone();
        let mut reached = Vec::new();
        while let Some(i) = stack.pop() {
            let i = i as usize;
            if self.modes.of(i) != Mode::Time {
                continue;
            }
            let p = &self.system.particles;
            let (xi, vi) = (p.position[i], self.td_velocity(i));
            let ai = norm(self.td.contact_acc(i));
            let list = self.td.list();
            reached.clear();
            for e in list.neighbours(i) {
                let j = list.split(e).0;
                if self.modes.of(j) != Mode::Event {
                    continue;
                }
                let (xj, vj) = self.ed.motion_at(j, t);
                let d = self.system.domain.min_image(sub(xi, xj));
                let gap = norm(d) - p.radius[i] - p.radius[j];
                let v_rel = sub(vi, vj);
                let reach = 2.0 * (norm(v_rel) * dt + ai * dt * dt + self.book.v_max * dt);
                if gap < reach {
                    // Overlapping and approaching: a contact the guard missed. (A pair
                    // just out of an eMD* collision overlaps by l(1 − ε_r) while it
                    // separates with zero force; that is no contact.)
                    if gap < 0.0 && dot(d, v_rel) < 0.0 {
                        self.stats.late_conversions += 1;
                        self.stats.max_late_overlap = self.stats.max_late_overlap.max(-gap);
                    }
                    reached.push(j);
                }
            }
            for &j in &reached {
                if self.modes.of(j) != Mode::Event {
                    continue;
                }
                if !in_step {
                    self.in_step(t)?;
                    in_step = true;
                }
                let partner = self.ed.transient_partner(j);
                self.switch_to_time(j);
                self.stats.guard_conversions += 1;
                stack.push(j as u32);
                if let Some(k) = partner.map(|k| k as usize)
                    && k < self.modes.len()
                    && self.modes.of(k) == Mode::Time
                {
                    stack.push(k as u32);
                }
            }
        }
        Ok(())
    }

    /// TD particle `i`'s velocity now: its stored one without the step's contact kick
    /// if taken, with a pending half kick.
    fn td_velocity(&self, i: usize) -> [f64; 3] {
        let (a, g) = (self.td.contact_acc(i), self.system.domain.gravity);
        let kick = self.td_kick.unwrap_or(0.0);
        let h = if self.td.is_lagging() {
            0.5 * self.opts.dt
        } else {
            0.0
        };
        let v = self.system.particles.velocity[i];
        std::array::from_fn(|k| v[k] - kick * a[k] + h * (a[k] + g[k]))
    }
}
