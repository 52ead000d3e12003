//! The exact frictional contact, solved to the accuracy eMD* needs: the equations of
//! [`super`] for two spheres or a sphere at a flat wall, in the frame that the normal
//! carries along, integrated by DOP853 stretch by stretch (stick or slip) with the
//! switches and the end located on the dense output.
//!
//! # The carried frame
//! e₀ = n and e₁, e₂ transported parallel with it (ė_i = −(e_i·ṅ)n): the frame turns at
//! ω_f = n × ṅ = (0, −v₂, v₁)/|r| in its own components, |r| = l − ξ. In it, for the
//! relative velocity v, the spin sum Ω = R₁ω₁ + R₂ω₂ and P = ∫ n × F_t dt,
//! - v̇₀ = F_n/m + (v₁² + v₂²)/|r|, v̇_{1,2} = F_{t,1,2}/m − v₀v_{1,2}/|r| (m = m_eff);
//! - Ω̇ = −(a − bξ) n × F_t − ω_f × Ω with a = Σ R_i²/I_i, b = Σ R_i/(2I_i), n × F_t =
//!   (0, −F_{t,2}, F_{t,1}); Ṗ = n × F_t − ω_f × P;
//! - the slip is (0, v₁ − Ω₂, v₂ + Ω₁), and the spring, transported with the normal, is
//!   two fixed components that grow by the slip (plus the pull onto the cap, sliding);
//! - ξ̇ = −v₀; the frame's attitude q (a unit quaternion relative to the frame at touch)
//!   follows q̇ = q ⊗ (0, ω_f)/2 and feeds nothing back.
//!
//! So the right-hand side needs no square root but that of a sliding direction, and a
//! wall is the same equations with 1/|r| = 0 (the frame stays; the slots of q hold the
//! displacement along the wall instead). At the end, the frame turns the state back:
//! r = (l − ξ) e₀, and the spins follow from Ω and P, Q = ∫ ξ n × F_t dt = (ΔΩ + aP)/b,
//! I_i Δω_i = −R_i P + Q/2: for identical spheres P drops out (Δω_i = ΔΩ/2R), and at a
//! wall ω = Ω/R, so P is carried only for spheres that differ.
//!
//! # The end of a sliding contact
//! Sliding, the force keeps to the cap µF_n along the spring, whose direction lags the
//! slip's and turns after it at the rate k_t|v_t|/(µF_n) (γ_t = 0): as F_n → 0 that rate
//! grows without bound, a regular singular point at the end, which a solver that
//! follows the spring reaches only by ever smaller steps. Where what is left of the
//! contact can move the state by little, the force is set along the direction the
//! spring would keep (against k_t v_t + γ_t v̇_t, less its lag to first order) for the
//! rest of it: the error is at most the impulse left, ≤ 2µF_n·F_n/|Ḟ_n|, times the
//! difference of the two directions at the hand-over, which the hand-over keeps below
//! a part of the accuracy, read at the last two checks (where α = k_t|v_t|/(µ|Ḟ_n|) <
//! 2 the lagged direction is no attractor, and the force may cross it by chance).

use super::{HistorySpring, MAX_SWITCHES, failure};
use crate::dop853::{Dop853, System, Tolerances};
use crate::{SolveError, SolveStats};
use rhs::{Eval, sliding_direction};
use std::cell::Cell;

mod events;
mod rhs;
mod tail;

/// State: v (frame), Ω (frame), the spring (e₁, e₂), ξ or √ξ, t, the attitude q (pair)
/// or the displacement along the wall (wall, two slots), and P (frame). Only what is
/// needed is integrated ([`Contact::carried`]): the first [`WALL`] components at a wall,
/// [`SAME`] for a pair of identical spheres (whose spins change alike, by ΔΩ/2R: P drops
/// out) or without friction, all [`N`] else.
pub(super) const N: usize = 17;
pub(super) const V: usize = 0;
pub(super) const OMEGA: usize = 3;
const SPRING: usize = 6;
pub(super) const S: usize = 8;
pub(super) const T: usize = 9;
pub(super) const Q: usize = 10;
pub(super) const P: usize = 14;
const WALL: usize = Q + 2;
const SAME: usize = P;

