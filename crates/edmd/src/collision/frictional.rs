//! eMD*'s three events for frictional spheres: each collision is the exact frictional
//! contact (`emdstar_mor::rule::frictional_collision`; docs/physics.md, "eMD* with
//! friction"), applied as E^φ (positions turned to where the contact leaves them, both
//! at the centre-of-mass velocity) and E^v (post-collision velocities). The spins take
//! their post-collision values at E^φ already: nothing in the event engine reads them
//! before E^v, and exception (a) puts them back.
//!
//! Exception (a), the rotation impossible: as eMD falls back on the restitution of the
//! exact contact without friction, the frictional collision falls back on the impulse of
//! the exact contact, J = m_eff (v_after − v_before), applied at touch: its normal part
//! on the velocities, its tangential part also on the spins through the lever arms R_i,
//! which keeps the total angular momentum (|r| = R_i + R_j at touch).

use super::rule::{Kick, PairImpact, Party, Transient, instant_pair};
use crate::error::{EngineError, Result};
use emdstar_contact::vec3::{add_scaled, cross, dot, from_na, norm, scale, sub};
use emdstar_contact::{HistorySpring, PairLaw, SOLID_SPHERE_INERTIA};
use emdstar_mor::rule::frictional_collision;
use emdstar_mor::{SolveError, SolverOptions};

/// The E^φ of the pair `parties` meeting now (the exact contact of `law` with the
/// history spring `spring`), with the exact impulse as exception (a)'s kick.
pub(super) fn pair(
    law: &PairLaw,
    spring: &HistorySpring,
    parties: &[Party; 2],
    impact: &PairImpact,
) -> Result<Transient> {
    let PairImpact { r, v, .. } = *impact;
    let radii = parties.map(|p| p.radius);
    let spins = parties.map(|p| p.spin);
    let (out, spins_after) = frictional_collision(
        law,
        spring,
        &parties.map(|p| p.body()),
        radii,
        spins,
        &SolverOptions::default(),
    )
    .map_err(unsolved)?;
    let placed = out.rotated_positions.map(|x| from_na(&x));
    let after = out.post_velocities.map(|x| from_na(&x));
    // eMD's fallback restitution: the normal speed after over the normal speed before.
    let r_end = sub(placed[0], placed[1]);
    let v_end = sub(after[0], after[1]);
    let restitution = (dot(v_end, r_end) / norm(r_end)) / (-dot(v, r) / norm(r));
    let [m_i, m_j] = parties.map(|p| p.mass);
    let m_eff = m_i * m_j / (m_i + m_j);
    let impulse = scale(m_eff, sub(v_end, v));
    Ok(Transient {
        placed,
        moving: from_na(&out.transient_velocity),
        after,
        spin: Some(spins_after),
        duration: out.duration,
        overlap_left: radii[0] + radii[1] - norm(r_end),
        fallback: impulse_kick(parties, r, v, impulse, restitution),
    })
}

/// The frictional contact of a sphere with a wall: refused until it is solved (the
/// method's compatibility check keeps frictional walls from eMD*).
pub(super) fn wall(
    _law: &PairLaw,
    _spring: &HistorySpring,
    _party: &Party,
    _n: &[f64; 3],
) -> Result<Transient> {
    Err(EngineError::Invalid(
        "eMD* has no frictional wall contact; run friction with walls on --engine md".into(),
    ))
}

/// Why the exact frictional contact failed, for the user.
fn unsolved(e: SolveError) -> EngineError {
    let why = match e {
        // The solver's own advice names options a run does not have.
        SolveError::TooManySteps(n) => format!(
            "it did not end within {n} solver steps: its friction, tangential spring and \
             dashpot, spins or speeds make it far stiffer or longer than the normal contact \
             alone"
        ),
        e => e.to_string(),
    };
    EngineError::Invalid(format!(
        "an exact frictional contact could not be solved ({why}); check the material and the \
         particles' spins and speeds: the stiffness and tangential keys must give a contact \
         that double precision can step through in a bounded number of steps"
    ))
}

/// Exception (a) of a frictional collision: the exact contact's impulse `impulse` (on
/// i) at touch, `r` = x_i − x_j, `v` = v_i − v_j before. Should the pair not separate
/// along r afterwards (a contact that turned its normal far), eMD's kick of restitution
/// `restitution` stands in, without friction (counted where it is applied).
fn impulse_kick(
    parties: &[Party; 2],
    r: [f64; 3],
    v: [f64; 3],
    impulse: [f64; 3],
    restitution: f64,
) -> Kick {
    let [m_i, m_j] = parties.map(|p| p.mass);
    let n = scale(1.0 / norm(r), r);
    let m_eff = m_i * m_j / (m_i + m_j);
    let spins = parties.map(|p| p.spin);
    if dot(add_scaled(v, 1.0 / m_eff, impulse), n) <= 0.0 {
        return Kick {
            spin: Some(spins),
            substitute: true,
            ..instant_pair(parties, r, v, restitution, None)
        };
    }
    let tangential = add_scaled(impulse, -dot(impulse, n), n);
    let turn = cross(n, tangential);
    let kick = |p: &Party, sign: f64| {
        // Δω = −(R/I) n × J_t on both (the torque of `emdstar_contact::torque`).
        let inertia = SOLID_SPHERE_INERTIA * p.mass * p.radius * p.radius;
        (
            add_scaled(p.velocity, sign / p.mass, impulse),
            add_scaled(p.spin, -p.radius / inertia, turn),
        )
    };
    let [(vi, wi), (vj, wj)] = [kick(&parties[0], 1.0), kick(&parties[1], -1.0)];
    Kick {
        velocity: [vi, vj],
        spin: Some([wi, wj]),
        substitute: false,
    }
}
