//! Stable event detection, Bannerman, Strobl, Formella & Pöschel, "Stable algorithm for
//! event detection in event-driven particle dynamics", Comp. Part. Mech. 1, 191 (2014).
//!
//! All functions return the time *interval* Δt ≥ 0 until the event, or `f64::INFINITY`
//! if there is none. An invalid (overlapping) state that is getting worse gives Δt = 0:
//! the caller executes a stabilising collision at once (Sec. 4.1, Eq. 10).

/// The two real roots of a·t² + b·t + c = 0 (a ≠ 0, b² − 4ac ≥ 0), computed without
/// catastrophic cancellation (Press et al., Numerical Recipes, Sec. 5.6, as required by
/// Bannerman 2014, Algorithm 2). Order is unspecified.
#[inline]
pub fn quadratic_roots(a: f64, b: f64, c: f64) -> (f64, f64) {
    let disc = (b * b - 4.0 * a * c).max(0.0);
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    if q == 0.0 {
        // b = 0 and c = 0: the double root at 0.
        return (0.0, 0.0);
    }
    (q / a, c / q)
}

/// Sphere–sphere collision time, Bannerman 2014, Algorithm 1.
///
/// `r` and `v` are the relative position r_ij and velocity v_ij now; `sigma` the contact
/// distance R_i + R_j. A uniform field cancels in the relative motion, so this holds
/// under gravity too.
///
/// - Receding or at the minimum of the overlap function (r·v ≥ 0): never.
/// - Overlapping and approaching: now (a stabilising collision).
/// - Miss or glancing touch: never.
/// - Otherwise the first root of f = |r + Δt v|² − σ², in the cancellation-free form
///   Δt = (r² − σ²)/(−r·v + √((r·v)² − v²(r² − σ²))).
#[inline]
pub fn sphere_sphere(r: [f64; 3], v: [f64; 3], sigma: f64) -> f64 {
    let b = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    if b >= 0.0 {
        return f64::INFINITY;
    }
    let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let gap = r2 - sigma * sigma;
    if gap <= 0.0 {
        return 0.0;
    }
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let disc = b * b - v2 * gap;
    if disc <= 0.0 {
        return f64::INFINITY;
    }
    gap / (-b + disc.sqrt())
}

/// The first collision time of a sphere with the periodic images along x of a
/// partner, r + k·`lx`·e_x (k any integer), moving at `v` relative to it: across a
/// Lees–Edwards face the images stream past along x, so the image that meets the
/// sphere first need not be the nearest now. Only the images whose x passage overlaps
/// the time window in which the y–z distance is below σ are tested.
pub fn sphere_x_images(r: [f64; 3], v: [f64; 3], sigma: f64, lx: f64) -> f64 {
    // Window [t1, t2] (t1 ≥ 0) where (r_y + v_y t)² + (r_z + v_z t)² < σ².
    let a = v[1] * v[1] + v[2] * v[2];
    let b = r[1] * v[1] + r[2] * v[2];
    let c = r[1] * r[1] + r[2] * r[2] - sigma * sigma;
    let (t1, t2) = if a == 0.0 {
        if c >= 0.0 {
            return f64::INFINITY;
        }
        // Two passages of the images along x, one of which lies wholly in the window.
        (0.0, 2.0 * lx / v[0].abs())
    } else {
        let disc = b * b - a * c;
        if disc <= 0.0 {
            return f64::INFINITY;
        }
        let root = disc.sqrt();
        let t2 = (-b + root) / a;
        if t2 < 0.0 {
            return f64::INFINITY;
        }
        (((-b - root) / a).max(0.0), t2)
    };
    if !t2.is_finite() {
        // At rest relative along x: only the nearest image.
        let k = -(r[0] / lx).round();
        return sphere_sphere([r[0] + k * lx, r[1], r[2]], v, sigma);
    }
    // r_x + k lx + v_x t ∈ [−σ, σ] for some t in the window.
    let (x1, x2) = (r[0] + v[0] * t1, r[0] + v[0] * t2);
    let (lo, hi) = (x1.min(x2), x1.max(x2));
    let k_min = ((-sigma - hi) / lx).ceil() as i64;
    let k_max = ((sigma - lo) / lx).floor() as i64;
    let mut best = f64::INFINITY;
    for k in k_min..=k_max.min(k_min + 64) {
        let rk = [r[0] + k as f64 * lx, r[1], r[2]];
        best = best.min(sphere_sphere(rk, v, sigma));
    }
    best
}

