//! The engine (cells, crossing events, delayed updates, queue) against an independent
//! brute-force reference: every step advances all particles and tests every pair in
//! all 27 periodic images with the textbook quadratic formula, O(N²) per collision.

mod common;

use common::fcc;
use emdstar_edmd::{
    BroadPhaseKind, CalendarQueue, Engine, Event, EventQueue, IndexedHeap, Physics,
};
use emdstar_system::{Domain, Particles};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Elastic hard spheres (the radii and masses of `setup`) in its periodic cube, run
/// by brute force: the first `count` collisions as (i, j, time) with i < j.
fn brute_force((setup, domain): &(Particles, Domain), count: usize) -> Vec<(u32, u32, f64)> {
    let side = domain.sim_box.expect("a periodic box").size[0];
    let mut x = setup.position.clone();
    let mut v = setup.velocity.clone();
    let n = x.len();
    let mut time = 0.0;
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let mut best = (f64::INFINITY, 0, 0, [0.0; 3]);
        for i in 0..n {
            for j in i + 1..n {
                // The nearest image and its 26 neighbours.
                let near: [f64; 3] =
                    std::array::from_fn(|k| ((x[i][k] - x[j][k]) / side).round() * side);
                for image in 0..27 {
                    let m = [image % 3, image / 3 % 3, image / 9];
                    let s: [f64; 3] = std::array::from_fn(|k| near[k] + (m[k] as f64 - 1.0) * side);
                    let r: [f64; 3] = std::array::from_fn(|k| x[i][k] - x[j][k] - s[k]);
                    let u: [f64; 3] = std::array::from_fn(|k| v[i][k] - v[j][k]);
                    let b: f64 = (0..3).map(|k| r[k] * u[k]).sum();
                    let r2: f64 = (0..3).map(|k| r[k] * r[k]).sum();
                    let u2: f64 = (0..3).map(|k| u[k] * u[k]).sum();
                    let sigma = setup.radius[i] + setup.radius[j];
                    let disc = b * b - u2 * (r2 - sigma * sigma);
                    if b < 0.0 && disc > 0.0 {
                        let t = (-b - disc.sqrt()) / u2;
                        if t < best.0 {
                            best = (t, i, j, s);
                        }
                    }
                }
            }
        }
        let (dt, i, j, s) = best;
        for (p, w) in x.iter_mut().zip(&v) {
            for k in 0..3 {
                p[k] += w[k] * dt;
            }
        }
        time += dt;
        // An elastic impulse along the line of centres.
        let r: [f64; 3] = std::array::from_fn(|k| x[i][k] - x[j][k] - s[k]);
        let r2: f64 = (0..3).map(|k| r[k] * r[k]).sum();
        let vn: f64 = (0..3).map(|k| r[k] * (v[i][k] - v[j][k])).sum::<f64>() / r2;
        let (mi, mj) = (setup.mass[i], setup.mass[j]);
        for k in 0..3 {
            v[i][k] -= 2.0 * mj / (mi + mj) * vn * r[k];
            v[j][k] += 2.0 * mi / (mi + mj) * vn * r[k];
        }
        out.push((i as u32, j as u32, time));
    }
    out
}

fn engine_collisions<Q: EventQueue>(mut e: Engine<Q>, count: usize) -> Vec<(u32, u32, f64)> {
    engine_collisions_of(&mut e, count)
}

fn engine_collisions_of<Q: EventQueue>(e: &mut Engine<Q>, count: usize) -> Vec<(u32, u32, f64)> {
    let mut out = vec![];
    while out.len() < count {
        if let Event::Collision(i, j) = e.step().unwrap() {
            out.push((i.min(j), i.max(j), e.time()));
        }
    }
    out
}

/// Same pairs in the same order; times agree to what round-off grows to in a chaotic
/// gas over a few collisions per particle.
fn assert_same(reference: &[(u32, u32, f64)], got: &[(u32, u32, f64)], what: &str) {
    for (k, (a, b)) in reference.iter().zip(got).enumerate() {
        assert_eq!(
            (a.0, a.1),
            (b.0, b.1),
            "{what}, collision {k}: {a:?} vs {b:?}"
        );
        assert!(
            (a.2 - b.2).abs() < 1e-7 * a.2.max(1.0),
            "{what}, collision {k}: {a:?} vs {b:?}"
        );
    }
}

