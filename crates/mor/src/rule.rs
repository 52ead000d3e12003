//! The eMD* collision rule in the laboratory frame (Müller & Pöschel 2013, Sec. IV,
//! Eqs. 25-39) and its split into one E^φ and two E^v events (Sec. VI B).
//!
//! Conventions (docs/physics.md, "Collision rule"): r = r₁ − r₂, the collision frame Σ has e_x = r̂ at contact,
//! e_z = L̂ and e_y = e_z × e_x; relative coordinates are shared out by mass, particle 1
//! getting +m₂/M and particle 2 getting −m₁/M.

use crate::frictional::{FrictionalEnd, Spinning, solve_contact, solve_wall_contact};
use crate::{Mor, SolveError, SolverOptions, solve};
use emdstar_contact::vec3::{from_na, to_na};
use emdstar_contact::{ContactError, HistorySpring, Impact, PairLaw, PairProperties, Vec3, scale};
use std::fmt;

/// Position, velocity and mass of one sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    pub position: Vec3,
    pub velocity: Vec3,
    pub mass: f64,
}

/// The result of one collision.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outcome {
    /// Both bodies at t* + τ, with the collision over.
    pub after: [Body; 2],
    /// Positions right after the E^φ event at t*: rotated about the centre of mass by
    /// ε_φ and set to the separation l·ε_r (Sec. VI B 2, item 3).
    pub rotated_positions: [Vec3; 2],
    /// The common velocity of both bodies between E^φ and E^v: the centre-of-mass
    /// velocity (Sec. VI B 2, item 4).
    pub transient_velocity: Vec3,
    /// The velocities the two E^v events apply at t* + τ (Sec. VI B 3).
    pub post_velocities: [Vec3; 2],
    /// τ = ε_t·T, in s.
    pub duration: f64,
}

/// Applies a matrix of restitution to two spheres touching at distance `l`, free of
/// external fields during the contact (a uniform field moves only the centre of mass
/// and can be added by the caller).
///
/// `time_scale` is the T of the scaling that produced `mor`.
pub fn resolve(bodies: &[Body; 2], l: f64, mor: &Mor, time_scale: f64) -> Outcome {
    let [b1, b2] = bodies;
    let total = b1.mass + b2.mass;
    let cm_position = (b1.position * b1.mass + b2.position * b2.mass) / total;
    let cm_velocity = (b1.velocity * b1.mass + b2.velocity * b2.mass) / total;
    let r0 = b1.position - b2.position;
    let v0 = b1.velocity - b2.velocity;

    // Collision frame Σ, Eq. (7).
    let e_x = r0.normalize();
    let rdot0 = v0.dot(&e_x);
    let v_t = (v0 - e_x * rdot0).norm();
    let e_z = angular_momentum_axis(&e_x, &r0.cross(&v0));
    let e_y = e_z.cross(&e_x);

    let (sin_phi, cos_phi) = mor.eps_phi.sin_cos();
    // Eq. (26)-(27): direction of r after the collision.
    let e_r = e_x * cos_phi + e_y * sin_phi;
    // Eq. (28): r' = l·ε_r.
    let r_after = l * mor.eps_r;
    // Eqs. (33)-(34): φ̇' = φ̇⁰/ε_r² with φ̇⁰ = L/(m_eff l²) = v_t/l.
    let phidot_after = v_t / (l * mor.eps_r * mor.eps_r);
    // Eq. (37): ṙ' = ε_ṙ·ṙ⁰.
    let rdot_after = mor.eps_rdot * rdot0;
    // Eqs. (35), (36), (38): relative velocity after the collision.
    let e_phi = e_y * cos_phi - e_x * sin_phi;
    let v_rel_after = e_r * rdot_after + e_phi * (r_after * phidot_after);

    let share = [b2.mass / total, -b1.mass / total];
    let duration = mor.eps_t * time_scale;
    let rotated_positions = share.map(|s| cm_position + e_r * (r_after * s));
    let post_velocities = share.map(|s| cm_velocity + v_rel_after * s);
    // Eqs. (31)-(32) and (39): the centre of mass moves on for τ.
    let after = [0, 1].map(|i| Body {
        position: rotated_positions[i] + cm_velocity * duration,
        velocity: post_velocities[i],
        mass: bodies[i].mass,
    });
    Outcome {
        after,
        rotated_positions,
        transient_velocity: cm_velocity,
        post_velocities,
        duration,
    }
}

