//! Friction in the event engine (Walton's rule): a frictional hard-sphere gas keeps its
//! momentum and never gains energy, a perfectly rough elastic one keeps its energy
//! while spins take their share; smooth limits leave spins alone; a rough sphere leaves
//! a wall as a superball does; eMD applies the force law's restitution; checkpoints
//! restore the spins bitwise, and frictional eMD*'s counters too, as do contacts solved
//! ahead on a second thread; eMD* refuses Walton's rule (it solves the history spring).

mod common;

use common::fcc;
use emdstar_contact::vec3::{add, cross, dot, norm, scale, sub};
use emdstar_contact::{ForceLaw, HistorySpring, LinearDashpot, Sphere, Tangential, Walton};
use emdstar_edmd::{BroadPhaseKind, Engine, Event, Interference, Physics};
use emdstar_system::{Domain, Interactions, Particles, Simulation, Wall};

/// Hard spheres of restitution `e` with Walton's rule `w`.
fn rough(e: f64, w: Walton) -> Physics {
    Physics::HardSpheres {
        restitution: e,
        walton: Some(w),
    }
}

/// Spins of a few rad/s, different for every particle (deterministic).
fn spin_up(p: &mut Particles, scale: f64) {
    for (i, w) in p.angular_velocity.iter_mut().enumerate() {
        let x = i as f64;
        *w = [
            scale * (0.7 * x).sin(),
            scale * (1.3 * x).cos(),
            scale * (2.1 * x + 0.5).sin(),
        ];
    }
}

/// Kinetic plus rotational energy, pending velocities applied.
fn total_energy(e: &Engine) -> f64 {
    let t = e.thermo();
    t.kinetic_energy + t.rotational_energy
}

#[test]
fn a_frictional_gas_keeps_its_momentum_and_never_gains_energy() {
    let (mut p, d) = fcc(5, 0.3, 1.0, 1.0, 1.0, 3);
    assert_eq!(p.len(), 500);
    spin_up(&mut p, 2.0);
    let w = Walton::new(0.3, 0.4).unwrap();
    let mut e: Engine = Engine::new(&p, &d, rough(0.95, w)).unwrap();
    let p0 = e.momentum();
    let speed_sum: f64 = p.velocity.iter().map(|v| norm(*v)).sum();
    let (mut energy, rot0) = (total_energy(&e), e.thermo().rotational_energy);
    for _ in 0..20 {
        e.run_collisions(2000).unwrap();
        let now = total_energy(&e);
        assert!(
            now <= energy * (1.0 + 1e-14),
            "energy rose {energy} → {now}"
        );
        energy = now;
        let p1 = e.momentum();
        assert!(
            norm(sub(p1, p0)) < 1e-12 * speed_sum,
            "momentum {p0:?} → {p1:?}"
        );
    }
    // Friction moved energy between spins and flights, and dissipated some.
    let rot = e.thermo().rotational_energy;
    assert!((rot - rot0).abs() > 0.01 * rot0, "spins {rot0} → {rot}");
    assert!(
        energy < 0.9 * (total_energy(&Engine::new(&p, &d, Physics::hard_spheres(1.0)).unwrap()))
    );
}

#[test]
fn a_perfectly_rough_elastic_gas_keeps_its_energy_and_spins_up() {
    let (p, d) = fcc(5, 0.3, 1.0, 1.0, 1.0, 5);
    let perfect = Walton::new(1e9, 1.0).unwrap();
    let mut e: Engine = Engine::new(&p, &d, rough(1.0, perfect)).unwrap();
    let e0 = total_energy(&e);
    assert_eq!(e.thermo().rotational_energy, 0.0);
    e.run_collisions(20_000).unwrap();
    let e1 = total_energy(&e);
    assert!(((e1 - e0) / e0).abs() < 1e-11, "energy {e0} → {e1}");
    // Collisions exchange translational and rotational energy: after 80 collisions per
    // sphere the spins hold a large share of it (perfectly rough spheres have
    // equipartition, T_rot = T_tr, as their equilibrium).
    let t = e.thermo();
    let ratio = t.rotational_temperature / t.granular_temperature;
    eprintln!(
        "rough elastic gas: energy drift {:e}, T_rot/T_tr {ratio}",
        (e1 - e0) / e0
    );
    assert!(ratio > 0.85 && ratio < 1.15, "T_rot/T_tr = {ratio}");
}

