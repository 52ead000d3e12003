//! The reference solver of the exact frictional contact: the equations of [`super`] in
//! the state (r − r_touch, v, ω₁, ω₂, ξ_t, ξ or √ξ, t), integrated by DOP853 to the
//! tolerance asked for, each stick or slip stretch to its end, through the singular end
//! of a sliding contact (the force direction turns ever faster as F_n → 0) by ever
//! smaller steps. Slow (about 10³ evaluations of the right-hand side per contact at
//! 10⁻¹¹) and plain: the yardstick of [`super::contact`].

use super::{
    FrictionalEnd, MAX_SWITCHES, Normal, Spinning, failure, first_crossing, sliding_direction,
};
use crate::dop853::{Dop853, System, Tolerances};
use crate::{SolveError, SolveStats, SolverOptions};
use emdstar_contact::vec3::{add, add_scaled, cross, dot, norm, scale, sub};
use emdstar_contact::{HistorySpring, PairLaw, lever_arm, slip_velocity};
use std::cell::Cell;

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
            low: Cell::new(f64::INFINITY),
            low_end: Cell::new(f64::INFINITY),
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
    /// The least switch function, and end function where ξ falls, at the stages of the
    /// current trial step (an event there and back within a step).
    low: Cell<f64>,
    low_end: Cell<f64>,
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
        let normal = Normal::of(law);
        let (hertz, elastic, viscous) = (normal.hertz, normal.elastic, normal.viscous);
        let overlap = normal.peak(m_eff, approach);
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
        self.law().force(s, rate)
    }

    /// dF_n/dt · dt/dx (finite at ξ = 0 for Hertz).
    fn normal_growth(&self, s: f64, rate: f64, rate_dot: f64) -> f64 {
        self.law().growth(s, rate, rate_dot)
    }

    fn law(&self) -> Normal {
        Normal {
            hertz: self.hertz,
            elastic: self.elastic,
            viscous: self.viscous,
        }
    }

    /// Whether the contact slides from its first instant ([`Normal::slides_from_touch`]).
    fn starts_sliding(&self, y: &[f64; N]) -> bool {
        let n = scale(1.0 / norm(self.touch), self.touch);
        let s = norm(self.slip(y, n));
        if s <= 1e-14 * self.speed {
            return false;
        }
        let spring = (self.mu, self.k_t, self.gamma_t);
        self.law().slides_from_touch(spring, s, -dot(vec(y, V), n))
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
        let e = self.contact.eval(y, self.sliding)?;
        self.low.set(self.low.get().min(e.mode));
        if e.rate < 0.0 {
            self.low_end.set(self.low_end.get().min(e.end));
        }
        Some(e.dy)
    }

    fn trial_started(&self) {
        self.low.set(f64::INFINITY);
        self.low_end.set(f64::INFINITY);
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
        let ends = (e_b.end <= 0.0 && e_b.rate < 0.0) || self.low_end.get() <= 0.0;
        let switches = e_b.mode < 0.0 || self.low.get() < 0.0;
        if !ends && !switches {
            return Ok(None);
        }
        let dense = solver.dense().map_err(failure)?;
        let (x_a, y_a) = solver.last_start();
        let y_a = *y_a;
        let x_b = solver.t();
        let e_a = c.eval(&y_a, self.sliding);
        let root = |g: &dyn Fn(&Eval) -> f64, g_a: f64| {
            let value = |x: f64| c.eval(&dense.eval(x), self.sliding).map_or(-1.0, |e| g(&e));
            first_crossing(value, (x_a, g_a), (x_b, g(&e_b)))
        };
        // Only a fall of ξ ends the contact (F_n is zero at touch too).
        let end = |e: &Eval| {
            if e.rate < 0.0 {
                e.end
            } else {
                e.end.abs().max(f64::MIN_POSITIVE)
            }
        };
        let x_end = if ends {
            root(&end, e_a.as_ref().map_or(1.0, end))
        } else {
            None
        };
        let x_switch = if switches {
            root(&|e: &Eval| e.mode, e_a.as_ref().map_or(1.0, |e| e.mode))
        } else {
            None
        };
        Ok(match (x_end, x_switch) {
            (Some(x_e), Some(x_s)) if x_s < x_e => Some(Found::Switch(x_s, dense.eval(x_s))),
            (Some(x_e), _) => Some(Found::End(dense.eval(x_e))),
            (None, Some(x_s)) => Some(Found::Switch(x_s, dense.eval(x_s))),
            (None, None) => None,
        })
    }
}

fn vec(y: &[f64; N], at: usize) -> [f64; 3] {
    [y[at], y[at + 1], y[at + 2]]
}

fn put(y: &mut [f64; N], at: usize, v: [f64; 3]) {
    y[at..at + 3].copy_from_slice(&v);
}
