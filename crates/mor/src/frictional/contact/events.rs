//! Where a stretch of the contact ends: a stick–slip switch or the end of the contact,
//! located on the dense output of the step in which it lies.
//!
//! The right-hand side gives the switch function g at each stage of a step, and within
//! a step g is smooth on the step's scale. The second divided differences of g over the
//! stage nodes, times [`CURVATURE_SAFETY`], bound its curvature K, and so the least value
//! g can reach between two nodes: that of the parabola of curvature K through them. Only
//! where that reaches zero is the dense output built and the gap searched on it, split
//! at the parabola's lowest point until g is seen at or below zero (the crossing is then
//! bracketed) or the bound clears every part. So a switch there and back between two
//! stages (a short slide within a sticking step, a short stick while sliding) is found
//! at any tolerance. The end of the contact, F_n falling through zero, is bracketed by
//! the first stage that sees it. The event functions are probed on the components of
//! the dense output they need only, and a crossing is located to where the error its
//! place makes is far below the step's tolerance, not to round-off.

use super::{Contact, Eval, Found, Mode, S, Stretch, WALL};
use crate::SolveError;
use crate::dop853::{Dense, Dop853, NODES};
use crate::frictional::{failure, first_crossing};
use crate::roots::anderson_bjorck;
use std::cell::Cell;

/// The stages of a step recorded: 0 to 11 and the step's end, 12.
const SLOTS: usize = 13;

/// The stages whose switch function bounds it, in the order of their nodes after the
/// step's start (stage 1, an Euler step, errs too much; 4 and 7 lie close to 6 and 5).
const SWITCH_STAGES: [usize; 8] = [2, 3, 6, 5, 9, 8, 10, 12];

/// The widest gap between the switch nodes.
const WIDEST: f64 = NODES[9] - NODES[5];

/// The stages that bracket the end, in the order of their nodes (11 lies at the step's
/// end as 12 does, less accurately).
const END_STAGES: [usize; 11] = [1, 2, 3, 6, 4, 7, 5, 9, 8, 10, 12];

/// The curvature bound as a multiple of the largest second divided difference over the
/// nodes (those average the curvature over two gaps).
const CURVATURE_SAFETY: f64 = 2.0;

/// A crossing is located to where |g| is this part of the tolerance (or of its square
/// root, [`Probe::enough`]) times g's size over the step.
const ROOT_SHARE: f64 = 1e-1;

/// A stage's g is taken for g on the dense output where it is this part of g's size over
/// the step away from zero.
const SURE: f64 = 1e-2;

/// Bound on the parts a gap is split into while its bound reaches zero.
const SPLITS: usize = 8;

/// The probed state: the components the event functions read (v, Ω, the spring, ξ or
/// √ξ), in a state as long as a wall's (whose right-hand side leaves out the attitude
/// and P of a pair).
const READ: usize = S + 1;

/// The event functions at the stages of the current trial step.
pub(super) struct Samples {
    /// The slot of the next evaluation (past the last after a step's end).
    next: Cell<usize>,
    switch: [Cell<f64>; SLOTS],
    /// The end function where ξ falls, +∞ where it does not.
    end: [Cell<f64>; SLOTS],
    /// The switch function at the start of the current step where it continues the
    /// stretch (at the step before's end); `None` at a stretch's start, where it starts
    /// at zero.
    start: Cell<Option<f64>>,
}

impl Samples {
    pub(super) fn new() -> Self {
        Self {
            next: Cell::new(SLOTS),
            switch: std::array::from_fn(|_| Cell::new(f64::INFINITY)),
            end: std::array::from_fn(|_| Cell::new(f64::INFINITY)),
            start: Cell::new(None),
        }
    }

    pub(super) fn trial_started(&self) {
        self.next.set(1);
    }

    /// The switch and end functions at the next stage.
    #[inline(always)]
    pub(super) fn record(&self, switch: f64, end: f64) {
        let i = self.next.get();
        if let (Some(s), Some(e)) = (self.switch.get(i), self.end.get(i)) {
            s.set(switch);
            e.set(end);
        }
        self.next.set(i + 1);
    }

