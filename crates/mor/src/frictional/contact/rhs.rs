//! The right-hand side of the contact's equations in the carried frame (see [`super`]):
//! the normal law, the frame's turning, the tangential force by mode, and what the events
//! and the tail read at a state.

use super::{Contact, Geometry, Mode, OMEGA, P, Q, S, SPRING, T, V};
use crate::frictional::Normal;

/// The right-hand side at one state, with the switch function and, when probed, what
/// the events and the tail need.
pub(super) struct Eval<const M: usize> {
    pub(super) dy: [f64; M],
    /// F_n, unclipped (w for elastic Hertz): the end is its crossing from above.
    pub(super) end: f64,
    pub(super) rate: f64,
    /// Sticking: µF_n − |f|; sliding: the pull c·dt/dx. Crosses zero from above at a
    /// switch.
    pub(super) mode: f64,
    /// F_n; sliding, dF_n/dx (x: the independent variable); probed, sliding, the
    /// force's direction and the tail's.
    pub(super) f_n: f64,
    pub(super) growth: f64,
    pub(super) direction: [f64; 2],
    pub(super) tail_direction: [f64; 2],
}

impl Contact {
    /// ξ, dt/dx and the normal force from the overlap coordinate s.
    #[inline(always)]
    pub(super) fn normal(&self, s: f64, rate: f64) -> (f64, f64, f64) {
        self.law().force(s, rate)
    }

    /// dF_n/dt · dt/dx (finite at ξ = 0 for Hertz).
    #[inline(always)]
    pub(super) fn normal_growth(&self, s: f64, rate: f64, rate_dot: f64) -> f64 {
        self.law().growth(s, rate, rate_dot)
    }

    #[inline(always)]
    pub(super) fn law(&self) -> Normal {
        Normal {
            hertz: self.hertz,
            elastic: self.elastic,
            viscous: self.viscous,
        }
    }

    /// 1/|r|: the frame turns and the centrifugal force acts (zero at a wall).
    #[inline(always)]
    pub(super) fn inverse_distance(&self, xi: f64) -> f64 {
        match self.geometry {
            Geometry::Pair { l } => 1.0 / (l - xi),
            Geometry::Wall => 0.0,
        }
    }

