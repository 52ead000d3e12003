//! The exact two-body contact of frictional soft spheres: the normal force law of
//! Müller & Pöschel 2013 (Eqs. 40 and 51) with the Cundall–Strack history spring of
//! `emdstar_contact::tangential` (docs/physics.md, "Friction and rotation"), both
//! spins, in three dimensions, from first touch to the end of the frictionless solver,
//! F_n = 0 with the spheres separating (Eq. 10).
//!
//! # Equations (relative coordinates r = x₁ − x₂, v = ṙ, n = r/|r|)
//! - m_eff v̇ = F_n n + F_t, F_n = F(ξ, ξ̇) the pair's law, ξ = l − |r|, ξ̇ = −v·n;
//! - I_i ω̇_i = −(R_i − ξ/2) n × F_t (both spheres, the lever arm of [`lever_arm`]);
//! - the slip v_t = v − (v·n)n − (R₁ω₁ + R₂ω₂) × n ([`slip_velocity`]);
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

use crate::dop853::{Dop853, StepFailure, System, Tolerances, illinois};
use crate::{SolveError, SolveStats, SolverOptions};
use emdstar_contact::vec3::{add, add_scaled, cross, dot, norm, scale, sub};
use emdstar_contact::{HistorySpring, PairLaw, SOLID_SPHERE_INERTIA, lever_arm, slip_velocity};

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

/// Index of the components of the state.
const D: usize = 0;
const V: usize = 3;
const W1: usize = 6;
const W2: usize = 9;
const SPRING: usize = 12;
/// ξ (linear) or w = √ξ (Hertz).
const S: usize = 15;
const T: usize = 16;
const N: usize = 17;

/// Samples of a step that bracket an event starting at zero.
const SAMPLES: usize = 16;

/// Bound on the stick–slip switches of one contact.
const MAX_SWITCHES: usize = 1000;

/// The contact of `bodies` touching at `separation` (|r| = R₁ + R₂) with relative velocity
/// `velocity` (approaching), under `law` and the history spring of `friction`.
pub fn solve_frictional(
    law: &PairLaw,
    friction: &HistorySpring,
    bodies: &[Spinning; 2],
    separation: [f64; 3],
    velocity: [f64; 3],
    opts: &SolverOptions,
) -> Result<FrictionalEnd, SolveError> {
    let ode = Contact::new(law, friction, bodies, separation, velocity)?;
    let mut y = [0.0; N];
    y[V..V + 3].copy_from_slice(&velocity);
    y[W1..W1 + 3].copy_from_slice(&bodies[0].spin);
    y[W2..W2 + 3].copy_from_slice(&bodies[1].spin);
    let mut sliding = ode.starts_sliding(&y);
    let tol = ode.tolerances(opts);
    let mut stats = SolveStats::default();
    let mut x = 0.0;
    let mut step = 0.01 * ode.first_step();
    let mut switches = 0;
    loop {
        let stretch = Stretch {
            contact: &ode,
            sliding,
        };
        if sliding {
            y = stretch.onto_cap(&y);
        }
        let mut solver = Dop853::new(&stretch, x, y, tol, step).map_err(failure)?;
        let found = loop {
            if stats.accepted_steps + solver.counters.accepted >= opts.max_steps {
                return Err(SolveError::TooManySteps(opts.max_steps));
            }
            solver.step().map_err(failure)?;
            if let Some(found) = stretch.event_in_step(&mut solver)? {
                break found;
            }
        };
        let c = solver.counters;
        stats.accepted_steps += c.accepted;
        stats.rejected_steps += c.rejected;
        stats.rhs_evaluations += c.evaluations;
        match found {
            Found::End(y_end) => return Ok(ode.end(&y_end, switches, stats)),
            Found::Switch(x_s, y_s) => {
                switches += 1;
                if switches > MAX_SWITCHES {
                    return Err(SolveError::TooManySteps(opts.max_steps));
                }
                (x, y, sliding) = (x_s, y_s, !sliding);
                step = solver.next_step();
            }
        }
    }
}

/// The parameters of one contact, in SI units.
struct Contact {
    hertz: bool,
    /// Linear: k, γ. Hertz: ρ_el, (3/2)A.
    elastic: f64,
    viscous: f64,
    mu: f64,
    k_t: f64,
    gamma_t: f64,
    radii: [f64; 2],
    inv_inertia: [f64; 2],
    m_eff: f64,
    /// r at first touch.
    touch: [f64; 3],
    /// Scales: speed, the estimated peak overlap and the contact time.
    speed: f64,
    overlap: f64,
    time: f64,
}