    /// The switch function at the [`SWITCH_NODES`] (NaN at the start of a stretch).
    #[inline(always)]
    fn switch_values(&self, start: Option<f64>) -> [f64; 9] {
        let mut values = [start.unwrap_or(f64::NAN); 9];
        for (value, &i) in values[1..].iter_mut().zip(&SWITCH_STAGES) {
            *value = self.switch[i].get();
        }
        values
    }
}

/// The nodes of the switch function in [0, 1]: the step's start and [`SWITCH_STAGES`].
const SWITCH_NODES: [f64; 9] = switch_nodes();

const fn switch_nodes() -> [f64; 9] {
    let mut s = [0.0; 9];
    let mut k = 0;
    while k < 8 {
        s[k + 1] = NODES[SWITCH_STAGES[k]];
        k += 1;
    }
    s
}

/// The second divided difference over the switch nodes k, k + 1, k + 2 as weights of
/// the values there.
const DIVIDED: [[f64; 3]; 7] = divided_differences();

const fn divided_differences() -> [[f64; 3]; 7] {
    let s = SWITCH_NODES;
    let mut out = [[0.0; 3]; 7];
    let mut k = 0;
    while k < 7 {
        let (s0, s1, s2) = (s[k], s[k + 1], s[k + 2]);
        let (left, right) = (2.0 / ((s2 - s0) * (s1 - s0)), 2.0 / ((s2 - s0) * (s2 - s1)));
        out[k] = [left, -left - right, right];
        k += 1;
    }
    out
}

/// The least value on [0, w] of the lowest function through g_l at 0 and g_r at w whose
/// curvature is at most k (the parabola of curvature k, or an end), and where it lies.
fn lowest(g_l: f64, g_r: f64, w: f64, k: f64) -> (f64, f64) {
    let d = g_r - g_l;
    let kw2 = k * w * w;
    if 2.0 * d.abs() >= kw2 {
        return if g_l <= g_r { (g_l, 0.0) } else { (g_r, w) };
    }
    let low = 0.5 * (g_l + g_r) - 0.125 * kw2 - d * d / (2.0 * kw2);
    (low, 0.5 * w - d * w / kw2)
}

/// The curvature bound of g over the step (units of s ∈ [0, 1]) and the first gap
/// (its left node) where g may reach zero, or `None` if none; the gaps from node `from`
/// on (1 at a stretch's start, whose value is not known).
#[inline(always)]
fn first_flagged(g: &[f64; 9], from: usize) -> (f64, Option<usize>) {
    let (mut k, mut least) = (0.0, g[8]);
    for j in from..7 {
        let w = DIVIDED[j];
        let dd = (w[0] * g[j] + w[1] * g[j + 1] + w[2] * g[j + 2]).abs();
        if dd > k {
            k = dd;
        }
        if g[j] < least {
            least = g[j];
        }
    }
    if g[7] < least {
        least = g[7];
    }
    let k = CURVATURE_SAFETY * k;
    // Clear at once where no gap (the widest, between stages 5 and 9) can reach zero.
    if least > 0.125 * k * WIDEST * WIDEST {
        return (k, None);
    }
    (k, (from..8).find(|&j| gap_flagged(g, j, k)))
}

/// Whether g may reach zero between switch nodes j and j + 1 with curvature at most `k`.
#[inline(always)]
fn gap_flagged(g: &[f64; 9], j: usize, k: f64) -> bool {
    let w = SWITCH_NODES[j + 1] - SWITCH_NODES[j];
    !(g[j] > 0.0 && lowest(g[j], g[j + 1], w, k).0 > 0.0)
}

