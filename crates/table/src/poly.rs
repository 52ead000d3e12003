//! Polynomials of bounded total degree in up to three variables on [−1, 1]³: their
//! term sets, the change from the Chebyshev basis (as stored in a file) to the monomial
//! basis (as evaluated), and a nested Horner evaluation of the four quantities at once.
//!
//! A term x^i y^j z^k (or T_i(x)T_j(y)T_k(z)) belongs to the set of total degree n with
//! per-axis limits d when i + j + k ≤ n and i ≤ d₀, j ≤ d₁, k ≤ d₂ (a limit of 0
//! collapses an axis, for the two-dimensional limit slices). Terms are ordered with i
//! outermost and k innermost, each ascending.

/// Number of stored quantities per point (the four logs of the MoR).
pub const NQ: usize = 4;

/// A term's coefficients of the four quantities, in float64 or float32.
pub trait Coef: Copy {
    fn wide(&self) -> [f64; NQ];
}

impl Coef for [f64; NQ] {
    #[inline(always)]
    fn wide(&self) -> [f64; NQ] {
        *self
    }
}

impl Coef for [f32; NQ] {
    #[inline(always)]
    fn wide(&self) -> [f64; NQ] {
        self.map(f64::from)
    }
}

/// The term set of total degree `degree` with per-axis limits `max`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Terms {
    pub degree: usize,
    pub max: [usize; 3],
    /// The exponents, in storage order.
    pub powers: Vec<[usize; 3]>,
    /// For each (i, j) run of the storage order: (i, j, number of k terms).
    runs: Vec<(usize, usize, usize)>,
    /// Position of term (i, j, k) at (i·(n+1) + j)·(n+1) + k (usize::MAX if absent).
    slot: Vec<usize>,
}

impl Terms {
    pub fn new(degree: usize, max: [usize; 3]) -> Self {
        let mut powers = Vec::new();
        let mut runs = Vec::new();
        for i in 0..=max[0].min(degree) {
            for j in 0..=max[1].min(degree - i) {
                let nk = max[2].min(degree - i - j) + 1;
                runs.push((i, j, nk));
                powers.extend((0..nk).map(|k| [i, j, k]));
            }
        }
        let m = degree + 1;
        let mut slot = vec![usize::MAX; m * m * m];
        for (k, p) in powers.iter().enumerate() {
            slot[(p[0] * m + p[1]) * m + p[2]] = k;
        }
        Self {
            degree,
            max,
            powers,
            runs,
            slot,
        }
    }

    pub fn len(&self) -> usize {
        self.powers.len()
    }

    pub fn is_empty(&self) -> bool {
        self.powers.is_empty()
    }

    /// Whether term `idx` is of total degree ≤ 1: a lookup evaluates these in float64
    /// monomials, the others (small, smooth residuals of the patch's linear part) in
    /// float32 ones.
    pub fn is_low(&self, idx: usize) -> bool {
        self.powers[idx].iter().sum::<usize>() <= 1
    }

    /// Number of terms of total degree ≤ 1.
    pub fn low_count(&self) -> usize {
        (0..self.len()).filter(|&k| self.is_low(k)).count()
    }

    /// Position of the term with exponents `p`, if it belongs to the set.
    pub fn index(&self, p: [usize; 3]) -> Option<usize> {
        let m = self.degree + 1;
        if p.iter().any(|&e| e >= m) {
            return None;
        }
        Some(self.slot[(p[0] * m + p[1]) * m + p[2]]).filter(|&k| k != usize::MAX)
    }

    /// Converts Chebyshev coefficients (in storage order) to monomial ones. The set is
    /// closed under lowering an exponent, and T_n has only powers up to n, so the
    /// monomial form uses the same terms.
    pub fn chebyshev_to_monomial(&self, cheb: &[[f64; NQ]]) -> Vec<[f64; NQ]> {
        let n = self.degree;
        let t = chebyshev_power_matrix(n);
        let mut out = vec![[0.0; NQ]; self.len()];
        for (c, p) in cheb.iter().zip(&self.powers) {
            for i in 0..=p[0] {
                let wi = t[p[0]][i];
                if wi == 0.0 {
                    continue;
                }
                for j in 0..=p[1] {
                    let wj = wi * t[p[1]][j];
                    if wj == 0.0 {
                        continue;
                    }
                    for k in 0..=p[2] {
                        let w = wj * t[p[2]][k];
                        if w == 0.0 {
                            continue;
                        }
                        let slot = &mut out[self.index([i, j, k]).expect("closed set")];
                        for q in 0..NQ {
                            slot[q] += w * c[q];
                        }
                    }
                }
            }
        }
        out
    }

