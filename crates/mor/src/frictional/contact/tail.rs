//! The end of a sliding contact: when the rest of it may be the tail, and the direction
//! the force keeps there (see the module documentation of [`super`]).

use super::{Contact, Mode, OMEGA, S, V};
use std::cell::Cell;

impl Contact {
    /// The direction the sliding force keeps where the spring's turning is fast: against
    /// g = k_t v_t + γ_t v̇_t (v̇_t without the tangential force), less the lag of a
    /// direction that turns after ĝ at the rate |g|/(µF_n): ĝ' µF_n/|g|.
    #[inline(always)]
    pub(super) fn tail_direction(
        &self,
        (s, rate): (f64, f64),
        f_n: f64,
        slip: [f64; 2],
        free_v: [f64; 3],
        free_o: [f64; 3],
    ) -> [f64; 2] {
        // The slip's rate without the tangential force.
        let free_slip = [free_v[1] - free_o[2], free_v[2] + free_o[1]];
        let g = [
            self.k_t * slip[0] + self.gamma_t * free_slip[0],
            self.k_t * slip[1] + self.gamma_t * free_slip[1],
        ];
        let floor = 1e-12 * self.k_t * self.speed;
        let g2 = g[0] * g[0] + g[1] * g[1] + floor * floor;
        // The force against ĝ turns the slip, and with it ĝ, at k_t (v̇_t · ĝ⊥)/|g|.
        let inv = 1.0 / g2.sqrt();
        let q = [-g[0] * inv, -g[1] * inv];
        let cap = self.mu * f_n;
        let slip_rate = [
            free_slip[0] + cap * q[0] * (self.inv_m_eff + self.a),
            free_slip[1] + cap * q[1] * (self.inv_m_eff + self.a),
        ];
        // ĝ' = P⊥ ġ/|g| with ġ ≈ k_t v̇_t. The lag δ follows δ' = |ĝ'| − λδ with
        // λ = |g|/(µF_n) growing as F_n falls: where it grows as fast as it relaxes,
        // δ = |ĝ'|/(λ + Ḟ_n/F_n) (exact for F_n, ĝ' and |g| linear in time).
        let along = slip_rate[0] * q[0] + slip_rate[1] * q[1];
        let perp = [slip_rate[0] - along * q[0], slip_rate[1] - along * q[1]];
        let jac = if self.hertz { s } else { 1.0 };
        let growth = self.normal_growth(s, rate, -free_v[0]);
        let f_n_rate = if jac > 0.0 { growth / jac } else { 0.0 };
        let size = g2.sqrt();
        let lag = self.k_t * cap / (size * (size + self.mu * f_n_rate).max(0.5 * size));
        let d = [q[0] + lag * perp[0], q[1] + lag * perp[1]];
        let size = (d[0] * d[0] + d[1] * d[1]).sqrt();
        // No slip, no friction (µ = 0 on a central impact): no direction.
        if size == 0.0 {
            return [0.0; 2];
        }
        [d[0] / size, d[1] / size]
    }

    /// Whether the rest of a sliding contact from `y` on may be the tail (the impulse
    /// left, at most 2µF_n·F_n/|Ḟ_n| while F_n falls, times the difference of the force's
    /// direction and the tail's, at this check and the last of the stretch, `last_off`,
    /// below `impulse`, the accuracy's share in N·s), and the estimated time left to the
    /// end, F_n/|Ḟ_n| in units of the independent variable (∞ while F_n grows).
    pub(super) fn slide_check<const M: usize>(
        &self,
        y: &[f64; M],
        impulse: f64,
        (f_n, growth): (f64, f64),
        last_off: &Cell<f64>,
    ) -> (bool, f64) {
        if !(f_n > 0.0 && growth < 0.0) {
            last_off.set(f64::INFINITY);
            return (false, f64::INFINITY);
        }
        let end_in = f_n / -growth;
        let jac = if self.hertz { y[S] } else { 1.0 };
        let left_time = end_in * jac;
        let left = 2.0 * self.mu * f_n * left_time;
        // Far from the end no direction is close enough to hand over.
        if left > 1e6 * impulse {
            last_off.set(f64::INFINITY);
            return (false, end_in);
        }
        let e = self.eval::<true, M>(y, Mode::Slide);
        let off = [
            e.direction[0] - e.tail_direction[0],
            e.direction[1] - e.tail_direction[1],
        ];
        // The force may cross the tail's direction by chance (where the lag is no
        // attractor, α < 2): the difference must be small at two checks in a row.
        let off = (off[0] * off[0] + off[1] * off[1]).sqrt();
        let bound = (2.0 * off.max(last_off.replace(off))).min(2.0);
        // The slip must keep its way to the end (the tail cannot stick again): the
        // impulse left changes it by at most left/m_t.
        let slip = (y[V + 1] - y[OMEGA + 2]).hypot(y[V + 2] + y[OMEGA + 1]);
        let keeps = slip > 4.0 * left / self.slip_mass() && e.mode > 0.0;
        (keeps && left * bound <= impulse, end_in)
    }
}