/// e_z = L̂, or for a central impact (L = 0) any unit vector perpendicular to e_x
/// (footnote [30] of the paper).
fn angular_momentum_axis(e_x: &Vec3, l_vec: &Vec3) -> Vec3 {
    let norm = l_vec.norm();
    if norm > 0.0 && norm.is_finite() {
        let e_z = l_vec / norm;
        // Guard against an L that is round-off only: it must be perpendicular to e_x.
        if e_z.dot(e_x).abs() < 1e-6 {
            return e_z;
        }
    }
    let least = e_x.iamin();
    let mut axis = Vec3::zeros();
    axis[least] = 1.0;
    e_x.cross(&axis).normalize()
}

/// Why an exact collision could not be computed.
#[derive(Debug, Clone, PartialEq)]
pub enum CollisionError {
    Contact(ContactError),
    Solve(SolveError),
}

impl fmt::Display for CollisionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Contact(e) => e.fmt(f),
            Self::Solve(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for CollisionError {}

impl From<ContactError> for CollisionError {
    fn from(e: ContactError) -> Self {
        Self::Contact(e)
    }
}

impl From<SolveError> for CollisionError {
    fn from(e: SolveError) -> Self {
        Self::Solve(e)
    }
}

/// The exact two-body collision of spheres touching at distance `pair.l`: scaling,
/// an exact MoR solve, and [`resolve`]. The reference every engine is checked against.
pub fn exact_collision(
    law: &PairLaw,
    pair: &PairProperties,
    bodies: &[Body; 2],
) -> Result<(Outcome, Mor), CollisionError> {
    let r = bodies[0].position - bodies[1].position;
    let v = bodies[0].velocity - bodies[1].velocity;
    let impact = Impact::from_relative(&r, &v)?;
    let scaled = scale(law, pair, &impact)?;
    let mor = solve(law.model(), &scaled.params)?;
    Ok((resolve(bodies, pair.l, &mor, scaled.time), mor))
}

/// What the exact frictional contact of a pair depends on: the two spheres, the
/// separation at touch (|r| = R₁ + R₂) and the relative velocity. [`PairContact::solve`]
/// is a pure function of it (and of the law, the spring and the options): equal inputs,
/// to the bit, give equal outcomes, whoever solves them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContact {
    pub spheres: [Spinning; 2],
    pub separation: [f64; 3],
    pub velocity: [f64; 3],
}

impl PairContact {
    /// The contact of `bodies` with radii `radii` and spins `spins`, meeting now.
    pub fn of(bodies: &[Body; 2], radii: [f64; 2], spins: [[f64; 3]; 2]) -> Self {
        let [b1, b2] = bodies;
        // The separation at touch, |r| = R₁ + R₂ (an impact is detected to round-off of it).
        let r0 = b1.position - b2.position;
        let touch = r0 * ((radii[0] + radii[1]) / r0.norm());
        Self {
            spheres: [0, 1].map(|i| Spinning {
                radius: radii[i],
                mass: bodies[i].mass,
                spin: spins[i],
            }),
            separation: from_na(&touch),
            velocity: from_na(&(b1.velocity - b2.velocity)),
        }
    }

    /// [`solve_contact`] of this contact.
    pub fn solve(
        &self,
        law: &PairLaw,
        friction: &HistorySpring,
        opts: &SolverOptions,
    ) -> Result<FrictionalEnd, SolveError> {
        solve_contact(
            law,
            friction,
            &self.spheres,
            self.separation,
            self.velocity,
            opts,
        )
    }
}