/// Whether [`sphere_sphere`] is finite: approaching (r·v < 0) with a positive
/// discriminant, Bannerman et al. 2014, Algorithm 1, lines 2-5, without a square
/// root or division and as a single comparison, so that a loop over candidate pairs
/// of which few approach has one branch, nearly always not taken.
#[inline(always)]
pub fn on_collision_course(r: [f64; 3], v: [f64; 3], sigma: f64) -> bool {
    let b = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    // b < 0 and b² − v²·(r² − σ²) > 0, as one comparison of their maximum.
    larger(b, v2 * (r2 - sigma * sigma) - b * b) < 0.0
}

/// The larger of `a` and `b`, or `b` if either is NaN: one instruction (`f64::max`
/// passes over a NaN, which costs two more). [`on_collision_course`] tests "both
/// quantities < 0" as "their maximum < 0", which for finite inputs (never NaN here) is
/// the same. (Tested apart and combined, the compiler branches on b < 0, a coin toss in
/// a gas: 18 % more mispredicted branches in the eMD* gas on epochs, 3 % slower.)
#[inline(always)]
fn larger(a: f64, b: f64) -> f64 {
    if a > b { a } else { b }
}

/// [`on_collision_course`], unless the collision provably comes more than `within`
/// (≥ 0, or +∞) from now, given here as `widened` = [`widen`]`(within)`: then the pair is
/// passed over without [`sphere_sphere`]'s square root and division. The first root
/// satisfies Δt ≥ (r² − σ²)/(−2 r·v), because √((r·v)² − v²(r² − σ²)) ≤ −r·v (the same
/// bound as Smallenburg, EPJE 45, 22 (2022), Sec. 2.2); the bound is widened by a
/// relative 10⁻⁹, far beyond the round-off of both sides, so that a pair passed over
/// would never have been kept: a scan that keeps collisions earlier than now + `within`
/// finds bitwise the same ones with or without this test. (A scan widens its best so
/// far once per improvement, not at every candidate.) It pays where many candidates
/// are on course (the neighbour lists of a dense gas); in a dilute gas its extra
/// arithmetic on every candidate costs more than the roots it saves, and the cells and
/// epochs use [`on_collision_course`].
#[inline(always)]
pub fn on_collision_course_before(r: [f64; 3], v: [f64; 3], sigma: f64, widened: f64) -> bool {
    let b = r[0] * v[0] + r[1] * v[1] + r[2] * v[2];
    let r2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    let v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    let gap = r2 - sigma * sigma;
    // −2b·within, widened (NaN for b = 0 and within = ∞; such a pair fails b < 0).
    let reach = -2.0 * b * widened;
    // b < 0, b² − v²·(r² − σ²) > 0 and r² − σ² < −2b·within, tested apart: here the
    // compiler's branch on b < 0 skips the rest for the receding half of a list, and
    // although it mispredicts more, it beat one comparison of the maximum in seven of
    // eight rounds in turns at η = 0.45.
    (b < 0.0) & (v2 * gap - b * b < 0.0) & (gap - reach < 0.0)
}

/// The horizon `within` widened for [`on_collision_course_before`].
#[inline(always)]
pub fn widen(within: f64) -> f64 {
    within * (1.0 + 1e-9)
}