/// One smooth stretch: the contact, sticking or sliding.
struct Stretch<'a> {
    contact: &'a Contact,
    sliding: bool,
}

/// What ends a stretch.
enum Found {
    End([f64; N]),
    Switch(f64, [f64; N]),
}

/// The right-hand side and the event functions at one state.
struct Eval {
    dy: [f64; N],
    /// F_n (unclipped), zero crossing from above = end (with ξ̇ < 0).
    end: f64,
    rate: f64,
    /// Sticking: µF_n − |f|; sliding: c·dt/dx. Crosses zero from above at a switch.
    mode: f64,
}

impl Contact {
    fn new(
        law: &PairLaw,
        friction: &HistorySpring,
        bodies: &[Spinning; 2],
        touch: [f64; 3],
        velocity: [f64; 3],
    ) -> Result<Self, SolveError> {
        let invalid = |why: String| Err(SolveError::InvalidParams(why));
        if !(friction.stiffness > 0.0 && friction.stiffness.is_finite()) {
            return invalid("the exact frictional contact needs tangential_stiffness > 0".into());
        }
        let l = bodies[0].radius + bodies[1].radius;
        let approach = -dot(velocity, touch) / norm(touch);
        if approach.is_nan() || approach <= 0.0 || (norm(touch) - l).abs() > 1e-9 * l {
            return invalid(format!(
                "the spheres must touch (|r| = {} for R1 + R2 = {l}) and approach (normal \
                 speed {approach})",
                norm(touch)
            ));
        }
        let m_eff = bodies[0].mass * bodies[1].mass / (bodies[0].mass + bodies[1].mass);
        let speed = norm(velocity);
        let (hertz, elastic, viscous, overlap) = match *law {
            PairLaw::Linear { stiffness, damping } => (
                false,
                stiffness,
                damping,
                approach * (m_eff / stiffness).sqrt(),
            ),
            PairLaw::Hertz {
                rho_el,
                dissipation,
            } => {
                let peak = (1.25 * m_eff * approach * approach / rho_el).powf(0.4);
                (true, rho_el, 1.5 * dissipation, peak)
            }
        };
        Ok(Self {
            hertz,
            elastic,
            viscous,
            mu: friction.friction,
            k_t: friction.stiffness,
            gamma_t: friction.damping,
            radii: [bodies[0].radius, bodies[1].radius],
            inv_inertia: [1.0 / bodies[0].inertia(), 1.0 / bodies[1].inertia()],
            m_eff,
            touch,
            speed,
            overlap,
            time: overlap / approach,
        })
    }

    fn first_step(&self) -> f64 {
        if self.hertz {
            // t ≈ σ²/4 near the start.
            2.0 * self.time.sqrt()
        } else {
            self.time
        }
    }

    fn tolerances(&self, opts: &SolverOptions) -> Tolerances<N> {
        let a = opts.atol;
        let travel = self.speed * self.time;
        let mut atol = [a * travel; N];
        for k in 0..3 {
            atol[V + k] = a * self.speed;
            atol[W1 + k] = a * self.speed / self.radii[0];
            atol[W2 + k] = a * self.speed / self.radii[1];
        }
        atol[S] = if self.hertz {
            a * self.overlap.sqrt()
        } else {
            a * self.overlap
        };
        atol[T] = a * self.time;
        Tolerances {
            rtol: opts.rtol,
            atol,
            atol_monitored: 0.0,
        }
    }

    /// ξ, dt/dx and the normal force from the overlap coordinate s, and the derivative
    /// of the force times dt/dx given ξ̇ and ξ̈.
    fn normal(&self, s: f64, rate: f64) -> (f64, f64, f64) {
        if self.hertz {
            let xi = s * s;
            (xi, s, self.elastic * s * (xi + self.viscous * rate))
        } else {
            (s, 1.0, self.elastic * s + self.viscous * rate)
        }
    }

    /// dF_n/dt · dt/dx (finite at ξ = 0 for Hertz).
    fn normal_growth(&self, s: f64, rate: f64, rate_dot: f64) -> f64 {
        if self.hertz {
            let xi = s * s;
            self.elastic
                * (0.5 * rate * (xi + self.viscous * rate) + xi * (rate + self.viscous * rate_dot))
        } else {
            self.elastic * rate + self.viscous * rate_dot
        }
    }

