//! Frictional contacts: the tangential forces and torques of
//! [`emdstar_contact::Friction`] in one velocity-Verlet step, with the springs each
//! contact carries from step to step ([`Springs`]).
//!
//! The normal force is the frictionless kernel's (predictor and touch correction
//! included). The tangential force of the step follows the conventions of
//! `emdstar_contact::tangential` (those of LAMMPS's `pair granular … tangential
//! linear_history` with `limit_damping`); for second order in dt:
//! - the spring of the step before is turned from the old normal to the new one, and
//!   grows by dt·**v**_t at the middle of the step (the stored half-step velocities and
//!   spins, with the normal at mid-step), projected onto the new tangent plane;
//! - the dashpot uses the predicted slip (velocities and spins v + (dt/2)·a, as the
//!   normal dashpot);
//! - in the first step of a contact the spring grows only over the part of the step
//!   after touch, and a tangential force that jumps on at touch (a linear dashpot's) is
//!   corrected like the normal force ([`crate::touch_correction`]).

use crate::forces::{ForceKernel, WALL, normal_force, touch_correction};
use emdstar_contact::vec3::{add, add_scaled, dot, norm, norm2, scale, sub};
use emdstar_contact::{Friction, TangentialModel, lever_arm, slip_velocity, torque, turn_spring};
use emdstar_system::Wall;

/// The key of a contact in [`Springs`]: the two config ids, smaller first; a wall
/// contact has `WALL - w` for wall `w` as its second id.
pub type ContactKey = (u32, u32);

/// The springs ξ_t of the contacts open at the end of a step, sorted by key. Each
/// spring is stored as seen by the contact's first id (the particle with the smaller
/// config id; the particle itself for a wall), so it survives the re-sorting of the
/// particles at a neighbour-list rebuild.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Springs {
    contacts: Vec<(ContactKey, [f64; 3])>,
}

impl Springs {
    /// The spring of a contact (zero for a contact that was not open).
    #[inline]
    pub fn get(&self, key: ContactKey) -> [f64; 3] {
        match self.contacts.binary_search_by_key(&key, |c| c.0) {
            Ok(k) => self.contacts[k].1,
            Err(_) => [0.0; 3],
        }
    }

    /// Replaces the springs by those of `records`.
    pub fn replace(&mut self, records: impl Iterator<Item = (ContactKey, [f64; 3])>) {
        self.contacts.clear();
        self.contacts.extend(records);
        self.contacts.sort_unstable_by_key(|c| c.0);
    }

    /// Whether decoded springs (a checkpoint's) are sorted by key, each key once, each
    /// seen by a particle below `n`.
    pub fn are_whole(&self, n: usize) -> bool {
        self.contacts.windows(2).all(|w| w[0].0 < w[1].0)
            && self.contacts.iter().all(|((a, _), _)| (*a as usize) < n)
    }

    /// The open contacts and their springs.
    pub fn iter(&self) -> impl Iterator<Item = &(ContactKey, [f64; 3])> {
        self.contacts.iter()
    }

    /// Number of open contacts.
    pub fn len(&self) -> usize {
        self.contacts.len()
    }

    /// True without open contacts.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// The elastic energy of the springs under `friction`, Σ ½ k_t |ξ_t|² (none for
    /// pure Coulomb sliding, which has no spring).
    pub fn energy(&self, friction: &Friction) -> f64 {
        match friction.model {
            TangentialModel::History => self
                .contacts
                .iter()
                .map(|(_, s)| 0.5 * friction.stiffness * norm2(*s))
                .sum(),
            TangentialModel::Coulomb => 0.0,
        }
    }
}

