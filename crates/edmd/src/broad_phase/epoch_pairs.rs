//! The epoch rebuild's pair tests: every candidate pair of the rebuild tested for a
//! collision before both horizons, with the earliest kept per particle (Bannerman et
//! al. 2014, Algorithm 1). Where the CPU has AVX the course test runs on four pairs at
//! once, bitwise as the portable test.

use super::epochs::Motion;
use crate::detect::{on_collision_course, sphere_sphere};
use crate::state::min_image_in;
use emdstar_contact::vec3::sub;

/// The rebuild's pair tests: each particle's motion and eMD\* partner, the earliest
/// pair kept for each so far, the epoch's start and the box's period (0 along closed
/// axes).
pub(super) struct PairTests<'a> {
    pub motion: &'a [Motion],
    pub partner: &'a [u32],
    pub best: &'a mut [(f64, u32)],
    pub t0: f64,
    pub period: [f64; 3],
}

impl PairTests<'_> {
    /// Tests the rebuild's candidate pairs for a collision before both horizons and
    /// keeps each particle's earliest (Bannerman et al. 2014, Algorithm 1:
    /// [`on_collision_course`] for the many pairs that miss, then [`sphere_sphere`]).
    /// Where the CPU has AVX, the course test runs on four pairs at once.
    pub fn run(&mut self, pairs: &[[u32; 2]]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU supports AVX (checked just above).
            return unsafe { self.run_avx(pairs) };
        }
        for &[i, j] in pairs {
            self.test(i as usize, j as usize);
        }
    }

    /// One pair of [`PairTests::run`].
    #[inline(always)]
    fn test(&mut self, i: usize, j: usize) {
        let (a, b) = (&self.motion[i], &self.motion[j]);
        let r = min_image_in(sub(a.pos, b.pos), self.period);
        let v = sub(a.vel, b.vel);
        let sigma = a.radius + b.radius;
        // The rare pair on course, then whether it shares an eMD* transient.
        let partner = self.partner;
        if !on_collision_course(r, v, sigma) || partner[i] == j as u32 && partner[j] == i as u32 {
            return;
        }
        let t = self.t0 + sphere_sphere(r, v, sigma);
        if t < a.horizon.min(b.horizon) {
            let best = &mut *self.best;
            if t < best[i].0 {
                best[i] = (t, j as u32);
            }
            if t < best[j].0 {
                best[j] = (t, i as u32);
            }
        }
    }

    /// [`PairTests::run`] with the course test on four pairs at once: each lane
    /// computes what [`min_image_in`], [`sub`] and [`on_collision_course`] compute, in
    /// the same order and without fused multiply-adds, so it passes exactly the pairs
    /// the portable test passes; those are then tested again and timed one by one, in
    /// their order.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn run_avx(&mut self, pairs: &[[u32; 2]]) {
        use std::arch::x86_64::*;
        let (motion, period) = (self.motion, self.period);
        let half = period.map(|l| _mm256_set1_pd(0.5 * l));
        let minus_half = period.map(|l| _mm256_set1_pd(-0.5 * l));
        let whole = period.map(|l| _mm256_set1_pd(l));
        let zero = _mm256_setzero_pd();
        let groups = pairs.chunks_exact(4);
        let rest = groups.remainder();
        for g in groups {
            let g: &[[u32; 2]; 4] = g.try_into().expect("a group of four");
            let rows = |k: usize, half_line: usize| {
                // SAFETY: a `Motion` is eight f64 (pos, radius, vel, horizon), 64-byte
                // aligned, and `motion[..]` checks the index.
                g.map(|p| unsafe {
                    _mm256_load_pd(
                        (&motion[p[k] as usize] as *const Motion as *const f64).add(half_line),
                    )
                })
            };
            let [ax, ay, az, ar] = transpose(rows(0, 0));
            let [au, av, aw, _] = transpose(rows(0, 4));
            let [bx, by, bz, br] = transpose(rows(1, 0));
            let [bu, bv, bw, _] = transpose(rows(1, 4));
            let image = |d: __m256d, k: usize| {
                let up = _mm256_and_pd(_mm256_cmp_pd::<_CMP_GT_OQ>(d, half[k]), whole[k]);
                let down = _mm256_and_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(d, minus_half[k]), whole[k]);
                _mm256_add_pd(_mm256_sub_pd(d, up), down)
            };
            let r = [
                image(_mm256_sub_pd(ax, bx), 0),
                image(_mm256_sub_pd(ay, by), 1),
                image(_mm256_sub_pd(az, bz), 2),
            ];
            let v = [
                _mm256_sub_pd(au, bu),
                _mm256_sub_pd(av, bv),
                _mm256_sub_pd(aw, bw),
            ];
            let sigma = _mm256_add_pd(ar, br);
            let dot = |a: [__m256d; 3], b: [__m256d; 3]| {
                let ab = _mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1]));
                _mm256_add_pd(ab, _mm256_mul_pd(a[2], b[2]))
            };
            let (b, r2, v2) = (dot(r, v), dot(r, r), dot(v, v));
            let gap = _mm256_sub_pd(r2, _mm256_mul_pd(sigma, sigma));
            let disc = _mm256_sub_pd(_mm256_mul_pd(v2, gap), _mm256_mul_pd(b, b));
            // `larger(b, disc)`: the maximum instruction returns its second operand unless
            // the first is greater, as `larger` does.
            let course = _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_max_pd(b, disc), zero);
            let mut pass = _mm256_movemask_pd(course);
            while pass != 0 {
                let [i, j] = g[pass.trailing_zeros() as usize];
                self.test(i as usize, j as usize);
                pass &= pass - 1;
            }
        }
        for &[i, j] in rest {
            self.test(i as usize, j as usize);
        }
    }
}