    /// Whether the contact slides from its first instant: the trial force −γ_t v_t
    /// against the cap µF_n(0⁺), and where both vanish their growth.
    fn starts_sliding(&self, y: &[f64; N]) -> bool {
        let v = vec(y, V);
        let n = scale(1.0 / norm(self.touch), self.touch);
        let slip = self.slip(y, n);
        let s = norm(slip);
        if s <= 1e-14 * self.speed {
            return false;
        }
        let approach = -dot(v, n);
        let (trial, cap) = (self.gamma_t * s, self.mu * self.viscous * approach);
        let cap = if self.hertz { 0.0 } else { cap };
        if trial != cap {
            return trial > cap;
        }
        // Both zero: |f| grows as k_t s t; the cap as µ k v_n t (linear), faster than t
        // (damped Hertz) or slower (elastic Hertz).
        if self.hertz {
            self.viscous == 0.0
        } else {
            self.k_t * s > self.mu * self.elastic * approach
        }
    }

    fn slip(&self, y: &[f64; N], n: [f64; 3]) -> [f64; 3] {
        slip_velocity(
            n,
            vec(y, V),
            (self.radii[0], vec(y, W1)),
            (self.radii[1], vec(y, W2)),
        )
    }

    fn eval(&self, y: &[f64; N], sliding: bool) -> Option<Eval> {
        let r = add(self.touch, vec(y, D));
        let dist = norm(r);
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        let n = scale(1.0 / dist, r);
        let v = vec(y, V);
        let rate = -dot(v, n);
        let (xi, jac, f_n) = self.normal(y[S], rate);
        let cap = self.mu * f_n;
        let slip = self.slip(y, n);
        let spring = vec(y, SPRING);
        let n_dot = scale(1.0 / dist, add_scaled(v, rate, n));
        let transport = add_scaled(slip, -dot(spring, n_dot), n);
        let trial = add_scaled(scale(-self.k_t, spring), -self.gamma_t, slip);
        let trial_norm = norm(trial);
        let direction = sliding_direction(trial, slip);
        let f_t = if sliding {
            scale(cap, direction)
        } else {
            trial
        };
        let acc = scale(1.0 / self.m_eff, add_scaled(f_t, f_n, n));
        let n_x_f = cross(n, f_t);
        let arms = self.radii.map(|r| lever_arm(r, xi));
        let dw = [0, 1].map(|i| scale(-arms[i] * self.inv_inertia[i], n_x_f));
        let mut dy = [0.0; N];
        put(&mut dy, D, scale(jac, v));
        put(&mut dy, V, scale(jac, acc));
        put(&mut dy, W1, scale(jac, dw[0]));
        put(&mut dy, W2, scale(jac, dw[1]));
        dy[S] = if self.hertz { 0.5 * rate } else { rate };
        dy[T] = jac;
        let rate_dot = -(dot(acc, n) + dot(v, n_dot));
        let mode = if sliding {
            // dv_t/dt of the slip velocity, for the spring's pull-back c.
            let spin_sum = add_scaled(scale(self.radii[0], vec(y, W1)), self.radii[1], vec(y, W2));
            let spin_rate = add_scaled(scale(self.radii[0], dw[0]), self.radii[1], dw[1]);
            let vn = -rate;
            let mut slip_dot = add_scaled(acc, -dot(acc, n), n);
            slip_dot = add_scaled(slip_dot, -dot(v, n_dot), n);
            slip_dot = add_scaled(slip_dot, -vn, n_dot);
            slip_dot = sub(slip_dot, cross(spin_rate, n));
            slip_dot = sub(slip_dot, cross(spin_sum, n_dot));
            let pull = (-self.k_t * jac * dot(direction, transport)
                - self.gamma_t * jac * dot(direction, slip_dot)
                - self.mu * self.normal_growth(y[S], rate, rate_dot))
                / self.k_t;
            if self.mu == 0.0 {
                // Without friction the force stays zero (the spring is not needed), and
                // nothing can stick.
                1.0
            } else {
                put(
                    &mut dy,
                    SPRING,
                    add_scaled(scale(jac, transport), pull, direction),
                );
                pull
            }
        } else {
            put(&mut dy, SPRING, scale(jac, transport));
            cap - trial_norm
        };
        let end = if self.hertz && self.viscous == 0.0 {
            y[S]
        } else {
            f_n
        };
        Some(Eval {
            dy,
            end,
            rate,
            mode,
        })
    }

