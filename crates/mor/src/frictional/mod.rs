//! The exact two-body contact of frictional soft spheres: the normal force law of
//! Müller & Pöschel 2013 (Eqs. 40 and 51) with the Cundall–Strack history spring of
//! `emdstar_contact::tangential` (docs/physics.md, "Friction and rotation"), both
//! spins, in three dimensions, from first touch to the end of the frictionless solver,
//! F_n = 0 with the spheres separating (Eq. 10).
//!
//! # Equations (relative coordinates r = x₁ − x₂, v = ṙ, n = r/|r|)
//! - m_eff v̇ = F_n n + F_t, F_n = F(ξ, ξ̇) the pair's law, ξ = l − |r|, ξ̇ = −v·n;
//! - I_i ω̇_i = −(R_i − ξ/2) n × F_t (both spheres, the lever arm of [`emdstar_contact::lever_arm`]);
//! - the slip v_t = v − (v·n)n − (R₁ω₁ + R₂ω₂) × n ([`emdstar_contact::slip_velocity`]);
//! - the spring, in the tangent plane, is transported with the normal and grows by the
//!   slip: ξ̇_t = v_t − (ξ_t·ṅ)n, ṅ = (v − (v·n)n)/|r| (the continuous form of
//!   [`emdstar_contact::turn_spring`] plus growth);
//! - sticking: F_t = f = −k_t ξ_t − γ_t v_t while |f| ≤ µF_n;
//! - sliding: F_t = µF_n f̂, and the spring stays where −k_t ξ_t − γ_t v_t = µF_n f̂
//!   (MD's reset of the spring onto the cap, in the limit dt → 0):
//!   ξ̇_t = v_t − (ξ_t·ṅ)n + c f̂ with c = (−k_t f̂·(v_t − (ξ_t·ṅ)n) − γ_t f̂·v̇_t − µḞ_n)/k_t,
//!   which keeps d|f|/dt = µḞ_n.
//!
//! Sticking turns to sliding where µF_n − |f| crosses zero, sliding to sticking where c
//! does (the cap would let go). Each stretch is one smooth ODE, integrated by DOP853; the
//! switches and the end are located on the dense output, and the next stretch starts
//! there. For Hertz, √ξ makes the start non-smooth; as in the frictionless solver the
//! state carries w = √ξ and the independent variable is σ with dt/dσ = w.
//!
//! The pure Coulomb model (F_t = −µF_n v̂_t) has no spring and chatters about v_t = 0;
//! it is not solved here.
//!
//! # Solvers
//! - [`solve_frictional`]: the reference, these equations as written (r, v, both spins,
//!   the spring), to the tolerance asked for; slow near the end of a sliding contact.
//! - [`solve_contact`]: what eMD* uses ([`CONTACT_OPTIONS`], within a few 10⁻⁹ of the
//!   reference on gas-like impacts): the same equations in the frame the normal carries
//!   along, with a tail for the end of a sliding contact (see its source, `contact/`).
//! - [`solve_wall_contact`]: a sphere at a flat wall, the limit of a partner of infinite
//!   mass and radius that does not spin, by the same solver with the normal fixed.

mod contact;
mod reference;

pub use reference::solve_frictional;

use crate::dop853::StepFailure;
use crate::roots::illinois;
use crate::{SolveError, SolveStats, SolverOptions};
use contact::{Contact, Geometry, check_spring};
pub use emdstar_contact::HistorySpring;
use emdstar_contact::vec3::{add, cross, dot, norm, scale, sub};
use emdstar_contact::{PairLaw, SOLID_SPHERE_INERTIA};

/// Samples of a step that bracket an event starting at zero.
const SAMPLES: usize = 16;

/// Bound on the stick–slip switches of one contact.
const MAX_SWITCHES: usize = 1000;

