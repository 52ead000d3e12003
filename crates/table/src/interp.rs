//! Local tensor-product Lagrange interpolation on uniform axes.
//!
//! Along each axis the value at x is the Lagrange polynomial through the `order`
//! nodes nearest to x (order 4: cubic, 6: quintic, 8: septic), centred where possible
//! and shifted inwards at the ends of the axis, so every stencil lies inside the grid:
//! this is interpolation only, never extrapolation. The interpolation error of one
//! axis is at most h^p·max|f^(p)|·max|Π(t−k)|/p! (p = order, h = step).

/// Largest supported stencil (points per axis).
pub const MAX_ORDER: usize = 8;

/// A uniform axis with `n` nodes from `min` to `max`, interpolated with `order` points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    pub n: usize,
    pub order: usize,
}

impl Axis {
    /// Node spacing.
    pub fn step(&self) -> f64 {
        (self.max - self.min) / (self.n - 1) as f64
    }

    /// Coordinate of node `i` (exactly `max` for the last node).
    pub fn node(&self, i: usize) -> f64 {
        if i + 1 == self.n {
            self.max
        } else {
            self.min + i as f64 * self.step()
        }
    }

    /// Whether the axis is usable: n ≥ order ≥ 2, order even and ≤ [`MAX_ORDER`],
    /// finite min < max.
    pub fn check(&self) -> Result<(), String> {
        if !(self.min.is_finite() && self.max.is_finite() && self.min < self.max) {
            return Err(format!(
                "axis range [{}, {}] is empty or not finite",
                self.min, self.max
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
        let t = (x - self.min) / self.step();
        let cell = (t.floor() as isize).clamp(0, self.n as isize - 2);
        let start = (cell - (p as isize / 2 - 1)).clamp(0, (self.n - p) as isize) as usize;
        let mut w = [0.0; MAX_ORDER];
        lagrange_weights(t - start as f64, p, &mut w);
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

/// Weights of the Lagrange polynomial through nodes 0..p at position `u`.
#[inline]
fn lagrange_weights(u: f64, p: usize, w: &mut [f64; MAX_ORDER]) {
    // w_j = Π_{k≠j}(u−k) / Π_{k≠j}(j−k), with Π_{k≠j}(j−k) = (−1)^{p−1−j} j! (p−1−j)!.
    const FACT: [f64; MAX_ORDER] = [1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0, 5040.0];
    let mut prefix = [1.0; MAX_ORDER + 1];
    for k in 0..p {
        prefix[k + 1] = prefix[k] * (u - k as f64);
    }
    let mut suffix = 1.0;
    for j in (0..p).rev() {
        let denom = FACT[j] * FACT[p - 1 - j];
        let sign = if (p - 1 - j) % 2 == 0 { 1.0 } else { -1.0 };
        w[j] = sign * prefix[j] * suffix / denom;
        suffix *= u - j as f64;
    }
}

/// Number of quantities stored per node.
pub const NQ: usize = 4;

/// Interpolates the `NQ` interleaved quantities of a C-order block `[d0][d1][d2][NQ]`.
#[inline]
pub fn interp3(data: &[f64], dims: [usize; 3], s: &[Stencil; 3]) -> [f64; NQ] {
    let mut acc = [0.0; NQ];
    for i in 0..s[0].len {
        let wi = s[0].w[i];
        let row_i = (s[0].start + i) * dims[1];
        for j in 0..s[1].len {
            let wij = wi * s[1].w[j];
            let base = ((row_i + s[1].start + j) * dims[2] + s[2].start) * NQ;
            let line = &data[base..base + s[2].len * NQ];
            let mut part = [0.0; NQ];
            for (k, node) in line.chunks_exact(NQ).enumerate() {
                let wk = s[2].w[k];
                for q in 0..NQ {
                    part[q] += wk * node[q];
                }
            }
            for q in 0..NQ {
                acc[q] += wij * part[q];
            }
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
    fn stencils_stay_inside_the_grid() {
        let ax = Axis {
            min: -1.0,
            max: 2.0,
            n: 7,
            order: 6,
        };
        for x in [-1.0, -0.99, 0.5, 1.99, 2.0] {
            let s = ax.stencil(x);
            assert!(s.start + s.len <= ax.n);
        }
        assert_eq!(ax.node(6), 2.0);
    }
}
