//! Lees–Edwards boundaries on eMD: a free particle through the sheared face against
//! the analytic image, the peculiar energy balance (the work of the boundaries,
//! −γ̇ V ∫P_xy dt, is the change of Σ ½ m c²), the conserved peculiar momentum, and
//! the broad phases and rules refused.

mod common;

use common::fcc;
use emdstar_edmd::{BroadPhaseKind, Engine, Physics};
use emdstar_system::{Domain, Particles, SimBox, Simulation, Species};

fn sheared(size: [f64; 3], rate: f64) -> Domain {
    Domain {
        shear_rate: rate,
        ..Domain::periodic(SimBox {
            lo: [0.0; 3],
            size,
            periodic: [true; 3],
        })
    }
}

#[test]
fn a_free_particle_through_the_sheared_face_becomes_its_slid_image() {
    // γ̇ = 0.3/s, L = (5, 4, 6) m: the image above moves at γ̇ L_y = 1.2 m/s. The
    // particle leaves through the top at t_c = (4 − 3.5)/0.25 = 2 s, where Δ = 2.4 m.
    let (rate, size) = (0.3, [5.0, 4.0, 6.0]);
    let s = [Species::new(0.2, 1.0)];
    let mut p = Particles::default();
    let (x0, v0) = ([1.0, 3.5, 2.0], [0.7, 0.25, -0.1]);
    p.push(&s, 0, x0, v0);
    let mut e: Engine = Engine::new(&p, &sheared(size, rate), Physics::hard_spheres(1.0)).unwrap();
    let t = 3.0;
    e.advance_to(t).unwrap();
    let now = e.particles();
    let tc = 2.0;
    let (u, delta) = (rate * size[1], (rate * size[1] * tc) % size[0]);
    let vx = v0[0] - u;
    let want_x = (x0[0] + v0[0] * tc - delta + vx * (t - tc)).rem_euclid(size[0]);
    let want = [want_x, x0[1] + v0[1] * t - size[1], x0[2] + v0[2] * t];
    for k in 0..3 {
        assert!(
            (now.position[0][k] - want[k]).abs() < 1e-12,
            "{:?} against {want:?}",
            now.position[0]
        );
    }
    assert!(
        (now.velocity[0][0] - vx).abs() < 1e-14,
        "{:?}",
        now.velocity[0]
    );
    assert_eq!(now.velocity[0][1], v0[1]);
    // And down through the bottom at t_c = 2 s: forward by the offset then, Δ = 2.4 m.
    let mut p = Particles::default();
    p.push(&s, 0, [1.0, 0.5, 2.0], [0.7, -0.25, 0.0]);
    let mut e: Engine = Engine::new(&p, &sheared(size, rate), Physics::hard_spheres(1.0)).unwrap();
    e.advance_to(3.0).unwrap();
    let now = e.particles();
    let want_x = (1.0 + 0.7 * tc + delta + (0.7 + u) * (t - tc)).rem_euclid(size[0]);
    assert!(
        (now.position[0][0] - want_x).abs() < 1e-12,
        "{:?}",
        now.position[0]
    );
    assert!(
        (now.position[0][1] - 3.75).abs() < 1e-12,
        "{:?}",
        now.position[0]
    );
    assert!((now.velocity[0][0] - (0.7 + u)).abs() < 1e-14);
}

/// Σ ½ m c² with c = v − γ̇ (y − L_y/2) e_x, and Σ m c.
fn peculiar(p: &Particles, rate: f64, ly: f64) -> (f64, [f64; 3]) {
    let (mut energy, mut momentum) = (0.0, [0.0; 3]);
    for i in 0..p.len() {
        let mut c = p.velocity[i];
        c[0] -= rate * (p.position[i][1] - 0.5 * ly);
        energy += 0.5 * p.mass[i] * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        for k in 0..3 {
            momentum[k] += p.mass[i] * c[k];
        }
    }
    (energy, momentum)
}

/// Elastic hard spheres at η ≈ 0.2 sheared hard (γ̇ of about a collision time): the
/// boundaries do work −γ̇ V ∫P_xy dt on the gas (the pressure tensor the engine sums,
/// kinetic and collisional), which must equal the change of the peculiar kinetic
/// energy to round-off; the peculiar momentum stays (Σ m v_y = 0).
#[test]
fn the_work_of_the_sheared_boundaries_heats_the_gas_by_the_shear_stress() {
    let (particles, periodic) = fcc(5, 0.4, 1.0, 1.0, 1.0, 7);
    let b = periodic.sim_box.unwrap();
    let rate = 0.5;
    let domain = Domain {
        shear_rate: rate,
        ..periodic
    };
    let mut e: Engine = Engine::new(&particles, &domain, Physics::hard_spheres(1.0)).unwrap();
    assert_eq!(e.broad_phase(), BroadPhaseKind::Crossings);
    let p0 = e.particles();
    let (e0, m0) = peculiar(&p0, rate, b.size[1]);
    let s0 = e.stress_sums();
    e.advance_to(6.0).unwrap();
    let p1 = e.particles();
    let (e1, m1) = peculiar(&p1, rate, b.size[1]);
    let s1 = e.stress_sums();
    let pxy_integral = (s1.kinetic[3] - s0.kinetic[3]) + (s1.collisional[3] - s0.collisional[3]);
    let work = -rate * pxy_integral;
    assert!(s1.collisions > 10_000, "{} collisions", s1.collisions);
    // The gas heats by a good fraction of its energy.
    assert!(e1 - e0 > 0.2 * e0, "{e0} -> {e1}");
    assert!(
        ((e1 - e0) - work).abs() < 1e-9 * e0,
        "peculiar energy {e0} -> {e1}: change {}, work of the boundaries {work}",
        e1 - e0
    );
    for k in 0..3 {
        assert!((m1[k] - m0[k]).abs() < 1e-9, "{m0:?} -> {m1:?}");
    }
}

#[test]
fn epochs_neighbours_and_emdstar_are_refused_under_shear() {
    let (particles, periodic) = fcc(3, 0.3, 1.0, 1.0, 1.0, 1);
    let domain = Domain {
        shear_rate: 0.1,
        ..periodic
    };
    for kind in [BroadPhaseKind::Epochs, BroadPhaseKind::Neighbours] {
        let got = Engine::<emdstar_edmd::IndexedHeap>::with_broad_phase(
            &particles,
            &domain,
            Physics::hard_spheres(1.0),
            kind,
        );
        assert!(got.is_err(), "{kind:?} ran a sheared box");
    }
}
