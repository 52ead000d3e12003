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
//! which keeps the total angular momentum (|r| = R_i + R_j at touch). A wall is the
//! partner of infinite mass and radius that does not spin, with the same events and the
//! same fallback.

use super::rule::{Kick, PairImpact, Party, Transient, instant_pair, instant_wall};
use crate::error::{EngineError, Result};
use emdstar_contact::vec3::{add_scaled, cross, dot, from_na, norm, scale, sub, to_na};
use emdstar_contact::{HistorySpring, PairLaw, SOLID_SPHERE_INERTIA};
use emdstar_mor::SolveError;
use emdstar_mor::frictional::CONTACT_OPTIONS;
use emdstar_mor::rule::{PairContact, frictional_outcome, frictional_wall_collision};

use super::ahead::SolveAhead;

/// The exact contact of `parties` meeting now: what its solve depends on.
pub(super) fn contact(parties: &[Party; 2]) -> PairContact {
    PairContact::of(
        &parties.map(|p| p.body()),
        parties.map(|p| p.radius),
        parties.map(|p| p.spin),
    )
}

/// The E^φ of the pair `parties` meeting now (the exact contact of `law` with the
/// history spring `spring`), with the exact impulse as exception (a)'s kick.
pub(super) fn pair(
    law: &PairLaw,
    spring: &HistorySpring,
    parties: &[Party; 2],
    impact: &PairImpact,
    ahead: Option<&SolveAhead>,
) -> Result<Transient> {
    let PairImpact { r, v, .. } = *impact;
    let radii = parties.map(|p| p.radius);
    let bodies = parties.map(|p| p.body());
    let contact = PairContact::of(&bodies, radii, parties.map(|p| p.spin));
    let end = match ahead {
        Some(ahead) => ahead.solve(law, spring, &contact),
        None => contact.solve(law, spring, &CONTACT_OPTIONS),
    }
    .map_err(unsolved)?;
    let (out, spins_after) = frictional_outcome(&bodies, &end);
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

/// The E^φ of `party` (its position relative to a point of the wall) meeting a wall of
/// unit normal `n` now: the exact contact with the infinitely heavy partner that does not
/// spin (`emdstar_mor::rule::frictional_wall_collision`), with the exact impulse as
/// exception (a)'s kick.
pub(super) fn wall(
    law: &PairLaw,
    spring: &HistorySpring,
    party: &Party,
    n: &[f64; 3],
) -> Result<Transient> {
    let (out, spin) = frictional_wall_collision(
        law,
        spring,
        &party.body(),
        party.radius,
        party.spin,
        &to_na(*n),
        &CONTACT_OPTIONS,
    )
    .map_err(unsolved)?;
    let placed = from_na(&out.rotated_positions[0]);
    let after = from_na(&out.post_velocities[0]);
    let v = party.velocity;
    let restitution = dot(after, *n) / -dot(v, *n);
    let impulse = scale(party.mass, sub(after, v));
    Ok(Transient {
        placed: [placed; 2],
        moving: from_na(&out.transient_velocity),
        after: [after; 2],
        spin: Some([spin; 2]),
        duration: out.duration,
        overlap_left: 0.0,
        fallback: wall_impulse_kick(party, *n, impulse, restitution),
    })
}

/// Exception (a) of a frictional wall collision: the exact impulse `impulse` at touch,
/// its tangential part also on the spin (Δω = −(R/I) n × J_t); should it not take the
/// sphere off the wall, eMD's kick of restitution `restitution` without friction
/// instead (counted where it is applied).
fn wall_impulse_kick(party: &Party, n: [f64; 3], impulse: [f64; 3], restitution: f64) -> Kick {
    let v = add_scaled(party.velocity, 1.0 / party.mass, impulse);
    if dot(v, n) <= 0.0 {
        let vn = dot(party.velocity, n);
        return Kick {
            spin: Some([party.spin; 2]),
            substitute: true,
            ..instant_wall(party, n, vn, restitution, None)
        };
    }
    let tangential = add_scaled(impulse, -dot(impulse, n), n);
    let inertia = SOLID_SPHERE_INERTIA * party.mass * party.radius * party.radius;
    let spin = add_scaled(party.spin, -party.radius / inertia, cross(n, tangential));
    Kick {
        velocity: [v; 2],
        spin: Some([spin; 2]),
        substitute: false,
    }
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
