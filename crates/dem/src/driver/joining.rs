//! Particles that become members mid-run (the hybrid engine's switches to
//! time-driven): their forces at the current velocities, as a run's first step has
//! them.

use super::slots::{FrictionalKind, SlotKind, SmoothKind};
use super::{Members, Verlet};
use crate::forces::{Accelerations, ContactRecord, apply_contacts};
use crate::neighbour::INDEX_MASK;
use emdstar_system::System;

impl Verlet {
    /// Adds the contact forces (and torques) of the members `fresh`, which have just
    /// joined, to theirs and their member partners' accelerations: the kernel with their
    /// velocities now (h = 0), as [`Verlet::start_forces`]; a pair of fresh particles
    /// once. The springs of their new contacts join the others. The velocities must be
    /// in step ([`Verlet::synchronise`]), and the list complete
    /// ([`Verlet::complete_list`]). Also raises the speed bound to their speeds.
    pub fn add_forces_of<M: Members>(&mut self, system: &System, members: M, fresh: &[u32]) {
        if fresh.is_empty() {
            return;
        }
        debug_assert!(!self.lagging && self.list.has_upper());
        let mut is_fresh = vec![false; system.particles.len()];
        for &i in fresh {
            is_fresh[i as usize] = true;
        }
        if self.rotation.is_some() {
            self.add_fresh::<FrictionalKind, M>(system, members, fresh, &is_fresh);
        } else {
            self.add_fresh::<SmoothKind, M>(system, members, fresh, &is_fresh);
        }
    }

    fn add_fresh<K: SlotKind, M: Members>(
        &mut self,
        system: &System,
        members: M,
        fresh: &[u32],
        is_fresh: &[bool],
    ) {
        let p = &system.particles;
        let mut contacts = Vec::new();
        let kernel = self.kernel::<K>(system, 0.0);
        let mut v2_max = self.v_max * self.v_max;
        for &i in fresh {
            let i = i as usize;
            let partners = self.list.neighbours(i).filter(|&e| {
                let j = (e & INDEX_MASK) as usize;
                members.contains(j) && !(is_fresh[j] && j < i)
            });
            let (xi, vi) = (p.position[i], p.velocity[i]);
            kernel.particle(i, xi, vi, partners, &p.position, &p.velocity, &mut contacts);
            v2_max = v2_max.max(vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]);
        }
        drop(kernel);
        self.v_max = v2_max.sqrt();
        let mut to = Accelerations {
            inv_mass: &self.inv_mass,
            acc: &mut self.contact_acc,
            angular: self
                .rotation
                .as_deref_mut()
                .map(|r| (&r.inv_inertia[..], &mut r.angular_acc[..])),
        };
        apply_contacts(contacts.iter(), &mut to, Some(&mut self.touched));
        self.touched.sort_unstable();
        self.touched.dedup();
        if let Some(rot) = self.rotation.as_mut() {
            let new = contacts.iter().filter_map(ContactRecord::spring);
            let all: Vec<_> = rot.springs.iter().copied().chain(new).collect();
            rot.springs.replace(all.into_iter());
        }
    }
}
