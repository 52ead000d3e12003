//! One velocity-Verlet step of a subset of the particles with friction: the
//! counterpart of [`crate::step_subset`] that runs MD's frictional kernel
//! ([`FrictionKernel`]), kicks the spins like the velocities and carries the contacts'
//! springs ([`Springs`]) from step to step.

use crate::forces::{ForceKernel, ForceModel, WALL};
use crate::frictional::{ContactForce, FrictionKernel, Springs};
use crate::neighbour::{INDEX_MASK, NeighbourList};
use crate::verlet::{Motion, StepBounds, close_step, drift, kick_contacts};
use emdstar_contact::Friction;

/// What friction adds to the state one step of a subset changes, indexed by particle.
pub struct SpinMotion<'a> {
    /// Spins, in step with the velocities.
    pub angular_velocity: &'a mut [[f64; 3]],
    /// Angular accelerations of the contacts at the start of the step; replaced by
    /// those at its end for the particles stepped.
    pub angular_acc: &'a mut [[f64; 3]],
    /// 1/I of every particle.
    pub inv_inertia: &'a [f64],
    /// Config id of every particle (the springs' keys).
    pub id: &'a [u32],
    /// The springs of the contacts open before the step; replaced by those open after.
    pub springs: &'a mut Springs,
    /// Scratch for the contacts of the step (its contents are replaced).
    pub contacts: &'a mut Vec<ContactForce>,
}

/// Adds the forces and torques of `contacts` to `acc` and `angular_acc` (a partner
/// gets −f and its own torque).
pub fn add_contact_forces(
    contacts: &[ContactForce],
    inv_mass: &[f64],
    inv_inertia: &[f64],
    acc: &mut [[f64; 3]],
    angular_acc: &mut [[f64; 3]],
) {
    for c in contacts {
        let i = c.i as usize;
        let (mi, ii) = (inv_mass[i], inv_inertia[i]);
        for k in 0..3 {
            acc[i][k] += c.f[k] * mi;
            angular_acc[i][k] += c.torque_i[k] * ii;
        }
        if c.j != WALL {
            let j = c.j as usize;
            let (mj, ij) = (inv_mass[j], inv_inertia[j]);
            for k in 0..3 {
                acc[j][k] -= c.f[k] * mj;
                angular_acc[j][k] += c.torque_j[k] * ij;
            }
        }
    }
}

/// [`crate::step_subset`] with `friction`: the same kicks, drift and normal forces,
/// plus the tangential forces and torques of [`FrictionKernel`] (MD's law, written
/// once), the spins kicked by the torques (ω += (dt/2)·τ/I, as MD), and the springs
/// of the contacts found kept for the next step. A contact absent from a step (ended,
/// or with a partner outside `ids` or refused by `partner`) loses its spring.
#[allow(clippy::too_many_arguments)]
pub fn step_subset_frictional(
    model: &ForceModel<'_>,
    friction: Friction,
    list: &NeighbourList,
    motion: Motion<'_>,
    spins: SpinMotion<'_>,
    ids: &[u32],
    partner: impl Fn(usize) -> bool,
    dt: f64,
) -> StepBounds {
    let Motion {
        position,
        velocity,
        contact_acc,
        new_acc,
        inv_mass,
    } = motion;
    let SpinMotion {
        angular_velocity,
        angular_acc,
        inv_inertia,
        id,
        springs,
        contacts,
    } = spins;
    let h = 0.5 * dt;
    let g = model.gravity;
    let gravity = g != [0.0; 3];
    let gk = [g[0] * h, g[1] * h, g[2] * h];
    kick_contacts(velocity, contact_acc, ids, h);
    kick_contacts(angular_velocity, angular_acc, ids, h);
    let v2_max = drift(position, velocity, ids, gk, dt, gravity);
    contacts.clear();
    {
        let kernel = FrictionKernel {
            base: ForceKernel {
                model: *model,
                list,
                contact_acc: &*contact_acc,
                h,
            },
            friction,
            id,
            angular_velocity: &*angular_velocity,
            angular_acc: &*angular_acc,
            springs: &*springs,
        };
        for &i in ids {
            let i = i as usize;
            let partners = list
                .once(i)
                .iter()
                .copied()
                .filter(|&e| partner((e & INDEX_MASK) as usize));
            let (x, v) = (position[i], velocity[i]);
            kernel.particle(i, x, v, partners, position, velocity, contacts);
        }
    }
    // The angular accelerations of the step are built in place: no scratch for them.
    for &i in ids {
        angular_acc[i as usize] = [0.0; 3];
    }
    add_contact_forces(contacts, inv_mass, inv_inertia, new_acc, angular_acc);
    springs.replace(contacts.iter().map(|c| (c.key, c.spring)));
    // The spins' half kick with the new torques (independent of the velocities' kicks).
    kick_contacts(angular_velocity, angular_acc, ids, h);
    close_step(velocity, contact_acc, new_acc, ids, h, gk, v2_max)
}
