//! The kicks and drifts of velocity Verlet (see the crate docs), and one whole step of
//! a subset of the particles, with or without friction.

use crate::forces::{
    Accelerations, ContactRecord, ForceKernel, ForceModel, PairForce, Smooth, TangentialSlot,
    apply_contacts,
};
use crate::frictional::{ContactForce, Frictional, Rotation};
use crate::neighbour::{INDEX_MASK, NeighbourList};

/// max(a, b) that lets a NaN through (so that a blow-up is noticed).
#[inline(always)]
pub(crate) fn max_nan(a: f64, b: f64) -> f64 {
    if b > a || b.is_nan() { b } else { a }
}

/// v += a·`kick` for the particles `ids` (a: their contact accelerations); returns
/// their largest |v|² (NaN passes).
pub fn kick_contacts(velocity: &mut [[f64; 3]], acc: &[[f64; 3]], ids: &[u32], kick: f64) -> f64 {
    let mut v2_max: f64 = 0.0;
    for &i in ids {
        let (i, a) = (i as usize, acc[i as usize]);
        let v = velocity[i];
        let w = [v[0] + a[0] * kick, v[1] + a[1] * kick, v[2] + a[2] * kick];
        velocity[i] = w;
        v2_max = max_nan(v2_max, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    v2_max
}

/// The gravity kick and the drift of one particle: w = v + `gk` (w = v if `gravity` is
/// false), y = x + w·dt. Returns (y, w).
#[inline(always)]
pub fn kick_drift(
    x: [f64; 3],
    v: [f64; 3],
    gk: [f64; 3],
    dt: f64,
    gravity: bool,
) -> ([f64; 3], [f64; 3]) {
    let w = if gravity {
        [v[0] + gk[0], v[1] + gk[1], v[2] + gk[2]]
    } else {
        v
    };
    ([x[0] + w[0] * dt, x[1] + w[1] * dt, x[2] + w[2] * dt], w)
}

/// The state one step of a subset changes, indexed by particle.
pub struct Motion<'a> {
    pub position: &'a mut [[f64; 3]],
    pub velocity: &'a mut [[f64; 3]],
    /// Contact accelerations at the start of the step; replaced by those at its end
    /// for the particles stepped.
    pub contact_acc: &'a mut [[f64; 3]],
    /// Scratch, all zero on entry and on return.
    pub new_acc: &'a mut [[f64; 3]],
    pub inv_mass: &'a [f64],
}

/// The largest speed and contact acceleration of the particles a step moved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepBounds {
    /// max |v| over the half step and the end of the step.
    pub v_max: f64,
    /// max |a_contact| at the end of the step.
    pub a_max: f64,
}

/// What friction adds to the state one step of a subset changes, indexed by particle.
pub struct SpinMotion<'a> {
    /// Spins, in step with the velocities.
    pub angular_velocity: &'a mut [[f64; 3]],
    /// 1/I, the angular accelerations (at the start of the step; replaced by those at
    /// its end for the particles stepped) and the springs (of the contacts open before
    /// the step; replaced by those open after).
    pub rotation: &'a mut Rotation,
    /// Config id of every particle (the springs' keys).
    pub id: &'a [u32],
}

/// Scratch for the contacts of a step (contents replaced).
#[derive(Debug, Clone, Default)]
pub struct ContactScratch {
    pub smooth: Vec<PairForce>,
    pub frictional: Vec<ContactForce>,
}

