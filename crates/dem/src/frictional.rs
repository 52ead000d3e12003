//! Frictional contacts: the tangential slot of the force kernel ([`Frictional`]), which
//! adds the tangential forces and torques of each contact's
//! [`emdstar_contact::Tangential`] law, the springs contacts carry from step to step
//! ([`Springs`]), and the spin state of a frictional run ([`Rotation`]).
//!
//! The normal force is the kernel's (predictor and touch correction included). The
//! tangential force of the step follows the conventions of `emdstar_contact::tangential`
//! (those of LAMMPS's `pair granular … tangential linear_history` with
//! `limit_damping`); for second order in dt:
//! - the spring of the step before is turned from the old normal to the new one, and
//!   grows by dt·**v**_t at the middle of the step (the stored half-step velocities and
//!   spins, with the normal at mid-step), projected onto the new tangent plane;
//! - the dashpot uses the predicted slip (velocities and spins v + (dt/2)·a, as the
//!   normal dashpot);
//! - in the first step of a contact the spring starts where the law puts it at touch
//!   (zero, or on the cap µF_n(0⁺) where the dashpot's force exceeds it: the contact
//!   slides from touch), grows only over the part of the step after touch, and a
//!   tangential force that jumps on at touch (a dashpot's) is corrected like the normal
//!   force ([`crate::touch_correction`]).

use crate::forces::{
    Accelerations, ContactKey, ContactRecord, ForceKernel, TangentialSlot, Touch, WALL,
};
use emdstar_contact::vec3::{add, add_scaled, dot, norm, scale, sub};
use emdstar_contact::{Tangential, lever_arm, slip_velocity, torque, turn_spring};
use emdstar_system::{Interactions, Particles, permute};

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

    /// The elastic energy of the springs, Σ ½ k_t |ξ_t|², with each contact's law from
    /// `interactions` and the species of a config id from `species_of`.
    pub fn energy(&self, interactions: &Interactions, species_of: impl Fn(u32) -> u32) -> f64 {
        self.contacts
            .iter()
            .map(|((a, b), spring)| {
                let s = species_of(*a);
                // Config ids stay far below 2³¹ (memory bounds them); wall keys are above.
                let contact = if *b > WALL / 2 {
                    interactions.wall(s, (WALL - b) as usize)
                } else {
                    interactions.pair(s, species_of(*b))
                };
                contact.tangential().spring_energy(*spring)
            })
            .sum()
    }
}

/// One frictional contact of a step: the force on i (normal and tangential; −f on j),
/// the torques on both, and the contact's spring afterwards (in the frame of the key's
/// first id; none for a law without a spring).
#[derive(Debug, Clone, Copy)]
pub struct ContactForce {
    pub i: u32,
    /// The partner, or [`WALL`].
    pub j: u32,
    pub f: [f64; 3],
    pub torque_i: [f64; 3],
    pub torque_j: [f64; 3],
    pub key: ContactKey,
    pub spring: Option<[f64; 3]>,
}

impl ContactRecord for ContactForce {
    #[inline(always)]
    fn parties(&self) -> (u32, u32) {
        (self.i, self.j)
    }

    #[inline(always)]
    fn add_to(&self, to: &mut Accelerations<'_>) {
        let i = self.i as usize;
        let mi = to.inv_mass[i];
        let (inv_inertia, angular) = to
            .angular
            .as_mut()
            .expect("frictional contacts are applied with spins");
        let ii = inv_inertia[i];
        for k in 0..3 {
            to.acc[i][k] += self.f[k] * mi;
            angular[i][k] += self.torque_i[k] * ii;
        }
        if self.j != WALL {
            let j = self.j as usize;
            let (mj, ij) = (to.inv_mass[j], inv_inertia[j]);
            for k in 0..3 {
                to.acc[j][k] -= self.f[k] * mj;
                angular[j][k] += self.torque_j[k] * ij;
            }
        }
    }

    #[inline(always)]
    fn spring(&self) -> Option<(ContactKey, [f64; 3])> {
        self.spring.map(|s| (self.key, s))
    }

    #[inline(always)]
    fn force(&self) -> [f64; 3] {
        self.f
    }
}

/// What friction adds to the state of a run: spins are kicked by the contact torques
/// like the velocities by the forces (LAMMPS's `fix nve/sphere`: ω += (dt/2)·τ/I,
/// I = (2/5) m R²), and each contact's spring is kept between steps.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct Rotation {
    /// 1/I of every particle.
    pub inv_inertia: Vec<f64>,
    /// Angular accelerations of the contacts at the current time (zero for particles
    /// without contacts).
    pub angular_acc: Vec<[f64; 3]>,
    /// The springs of the open contacts.
    pub springs: Springs,
}

impl Rotation {
    /// The rotation of particles `p`, at rest in their springs.
    pub fn new(p: &Particles) -> Self {
        Self {
            inv_inertia: inverse_inertia(p),
            angular_acc: vec![[0.0; 3]; p.len()],
            springs: Springs::default(),
        }
    }

    /// After the particles were reordered by `order` (see [`Particles::permute`]).
    pub fn permute(&mut self, order: &[u32]) {
        permute(&mut self.inv_inertia, order);
        permute(&mut self.angular_acc, order);
    }

    /// After a restored state replaced the particles.
    pub fn reset_inertia(&mut self, p: &Particles) {
        self.inv_inertia = inverse_inertia(p);
    }

