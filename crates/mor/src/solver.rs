//! Solver of the scaled collision ODE of Müller & Pöschel 2013, Eqs. (42) and (54), with
//! the force-zero end of the collision, Eq. (10) (Schwager & Pöschel 2007).
//!
//! # Formulation
//! With the scaled overlap ξ = l̃ − r̃ and its rate u = ξ' = −r̃' (l̃ reaches e^17 while ξ
//! stays O(1), so r̃ itself would lose the digits of ξ), Eqs. (42) and (54) read
//!
//! - ξ' = u
//! - u' = −c_φ²/(l̃−ξ)³ − g(ξ)·h, with the bracket h = ξ + c_dis·u
//! - φ' = c_φ/(l̃−ξ)²
//!
//! with g = 1 for the linear dashpot and g = √ξ for viscoelastic Hertz spheres: the scaled
//! normal force is F = g·h. The start values r̃ = l̃, r̃' = −1, φ = 0 (Eq. 44) are ξ = 0,
//! u = 1, φ = 0.
//!
//! - **Linear dashpot:** the state (ξ, u, φ) is integrated in t. The right-hand side is
//!   analytic, also for ξ < 0, where trial stages may go beyond the end.
//! - **Hertz:** √ξ makes the solution non-smooth where ξ → 0 (ξ ~ t, F ~ t^{3/2} at the
//!   start and, for small c_dis, near the end), which ruins the order of any Runge–Kutta
//!   method. The state (w, u, φ, t) with w = √ξ is integrated in the regularising time σ,
//!   dt/dσ = w: w' = u/2, u' = −w·c_φ²/r³ − w²·h, φ' = w·c_φ/r², t' = w, with
//!   r = l̃ − w² and h = w² + c_dis·u. This system is polynomial in w and u, hence analytic
//!   (w = σ/2 + … at the start, and w crosses 0 with slope u/2 if c_dis = 0), so the
//!   question of how to evaluate the Hertz law at ξ < 0 disappears: beyond the end, trial
//!   stages follow the analytic continuation, never used for the result.
//!
//! # End of the collision
//! The collision ends where r̃' > 0 and F = 0 (Eq. 10): h crosses zero from above with
//! u < 0; for c_dis = 0 that is ξ = 0 (w = 0 for Hertz), skipping the trivial root at t = 0.
//! While ξ > 0, h ≥ 0 ⇔ F ≥ 0, so the clipping F = max(0, …) never acts before the end. The
//! end is bracketed by an accepted step and located on that step's 7th-order dense output
//! by the Illinois method. There ξ = −c_dis·u holds exactly; of the two, the one with the
//! smaller relative error (the one far from zero relative to its peak) fixes the other.
//!
//! # Tolerances
//! ξ is tiny where c_dis is large (ξ_max ≈ (1.5/c_dis)^{2/3} for Hertz, 1/c_dis for the
//! linear dashpot) and u ends near −ξ/c_dis there, so absolute tolerances are set relative
//! to an estimated overlap scale Ξ: atol·Ξ on ξ (atol·√Ξ on w, atol·Ξ on t),
//! atol·min(1, Ξ/c_dis) on u (an error in u moves h by c_dis times as much), and
//! atol·Ξ·c_φ/l̃² on φ. The relative tolerance on ξ refers to min(|ξ|, |l̃−ξ|), so that r̃ is
//! also resolved where the spheres nearly pass through each other (small l̃).

use crate::dop853::{Dop853, StepFailure, System, Tolerances};
use emdstar_contact::{Model, ScaledParams};
use std::fmt;

/// The independent components of the matrix of restitution, Eq. (23).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mor {
    /// ε_r = r̃(τ̃)/l̃, Eq. (16).
    pub eps_r: f64,
    /// 1 − ε_r = ξ̃(τ̃)/l̃, computed from the overlap without cancellation.
    pub one_minus_eps_r: f64,
    /// ε_ṙ = r̃'(τ̃)/r̃'(0), Eq. (21); negative, ε_n = −ε_ṙ.
    pub eps_rdot: f64,
    /// ε_φ = φ̃(τ̃), Eq. (17), in radians (Φ = 1).
    pub eps_phi: f64,
    /// ε_t = τ̃, Eq. (20).
    pub eps_t: f64,
}

