//! Solver of the scaled collision ODE of Müller & Pöschel 2013, Eqs. (42) and (54), with
//! the force-zero end of the collision, Eq. (10) (Schwager & Pöschel 2007).
//!
//! # Formulation
//! In the overlap ξ = l̃ − r̃ and its rate u = ξ' = −r̃' (l̃ reaches e^17 while ξ = O(1), so
//! r̃ would lose the digits of ξ): ξ' = u, u' = −c_φ²/(l̃−ξ)³ − g(ξ)·h, φ' = c_φ/(l̃−ξ)²,
//! with the bracket h = ξ + c_dis·u and g = 1 (linear) or √ξ (Hertz); the scaled normal
//! force is F = g·h. Start (Eq. 44): ξ = 0, u = 1, φ = 0.
//!
//! - **Linear dashpot:** (ξ, u, φ) in t; analytic also for ξ < 0 (stages beyond the end).
//! - **Hertz:** √ξ makes the solution non-smooth where ξ → 0 (F ~ t^{3/2} at the start),
//!   which ruins the order of any Runge–Kutta method. So (w, u, φ, t), w = √ξ, is
//!   integrated in σ with dt/dσ = w: w' = u/2, u' = −w·c_φ²/r³ − w²·h, φ' = w·c_φ/r²,
//!   t' = w (r = l̃ − w², h = w² + c_dis·u). This is polynomial in w and u, hence analytic;
//!   how to evaluate the Hertz law at ξ < 0 never arises: beyond the end, stages follow
//!   the analytic continuation, which is never used for the result.
//! - **c_dis ≥ 1:** the second component is h itself (u = (h − ξ)/c_dis). Near the end h is
//!   a tiny difference of ξ and c_dis·u crossing zero with slope u − c_dis·c_φ²/r³ (tiny for
//!   central impacts); computed from (ξ, u) its rounding ε·ξ would shift τ by ~ε·c_dis²
//!   relative. For Hertz, h then relaxes over many e-foldings to a slowly drifting
//!   asymptote h_∞ < 0; that tail is handed over to q = ln(h − h_∞) ([`HertzTail`]).
//!
//! # End of the collision
//! Where r̃' > 0 and F = 0 (Eq. 10): h crosses zero from above with u < 0 (ξ = 0, w = 0
//! for c_dis = 0; the trivial root at t = 0 is skipped). While ξ > 0, h ≥ 0 ⇔ F ≥ 0, so the
//! clipping F = max(0, …) never acts before. The end is bracketed by an accepted step and
//! located on its 7th-order dense output (Illinois). There ξ = −c_dis·u exactly; of the two,
//! the one far from zero relative to its peak fixes the other.
//!
//! # Tolerances
//! With an estimated maximal overlap Ξ (≈ (1.5/c_dis)^{2/3} for stiff Hertz, 1/c_dis for
//! the overdamped dashpot), absolute tolerances are atol·Ξ on ξ (atol·√Ξ on w, atol·Ξ on
//! t), atol·min(1, Ξ/c_dis) on u, atol·Ξ·c_φ/l̃² on φ, and atol·Ξ·|h'|_end on h (as a state
//! or a monitored combination; an error δh moves the end by δh/|h'|). The relative
//! tolerance on ξ refers to min(|ξ|, |l̃−ξ|), resolving r̃ also where the spheres nearly
//! pass through each other (small l̃).

use crate::dop853::{Dop853, StepFailure, System, Tolerances};
use crate::roots::illinois;
use emdstar_contact::{Model, Mor, ScaledParams};
use std::fmt;

