//! Starting states and runs shared by the integration tests.
// Each test binary uses part of it.
#![allow(dead_code)]

use emdstar_edmd::{BroadPhaseKind, Engine, Event, Physics, Stats};
use emdstar_system::{Domain, Particles, SimBox, Wall, fcc_gas};

/// 4·cells³ spheres of diameter `sigma` and mass `mass` on an fcc lattice in a periodic
/// cube at number density `density` (in the units of `sigma`), Maxwell velocities with
/// kT = `kt`.
pub fn fcc(
    cells: usize,
    density: f64,
    sigma: f64,
    mass: f64,
    kt: f64,
    seed: u64,
) -> (Particles, Domain) {
    let eta = density * std::f64::consts::PI / 6.0 * sigma.powi(3);
    // Σ ½mv² = (3/2)NkT: the rms speed is √(3kT/m).
    fcc_gas(
        cells,
        eta,
        0.5 * sigma,
        mass,
        (3.0 * kt / mass).sqrt(),
        seed,
    )
    .expect("a valid fcc gas")
}

/// [`fcc`] of unit spheres in a closed box: the periodic cube's axes closed by six walls
/// half a diameter outside it.
pub fn walled_fcc(cells: usize, density: f64, seed: u64) -> (Particles, Domain) {
    let mut setup = fcc(cells, density, 1.0, 1.0, 1.0, seed);
    let region = setup.1.sim_box.expect("fcc gives a box");
    setup.1.sim_box = Some(SimBox {
        periodic: [false; 3],
        ..region
    });
    for k in 0..3 {
        for (side, sign) in [(region.lo[k], 1.0), (region.lo[k] + region.size[k], -1.0)] {
            let mut normal = [0.0; 3];
            normal[k] = sign;
            let mut point = [0.0; 3];
            point[k] = side - sign * 0.5;
            setup.1.walls.push(Wall::fixed(normal, point));
        }
    }
    setup
}

/// The first `n` pair and wall collisions of elastic hard spheres on `broad_phase`,
/// as (i, j or u32::MAX − wall, time), and the engine's statistics then.
pub fn first_collisions(
    setup: &(Particles, Domain),
    broad_phase: BroadPhaseKind,
    n: usize,
) -> (Vec<(u32, u32, f64)>, Stats) {
    let physics = Physics::hard_spheres(1.0);
    let mut e: Engine = Engine::with_broad_phase(&setup.0, &setup.1, physics, broad_phase)
        .expect("an engine for a valid gas");
    let mut out = vec![];
    while out.len() < n {
        match e.step().expect("an event") {
            Event::Collision(i, j) => out.push((i.min(j), i.max(j), e.time())),
            Event::Wall(i, w) => out.push((i, u32::MAX - w, e.time())),
            _ => {}
        }
    }
    (out, *e.stats())
}

/// The same collisions in the same order, at times equal to 1e-9 (relative).
pub fn assert_same_collisions(a: &[(u32, u32, f64)], b: &[(u32, u32, f64)]) {
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!((x.0, x.1), (y.0, y.1), "event {k}: {x:?} {y:?}");
        assert!(
            (x.2 - y.2).abs() < 1e-9 * x.2.max(1.0),
            "event {k}: {x:?} {y:?}"
        );
    }
}