/// The first crossing from above of g in [l, r] (g(l) > 0) where the lowest function of
/// curvature at most `k` through its ends reaches zero: the gap is split at that
/// function's lowest point until g is at or below zero at a split (the crossing then
/// located by the Anderson–Björck method to |g| ≤ `enough`), or the bound stays above
/// −`enough` on every part (`None`).
#[inline(always)]
fn first_dip(
    g: impl Fn(f64) -> f64,
    (l, g_l): (f64, f64),
    (r, g_r): (f64, f64),
    k: f64,
    enough: f64,
) -> Option<f64> {
    // Parts yet to clear, the leftmost last.
    let mut parts = [(0.0, 0.0, 0.0, 0.0); SPLITS];
    parts[0] = (l, g_l, r, g_r);
    let mut n = 1;
    while n > 0 {
        n -= 1;
        let (l, g_l, r, g_r) = parts[n];
        if g_r <= 0.0 {
            return Some(anderson_bjorck(&g, (l, g_l), (r, g_r), enough));
        }
        let w = r - l;
        let (low, at) = lowest(g_l, g_r, w, k);
        if low > -enough || n + 2 > SPLITS {
            continue;
        }
        let m = l + at.clamp(0.125 * w, 0.875 * w);
        let g_m = g(m);
        parts[n] = (m, g_m, r, g_r);
        parts[n + 1] = (l, g_l, m, g_m);
        n += 2;
    }
    None
}

impl<const M: usize> Stretch<'_, M> {
    /// The first event inside the last accepted step: the end of the contact or a switch
    /// (also one there and back within the step).
    #[inline(always)]
    pub(super) fn event_in_step(
        &self,
        solver: &mut Dop853<'_, Self, M>,
    ) -> Result<Option<Found<M>>, SolveError> {
        let (c, mode, samples) = (self.contact, self.mode.get(), &self.samples);
        let free = matches!(mode, Mode::Tail | Mode::Head);
        let start = samples.start.take();
        let values = samples.switch_values(start);
        let (k, flagged) = if free {
            (0.0, None)
        } else {
            first_flagged(&values, usize::from(start.is_none()))
        };
        let ends = END_STAGES.iter().any(|&i| samples.end[i].get() <= 0.0);
        let g_b = values[8];
        if !ends && flagged.is_none() {
            samples.start.set((!free).then_some(g_b));
            return Ok(None);
        }
        // The dense output's stages are evaluated last now: keep the step's end in `last`.
        let last = self.last.get();
        let dense = solver.dense().map_err(failure)?;
        self.last.set(last);
        let (x_a, x_b) = (solver.last_start().0, solver.t());
        let probe = Probe {
            contact: c,
            mode,
            dense: &dense,
        };
        let x_end = if ends {
            probe.end(samples, x_a, x_b)
        } else {
            None
        };
        let x_switch = match flagged {
            Some(first) => probe.switch(&values, first, k, (x_a, x_b)),
            None => None,
        };
        let found = match (x_end, x_switch) {
            (Some(x_e), Some(x_s)) if x_s < x_e => Some(Found::Switch(x_s, dense.eval(x_s))),
            (Some(x_e), _) => Some(Found::End(dense.eval(x_e))),
            (None, Some(x_s)) => Some(Found::Switch(x_s, dense.eval(x_s))),
            (None, None) => None,
        };
        if found.is_none() && !free {
            samples.start.set(Some(g_b));
        }
        Ok(found)
    }
}

/// The event functions on a step's dense output.
struct Probe<'a, const M: usize> {
    contact: &'a Contact,
    mode: Mode,
    dense: &'a Dense<M>,
}

