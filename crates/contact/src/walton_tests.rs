//! Walton's rule against analytic limits: smooth and perfectly rough impacts, sliding
//! impacts against Coulomb's law and the work of friction, solid spheres against walls,
//! and the continuity of the switch between sticking and sliding.

use super::*;
use crate::vec3::{add, norm2, sub};

const Q: f64 = 0.4;

/// A fixed stream of numbers in [−1, 1) (xorshift64*), so the cases are reproducible.
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        2.0 * (x as f64 / (1u64 << 53) as f64) - 1.0
    }
    fn vec(&mut self, scale: f64) -> [f64; 3] {
        [
            self.next() * scale,
            self.next() * scale,
            self.next() * scale,
        ]
    }
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    scale(1.0 / norm(a), a)
}

fn sphere(velocity: [f64; 3], spin: [f64; 3], radius: f64, mass: f64) -> Rough {
    Rough {
        velocity,
        spin,
        radius,
        mass,
    }
}

/// The tangential part of a.
fn tangential(a: [f64; 3], n: [f64; 3]) -> [f64; 3] {
    add_scaled(a, -dot(a, n), n)
}

/// Velocity of the contact point of i relative to that of j: each point moves with its
/// centre plus ω × (its offset from the centre), i's at −R_i n, j's at +R_j n.
fn contact_velocity(n: [f64; 3], i: &Rough, j: &Rough) -> [f64; 3] {
    let pi = add(i.velocity, cross(i.spin, scale(-i.radius, n)));
    let pj = add(j.velocity, cross(j.spin, scale(j.radius, n)));
    sub(pi, pj)
}

fn energy(s: &Rough) -> f64 {
    0.5 * s.mass * norm2(s.velocity) + 0.5 * Q * s.mass * s.radius * s.radius * norm2(s.spin)
}

fn after(s: &Rough, o: &RoughOutcome, k: usize) -> Rough {
    Rough {
        velocity: o.velocity[k],
        spin: o.spin[k],
        ..*s
    }
}

/// A random oblique approach: n, and two spheres whose contact points approach.
fn random_pair(rng: &mut Stream, unequal: bool) -> ([f64; 3], Rough, Rough) {
    let n = unit(rng.vec(1.0));
    let (ri, rj) = if unequal {
        (0.05 + 0.04 * rng.next(), 0.2 + 0.1 * rng.next())
    } else {
        (0.1, 0.1)
    };
    let (mi, mj) = if unequal {
        (1.0 + 0.5 * rng.next(), 7.0 + 3.0 * rng.next())
    } else {
        (2.0, 2.0)
    };
    let mut i = sphere(rng.vec(2.0), rng.vec(30.0), ri, mi);
    let j = sphere(rng.vec(2.0), rng.vec(30.0), rj, mj);
    // Make the normal approach speed at least 0.5 m/s.
    let g_n = dot(sub(i.velocity, j.velocity), n);
    i.velocity = add_scaled(i.velocity, -g_n - 0.5 - rng.next().abs(), n);
    (n, i, j)
}

#[test]
fn smooth_impacts_leave_tangential_velocities_and_spins_alone() {
    let mut rng = Stream(7);
    for (mu, b0) in [(0.0, 0.6), (0.0, 1.0), (0.8, -1.0), (1e6, -1.0)] {
        for _ in 0..50 {
            let (n, i, j) = random_pair(&mut rng, true);
            let o = rough_pair(n, &i, &j, 0.7, &Walton::new(mu, b0).unwrap());
            assert_eq!(o.spin, [i.spin, j.spin], "µ = {mu}, β₀ = {b0}");
            for (k, s) in [i, j].iter().enumerate() {
                let (before, now) = (tangential(s.velocity, n), tangential(o.velocity[k], n));
                assert!(norm(sub(before, now)) <= 1e-15 * norm(s.velocity) * 4.0);
            }
            // The normal relative velocity is reversed and scaled by e.
            let g_n = dot(sub(i.velocity, j.velocity), n);
            let g_n_after = dot(sub(o.velocity[0], o.velocity[1]), n);
            assert!((g_n_after + 0.7 * g_n).abs() < 1e-14 * g_n.abs() * 10.0);
        }
    }
}