/// Tolerances and limits of the integration.
///
/// The defaults give ≤ 1e-9 relative error in each of 1−ε_r, ε_ṙ, ε_φ and ε_t over the
/// paper's Tab. I and Tab. II rectangles (see the crate's `solver` tests).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Relative tolerance per step.
    pub rtol: f64,
    /// Absolute tolerance per step, in units of each component's natural scale (the
    /// estimated maximal overlap for ξ; see the module documentation).
    pub atol: f64,
    /// Limit on the accepted steps.
    pub max_steps: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            rtol: 1e-11,
            atol: 1e-11,
            max_steps: 100_000,
        }
    }
}

/// Work done by one solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SolveStats {
    pub accepted_steps: usize,
    pub rejected_steps: usize,
    pub rhs_evaluations: usize,
}

/// Why a solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveError {
    InvalidParams(String),
    TooManySteps(usize),
    StepSizeUnderflow { t: f64 },
}

impl fmt::Display for SolveError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidParams(why) => write!(f, "invalid scaled parameters: {why}"),
            Self::TooManySteps(n) => write!(
                f,
                "collision did not end within {n} steps (raise max_steps or loosen rtol)"
            ),
            Self::StepSizeUnderflow { t } => write!(f, "step size underflow at t = {t}"),
        }
    }
}

impl std::error::Error for SolveError {}

/// MoR of one collision with default tolerances.
pub fn solve(model: Model, p: &ScaledParams) -> Result<Mor, SolveError> {
    solve_with(model, p, &SolverOptions::default()).map(|(m, _)| m)
}

/// MoR of one collision with explicit tolerances, and the work it took.
pub fn solve_with(
    model: Model,
    p: &ScaledParams,
    opts: &SolverOptions,
) -> Result<(Mor, SolveStats), SolveError> {
    check_params(p)?;
    check_options(opts)?;
    let scales = Scales::new(model, p);
    match model {
        Model::Linear => integrate(&LinearDashpot { p: *p }, p, &scales, opts),
        Model::Hertz => integrate(&HertzRegularised { p: *p }, p, &scales, opts),
    }
}

/// One formulation of the collision ODE: its state, scales and the physical quantities.
trait Formulation<const N: usize>: System<N> {
    fn start(&self) -> [f64; N];
    /// Absolute tolerances for `opts.atol`.
    fn atol(&self, atol: f64, s: &Scales) -> [f64; N];
    /// A first trial step of the independent variable.
    fn first_step(&self, s: &Scales) -> f64;
    /// (t, ξ, u, φ) of a state at the independent variable `x`.
    fn physical(&self, x: f64, y: &[f64; N]) -> [f64; 4];
    /// A function that crosses zero from above where the collision ends.
    fn event(&self, y: &[f64; N]) -> f64;
}

/// Characteristic scales of one collision.
struct Scales {
    /// Estimated maximal overlap Ξ; also the time scale, as u(0) = 1.
    overlap: f64,
    /// Scale of u near the end of the collision.
    rate: f64,
    /// Scale of φ: Ξ·c_φ/l̃².
    phase: f64,
    /// Scale of |h'| at the end, |u| + c_dis·c_φ²/r³: an error δh moves the end by δh/|h'|.
    end_slope: f64,
}

impl Scales {
    fn new(model: Model, p: &ScaledParams) -> Self {
        let damped = match model {
            Model::Linear => 1.0 / (1.0 + p.c_dis),
            // Elastic: (5/4)^{2/5}; strongly damped: u ≈ 1 − (2/3)·c_dis·ξ^{3/2}.
            Model::Hertz => 1.25f64.powf(0.4).min((1.5 / p.c_dis).powf(2.0 / 3.0)),
        };
        // The centrifugal term c_φ²/l̃³ alone stops the approach within l̃³/(2c_φ²).
        let centrifugal = p.l_tilde.powi(3) / (2.0 * p.c_phi * p.c_phi);
        let overlap = damped.min(centrifugal).min(p.l_tilde);
        let rate = (overlap / p.c_dis).min(1.0);
        Self {
            overlap,
            rate,
            phase: overlap * p.c_phi / (p.l_tilde * p.l_tilde),
            end_slope: rate + p.c_dis * (p.c_phi / p.l_tilde).powi(2) / p.l_tilde,
        }
    }
}

