//! The neighbour-list broad phase in dense hard-sphere gases: the collision rate against
//! the Carnahan–Starling equation of state, the cell engine's collisions between walls,
//! inelastic stability, determinism, restarts, and which inputs it refuses.

mod common;

use common::{assert_same_collisions, fcc, first_collisions, walled_fcc};
use emdstar_edmd::{BroadPhaseKind, Engine, EngineError, Physics};

fn elastic() -> Physics {
    Physics::hard_spheres(1.0)
}

/// Enskog's mean free time 1/(4ρσ²g(σ)√(πkT/m)) with the Carnahan–Starling contact
/// value g(σ) = (1 − η/2)/(1 − η)³ (Carnahan & Starling 1969; Hansen & McDonald,
/// Sec. 3.9): exact for hard spheres given the true contact value, which CS gives to
/// about 0.5 % at η = 0.45.
fn enskog_cs_mean_free_time(density: f64) -> f64 {
    let eta = std::f64::consts::PI / 6.0 * density;
    let g = (1.0 - 0.5 * eta) / (1.0 - eta).powi(3);
    1.0 / (4.0 * density * g * std::f64::consts::PI.sqrt())
}

/// N = 500 elastic hard spheres at η = 0.45 (ρσ³ = 0.859), kT = 1: the automatic choice
/// takes neighbour lists, and the mean free time matches Enskog–Carnahan–Starling.
#[test]
fn dense_mean_free_time_matches_carnahan_starling() {
    let density = 0.45 * 6.0 / std::f64::consts::PI;
    let setup = fcc(5, density, 1.0, 1.0, 1.0, 23);
    let n = setup.0.len() as f64;
    let mut e: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
    assert_eq!(e.broad_phase(), BroadPhaseKind::Neighbours);
    e.run_collisions(50_000).unwrap();
    let (t0, c0) = (e.time(), e.stats().collisions());
    e.run_collisions(300_000).unwrap();
    let (t1, c1) = (e.time(), e.stats().collisions());
    let mft = (t1 - t0) * n / (2.0 * (c1 - c0) as f64);
    let reference = enskog_cs_mean_free_time(density);
    eprintln!("mean free time {mft}, Enskog-CS {reference}");
    assert!((mft / reference - 1.0).abs() < 0.02, "{mft} vs {reference}");
    assert!(e.stats().max_impact_overlap < 1e-12);
}

/// A dense gas in a closed box with six walls: the lists give the cell engine's pair
/// and wall collisions.
#[test]
fn lists_agree_with_crossings_between_walls() {
    let setup = walled_fcc(4, 0.6, 29);
    let (a, sa) = first_collisions(&setup, BroadPhaseKind::Crossings, 400);
    let (b, sb) = first_collisions(&setup, BroadPhaseKind::Neighbours, 400);
    assert_same_collisions(&a, &b);
    assert!(sb.wall_collisions > 20 && sb.crossings > 20, "{sb:?}");
    assert_eq!(
        (sa.pair_collisions, sa.wall_collisions),
        (sb.pair_collisions, sb.wall_collisions)
    );
}

/// Inelastic spheres (ε = 0.8) cluster: overlaps stay at round-off on the lists too.
#[test]
fn inelastic_overlaps_never_grow_on_lists() {
    let setup = fcc(6, 0.6, 1.0, 1.0, 1.0, 9);
    let physics = Physics::hard_spheres(0.8);
    let mut e: Engine =
        Engine::with_broad_phase(&setup.0, &setup.1, physics, BroadPhaseKind::Neighbours).unwrap();
    e.run_collisions(200_000).unwrap();
    assert!(e.stats().max_impact_overlap < 1e-12, "{:?}", e.stats());
}

