//! Local tensor-product Lagrange interpolation on uniform or stretched axes.
//!
//! Along each axis the value at x is the Lagrange polynomial through the `order`
//! nodes nearest to x (order 4: cubic, 6: quintic, 8: septic), centred where possible
//! and shifted inwards at the ends of the axis, so every stencil lies inside the grid:
//! this is interpolation only, never extrapolation. The interpolation error of one
//! axis is at most h^p·max|f^(p)|·max|Π(t−k)|/p! (p = order, h = step).
//!
//! A stretched axis is uniform in w(x) = (x − min) + λ·ln(1 + (x − min)/d) instead of
//! in x, so its nodes crowd towards `min` (spacing smaller by d/(d + λ) there, the
//! uniform spacing far away). The interpolation is the Lagrange polynomial in w. This
//! serves a function with a singularity at a distance of about d below `min` (the
//! pass-through of strongly penetrating impacts below the b axis of a table).

/// Largest supported stencil (points per axis).
pub const MAX_ORDER: usize = 8;

/// Node crowding towards the low end of an axis: w(x) = (x − min) + amount·ln(1 + (x − min)/knee).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stretch {
    /// λ ≥ 0; 0 means a uniform axis.
    pub amount: f64,
    /// d > 0, the distance over which the nodes crowd.
    pub knee: f64,
}

impl Stretch {
    /// No stretching: a uniform axis.
    pub const NONE: Self = Self {
        amount: 0.0,
        knee: 1.0,
    };

    /// w(y) for y = x − min ≥ 0.
    #[inline]
    pub fn w(&self, y: f64) -> f64 {
        if self.amount == 0.0 {
            y
        } else {
            y + self.amount * (y / self.knee).ln_1p()
        }
    }

    /// The inverse: y ≥ 0 with w(y) = w (Newton; w is increasing and concave).
    pub fn y(&self, w: f64) -> f64 {
        if self.amount == 0.0 {
            return w;
        }
        // Start at y = w ≥ the root; Newton steps from the right of a concave
        // increasing function decrease monotonically onto the root.
        let mut y = w;
        for _ in 0..100 {
            let f = self.w(y) - w;
            let step = f / (1.0 + self.amount / (self.knee + y));
            let next = (y - step).max(0.0);
            if next == y || step.abs() <= 1e-16 * (1.0 + y) {
                return next;
            }
            y = next;
        }
        y
    }
}

/// An axis with `n` nodes from `min` to `max`, uniform in w(x) (see [`Stretch`]),
/// interpolated with `order` points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub n: usize,
    pub order: usize,
    pub stretch: Stretch,
    /// (n − 1)/w(max − min): grid units per unit of w.
    scale: f64,
}

impl Axis {
    /// A uniform axis.
    pub fn uniform(min: f64, max: f64, n: usize, order: usize) -> Self {
        Self::new(min, max, n, order, Stretch::NONE)
    }

    /// An axis uniform in w(x) of `stretch`.
    pub fn new(min: f64, max: f64, n: usize, order: usize, stretch: Stretch) -> Self {
        let scale = (n as f64 - 1.0) / stretch.w(max - min);
        Self {
            min,
            max,
            n,
            order,
            stretch,
            scale,
        }
    }

    /// The same axis interpolated with `order` points.
    pub fn with_order(&self, order: usize) -> Self {
        Self { order, ..*self }
    }

    /// Node spacing in w (the spacing in x for a uniform axis).
    pub fn step(&self) -> f64 {
        1.0 / self.scale
    }

    /// Coordinate of node `i` (exactly `min` and `max` at the ends).
    pub fn node(&self, i: usize) -> f64 {
        if i + 1 == self.n {
            self.max
        } else if self.stretch.amount == 0.0 {
            self.min + i as f64 * self.step()
        } else {
            self.min + self.stretch.y(i as f64 * self.step())
        }
    }

    /// Position of x in grid units (node i at i).
    #[inline]
    pub fn grid_position(&self, x: f64) -> f64 {
        self.stretch.w(x - self.min) * self.scale
    }

    /// Whether the axis is usable: n ≥ order ≥ 2, order even and ≤ [`MAX_ORDER`],
    /// finite min < max, a finite stretch ≥ 0 with a positive knee.
    pub fn check(&self) -> Result<(), String> {
        if !(self.min.is_finite() && self.max.is_finite() && self.min < self.max) {
            return Err(format!(
                "axis range [{}, {}] is empty or not finite",
                self.min, self.max
            ));
        }
        let s = self.stretch;
        if !(s.amount.is_finite() && s.amount >= 0.0 && s.knee.is_finite() && s.knee > 0.0) {
            return Err(format!(
                "stretch [{}, {}] must be [amount >= 0, knee > 0], both finite",
                s.amount, s.knee
            ));
        }
        if self.order < 2 || self.order > MAX_ORDER || self.order % 2 != 0 {
            return Err(format!(
                "interpolation order {} must be one of 2, 4, 6, 8 (points per axis)",
                self.order
            ));
        }
        if self.n < self.order {
            return Err(format!(
                "an axis with {} nodes cannot carry {}-point interpolation; use at least {} nodes",
                self.n, self.order, self.order
            ));
        }
        Ok(())
    }