#[test]
fn smooth_limits_leave_the_spins_alone_and_mu_zero_is_the_frictionless_rule() {
    let (mut p, d) = fcc(4, 0.2, 1.0, 1.0, 1.0, 7);
    spin_up(&mut p, 3.0);
    // β₀ = −1: no tangential impulse, whatever µ.
    let smooth = Walton::new(0.8, -1.0).unwrap();
    let mut e: Engine = Engine::new(&p, &d, rough(0.9, smooth)).unwrap();
    e.run_collisions(5000).unwrap();
    assert_eq!(e.angular_velocities(), p.angular_velocity);
    // µ = 0: the frictionless rule itself, bit for bit.
    let mut plain: Engine = Engine::new(&p, &d, Physics::hard_spheres(0.9)).unwrap();
    let mut zero: Engine = Engine::new(&p, &d, rough(0.9, Walton::new(0.0, 0.5).unwrap())).unwrap();
    assert!(!zero.rules().is_frictional());
    plain.run_collisions(3000).unwrap();
    zero.advance_to(plain.time()).unwrap();
    assert_eq!(plain.particles(), zero.particles());
}

#[test]
fn a_rough_sphere_leaves_a_wall_like_a_superball() {
    // Perfectly rough and elastic against a floor: the contact point's slip reverses,
    // so v_x' = (3/7)u and Rω_y' = (10/7)u (I = (2/5)mR²).
    let (u, r) = (2.0, 0.1);
    let p = Particles::from_columns(
        vec![[0.0, 0.0, 0.5]],
        vec![[u, 0.0, -1.0]],
        vec![r],
        vec![0.3],
        vec![0],
    )
    .unwrap();
    let d = Domain {
        walls: vec![Wall {
            normal: [0.0, 0.0, 1.0],
            point: [0.0; 3],
            vibration: None,
        }],
        ..Domain::default()
    };
    let mut e: Engine = Engine::new(&p, &d, rough(1.0, Walton::new(1e9, 1.0).unwrap())).unwrap();
    while !matches!(e.step().unwrap(), Event::Wall(..)) {}
    let (v, w) = (e.velocities()[0], e.angular_velocities()[0]);
    assert!((v[0] - 3.0 / 7.0 * u).abs() < 1e-14, "{v:?}");
    assert!((v[2] - 1.0).abs() < 1e-14 && v[1] == 0.0, "{v:?}");
    assert!(
        (w[1] * r - 10.0 / 7.0 * u).abs() < 1e-13 && w[0] == 0.0,
        "{w:?}"
    );
}

#[test]
fn emd_applies_the_force_laws_restitution_and_beta0_to_the_contact_point() {
    // Linear dashpot: ε = exp(−β t_c) with β = γ/(2 m_eff), t_c = (π − atan(2βω/(ω² −
    // β²)))/ω, ω² = k/m_eff − β² (Schwager & Pöschel 2007; docs/physics.md).
    let (k, gamma) = (2000.0, 1.0);
    let sphere = Sphere::from_density(0.1, 1140.0).unwrap();
    let m_eff = 0.5 * sphere.mass;
    let beta = gamma / (2.0 * m_eff);
    let omega = (k / m_eff - beta * beta).sqrt();
    let tc = (std::f64::consts::PI - (2.0 * beta * omega / (omega * omega - beta * beta)).atan())
        / omega;
    let eps = (-beta * tc).exp();
    let law = ForceLaw::Linear(LinearDashpot::new(k, gamma).unwrap());
    let b0 = 0.45;
    let walton = Tangential::Walton(Walton::new(1e9, b0).unwrap());
    let physics = Physics::Emd(Interactions::of_spheres(&law, walton, &[sphere]).unwrap());
    let mut p = Particles::from_columns(
        vec![[-0.3, 0.05, 0.0], [0.3, -0.05, 0.02]],
        vec![[1.0, 0.3, 0.0], [-1.0, 0.0, -0.2]],
        vec![0.1, 0.1],
        vec![sphere.mass; 2],
        vec![0, 0],
    )
    .unwrap();
    p.angular_velocity = vec![[0.0, 0.0, 5.0], [3.0, -1.0, 0.0]];
    let mut e: Engine = Engine::new(&p, &Domain::default(), physics).unwrap();
    let contact = |e: &Engine, n: [f64; 3]| {
        let (v, w) = (e.velocities(), e.angular_velocities());
        // Each contact point moves with its centre plus ω × (its offset).
        let a = add(v[0], cross(w[0], scale(-0.1, n)));
        let b = add(v[1], cross(w[1], scale(0.1, n)));
        sub(a, b)
    };
    while !matches!(e.step().unwrap(), Event::Collision(..)) {}
    let x = e.positions();
    let n = {
        let d = sub(x[0], x[1]);
        scale(1.0 / norm(d), d)
    };
    // Before the collision: the initial velocities and spins (free flights).
    let g_before = {
        let (v, w) = (&p.velocity, &p.angular_velocity);
        sub(
            add(v[0], cross(w[0], scale(-0.1, n))),
            add(v[1], cross(w[1], scale(0.1, n))),
        )
    };
    let g_after = contact(&e, n);
    let (gn0, gn1) = (dot(g_before, n), dot(g_after, n));
    assert!(gn0 < 0.0);
    assert!(
        (gn1 + eps * gn0).abs() < 1e-12,
        "ε: {} vs {eps}",
        -gn1 / gn0
    );
    let t0 = sub(g_before, scale(gn0, n));
    let t1 = sub(g_after, scale(gn1, n));
    assert!(norm(add(t1, scale(b0, t0))) < 1e-12, "{t0:?} → {t1:?}");
}