    #[inline(always)]
    pub(super) fn eval<const PROBE: bool, const M: usize>(
        &self,
        y: &[f64; M],
        mode: Mode,
    ) -> Eval<M> {
        let [v0, v1, v2] = [y[V], y[V + 1], y[V + 2]];
        let [o0, o1, o2] = [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]];
        let rate = -v0;
        let (xi, jac, f_n) = self.normal(y[S], rate);
        let inv_r = self.inverse_distance(xi);
        let slip = [v1 - o2, v2 + o1];
        let spring = [y[SPRING], y[SPRING + 1]];
        let trial = [
            -self.k_t * spring[0] - self.gamma_t * slip[0],
            -self.k_t * spring[1] - self.gamma_t * slip[1],
        ];
        let cap = self.mu * f_n;
        // The frame's turning: ω_f = (0, −v₂, v₁)/|r|.
        let (w1, w2) = (-v2 * inv_r, v1 * inv_r);
        // Accelerations and spin rates without the tangential force, then its share.
        let free_v = [
            f_n * self.inv_m_eff + (v1 * v1 + v2 * v2) * inv_r,
            -v0 * v1 * inv_r,
            -v0 * v2 * inv_r,
        ];
        // −ω_f × Ω and −ω_f × P.
        let free_o = [
            (v2 * o2 + v1 * o1) * inv_r,
            -v1 * o0 * inv_r,
            -v2 * o0 * inv_r,
        ];
        let (direction, f_t) = match mode {
            Mode::Stick => ([0.0; 2], trial),
            Mode::Slide => {
                let d = sliding_direction(trial, slip);
                (d, [cap * d[0], cap * d[1]])
            }
            Mode::Tail | Mode::Head => {
                let d = self.tail_direction((y[S], rate), f_n, slip, free_v, free_o);
                (d, [cap * d[0], cap * d[1]])
            }
        };
        let arm = -(self.a - self.b * xi);
        let inv_m = self.inv_m_eff;
        let dv = [
            free_v[0],
            free_v[1] + f_t[0] * inv_m,
            free_v[2] + f_t[1] * inv_m,
        ];
        // n × F_t = (0, −F₂, F₁).
        let d_omega = [
            free_o[0],
            free_o[1] - arm * f_t[1],
            free_o[2] + arm * f_t[0],
        ];
        let mut dy = [0.0; M];
        for k in 0..3 {
            dy[V + k] = jac * dv[k];
            dy[OMEGA + k] = jac * d_omega[k];
        }
        if let Some(p) = y.get(P..P + 3) {
            // Ṗ = n × F_t − ω_f × P.
            let dp = [
                (v2 * p[2] + v1 * p[1]) * inv_r,
                -v1 * p[0] * inv_r - f_t[1],
                -v2 * p[0] * inv_r + f_t[0],
            ];
            for k in 0..3 {
                dy[P + k] = jac * dp[k];
            }
        }
        dy[S] = if self.hertz { 0.5 * rate } else { rate };
        dy[T] = jac;
        match self.geometry {
            Geometry::Pair { .. } => {
                // q̇ = q ⊗ (0, w⃗)/2 with w⃗ = (0, w₁, w₂): (−q⃗·w⃗, q_a w⃗ + q⃗ × w⃗)/2.
                if let (Some(&[qa, qb, qc, qd]), Some(dq)) = (y.get(Q..Q + 4), dy.get_mut(Q..Q + 4))
                {
                    let h = 0.5 * jac;
                    dq[0] = -h * (qc * w1 + qd * w2);
                    dq[1] = h * (qc * w2 - qd * w1);
                    dq[2] = h * (qa * w1 - qb * w2);
                    dq[3] = h * (qa * w2 + qb * w1);
                }
            }
            Geometry::Wall => {
                dy[Q] = jac * v1;
                dy[Q + 1] = jac * v2;
            }
        }
        let mut e = Eval {
            dy,
            end: if self.hertz && self.viscous == 0.0 {
                y[S]
            } else {
                f_n
            },
            rate,
            mode: 0.0,
            f_n,
            growth: 0.0,
            direction,
            tail_direction: [0.0; 2],
        };
        match mode {
            Mode::Stick => {
                e.dy[SPRING] = jac * slip[0];
                e.dy[SPRING + 1] = jac * slip[1];
                e.mode = cap - (trial[0] * trial[0] + trial[1] * trial[1]).sqrt();
            }
            Mode::Slide => {
                let growth = self.normal_growth(y[S], rate, -dv[0]);
                let mut pull = -self.k_t * jac * (direction[0] * slip[0] + direction[1] * slip[1])
                    - self.mu * growth;
                if self.gamma_t != 0.0 {
                    // The slip's rate: (v̇₁ − Ω̇₂, v̇₂ + Ω̇₁).
                    let slip_rate = [dv[1] - d_omega[2], dv[2] + d_omega[1]];
                    pull -= self.gamma_t
                        * jac
                        * (direction[0] * slip_rate[0] + direction[1] * slip_rate[1]);
                }
                pull *= self.inv_k_t;
                e.dy[SPRING] = jac * slip[0] + pull * direction[0];
                e.dy[SPRING + 1] = jac * slip[1] + pull * direction[1];
                e.mode = pull;
                e.growth = growth;
                if PROBE {
                    e.tail_direction = self.tail_direction((y[S], rate), f_n, slip, free_v, free_o);
                }
            }
            Mode::Tail | Mode::Head => {}
        }
        e
    }
}

/// The direction of the tangential force at the cap: that of the trial force
/// −k_t ξ_t − γ_t v_t, or against the slip where the trial force vanishes (zero
/// without slip).
#[inline(always)]
pub(super) fn sliding_direction(trial: [f64; 2], slip: [f64; 2]) -> [f64; 2] {
    let t = (trial[0] * trial[0] + trial[1] * trial[1]).sqrt();
    if t > 0.0 {
        let inv = 1.0 / t;
        return [trial[0] * inv, trial[1] * inv];
    }
    let s = (slip[0] * slip[0] + slip[1] * slip[1]).sqrt();
    if s > 0.0 {
        [-slip[0] / s, -slip[1] / s]
    } else {
        [0.0; 2]
    }
}