    /// The stencil at `x`, which must lie in [min, max].
    #[inline]
    pub fn stencil(&self, x: f64) -> Stencil {
        let p = self.order;
        let t = self.grid_position(x);
        // t ≥ 0 up to rounding, so truncation is the floor (and needs no libm call).
        let cell = (t as isize).clamp(0, self.n as isize - 2);
        let start = (cell - (p as isize / 2 - 1)).clamp(0, (self.n - p) as isize) as usize;
        let u = t - start as f64;
        let w = match p {
            4 => weights::<4>(u),
            6 => weights::<6>(u),
            8 => weights::<8>(u),
            _ => {
                let mut w = [0.0; MAX_ORDER];
                lagrange_weights(u, p, &mut w);
                w
            }
        };
        Stencil { start, len: p, w }
    }
}

/// Nodes `start..start+len` with weights `w[..len]`.
#[derive(Debug, Clone, Copy)]
pub struct Stencil {
    pub start: usize,
    pub len: usize,
    pub w: [f64; MAX_ORDER],
}

impl Stencil {
    /// The single node `i` with weight 1 (a fixed index).
    pub fn at(i: usize) -> Self {
        let mut w = [0.0; MAX_ORDER];
        w[0] = 1.0;
        Self {
            start: i,
            len: 1,
            w,
        }
    }
}

/// 1/Π_{k≠j}(j−k) = (−1)^{p−1−j}/(j!(p−1−j)!) for p points, row p.
const INV_DENOM: [[f64; MAX_ORDER]; MAX_ORDER + 1] = {
    const FACT: [f64; MAX_ORDER] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0, 5040.0];
    let mut t = [[0.0; MAX_ORDER]; MAX_ORDER + 1];
    let mut p = 1;
    while p <= MAX_ORDER {
        let mut j = 0;
        while j < p {
            let sign = if (p - 1 - j) % 2 == 0 { 1.0 } else { -1.0 };
            t[p][j] = sign / (FACT[j] * FACT[p - 1 - j]);
            j += 1;
        }
        p += 1;
    }
    t
};

/// Weights of the Lagrange polynomial through nodes 0..p at position `u`.
#[inline]
fn lagrange_weights(u: f64, p: usize, w: &mut [f64; MAX_ORDER]) {
    // w_j = Π_{k≠j}(u−k) / Π_{k≠j}(j−k), from prefix and suffix products.
    let mut prefix = [1.0; MAX_ORDER + 1];
    for k in 0..p {
        prefix[k + 1] = prefix[k] * (u - k as f64);
    }
    let mut suffix = 1.0;
    for j in (0..p).rev() {
        w[j] = prefix[j] * suffix * INV_DENOM[p][j];
        suffix *= u - j as f64;
    }
}

/// [`lagrange_weights`] for `P` points, unrolled (the same arithmetic).
#[inline(always)]
fn weights<const P: usize>(u: f64) -> [f64; MAX_ORDER] {
    let mut prefix = [1.0; MAX_ORDER + 1];
    for k in 0..P {
        prefix[k + 1] = prefix[k] * (u - k as f64);
    }
    let mut w = [0.0; MAX_ORDER];
    let mut suffix = 1.0;
    for j in (0..P).rev() {
        w[j] = prefix[j] * suffix * INV_DENOM[P][j];
        suffix *= u - j as f64;
    }
    w
}

/// Number of quantities stored per node.
pub const NQ: usize = 4;

/// Interpolates the `NQ` interleaved quantities of a C-order block `[d0][d1][d2][NQ]`.
///
/// The stencils must lie inside the block (as [`Axis::stencil`] and [`Stencil::at`]
/// guarantee). Common stencil shapes run through loops of fixed length that the
/// compiler unrolls and vectorises (the four quantities of a node are one contiguous
/// 32-byte run); the rest through a general loop with the same arithmetic.
#[inline]
pub fn interp3(data: &[f64], dims: [usize; 3], s: &[Stencil; 3]) -> [f64; NQ] {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX (checked just above).
        return unsafe { interp3_avx(data, dims, s) };
    }
    dispatch(data, dims, s)
}

/// [`dispatch`] compiled with 256-bit AVX registers: one node's four quantities are
/// one load and one multiply-add pair. Separate multiplies and adds (no FMA) keep the
/// results bitwise equal to the portable path.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn interp3_avx(data: &[f64], dims: [usize; 3], s: &[Stencil; 3]) -> [f64; NQ] {
    dispatch(data, dims, s)
}

