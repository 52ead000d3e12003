//! The eMD* collision rule in the laboratory frame (Müller & Pöschel 2013, Sec. IV,
//! Eqs. 25-39; `emdstar_mor::rule`) for a pair handle.

use crate::pair::pair_of_ptr;
use crate::{EmdstarMor, EmdstarPair, EmdstarStatus, guarded, input_err, put};
use emdstar_contact::{Impact, Vec3};
use emdstar_mor::rule::{Body, Outcome, resolve, resolve_wall};

/// Position (m) and velocity (m/s) of one body.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EmdstarBody {
    pub position: [f64; 3],
    pub velocity: [f64; 3],
}

/// A collision, resolved.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EmdstarCollision {
    /// Both bodies at t* + τ, the collision over (for a wall, body 0; body 1 repeats it).
    pub after: [EmdstarBody; 2],
    /// Positions right after the E^φ event at t*: rotated about the centre of mass by
    /// eps_phi and set to the separation l·eps_r (Sec. VI B 2).
    pub rotated_positions: [[f64; 3]; 2],
    /// The common velocity of both bodies between E^φ and E^v: the centre-of-mass one.
    pub transient_velocity: [f64; 3],
    /// The velocities the E^v events apply at t* + τ (Sec. VI B 3).
    pub post_velocities: [[f64; 3]; 2],
    /// τ = eps_t·T, s.
    pub duration: f64,
    /// The MoR applied, with its source.
    pub mor: EmdstarMor,
}

fn v3(x: [f64; 3]) -> Vec3 {
    Vec3::new(x[0], x[1], x[2])
}

fn a3(v: Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn collision(o: &Outcome, mor: EmdstarMor) -> EmdstarCollision {
    let body = |b: &Body| EmdstarBody {
        position: a3(b.position),
        velocity: a3(b.velocity),
    };
    EmdstarCollision {
        after: [body(&o.after[0]), body(&o.after[1])],
        rotated_positions: o.rotated_positions.map(a3),
        transient_velocity: a3(o.transient_velocity),
        post_velocities: o.post_velocities.map(a3),
        duration: o.duration,
        mor,
    }
}

fn finite(b: &EmdstarBody) -> bool {
    b.position.iter().chain(&b.velocity).all(|x| x.is_finite())
}

/// Resolves the collision of the pair's two spheres at first touch (their centres
/// the pair's contact distance apart), with their masses in kg (those given to the
/// pair constructor). With `exact_fallback` nonzero, impacts the table does not answer
/// are solved exactly.
///
/// # Safety
/// `pair` from a sphere-sphere constructor; `b1`, `b2` readable; `out` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_collide(
    pair: *const EmdstarPair,
    mass1: f64,
    mass2: f64,
    b1: *const EmdstarBody,
    b2: *const EmdstarBody,
    exact_fallback: i32,
    out: *mut EmdstarCollision,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let p = unsafe { pair_of_ptr(pair) }?;
        if b1.is_null() || b2.is_null() {
            return Err(input_err("a body pointer is NULL"));
        }
        // SAFETY: non-null and readable by the caller's contract.
        let (b1, b2) = unsafe { (*b1, *b2) };
        if !(finite(&b1) && finite(&b2) && mass1 > 0.0 && mass2 > 0.0) {
            return Err(input_err(
                "positions and velocities must be finite and masses > 0",
            ));
        }
        let r = v3(b1.position) - v3(b2.position);
        let v = v3(b1.velocity) - v3(b2.velocity);
        let impact = Impact::from_relative(&r, &v).map_err(input_err)?;
        let mor = p.mor(&impact, exact_fallback != 0)?;
        let bodies = [(b1, mass1), (b2, mass2)].map(|(b, m)| Body {
            position: v3(b.position),
            velocity: v3(b.velocity),
            mass: m,
        });
        let o = resolve(&bodies, p.own.map().pair().l, &mor.mor(), mor.time_scale);
        // SAFETY: by the caller's contract.
        unsafe { put(out, collision(&o, mor)) }
    })
}

/// Resolves the collision of the pair's sphere (built with radius2 = mass2 = 0) with a
/// flat wall of unit normal `normal` (pointing into the sphere's half-space): the
/// central MoR along the normal, the tangential velocity unchanged.
///
/// # Safety
/// `pair` from a wall constructor; `body`, `normal` readable; `out` writable.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_pair_collide_wall(
    pair: *const EmdstarPair,
    body: *const EmdstarBody,
    normal: *const f64,
    exact_fallback: i32,
    out: *mut EmdstarCollision,
) -> EmdstarStatus {
    guarded(|| {
        // SAFETY: by the caller's contract.
        let p = unsafe { pair_of_ptr(pair) }?;
        if body.is_null() || normal.is_null() {
            return Err(input_err("body or normal is NULL"));
        }
        // SAFETY: non-null and readable (one body, three doubles) by contract.
        let (b, n) = unsafe { (*body, std::slice::from_raw_parts(normal, 3)) };
        let n = Vec3::new(n[0], n[1], n[2]);
        if !(finite(&b) && n.iter().all(|x| x.is_finite()) && n.norm() > 0.0) {
            return Err(input_err(
                "the body must be finite and the normal finite and nonzero",
            ));
        }
        let n = n.normalize();
        let approach = -v3(b.velocity).dot(&n);
        if approach <= 0.0 {
            return Err(input_err(format!(
                "the sphere does not approach the wall (normal speed {approach} m/s)"
            )));
        }
        let impact = Impact {
            normal_speed: approach,
            tangential_speed: 0.0,
        };
        let mor = p.mor(&impact, exact_fallback != 0)?;
        let body = Body {
            position: v3(b.position),
            velocity: v3(b.velocity),
            mass: p.own.map().pair().m_eff,
        };
        let o = resolve_wall(&body, &n, p.own.map().pair().l, &mor.mor(), mor.time_scale);
        // SAFETY: by the caller's contract.
        unsafe { put(out, collision(&o, mor)) }
    })
}