#[test]
fn a_restored_frictional_gas_continues_bitwise_with_its_spins() {
    for kind in [BroadPhaseKind::Crossings, BroadPhaseKind::Epochs] {
        let engine = || {
            let (mut p, d) = fcc(4, 0.01, 1.0, 1.0, 1.0, 13);
            spin_up(&mut p, 1.0);
            Engine::with_broad_phase(&p, &d, rough(0.9, Walton::new(0.25, 0.3).unwrap()), kind)
                .unwrap()
        };
        let t_end = 40.0;
        let mut straight: Engine = engine();
        straight.advance_to(t_end).unwrap();
        let mut first: Engine = engine();
        first.advance_to(0.5 * t_end).unwrap();
        let saved = Simulation::save_state(&first);
        let mut resumed: Engine = engine();
        resumed.restore_state(&saved).unwrap();
        assert_eq!(Simulation::save_state(&resumed), saved, "{kind:?}");
        resumed.advance_to(t_end).unwrap();
        let (a, b) = (straight.particles(), resumed.particles());
        assert_eq!(a, b, "{kind:?}: the restored run differs");
        assert_ne!(a.angular_velocity, engine().particles().angular_velocity);
        assert!(straight.stats().pair_collisions > 200, "{kind:?}");
    }
}

#[test]
fn emdstar_refuses_waltons_rule_and_names_the_engines_that_run_it() {
    let (p, d) = fcc(2, 0.05, 1.0, 1.0, 1.0, 1);
    let sphere = Sphere::new(0.5, 1.0).unwrap();
    let law = ForceLaw::Linear(LinearDashpot::new(1e4, 0.0).unwrap());
    let walton = Tangential::Walton(Walton::new(0.2, 0.4).unwrap());
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, walton, &[sphere]).unwrap(),
        mor: Box::new(emdstar_edmd::rules::ExactMor),
        interference: Interference::HitOnly,
    };
    let err = Engine::<emdstar_edmd::CalendarQueue>::new(&p, &d, physics)
        .err()
        .expect("eMD* refuses Walton's rule")
        .to_string();
    assert!(
        err.contains("eMD*") && err.contains("eMD") && err.contains("MD"),
        "{err}"
    );
}

#[test]
fn a_frictional_gas_between_walls_under_gravity_never_gains_energy() {
    // Periodic along x and y, a floor and a lid along z, gravity down: walls take part
    // in most collisions, and their impulses change spins too.
    let (mut p, d) = fcc(4, 0.05, 1.0, 1.0, 1.0, 17);
    spin_up(&mut p, 1.0);
    let b = d.sim_box.unwrap();
    let (lo, hi) = (b.lo[2], b.lo[2] + b.size[2]);
    // Lift every sphere off the faces (the lattice may touch them).
    for x in &mut p.position {
        x[2] = lo + 0.6 + (x[2] - lo) * (hi - lo - 1.2) / (hi - lo);
    }
    let d = Domain {
        sim_box: Some(emdstar_system::SimBox {
            periodic: [true, true, false],
            ..b
        }),
        walls: vec![
            Wall {
                normal: [0.0, 0.0, 1.0],
                point: [0.0, 0.0, lo],
                vibration: None,
            },
            Wall {
                normal: [0.0, 0.0, -1.0],
                point: [0.0, 0.0, hi],
                vibration: None,
            },
        ],
        gravity: [0.0, 0.0, -0.5],
        ..Domain::default()
    };
    let mut e: Engine = Engine::new(&p, &d, rough(0.9, Walton::new(0.4, 0.2).unwrap())).unwrap();
    let total = |e: &Engine| {
        let t = e.thermo();
        t.kinetic_energy + t.rotational_energy + t.potential_energy
    };
    let mut energy = total(&e);
    let scale = e.thermo().kinetic_energy;
    for _ in 0..20 {
        e.run_collisions(500).unwrap();
        let now = total(&e);
        assert!(
            now <= energy + 1e-12 * scale,
            "energy rose {energy} → {now}"
        );
        energy = now;
    }
    assert!(e.stats().wall_collisions > 500, "{:?}", e.stats());
}

