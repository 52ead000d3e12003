//! Hard-sphere gases: conservation laws, kinetic theory, cells against brute force,
//! stability of inelastic runs, and bad input.

mod common;

use common::{assert_same_collisions, fcc, first_collisions, walled_fcc};
use emdstar_edmd::{BroadPhaseKind, Engine, EngineError, Event, EventQueue, IndexedHeap, Physics};
use emdstar_system::{Domain, Particles, SimBox, SystemError, Wall};

fn elastic() -> Physics {
    Physics::hard_spheres(1.0)
}

fn energy_momentum(e: &Engine) -> (f64, [f64; 3]) {
    (e.kinetic_energy(), e.momentum())
}

#[test]
fn elastic_gas_conserves_energy_and_momentum() {
    let setup = fcc(5, 0.3, 1.0, 1.0, 1.0, 3);
    let mut e: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
    let (e0, p0) = energy_momentum(&e);
    e.run_collisions(100_000).unwrap();
    e.sync();
    let (e1, p1) = energy_momentum(&e);
    assert!(
        ((e1 - e0) / e0).abs() < 1e-10,
        "energy drift {}",
        (e1 - e0) / e0
    );
    for k in 0..3 {
        assert!((p1[k] - p0[k]).abs() < 1e-9, "momentum {p0:?} -> {p1:?}");
    }
    // Elastic spheres that started apart stay apart up to round-off.
    assert!(e.stats().max_impact_overlap < 1e-12);
}

/// N = 1372 elastic hard spheres from an FCC start at ρσ³ = 0.5 and kT = 1: the mean
/// free time is 0.13031 (the reference value of docs/physics.md; the Enskog estimate with the
/// Carnahan–Starling contact value, 1/(4ρσ²g(σ)√(πkT/m)) = 0.1310, is 0.5 % above it).
#[test]
fn mean_free_time_matches_the_reference() {
    let setup = fcc(7, 0.5, 1.0, 1.0, 1.0, 11);
    let n = setup.0.len() as f64;
    assert_eq!(n, 1372.0);
    let mut e: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
    e.run_collisions(100_000).unwrap();
    let (t0, c0) = (e.time(), e.stats().collisions());
    e.run_collisions(800_000).unwrap();
    let (t1, c1) = (e.time(), e.stats().collisions());
    // Each collision ends two free flights.
    let mft = (t1 - t0) * n / (2.0 * (c1 - c0) as f64);
    eprintln!("mean free time {mft} (reference 0.13031)");
    assert!((mft / 0.13031 - 1.0).abs() < 0.01, "mean free time {mft}");
}

/// A gas whose particle records outgrow a core's cache (16 384 particles, where the
/// engine asks for memory ahead of use): cell crossings find the collisions that
/// epochs find by another route, in the same order.
#[test]
fn a_large_gas_on_cells_agrees_with_epochs() {
    let setup = fcc(16, 0.1, 1.0, 1.0, 1.0, 13);
    assert_eq!(setup.0.len(), 16_384);
    let (cells, _) = first_collisions(&setup, BroadPhaseKind::Crossings, 20_000);
    let (epochs, _) = first_collisions(&setup, BroadPhaseKind::Epochs, 20_000);
    assert_same_collisions(&cells, &epochs);
}

/// The same size dense (η = 0.45), where neighbour lists ask for the lists of the
/// particles whose events come next: they find the collisions of cell crossings.
#[test]
fn a_large_dense_gas_on_lists_agrees_with_cells() {
    let density = 0.45 * 6.0 / std::f64::consts::PI;
    let setup = fcc(16, density, 1.0, 1.0, 1.0, 17);
    assert_eq!(setup.0.len(), 16_384);
    let (cells, _) = first_collisions(&setup, BroadPhaseKind::Crossings, 20_000);
    let (lists, stats) = first_collisions(&setup, BroadPhaseKind::Neighbours, 20_000);
    assert_same_collisions(&cells, &lists);
    assert!(stats.crossings > 100, "shells reached: {}", stats.crossings);
}