/// The options of [`solve_contact`] and [`solve_wall_contact`] that eMD* uses: accuracy
/// 3·10⁻⁹ per step (rtol, and atol in units of each component's scale), matched to the
/// 10⁻⁷ eMD* asks of a contact: against the reference at 10⁻¹² the outcome of gas-like
/// impacts is then within 2·10⁻⁸ (positions in units of l, velocities and R ω in units of
/// |v|; 99 % within 6·10⁻⁹).
pub const CONTACT_OPTIONS: SolverOptions = SolverOptions {
    rtol: 3e-9,
    atol: 3e-9,
    max_steps: 100_000,
};

/// The contact of `bodies` touching at `separation` (|r| = R₁ + R₂) with relative
/// velocity `velocity` (approaching), under `law` and the history spring `spring`: the
/// equations of this module solved by the fast solver (the carried frame), to `opts.rtol` per step
/// and `opts.atol` in units of each component's scale.
pub fn solve_contact(
    law: &PairLaw,
    spring: &HistorySpring,
    bodies: &[Spinning; 2],
    separation: [f64; 3],
    velocity: [f64; 3],
    opts: &SolverOptions,
) -> Result<FrictionalEnd, SolveError> {
    check_spring(spring)?;
    let l = bodies[0].radius + bodies[1].radius;
    let approach = touching(separation, velocity, l)?;
    let m_eff = bodies[0].mass * bodies[1].mass / (bodies[0].mass + bodies[1].mass);
    let inertia = bodies.map(|b| b.inertia());
    let a = (0..2).map(|i| bodies[i].radius.powi(2) / inertia[i]).sum();
    let b = (0..2).map(|i| 0.5 * bodies[i].radius / inertia[i]).sum();
    let spin_sum = add(
        scale(bodies[0].radius, bodies[0].spin),
        scale(bodies[1].radius, bodies[1].spin),
    );
    let frame = Frame::new(separation, velocity);
    let mut c = contact(
        law,
        spring,
        Geometry::Pair { l },
        m_eff,
        (a, b),
        velocity,
        approach,
        l,
        opts,
    );
    c.spins_apart = spring.friction != 0.0
        && (bodies[0].radius != bodies[1].radius || bodies[0].mass != bodies[1].mass);
    let (y, switches, stats) =
        c.integrate(start(&frame, velocity, spin_sum, [1.0, 0.0, 0.0, 0.0]))?;
    let turned = frame.turned(&y);
    let xi = overlap(&c, &y);
    let p = turned.world(slot(&y, contact::P));
    let spins = if spring.friction == 0.0 {
        [bodies[0].spin, bodies[1].spin]
    } else {
        // Q = ∫ ξ n × F_t dt from ΔΩ = −aP + bQ; I_i Δω_i = −R_i P + Q/2 (P drops out
        // for identical spheres, Δω_i = ΔΩ/2R, and is not carried: zero).
        let d_omega = sub(turned.world(slot(&y, contact::OMEGA)), spin_sum);
        let q = scale(1.0 / b, add(d_omega, scale(a, p)));
        [0, 1].map(|i| {
            let body = &bodies[i];
            add(
                body.spin,
                scale(1.0 / inertia[i], sub(scale(0.5, q), scale(body.radius, p))),
            )
        })
    };
    Ok(FrictionalEnd {
        separation: turned.world([l - xi, 0.0, 0.0]),
        velocity: turned.world(slot(&y, contact::V)),
        spins,
        duration: y[contact::T],
        switches,
        stats,
    })
}