/// One frictional contact of a step: the force on i (normal and tangential; −f on j),
/// the torques on both, and the contact's spring afterwards.
#[derive(Debug, Clone, Copy)]
pub struct ContactForce {
    pub i: u32,
    /// The partner, or [`WALL`].
    pub j: u32,
    pub f: [f64; 3],
    pub torque_i: [f64; 3],
    pub torque_j: [f64; 3],
    pub key: ContactKey,
    /// The spring in the frame of the key's first id.
    pub spring: [f64; 3],
}

/// The frictional force kernel of one step: the frictionless one for the normal
/// forces, the spins, and the springs of the step before.
pub struct FrictionKernel<'a> {
    pub base: ForceKernel<'a>,
    pub friction: Friction,
    /// Config id of each particle (the springs are keyed by them).
    pub id: &'a [u32],
    /// Stored spins, half a kick behind like the velocities.
    pub angular_velocity: &'a [[f64; 3]],
    /// Angular accelerations of the contacts of the previous step.
    pub angular_acc: &'a [[f64; 3]],
    pub springs: &'a Springs,
}

/// Where the mid-step values and the predicted ones of one party of a contact meet.
#[derive(Clone, Copy)]
struct Party {
    radius: f64,
    /// Stored (mid-step) velocity and spin.
    v: [f64; 3],
    w: [f64; 3],
    /// Predicted (end-of-step) velocity and spin.
    v_pred: [f64; 3],
    w_pred: [f64; 3],
}

const WALL_PARTY: Party = Party {
    radius: 0.0,
    v: [0.0; 3],
    w: [0.0; 3],
    v_pred: [0.0; 3],
    w_pred: [0.0; 3],
};