/// Tolerances and limits of the integration.
///
/// The defaults give ≤ 1e-9 relative error in each of 1−ε_r, ε_ṙ, ε_φ and ε_t over the
/// paper's Tab. I and Tab. II rectangles: the worst found against rtol = 1e-14 and two
/// independent oracles over 4·10⁴ points was 2.3e-10 (see the `acceptance` test of
/// `tests/solver`).
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
    let mut run = Progress::default();
    let end = match model {
        Model::Linear => {
            let sys = LinearDashpot::new(p);
            integrate(&sys, p, &scales, opts, sys.start(), &mut run)?
        }
        Model::Hertz => {
            let mut sys = HertzRegularised::new(p);
            let end = match integrate(&sys, p, &scales, opts, sys.start(), &mut run)? {
                Outcome::HandOver(start) => {
                    integrate(&HertzTail { p: *p }, p, &scales, opts, start, &mut run)
                }
                end => Ok(end),
            };
            // Should the tail form ever fail, the h-form alone still gets there.
            if end.is_err() {
                sys.tail = false;
                integrate(&sys, p, &scales, opts, sys.start(), &mut run)?
            } else {
                end?
            }
        }
    };
    let Outcome::End([tau, xi, u, phi]) = end else {
        return Err(SolveError::StepSizeUnderflow { t: f64::NAN });
    };
    let (xi, u) = if p.c_dis == 0.0 {
        (0.0, u)
    } else if xi / run.xi_max < u.abs() {
        (-p.c_dis * u, u)
    } else {
        (xi, -xi / p.c_dis)
    };
    let one_minus_eps_r = xi / p.l_tilde;
    Ok((
        Mor {
            eps_r: 1.0 - one_minus_eps_r,
            one_minus_eps_r,
            eps_rdot: u,
            eps_phi: phi,
            eps_t: tau,
        },
        run.stats,
    ))
}

/// Where an integration starts: independent variable, state and first trial step.
type Start<const N: usize> = (f64, [f64; N], f64);

/// What one formulation's integration ends with.
enum Outcome {
    /// (τ, ξ, u, φ) at the end of the collision.
    End([f64; 4]),
    /// The start of the Hertz tail formulation.
    HandOver(Start<4>),
}

/// Work and the peak overlap, accumulated over formulations.
#[derive(Default)]
struct Progress {
    stats: SolveStats,
    xi_max: f64,
}

/// One formulation of the collision ODE: its state, scales and the physical quantities.
trait Formulation<const N: usize>: System<N> {
    /// Absolute tolerances for `opts.atol`.
    fn atol(&self, atol: f64, s: &Scales) -> [f64; N];
    /// The start of another formulation to continue with from the state `y` at `x`.
    fn hand_over(&self, _x: f64, _y: &[f64; N], _step: f64) -> Option<Start<4>> {
        None
    }
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
    /// Absolute scale of h near the end: Ξ·|h'|, with |h'| ≈ |u| + c_dis·c_φ²/r³ there
    /// (an error δh moves the end by δh/|h'|).
    bracket: f64,
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
        let end_slope = rate + p.c_dis * (p.c_phi / p.l_tilde).powi(2) / p.l_tilde;
        Self {
            overlap,
            rate,
            phase: overlap * p.c_phi / (p.l_tilde * p.l_tilde),
            bracket: overlap * end_slope,
        }
    }
}

fn integrate<F: Formulation<N>, const N: usize>(
    sys: &F,
    p: &ScaledParams,
    scales: &Scales,
    opts: &SolverOptions,
    (x0, y0, h0): Start<N>,
    run: &mut Progress,
) -> Result<Outcome, SolveError> {
    let tol = Tolerances {
        rtol: opts.rtol,
        atol: sys.atol(opts.atol, scales),
        atol_monitored: opts.atol * scales.bracket,
    };
    let mut ode = Dop853::new(sys, x0, y0, tol, h0).map_err(failure)?;
    let outcome = loop {
        if run.stats.accepted_steps + ode.counters.accepted >= opts.max_steps {
            return Err(SolveError::TooManySteps(opts.max_steps));
        }
        ode.step().map_err(failure)?;
        let y = *ode.y();
        let [t, xi, u, _] = sys.physical(ode.t(), &y);
        run.xi_max = run.xi_max.max(xi);
        if p.c_phi == 0.0 && xi >= p.l_tilde && u > 0.0 {
            return Err(SolveError::InvalidParams(format!(
                "central impact (c_phi = 0) with l_tilde = {} not larger than the overlap it \
                 reaches: the centres meet (r = 0) at t = {t:.6}; use c_phi > 0 or a larger \
                 l_tilde (a stiffer contact or a slower impact)",
                p.l_tilde
            )));
        }
        if sys.event(&y) <= 0.0 && u < 0.0 {
            let dense = ode.dense().map_err(failure)?;
            let (x_a, y_a) = ode.last_start();
            let x_end = illinois(
                |x| sys.event(&dense.eval(x)),
                (x_a, sys.event(y_a)),
                (ode.t(), sys.event(&y)),
            );
            break Outcome::End(sys.physical(x_end, &dense.eval(x_end)));
        }
        if let Some(start) = sys.hand_over(ode.t(), &y, ode.next_step()) {
            break Outcome::HandOver(start);
        }
    };
    let c = ode.counters;
    run.stats.accepted_steps += c.accepted;
    run.stats.rejected_steps += c.rejected;
    run.stats.rhs_evaluations += c.evaluations;
    Ok(outcome)
}