/// The contact of `body` with a flat wall of unit normal `normal` (pointing from the wall
/// into the sphere's side), touching it (centre at R from the plane) with velocity
/// `velocity` against it: the wall is the limit of a partner of infinite mass and radius
/// that does not spin, so n is fixed, m_eff = m, the slip is v − (v·n)n − Rω × n and the
/// torque on the sphere −(R − ξ/2) n × F_t; `law` is the normal law of the sphere–wall
/// pair. The result is that of a pair with the wall as partner: `separation` is the
/// centre less the point of the plane it touched, `velocity` the sphere's, `spins[0]` its
/// spin (`spins[1]` zero).
pub fn solve_wall_contact(
    law: &PairLaw,
    spring: &HistorySpring,
    body: &Spinning,
    normal: [f64; 3],
    velocity: [f64; 3],
    opts: &SolverOptions,
) -> Result<FrictionalEnd, SolveError> {
    check_spring(spring)?;
    let length = norm(normal);
    if !(length > 0.0 && length.is_finite()) {
        return Err(SolveError::InvalidParams(format!(
            "the wall's normal {normal:?} must be a finite non-zero vector"
        )));
    }
    let n = scale(1.0 / length, normal);
    let touch = scale(body.radius, n);
    let approach = touching(touch, velocity, body.radius)?;
    let inertia = body.inertia();
    let ab = (body.radius.powi(2) / inertia, 0.5 * body.radius / inertia);
    let frame = Frame::new(n, velocity);
    let spin_sum = scale(body.radius, body.spin);
    let c = contact(
        law,
        spring,
        Geometry::Wall,
        body.mass,
        ab,
        velocity,
        approach,
        body.radius,
        opts,
    );
    let (y, switches, stats) = c.integrate(start(&frame, velocity, spin_sum, [0.0; 4]))?;
    let xi = overlap(&c, &y);
    let (d1, d2) = (y[contact::Q], y[contact::Q + 1]);
    let spin = if spring.friction == 0.0 {
        body.spin
    } else {
        scale(1.0 / body.radius, frame.world(slot(&y, contact::OMEGA)))
    };
    Ok(FrictionalEnd {
        separation: frame.world([body.radius - xi, d1, d2]),
        velocity: frame.world(slot(&y, contact::V)),
        spins: [spin, [0.0; 3]],
        duration: y[contact::T],
        switches,
        stats,
    })
}

/// An orthonormal frame: e₀ along `normal`, e₁ along the part of `along` across it (or
/// any direction across it).
struct Frame {
    e: [[f64; 3]; 3],
}

impl Frame {
    fn new(normal: [f64; 3], along: [f64; 3]) -> Self {
        let e0 = scale(1.0 / norm(normal), normal);
        let mut t = sub(along, scale(dot(along, e0), e0));
        if norm(t) <= 1e-12 * norm(along) || norm(t) == 0.0 {
            // Any direction across e₀: the axis it has least of.
            let least = (0..3)
                .min_by(|&i, &j| e0[i].abs().total_cmp(&e0[j].abs()))
                .unwrap_or(0);
            let mut axis = [0.0; 3];
            axis[least] = 1.0;
            t = cross(e0, axis);
        }
        let e1 = scale(1.0 / norm(t), t);
        Self {
            e: [e0, e1, cross(e0, e1)],
        }
    }

    /// The components of a vector.
    fn local(&self, u: [f64; 3]) -> [f64; 3] {
        self.e.map(|e| dot(e, u))
    }

    /// The vector of components `c`.
    fn world(&self, c: [f64; 3]) -> [f64; 3] {
        let [a, b, d] = self.e;
        add(add(scale(c[0], a), scale(c[1], b)), scale(c[2], d))
    }

    /// The frame carried to the end of a pair contact, by its attitude in `y`.
    fn turned(&self, y: &[f64; contact::N]) -> Frame {
        let q = [
            y[contact::Q],
            y[contact::Q + 1],
            y[contact::Q + 2],
            y[contact::Q + 3],
        ];
        let size = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        let [a, b, c, d] = q.map(|x| x / size);
        // The columns of the rotation matrix of q, in the components of the frame at touch.
        let columns = [
            [
                a * a + b * b - c * c - d * d,
                2.0 * (b * c + a * d),
                2.0 * (b * d - a * c),
            ],
            [
                2.0 * (b * c - a * d),
                a * a - b * b + c * c - d * d,
                2.0 * (c * d + a * b),
            ],
            [
                2.0 * (b * d + a * c),
                2.0 * (c * d - a * b),
                a * a - b * b - c * c + d * d,
            ],
        ];
        Frame {
            e: columns.map(|col| self.world(col)),
        }
    }
}