/// Part of the accuracy the end of a sliding contact may spend: its bound (the impulse
/// left times the difference of the directions) is far above the error it makes, which
/// stays below the rest's at 10.
const TAIL_SHARE: f64 = 10.0;
/// The first trial step, in units of the time scale.
const FIRST_STEP: f64 = 0.05;
/// The safety factor of the step-size control.
const SAFETY: f64 = 0.8;
/// The head ends where the spring on the cap is this many times its absolute tolerance.
const RESOLVED: f64 = 1e3;
/// Sliding, the longest step as a part of the estimated time left to the end (F_n over
/// its rate): the spring's direction turns ever faster there.
const END_REACH: f64 = 0.6;

/// How the tangential force is found in a stretch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Mode {
    /// F_t = −k_t ξ_t − γ_t v_t.
    Stick,
    /// F_t = µF_n f̂, the spring kept on the cap.
    Slide,
    /// F_t = µF_n along the direction the spring would keep (the end of a sliding
    /// contact; µ = 0 throughout).
    Tail,
    /// As the tail, for one short step from touch where a contact slides from touch and
    /// F_n(0) = 0, while the spring on the cap, µF_n/k_t, is too short for its direction
    /// to be resolved (its direction turns at k_t|v_t|/(µF_n), without bound at touch).
    Head,
}

/// The partner of the sphere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Geometry {
    /// A second sphere; `l` = R₁ + R₂.
    Pair { l: f64 },
    /// A flat wall.
    Wall,
}

/// One contact, in SI units.
pub(super) struct Contact {
    pub geometry: Geometry,
    pub hertz: bool,
    /// Linear: k, γ. Hertz: ρ_el, (3/2)A.
    pub elastic: f64,
    pub viscous: f64,
    pub mu: f64,
    pub k_t: f64,
    pub gamma_t: f64,
    pub m_eff: f64,
    /// 1/m_eff and 1/k_t.
    pub inv_m_eff: f64,
    pub inv_k_t: f64,
    /// Σ R_i²/I_i and Σ R_i/(2I_i): Ω̇ = −(a − bξ) n × F_t.
    pub a: f64,
    pub b: f64,
    /// Whether the two spins must be told apart (P carried): a pair of spheres that differ
    /// in radius or mass, with friction.
    pub spins_apart: bool,
    /// Scales: speed, the estimated peak overlap, the contact time, the contact distance.
    pub speed: f64,
    pub overlap: f64,
    pub time: f64,
    pub length: f64,
    /// Per step: the relative tolerance, and the absolute one in units of each
    /// component's scale.
    pub rtol: f64,
    pub accuracy: f64,
    pub max_steps: usize,
}

/// What ends a stretch.
enum Found<const M: usize> {
    End([f64; M]),
    Switch(f64, [f64; M]),
    Tail(f64, [f64; M]),
    /// The head's spring is long enough to follow.
    Resolved(f64, [f64; M]),
}

/// One smooth stretch of the contact.
struct Stretch<'a, const M: usize> {
    contact: &'a Contact,
    mode: Cell<Mode>,
    /// The switch function and the end function (where ξ falls) at the stages of the
    /// current trial step: a switch there and back within a step, or an end that a long
    /// step passes (damped Hertz: F_n = ρw(w² + (3/2)Aξ̇) is positive again once w < 0),
    /// is found from them, not from the step's ends alone.
    samples: events::Samples,
    /// F_n and dF_n/dx at the last evaluation: at the end of an accepted step, those of
    /// its end (the first stage of the next, evaluated last).
    last: Cell<(f64, f64)>,
    /// The difference of the sliding force's direction from the tail's at the last check
    /// of this sliding stretch (∞ before one).
    last_off: Cell<f64>,
}