impl FrictionKernel<'_> {
    /// The contacts of particle `i` (at `xi` with stored velocity `vi`) with the walls
    /// and the partners `entries`, walls first, as [`ForceKernel::particle`].
    #[allow(clippy::too_many_arguments)]
    pub fn particle(
        &self,
        i: usize,
        xi: [f64; 3],
        vi: [f64; 3],
        entries: impl IntoIterator<Item = u32>,
        position: &[[f64; 3]],
        velocity: &[[f64; 3]],
        out: &mut Vec<ContactForce>,
    ) {
        let model = &self.base.model;
        let ri = model.radius[i];
        let pi = self.party(i, vi);
        for (w, wall) in model.walls.iter().enumerate() {
            let overlap = ri - wall.distance(xi);
            if overlap > 0.0 {
                self.wall(i, w, wall, overlap, pi, out);
            }
        }
        let list = self.base.list;
        for entry in entries {
            let (j, s) = list.split(entry);
            let d: [f64; 3] = std::array::from_fn(|k| xi[k] - position[j][k] - s[k]);
            let l = ri + model.radius[j];
            if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < l * l {
                let pj = self.party(j, velocity[j]);
                self.pair(i, j, d, l, pi, pj, out);
            }
        }
    }

    fn party(&self, i: usize, v: [f64; 3]) -> Party {
        let h = self.base.h;
        let w = self.angular_velocity[i];
        Party {
            radius: self.base.model.radius[i],
            v,
            w,
            v_pred: self.base.predict(i, v),
            w_pred: add_scaled(w, h, self.angular_acc[i]),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn pair(
        &self,
        i: usize,
        j: usize,
        d: [f64; 3],
        l: f64,
        pi: Party,
        pj: Party,
        out: &mut Vec<ContactForce>,
    ) {
        let dt = 2.0 * self.base.h;
        let r = norm(d);
        let n = scale(1.0 / r, d);
        let v_mid = sub(pi.v, pj.v);
        // The drift was x += dt·v exactly: the separation one step and half a step ago.
        let d_prev = add_scaled(d, -dt, v_mid);
        let d_mid = add_scaled(d, -0.5 * dt, v_mid);
        let overlap_prev = l - norm(d_prev);
        let model = &self.base.model;
        let law = &model
            .interactions
            .pair(model.species[i], model.species[j])
            .law;
        let (id_i, id_j) = (self.id[i], self.id[j]);
        let (key, sign) = if id_i < id_j {
            ((id_i, id_j), 1.0)
        } else {
            ((id_j, id_i), -1.0)
        };
        let c = self.contact(
            law,
            [
                scale(1.0 / norm(d_prev), d_prev),
                scale(1.0 / norm(d_mid), d_mid),
                n,
            ],
            (l - r, overlap_prev),
            (pi, pj),
            scale(sign, self.springs.get(key)),
        );
        out.push(ContactForce {
            i: i as u32,
            j: j as u32,
            f: c.force,
            torque_i: torque(lever_arm(pi.radius, l - r), n, c.tangential),
            torque_j: torque(lever_arm(pj.radius, l - r), n, c.tangential),
            key,
            spring: scale(sign, c.spring),
        });
    }

    fn wall(
        &self,
        i: usize,
        w: usize,
        wall: &Wall,
        overlap: f64,
        pi: Party,
        out: &mut Vec<ContactForce>,
    ) {
        let dt = 2.0 * self.base.h;
        let n = wall.normal;
        let approach = n[0] * pi.v[0] + n[1] * pi.v[1] + n[2] * pi.v[2];
        let model = &self.base.model;
        let law = &model.interactions.wall(model.species[i]).law;
        let key = (self.id[i], WALL - w as u32);
        let c = self.contact(
            law,
            [n; 3],
            (overlap, overlap + dt * approach),
            (pi, WALL_PARTY),
            self.springs.get(key),
        );
        out.push(ContactForce {
            i: i as u32,
            j: WALL,
            f: c.force,
            torque_i: torque(lever_arm(pi.radius, overlap), n, c.tangential),
            torque_j: [0.0; 3],
            key,
            spring: c.spring,
        });
    }

    /// The force of one contact on its first party: normals one step ago, at mid-step
    /// and now, overlaps now and one step ago, the parties, the spring of the step
    /// before (in the first party's frame).
    fn contact(
        &self,
        law: &emdstar_contact::PairLaw,
        [n_prev, n_mid, n]: [[f64; 3]; 3],
        (overlap, overlap_prev): (f64, f64),
        (a, b): (Party, Party),
        spring: [f64; 3],
    ) -> ContactOutcome {
        let dt = 2.0 * self.base.h;
        let v_pred = sub(a.v_pred, b.v_pred);
        let rate = -(n[0] * v_pred[0] + n[1] * v_pred[1] + n[2] * v_pred[2]);
        let normal = normal_force(law, overlap, rate, self.base.model.contact_end);
        let correction = touch_correction(law, overlap_prev, overlap, rate);
        let slip = slip_velocity(n, v_pred, (a.radius, a.w_pred), (b.radius, b.w_pred));
        let slip_mid = slip_velocity(n_mid, sub(a.v, b.v), (a.radius, a.w), (b.radius, b.w));
        // Only the part of the step after touch counts in a contact's first step.
        let in_contact = if overlap_prev < 0.0 {
            overlap / (overlap - overlap_prev)
        } else {
            1.0
        };
        let grown = add_scaled(
            turn_spring(spring, n_prev, n),
            in_contact * dt,
            add_scaled(slip_mid, -dot(slip_mid, n), n),
        );
        let t = self.friction.force(normal + correction, slip, grown);
        let mut tangential = t.force;
        if correction != 0.0 {
            // The tangential force at touch, F_t(0⁺), misplaced as the normal one is.
            let jump = law.normal_force(f64::MIN_POSITIVE, rate);
            let at_touch = self.friction.force(jump, slip, [0.0; 3]).force;
            tangential = add_scaled(tangential, correction / jump, at_touch);
        }
        ContactOutcome {
            force: add(scale(normal + correction, n), tangential),
            tangential,
            spring: t.spring,
        }
    }
}

struct ContactOutcome {
    force: [f64; 3],
    tangential: [f64; 3],
    spring: [f64; 3],
}
