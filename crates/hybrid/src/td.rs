//! The time-driven part: velocity Verlet for the TD particles, the guard that keeps
//! ED particles out of contact with TD particles, and the forces of fresh TD particles.

use crate::engine::{Hybrid, norm};
use crate::options::Mode;
use emdstar_contact::PairLaw;
use emdstar_dem::touch_correction;

impl Hybrid {
    /// Refreshes the sorted list of TD particles after switches.
    pub(crate) fn refresh_td(&mut self) {
        if self.td_dirty {
            self.td.clear();
            self.td.extend(
                (0..self.mode.len() as u32).filter(|&i| self.mode[i as usize] == Mode::Time),
            );
            self.td_dirty = false;
        }
    }

    /// The normal force of `law` at overlap ξ > 0 and rate ξ̇ (clipped, F ≥ 0), plus
    /// the touch correction of emdstar-dem for a contact that started within the step
    /// (`overlap_prev` < 0; see `emdstar_dem::touch_correction`).
    #[inline]
    fn force(law: &PairLaw, overlap_prev: f64, overlap: f64, rate: f64) -> f64 {
        law.normal_force(overlap, rate) + touch_correction(law, overlap_prev, overlap, rate)
    }

    /// One velocity-Verlet step of the TD particles, as emdstar-dem does it:
    /// v(t+dt/2) = v + (dt/2)·a(t); x += dt·v(t+dt/2); forces at the new positions with
    /// the predicted velocity v* = v(t+dt/2) + (dt/2)·a(t); v(t+dt) = v(t+dt/2) +
    /// (dt/2)·a(t+dt). Pairs with an ED particle have no force (there are no mixed
    /// contacts, see the crate docs).
    #[inline(never)]
    pub(crate) fn td_step(&mut self) {
        self.refresh_td();
        let dt = self.opts.dt;
        let h = 0.5 * dt;
        let g = self.system.domain.gravity;
        let p = &mut self.system.particles;
        let mut v2_max: f64 = 0.0;
        for &i in &self.td {
            let i = i as usize;
            let a = self.contact_acc[i];
            let v = p.velocity[i];
            let w: [f64; 3] = std::array::from_fn(|k| v[k] + h * (g[k] + a[k]));
            let x = p.position[i];
            p.position[i] = std::array::from_fn(|k| x[k] + dt * w[k]);
            p.velocity[i] = w;
            v2_max = v2_max.max(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        }
        let predict = |i: usize, v: [f64; 3]| -> [f64; 3] {
            let a = self.contact_acc[i];
            std::array::from_fn(|k| v[k] + h * (g[k] + a[k]))
        };
        let new_acc = &mut self.new_acc;
        for &i in &self.td {
            let i = i as usize;
            let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
            for w in &self.system.domain.walls {
                let overlap = ri - w.distance(xi);
                if overlap > 0.0 {
                    let n = w.normal;
                    let overlap_prev = overlap + dt * (n[0] * vi[0] + n[1] * vi[1] + n[2] * vi[2]);
                    let v = predict(i, vi);
                    let rate = -(n[0] * v[0] + n[1] * v[1] + n[2] * v[2]);
                    let law = &self.materials.wall(p.species[i]).interaction.law;
                    let f = Self::force(law, overlap_prev, overlap, rate) * self.inv_mass[i];
                    for k in 0..3 {
                        new_acc[i][k] += f * n[k];
                    }
                }
            }
            for &entry in self.list.upper(i) {
                let (j, s) = self.list.split(entry);
                if self.mode[j] != Mode::Time {
                    continue;
                }
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
                let l = ri + p.radius[j];
                let r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if r2 >= l * l {
                    continue;
                }
                let r = r2.sqrt();
                let n = d.map(|c| c / r);
                let vj = p.velocity[j];
                let d_prev: [f64; 3] = std::array::from_fn(|k| d[k] - dt * (vi[k] - vj[k]));
                let overlap_prev = l - norm(d_prev);
                let (ui, uj) = (predict(i, vi), predict(j, vj));
                let rate = -(0..3).map(|k| n[k] * (ui[k] - uj[k])).sum::<f64>();
                let law = &self
                    .materials
                    .pair(p.species[i], p.species[j])
                    .interaction
                    .law;
                let f = Self::force(law, overlap_prev, l - r, rate);
                let (fi, fj) = (f * self.inv_mass[i], f * self.inv_mass[j]);
                for k in 0..3 {
                    new_acc[i][k] += fi * n[k];
                    new_acc[j][k] -= fj * n[k];
                }
            }
        }
        let mut a2_max: f64 = 0.0;
        for &i in &self.td {
            let i = i as usize;
            let a = new_acc[i];
            new_acc[i] = [0.0; 3];
            self.contact_acc[i] = a;
            a2_max = a2_max.max(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            let v = p.velocity[i];
            let w: [f64; 3] = std::array::from_fn(|k| v[k] + h * (g[k] + a[k]));
            p.velocity[i] = w;
            v2_max = v2_max.max(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        }
        self.v_max_td = v2_max.sqrt();
        self.a_max_td = a2_max.sqrt();
        self.steps += 1;
        self.stats.steps += 1;
        self.stats.td_particle_steps += self.td.len() as u64;
    }

    /// Adds the contact forces of the particles switched to TD at this boundary (with
    /// their velocities now, as MD's first step does) to their and their TD
    /// partners' accelerations.
    pub(crate) fn add_converted_forces(&mut self) {
        if self.converted.is_empty() {
            return;
        }
        let converted = std::mem::take(&mut self.converted);
        let mut fresh = vec![false; 0];
        fresh.resize(self.mode.len(), false);
        for &i in &converted {
            fresh[i as usize] = self.mode[i as usize] == Mode::Time;
        }
        let p = &self.system.particles;
        let mut a2_max = self.a_max_td * self.a_max_td;
        for &i in &converted {
            let i = i as usize;
            if !fresh[i] {
                continue;
            }
            let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
            for w in &self.system.domain.walls {
                let overlap = ri - w.distance(xi);
                if overlap > 0.0 {
                    let n = w.normal;
                    let rate = -(n[0] * vi[0] + n[1] * vi[1] + n[2] * vi[2]);
                    let law = &self.materials.wall(p.species[i]).interaction.law;
                    let f = law.normal_force(overlap, rate) * self.inv_mass[i];
                    for k in 0..3 {
                        self.contact_acc[i][k] += f * n[k];
                    }
                }
            }
            for &entry in self.list.of(i) {
                let (j, s) = self.list.split(entry);
                if self.mode[j] != Mode::Time || (fresh[j] && j < i) {
                    continue;
                }
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
                let l = ri + p.radius[j];
                let r = norm(d);
                if r >= l {
                    continue;
                }
                let n = d.map(|c| c / r);
                let vj = p.velocity[j];
                let rate = -(0..3).map(|k| n[k] * (vi[k] - vj[k])).sum::<f64>();
                let law = &self
                    .materials
                    .pair(p.species[i], p.species[j])
                    .interaction
                    .law;
                let f = law.normal_force(l - r, rate);
                for k in 0..3 {
                    self.contact_acc[i][k] += f * self.inv_mass[i] * n[k];
                    self.contact_acc[j][k] -= f * self.inv_mass[j] * n[k];
                }
            }
            let a = self.contact_acc[i];
            a2_max = a2_max.max(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            self.v_max_td = self.v_max_td.max(norm(vi));
        }
        self.a_max_td = a2_max.sqrt();
    }

    /// The guard (crate docs): ED particles that could reach a TD particle within the
    /// next step become TD now, and so on from them.
    #[inline(never)]
    pub(crate) fn guard(&mut self) {
        self.refresh_td();
        let active = self.mode.len() - self.stats.removed as usize;
        if self.td.len() == active || self.td.is_empty() {
            return; // no mixed pairs
        }
        let dt = self.opts.dt;
        let t = self.time();
        // Only TD particles with ED list neighbours can meet one; the list of those
        // only grows (by switches to TD) until the next rebuild.
        let mut stack: Vec<u32> = self.boundary.clone();
        while let Some(i) = stack.pop() {
            let i = i as usize;
            if self.mode[i] != Mode::Time {
                continue;
            }
            let (xi, vi) = (
                self.system.particles.position[i],
                self.system.particles.velocity[i],
            );
            let ai = norm(self.contact_acc[i]);
            let n_entries = self.list.of(i).len();
            for e in 0..n_entries {
                let (j, s) = self.list.split(self.list.of(i)[e]);
                if self.mode[j] != Mode::Event {
                    continue;
                }
                let (xj, vj) = self.state_at(j, t);
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - xj[k] - s[k]);
                let gap =
                    norm(d) - self.system.particles.radius[i] - self.system.particles.radius[j];
                let v_rel = norm(std::array::from_fn(|k| vi[k] - vj[k]));
                let reach = 2.0 * (v_rel * dt + ai * dt * dt + self.v_max_ed * dt);
                if gap < reach {
                    // Overlapping and approaching: a contact the guard missed. (A pair
                    // just out of an eMD* collision overlaps by l(1 − ε_r) while it
                    // separates with zero force; that is no contact.)
                    let approach: f64 = (0..3).map(|k| d[k] * (vi[k] - vj[k])).sum();
                    if gap < 0.0 && approach < 0.0 {
                        self.stats.late_conversions += 1;
                        self.stats.max_late_overlap = self.stats.max_late_overlap.max(-gap);
                    }
                    let partner = self.ed[j].partner as usize;
                    self.switch_to_td(j, t);
                    self.stats.guard_conversions += 1;
                    stack.push(j as u32);
                    if partner < self.mode.len() && self.mode[partner] == Mode::Time {
                        stack.push(partner as u32);
                    }
                }
            }
        }
    }
}