#[test]
fn a_rough_collision_of_unequal_spheres_keeps_the_angular_momentum_about_the_origin() {
    // Free space, away from the origin: orbital plus spin angular momentum is conserved
    // because the impulse acts at the contact point.
    let mut p = Particles::from_columns(
        vec![[3.0, 2.0, -1.0], [3.6, 2.1, -0.9]],
        vec![[1.0, 0.2, 0.1], [-0.5, 0.0, 0.0]],
        vec![0.12, 0.3],
        vec![0.4, 2.5],
        vec![0, 1],
    )
    .unwrap();
    p.angular_velocity = vec![[4.0, -2.0, 7.0], [0.0, 3.0, -1.0]];
    let mut e: Engine = Engine::new(
        &p,
        &Domain::default(),
        rough(0.8, Walton::new(0.3, 0.4).unwrap()),
    )
    .unwrap();
    let l0 = p.angular_momentum();
    while !matches!(e.step().unwrap(), Event::Collision(..)) {}
    let after = e.particles();
    assert_ne!(after.angular_velocity, p.angular_velocity);
    let l1 = after.angular_momentum();
    let scale = norm(l0) + 1.0;
    assert!(norm(sub(l1, l0)) < 1e-14 * scale, "{l0:?} → {l1:?}");
}

/// eMD* with the exact frictional contact on a gas of spheres (σ = 1, m = 1).
fn frictional_emdstar(p: &Particles, d: &Domain, friction: Tangential) -> Engine {
    let sphere = Sphere::new(0.5, 1.0).unwrap();
    let law = ForceLaw::Linear(LinearDashpot::new(1e4, 5.0).unwrap());
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, friction, &[sphere]).unwrap(),
        mor: Box::new(emdstar_edmd::rules::ExactMor),
        interference: Interference::HitOnly,
    };
    Engine::new(p, d, physics).unwrap()
}

/// The history spring of the frictional eMD* tests (µ, k_t, no dashpot).
fn history(mu: f64, k_t: f64) -> Tangential {
    Tangential::History(HistorySpring::new(mu, k_t, 0.0).unwrap())
}

#[test]
fn frictional_emdstar_keeps_momentum_moves_energy_into_spins_and_counts_its_solves() {
    let (p, d) = fcc(3, 0.3, 1.0, 1.0, 1.0, 7);
    let mut e = frictional_emdstar(&p, &d, history(0.5, 2e4 / 7.0));
    let p0 = e.momentum();
    let speed_sum: f64 = p.velocity.iter().map(|v| norm(*v)).sum();
    assert_eq!(e.thermo().rotational_energy, 0.0);
    e.run_collisions(1000).unwrap();
    let p1 = e.momentum();
    assert!(norm(sub(p1, p0)) < 1e-12 * speed_sum, "{p0:?} → {p1:?}");
    let stats = *e.stats();
    // Every pair collision is an exact frictional solve; the exceptions (a) among them
    // took the contact's impulse (the kick of restitution only when that would not
    // separate the pair).
    assert_eq!(stats.frictional_solves, stats.pair_collisions);
    assert!(stats.frictional_fallback_kicks <= stats.exception_rotation);
    // Spins took up energy from rest, and the damped gas cooled.
    let t = e.thermo();
    assert!(t.rotational_energy > 0.05 * t.kinetic_energy, "{t:?}");
    let smooth = frictional_emdstar(&p, &d, history(0.0, 2e4 / 7.0));
    assert!(
        !smooth.rules().is_frictional(),
        "µ = 0 keeps the frictionless rule"
    );
}

/// A frictional eMD* gas saved half way and restored into a fresh engine ends with the
/// particles and the counters of the run that went through, its frictional solves
/// included.
#[test]
fn a_restored_frictional_emdstar_gas_continues_bitwise_with_its_counters() {
    let (p, d) = fcc(3, 0.3, 1.0, 1.0, 1.0, 11);
    let engine = || frictional_emdstar(&p, &d, history(0.4, 2e4 / 7.0));
    let t_end = 4.0;
    let mut straight = engine();
    straight.advance_to(t_end).unwrap();
    let mut first = engine();
    first.advance_to(0.5 * t_end).unwrap();
    assert!(first.stats().frictional_solves > 50, "{:?}", first.stats());
    let saved = Simulation::save_state(&first);
    let mut resumed = engine();
    resumed.restore_state(&saved).unwrap();
    resumed.advance_to(t_end).unwrap();
    assert_eq!(straight.particles(), resumed.particles());
    assert_eq!(straight.stats(), resumed.stats());
    assert!(straight.stats().frictional_solves > first.stats().frictional_solves);
}