/// Above this c_dis the second state component is the bracket h instead of u.
const BRACKET_FORM_FROM: f64 = 1.0;

/// The rate u and the bracket h = ξ + c_dis·u from the second state component `v`, which
/// is u (`bracket_form` false) or h (true).
#[inline(always)]
fn rate_and_bracket(bracket_form: bool, c_dis: f64, xi: f64, v: f64) -> (f64, f64) {
    if bracket_form {
        ((v - xi) / c_dis, v)
    } else {
        (v, xi + c_dis * v)
    }
}

/// Eq. (42) in (ξ, v, φ) and t, v = u or v = h.
struct LinearDashpot {
    p: ScaledParams,
    bracket_form: bool,
}

impl System<3> for LinearDashpot {
    fn rhs(&self, _t: f64, y: &[f64; 3]) -> Option<[f64; 3]> {
        let [xi, v, _] = *y;
        let (u, h) = rate_and_bracket(self.bracket_form, self.p.c_dis, xi, v);
        let (centrifugal, phi_dot) = centrifugal(&self.p, self.p.l_tilde - xi)?;
        let du = -centrifugal - h;
        let dv = if self.bracket_form {
            u + self.p.c_dis * du
        } else {
            du
        };
        Some([u, dv, phi_dot])
    }

    fn magnitude(&self, y: &[f64; 3]) -> [f64; 3] {
        let r = self.p.l_tilde - y[0];
        [y[0].abs().min(r.abs()), y[1].abs(), y[2].abs()]
    }

    /// In the u-form, the bracket h = ξ + c_dis·u: near the end it is a small difference
    /// of ξ and c_dis·u, and its error sets the error of τ.
    fn monitored(&self, y: &[f64; 3]) -> Option<(f64, [f64; 3])> {
        (!self.bracket_form).then(|| (y[0] + self.p.c_dis * y[1], [1.0, self.p.c_dis, 0.0]))
    }
}

impl LinearDashpot {
    fn new(p: &ScaledParams) -> Self {
        let bracket_form = p.c_dis >= BRACKET_FORM_FROM;
        Self {
            p: *p,
            bracket_form,
        }
    }

    /// ξ = 0, u = 1 (h = c_dis), φ = 0 at t = 0, and a first trial step.
    fn start(&self) -> Start<3> {
        let v = if self.bracket_form { self.p.c_dis } else { 1.0 };
        let step = 0.01 * Scales::new(Model::Linear, &self.p).overlap;
        (0.0, [0.0, v, 0.0], step)
    }
}

impl Formulation<3> for LinearDashpot {
    fn atol(&self, atol: f64, s: &Scales) -> [f64; 3] {
        let v = if self.bracket_form { s.bracket } else { s.rate };
        [atol * s.overlap, atol * v, atol * s.phase]
    }

    fn physical(&self, t: f64, y: &[f64; 3]) -> [f64; 4] {
        let (u, _) = rate_and_bracket(self.bracket_form, self.p.c_dis, y[0], y[1]);
        [t, y[0], u, y[2]]
    }

    fn event(&self, y: &[f64; 3]) -> f64 {
        rate_and_bracket(self.bracket_form, self.p.c_dis, y[0], y[1]).1
    }
}

/// Eq. (54) in (w, v, φ, t), w = √ξ, v = u or v = h, and the regularising time σ,
/// dt/dσ = w.
struct HertzRegularised {
    p: ScaledParams,
    bracket_form: bool,
    /// Whether the exponential tail may be handed over to [`HertzTail`].
    tail: bool,
}