    /// Σ c·x^i y^j z^k at t = (x, y, z).
    ///
    /// The usual shapes run through nested Horner with loop bounds known at compile
    /// time; other sets of up to [`FAST_TERMS`] terms form the monomials first and sum
    /// them in four independent accumulators; larger ones use the general Horner.
    #[inline(always)]
    pub fn eval<K: Coef>(&self, coefs: &[K], t: [f64; 3]) -> [f64; NQ] {
        macro_rules! fixed {
            ($($n:literal),*) => {
                match (self.degree, self.max) {
                    $(
                        ($n, [$n, $n, $n]) => return eval_fixed::<K, $n, $n, $n, $n>(coefs, t),
                        ($n, [$n, $n, 0]) => return eval_fixed::<K, $n, $n, $n, 0>(coefs, t),
                        ($n, [0, $n, $n]) => return eval_fixed::<K, $n, 0, $n, $n>(coefs, t),
                        ($n, [0, $n, 0]) => return eval_fixed::<K, $n, 0, $n, 0>(coefs, t),
                    )*
                    _ => {}
                }
            };
        }
        match (self.degree, self.max) {
            (7, [7, 7, 7]) => return crate::straight::eval7_xyz(coefs, t),
            (7, [7, 7, 0]) => return crate::straight::eval7_xy(coefs, t),
            (7, [0, 7, 7]) => return crate::straight::eval7_yz(coefs, t),
            (7, [0, 7, 0]) => return crate::straight::eval7_y(coefs, t),
            (10, [10, 10, 10]) => return crate::straight::eval10_xyz(coefs, t),
            (10, [10, 10, 0]) => return crate::straight::eval10_xy(coefs, t),
            (10, [0, 10, 10]) => return crate::straight::eval10_yz(coefs, t),
            (10, [0, 10, 0]) => return crate::straight::eval10_y(coefs, t),
            _ => {}
        }
        fixed!(5, 6, 8);
        let nt = self.len();
        if nt > FAST_TERMS || self.degree > MAX_DEGREE {
            return horner_runs(&self.runs, coefs, t);
        }
        let coefs = &coefs[..nt];
        let n = self.degree;
        let mut pw = [[1.0f64; MAX_DEGREE + 1]; 3];
        for (axis, p) in pw.iter_mut().enumerate() {
            for e in 1..=n {
                p[e] = p[e - 1] * t[axis];
            }
        }
        let mut m = [0.0f64; FAST_TERMS];
        let mut idx = 0;
        for &(i, j, nk) in &self.runs {
            let xy = pw[0][i] * pw[1][j];
            for k in 0..nk {
                m[idx + k] = xy * pw[2][k];
            }
            idx += nk;
        }
        let mut acc = [[0.0f64; NQ]; 4];
        let full = nt / 4 * 4;
        for (cs, ms) in coefs[..full].chunks_exact(4).zip(m[..full].chunks_exact(4)) {
            for l in 0..4 {
                let c = cs[l].wide();
                for q in 0..NQ {
                    acc[l][q] += c[q] * ms[l];
                }
            }
        }
        for (l, (c, w)) in coefs[full..].iter().zip(&m[full..nt]).enumerate() {
            let c = c.wide();
            for q in 0..NQ {
                acc[l][q] += c[q] * w;
            }
        }
        std::array::from_fn(|q| (acc[0][q] + acc[1][q]) + (acc[2][q] + acc[3][q]))
    }

    /// The same polynomial by nested Horner (k, then j, then i): a second route for
    /// the tests and for term sets beyond [`FAST_TERMS`].
    pub fn horner<K: Coef>(&self, coefs: &[K], t: [f64; 3]) -> [f64; NQ] {
        horner_runs(&self.runs, coefs, t)
    }
}

/// Nested Horner for the set (N, [A, B, C]): every loop bound is known at compile
/// time.
#[inline(always)]
fn eval_fixed<K: Coef, const N: usize, const A: usize, const B: usize, const C: usize>(
    coefs: &[K],
    t: [f64; 3],
) -> [f64; NQ] {
    let [x, y, z] = t;
    let imax = if A < N { A } else { N };
    let mut p = [0.0; NQ];
    let mut offset = count_terms::<N, A, B, C>();
    let coefs = &coefs[..offset];
    let mut i = imax + 1;
    while i > 0 {
        i -= 1;
        let jmax = if B < N - i { B } else { N - i };
        let mut q = [0.0; NQ];
        let mut j = jmax + 1;
        while j > 0 {
            j -= 1;
            let nk = (if C < N - i - j { C } else { N - i - j }) + 1;
            offset -= nk;
            let line = &coefs[offset..offset + nk];
            let mut r = line[nk - 1].wide();
            let mut k = nk - 1;
            while k > 0 {
                k -= 1;
                r = fmadd(r, z, &line[k]);
            }
            q = fmadd(q, y, &r);
        }
        p = fmadd(p, x, &q);
    }
    p
}

/// Number of terms of the set (N, [A, B, C]).
const fn count_terms<const N: usize, const A: usize, const B: usize, const C: usize>() -> usize {
    let mut n = 0;
    let mut i = 0;
    while i <= A && i <= N {
        let mut j = 0;
        while j <= B && j <= N - i {
            n += (if C < N - i - j { C } else { N - i - j }) + 1;
            j += 1;
        }
        i += 1;
    }
    n
}

/// Largest term set evaluated by [`Terms::eval`]'s fast path (total degree 9 in three
/// variables).
pub const FAST_TERMS: usize = 220;
const MAX_DEGREE: usize = 16;