/// A frictional eMD* gas run on one thread and with its contacts solved ahead on a
/// second ends with the same particles and counters, to the bit, and the second run
/// took solves from the worker.
#[test]
fn contacts_solved_ahead_leave_a_frictional_emdstar_run_bitwise_the_same() {
    let (p, d) = fcc(3, 0.3, 1.0, 1.0, 1.0, 5);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut e = frictional_emdstar(&p, &d, history(0.4, 2e4 / 7.0));
            e.advance_to(4.0).unwrap();
            let taken = e.rules().solves_ahead().map(|a| a.counts().0);
            (e.particles(), *e.stats(), taken)
        })
    };
    let (alone, ahead) = (run(1), run(2));
    assert_eq!(alone.2, None, "one thread: no worker");
    assert!(alone.1.frictional_solves > 100, "{:?}", alone.1);
    assert_eq!(alone.0, ahead.0);
    assert_eq!(alone.1, ahead.1);
    assert!(ahead.2.is_some_and(|taken| taken > 0), "{:?}", ahead.2);
}

/// A spinning sphere thrown at a wall by eMD* with the exact frictional contact: the wall
/// takes part like a partner of infinite mass (the spin changes, the wall's impulse is
/// the contact's, with the sphere's tangential velocity and spin tied by the spring), and
/// pure Coulomb sliding, which has no exact solve, is refused.
#[test]
fn frictional_emdstar_runs_walls_and_refuses_pure_coulomb_sliding() {
    let mut p = Particles::from_columns(
        vec![[0.0, 0.0, 0.6]],
        vec![[1.0, 0.0, -1.0]],
        vec![0.5],
        vec![1.0],
        vec![0],
    )
    .unwrap();
    p.angular_velocity = vec![[0.0, -3.0, 0.0]];
    let walled = Domain {
        walls: vec![Wall {
            normal: [0.0, 0.0, 1.0],
            point: [0.0; 3],
            vibration: None,
        }],
        ..Domain::default()
    };
    let sphere = Sphere::new(0.5, 1.0).unwrap();
    let law = ForceLaw::Linear(LinearDashpot::new(1e4, 0.0).unwrap());
    let build = |d: &Domain, friction: Tangential| {
        Engine::<emdstar_edmd::CalendarQueue>::new(
            &p,
            d,
            Physics::EmdStar {
                interactions: Interactions::of_spheres(&law, friction, &[sphere]).unwrap(),
                mor: Box::new(emdstar_edmd::rules::ExactMor),
                interference: Interference::HitOnly,
            },
        )
    };
    let mut e = build(&walled, history(0.3, 2e4 / 7.0)).unwrap();
    e.advance_to(0.5).unwrap();
    assert_eq!(e.stats().wall_collisions, 1);
    assert_eq!(e.stats().frictional_solves, 1);
    // An elastic normal law: the normal speed comes back; the wall takes no energy but
    // the spring's and the dashpot-free slip's exchange (elastic spring: none is lost
    // beyond the lever arm's O(ξ/R)); the spin changed towards rolling.
    let q = e.particles();
    assert!((q.velocity[0][2] - 1.0).abs() < 1e-3, "{:?}", q.velocity[0]);
    assert_ne!(q.angular_velocity[0], p.angular_velocity[0]);
    let slip = |v: [f64; 3], w: [f64; 3]| v[0] - 0.5 * w[1];
    let (s0, s1) = (
        slip(p.velocity[0], p.angular_velocity[0]),
        slip(q.velocity[0], q.angular_velocity[0]),
    );
    assert!(s1.abs() < s0.abs(), "slip {s0} → {s1}");
    let energy = |v: [f64; 3], w: [f64; 3]| 0.5 * dot(v, v) + 0.5 * 0.4 * 0.25 * dot(w, w);
    let (e0, e1) = (
        energy(p.velocity[0], p.angular_velocity[0]),
        energy(q.velocity[0], q.angular_velocity[0]),
    );
    assert!(e1 <= e0 * (1.0 + 1e-9), "energy {e0} → {e1}");
    let coulomb = Tangential::Coulomb { friction: 0.3 };
    let err = build(&Domain::default(), coulomb)
        .err()
        .unwrap()
        .to_string();
    assert!(err.contains("coulomb"), "{err}");
}