impl<const M: usize> System<M> for Stretch<'_, M> {
    #[inline(always)]
    fn rhs(&self, _x: f64, y: &[f64; M]) -> Option<[f64; M]> {
        let c = self.contact;
        // One branch per evaluation: each arm is compiled for its mode alone.
        let e = match self.mode.get() {
            Mode::Stick => c.eval::<false, M>(y, Mode::Stick),
            Mode::Slide => c.eval::<false, M>(y, Mode::Slide),
            Mode::Tail | Mode::Head => c.eval::<false, M>(y, Mode::Tail),
        };
        let end = if e.rate < 0.0 { e.end } else { f64::INFINITY };
        self.samples.record(e.mode, end);
        self.last.set((e.f_n, e.growth));
        Some(e.dy)
    }

    fn trial_started(&self) {
        self.samples.trial_started();
    }

    /// The steps run in [`Contact::integrate_avx2`], with FMA.
    const FUSED: bool = true;
    const LANES: bool = true;
}

impl Contact {
    /// Integrates from the touch state `y0` to the end of the contact: the state there,
    /// the stick–slip switches and the work done. With AVX2 and FMA where the CPU has
    /// them (the same operations in the same order, the Runge–Kutta sums fused
    /// multiply-adds either way: the same result to the bit).
    pub fn integrate(&self, y0: [f64; N]) -> Result<([f64; N], usize, SolveStats), SolveError> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
        {
            // SAFETY: the CPU has AVX2 and FMA.
            return unsafe { self.integrate_avx2(y0) };
        }
        self.integrate_portable(y0)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn integrate_avx2(
        &self,
        y0: [f64; N],
    ) -> Result<([f64; N], usize, SolveStats), SolveError> {
        self.integrate_portable(y0)
    }

    /// The integration over the components carried ([`Self::carried`]); the others stay
    /// zero.
    #[inline(always)]
    fn integrate_portable(
        &self,
        y0: [f64; N],
    ) -> Result<([f64; N], usize, SolveStats), SolveError> {
        fn widen<const M: usize>(
            (y, switches, stats): ([f64; M], usize, SolveStats),
        ) -> ([f64; N], usize, SolveStats) {
            let mut out = [0.0; N];
            out[..M].copy_from_slice(&y);
            (out, switches, stats)
        }
        match self.carried() {
            WALL => self.integrate_carried::<WALL>(narrow(&y0)).map(widen),
            SAME => self.integrate_carried::<SAME>(narrow(&y0)).map(widen),
            _ => self.integrate_carried::<N>(y0),
        }
    }

    /// How many components of the state are integrated.
    fn carried(&self) -> usize {
        match self.geometry {
            Geometry::Wall => WALL,
            Geometry::Pair { .. } if self.spins_apart => N,
            Geometry::Pair { .. } => SAME,
        }
    }

