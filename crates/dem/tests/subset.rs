//! MD's Verlet driver over a subset of the particles (the hybrid engine's time-driven
//! part): over every particle it is MD bit for bit, particles outside are left alone
//! and pairs with them left out, and a collision in a subset has its exact outcome.

mod common;

use common::*;
use emdstar_contact::Vec3;
use emdstar_dem::{ContactEnd, MdOptions, Verlet, default_skin, shortest_contact_time};
use emdstar_system::{Config, Particles, System};

/// Integrates the particles `members` names of `system` for `steps` steps of `dt`
/// with MD's driver, as MD does (the list rebuilt when its skin is used up), and
/// returns the particles in config order, velocities in step.
fn run_subset(system: &System, members: &[bool], dt: f64, steps: u64) -> Particles {
    let mut system = system.clone();
    let opts = MdOptions {
        dt,
        contact_end: ContactEnd::ForceZero,
        skin: None,
    };
    // MD's skin; no checks of the state (the tests overlap particles outside).
    let skin = default_skin(&system);
    let mut members = members.to_vec();
    let mut verlet = Verlet::new(&system, opts, skin);
    let renumber = |members: &mut Vec<bool>, order: &[u32]| {
        *members = order.iter().map(|&k| members[k as usize]).collect();
    };
    let order = verlet.rebuild(&mut system, 0.0, |_| false).unwrap();
    renumber(&mut members, &order);
    verlet.start_forces(&system, &members[..]);
    let g = system.domain.gravity;
    for step in 0..steps {
        let kick = verlet.next_kick();
        let v2 = verlet.kick(&mut system.particles, kick);
        let v_bound = verlet.speed_bound(v2, g, kick);
        if !verlet.list_holds(verlet.drift_bound(), v_bound, dt) {
            let t = step as f64 * dt;
            let order = verlet.rebuild(&mut system, t, |_| false).unwrap();
            renumber(&mut members, &order);
        }
        verlet.sweep(&mut system, &members[..], kick, dt);
    }
    let t = steps as f64 * dt;
    verlet
        .synchronise(&mut system.particles, &members[..], g, t)
        .unwrap();
    let mut p = system.particles;
    let mut back = vec![0u32; p.len()];
    for (k, &id) in p.id.iter().enumerate() {
        back[id as usize] = k as u32;
    }
    p.permute(&back);
    p
}

/// Largest position (nearest image) and velocity differences.
fn max_difference(a: &Particles, b: &Particles, system: &System) -> (f64, f64) {
    let (mut dx, mut dv): (f64, f64) = (0.0, 0.0);
    for i in 0..a.len() {
        let mut d: [f64; 3] = std::array::from_fn(|k| a.position[i][k] - b.position[i][k]);
        if let Some(s) = &system.domain.sim_box {
            d = s.min_image(d);
        }
        dx = dx.max(Vec3::from(d).norm());
        dv = dv.max((Vec3::from(a.velocity[i]) - Vec3::from(b.velocity[i])).norm());
    }
    (dx, dv)
}

#[test]
fn the_driver_over_every_particle_is_md_bit_for_bit() {
    // A dense, damped Hertz gas with many contacts and rebuilds.
    let system = Config::from_toml(
        "t_end = 0.1\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
         dissipation = 1e-4\ndensity = 1140.0\n[gas]\ncount = 64\nradius = 0.1\n\
         arrangement = \"random\"\npacking_fraction = 0.3\nrms_speed = 1.0\nseed = 5\n",
    )
    .unwrap()
    .build()
    .unwrap();
    let dt = shortest_contact_time(&system, 0.0).unwrap().unwrap() / 50.0;
    let steps = (0.1 / dt).round() as u64;
    let mut md = engine(system.clone(), dt, 0.1);
    md.advance(steps).unwrap();
    let e0 = system.particles.kinetic_energy();
    assert!(md.thermo().total_energy() < 0.95 * e0, "no collisions");
    let all = vec![true; system.particles.len()];
    let subset = run_subset(&system, &all, dt, steps);
    let reference = md.particles_in_config_order();
    assert_eq!(subset.position, reference.position);
    assert_eq!(subset.velocity, reference.velocity);
}

#[test]
fn members_fly_through_particles_outside_which_stay_put() {
    // Two spheres on a head-on course under gravity, and a third sphere that overlaps
    // the first: with only the first a member, every pair is left out (as the hybrid
    // leaves out the pairs of time-driven and event-driven particles).
    let bodies = [
        (Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.2, 0.0)),
        (Vec3::new(0.5, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.3)),
        (Vec3::new(-0.15, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0)),
    ];
    let mut system = free_system(linear(0.5), &bodies);
    let g = [0.0, -9.81, 0.0];
    system.domain.gravity = g;
    let (dt, steps) = (1e-4, 5000);
    let p = run_subset(&system, &[true, false, false], dt, steps);
    let t = dt * steps as f64;
    for (k, (x0, v0)) in bodies[..1].iter().enumerate() {
        let x: [f64; 3] = std::array::from_fn(|c| x0[c] + v0[c] * t + 0.5 * g[c] * t * t);
        let v: [f64; 3] = std::array::from_fn(|c| v0[c] + g[c] * t);
        for c in 0..3 {
            assert!(
                (p.position[k][c] - x[c]).abs() < 1e-12,
                "{k} {:?}",
                p.position[k]
            );
            assert!(
                (p.velocity[k][c] - v[c]).abs() < 1e-12,
                "{k} {:?}",
                p.velocity[k]
            );
        }
    }
    for k in 1..3 {
        assert_eq!(p.position[k], system.particles.position[k]);
        assert_eq!(p.velocity[k], system.particles.velocity[k]);
    }
}

#[test]
fn a_collision_in_a_subset_has_the_exact_outcome_as_in_md() {
    // Damped linear dashpot, oblique: the touch correction and the predictor act.
    let collision = Collision::new(linear(1.0), 1.0, 0.4);
    let per_contact = 100;
    let t_pre = 0.3 * collision.duration;
    let t_end = t_pre + 1.6 * collision.duration;
    let steps = (t_end / collision.duration * per_contact as f64).round() as u64;
    let dt = t_end / steps as f64;
    let start = collision
        .touch
        .map(|b| (b.position - b.velocity * t_pre, b.velocity));
    // A third sphere, far away and outside the subset, stays put.
    let far = (Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    let mut bodies = start.to_vec();
    bodies.push(far);
    let system = free_system(collision.law, &bodies);
    let p = run_subset(&system, &[true, true, false], dt, steps);
    assert_eq!(p.position[2], system.particles.position[2]);
    let system = free_system(collision.law, &start);
    let mut md = engine(system.clone(), dt, t_end);
    md.advance(steps).unwrap();
    let q = md.particles_in_config_order();
    let two = |p: &Particles| Particles {
        position: p.position[..2].to_vec(),
        velocity: p.velocity[..2].to_vec(),
        ..q.clone()
    };
    let (dx, dv) = max_difference(&two(&p), &q, &system);
    assert!(
        dx < 1e-14 && dv < 1e-13,
        "subset against MD: {dx:e} m, {dv:e} m/s"
    );
    for (k, b) in collision.after.iter().enumerate() {
        let x = b.position + b.velocity * (t_end - t_pre - collision.duration);
        let ex = (Vec3::from(p.position[k]) - x).norm() / collision.l;
        let ev = (Vec3::from(p.velocity[k]) - b.velocity).norm() / collision.speed;
        // Second order: about (π/100)² of the contact's scales.
        assert!(
            ex < 1e-3 && ev < 1e-3,
            "against the exact solution: {ex:e} {ev:e}"
        );
    }
}