#[test]
fn cells_agree_with_one_big_cell() {
    // A dilute gas where a 4×4×4 grid and a single cell must give the same events.
    let setup = fcc(4, 0.1, 1.0, 1.0, 1.0, 5);
    let side = setup.1.sim_box.unwrap().size[0];
    let fine_setup = setup.clone();
    let mut fine: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
    let mut coarse: Engine = Engine::with_cell_width(&setup.0, &setup.1, elastic(), side).unwrap();
    fn collisions<Q: EventQueue>(e: &mut Engine<Q>, count: usize) -> Vec<(u32, u32, f64)> {
        let mut out = vec![];
        while out.len() < count {
            if let Event::Collision(i, j) = e.step().unwrap() {
                out.push((i.min(j), i.max(j), e.time()));
            }
        }
        out
    }
    // Frequent spatial re-sorting renumbers slots but must not change the physics.
    let mut resorted: Engine = Engine::new(&fine_setup.0, &fine_setup.1, elastic()).unwrap();
    resorted.set_resort_interval(97);
    // The calendar queue (the default) must give exactly the heap's event order.
    let mut heap: Engine<IndexedHeap> =
        Engine::new(&fine_setup.0, &fine_setup.1, elastic()).unwrap();
    let a = collisions(&mut fine, 300);
    let b = collisions(&mut coarse, 300);
    let c = collisions(&mut resorted, 300);
    assert_eq!(collisions(&mut heap, 300), a);
    assert!(resorted.stats().resorts > 5);
    for (k, ((x, y), z)) in a.iter().zip(&b).zip(&c).enumerate() {
        assert_eq!((x.0, x.1), (y.0, y.1), "collision {k}: {x:?} {y:?}");
        assert!((x.2 - y.2).abs() < 1e-9 * x.2.max(1.0), "{x:?} {y:?}");
        assert_eq!((x.0, x.1), (z.0, z.1), "collision {k}: {x:?} {z:?}");
        assert!((x.2 - z.2).abs() < 1e-9 * x.2.max(1.0), "{x:?} {z:?}");
    }
    assert!(fine.stats().crossings > 0 && coarse.stats().crossings > 0);
}

/// Inelastic hard spheres (ε = 0.8) cool and cluster, which makes round-off overlaps
/// and three-body events frequent (Bannerman 2014, Figs. 3 and 5). With the stable
/// algorithm no overlap may grow beyond round-off. (CI size; `emdstar bench edmd`
/// runs the N = 13500 version.)
#[test]
fn inelastic_overlaps_never_grow() {
    for (broad_phase, collisions) in [
        (BroadPhaseKind::Crossings, 300_000),
        (BroadPhaseKind::Epochs, 100_000),
    ] {
        let setup = fcc(8, 0.2, 1.0, 1.0, 1.0, 9);
        let physics = Physics::hard_spheres(0.8);
        let mut e: Engine =
            Engine::with_broad_phase(&setup.0, &setup.1, physics, broad_phase).unwrap();
        e.run_collisions(collisions).unwrap();
        let s = e.stats();
        assert!(
            s.max_impact_overlap < 1e-12,
            "{broad_phase:?}: {}",
            s.max_impact_overlap
        );
        // Impacts land on both sides of σ (Fig. 3): some overlap, some stop short.
        let h = s.separation_histogram;
        assert!(
            h[..8].iter().sum::<u64>() > 0 && h[9..].iter().sum::<u64>() > 0,
            "{broad_phase:?}: {h:?}"
        );
    }
}

/// A dilute gas in a closed box with six walls: epochs (closed axes, border cells
/// reaching to ±∞, wall predictions kept across epochs) give the crossing engine's
/// pair and wall collisions.
#[test]
fn epochs_agree_with_crossings_between_walls() {
    let setup = walled_fcc(4, 0.01, 13);
    let (a, sa) = first_collisions(&setup, BroadPhaseKind::Crossings, 400);
    let (b, sb) = first_collisions(&setup, BroadPhaseKind::Epochs, 400);
    assert_same_collisions(&a, &b);
    assert!(
        sb.epochs > 5 && sb.pair_collisions > 20 && sb.wall_collisions > 20,
        "{sb:?}"
    );
    assert_eq!(
        (sa.pair_collisions, sa.wall_collisions),
        (sb.pair_collisions, sb.wall_collisions)
    );
}

/// The automatic choice takes epochs only where the gas cannot spread out of the grid:
/// periodic axes, or closed axes held by walls from both sides (a closed axis without
/// them is refused at the set-up).
#[test]
fn automatic_broad_phase_takes_epochs_only_for_a_held_gas() {
    let periodic = fcc(4, 0.01, 1.0, 1.0, 1.0, 13);
    let region = periodic.1.sim_box.unwrap();
    let uses_epochs = |setup: &(Particles, Domain)| {
        let e: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
        e.stats().epochs > 0
    };
    assert!(uses_epochs(&periodic));
    let mut free = periodic.clone();
    free.1.sim_box = None;
    assert!(!uses_epochs(&free), "free space");
    let mut open_z = periodic.clone();
    open_z.1.sim_box = Some(SimBox {
        periodic: [true, true, false],
        ..region
    });
    let refused = |setup: &(Particles, Domain)| {
        Engine::<emdstar_edmd::IndexedHeap>::new(&setup.0, &setup.1, elastic())
            .err()
            .is_some_and(|e| e.to_string().contains("no wall holds"))
    };
    assert!(refused(&open_z), "closed z without walls");
    let floor = |sign: f64, z: f64| Wall {
        normal: [0.0, 0.0, sign],
        point: [0.0, 0.0, z],
        vibration: None,
    };
    let z = (region.lo[2], region.lo[2] + region.size[2]);
    open_z.1.walls.push(floor(1.0, z.0));
    assert!(refused(&open_z), "a floor but no lid");
    open_z.1.walls.push(floor(-1.0, z.1));
    assert!(uses_epochs(&open_z), "floor and lid");
}