    fn end(&self, y: &[f64; N], switches: usize, stats: SolveStats) -> FrictionalEnd {
        FrictionalEnd {
            separation: add(self.touch, vec(y, D)),
            velocity: vec(y, V),
            spins: [vec(y, W1), vec(y, W2)],
            duration: y[T],
            switches,
            stats,
        }
    }
}

impl System<N> for Stretch<'_> {
    fn rhs(&self, _x: f64, y: &[f64; N]) -> Option<[f64; N]> {
        self.contact.eval(y, self.sliding).map(|e| e.dy)
    }
}

impl Stretch<'_> {
    /// The state with the spring set onto the cap, −k_t ξ_t − γ_t v_t = µF_n f̂ (as MD
    /// resets it), at the start of a sliding stretch.
    fn onto_cap(&self, y: &[f64; N]) -> [f64; N] {
        let c = self.contact;
        let Some(e) = c.eval(y, true) else {
            return *y;
        };
        let r = add(c.touch, vec(y, D));
        let n = scale(1.0 / norm(r), r);
        let slip = c.slip(y, n);
        let (_, _, f_n) = c.normal(y[S], e.rate);
        let trial = add_scaled(scale(-c.k_t, vec(y, SPRING)), -c.gamma_t, slip);
        let direction = sliding_direction(trial, slip);
        let spring = scale(
            -1.0 / c.k_t,
            add_scaled(scale(c.mu * f_n.max(0.0), direction), c.gamma_t, slip),
        );
        let mut out = *y;
        put(&mut out, SPRING, spring);
        out
    }

    /// The first event inside the last accepted step: the end of the contact or a switch.
    fn event_in_step(&self, solver: &mut Dop853<'_, Self, N>) -> Result<Option<Found>, SolveError> {
        let c = self.contact;
        let y_b = *solver.y();
        let e_b = c
            .eval(&y_b, self.sliding)
            .ok_or(SolveError::StepSizeUnderflow { t: solver.t() })?;
        let ends = e_b.end <= 0.0 && e_b.rate < 0.0;
        let switches = e_b.mode < 0.0;
        if !ends && !switches {
            return Ok(None);
        }
        let dense = solver.dense().map_err(failure)?;
        let (x_a, y_a) = solver.last_start();
        let y_a = *y_a;
        let x_b = solver.t();
        let e_a = c.eval(&y_a, self.sliding);
        let at = |x: f64| c.eval(&dense.eval(x), self.sliding);
        let root = |g: &dyn Fn(&Eval) -> f64, g_a: f64| {
            let value = |x: f64| at(x).map_or(-1.0, |e| g(&e));
            let mut from = (x_a, g_a);
            let mut to = (x_b, g(&e_b));
            if g_a <= 0.0 {
                // At the start of a stretch the event is zero: bracket its crossing by
                // samples of the step, or switch right there if it never rises.
                let xs: Vec<f64> = (1..SAMPLES)
                    .map(|i| x_a + (x_b - x_a) * i as f64 / SAMPLES as f64)
                    .collect();
                let Some(first) = xs.iter().position(|&x| value(x) > 0.0) else {
                    return x_a;
                };
                from = (xs[first], value(xs[first]));
                for &x in &xs[first + 1..] {
                    let g_x = value(x);
                    if g_x <= 0.0 {
                        to = (x, g_x);
                        break;
                    }
                    from = (x, g_x);
                }
            }
            illinois(value, from, to)
        };
        let x_end = ends.then(|| root(&|e: &Eval| e.end, e_a.as_ref().map_or(1.0, |e| e.end)));
        let x_switch =
            switches.then(|| root(&|e: &Eval| e.mode, e_a.as_ref().map_or(1.0, |e| e.mode)));
        Ok(Some(match (x_end, x_switch) {
            (Some(x_e), Some(x_s)) if x_s < x_e => Found::Switch(x_s, dense.eval(x_s)),
            (Some(x_e), _) => Found::End(dense.eval(x_e)),
            (None, Some(x_s)) => Found::Switch(x_s, dense.eval(x_s)),
            (None, None) => unreachable!("an event was found"),
        }))
    }
}

fn vec(y: &[f64; N], at: usize) -> [f64; 3] {
    [y[at], y[at + 1], y[at + 2]]
}

fn put(y: &mut [f64; N], at: usize, v: [f64; 3]) {
    y[at..at + 3].copy_from_slice(&v);
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