impl<const M: usize> Probe<'_, M> {
    /// The right-hand side at x from the components it reads (inlined where one of its
    /// parts is used, the rest left out).
    #[inline(always)]
    fn at(&self, x: f64) -> Eval<WALL> {
        let mut y = [0.0; WALL];
        y[..READ].copy_from_slice(&self.dense.eval_leading::<READ>(x));
        self.contact.eval::<false, WALL>(&y, self.mode)
    }

    #[inline(always)]
    fn switch_at(&self, x: f64) -> f64 {
        self.at(x).mode
    }

    /// Only a fall of ξ ends the contact (F_n is zero at touch too).
    #[inline(always)]
    fn end_at(&self, x: f64) -> f64 {
        let e = self.at(x);
        if e.rate < 0.0 {
            e.end
        } else {
            e.end.abs().max(f64::MIN_POSITIVE)
        }
    }

    /// |g| at which a switch is located well enough, for g of size `size`: where the
    /// state is set onto the cap there (a switch to sliding), a change of |g|/k_t, that
    /// part of the tolerance; a switch to sticking changes the state by the square of
    /// the place's error (the force is continuous there), and the square root of that
    /// part will do. (The end's place moves the end state along its way, by the error.)
    fn enough(&self, size: f64) -> f64 {
        let c = self.contact;
        let tolerance = c.rtol.min(c.accuracy);
        let share = if self.mode == Mode::Stick {
            tolerance
        } else {
            tolerance.sqrt()
        };
        ROOT_SHARE * share * size
    }

    /// The end: bracketed by the first stage at which F_n ≤ 0 while ξ falls and the one
    /// before it, or else found by [`first_crossing`] over the step.
    #[inline(always)]
    fn end(&self, samples: &Samples, x_a: f64, x_b: f64) -> Option<f64> {
        let x_of = |i: usize| x_a + NODES[i] * (x_b - x_a);
        let first = END_STAGES
            .iter()
            .position(|&i| samples.end[i].get() <= 0.0)?;
        let size = END_STAGES
            .iter()
            .map(|&i| samples.end[i].get().abs())
            .filter(|g| g.is_finite())
            .fold(0.0, f64::max);
        let enough = ROOT_SHARE * self.contact.rtol.min(self.contact.accuracy) * size;
        let value = |x| self.end_at(x);
        let (l, g_l) = if first == 0 {
            (x_a, value(x_a))
        } else {
            let i = END_STAGES[first - 1];
            let l = x_of(i);
            (l, sure(samples.end[i].get(), size, || value(l)))
        };
        let i = END_STAGES[first];
        let r = x_of(i);
        let g_r = sure(samples.end[i].get(), size, || value(r));
        if g_l > 0.0 && g_r <= 0.0 {
            return Some(anderson_bjorck(value, (l, g_l), (r, g_r), enough));
        }
        first_crossing(value, (x_a, value(x_a)), (x_b, value(x_b)))
    }

    /// The first switch from the gap `first` of the switch nodes on, with the curvature
    /// bound `k` (units of the step), or else by [`first_crossing`] over the step where g
    /// is not above zero at a gap's start (a stretch that starts at zero and does not
    /// rise at once).
    #[inline(always)]
    fn switch(
        &self,
        values: &[f64; 9],
        first: usize,
        k: f64,
        (x_a, x_b): (f64, f64),
    ) -> Option<f64> {
        let h = x_b - x_a;
        let size = values
            .iter()
            .map(|g| g.abs())
            .filter(|g| !g.is_nan())
            .fold(0.0, f64::max);
        let enough = self.enough(size);
        let k_x = k / (h * h);
        let g = |x| self.switch_at(x);
        for j in first..8 {
            if !gap_flagged(values, j, k) {
                continue;
            }
            let (l, r) = (x_a + SWITCH_NODES[j] * h, x_a + SWITCH_NODES[j + 1] * h);
            let g_l = sure(values[j], size, || g(l));
            if g_l.is_nan() || g_l <= 0.0 {
                let g_a = if values[0].is_nan() {
                    g(x_a)
                } else {
                    values[0]
                };
                return first_crossing(g, (x_a, g_a), (x_b, values[8]));
            }
            let g_r = sure(values[j + 1], size, || g(r));
            if let Some(x) = first_dip(g, (l, g_l), (r, g_r), k_x, enough) {
                return Some(x);
            }
        }
        None
    }
}

/// g at a node: its sample where that lies far enough from zero for its sign to be sure
/// (a stage's g errs by about 10⁻⁵ of g's size over the step), else probed. Regula falsi
/// needs the signs at a bracket's ends; their values only steer it.
fn sure(sample: f64, size: f64, probe: impl FnOnce() -> f64) -> f64 {
    if sample.is_finite() && sample.abs() > SURE * size {
        sample
    } else {
        probe()
    }
}

#[cfg(test)]
mod tests;
