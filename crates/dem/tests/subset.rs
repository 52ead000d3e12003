//! The building blocks that other engines integrate a subset of the particles with
//! (`step_subset`, the force kernel, the full list): against MD itself, against free
//! flight, and against the exact solution of a collision.

mod common;

use common::*;
use emdstar_contact::Vec3;
use emdstar_dem::{
    Accelerations, ContactEnd, ContactScratch, ForceKernel, ForceModel, Motion, NeighbourList,
    Smooth, apply_contacts, shortest_contact_time, step_subset,
};
use emdstar_system::{Config, Particles, System};

/// Integrates the particles `ids` of `system` for `steps` steps of `dt` with
/// `step_subset` on a full list (rebuilt every step, so that no skin needs watching),
/// keeping the pairs whose partner passes `partner`. The forces at t = 0 come from the
/// kernel with the velocities as they are (h = 0), as MD starts.
fn run_subset(
    system: &System,
    ids: &[u32],
    partner: impl Fn(usize) -> bool + Copy,
    dt: f64,
    steps: u64,
) -> Particles {
    let mut p = system.particles.clone();
    let interactions = system.interactions();
    let inv_mass: Vec<f64> = p.mass.iter().map(|m| 1.0 / m).collect();
    let mut contact_acc = vec![[0.0; 3]; p.len()];
    let mut new_acc = vec![[0.0; 3]; p.len()];
    let skin = 0.5 * RADIUS;
    let min_cell = 2.0 * system.max_radius() + skin;
    let sim_box = system.domain.sim_box.as_ref();
    let mut list = NeighbourList::default();
    list.build_full(&p.position, &p.radius, sim_box, min_cell, skin)
        .unwrap();
    let model = ForceModel::new(
        &p.radius,
        &p.species,
        interactions,
        &system.domain,
        ContactEnd::ForceZero,
    );
    let kernel = ForceKernel {
        model,
        list: &list,
        contact_acc: &new_acc,
        h: 0.0,
        slot: Smooth,
    };
    let mut first = Vec::new();
    for &i in ids {
        let i = i as usize;
        let partners = list.once(i).iter().copied();
        let partners = partners.filter(|&e| partner(list.split(e).0));
        let (x, v) = (p.position[i], p.velocity[i]);
        kernel.particle(i, x, v, partners, &p.position, &p.velocity, &mut first);
    }
    let mut to = Accelerations {
        inv_mass: &inv_mass,
        acc: &mut contact_acc,
        angular: None,
    };
    apply_contacts(first.iter(), &mut to, None);
    let mut scratch = ContactScratch::default();
    for _ in 0..steps {
        if let Some(b) = sim_box {
            p.position.iter_mut().for_each(|x| *x = b.wrap(*x));
        }
        list.build_full(&p.position, &p.radius, sim_box, min_cell, skin)
            .unwrap();
        let motion = Motion {
            position: &mut p.position,
            velocity: &mut p.velocity,
            contact_acc: &mut contact_acc,
            new_acc: &mut new_acc,
            inv_mass: &inv_mass,
        };
        step_subset(&model, &list, motion, None, &mut scratch, ids, partner, dt);
    }
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
fn a_subset_of_every_particle_moves_as_md() {
    // A dense, damped Hertz gas with many contacts; the subset step sums its forces in
    // another order (full list, particles unsorted), so the two agree to round-off.
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
    let all: Vec<u32> = (0..system.particles.len() as u32).collect();
    let subset = run_subset(&system, &all, |_| true, dt, steps);
    let (dx, dv) = max_difference(&subset, &md.particles_in_config_order(), &system);
    assert!(
        dx < 1e-10 && dv < 1e-8,
        "|dx| = {dx:e} m, |dv| = {dv:e} m/s"
    );
}

#[test]
fn pairs_left_out_fly_through_each_other_and_others_stay_put() {
    // Two spheres on a head-on course under gravity, and a third sphere outside the
    // subset that overlaps the first: the filter leaves every pair out (as the hybrid
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
    let p = run_subset(&system, &[0, 1], |_| false, dt, steps);
    let t = dt * steps as f64;
    for (k, (x0, v0)) in bodies[..2].iter().enumerate() {
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
    assert_eq!(p.position[2], system.particles.position[2]);
    assert_eq!(p.velocity[2], system.particles.velocity[2]);
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
    let system = free_system(collision.law, &start);
    let p = run_subset(&system, &[0, 1], |_| true, dt, steps);
    let mut md = engine(system.clone(), dt, t_end);
    md.advance(steps).unwrap();
    let q = md.particles_in_config_order();
    let (dx, dv) = max_difference(&p, &q, &system);
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