fn integrate<F: Formulation<N>, const N: usize>(
    sys: &F,
    p: &ScaledParams,
    scales: &Scales,
    opts: &SolverOptions,
) -> Result<(Mor, SolveStats), SolveError> {
    let tol = Tolerances {
        rtol: opts.rtol,
        atol: sys.atol(opts.atol, scales),
        atol_monitored: opts.atol * scales.overlap * scales.end_slope,
    };
    let mut ode =
        Dop853::new(sys, 0.0, sys.start(), tol, sys.first_step(scales)).map_err(failure)?;
    let mut xi_max = 0.0f64;
    loop {
        if ode.counters.accepted >= opts.max_steps {
            return Err(SolveError::TooManySteps(opts.max_steps));
        }
        ode.step().map_err(failure)?;
        let y = *ode.y();
        let [t, xi, u, _] = sys.physical(ode.t(), &y);
        xi_max = xi_max.max(xi);
        if p.c_phi == 0.0 && xi >= p.l_tilde && u > 0.0 {
            return Err(SolveError::InvalidParams(format!(
                "central impact (c_phi = 0) with l_tilde = {} not larger than the overlap it \
                 reaches: the centres meet (r = 0) at t = {t:.6}; use c_phi > 0 or a larger \
                 l_tilde (a stiffer contact or a slower impact)",
                p.l_tilde
            )));
        }
        if sys.event(&y) <= 0.0 && u < 0.0 {
            break;
        }
    }
    let dense = ode.dense().map_err(failure)?;
    let (x_a, y_a) = ode.last_start();
    let x_end = illinois(
        |x| sys.event(&dense.eval(x)),
        (x_a, sys.event(y_a)),
        (ode.t(), sys.event(ode.y())),
    );
    let [tau, xi, u, phi] = sys.physical(x_end, &dense.eval(x_end));
    let (xi, u) = if p.c_dis == 0.0 {
        (0.0, u)
    } else if xi / xi_max < u.abs() {
        (-p.c_dis * u, u)
    } else {
        (xi, -xi / p.c_dis)
    };
    let one_minus_eps_r = xi / p.l_tilde;
    let c = ode.counters;
    Ok((
        Mor {
            eps_r: 1.0 - one_minus_eps_r,
            one_minus_eps_r,
            eps_rdot: u,
            eps_phi: phi,
            eps_t: tau,
        },
        SolveStats {
            accepted_steps: c.accepted,
            rejected_steps: c.rejected,
            rhs_evaluations: c.evaluations,
        },
    ))
}

/// Eq. (42) in (ξ, u, φ) and t.
struct LinearDashpot {
    p: ScaledParams,
}

impl System<3> for LinearDashpot {
    fn rhs(&self, _t: f64, y: &[f64; 3]) -> Option<[f64; 3]> {
        let [xi, u, _] = *y;
        let force = xi + self.p.c_dis * u;
        let (centrifugal, phi_dot) = centrifugal(&self.p, self.p.l_tilde - xi)?;
        Some([u, -centrifugal - force, phi_dot])
    }

    fn magnitude(&self, y: &[f64; 3]) -> [f64; 3] {
        let r = self.p.l_tilde - y[0];
        [y[0].abs().min(r.abs()), y[1].abs(), y[2].abs()]
    }

    /// The bracket h = ξ + c_dis·u: near the end it is a small difference of ξ and c_dis·u,
    /// and its error sets the error of τ.
    fn monitored(&self, y: &[f64; 3]) -> Option<(f64, [f64; 3])> {
        Some((y[0] + self.p.c_dis * y[1], [1.0, self.p.c_dis, 0.0]))
    }
}

impl Formulation<3> for LinearDashpot {
    fn start(&self) -> [f64; 3] {
        [0.0, 1.0, 0.0]
    }

    fn atol(&self, atol: f64, s: &Scales) -> [f64; 3] {
        [atol * s.overlap, atol * s.rate, atol * s.phase]
    }

    fn first_step(&self, s: &Scales) -> f64 {
        0.01 * s.overlap
    }

    fn physical(&self, t: f64, y: &[f64; 3]) -> [f64; 4] {
        [t, y[0], y[1], y[2]]
    }

    fn event(&self, y: &[f64; 3]) -> f64 {
        y[0] + self.p.c_dis * y[1]
    }
}

/// Eq. (54) in (w, u, φ, t), w = √ξ, and the regularising time σ, dt/dσ = w.
struct HertzRegularised {
    p: ScaledParams,
}

impl System<4> for HertzRegularised {
    fn rhs(&self, _sigma: f64, y: &[f64; 4]) -> Option<[f64; 4]> {
        let [w, u, _, _] = *y;
        let xi = w * w;
        let bracket = xi + self.p.c_dis * u;
        let (centrifugal, phi_dot) = centrifugal(&self.p, self.p.l_tilde - xi)?;
        Some([0.5 * u, -w * (centrifugal + w * bracket), w * phi_dot, w])
    }

