//! When a sphere in free flight (under gravity) meets a wall vibrating along its
//! normal: the first root of a non-linear overlap function, found robustly.
//!
//! In the normal coordinate the gap is f(τ) = c(τ) − s(t₀ + τ), with
//! c(τ) = h + v τ + g τ²/2 − R the sphere's gap to the plane at rest and
//! s(t) = A sin(ω t + φ) the wall's displacement. Following the stable event detection
//! of Bannerman et al. 2014 (Sec. 4.1: a collision happens at the first time the
//! overlap function is ≤ 0 *and* decreasing; an overlap that recedes is left alone),
//! the root is bracketed with the bound |f''| ≤ |g| + A ω² = M: from a time where
//! f > 0, f stays positive for s < s* with f + f' s − M s²/2 = 0 (conservative
//! advancement, which never steps over a root and converges quadratically onto a
//! crossing one); in contact and receding, f' stays positive for f'/M. Outside the band
//! c ≤ A no contact is possible, and the flight is followed there in closed form.

use crate::detect::time_to_face;
use emdstar_system::Vibration;

/// Steps of one prediction at most; beyond them the time reached is returned and the
/// sphere is predicted again then (a check, not a collision: see [`contact_tolerance`]).
const MAX_STEPS: usize = 200;

/// The gap below which a sphere counts as touching a vibrated wall: round-off of the
/// positions (height, radius, amplitude) and of the time `t` times the relative speed.
#[inline]
pub fn contact_tolerance(height: f64, radius: f64, amplitude: f64, speed: f64, t: f64) -> f64 {
    64.0 * f64::EPSILON * (height.abs() + radius + amplitude + speed.abs() * t.abs())
}