/// The exact collision of two frictional spheres with radii `radii` and spins `spins`
/// ([`solve_contact`], to the accuracy of `opts`: eMD* uses
/// [`crate::frictional::CONTACT_OPTIONS`]) in eMD*'s events: the E^φ event places the spheres where the
/// contact leaves them relative to their centre of mass and gives both its velocity, the
/// E^v event the post-collision velocities; the spins after the contact come second.
pub fn frictional_collision(
    law: &PairLaw,
    friction: &HistorySpring,
    bodies: &[Body; 2],
    radii: [f64; 2],
    spins: [[f64; 3]; 2],
    opts: &SolverOptions,
) -> Result<(Outcome, [[f64; 3]; 2]), SolveError> {
    let end = PairContact::of(bodies, radii, spins).solve(law, friction, opts)?;
    Ok(frictional_outcome(bodies, &end))
}

/// eMD*'s events of the pair `bodies` (as met) from the end of their exact frictional
/// contact `end` ([`frictional_collision`]).
pub fn frictional_outcome(bodies: &[Body; 2], end: &FrictionalEnd) -> (Outcome, [[f64; 3]; 2]) {
    let [b1, b2] = bodies;
    let total = b1.mass + b2.mass;
    let cm_position = (b1.position * b1.mass + b2.position * b2.mass) / total;
    let cm_velocity = (b1.velocity * b1.mass + b2.velocity * b2.mass) / total;
    let share = [b2.mass / total, -b1.mass / total];
    let (r_end, v_end) = (to_na(end.separation), to_na(end.velocity));
    let rotated_positions = share.map(|s| cm_position + r_end * s);
    let post_velocities = share.map(|s| cm_velocity + v_end * s);
    let after = [0, 1].map(|i| Body {
        position: rotated_positions[i] + cm_velocity * end.duration,
        velocity: post_velocities[i],
        mass: bodies[i].mass,
    });
    let outcome = Outcome {
        after,
        rotated_positions,
        transient_velocity: cm_velocity,
        post_velocities,
        duration: end.duration,
    };
    (outcome, end.spins)
}

/// The exact collision of a frictional sphere (`body`, radius `radius`, spin `spin`)
/// with a flat wall at rest of unit normal `normal` (pointing into the sphere's side),
/// touching it, under the normal law `law` of the sphere–wall pair and the history
/// spring `spring` ([`solve_wall_contact`]: the wall is the limit of a partner of
/// infinite mass and radius that does not spin). In eMD*'s events as
/// [`resolve_wall`] has them: the E^φ event puts the sphere above the point of the
/// plane it touched, at the height the contact leaves it, moving along the wall at its
/// mean tangential velocity over the contact (`transient_velocity`), so that it is where
/// the contact leaves it after τ; the E^v event gives it the velocity after the contact.
/// Both entries of the outcome's pairs are the sphere's; its spin after the contact
/// comes second.
pub fn frictional_wall_collision(
    law: &PairLaw,
    spring: &HistorySpring,
    body: &Body,
    radius: f64,
    spin: [f64; 3],
    normal: &Vec3,
    opts: &SolverOptions,
) -> Result<(Outcome, [f64; 3]), SolveError> {
    let sphere = Spinning {
        radius,
        mass: body.mass,
        spin,
    };
    let end = solve_wall_contact(
        law,
        spring,
        &sphere,
        from_na(normal),
        from_na(&body.velocity),
        opts,
    )?;
    let n = normal.normalize();
    // The point of the plane under the centre at touch, and the centre at the end.
    let plane_point = body.position - n * radius;
    let separation = to_na(end.separation);
    let height = separation.dot(&n);
    let position = plane_point + separation;
    // The centre's way along the wall over the contact, at a constant pace.
    let transient_velocity = (separation - n * height) / end.duration;
    let rotated = plane_point + n * height;
    let velocity = to_na(end.velocity);
    let after = Body {
        position,
        velocity,
        mass: body.mass,
    };
    let outcome = Outcome {
        after: [after, after],
        rotated_positions: [rotated, rotated],
        transient_velocity,
        post_velocities: [velocity, velocity],
        duration: end.duration,
    };
    Ok((outcome, end.spins[0]))
}