/// The touch state: v and Ω = Σ R_i ω_i in the frame's components, the attitude slots.
fn start(
    frame: &Frame,
    velocity: [f64; 3],
    spin_sum: [f64; 3],
    attitude: [f64; 4],
) -> [f64; contact::N] {
    let mut y = [0.0; contact::N];
    y[contact::V..contact::V + 3].copy_from_slice(&frame.local(velocity));
    y[contact::OMEGA..contact::OMEGA + 3].copy_from_slice(&frame.local(spin_sum));
    y[contact::Q..contact::Q + 4].copy_from_slice(&attitude);
    y
}

fn slot(y: &[f64; contact::N], at: usize) -> [f64; 3] {
    [y[at], y[at + 1], y[at + 2]]
}

/// ξ at the end state.
fn overlap(c: &Contact, y: &[f64; contact::N]) -> f64 {
    let s = y[contact::S];
    if c.hertz { s * s } else { s }
}

/// The normal speed of an approach at touch, or why the bodies do not touch and approach.
fn touching(separation: [f64; 3], velocity: [f64; 3], l: f64) -> Result<f64, SolveError> {
    let approach = -dot(velocity, separation) / norm(separation);
    if approach.is_nan() || approach <= 0.0 || (norm(separation) - l).abs() > 1e-9 * l {
        return Err(SolveError::InvalidParams(format!(
            "the spheres must touch (|r| = {} for R1 + R2 = {l}) and approach (normal \
             speed {approach})",
            norm(separation)
        )));
    }
    Ok(approach)
}

#[allow(clippy::too_many_arguments)]
fn contact(
    law: &PairLaw,
    spring: &HistorySpring,
    geometry: Geometry,
    m_eff: f64,
    (a, b): (f64, f64),
    velocity: [f64; 3],
    approach: f64,
    length: f64,
    opts: &SolverOptions,
) -> Contact {
    let normal = Normal::of(law);
    let peak = normal.peak(m_eff, approach);
    Contact {
        geometry,
        hertz: normal.hertz,
        elastic: normal.elastic,
        viscous: normal.viscous,
        mu: spring.friction,
        k_t: spring.stiffness,
        gamma_t: spring.damping,
        m_eff,
        inv_m_eff: 1.0 / m_eff,
        inv_k_t: 1.0 / spring.stiffness,
        a,
        b,
        spins_apart: false,
        speed: norm(velocity),
        overlap: peak,
        time: peak / approach,
        length,
        rtol: opts.rtol,
        accuracy: opts.atol,
        max_steps: opts.max_steps,
    }
}

/// One sphere of a frictional contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spinning {
    pub radius: f64,
    pub mass: f64,
    /// Angular velocity in rad/s.
    pub spin: [f64; 3],
}

impl Spinning {
    fn inertia(&self) -> f64 {
        SOLID_SPHERE_INERTIA * self.mass * self.radius * self.radius
    }
}

/// The relative state of a pair at the end of its contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionalEnd {
    /// r = x₁ − x₂ at the end, in m.
    pub separation: [f64; 3],
    /// v = v₁ − v₂ at the end, in m/s.
    pub velocity: [f64; 3],
    /// ω₁ and ω₂ at the end, in rad/s.
    pub spins: [[f64; 3]; 2],
    /// Contact duration τ, in s.
    pub duration: f64,
    /// Switches between sticking and sliding.
    pub switches: usize,
    pub stats: SolveStats,
}

/// The normal law in the solvers' terms: linear (k, γ) or Hertz (ρ_el, (3/2)A), the
/// overlap coordinate s being ξ (linear) or w = √ξ (Hertz, in the time σ, dt/dσ = w).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Normal {
    hertz: bool,
    elastic: f64,
    viscous: f64,
}

impl Normal {
    fn of(law: &PairLaw) -> Self {
        match *law {
            PairLaw::Linear { stiffness, damping } => Self {
                hertz: false,
                elastic: stiffness,
                viscous: damping,
            },
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => Self {
                hertz: true,
                elastic: rho_el,
                viscous: 1.5 * dissipation,
            },
        }
    }

    /// The estimated peak overlap of an approach at `approach` with effective mass `m_eff`.
    fn peak(&self, m_eff: f64, approach: f64) -> f64 {
        if self.hertz {
            (1.25 * m_eff * approach * approach / self.elastic).powf(0.4)
        } else {
            approach * (m_eff / self.elastic).sqrt()
        }
    }

