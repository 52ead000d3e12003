//! The time-driven part: the TD particles' steps and the forces of fresh TD particles
//! (both by emdstar-dem's Verlet step and force kernel), and the guard that keeps ED
//! particles out of contact with TD particles.

use super::Hybrid;
use crate::options::Mode;
use emdstar_contact::vec3::{norm, norm2};
use emdstar_dem::{
    Accelerations, ContactEnd, ContactRecord, ForceKernel, ForceModel, Frictional, Motion,
    NeighbourList, Smooth, SpinMotion, TangentialSlot, WALL, apply_contacts, step_subset,
};
use emdstar_system::{Domain, Interactions};

/// MD's force model for particles of `radius` and `species`: the contacts of
/// `interactions`, clipped (F ≥ 0: the only contact end the hybrid supports, see the
/// crate docs).
pub(crate) fn force_model<'a>(
    radius: &'a [f64],
    species: &'a [u32],
    interactions: &'a Interactions,
    domain: &'a Domain,
) -> ForceModel<'a> {
    ForceModel::new(radius, species, interactions, domain, ContactEnd::ForceZero)
}

/// The TD partners of fresh TD particle `i` in `list` whose contacts are not yet in: a
/// pair of fresh particles once, from its lower index.
fn fresh_partners<'a>(
    list: &'a NeighbourList,
    mode: &'a [Mode],
    i: usize,
    fresh: &'a [bool],
) -> impl Iterator<Item = u32> + 'a {
    list.of(i).iter().copied().filter(move |&e| {
        let j = list.split(e).0;
        mode[j] == Mode::Time && !(fresh[j] && j < i)
    })
}

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

    /// One velocity-Verlet step of the TD particles: [`emdstar_dem::step_subset`] on
    /// them (with their spins where contacts have friction), with the pairs of the upper
    /// list (each once) whose partner is TD too (there are no mixed contacts, see the
    /// crate docs).
    #[inline(never)]
    pub(crate) fn td_step(&mut self) {
        self.refresh_td();
        let mode = &self.mode;
        let p = &mut self.system.particles;
        let model = force_model(
            &p.radius,
            &p.species,
            &self.system.interactions,
            &self.system.domain,
        );
        let motion = Motion {
            position: &mut p.position,
            velocity: &mut p.velocity,
            contact_acc: &mut self.contact_acc,
            new_acc: &mut self.new_acc,
            inv_mass: &self.inv_mass,
        };
        let time_driven = |j: usize| mode[j] == Mode::Time;
        let (list, td, dt) = (&self.list, &self.td, self.opts.dt);
        let spins = self.rotation.as_deref_mut().map(|rotation| SpinMotion {
            angular_velocity: &mut p.angular_velocity,
            rotation,
            id: &p.id,
        });
        let scratch = &mut self.contacts;
        let bounds = step_subset(&model, list, motion, spins, scratch, td, time_driven, dt);
        self.v_max_td = bounds.v_max;
        self.a_max_td = bounds.a_max;
        self.steps += 1;
        self.stats.steps += 1;
        self.stats.td_particle_steps += self.td.len() as u64;
    }

    /// Adds the contact forces (and torques) of the particles switched to TD at this
    /// boundary to their and their TD partners' accelerations: the kernel of
    /// emdstar-dem with their velocities now (h = 0), as MD's first step does; the
    /// springs of their new contacts join the others.
    pub(crate) fn add_converted_forces(&mut self) {
        if self.converted.is_empty() {
            return;
        }
        let converted = std::mem::take(&mut self.converted);
        let mut fresh = vec![false; self.mode.len()];
        for &i in &converted {
            fresh[i as usize] = self.mode[i as usize] == Mode::Time;
        }
        let mut scratch = std::mem::take(&mut self.contacts);
        let mut ends = Vec::new();
        let Some(mut rot) = self.rotation.take() else {
            let c = &mut scratch.smooth;
            self.v_max_td = self.fresh_contacts(Smooth, &converted, &fresh, c, &mut ends);
            // Each fresh particle's acceleration once its own contacts are in.
            let mut a2_max = self.a_max_td * self.a_max_td;
            let mut to = Accelerations {
                inv_mass: &self.inv_mass,
                acc: &mut self.contact_acc,
                angular: None,
            };
            let mut start = 0;
            for &(i, end) in &ends {
                apply_contacts(&c[start..end], &mut to, None);
                a2_max = a2_max.max(norm2(to.acc[i]));
                start = end;
            }
            self.a_max_td = a2_max.sqrt();
            self.contacts = scratch;
            return;
        };
        let p = &self.system.particles;
        let slot = Frictional {
            id: &p.id,
            angular_velocity: &p.angular_velocity,
            angular_acc: &rot.angular_acc,
            springs: &rot.springs,
        };
        let c = &mut scratch.frictional;
        self.v_max_td = self.fresh_contacts(slot, &converted, &fresh, c, &mut ends);
        let mut to = Accelerations {
            inv_mass: &self.inv_mass,
            acc: &mut self.contact_acc,
            angular: Some((&rot.inv_inertia, &mut rot.angular_acc)),
        };
        apply_contacts(c.iter(), &mut to, None);
        let mut a2_max = self.a_max_td * self.a_max_td;
        for contact in c.iter() {
            a2_max = a2_max.max(norm2(self.contact_acc[contact.i as usize]));
            if contact.j != WALL {
                a2_max = a2_max.max(norm2(self.contact_acc[contact.j as usize]));
            }
        }
        self.a_max_td = a2_max.sqrt();
        let fresh_springs = c.iter().filter_map(ContactRecord::spring);
        let springs: Vec<_> = rot.springs.iter().copied().chain(fresh_springs).collect();
        rot.springs.replace(springs.into_iter());
        self.rotation = Some(rot);
        self.contacts = scratch;
    }

    /// The contacts of the fresh TD particles among `converted` with their fresh and
    /// older TD partners (a pair of fresh ones once), in order, into `out` (cleared),
    /// with where each particle's end (`ends`: the particle, the length of `out`
    /// after it). Returns the TD speed bound with their speeds.
    fn fresh_contacts<S: TangentialSlot>(
        &self,
        slot: S,
        converted: &[u32],
        fresh: &[bool],
        out: &mut Vec<S::Contact>,
        ends: &mut Vec<(usize, usize)>,
    ) -> f64 {
        out.clear();
        let p = &self.system.particles;
        let kernel = ForceKernel {
            model: force_model(
                &p.radius,
                &p.species,
                &self.system.interactions,
                &self.system.domain,
            ),
            list: &self.list,
            // Not read with h = 0 (zero between steps).
            contact_acc: &self.new_acc,
            h: 0.0,
            slot,
        };
        let mut v_max = self.v_max_td;
        for &i in converted {
            let i = i as usize;
            if fresh[i] {
                let partners = fresh_partners(&self.list, &self.mode, i, fresh);
                let (xi, vi) = (p.position[i], p.velocity[i]);
                kernel.particle(i, xi, vi, partners, &p.position, &p.velocity, out);
                ends.push((i, out.len()));
                v_max = v_max.max(norm(vi));
            }
        }
        v_max
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