#[test]
fn perfectly_rough_elastic_impacts_conserve_energy_and_both_momenta() {
    let mut rng = Stream(11);
    let rough = Walton::new(1e9, 1.0).unwrap();
    for case in 0..200 {
        let (n, i, j) = random_pair(&mut rng, case % 2 == 1);
        let o = rough_pair(n, &i, &j, 1.0, &rough);
        assert!(!o.sliding);
        let (i2, j2) = (after(&i, &o, 0), after(&j, &o, 1));
        // Energy, translational plus rotational.
        let (e0, e1) = (energy(&i) + energy(&j), energy(&i2) + energy(&j2));
        assert!((e1 - e0).abs() < 1e-14 * e0, "case {case}: {e0} → {e1}");
        // Momentum.
        let p = |a: &Rough, b: &Rough| add(scale(a.mass, a.velocity), scale(b.mass, b.velocity));
        let (p0, p1) = (p(&i, &j), p(&i2, &j2));
        assert!(norm(sub(p1, p0)) < 1e-14 * (i.mass + j.mass) * 4.0);
        // Angular momentum about the origin, orbital plus spin, with the pair at
        // contact somewhere away from the origin.
        let xj = rng.vec(5.0);
        let xi = add_scaled(xj, i.radius + j.radius, n);
        let l = |a: &Rough, b: &Rough| {
            let spin = |s: &Rough| scale(Q * s.mass * s.radius * s.radius, s.spin);
            let orbital = add(
                scale(a.mass, cross(xi, a.velocity)),
                scale(b.mass, cross(xj, b.velocity)),
            );
            add(orbital, add(spin(a), spin(b)))
        };
        let (l0, l1) = (l(&i, &j), l(&i2, &j2));
        let l_scale = (i.mass + j.mass) * 5.0 * 4.0;
        assert!(
            norm(sub(l1, l0)) < 1e-14 * l_scale,
            "case {case}: {l0:?} → {l1:?}"
        );
        // And the contact point's tangential velocity is reversed (Eq. 1.1b, β = 1).
        let (g0, g1) = (
            tangential(contact_velocity(n, &i, &j), n),
            tangential(contact_velocity(n, &i2, &j2), n),
        );
        assert!(norm(add(g1, g0)) < 1e-13 * (1.0 + norm(g0)), "case {case}");
    }
}

#[test]
fn a_sliding_impact_takes_mu_times_the_normal_impulse_and_loses_its_work() {
    let mut rng = Stream(3);
    let (mu, e) = (0.15, 0.8);
    let w = Walton::new(mu, 0.4).unwrap();
    let mut slid = 0;
    for case in 0..200 {
        let (n, mut i, j) = random_pair(&mut rng, case % 2 == 0);
        // A fast slip along the surface makes most impacts slide.
        i.velocity = add(i.velocity, scale(4.0, unit(tangential(rng.vec(1.0), n))));
        let o = rough_pair(n, &i, &j, e, &w);
        if !o.sliding {
            continue;
        }
        slid += 1;
        let (i2, j2) = (after(&i, &o, 0), after(&j, &o, 1));
        // The impulses, read off particle i's change of momentum.
        let dp = scale(i.mass, sub(i2.velocity, i.velocity));
        let j_n = dot(dp, n);
        let p_t = norm(tangential(dp, n));
        assert!((p_t - mu * j_n).abs() < 1e-13 * j_n, "case {case}");
        // Coulomb's force opposes the slip: the slip keeps its direction while it
        // slows (β ≤ 0 here), so friction works against the mean slip speed.
        let g0 = tangential(contact_velocity(n, &i, &j), n);
        let g1 = tangential(contact_velocity(n, &i2, &j2), n);
        assert!(dot(g0, g1) >= 0.0 && norm(g1) < norm(g0), "case {case}");
        assert!(norm(cross(g0, g1)) < 1e-12 * norm2(g0));
        let m_eff = i.mass * j.mass / (i.mass + j.mass);
        let g_n = dot(sub(i.velocity, j.velocity), n);
        let normal_loss = 0.5 * m_eff * (1.0 - e * e) * g_n * g_n;
        let friction_work = mu * j_n * 0.5 * (norm(g0) + norm(g1));
        let loss = energy(&i) + energy(&j) - energy(&i2) - energy(&j2);
        let want = normal_loss + friction_work;
        assert!(
            (loss - want).abs() < 1e-12 * want,
            "case {case}: {loss} vs {want}"
        );
    }
    assert!(slid > 100, "only {slid} sliding impacts");
}

#[test]
fn unequal_spheres_stick_by_beta0_and_share_spin_by_their_radii() {
    let mut rng = Stream(5);
    let (b0, e) = (0.35, 0.9);
    let w = Walton::new(1e9, b0).unwrap();
    for case in 0..100 {
        let (n, i, j) = random_pair(&mut rng, true);
        let o = rough_pair(n, &i, &j, e, &w);
        let (i2, j2) = (after(&i, &o, 0), after(&j, &o, 1));
        let g0 = tangential(contact_velocity(n, &i, &j), n);
        let g1 = tangential(contact_velocity(n, &i2, &j2), n);
        assert!(
            norm(add(g1, scale(b0, g0))) < 1e-13 * (1.0 + norm(g0)),
            "case {case}"
        );
        // Each sphere's angular impulse is its lever arm R times its linear impulse:
        // I Δω = R |Δp_t|, so R|Δω| = |Δv_t|/q (HAET Eq. 3.3).
        for (s, s2) in [(i, i2), (j, j2)] {
            let dv_t = norm(tangential(sub(s2.velocity, s.velocity), n));
            let dw = norm(sub(s2.spin, s.spin));
            assert!((s.radius * dw - dv_t / Q).abs() < 1e-12 * (1.0 + dv_t / Q));
        }
    }
}

