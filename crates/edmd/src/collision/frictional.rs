//! eMD*'s three events for frictional spheres: each pair collision is the exact
//! frictional two-body contact (`emdstar_mor::rule::frictional_collision`;
//! docs/physics.md, "eMD* with friction"), applied as E^φ (positions turned to where the
//! contact leaves them, both at the centre-of-mass velocity) and E^v (post-collision
//! velocities). The spins take their post-collision values at E^φ already: nothing in
//! the event engine reads them before E^v, and exception (a) puts them back.

use super::{Host, RotationProbe, note_contact, walls_block};
use crate::error::Result;
use crate::physics::Physics;
use emdstar_contact::Friction;
use emdstar_contact::vec3::{dot, from_na, norm, to_na};
use emdstar_mor::SolverOptions;
use emdstar_mor::rule::{Body, frictional_collision};

/// The E^φ of the pair `i`, `j` meeting now with `r` = x_i − x_j (minimum image) and
/// `v` = v_i − v_j, or the restitution of eMD's fallback (exception a).
pub(super) fn pair<H: Host>(
    h: &mut H,
    i: usize,
    j: usize,
    r: [f64; 3],
    v: [f64; 3],
    friction: &Friction,
) -> Result<Option<f64>> {
    let (si, sj) = (h.species(i), h.species(j));
    let law = {
        let Physics::EmdStar { materials, .. } = h.rule().0 else {
            unreachable!("eMD* event without eMD* physics")
        };
        materials.pair(si, sj).interaction.law
    };
    // Unwrap i next to j so that the pair is contiguous.
    let pj = h.position(j);
    let pi: [f64; 3] = std::array::from_fn(|k| pj[k] + r[k]);
    let bodies = [(pi, i), (pj, j)].map(|(x, p)| Body {
        position: to_na(x),
        velocity: to_na(h.velocity(p)),
        mass: h.mass(p),
    });
    let radii = [h.radius(i), h.radius(j)];
    let spins_before = [h.spin(i), h.spin(j)];
    let (out, spins) = frictional_collision(
        &law,
        friction,
        &bodies,
        radii,
        spins_before,
        &SolverOptions::default(),
    )?;
    h.stats().frictional_solves += 1;
    let new = [
        from_na(&out.rotated_positions[0]),
        from_na(&out.rotated_positions[1]),
    ];
    // eMD's fallback restitution: the normal speed after over the normal speed before.
    let r_end = from_na(&(out.rotated_positions[0] - out.rotated_positions[1]));
    let v_end = from_na(&(out.post_velocities[0] - out.post_velocities[1]));
    let restitution = (dot(v_end, r_end) / norm(r_end)) / (-dot(v, r) / norm(r));
    if walls_block(h, &[i, j], &new, None) {
        h.stats().exception_rotation += 1;
        return Ok(Some(restitution));
    }
    *h.probe() = Some(RotationProbe {
        parties: [i as u32, j as u32],
        before: [h.save(i), h.save(j)],
        old_position: [h.position(i), h.position(j)],
        fallback: restitution,
        spins_before: Some(spins_before),
        blocked: false,
    });
    let l = radii[0] + radii[1];
    note_contact(h, i, j, l - norm(r_end));
    let g = h.gravity();
    let end = h.now() + out.duration;
    let partners = [j as u32, i as u32];
    for (slot, &p) in [i, j].iter().enumerate() {
        h.place(p, new[slot]);
        h.set_velocity(p, from_na(&out.transient_velocity));
        h.set_spin(p, spins[slot]);
        let post = out.post_velocities[slot];
        let after = std::array::from_fn(|k| post[k] + g[k] * out.duration);
        h.begin_transient(p, end, after, partners[slot]);
    }
    Ok(None)
}
