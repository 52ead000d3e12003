//! eMD*'s three events for frictional spheres: each pair collision is the exact
//! frictional two-body contact (`emdstar_mor::rule::frictional_collision`;
//! docs/physics.md, "eMD* with friction"), applied as E^φ (positions turned to where the
//! contact leaves them, both at the centre-of-mass velocity) and E^v (post-collision
//! velocities). The spins take their post-collision values at E^φ already: nothing in
//! the event engine reads them before E^v, and exception (a) puts them back.
//!
//! Exception (a), the rotation impossible: as eMD falls back on the restitution of the
//! exact contact without friction, the frictional collision falls back on the impulse of
//! the exact contact, J = m_eff (v_after − v_before), applied at touch: its normal part
//! on the velocities, its tangential part also on the spins through the lever arms R_i,
//! which keeps the total angular momentum (|r| = R_i + R_j at touch).

use super::{
    FrictionalFallback, Host, RotationProbe, begin_pair_transients, kick_pair, note_contact,
    walls_block,
};
use crate::error::{EngineError, Result};
use crate::physics::Physics;
use emdstar_contact::vec3::{add_scaled, cross, dot, from_na, norm, scale, sub, to_na};
use emdstar_contact::{Friction, SOLID_SPHERE_INERTIA};
use emdstar_mor::SolveError;
use emdstar_mor::frictional::CONTACT_OPTIONS;
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
        &CONTACT_OPTIONS,
    )
    .map_err(|e| {
        let why = match e {
            // The solver's own advice names options a run does not have.
            SolveError::TooManySteps(n) => format!(
                "it did not end within {n} solver steps: its friction, tangential spring \
                 and dashpot, spins or speeds make it far stiffer or longer than the normal \
                 contact alone"
            ),
            e => e.to_string(),
        };
        EngineError::Invalid(format!(
            "the exact frictional contact of particles {i} and {j} could not be solved \
             ({why}); check the material and the particles' spins and speeds: the stiffness \
             and tangential keys must give a contact that double precision can step through \
             in a bounded number of steps"
        ))
    })?;
    h.stats().frictional_solves += 1;
    let new = [
        from_na(&out.rotated_positions[0]),
        from_na(&out.rotated_positions[1]),
    ];
    // eMD's fallback restitution: the normal speed after over the normal speed before.
    let r_end = from_na(&(out.rotated_positions[0] - out.rotated_positions[1]));
    let v_end = from_na(&(out.post_velocities[0] - out.post_velocities[1]));
    let restitution = (dot(v_end, r_end) / norm(r_end)) / (-dot(v, r) / norm(r));
    let m_eff = h.mass(i) * h.mass(j) / (h.mass(i) + h.mass(j));
    let impulse = scale(m_eff, sub(v_end, v));
    if walls_block(h, &[i, j], &new, None) {
        h.stats().exception_rotation += 1;
        note_contact(h, i, j, 0.0);
        impulse_kick(h, i, j, r, v, impulse, restitution);
        return Ok(None);
    }
    *h.probe() = Some(RotationProbe {
        parties: [i as u32, j as u32],
        before: [h.save(i), h.save(j)],
        old_position: [h.position(i), h.position(j)],
        fallback: restitution,
        friction: Some(FrictionalFallback {
            spins_before,
            impulse,
        }),
        blocked: false,
    });
    let l = radii[0] + radii[1];
    note_contact(h, i, j, l - norm(r_end));
    begin_pair_transients(h, [i, j], new, &out, Some(spins));
    Ok(None)
}

/// Exception (a) of a frictional collision: the exact contact's impulse `impulse` (on
/// i) at touch, `r` = x_i − x_j, `v` = v_i − v_j before. Should the pair not separate
/// along r afterwards (a contact that turned its normal far), eMD's kick of restitution
/// `restitution` is applied instead, without friction, and counted.
pub(super) fn impulse_kick<H: Host>(
    h: &mut H,
    i: usize,
    j: usize,
    r: [f64; 3],
    v: [f64; 3],
    impulse: [f64; 3],
    restitution: f64,
) {
    let (m_i, m_j) = (h.mass(i), h.mass(j));
    let n = scale(1.0 / norm(r), r);
    let m_eff = m_i * m_j / (m_i + m_j);
    if dot(add_scaled(v, 1.0 / m_eff, impulse), n) <= 0.0 {
        h.stats().frictional_fallback_kicks += 1;
        return kick_pair(h, i, j, r, v, restitution);
    }
    let tangential = add_scaled(impulse, -dot(impulse, n), n);
    let turn = cross(n, tangential);
    for (p, sign) in [(i, 1.0), (j, -1.0)] {
        let (m, radius) = (h.mass(p), h.radius(p));
        h.set_velocity(p, add_scaled(h.velocity(p), sign / m, impulse));
        // Δω = −(R/I) n × J_t on both (the torque of `emdstar_contact::torque`).
        let inertia = SOLID_SPHERE_INERTIA * m * radius * radius;
        h.set_spin(p, add_scaled(h.spin(p), -radius / inertia, turn));
    }
}