/// One velocity-Verlet step of dt for the particles `ids` (each once), with
/// velocities synchronised with positions before and after: the half kick with a(t),
/// the drift, the forces at the new positions (predictor and touch correction as MD's,
/// see the crate docs), the half kick with a(t + dt): the operations of
/// [`crate::Md::advance`] by one step, on the subset. With `spins`, the same kernel
/// adds the tangential forces and torques ([`Frictional`]), the spins are kicked like
/// the velocities (ω += (dt/2)·τ/I), and the springs of the contacts found are kept for
/// the next step; a contact absent from a step (ended, or with a partner outside `ids`
/// or refused by `partner`) loses its spring.
///
/// Pairs are taken from `list` once each ([`NeighbourList::once`]), and only with
/// partners j for which `partner(j)` holds; both particles of a pair kept must be in
/// `ids` (a partner outside would be left with a force in `new_acc`). The caller keeps
/// `list` fresh: it must hold every pair that can touch by the end of the step.
/// Particles outside `ids` are not touched.
#[allow(clippy::too_many_arguments)]
pub fn step_subset(
    model: &ForceModel<'_>,
    list: &NeighbourList,
    motion: Motion<'_>,
    spins: Option<SpinMotion<'_>>,
    scratch: &mut ContactScratch,
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
    let h = 0.5 * dt;
    let g = model.gravity;
    let gravity = g != [0.0; 3];
    let gk = [g[0] * h, g[1] * h, g[2] * h];
    kick_contacts(velocity, contact_acc, ids, h);
    let Some(spins) = spins else {
        let v2_max = drift(position, velocity, ids, gk, dt, gravity);
        let kernel = ForceKernel {
            model: *model,
            list,
            contact_acc: &*contact_acc,
            h,
            slot: Smooth,
        };
        let contacts = &mut scratch.smooth;
        subset_contacts(&kernel, ids, &partner, position, velocity, contacts);
        let mut to = Accelerations {
            inv_mass,
            acc: new_acc,
            angular: None,
        };
        apply_contacts(contacts.iter(), &mut to, None);
        return close_step(velocity, contact_acc, new_acc, ids, h, gk, v2_max);
    };
    let SpinMotion {
        angular_velocity,
        rotation,
        id,
    } = spins;
    kick_contacts(angular_velocity, &rotation.angular_acc, ids, h);
    let v2_max = drift(position, velocity, ids, gk, dt, gravity);
    let kernel = ForceKernel {
        model: *model,
        list,
        contact_acc: &*contact_acc,
        h,
        slot: Frictional {
            id,
            angular_velocity: &*angular_velocity,
            angular_acc: &rotation.angular_acc,
            springs: &rotation.springs,
        },
    };
    let contacts = &mut scratch.frictional;
    subset_contacts(&kernel, ids, &partner, position, velocity, contacts);
    // The angular accelerations of the step are built in place: no scratch for them.
    for &i in ids {
        rotation.angular_acc[i as usize] = [0.0; 3];
    }
    let mut to = Accelerations {
        inv_mass,
        acc: new_acc,
        angular: Some((&rotation.inv_inertia, &mut rotation.angular_acc)),
    };
    apply_contacts(contacts.iter(), &mut to, None);
    rotation
        .springs
        .replace(contacts.iter().filter_map(ContactRecord::spring));
    // The spins' half kick with the new torques (independent of the velocities' kicks).
    kick_contacts(angular_velocity, &rotation.angular_acc, ids, h);
    close_step(velocity, contact_acc, new_acc, ids, h, gk, v2_max)
}

/// The contacts of the particles `ids` with their partners in `list` (each pair once)
/// that `partner` keeps, in order, into `out` (cleared first).
pub fn subset_contacts<S: TangentialSlot>(
    kernel: &ForceKernel<'_, S>,
    ids: &[u32],
    partner: &impl Fn(usize) -> bool,
    position: &[[f64; 3]],
    velocity: &[[f64; 3]],
    out: &mut Vec<S::Contact>,
) {
    out.clear();
    let list = kernel.list;
    for &i in ids {
        let i = i as usize;
        let partners = list
            .once(i)
            .iter()
            .copied()
            .filter(|&e| partner((e & INDEX_MASK) as usize));
        kernel.particle(
            i,
            position[i],
            velocity[i],
            partners,
            position,
            velocity,
            out,
        );
    }
}

/// The drift of a subset's step, after the contact half kick: gravity's half kick
/// (`gk`, if `gravity`) and x += v·dt for `ids`. Returns their largest |v|² (NaN
/// passes).
pub(crate) fn drift(
    position: &mut [[f64; 3]],
    velocity: &mut [[f64; 3]],
    ids: &[u32],
    gk: [f64; 3],
    dt: f64,
    gravity: bool,
) -> f64 {
    let mut v2_max: f64 = 0.0;
    for &i in ids {
        let i = i as usize;
        let (y, w) = kick_drift(position[i], velocity[i], gk, dt, gravity);
        position[i] = y;
        velocity[i] = w;
        v2_max = max_nan(v2_max, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    v2_max
}

/// The end of a subset's step, once the forces at the new positions are in `new_acc`:
/// they become `contact_acc` (the scratch zeroed), then the contact and gravity half
/// kicks. `v2_max` is the largest |v|² of the drift; the bounds cover both.
pub(crate) fn close_step(
    velocity: &mut [[f64; 3]],
    contact_acc: &mut [[f64; 3]],
    new_acc: &mut [[f64; 3]],
    ids: &[u32],
    h: f64,
    gk: [f64; 3],
    mut v2_max: f64,
) -> StepBounds {
    let mut a2_max: f64 = 0.0;
    for &i in ids {
        let i = i as usize;
        let a = new_acc[i];
        new_acc[i] = [0.0; 3];
        contact_acc[i] = a;
        a2_max = max_nan(a2_max, a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    }
    kick_contacts(velocity, contact_acc, ids, h);
    for &i in ids {
        let i = i as usize;
        let v = velocity[i];
        let w = [v[0] + gk[0], v[1] + gk[1], v[2] + gk[2]];
        velocity[i] = w;
        v2_max = max_nan(v2_max, w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    }
    StepBounds {
        v_max: v2_max.sqrt(),
        a_max: a2_max.sqrt(),
    }
}