#[inline(always)]
fn dispatch(data: &[f64], dims: [usize; 3], s: &[Stencil; 3]) -> [f64; NQ] {
    macro_rules! fixed {
        ($($a:literal $b:literal $c:literal),*) => {
            match (s[0].len, s[1].len, s[2].len) {
                $(($a, $b, $c) => block::<$a, $b, $c>(data, dims, s),)*
                _ => general(data, dims, s),
            }
        };
    }
    fixed!(4 4 4, 6 6 6, 8 8 8, 4 4 1, 6 6 1, 8 8 1, 1 4 4, 1 6 6, 1 8 8, 1 4 1, 1 6 1, 1 8 1)
}

/// [`interp3`] for stencils of `A`, `B` and `C` points.
#[inline(always)]
fn block<const A: usize, const B: usize, const C: usize>(
    data: &[f64],
    dims: [usize; 3],
    s: &[Stencil; 3],
) -> [f64; NQ] {
    let mut acc = [0.0; NQ];
    for i in 0..A {
        let row_i = (s[0].start + i) * dims[1];
        let mut acc_i = [0.0; NQ];
        for j in 0..B {
            let base = ((row_i + s[1].start + j) * dims[2] + s[2].start) * NQ;
            let line = &data[base..base + C * NQ];
            // Two interleaved sums shorten the chain of dependent additions.
            let (mut even, mut odd) = ([0.0; NQ], [0.0; NQ]);
            for k in (0..C).step_by(2) {
                let wk = s[2].w[k];
                for q in 0..NQ {
                    even[q] += wk * line[k * NQ + q];
                }
                if k + 1 < C {
                    let wk = s[2].w[k + 1];
                    for q in 0..NQ {
                        odd[q] += wk * line[(k + 1) * NQ + q];
                    }
                }
            }
            let part: [f64; NQ] = std::array::from_fn(|q| even[q] + odd[q]);
            let wj = s[1].w[j];
            for q in 0..NQ {
                acc_i[q] += wj * part[q];
            }
        }
        let wi = s[0].w[i];
        for q in 0..NQ {
            acc[q] += wi * acc_i[q];
        }
    }
    acc
}

/// [`interp3`] for any stencil lengths (same arithmetic as [`block`]).
#[inline(always)]
fn general(data: &[f64], dims: [usize; 3], s: &[Stencil; 3]) -> [f64; NQ] {
    let mut acc = [0.0; NQ];
    for i in 0..s[0].len {
        let row_i = (s[0].start + i) * dims[1];
        let mut acc_i = [0.0; NQ];
        for j in 0..s[1].len {
            let base = ((row_i + s[1].start + j) * dims[2] + s[2].start) * NQ;
            let line = &data[base..base + s[2].len * NQ];
            let (mut even, mut odd) = ([0.0; NQ], [0.0; NQ]);
            for (k, node) in line.chunks_exact(NQ).enumerate() {
                let wk = s[2].w[k];
                let sum = if k % 2 == 0 { &mut even } else { &mut odd };
                for q in 0..NQ {
                    sum[q] += wk * node[q];
                }
            }
            let part: [f64; NQ] = std::array::from_fn(|q| even[q] + odd[q]);
            let wj = s[1].w[j];
            for q in 0..NQ {
                acc_i[q] += wj * part[q];
            }
        }
        let wi = s[0].w[i];
        for q in 0..NQ {
            acc[q] += wi * acc_i[q];
        }
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_reproduce_polynomials_up_to_their_degree() {
        for p in [2, 4, 6, 8] {
            let mut w = [0.0; MAX_ORDER];
            let u = 1.37;
            lagrange_weights(u, p, &mut w);
            let unrolled = match p {
                4 => weights::<4>(u),
                6 => weights::<6>(u),
                8 => weights::<8>(u),
                _ => w,
            };
            assert_eq!(unrolled, w);
            for deg in 0..p {
                let got: f64 = (0..p).map(|j| w[j] * (j as f64).powi(deg as i32)).sum();
                let scale = (p as f64).powi(deg as i32);
                assert!(
                    (got - u.powi(deg as i32)).abs() < 1e-13 * scale,
                    "p={p} deg={deg}"
                );
            }
        }
    }

    #[test]
    fn the_stretch_map_inverts() {
        let s = Stretch {
            amount: 1.3,
            knee: 0.66,
        };
        for y in [0.0, 1e-9, 0.01, 0.66, 5.0, 13.0] {
            let back = s.y(s.w(y));
            assert!((back - y).abs() <= 1e-14 * (1.0 + y), "{y} -> {back}");
        }
        let ax = Axis::new(0.0, 12.9, 97, 6, s);
        assert!((ax.grid_position(ax.node(40)) - 40.0).abs() < 1e-12);
        assert!((ax.grid_position(12.9) - 96.0).abs() < 1e-12);
    }

    #[test]
    fn stencils_stay_inside_the_grid() {
        let ax = Axis::uniform(-1.0, 2.0, 7, 6);
        for x in [-1.0, -0.99, 0.5, 1.99, 2.0] {
            let s = ax.stencil(x);
            assert!(s.start + s.len <= ax.n);
        }
        assert_eq!(ax.node(6), 2.0);
    }
}