    fn magnitude(&self, y: &[f64; 4]) -> [f64; 4] {
        // δr = 2w·δw, so w must also be resolved relative to r/(2w) where r is small.
        let w = y[0].abs();
        let r = (self.p.l_tilde - w * w).abs();
        [w.min(r / (2.0 * w)), y[1].abs(), y[2].abs(), y[3].abs()]
    }

    /// The bracket h = w² + c_dis·u, as for the linear dashpot.
    fn monitored(&self, y: &[f64; 4]) -> Option<(f64, [f64; 4])> {
        let [w, u, _, _] = *y;
        Some((w * w + self.p.c_dis * u, [2.0 * w, self.p.c_dis, 0.0, 0.0]))
    }
}

impl Formulation<4> for HertzRegularised {
    fn start(&self) -> [f64; 4] {
        [0.0, 1.0, 0.0, 0.0]
    }

    fn atol(&self, atol: f64, s: &Scales) -> [f64; 4] {
        [
            atol * s.overlap.sqrt(),
            atol * s.rate,
            atol * s.phase,
            atol * s.overlap,
        ]
    }

    fn first_step(&self, s: &Scales) -> f64 {
        // t = σ²/4 near the start.
        0.02 * s.overlap.sqrt()
    }

    fn physical(&self, _sigma: f64, y: &[f64; 4]) -> [f64; 4] {
        [y[3], y[0] * y[0], y[1], y[2]]
    }

    /// w + sign(u)·√(c_dis·|u|), which has the sign of h = w² + c_dis·u where w > 0 and
    /// u < 0, but keeps a simple root where h only touches zero (w = 0 for c_dis = 0) or
    /// would turn positive again (w < 0 beyond the end).
    fn event(&self, y: &[f64; 4]) -> f64 {
        let [w, u, _, _] = *y;
        w + (self.p.c_dis * u.abs()).sqrt().copysign(u)
    }
}

/// (c_φ²/r³, c_φ/r²), or `None` if r ≤ 0 with c_φ > 0 (a trial stage beyond the centre).
#[inline(always)]
fn centrifugal(p: &ScaledParams, r: f64) -> Option<(f64, f64)> {
    if p.c_phi == 0.0 {
        return Some((0.0, 0.0));
    }
    if r <= 0.0 || r.is_nan() {
        return None;
    }
    let w = p.c_phi / r;
    let phi_dot = w / r;
    Some((w * phi_dot, phi_dot))
}

/// Root of f in [a, b] with f(a) > 0 ≥ f(b), by the Illinois variant of regula falsi.
fn illinois(
    f: impl Fn(f64) -> f64,
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
) -> f64 {
    let mut side = 0i8;
    let mut c = b;
    for _ in 0..200 {
        if fb == 0.0 {
            return b;
        }
        let mut next = (a * fb - b * fa) / (fb - fa);
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
        }
        let converged = (next - c).abs() <= 4.0 * f64::EPSILON * next.abs();
        c = next;
        if converged || b - a <= 4.0 * f64::EPSILON * b.abs() {
            break;
        }
        let fc = f(c);
        if fc > 0.0 {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    c
}

fn failure(f: StepFailure) -> SolveError {
    match f {
        StepFailure::Underflow { t } | StepFailure::OutsideDomain { t } => {
            SolveError::StepSizeUnderflow { t }
        }
    }
}

fn check_params(p: &ScaledParams) -> Result<(), SolveError> {
    let bad = |name: &str, v: f64, want: &str| {
        Err(SolveError::InvalidParams(format!(
            "{name} = {v} but it must be finite and {want}"
        )))
    };
    if !(p.l_tilde.is_finite() && p.l_tilde > 0.0) {
        return bad("l_tilde", p.l_tilde, "> 0");
    }
    if !(p.c_phi.is_finite() && p.c_phi >= 0.0) {
        return bad("c_phi", p.c_phi, ">= 0");
    }
    if !(p.c_dis.is_finite() && p.c_dis >= 0.0) {
        return bad("c_dis", p.c_dis, ">= 0");
    }
    Ok(())
}

fn check_options(o: &SolverOptions) -> Result<(), SolveError> {
    let ok = o.rtol.is_finite()
        && (1e-15..=1e-2).contains(&o.rtol)
        && o.atol.is_finite()
        && o.atol >= 0.0
        && o.max_steps > 0;
    if ok {
        Ok(())
    } else {
        Err(SolveError::InvalidParams(format!(
            "solver options {o:?}: need 1e-15 <= rtol <= 1e-2, finite atol >= 0, max_steps > 0"
        )))
    }
}
