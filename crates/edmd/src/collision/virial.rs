//! The collisional part of the pressure tensor, Σ r_ij ⊗ Δp_i over the pair impulses
//! (Allen & Tildesley 1987, Sec. 3.7 for hard spheres), as the executor counts it.
//!
//! eMD* changes a pair's momenta twice (Müller & Pöschel 2013, Sec. VI B): at E^φ to
//! the centre-of-mass velocity, at r_ij of the impact, and at E^v to the
//! post-collision velocities, at the separation r'_ij E^φ placed the pair at (the pair
//! moves rigidly in between). E^φ's displacement adds nothing to Σ x ⊗ p: both
//! particles then carry the centre-of-mass velocity and the centre of mass stays. The
//! sum of both terms and the kinetic tensor of the transient (the relative motion is
//! frozen) equals ∫ r ⊗ F dt + ∫ μ v ⊗ v dt over the real contact, whose end points
//! eMD* reproduces (see docs/physics.md).

use super::{Party, Transient};
use emdstar_system::{Sym3, add_scaled, sym_outer};

/// Adds r ⊗ Δp_i of an impulse that took the pair `parties` (velocities before) to
/// the velocities `after`; Δp_i = −Δp_j up to round-off, so their half difference.
pub(super) fn add_pair_impulse(
    w: &mut Sym3,
    r: [f64; 3],
    parties: &[Party; 2],
    after: [[f64; 3]; 2],
) {
    let dp: [f64; 3] = std::array::from_fn(|k| {
        0.5 * (parties[0].mass * (after[0][k] - parties[0].velocity[k])
            - parties[1].mass * (after[1][k] - parties[1].velocity[k]))
    });
    add_scaled(w, sym_outer(r, dp), 1.0);
}

/// r'_ij ⊗ Δp_i of the E^v events of the transient `t` of a pair of `masses`.
pub(super) fn velocity_events(t: &Transient, masses: [f64; 2]) -> Sym3 {
    let r: [f64; 3] = std::array::from_fn(|k| t.placed[0][k] - t.placed[1][k]);
    let dp: [f64; 3] = std::array::from_fn(|k| {
        0.5 * (masses[0] * (t.after[0][k] - t.moving[k])
            - masses[1] * (t.after[1][k] - t.moving[k]))
    });
    sym_outer(r, dp)
}