impl System<4> for HertzRegularised {
    fn rhs(&self, _sigma: f64, y: &[f64; 4]) -> Option<[f64; 4]> {
        let [w, v, _, _] = *y;
        let xi = w * w;
        let (u, h) = rate_and_bracket(self.bracket_form, self.p.c_dis, xi, v);
        let (centrifugal, phi_dot) = centrifugal(&self.p, self.p.l_tilde - xi)?;
        let du = -w * (centrifugal + w * h);
        // d(w²)/dσ = 2w·w' = w·u.
        let dv = if self.bracket_form {
            w * u + self.p.c_dis * du
        } else {
            du
        };
        Some([0.5 * u, dv, w * phi_dot, w])
    }

    fn magnitude(&self, y: &[f64; 4]) -> [f64; 4] {
        // δr = 2w·δw, so w must also be resolved relative to r/(2w) where r is small.
        let w = y[0].abs();
        let r = (self.p.l_tilde - w * w).abs();
        [w.min(r / (2.0 * w)), y[1].abs(), y[2].abs(), y[3].abs()]
    }

    /// In the u-form, the bracket h = w² + c_dis·u, as for the linear dashpot.
    fn monitored(&self, y: &[f64; 4]) -> Option<(f64, [f64; 4])> {
        let [w, u, _, _] = *y;
        (!self.bracket_form)
            .then_some((w * w + self.p.c_dis * u, [2.0 * w, self.p.c_dis, 0.0, 0.0]))
    }
}

impl HertzRegularised {
    /// w = 0, u = 1 (h = c_dis), φ = 0, t = 0 at σ = 0, and a first trial step (t = σ²/4
    /// near the start).
    fn new(p: &ScaledParams) -> Self {
        let bracket_form = p.c_dis >= BRACKET_FORM_FROM;
        Self {
            p: *p,
            bracket_form,
            tail: bracket_form,
        }
    }

    fn start(&self) -> Start<4> {
        let v = if self.bracket_form { self.p.c_dis } else { 1.0 };
        let overlap = Scales::new(Model::Hertz, &self.p).overlap;
        (0.0, [0.0, v, 0.0, 0.0], 0.02 * overlap.sqrt())
    }
}

impl Formulation<4> for HertzRegularised {
    fn atol(&self, atol: f64, s: &Scales) -> [f64; 4] {
        let v = if self.bracket_form { s.bracket } else { s.rate };
        [s.overlap.sqrt(), v, s.phase, s.overlap].map(|x| atol * x)
    }

    fn physical(&self, _sigma: f64, y: &[f64; 4]) -> [f64; 4] {
        let xi = y[0] * y[0];
        let (u, _) = rate_and_bracket(self.bracket_form, self.p.c_dis, xi, y[1]);
        [y[3], xi, u, y[2]]
    }

    /// The h-form uses h itself (for c_dis ≥ 1 the end comes at ξ = c_dis·|u|, far from
    /// w = 0). The u-form uses w + sign(u)·√(c_dis·|u|), which has the sign of
    /// h = w² + c_dis·u where w > 0 and u < 0, but keeps a simple root where h only
    /// touches zero (w = 0 for c_dis = 0) or would turn positive again (w < 0 beyond the end).
    fn event(&self, y: &[f64; 4]) -> f64 {
        let [w, v, _, _] = *y;
        if self.bracket_form {
            v
        } else {
            w + (self.p.c_dis * v.abs()).sqrt().copysign(v)
        }
    }

    /// Hands the exponential tail of a strongly damped collision (the creeping end of the
    /// approach and the release) over to [`HertzTail`], once the relaxation of h is fast
    /// against the drift of its asymptote.
    fn hand_over(&self, sigma: f64, y: &[f64; 4], step: f64) -> Option<Start<4>> {
        let [w, h, phi, t] = *y;
        if !self.tail || h <= 0.0 {
            return None;
        }
        let tail = HertzTail { p: self.p };
        let a = tail.asymptote(w)?;
        // Stiff (c_dis·w ≫ 1/c_dis keeps h_∞ regular while w shrinks a little more), at
        // least 5 e-foldings of h − h_∞ left, and h_∞ drifting little per e-folding.
        let drift = (a.slope * 0.5 * (h - w * w) / self.p.c_dis).abs() / a.rate;
        let stiff = self.p.c_dis * self.p.c_dis * w >= 100.0;
        let folds = ((h - a.value) / -a.value).ln();
        (stiff && folds >= 5.0 && drift <= 1e-3 * a.value.abs()).then_some((
            sigma,
            [w, (h - a.value).ln(), phi, t],
            step,
        ))
    }
}