/// A sphere against an infinitely heavy flat wall with unit normal `normal` (pointing
/// into the sphere's half-space), touching at distance `l` = R from the plane.
///
/// A flat wall does not turn the contact normal, so the wall collision is the central
/// one (use a MoR solved with c_φ = 0) along the normal while the tangential velocity
/// carries on unchanged (frictionless). The E^φ event sets the normal distance to
/// l·ε_r and keeps only the tangential velocity; the E^v event restores the normal
/// velocity ε_ṙ·ṙ⁰.
pub fn resolve_wall(body: &Body, normal: &Vec3, l: f64, mor: &Mor, time_scale: f64) -> Outcome {
    let n = normal.normalize();
    let height = body.position.dot(&n);
    let plane_point = body.position - n * height;
    let rdot0 = body.velocity.dot(&n);
    let tangential = body.velocity - n * rdot0;
    let rotated = plane_point + n * (l * mor.eps_r);
    let post = tangential + n * (mor.eps_rdot * rdot0);
    let duration = mor.eps_t * time_scale;
    let after = Body {
        position: rotated + tangential * duration,
        velocity: post,
        mass: body.mass,
    };
    Outcome {
        after: [after, after],
        rotated_positions: [rotated, rotated],
        transient_velocity: tangential,
        post_velocities: [post, post],
        duration,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn bodies(m1: f64, m2: f64, e: f64) -> [Body; 2] {
        // Two bodies touching at distance 0.3 along a tilted direction, approaching
        // with eccentricity e and some drift of the centre of mass.
        let l = 0.3;
        let dir = Vec3::new(1.0, 2.0, -0.5).normalize();
        let side = dir.cross(&Vec3::new(0.3, -0.2, 1.0)).normalize();
        let v_rel = (-dir * (1.0 - e * e).sqrt() + side * e) * 4.0;
        let drift = Vec3::new(0.7, -1.1, 0.25);
        let x1 = Vec3::new(0.1, 0.2, 0.3);
        [
            Body {
                position: x1,
                velocity: drift + v_rel * (m2 / (m1 + m2)),
                mass: m1,
            },
            Body {
                position: x1 - dir * l,
                velocity: drift - v_rel * (m1 / (m1 + m2)),
                mass: m2,
            },
        ]
    }

    fn sample_mor(eps_rdot: f64) -> Mor {
        Mor {
            eps_r: 0.97,
            one_minus_eps_r: 0.03,
            eps_rdot,
            eps_phi: 0.4,
            eps_t: 3.0,
        }
    }

    fn momentum(b: &[Body; 2]) -> Vec3 {
        b[0].velocity * b[0].mass + b[1].velocity * b[1].mass
    }

    fn energy(b: &[Body; 2]) -> f64 {
        0.5 * (b[0].mass * b[0].velocity.norm_squared() + b[1].mass * b[1].velocity.norm_squared())
    }

    fn angular_momentum_about_cm(b: &[Body; 2]) -> Vec3 {
        let total = b[0].mass + b[1].mass;
        let cm = (b[0].position * b[0].mass + b[1].position * b[1].mass) / total;
        let vcm = (b[0].velocity * b[0].mass + b[1].velocity * b[1].mass) / total;
        b.iter().fold(Vec3::zeros(), |acc, x| {
            acc + (x.position - cm).cross(&(x.velocity - vcm)) * x.mass
        })
    }

    #[test]
    fn conserves_momentum_and_angular_momentum() {
        for (m1, m2) in [(1.0, 1.0), (0.3, 2.5)] {
            let before = bodies(m1, m2, 0.6);
            let out = resolve(&before, 0.3, &sample_mor(-0.8), 0.01);
            let p0 = momentum(&before);
            assert_relative_eq!(momentum(&out.after), p0, max_relative = 1e-14);
            // Angular momentum about the CM: L = m_eff r × ṙ is conserved because
            // r'²φ̇' = (lε_r)²·φ̇⁰/ε_r² = l²φ̇⁰ (Eq. 19).
            assert_relative_eq!(
                angular_momentum_about_cm(&out.after),
                angular_momentum_about_cm(&before),
                max_relative = 1e-13
            );
            // The E^φ state carries the total momentum at the CM velocity.
            let total = m1 + m2;
            assert_relative_eq!(out.transient_velocity * total, p0, max_relative = 1e-14);
        }
    }

    #[test]
    fn conserves_energy_when_elastic() {
        // ε_ṙ = −1 and ε_r = 1: the relative speed keeps its magnitude.
        let mut mor = sample_mor(-1.0);
        mor.eps_r = 1.0;
        mor.one_minus_eps_r = 0.0;
        let before = bodies(0.3, 2.5, 0.8);
        let out = resolve(&before, 0.3, &mor, 0.01);
        assert_relative_eq!(energy(&out.after), energy(&before), max_relative = 1e-14);
        // Inelastic loses energy.
        let lossy = resolve(&before, 0.3, &sample_mor(-0.5), 0.01);
        assert!(energy(&lossy.after) < energy(&before));
    }

    #[test]
    fn the_separation_and_rotation_are_the_mor_ones() {
        let before = bodies(0.3, 2.5, 0.5);
        let mor = sample_mor(-0.8);
        let out = resolve(&before, 0.3, &mor, 0.01);
        let r0 = before[0].position - before[1].position;
        let r1 = out.after[0].position - out.after[1].position;
        assert_relative_eq!(r1.norm(), 0.3 * mor.eps_r, max_relative = 1e-14);
        assert_relative_eq!(
            r0.normalize().dot(&r1.normalize()),
            mor.eps_phi.cos(),
            max_relative = 1e-14
        );
        // The rotation goes the way of the angular momentum.
        let l_vec = r0.cross(&(before[0].velocity - before[1].velocity));
        assert!(r0.cross(&r1).dot(&l_vec) > 0.0);
        // Normal part of the relative velocity after: ε_ṙ·ṙ⁰.
        let v0 = before[0].velocity - before[1].velocity;
        let v1 = out.after[0].velocity - out.after[1].velocity;
        assert_relative_eq!(
            v1.dot(&r1.normalize()),
            mor.eps_rdot * v0.dot(&r0.normalize()),
            max_relative = 1e-13
        );
    }

    #[test]
    fn central_impacts_have_a_frame() {
        let mut before = bodies(1.0, 2.0, 0.0);
        let dir = (before[0].position - before[1].position).normalize();
        before[0].velocity = -dir * 2.0;
        before[1].velocity = dir * 1.0;
        let mut mor = sample_mor(-0.7);
        mor.eps_phi = 0.0;
        let out = resolve(&before, 0.3, &mor, 0.01);
        for b in &out.after {
            assert!(
                b.position
                    .iter()
                    .chain(b.velocity.iter())
                    .all(|x| x.is_finite())
            );
        }
        let v1 = out.after[0].velocity - out.after[1].velocity;
        assert_relative_eq!(v1, dir * 3.0 * 0.7, max_relative = 1e-14);
    }

    #[test]
    fn a_wall_reflects_the_normal_velocity_and_keeps_the_tangential() {
        let body = Body {
            position: Vec3::new(2.0, 0.5, -1.0),
            velocity: Vec3::new(0.3, -2.0, 0.1),
            mass: 1.0,
        };
        let n = Vec3::new(0.0, 1.0, 0.0);
        let mor = Mor {
            eps_r: 0.99,
            one_minus_eps_r: 0.01,
            eps_rdot: -0.6,
            eps_phi: 0.0,
            eps_t: 3.0,
        };
        let out = resolve_wall(&body, &n, 0.5, &mor, 0.1);
        assert_relative_eq!(
            out.after[0].velocity,
            Vec3::new(0.3, 1.2, 0.1),
            max_relative = 1e-14
        );
        assert_relative_eq!(
            out.after[0].position,
            Vec3::new(2.0 + 0.3 * 0.3, 0.495, -1.0 + 0.1 * 0.3),
            max_relative = 1e-14
        );
    }
}
