//! The TC model (Luding & McNamara 1998, Granular Matter 1, 113): a collision within
//! t_c of a particle's previous one is elastic.

use emdstar_edmd::{Engine, Physics};
use emdstar_system::{Domain, Particles, Wall};

/// A ball dropped onto a floor with ε = 0.8 bounces ever lower and, without TC,
/// collapses (its flights shrink to round-off). With TC its bounces dissipate until a
/// flight, 2v'/g for the speed v' it leaves the floor with, is shorter than t_c; from
/// then on every bounce is elastic: it leaves the floor with the first v' = ε^K v₀
/// below g·t_c/2 for ever, and the engine counts those bounces as TC's.
#[test]
fn a_ball_on_a_floor_bounces_elastically_once_its_flights_are_shorter_than_tc() {
    let (radius, height, g, eps, mass) = (0.005, 0.045, 9.81, 0.8, 1.3e-3);
    let tc = 1e-3;
    let p = Particles::from_columns(
        vec![[0.0, 0.0, radius + height]],
        vec![[0.0; 3]],
        vec![radius],
        vec![mass],
        vec![0],
    )
    .unwrap();
    let domain = Domain {
        walls: vec![Wall {
            normal: [0.0, 0.0, 1.0],
            point: [0.0; 3],
            vibration: None,
        }],
        gravity: [0.0, 0.0, -g],
        ..Domain::default()
    };
    let build = |tc| {
        let mut e: Engine = Engine::new(&p, &domain, Physics::hard_spheres(eps)).unwrap();
        e.set_tc(tc).unwrap();
        e
    };
    let mut without = build(None);
    assert!(without.run_until(2.0).is_err());
    let mut e = build(Some(tc));
    let t_end = 2.0;
    e.run_until(t_end).unwrap();
    e.sync();
    // The analytic bounce at which TC takes over.
    let v0 = (2.0 * g * height).sqrt();
    let dissipative = (1..).find(|&k| 2.0 * eps.powi(k) * v0 / g < tc).unwrap();
    let v_star = eps.powi(dissipative) * v0;
    assert!(v_star < g * tc / 2.0 && v_star >= eps * g * tc / 2.0);
    let (x, v) = (e.positions()[0], e.velocities()[0]);
    let energy = 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + g * x[2];
    let expected = 0.5 * v_star * v_star + g * radius;
    assert!(
        (energy - expected).abs() < 1e-9 * expected,
        "{energy} vs {expected} (per unit mass)"
    );
    let s = e.stats();
    assert_eq!(
        s.tc_elastic,
        s.wall_collisions - dissipative as u64,
        "{s:?}"
    );
    // Bounces of period 2v*/g after the dissipative ones.
    assert!(s.tc_elastic as f64 > 0.5 * t_end * g / (2.0 * v_star));
    assert!(e.set_tc(Some(0.0)).is_err() && e.set_tc(Some(f64::NAN)).is_err());
}