/// The columns of four rows of four: component k of every row in column k.
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx")]
fn transpose(rows: [std::arch::x86_64::__m256d; 4]) -> [std::arch::x86_64::__m256d; 4] {
    use std::arch::x86_64::*;
    let [a, b, c, d] = rows;
    let (ab_even, ab_odd) = (_mm256_unpacklo_pd(a, b), _mm256_unpackhi_pd(a, b));
    let (cd_even, cd_odd) = (_mm256_unpacklo_pd(c, d), _mm256_unpackhi_pd(c, d));
    [
        _mm256_permute2f128_pd::<0x20>(ab_even, cd_even),
        _mm256_permute2f128_pd::<0x20>(ab_odd, cd_odd),
        _mm256_permute2f128_pd::<0x31>(ab_even, cd_even),
        _mm256_permute2f128_pd::<0x31>(ab_odd, cd_odd),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cells::NONE;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The four-lane course test keeps bitwise the portable test's best pairs, with
    /// periodic images along two axes, a closed one, eMD* partners and horizons.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn four_lane_pair_tests_keep_the_portable_best() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("no AVX on this CPU: nothing to compare");
            return;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let period = [6.0, 7.0, 0.0];
        let (n, t0) = (48, 1.5);
        let mut kept = 0;
        for round in 0..300 {
            let motion: Vec<Motion> = (0..n)
                .map(|_| Motion {
                    pos: std::array::from_fn(|k| rng.random::<f64>() * [6.0, 7.0, 3.0][k]),
                    radius: 0.3 + 0.2 * rng.random::<f64>(),
                    vel: std::array::from_fn(|_| (rng.random::<f64>() - 0.5) * 4.0),
                    horizon: t0 + rng.random::<f64>() * 2.0,
                })
                .collect();
            let partner: Vec<u32> = (0..n as u32)
                .map(|i| if i < 8 { i ^ 1 } else { NONE })
                .collect();
            let pairs: Vec<[u32; 2]> = (0..round % 97 + 40)
                .map(|_| {
                    let i = rng.random_range(0..n as u32);
                    [i, (i + 1 + rng.random_range(0..n as u32 - 1)) % n as u32]
                })
                .collect();
            let mut portable = vec![(f64::INFINITY, 0); n];
            let mut lanes = vec![(f64::INFINITY, 0); n];
            let tests = |best| PairTests {
                motion: &motion,
                partner: &partner,
                best,
                t0,
                period,
            };
            let mut one_by_one = tests(&mut portable);
            for &[i, j] in &pairs {
                one_by_one.test(i as usize, j as usize);
            }
            // SAFETY: the CPU supports AVX (checked above).
            unsafe { tests(&mut lanes).run_avx(&pairs) };
            let bits =
                |b: &[(f64, u32)]| b.iter().map(|&(t, j)| (t.to_bits(), j)).collect::<Vec<_>>();
            assert_eq!(bits(&portable), bits(&lanes), "round {round}");
            kept += portable.iter().filter(|b| b.0.is_finite()).count();
        }
        assert!(kept > 1000, "{kept} particles kept a collision");
    }
}