#[test]
fn bad_input_gets_clear_errors() {
    let good = fcc(2, 0.3, 1.0, 1.0, 1.0, 1);
    let mut overlap = good.clone();
    overlap.0.position[1] = overlap.0.position[0];
    overlap.0.position[1][0] += 0.9;
    let err = Engine::<emdstar_edmd::IndexedHeap>::new(&overlap.0, &overlap.1, elastic())
        .err()
        .unwrap();
    assert!(
        matches!(err, EngineError::System(SystemError::Overlap { .. })),
        "{err}"
    );
    assert!(err.to_string().contains("move them apart"));

    let mut packed = good.clone();
    packed.1.sim_box = Some(SimBox {
        lo: [0.0; 3],
        size: [2.5; 3],
        periodic: [true; 3],
    });
    let err = Engine::<emdstar_edmd::IndexedHeap>::new(&packed.0, &packed.1, elastic())
        .err()
        .unwrap();
    assert!(matches!(err, EngineError::Packing { .. }), "{err}");

    let mut walled = good.clone();
    // A wall needs a closed axis across it (its periodic images would cut the box).
    if let Some(b) = &mut walled.1.sim_box {
        b.periodic[0] = false;
    }
    let x = walled.0.position[3];
    walled.1.walls.push(Wall {
        normal: [1.0, 0.0, 0.0],
        point: [x[0] - 0.2, 0.0, 0.0],
        vibration: None,
    });
    let b = walled.1.sim_box.unwrap();
    walled.1.walls.push(Wall {
        normal: [-1.0, 0.0, 0.0],
        point: [b.lo[0] + b.size[0], 0.0, 0.0],
        vibration: None,
    });
    let err = Engine::<emdstar_edmd::IndexedHeap>::new(&walled.0, &walled.1, elastic())
        .err()
        .unwrap();
    assert!(
        matches!(err, EngineError::System(SystemError::Misplaced { .. })),
        "{err}"
    );
    assert!(err.to_string().contains("wall 0"), "{err}");

    let bad_eps =
        Engine::<emdstar_edmd::IndexedHeap>::new(&good.0, &good.1, Physics::hard_spheres(1.5));
    assert!(bad_eps.err().unwrap().to_string().contains("[0, 1]"));

    let mut nan = good;
    nan.0.velocity[0][2] = f64::NAN;
    let err = Engine::<emdstar_edmd::IndexedHeap>::new(&nan.0, &nan.1, elastic())
        .err()
        .unwrap();
    assert!(err.to_string().contains("finite"));
}

#[test]
fn ball_between_walls_under_gravity_keeps_its_energy() {
    // One elastic ball bouncing on a floor in a closed box: E = ½mv² + mgz stays.
    let ball = Particles::from_columns(
        vec![[0.5, 0.5, 3.0]],
        vec![[0.3, -0.2, 0.0]],
        vec![0.5],
        vec![1.0],
        vec![0],
    )
    .unwrap();
    let domain = Domain {
        sim_box: Some(SimBox {
            lo: [0.0; 3],
            size: [4.0, 4.0, 10.0],
            periodic: [true, true, false],
        }),
        walls: vec![
            Wall {
                normal: [0.0, 0.0, 1.0],
                point: [0.0; 3],
                vibration: None,
            },
            // A lid the ball never reaches (it bounces up to z = 3).
            Wall {
                normal: [0.0, 0.0, -1.0],
                point: [0.0, 0.0, 10.0],
                vibration: None,
            },
        ],
        gravity: [0.0, 0.0, -9.81],
        ..Domain::default()
    };
    let setup = (ball, domain);
    let mut e: Engine = Engine::new(&setup.0, &setup.1, elastic()).unwrap();
    let energy = |e: &Engine| {
        let v = e.velocities()[0];
        0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) + 9.81 * e.positions()[0][2]
    };
    let e0 = energy(&e);
    e.run_collisions(200).unwrap();
    e.sync();
    assert!((energy(&e) / e0 - 1.0).abs() < 1e-9);
    // Bounce period 2√(2h/g) with drop height h = 2.5.
    let period = 2.0 * (2.0 * 2.5 / 9.81f64).sqrt();
    let expect = period * 199.5;
    assert!(
        (e.time() / expect - 1.0).abs() < 1e-9,
        "{} {expect}",
        e.time()
    );
    assert!(e.positions()[0][2] >= 0.5 - 1e-9);
}