/// The time from `t0` until a sphere of contact distance `radius` at `height` =
/// n̂·(x − point at rest) with normal velocity `speed` and normal acceleration `accel`
/// collides with a wall vibrating by `vib`: 0 if it touches and approaches now, +∞ if
/// it never will. May return an earlier time at which the sphere does not yet touch
/// (after [`MAX_STEPS`]); predicting again from there goes on.
pub fn sphere_vibrated_wall(
    t0: f64,
    height: f64,
    speed: f64,
    accel: f64,
    radius: f64,
    vib: &Vibration,
) -> f64 {
    let (amplitude, omega) = (vib.amplitude, vib.omega());
    let m = accel.abs() + vib.max_acceleration();
    let mut tau = 0.0;
    for _ in 0..MAX_STEPS {
        let c = height + speed * tau + 0.5 * accel * tau * tau - radius;
        let cd = speed + accel * tau;
        if c > amplitude {
            // Beyond the wall's reach: on until the flight comes back to c = A.
            if accel >= 0.0 && cd >= 0.0 {
                return f64::INFINITY;
            }
            let s = time_to_face(c - amplitude, cd, accel, -1.0);
            if !s.is_finite() {
                return f64::INFINITY;
            }
            let next = tau + s;
            if next > tau {
                tau = next;
                continue;
            }
            // At the band's edge within round-off: go on as inside it.
        }
        let t = t0 + tau;
        let f = c - vib.displacement(t);
        let fd = cd - vib.speed(t);
        if f <= contact_tolerance(height + speed * tau, radius, amplitude, fd, t) {
            if fd <= 0.0 {
                // Touching and approaching (or at a turning point): now.
                return tau;
            }
            // Receding in contact: f' > 0 for at least f'/M more.
            tau += fd / m;
            continue;
        }
        if accel >= 0.0 && cd > amplitude * omega {
            // Faster away than the wall can ever move, and not slowing down.
            return f64::INFINITY;
        }
        // f(τ + s) ≥ f + f' s − M s²/2 > 0 up to the positive root s*.
        let disc = (fd * fd + 2.0 * m * f).sqrt();
        let s = if fd <= 0.0 {
            2.0 * f / (disc - fd)
        } else {
            (fd + disc) / m
        };
        let next = tau + s;
        if next == tau {
            return tau;
        }
        tau = next;
    }
    tau
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plate(amplitude: f64, frequency: f64, phase: f64) -> Vibration {
        Vibration {
            amplitude,
            frequency,
            phase,
        }
    }

    /// The gap at t0 + τ, straight from its definition.
    fn gap(t0: f64, h: f64, v: f64, g: f64, r: f64, vib: &Vibration, tau: f64) -> f64 {
        h + v * tau + 0.5 * g * tau * tau - r - vib.displacement(t0 + tau)
    }

    /// A dense scan for the first sign change of the gap from + to −: an independent
    /// reference, refined by bisection.
    fn scanned_root(t0: f64, h: f64, v: f64, g: f64, r: f64, vib: &Vibration, end: f64) -> f64 {
        let n = 200_000;
        let dt = end / n as f64;
        let f = |tau: f64| gap(t0, h, v, g, r, vib, tau);
        for k in 0..n {
            let (a, b) = (k as f64 * dt, (k + 1) as f64 * dt);
            if f(a) > 0.0 && f(b) <= 0.0 {
                let (mut lo, mut hi) = (a, b);
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    if f(mid) > 0.0 { lo = mid } else { hi = mid }
                }
                return hi;
            }
        }
        f64::INFINITY
    }

    #[test]
    fn the_first_contact_matches_a_dense_scan() {
        let vib = plate(0.01, 20.0, 0.3);
        let g = -9.81;
        // Falling from above, launched upwards, and skimming the band: each against a scan.
        for (t0, h, v) in [
            (0.0, 0.5, 0.0),
            (0.37, 0.12, 1.0),
            (1.1, 0.111, -0.05),
            (2.0, 0.1 + 0.009, 0.2),
            (5.5, 0.3, -2.0),
        ] {
            let r = 0.1;
            let got = sphere_vibrated_wall(t0, h, v, g, r, &vib);
            let want = scanned_root(t0, h, v, g, r, &vib, 2.0);
            assert!(
                (got - want).abs() < 1e-9,
                "t0 {t0} h {h} v {v}: got {got}, scan {want}"
            );
            let fd = v + g * got - vib.speed(t0 + got);
            assert!(fd < 0.0, "approaching at contact");
        }
    }

    #[test]
    fn a_sphere_leaving_a_collision_is_not_hit_at_once() {
        let vib = plate(0.01, 20.0, 0.0);
        let (r, t0) = (0.1, 0.123);
        // Just kicked off the wall (gap within round-off on either side), receding at
        // 0.5 m/s relative to it: no collision before it has flown.
        for dh in [-1e-17, 0.0, 1e-17] {
            let h = r + vib.displacement(t0) + dh;
            let v = vib.speed(t0) + 0.5;
            let dt = sphere_vibrated_wall(t0, h, v, -9.81, r, &vib);
            assert!(dt > 1e-3, "dh {dh}: {dt}");
        }
        // Overlapping and approaching: now.
        let h = r + vib.displacement(t0) - 1e-12;
        assert_eq!(
            sphere_vibrated_wall(t0, h, vib.speed(t0) - 0.1, -9.81, r, &vib),
            0.0
        );
    }

    #[test]
    fn a_sphere_out_of_reach_never_collides() {
        let vib = plate(0.01, 20.0, 0.0);
        // No gravity, moving away faster than the wall ever moves.
        assert_eq!(
            sphere_vibrated_wall(0.0, 0.5, 2.0, 0.0, 0.1, &vib),
            f64::INFINITY
        );
        // Gravity pulling away (a lid above), moving away.
        assert_eq!(
            sphere_vibrated_wall(0.0, 0.5, 0.1, 9.81, 0.1, &vib),
            f64::INFINITY
        );
        // At rest above the band without gravity.
        assert_eq!(
            sphere_vibrated_wall(0.0, 0.5, 0.0, 0.0, 0.1, &vib),
            f64::INFINITY
        );
    }
}