/// Same input, same events, bit for bit; re-sorting (a renumbering) changes nothing.
#[test]
fn lists_are_deterministic_and_independent_of_resorting() {
    let setup = fcc(7, 0.7, 1.0, 1.0, 1.0, 31);
    let run = |resort: u64| {
        let mut e: Engine =
            Engine::with_broad_phase(&setup.0, &setup.1, elastic(), BroadPhaseKind::Neighbours)
                .unwrap();
        e.set_resort_interval(resort);
        e.run_collisions(30_000).unwrap();
        e.sync();
        (e.time(), e.positions(), e.velocities(), e.stats().resorts)
    };
    let (a, b, c) = (run(0), run(0), run(997));
    assert_eq!((a.0, &a.1, &a.2), (b.0, &b.1, &b.2));
    assert_eq!((a.0, &a.1, &a.2), (c.0, &c.1, &c.2));
    // Both re-sort once at the start (N ≥ 1000), the second every 997 events after.
    assert!(c.3 > a.3 + 10, "{} {}", c.3, a.3);
}

/// Refused with a clear error: gravity, eMD*'s physics aside, a periodic box narrower
/// than 4.5 contact distances.
#[test]
fn lists_refuse_what_they_cannot_run() {
    let refused =
        |setup: &(emdstar_system::Particles, emdstar_system::Domain)| match Engine::<
            emdstar_edmd::CalendarQueue,
        >::with_broad_phase(
            &setup.0,
            &setup.1,
            elastic(),
            BroadPhaseKind::Neighbours,
        ) {
            Err(EngineError::Invalid(msg)) => msg.contains("neighbour-list"),
            _ => false,
        };
    let mut heavy = fcc(4, 0.6, 1.0, 1.0, 1.0, 3);
    heavy.1.gravity = [0.0, 0.0, -1.0];
    assert!(refused(&heavy));
    // N = 32 at ρσ³ = 0.8: a box of 3.4σ.
    let small = fcc(2, 0.8, 1.0, 1.0, 1.0, 3);
    assert!(refused(&small));
    // The automatic choice falls back to cells there.
    let e: Engine = Engine::new(&small.0, &small.1, elastic()).unwrap();
    assert_eq!(e.broad_phase(), BroadPhaseKind::Crossings);
}

/// A dense gas saved in mid-run and restored into a fresh engine continues bitwise as
/// the uninterrupted run.
#[test]
fn a_restored_dense_gas_continues_bitwise() {
    use emdstar_system::Simulation;
    let setup = fcc(6, 0.7, 1.0, 1.0, 1.0, 37);
    let engine = || -> Engine {
        Engine::with_broad_phase(&setup.0, &setup.1, elastic(), BroadPhaseKind::Neighbours).unwrap()
    };
    let t_end = 3.0;
    let mut straight = engine();
    straight.advance_to(t_end).unwrap();
    let mut first = engine();
    first.advance_to(0.5 * t_end).unwrap();
    let saved = first.save_state();
    let mut resumed = engine();
    resumed.restore_state(&saved).unwrap();
    assert_eq!(resumed.save_state(), saved);
    resumed.advance_to(t_end).unwrap();
    assert_eq!(straight.particles(), resumed.particles());
    assert_eq!(straight.stats(), resumed.stats());
    assert!(straight.stats().crossings > 1000, "{:?}", straight.stats());
}

/// Spheres whose radii differ by more than a factor of two are refused (every list would
/// be as long as the large spheres'), and the automatic choice keeps cells for them.
#[test]
fn lists_refuse_widely_different_radii() {
    // One sphere in eight shrunk to a fifth: η ≈ 0.43, dense enough for lists.
    let mut mixed = fcc(5, 0.95, 1.0, 1.0, 1.0, 41);
    for r in mixed.0.radius.iter_mut().step_by(8) {
        *r = 0.1;
    }
    let lists = Engine::<emdstar_edmd::CalendarQueue>::with_broad_phase(
        &mixed.0,
        &mixed.1,
        elastic(),
        BroadPhaseKind::Neighbours,
    );
    assert!(matches!(lists, Err(EngineError::Invalid(m)) if m.contains("factor of two")));
    let e: Engine = Engine::new(&mixed.0, &mixed.1, elastic()).unwrap();
    assert_eq!(e.broad_phase(), BroadPhaseKind::Crossings);
}