#[test]
fn collision_sequence_equals_the_brute_force_reference() {
    // N = 108 in a box 7 cells wide (interior and border cells) and N = 32 in a box of
    // three cells, where every neighbour cell is reached through a periodic image.
    for (cells, density, count) in [(3, 0.2, 150), (2, 0.15, 150)] {
        let setup = fcc(cells, density, 1.0, 1.0, 1.0, 17);
        let reference = brute_force(&setup, count);
        let physics = || Physics::hard_spheres(1.0);
        let (p, d) = &setup;
        let heap: Engine<IndexedHeap> = Engine::new(p, d, physics()).unwrap();
        assert_same(&reference, &engine_collisions(heap, count), "heap");
        let calendar: Engine<CalendarQueue> = Engine::new(p, d, physics()).unwrap();
        assert_same(&reference, &engine_collisions(calendar, count), "calendar");
        let mut resorted: Engine = Engine::new(p, d, physics()).unwrap();
        resorted.set_resort_interval(53);
        assert_same(&reference, &engine_collisions(resorted, count), "re-sorted");
    }
}

#[test]
fn neighbour_lists_give_the_brute_force_collision_sequence() {
    // As above, and a dense gas (η ≈ 0.42, N = 108 in a box of 5.1σ) where every list
    // reaches across the periodic faces and particles leave their shells often.
    for (cells, density, count) in [(3, 0.2, 150), (2, 0.15, 150), (3, 0.8, 300)] {
        let setup = fcc(cells, density, 1.0, 1.0, 1.0, 17);
        let reference = brute_force(&setup, count);
        let physics = || Physics::hard_spheres(1.0);
        let (p, d) = &setup;
        let lists = || Engine::with_broad_phase(p, d, physics(), BroadPhaseKind::Neighbours);
        let plain: Engine = lists().unwrap();
        assert_same(&reference, &engine_collisions(plain, count), "lists");
        let mut resorted: Engine = lists().unwrap();
        resorted.set_resort_interval(53);
        let got = engine_collisions_of(&mut resorted, count);
        assert_same(&reference, &got, "lists, re-sorted");
        // Shell events (counted as crossings) and re-sorts both happened.
        let stats = resorted.stats();
        assert!(stats.resorts > 0 && stats.crossings > 0, "{stats:?}");
    }
}

#[test]
fn epochs_give_the_brute_force_collision_sequence_in_a_dilute_gas() {
    // η ≈ 0.003: the mean free path exceeds the box, so spheres wrap around many times
    // between collisions; one sphere flies 20 times faster than the rest, so that its
    // swept box must end early (a renewal before the epoch's end).
    let mut setup = fcc(3, 0.005, 1.0, 1.0, 1.0, 5);
    let rms = (setup
        .0
        .velocity
        .iter()
        .flatten()
        .map(|v| v * v)
        .sum::<f64>()
        / setup.0.velocity.len() as f64)
        .sqrt();
    setup.0.velocity[0] = [20.0 * rms / 3f64.sqrt(); 3];
    // Round-off grows so fast here (a near-grazing collision near the 55th) that
    // crossings and the brute force also part after about 50 collisions.
    let count = 45;
    let reference = brute_force(&setup, count);
    let physics = || Physics::hard_spheres(1.0);
    let (p, d) = &setup;
    let mut e: Engine = Engine::with_broad_phase(p, d, physics(), BroadPhaseKind::Epochs).unwrap();
    let mut got = vec![];
    while got.len() < count {
        if let Event::Collision(i, j) = e.step().unwrap() {
            got.push((i.min(j), i.max(j), e.time()));
        }
    }
    assert_same(&reference, &got, "epochs");
    let s = e.stats();
    assert!(s.epochs > 10 && s.crossings > 0, "{s:?}");
    // The automatic choice takes epochs here and crossings in a dense gas.
    let auto: Engine = Engine::new(p, d, physics()).unwrap();
    assert!(auto.stats().epochs > 0);
    let (p, d) = fcc(3, 0.5, 1.0, 1.0, 1.0, 5);
    let dense: Engine = Engine::new(&p, &d, physics()).unwrap();
    assert_eq!(dense.stats().epochs, 0);
}

#[test]
fn epochs_and_crossings_give_the_brute_force_sequence_of_a_polydisperse_gas() {
    // Diameters 0.5-1.5 and masses as their cubes, at η ≈ 0.01: unequal swept boxes,
    // contact distances and impulses in both broad phases.
    let mut setup = fcc(3, 0.01, 1.0, 1.0, 1.0, 23);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for i in 0..setup.0.len() {
        let diameter = 0.5 + rng.random::<f64>();
        setup.0.radius[i] = 0.5 * diameter;
        setup.0.mass[i] = diameter.powi(3);
    }
    let count = 60;
    let reference = brute_force(&setup, count);
    let physics = || Physics::hard_spheres(1.0);
    for broad_phase in [BroadPhaseKind::Epochs, BroadPhaseKind::Crossings] {
        let e: Engine =
            Engine::with_broad_phase(&setup.0, &setup.1, physics(), broad_phase).unwrap();
        assert_same(
            &reference,
            &engine_collisions(e, count),
            &format!("{broad_phase:?}"),
        );
    }
}