    /// The elastic energy of the springs of particles `p` (any order), Σ ½ k_t |ξ_t|²
    /// (exactly zero where no contact has a spring).
    pub fn spring_energy(&self, interactions: &Interactions, p: &Particles) -> f64 {
        let springs =
            |i: &emdstar_system::Interaction| matches!(i.tangential(), Tangential::History(_));
        if !interactions.distinct().any(springs) {
            return 0.0;
        }
        let mut species = vec![0; p.len()];
        for (k, &id) in p.id.iter().enumerate() {
            species[id as usize] = p.species[k];
        }
        self.springs.energy(interactions, |id| species[id as usize])
    }
}

/// 1/I of every particle, I = (2/5) m R².
fn inverse_inertia(p: &Particles) -> Vec<f64> {
    (0..p.len()).map(|i| 1.0 / p.inertia(i)).collect()
}

/// The tangential slot of frictional runs: the spins and springs the tangential forces
/// depend on.
#[derive(Clone, Copy)]
pub struct Frictional<'a> {
    /// Config id of each particle (the springs are keyed by them).
    pub id: &'a [u32],
    /// Stored spins, half a kick behind like the velocities.
    pub angular_velocity: &'a [[f64; 3]],
    /// Angular accelerations of the contacts of the previous step.
    pub angular_acc: &'a [[f64; 3]],
    pub springs: &'a Springs,
}

/// One party of a contact: its radius, stored (mid-step) and predicted spins.
#[derive(Clone, Copy)]
struct Party {
    radius: f64,
    w: [f64; 3],
    w_pred: [f64; 3],
}

/// A wall: infinitely heavy, flat, not spinning.
const WALL_PARTY: Party = Party {
    radius: 0.0,
    w: [0.0; 3],
    w_pred: [0.0; 3],
};

impl Frictional<'_> {
    fn party(&self, kernel: &ForceKernel<'_, Self>, i: usize) -> Party {
        let w = self.angular_velocity[i];
        Party {
            radius: kernel.model.radius[i],
            w,
            w_pred: add_scaled(w, kernel.h, self.angular_acc[i]),
        }
    }
}

impl TangentialSlot for Frictional<'_> {
    type Contact = ContactForce;

    fn contact(&self, kernel: &ForceKernel<'_, Self>, t: &Touch<'_>) -> Option<ContactForce> {
        let dt = 2.0 * kernel.h;
        let i = t.i;
        let a = self.party(kernel, i);
        let (b, normals, key, sign) = if t.j == WALL {
            let key = (self.id[i], WALL - t.wall as u32);
            (WALL_PARTY, [t.n; 3], key, 1.0)
        } else {
            let j = t.j as usize;
            // The normals one step ago and at mid-step: the drift was x += dt·v exactly.
            let d_mid = add_scaled(t.d, -0.5 * dt, sub(t.v[0], t.v[1]));
            let n_prev = scale(1.0 / norm(t.d_prev), t.d_prev);
            let n_mid = scale(1.0 / norm(d_mid), d_mid);
            let (id_i, id_j) = (self.id[i], self.id[j]);
            let (key, sign) = if id_i < id_j {
                ((id_i, id_j), 1.0)
            } else {
                ((id_j, id_i), -1.0)
            };
            (self.party(kernel, j), [n_prev, n_mid, t.n], key, sign)
        };
        let [n_prev, n_mid, n] = normals;
        let law = t.interaction.law();
        let tangential_law = t.interaction.tangential();
        let (overlap, overlap_prev) = (t.overlap, t.overlap_prev);
        let v_pred = sub(t.v_pred[0], t.v_pred[1]);
        let (normal, correction) = (t.normal, t.correction);
        let slip = slip_velocity(n, v_pred, (a.radius, a.w_pred), (b.radius, b.w_pred));
        let slip_mid = slip_velocity(n_mid, sub(t.v[0], t.v[1]), (a.radius, a.w), (b.radius, b.w));
        // Only the part of the step after touch counts in a contact's first step.
        let in_contact = if overlap_prev < 0.0 {
            overlap / (overlap - overlap_prev)
        } else {
            1.0
        };
        // The law at touch (zero overlap): F_n(0⁺), and the tangential force and spring
        // there, which a contact sliding from touch sets at once (the cap below the
        // dashpot: the spring jumps to −(F_t + γ_t v_t)/k_t, as in the exact contact).
        let first = overlap_prev < 0.0;
        let jump = law.normal_force(f64::MIN_POSITIVE, t.rate);
        let at_touch = first.then(|| tangential_law.force(jump, slip, [0.0; 3]));
        let spring = match at_touch {
            Some(touch) => touch.spring,
            None => scale(sign, self.springs.get(key)),
        };
        let grown = add_scaled(
            turn_spring(spring, n_prev, n),
            in_contact * dt,
            add_scaled(slip_mid, -dot(slip_mid, n), n),
        );
        // The force at the end of the step, capped by the normal force there (the
        // spring's state for the next step), ...
        let f = tangential_law.force(normal, slip, grown);
        let mut tangential = f.force;
        if let (true, Some(touch)) = (correction != 0.0, at_touch) {
            // ... and the impulse of the tangential force at touch, F_t(0⁺), misplaced
            // as the normal one is: corrected once, like it (F_t(0⁺) is capped by µF(0⁺)
            // itself).
            tangential = add_scaled(tangential, correction / jump, touch.force);
        }
        let keeps = matches!(tangential_law, Tangential::History(_));
        Some(ContactForce {
            i: i as u32,
            j: t.j,
            f: add(scale(normal + correction, n), tangential),
            torque_i: torque(lever_arm(a.radius, overlap), n, tangential),
            torque_j: torque(lever_arm(b.radius, overlap), n, tangential),
            key,
            spring: keeps.then(|| scale(sign, f.spring)),
        })
    }
}
