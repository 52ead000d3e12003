//! Unit tests of the event loop that need access to its internals.

use crate::setup::{Physics, Setup};
use crate::{Engine, Event};

fn line(x: &[f64], v: &[f64]) -> Setup {
    let n = x.len();
    Setup {
        position: x.iter().map(|&x| [x, 0.0, 0.0]).collect(),
        velocity: v.iter().map(|&v| [v, 0.0, 0.0]).collect(),
        radius: vec![0.5; n],
        mass: vec![1.0; n],
        species: vec![0; n],
        ..Default::default()
    }
}

/// Bannerman et al. 2014, Figs. 4 and 6: B and C overlap by round-off and recede
/// slowly; A hits B before the overlap has healed, so B now approaches C while they
/// overlap. Algorithm 1 executes a stabilising B–C collision at once and all three
/// separate; without it B would run through C.
#[test]
fn three_body_overlap_resolves_by_a_stabilising_collision() {
    let mut e: Engine = Engine::new(
        line(&[-2.0, 0.0, 1.5], &[10.0, 0.0, 1e-7]),
        Physics::HardSpheres { restitution: 1.0 },
    )
    .unwrap();
    // The invalid state of Fig. 4: C overlapping B by 1e-7 σ, receding at 1e-7.
    e.pos[2][0] = 1.0 - 1e-7;
    for i in 0..3 {
        e.predict(i);
    }
    let mut collisions = vec![];
    while e.time() < 1.0 && collisions.len() < 10 {
        match e.step().unwrap() {
            Event::Collision(i, j) => collisions.push((i.min(j), i.max(j), e.time())),
            _ => continue,
        }
        if e.queue_is_empty_of_collisions() {
            break;
        }
    }
    assert_eq!(collisions.len(), 2, "{collisions:?}");
    assert_eq!((collisions[0].0, collisions[0].1), (0, 1));
    assert!((collisions[0].2 - 0.1).abs() < 1e-14);
    // The stabilising collision happens at the same instant.
    assert_eq!((collisions[1].0, collisions[1].1), (1, 2));
    assert_eq!(collisions[1].2, collisions[0].2);
    assert_eq!(e.stats().stabilising, 1);
    e.run_until(1.0).unwrap();
    e.sync();
    let v: Vec<f64> = e.velocities().iter().map(|v| v[0]).collect();
    assert!(v[0].abs() < 1e-12 && (v[1] - 1e-7).abs() < 1e-12 && (v[2] - 10.0).abs() < 1e-12);
    // The overlap has healed: C is far ahead of B.
    let x: Vec<f64> = e.positions().iter().map(|p| p[0]).collect();
    assert!(x[2] - x[1] > 1.0, "{x:?}");
}

#[test]
fn without_the_stabilising_rule_the_pair_would_pass_through() {
    // The same geometry checked with the textbook root: the overlapped, approaching
    // pair has a negative first root, i.e. no future event at all.
    let (r, v, sigma) = (1.0 - 1e-7, -10.0f64, 1.0f64);
    let disc = (r * v) * (r * v) - v * v * (r * r - sigma * sigma);
    let textbook = (-(r * v) - disc.sqrt()) / (v * v);
    assert!(textbook < 0.0);
    assert_eq!(
        crate::detect::sphere_sphere([r, 0.0, 0.0], [v, 0.0, 0.0], sigma),
        0.0
    );
}

impl Engine {
    fn queue_is_empty_of_collisions(&self) -> bool {
        (0..self.len()).all(|i| !self.coll_time[i].is_finite() && !self.pending_time[i].is_finite())
    }
}