/// Sphere–wall collision time under a constant acceleration, Bannerman 2014,
/// Algorithm 2 (parabolic free flight), in the wall's normal coordinate.
///
/// - `height`: signed distance n̂·(r − r_wall) of the centre from the plane, on the side
///   the normal points to (the caller flips n̂ if needed, line 1);
/// - `speed`: n̂·v; `accel`: n̂·g; `radius`: the contact distance (σ/2).
///
/// Overlapping and approaching gives 0. Under an acceleration towards the wall an
/// overlapped sphere with no real root (it cannot leave the overlap) collides at the
/// top of its flight, where its normal velocity is zero; the next detection then gives
/// 0 again and the overlap cannot grow (Sec. 5).
#[inline]
pub fn sphere_wall(height: f64, speed: f64, accel: f64, radius: f64) -> f64 {
    let gap = height - radius;
    if gap <= 0.0 && speed < 0.0 {
        return 0.0;
    }
    if accel == 0.0 {
        if speed >= 0.0 {
            return f64::INFINITY;
        }
        return -gap / speed;
    }
    let dt_min = -speed / accel;
    let disc = speed * speed - 2.0 * accel * gap;
    if accel < 0.0 {
        if disc < 0.0 {
            return dt_min.max(0.0);
        }
        let (t1, t2) = quadratic_roots(0.5 * accel, speed, gap);
        t1.max(t2).max(0.0)
    } else {
        if disc < 0.0 || dt_min < 0.0 {
            return f64::INFINITY;
        }
        let (t1, t2) = quadratic_roots(0.5 * accel, speed, gap);
        t1.min(t2).max(0.0)
    }
}

/// The naive sphere–wall time of Bannerman 2014, Eq. (12): the textbook quadratic
/// formula for a ball falling onto a plate (`accel` < 0). Returns NaN when the
/// discriminant is negative, the failure the paper reports in about half of all runs.
#[inline]
pub fn sphere_wall_naive(height: f64, speed: f64, accel: f64, radius: f64) -> f64 {
    -(speed + (speed * speed - 2.0 * accel * (height - radius)).sqrt()) / accel
}