    #[inline(always)]
    fn integrate_carried<const M: usize>(
        &self,
        y0: [f64; M],
    ) -> Result<([f64; M], usize, SolveStats), SolveError> {
        let tail_impulse =
            TAIL_SHARE * self.accuracy.min(self.rtol) * self.slip_mass() * self.speed;
        // The spring's direction is resolved once its length on the cap is this many
        // times its absolute tolerance.
        let resolved = RESOLVED * self.tolerances::<M>().atol[SPRING] * self.k_t;
        let mut y = y0;
        let mut switches = 0;
        let mode = if self.mu == 0.0 {
            Mode::Tail
        } else if self.starts_sliding(&y0) {
            // The spring goes onto the cap; where the cap then outgrows the trial force
            // (the pull is negative: damped Hertz, F_n ~ √t), the contact sticks at once.
            y = self.onto_cap(&y);
            let (_, _, f_n) = self.normal(y[S], -y[V]);
            if self.eval::<true, M>(&y, Mode::Slide).mode < 0.0 {
                switches += 1;
                Mode::Stick
            } else if self.mu * f_n < resolved {
                Mode::Head
            } else {
                Mode::Slide
            }
        } else {
            Mode::Stick
        };
        let stretch = Stretch {
            contact: self,
            mode: Cell::new(mode),
            samples: events::Samples::new(),
            last: Cell::new((0.0, 0.0)),
            last_off: Cell::new(f64::INFINITY),
        };
        let mut step = FIRST_STEP * self.first_step();
        match mode {
            Mode::Slide => {
                let end_in = self
                    .slide_check(&y, tail_impulse, self.load(&y), &stretch.last_off)
                    .1;
                step = step.min(END_REACH * end_in);
            }
            // One step, to where the cap µF_n reaches `resolved`: F_n = k v_n t (linear)
            // or ρ(v_n σ/2)³ (elastic Hertz, w = v_n σ/2) from touch.
            Mode::Head => {
                let (cap, v_n) = (resolved / self.mu, -y0[V]);
                step = if self.hertz {
                    2.0 / v_n * (cap / self.elastic).cbrt()
                } else {
                    cap / (self.elastic * v_n)
                };
            }
            _ => {}
        }
        let mut solver = Dop853::new(&stretch, 0.0, y, self.tolerances(), step).map_err(failure)?;
        solver.set_safety(SAFETY);
        loop {
            if solver.counters.accepted >= self.max_steps {
                return Err(SolveError::TooManySteps(self.max_steps));
            }
            solver.step().map_err(failure)?;
            let mode = stretch.mode.get();
            let found = match stretch.event_in_step(&mut solver)? {
                Some(found) => found,
                None if mode == Mode::Head => {
                    // The spring onto the cap along the head's direction.
                    let y = solver.y();
                    let (_, _, f_n) = self.normal(y[S], -y[V]);
                    let e = self.eval::<true, M>(y, Mode::Head);
                    let mut y = *y;
                    let slip = [y[V + 1] - y[OMEGA + 2], y[V + 2] + y[OMEGA + 1]];
                    for k in 0..2 {
                        y[SPRING + k] = -(self.mu * f_n * e.direction[k] + self.gamma_t * slip[k])
                            * self.inv_k_t;
                    }
                    Found::Resolved(solver.t(), y)
                }
                None if mode == Mode::Slide => {
                    let (ready, end_in) = self.slide_check(
                        solver.y(),
                        tail_impulse,
                        stretch.last.get(),
                        &stretch.last_off,
                    );
                    if ready {
                        Found::Tail(solver.t(), *solver.y())
                    } else {
                        solver.limit_step(END_REACH * end_in);
                        continue;
                    }
                }
                None => continue,
            };
            let (x, mut y, mut next) = match found {
                Found::End(y_end) => {
                    let c = solver.counters;
                    let stats = SolveStats {
                        accepted_steps: c.accepted,
                        rejected_steps: c.rejected,
                        rhs_evaluations: c.evaluations,
                    };
                    return Ok((y_end, switches, stats));
                }
                Found::Switch(x_s, y_s) => {
                    stretch.last_off.set(f64::INFINITY);
                    switches += 1;
                    if switches > MAX_SWITCHES {
                        return Err(SolveError::TooManySteps(self.max_steps));
                    }
                    let next = if mode == Mode::Stick {
                        Mode::Slide
                    } else {
                        Mode::Stick
                    };
                    (x_s, y_s, next)
                }
                Found::Tail(x_t, y_t) => (x_t, y_t, Mode::Tail),
                Found::Resolved(x_r, y_r) => (x_r, y_r, Mode::Slide),
            };
            let mut step = solver.next_step();
            if next == Mode::Slide {
                if mode != Mode::Head {
                    y = self.onto_cap(&y);
                }
                let (ready, end_in) =
                    self.slide_check(&y, tail_impulse, self.load(&y), &stretch.last_off);
                if ready {
                    next = Mode::Tail;
                } else {
                    step = step.min(END_REACH * end_in);
                }
            }
            stretch.mode.set(next);
            solver.restart(x, y, step).map_err(failure)?;
        }
    }