#[test]
fn sticking_turns_to_sliding_where_beta0_meets_the_sliding_value_for_any_masses() {
    // HAET Eq. 3.2 generalised: an impact sticks while
    // (1 + β₀)|v_t| ≤ (7/2) µ (1 + e) |g_n|, whatever the radii and masses.
    let mut rng = Stream(9);
    let (b0, e) = (0.3, 0.6);
    for case in 0..100 {
        let (n, i, j) = random_pair(&mut rng, case % 2 == 0);
        let g = contact_velocity(n, &i, &j);
        let (g_n, v_t) = (dot(g, n).abs(), norm(tangential(g, n)));
        let mu_star = (1.0 + b0) * v_t / (3.5 * (1.0 + e) * g_n);
        let at = |mu: f64| rough_pair(n, &i, &j, e, &Walton::new(mu, b0).unwrap());
        let (below, above) = (at(mu_star * (1.0 - 1e-9)), at(mu_star * (1.0 + 1e-9)));
        assert!(below.sliding && !above.sliding, "case {case}");
        assert!((below.beta - b0).abs() < 1e-8 && above.beta == b0);
        // Continuous: a relative change of 2e-9 in µ moves the outcome by about as much.
        for k in 0..2 {
            let dv = norm(sub(below.velocity[k], above.velocity[k]));
            let dw = norm(sub(below.spin[k], above.spin[k]));
            assert!(dv < 1e-8 * (1.0 + v_t), "case {case}: {dv}");
            let r = [i.radius, j.radius][k];
            assert!(dw * r < 1e-8 * (1.0 + v_t), "case {case}: {dw}");
        }
        // Far from the threshold the switch stays where it is.
        assert!(at(0.5 * mu_star).sliding && !at(2.0 * mu_star).sliding);
    }
}

#[test]
fn a_solid_sphere_on_a_wall_follows_the_textbook_limits() {
    let (u, vn, r, m) = (3.0, -2.0, 0.1, 0.5);
    let s = sphere([u, 0.0, vn], [0.0; 3], r, m);
    let n = [0.0, 0.0, 1.0];
    // Perfectly rough and elastic: the contact point's slip reverses, v_t' = (3/7)u and
    // Rω = (10/7)u (the superball), energy conserved.
    let o = rough_wall(n, &s, 1.0, &Walton::new(1e9, 1.0).unwrap());
    let [vx, vy, vz] = o.velocity[0];
    assert!((vx - 3.0 / 7.0 * u).abs() < 1e-14 && vy == 0.0 && (vz + vn).abs() < 1e-14);
    // The contact point moves at v_x − R ω_y: it went forwards at u and comes back at −u.
    assert!((o.spin[0][1] * r - 10.0 / 7.0 * u).abs() < 1e-13);
    assert!((energy(&after(&s, &o, 0)) - energy(&s)).abs() < 1e-14 * energy(&s));
    assert_eq!(o.velocity[1], [0.0; 3]);
    assert_eq!(o.spin[1], [0.0; 3]);
    // Sliding: Δv_t = µ(1 + e)|v_n| against the slip, RΔω = (5/2) of it.
    let (mu, e) = (0.1, 0.5);
    let o = rough_wall(n, &s, e, &Walton::new(mu, 1.0).unwrap());
    assert!(o.sliding);
    let dv = mu * (1.0 + e) * vn.abs();
    assert!((o.velocity[0][0] - (u - dv)).abs() < 1e-14);
    assert!((o.velocity[0][2] + e * vn).abs() < 1e-14);
    assert!((o.spin[0][1] * r - 2.5 * dv).abs() < 1e-13);
    // A sphere rolling without slip onto the wall keeps rolling: no tangential impulse.
    let rolling = sphere([u, 0.0, vn], [0.0, u / r, 0.0], r, m);
    let o = rough_wall(n, &rolling, e, &Walton::new(0.5, 0.5).unwrap());
    assert!((o.velocity[0][0] - u).abs() < 1e-14 && o.spin[0] == rolling.spin);
}

#[test]
fn bad_parameters_are_refused_with_the_key() {
    for b in [f64::NAN, 1.5, -1.01, f64::INFINITY] {
        let err = Walton::new(0.2, b).unwrap_err().to_string();
        assert!(err.contains("tangential_restitution"), "{err}");
    }
    assert!(
        Walton::new(-0.1, 0.5)
            .unwrap_err()
            .to_string()
            .contains("friction")
    );
    assert!(Walton::new(0.0, -1.0).is_ok() && Walton::new(2.0, 1.0).is_ok());
}