/// Time until a coordinate at `d` = x − face, moving with `v` under `g`, crosses the
/// face in direction `dir` (±1): the first root of d + v·t + g·t²/2 = 0 with the
/// velocity pointing along `dir` (parabolic flight, Bannerman et al. 2014, Sec. 3);
/// 0 if it is already beyond the face and moving outwards (round-off), +∞ if never.
#[inline]
pub fn time_to_face(d: f64, v: f64, g: f64, dir: f64) -> f64 {
    if d * dir >= 0.0 && v * dir > 0.0 {
        return 0.0;
    }
    if g == 0.0 {
        if v * dir <= 0.0 {
            return f64::INFINITY;
        }
        return (-d / v).max(0.0);
    }
    if v * v - 2.0 * g * d < 0.0 {
        return f64::INFINITY;
    }
    let (t1, t2) = quadratic_roots(0.5 * g, v, d);
    let mut best = f64::INFINITY;
    for t in [t1, t2] {
        if t >= 0.0 && (v + g * t) * dir > 0.0 && t < best {
            best = t;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn the_collision_course_test_says_when_a_collision_time_is_finite() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut rand = || rng.random::<f64>() * 2.0 - 1.0;
        let mut cases: Vec<([f64; 3], [f64; 3], f64)> = (0..20_000)
            .map(|_| {
                let r = [rand() * 3.0, rand() * 3.0, rand() * 3.0];
                let v = [rand(), rand(), rand()];
                (r, v, 1.0 + rand().abs())
            })
            .collect();
        // Touching, overlapping, at rest, and grazing pairs.
        cases.extend([
            ([2.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 2.0),
            ([1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], 2.0),
            ([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 2.0),
            ([3.0, 2.0, 0.0], [-1.0, 0.0, 0.0], 2.0),
            ([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], 2.0),
        ]);
        let mut hits = 0;
        for (r, v, sigma) in cases {
            let a = sphere_sphere(r, v, sigma);
            assert_eq!(
                on_collision_course(r, v, sigma),
                a.is_finite(),
                "r {r:?} v {v:?}"
            );
            hits += usize::from(a.is_finite());
        }
        assert!(hits > 1000, "only {hits} approaching pairs were tried");
    }

    /// A pair passed over for lying beyond `within` would never have been kept by a scan
    /// that keeps collisions before now + within, at any time now: tested where it is
    /// tight (bounds a few ulps around the collision time itself), on grazing pairs,
    /// overlaps and ∞; and the bound does pass over most pairs that hit late.
    #[test]
    fn pairs_passed_over_never_collide_within_the_bound() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (mut passed_over, mut late) = (0, 0);
        for n in 0..200_000 {
            let mut rand = || rng.random::<f64>() * 2.0 - 1.0;
            let scale = 10f64.powf(3.0 * rand());
            let r = [
                rand() * 3.0 * scale,
                rand() * 3.0 * scale,
                rand() * 3.0 * scale,
            ];
            let mut v = [rand(), rand(), rand()];
            if n % 7 == 0 {
                // Nearly grazing: aimed to pass at about σ.
                let d = r.map(|x| -x);
                let side = [d[1], -d[0], 0.0];
                let len = (side[0] * side[0] + side[1] * side[1]).sqrt().max(1e-300);
                v = std::array::from_fn(|k| d[k] + side[k] / len * scale * (1.0 + 1e-7 * rand()));
            }
            let mut sigma = scale * (1.0 + rand().abs());
            if n % 7 == 3 {
                // Head-on, a hair from contact: the bound is tight to about 1e-14.
                let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                sigma = len / (1.0 + 1e-14 * (1.0 + rand().abs()));
                v = std::array::from_fn(|k| -r[k] / len + 1e-9 * rand());
            }
            let now = [0.0, 1.0, 1e4, 3.7e6][n % 4];
            let dt = sphere_sphere(r, v, sigma);
            // The scan's best so far, and the bound it passes: best − now.
            let best = match n % 5 {
                0 => f64::INFINITY,
                1 => now + 10f64.powf(4.0 * rand()) * scale,
                2 => (now + dt).next_up(),
                3 => (now + dt).next_down().next_down(),
                _ => now + dt * (1.0 + 1e-12 * rand()),
            };
            let within = best - now;
            if within.is_nan() || within < 0.0 {
                continue;
            }
            let kept = now + dt < best;
            if on_collision_course(r, v, sigma)
                && !on_collision_course_before(r, v, sigma, widen(within))
            {
                passed_over += 1;
                assert!(!kept, "r {r:?} v {v:?} σ {sigma} within {within}: Δt {dt}");
            }
            late += usize::from(dt.is_finite() && dt > 2.0 * within);
        }
        assert!(
            passed_over > late / 2,
            "{passed_over} passed over, {late} late"
        );
    }

    #[test]
    fn roots_are_accurate_when_b_dominates() {
        // t² − 1e8 t + 1 = 0: the small root 1e-8 is lost by the textbook formula.
        let (t1, t2) = quadratic_roots(1.0, -1e8, 1.0);
        let (small, large) = (t1.min(t2), t1.max(t2));
        assert!((small - 1e-8).abs() < 1e-22);
        assert!((large - 1e8).abs() < 1e-6);
        let textbook = (1e8 - (1e16f64 - 4.0).sqrt()) / 2.0;
        assert!((textbook - 1e-8).abs() > 1e-10);
    }

    #[test]
    fn head_on_spheres_meet_when_the_gap_closes() {
        // Gap 1 between surfaces, closing at 2: Δt = 0.5.
        let dt = sphere_sphere([3.0, 0.0, 0.0], [-2.0, 0.0, 0.0], 2.0);
        assert!((dt - 0.5).abs() < 1e-15);
        // Oblique: r = (3, 1, 0), v = (−1, 0, 0), σ = 2: x = 3 − t, x² + 1 = 4.
        let dt = sphere_sphere([3.0, 1.0, 0.0], [-1.0, 0.0, 0.0], 2.0);
        assert!((dt - (3.0 - 3f64.sqrt())).abs() < 1e-14);
    }

    #[test]
    fn misses_glances_and_receding_pairs_never_collide() {
        assert_eq!(
            sphere_sphere([3.0, 0.0, 0.0], [1.0, 0.0, 0.0], 2.0),
            f64::INFINITY
        );
        assert_eq!(
            sphere_sphere([3.0, 2.5, 0.0], [-1.0, 0.0, 0.0], 2.0),
            f64::INFINITY
        );
        // Glancing: impact parameter exactly σ.
        assert_eq!(
            sphere_sphere([3.0, 2.0, 0.0], [-1.0, 0.0, 0.0], 2.0),
            f64::INFINITY
        );
        // Overlapping but receding (or at rest): no event, the overlap heals by itself.
        assert_eq!(
            sphere_sphere([1.9, 0.0, 0.0], [1e-3, 0.0, 0.0], 2.0),
            f64::INFINITY
        );
        assert_eq!(sphere_sphere([1.9, 0.0, 0.0], [0.0; 3], 2.0), f64::INFINITY);
    }

    #[test]
    fn overlapping_approaching_pairs_collide_now() {
        assert_eq!(sphere_sphere([1.9, 0.0, 0.0], [-1e-12, 0.0, 0.0], 2.0), 0.0);
        // Even a pair overlapping by one ulp.
        let r = 2.0f64.next_down();
        assert_eq!(sphere_sphere([r, 0.0, 0.0], [-1.0, 0.0, 0.0], 2.0), 0.0);
    }

    #[test]
    fn wall_without_field_is_linear() {
        assert!((sphere_wall(3.0, -2.0, 0.0, 1.0) - 1.0).abs() < 1e-15);
        assert_eq!(sphere_wall(3.0, 2.0, 0.0, 1.0), f64::INFINITY);
        assert_eq!(sphere_wall(0.9, -2.0, 0.0, 1.0), 0.0);
    }

    #[test]
    fn falling_ball_hits_at_the_parabola_root() {
        // Height 1.5, radius 0.5, at rest, g = −1: gap 1, Δt = √2.
        let dt = sphere_wall(1.5, 0.0, -1.0, 0.5);
        assert!((dt - 2f64.sqrt()).abs() < 1e-15);
        assert!((sphere_wall_naive(1.5, 0.0, -1.0, 0.5) - dt).abs() < 1e-15);
        // Launched upwards from contact: back after 2v/g.
        let dt = sphere_wall(0.5, 3.0, -1.0, 0.5);
        assert!((dt - 6.0).abs() < 1e-14);
    }

    #[test]
    fn overlapped_ball_that_cannot_escape_stops_at_its_peak() {
        // 1e-10 deep, rising at 1e-6 with g = −1: the peak (5e-13 high) stays inside.
        let dt = sphere_wall(0.5 - 1e-10, 1e-6, -1.0, 0.5);
        assert!((dt - 1e-6).abs() < 1e-21);
        // The naive formula has a negative discriminant there.
        assert!(sphere_wall_naive(0.5 - 1e-10, 1e-6, -1.0, 0.5).is_nan());
        // At the peak (v = 0) the next event is now, for ever.
        assert_eq!(sphere_wall(0.5 - 1e-10, 0.0, -1.0, 0.5), 0.0);
    }

    #[test]
    fn field_away_from_the_wall_can_only_turn_back_before_it() {
        // Pushed away from the wall (g > 0) while approaching: hits if fast enough.
        let dt = sphere_wall(1.5, -2.0, 1.0, 0.5);
        // 0.5 t² − 2t + 1 = 0: t = 2 − √2.
        assert!((dt - (2.0 - 2f64.sqrt())).abs() < 1e-15);
        assert_eq!(sphere_wall(1.5, -1.0, 1.0, 0.5), f64::INFINITY);
        assert_eq!(sphere_wall(1.5, 1.0, 1.0, 0.5), f64::INFINITY);
    }
}