    /// F_n and dF_n/dx at `y`, sliding.
    fn load<const M: usize>(&self, y: &[f64; M]) -> (f64, f64) {
        let e = self.eval::<false, M>(y, Mode::Slide);
        (e.f_n, e.growth)
    }

    /// 1/(1/m_eff + Σ R_i²/I_i): the mass the slip sees.
    fn slip_mass(&self) -> f64 {
        1.0 / (1.0 / self.m_eff + self.a)
    }

    fn first_step(&self) -> f64 {
        if self.hertz {
            // t ≈ σ²/4 near the start.
            2.0 * self.time.sqrt()
        } else {
            self.time
        }
    }

    fn tolerances<const M: usize>(&self) -> Tolerances<M> {
        let a = self.accuracy;
        let mut atol = [0.0; N];
        // The force whose action over the contact moves the slip by |v|.
        let force = self.slip_mass() * self.speed / self.time;
        for k in 0..3 {
            atol[V + k] = a * self.speed;
            atol[OMEGA + k] = a * self.speed;
            atol[P + k] = a * self.slip_mass() * self.speed;
        }
        for k in 0..2 {
            atol[SPRING + k] = a * force / self.k_t;
        }
        atol[S] = if self.hertz {
            a * self.overlap.sqrt()
        } else {
            a * self.overlap
        };
        atol[T] = a * self.time;
        let attitude = match self.geometry {
            Geometry::Pair { .. } => 1.0,
            Geometry::Wall => self.length,
        };
        for k in 0..4 {
            atol[Q + k] = a * attitude;
        }
        Tolerances {
            rtol: self.rtol,
            atol: narrow(&atol),
            atol_monitored: 0.0,
        }
    }

    /// Whether the contact slides from its first instant ([`super::Normal::slides_from_touch`]).
    fn starts_sliding<const M: usize>(&self, y: &[f64; M]) -> bool {
        let slip = (y[V + 1] - y[OMEGA + 2]).hypot(y[V + 2] + y[OMEGA + 1]);
        if slip <= 1e-14 * self.speed {
            return false;
        }
        let spring = (self.mu, self.k_t, self.gamma_t);
        self.law().slides_from_touch(spring, slip, -y[V])
    }

    /// The state with the spring set onto the cap, −k_t ξ_t − γ_t v_t = µF_n f̂ (as MD
    /// resets it), at the start of a sliding stretch.
    fn onto_cap<const M: usize>(&self, y: &[f64; M]) -> [f64; M] {
        let slip = [y[V + 1] - y[OMEGA + 2], y[V + 2] + y[OMEGA + 1]];
        let trial = [
            -self.k_t * y[SPRING] - self.gamma_t * slip[0],
            -self.k_t * y[SPRING + 1] - self.gamma_t * slip[1],
        ];
        let d = sliding_direction(trial, slip);
        let (_, _, f_n) = self.normal(y[S], -y[V]);
        let cap = self.mu * f_n.max(0.0);
        let mut out = *y;
        for k in 0..2 {
            out[SPRING + k] = -(cap * d[k] + self.gamma_t * slip[k]) / self.k_t;
        }
        out
    }
}

/// The first M components of `y`.
#[inline(always)]
fn narrow<const M: usize>(y: &[f64; N]) -> [f64; M] {
    std::array::from_fn(|k| y[k])
}

/// Checks the parameters shared by pairs and walls.
pub(super) fn check_spring(spring: &HistorySpring) -> Result<(), SolveError> {
    let ok = |x: f64| x.is_finite() && x >= 0.0;
    if !(ok(spring.friction) && ok(spring.damping)) {
        return Err(SolveError::InvalidParams(format!(
            "friction {} and tangential damping {} must be finite and not negative",
            spring.friction, spring.damping
        )));
    }
    if !(spring.stiffness > 0.0 && spring.stiffness.is_finite()) {
        return Err(SolveError::InvalidParams(
            "the exact frictional contact needs tangential_stiffness > 0".into(),
        ));
    }
    Ok(())
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests;