/// Coefficients of T_n(x) = Σ_m a[n][m] x^m for n ≤ `n_max`.
fn chebyshev_power_matrix(n_max: usize) -> Vec<Vec<f64>> {
    let mut a = vec![vec![0.0; n_max + 1]; n_max + 1];
    a[0][0] = 1.0;
    if n_max >= 1 {
        a[1][1] = 1.0;
    }
    for n in 2..=n_max {
        for m in 0..=n {
            let up = if m > 0 { 2.0 * a[n - 1][m - 1] } else { 0.0 };
            a[n][m] = up - a[n - 2][m];
        }
    }
    a
}

#[inline(always)]
fn fmadd<K: Coef>(acc: [f64; NQ], x: f64, c: &K) -> [f64; NQ] {
    let c = c.wide();
    [
        acc[0] * x + c[0],
        acc[1] * x + c[1],
        acc[2] * x + c[2],
        acc[3] * x + c[3],
    ]
}

#[inline(always)]
fn horner_runs<K: Coef>(runs: &[(usize, usize, usize)], coefs: &[K], t: [f64; 3]) -> [f64; NQ] {
    let [x, y, z] = t;
    // Walk the runs backwards: for fixed i the j-polynomial is built by Horner in y from
    // its highest j down, each j's k-polynomial by Horner in z.
    let mut end = coefs.len();
    let mut p = [0.0; NQ];
    let mut q = [0.0; NQ];
    let mut current_i = usize::MAX;
    for &(i, _, nk) in runs.iter().rev() {
        if i != current_i {
            if current_i != usize::MAX {
                p = fmadd(p, x, &q);
                q = [0.0; NQ];
            }
            current_i = i;
        }
        let start = end - nk;
        let line = &coefs[start..end];
        let mut r = line[nk - 1].wide();
        for c in line[..nk - 1].iter().rev() {
            r = fmadd(r, z, c);
        }
        q = fmadd(q, y, &r);
        end = start;
    }
    // The i groups are consecutive, so each step of the outer Horner is one x.
    fmadd(p, x, &q)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chebyshev_polynomials_expand_correctly() {
        let a = chebyshev_power_matrix(5);
        // T_4 = 8x⁴ − 8x² + 1, T_5 = 16x⁵ − 20x³ + 5x.
        assert_eq!(a[4], vec![1.0, 0.0, -8.0, 0.0, 8.0, 0.0]);
        assert_eq!(a[5], vec![0.0, 5.0, 0.0, -20.0, 0.0, 16.0]);
    }

    #[test]
    fn unrolled_degrees_seven_and_ten_agree_with_the_general_horner() {
        for (n, max) in [7, 10]
            .into_iter()
            .flat_map(|n| [[n, n, n], [n, n, 0], [0, n, n], [0, n, 0]].map(|m| (n, m)))
        {
            let terms = Terms::new(n, max);
            let c: Vec<[f32; NQ]> = (0..terms.len())
                .map(|k| std::array::from_fn(|q| ((k * 13 + q * 5) % 17) as f32 / 17.0 - 0.45))
                .collect();
            for t in [[0.31, -0.77, 0.52], [-1.0, 1.0, 0.999], [0.0, 0.5, -0.25]] {
                let t = std::array::from_fn(|k| if max[k] > 0 { t[k] } else { 0.0 });
                let (got, want) = (terms.eval(&c, t), terms.horner(&c, t));
                for q in 0..NQ {
                    assert!((got[q] - want[q]).abs() < 1e-14, "{max:?} {t:?}");
                }
            }
        }
    }

    #[test]
    fn horner_matches_a_direct_sum_of_chebyshev_products() {
        for (degree, max) in [
            (5, [5, 5, 5]),
            (4, [0, 4, 4]),
            (3, [3, 3, 0]),
            (6, [0, 6, 0]),
            (7, [7, 7, 7]),
            (7, [0, 7, 7]),
            (10, [10, 10, 10]),
            (10, [10, 10, 0]),
        ] {
            let terms = Terms::new(degree, max);
            let cheb: Vec<[f64; NQ]> = (0..terms.len())
                .map(|k| std::array::from_fn(|q| ((k * 7 + q * 3) % 11) as f64 / 11.0 - 0.4))
                .collect();
            let mono = terms.chebyshev_to_monomial(&cheb);
            let t = [0.31, -0.77, 0.52];
            let cheb_t = |n: usize, x: f64| (n as f64 * x.acos()).cos();
            let mut direct = [0.0; NQ];
            for (c, p) in cheb.iter().zip(&terms.powers) {
                let w = cheb_t(p[0], t[0]) * cheb_t(p[1], t[1]) * cheb_t(p[2], t[2]);
                for q in 0..NQ {
                    direct[q] += w * c[q];
                }
            }
            for got in [terms.horner(&mono, t), terms.eval(&mono, t)] {
                for q in 0..NQ {
                    assert!((got[q] - direct[q]).abs() < 1e-12, "{degree} {max:?}");
                }
            }
        }
    }
}