/// The exponential tail of a strongly damped Hertz collision, in (w, q, φ, t) with
/// q = ln(h − h_∞(w)) and the time σ of [`HertzRegularised`].
///
/// There dh/dσ = −λ·(h − h_∞) with λ = w·(c_dis·w − 1/c_dis) and the quasi-static
/// h_∞ = −(w²/c_dis + c_dis·c_φ²/r³)/(c_dis·w − 1/c_dis) < 0 drifting only slowly with w:
/// h decays over many e-foldings, which an explicit method resolved in h follows with
/// λ·Δσ ≈ 1/4 per step, but q just decreases about linearly. The end h = 0 is
/// e^q = −h_∞, a simple root.
struct HertzTail {
    p: ScaledParams,
}

/// h_∞, dh_∞/dw and λ at one w.
struct Asymptote {
    value: f64,
    slope: f64,
    rate: f64,
}

impl HertzTail {
    fn asymptote(&self, w: f64) -> Option<Asymptote> {
        let c = self.p.c_dis;
        let r = self.p.l_tilde - w * w;
        let (centrifugal, _) = centrifugal(&self.p, r)?;
        let den = c * w - 1.0 / c;
        if den <= 0.0 || w <= 0.0 {
            return None;
        }
        let num = w * w / c + c * centrifugal;
        // d(c_φ²/r³)/dw = 6w·c_φ²/r⁴.
        let dnum = 2.0 * w / c + 6.0 * c * w * centrifugal / r;
        Some(Asymptote {
            value: -num / den,
            slope: -(dnum * den - num * c) / (den * den),
            rate: w * den,
        })
    }

    /// (h, u) of a state.
    fn bracket_and_rate(&self, a: &Asymptote, y: &[f64; 4]) -> (f64, f64) {
        let h = a.value + y[1].exp();
        (h, (h - y[0] * y[0]) / self.p.c_dis)
    }
}

impl System<4> for HertzTail {
    fn rhs(&self, _sigma: f64, y: &[f64; 4]) -> Option<[f64; 4]> {
        let [w, q, _, _] = *y;
        let a = self.asymptote(w)?;
        let (h, u) = self.bracket_and_rate(&a, y);
        let (centrifugal, phi_dot) = centrifugal(&self.p, self.p.l_tilde - w * w)?;
        let dw = 0.5 * u;
        let dh = w * u - self.p.c_dis * w * (centrifugal + w * h);
        Some([dw, (dh - a.slope * dw) * (-q).exp(), w * phi_dot, w])
    }

    fn magnitude(&self, y: &[f64; 4]) -> [f64; 4] {
        // q is a logarithm: its absolute error is the relative error of h − h_∞.
        [y[0].abs(), 1.0, y[2].abs(), y[3].abs()]
    }
}

impl Formulation<4> for HertzTail {
    fn atol(&self, atol: f64, s: &Scales) -> [f64; 4] {
        [s.overlap.sqrt(), 0.0, s.phase, s.overlap].map(|x| atol * x)
    }

    fn physical(&self, _sigma: f64, y: &[f64; 4]) -> [f64; 4] {
        let u = self
            .asymptote(y[0])
            .map_or(f64::NAN, |a| self.bracket_and_rate(&a, y).1);
        [y[3], y[0] * y[0], u, y[2]]
    }

    fn event(&self, y: &[f64; 4]) -> f64 {
        self.asymptote(y[0])
            .map_or(f64::NAN, |a| self.bracket_and_rate(&a, y).0)
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

fn failure(f: StepFailure) -> SolveError {
    match f {
        StepFailure::Underflow { t } | StepFailure::OutsideDomain { t } => {
            SolveError::StepSizeUnderflow { t }
        }
    }
}

fn check_params(p: &ScaledParams) -> Result<(), SolveError> {
    for (name, v, zero_ok) in [
        ("l_tilde", p.l_tilde, false),
        ("c_phi", p.c_phi, true),
        ("c_dis", p.c_dis, true),
    ] {
        if !(v.is_finite() && (v > 0.0 || zero_ok && v == 0.0)) {
            let want = if zero_ok { ">= 0" } else { "> 0" };
            let why = format!("{name} = {v} but it must be finite and {want}");
            return Err(SolveError::InvalidParams(why));
        }
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