    /// ξ, dt/dx and the normal force from the overlap coordinate s and ξ̇ = `rate`.
    #[inline(always)]
    fn force(&self, s: f64, rate: f64) -> (f64, f64, f64) {
        if self.hertz {
            let xi = s * s;
            (xi, s, self.elastic * s * (xi + self.viscous * rate))
        } else {
            (s, 1.0, self.elastic * s + self.viscous * rate)
        }
    }

    /// dF_n/dt · dt/dx given ξ̇ and ξ̈ (finite at ξ = 0 for Hertz).
    #[inline(always)]
    fn growth(&self, s: f64, rate: f64, rate_dot: f64) -> f64 {
        if self.hertz {
            let xi = s * s;
            self.elastic
                * (0.5 * rate * (xi + self.viscous * rate) + xi * (rate + self.viscous * rate_dot))
        } else {
            self.elastic * rate + self.viscous * rate_dot
        }
    }

    /// Whether a contact with slip speed `slip` and normal speed `approach` at touch
    /// slides from its first instant under the spring (µ, k_t, γ_t): the trial force
    /// −γ_t v_t against the cap µF_n(0⁺), and where both vanish their growth.
    fn slides_from_touch(
        &self,
        (mu, k_t, gamma_t): (f64, f64, f64),
        slip: f64,
        approach: f64,
    ) -> bool {
        let (trial, cap) = (gamma_t * slip, mu * self.viscous * approach);
        let cap = if self.hertz { 0.0 } else { cap };
        if trial != cap {
            return trial > cap;
        }
        // Both zero: |f| grows as k_t s t; the cap as µ k v_n t (linear), faster than t
        // (damped Hertz) or slower (elastic Hertz).
        if self.hertz {
            self.viscous == 0.0
        } else {
            k_t * slip > mu * self.elastic * approach
        }
    }
}

/// The first zero crossing from above of an event function g on a step [x_a, x_b]
/// (`value` evaluates it on the step's dense output; g_a and g_b are its values at the
/// ends): by the Illinois method where the ends bracket it, else by SAMPLES samples of
/// the step (g positive at both ends but below zero in between: a switch there and back;
/// or g zero at the start of a stretch). `None` if g stays positive; x_a if it starts at
/// or below zero and never rises (a switch right at a stretch's start).
fn first_crossing(
    value: impl Fn(f64) -> f64,
    (x_a, g_a): (f64, f64),
    (x_b, g_b): (f64, f64),
) -> Option<f64> {
    if g_a > 0.0 && g_b <= 0.0 {
        return Some(illinois(value, (x_a, g_a), (x_b, g_b)));
    }
    let mut from = (g_a > 0.0).then_some((x_a, g_a));
    for i in 1..=SAMPLES {
        let x = x_a + (x_b - x_a) * i as f64 / SAMPLES as f64;
        let g_x = if i == SAMPLES { g_b } else { value(x) };
        match from {
            Some(a) if g_x <= 0.0 => return Some(illinois(value, a, (x, g_x))),
            _ if g_x > 0.0 => from = Some((x, g_x)),
            _ => {}
        }
    }
    (g_a <= 0.0 && from.is_none()).then_some(x_a)
}

fn failure(f: StepFailure) -> SolveError {
    match f {
        StepFailure::Underflow { t } | StepFailure::OutsideDomain { t } => {
            SolveError::StepSizeUnderflow { t }
        }
    }
}

/// The direction of the tangential force at the cap: that of the trial force
/// −k_t ξ_t − γ_t v_t, or against the slip where the trial force vanishes (zero
/// without slip).
fn sliding_direction(trial: [f64; 3], slip: [f64; 3]) -> [f64; 3] {
    let t = norm(trial);
    if t > 0.0 {
        return scale(1.0 / t, trial);
    }
    let s = norm(slip);
    if s > 0.0 {
        scale(-1.0 / s, slip)
    } else {
        [0.0; 3]
    }
}
