//! Unit tests of the event loop that need access to its internals.

use super::EventEngine;
use crate::Event;
use crate::broad_phase::{Crossings, Epochs};
use crate::physics::Physics;
use emdstar_contact::vec3::{dot, sub};
use emdstar_system::{Domain, Particles};

fn line(x: &[f64], v: &[f64]) -> Particles {
    let n = x.len();
    Particles::from_columns(
        x.iter().map(|&x| [x, 0.0, 0.0]).collect(),
        v.iter().map(|&v| [v, 0.0, 0.0]).collect(),
        vec![0.5; n],
        vec![1.0; n],
        vec![0; n],
    )
    .unwrap()
}

/// Bannerman et al. 2014, Figs. 4 and 6: B and C overlap by round-off and recede
/// slowly; A hits B before the overlap has healed, so B now approaches C while they
/// overlap. Algorithm 1 executes a stabilising B–C collision at once and all three
/// separate; without it B would run through C.
#[test]
fn three_body_overlap_resolves_by_a_stabilising_collision() {
    let mut e: EventEngine<Crossings> = EventEngine::crossings(
        &line(&[-2.0, 0.0, 1.5], &[10.0, 0.0, 1e-7]),
        &Domain::default(),
        Physics::hard_spheres(1.0),
        0.0,
    )
    .unwrap();
    // The invalid state of Fig. 4: C overlapping B by 1e-7 σ, receding at 1e-7.
    e.state.slot[2].kin.pos[0] = 1.0 - 1e-7;
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

impl EventEngine<Crossings> {
    fn queue_is_empty_of_collisions(&self) -> bool {
        (0..self.len()).all(|i| {
            !self.state.slot[i].ev.coll_time.is_finite()
                && !self.state.slot[i].ev.pending_time.is_finite()
        })
    }
}

fn soft_pair() -> (Particles, Physics) {
    use crate::physics::Interference;
    use crate::rules::ExactMor;
    use emdstar_contact::Tangential;
    use emdstar_contact::{ForceLaw, LinearDashpot, Sphere};
    use emdstar_system::Interactions;
    let s = Sphere::from_density(0.1, 1140.0).unwrap();
    let law = ForceLaw::Linear(LinearDashpot::new(2000.0, 0.0).unwrap());
    let setup = Particles::from_columns(
        vec![[0.0, 0.0, 0.0], [0.25, 0.1, 0.0]],
        vec![[2.5, 0.0, 0.0], [-2.5, 0.0, 0.0]],
        vec![0.1; 2],
        vec![s.mass; 2],
        vec![0; 2],
    )
    .unwrap();
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, Tangential::None, &[s]).unwrap(),
        mor: Box::new(ExactMor),
        interference: Interference::HitOnly,
    };
    (setup, physics)
}

/// Between E^φ and E^v both partners move at the centre-of-mass velocity while
/// overlapping by l(1 − ε_r). If round-off makes that common velocity slightly
/// approaching, Algorithm 1 alone would fire a stabilising collision at once. The
/// engine skips pairs that share a transient (`in_shared_transient`).
#[test]
fn transient_partners_are_not_tested_against_each_other() {
    let (setup, physics) = soft_pair();
    let mut e: EventEngine<Crossings> =
        EventEngine::crossings(&setup, &Domain::default(), physics, 0.0).unwrap();
    while !matches!(e.step().unwrap(), Event::Collision(..)) {}
    let now = e.time();
    assert!(
        e.state.slot[0].ev.pending_time > now
            && e.state.slot[0].ev.pending_time == e.state.slot[1].ev.pending_time
    );
    // Round-off-sized approach between the partners.
    approach(&mut e, 1e-13);
    e.predict(0);
    e.predict(1);
    assert!(
        e.state.slot[0].ev.coll_time.is_infinite() && e.state.slot[1].ev.coll_time.is_infinite()
    );
    // The next events are the two E^v at t* + τ.
    let mut next = vec![];
    while next.len() < 2 {
        match e.step().unwrap() {
            Event::Crossing(_) => {}
            ev => next.push(ev),
        }
    }
    assert_eq!(next, vec![Event::Velocity(0), Event::Velocity(1)]);
    // Without the exclusion the same state collides at once.
    let (setup, physics) = soft_pair();
    let mut e: EventEngine<Crossings> =
        EventEngine::crossings(&setup, &Domain::default(), physics, 0.0).unwrap();
    while !matches!(e.step().unwrap(), Event::Collision(..)) {}
    approach(&mut e, 1e-13);
    e.state.slot[0].ev.partner = crate::collision::NONE;
    e.predict(0);
    assert!(
        e.state.slot[0].ev.coll_time < e.state.slot[0].ev.pending_time
            && e.state.slot[0].ev.coll_partner == 1
    );
}

/// Makes particles 0 and 1 approach along their line of centres by `speed`.
fn approach(e: &mut EventEngine<Crossings>, speed: f64) {
    let r = sub(e.state.slot[0].kin.pos, e.state.slot[1].kin.pos);
    let norm = dot(r, r).sqrt();
    for (k, rk) in r.iter().enumerate() {
        e.state.slot[0].kin.vel[k] -= 0.5 * speed * rk / norm;
        e.state.slot[1].kin.vel[k] += 0.5 * speed * rk / norm;
    }
}

/// A small periodic gas of hard spheres on a lattice, at rest apart from a few.
fn lattice_gas(side: usize) -> (Particles, Domain) {
    let n = side * side * side;
    let spacing = 4.0;
    let x: Vec<[f64; 3]> = (0..n)
        .map(|i| [i % side, i / side % side, i / (side * side)].map(|c| (c as f64 + 0.5) * spacing))
        .collect();
    let v: Vec<[f64; 3]> = (0..n)
        .map(|i| [1.0, -0.5, 0.25].map(|c| c * ((i * 7 % 5) as f64 - 2.0)))
        .collect();
    let particles = Particles::from_columns(x, v, vec![0.5; n], vec![1.0; n], vec![0; n]).unwrap();
    let size = side as f64 * spacing;
    let domain = Domain::periodic(emdstar_system::SimBox {
        lo: [0.0; 3],
        size: [size; 3],
        periodic: [true; 3],
    });
    (particles, domain)
}

/// Saves `engine` after a few events, spoils the decoded state with `spoil`, and
/// restores the result into a fresh engine from `build`: it must be refused (a
/// decoded checkpoint with a valid checksum may still be nonsense, and running it
/// would index out of bounds).
fn spoiled_restore_is_refused<B>(
    build: impl Fn() -> EventEngine<B>,
    spoil: impl Fn(&mut EventEngine<B>),
) -> String
where
    B: crate::broad_phase::BroadPhase + serde::Serialize + serde::de::DeserializeOwned,
{
    let mut e = build();
    for _ in 0..40 {
        e.step().unwrap();
    }
    let bytes = e.save_state();
    build()
        .restore_state(&bytes)
        .expect("the unspoilt state restores");
    let mut decoded: EventEngine<B> = postcard::from_bytes(&bytes).unwrap();
    spoil(&mut decoded);
    let spoilt = postcard::to_allocvec(&decoded).unwrap();
    let err = build()
        .restore_state(&spoilt)
        .expect_err("a spoilt state is refused");
    err.to_string()
}

#[test]
fn decoded_checkpoints_that_do_not_fit_the_config_are_refused() {
    let (particles, domain) = lattice_gas(5);
    let hard = || Physics::hard_spheres(1.0);
    let crossings = || EventEngine::crossings(&particles, &domain, hard(), 0.0).unwrap();
    let epochs = || EventEngine::<Epochs>::epochs(&particles, &domain, hard()).unwrap();
    // The fuzzing finding: no spins although the gas has particles.
    let err = spoiled_restore_is_refused(epochs, |e| e.state.spin.clear());
    assert!(err.contains("per-particle arrays"), "{err}");
    let err = spoiled_restore_is_refused(crossings, |e| e.state.id[3] = e.state.id[5]);
    assert!(err.contains("missing or repeated"), "{err}");
    let err = spoiled_restore_is_refused(crossings, |e| e.state.slot[2].ev.partner = 1 << 20);
    assert!(err.contains("differs from the config"), "{err}");
    let err = spoiled_restore_is_refused(crossings, |e| e.state.mass[0] *= 2.0);
    assert!(err.contains("differs from the config"), "{err}");
    // A queue whose lists or heap no longer hold every particle once.
    let err = spoiled_restore_is_refused(crossings, |e| {
        e.state.queue = <crate::CalendarQueue as crate::queue::EventQueue>::new(e.state.len() - 1)
    });
    assert!(err.contains("calendar queue"), "{err}");
    // Cell lists: a particle taken out of its cell without being put anywhere else.
    let err = spoiled_restore_is_refused(crossings, |e| e.broad.grid.remove(7));
    assert!(err.contains("in no cell"), "{err}");
    // An epoch grid with a box fewer than particles.
    let err = spoiled_restore_is_refused(epochs, |e| e.broad.grid.spans.pop().map(drop).unwrap());
    assert!(err.contains("epoch grid"), "{err}");
}

/// A ball dropped onto a floor under gravity with ε = 0.8 bounces ever lower; its
/// flights shrink geometrically to one ulp of the time each (the inelastic collapse of
/// Bannerman et al. 2014, Sec. 5: time stands still in all but round-off). The engine
/// must stop with the collapse named and the hybrid offered, not run for ever (as it
/// did while only events at exactly the same time counted).
#[test]
fn a_ball_coming_to_rest_on_a_floor_stops_as_an_inelastic_collapse() {
    let (radius, height, g, eps) = (0.005, 0.045, 9.81, 0.8);
    let p = Particles::from_columns(
        vec![[0.0, 0.0, radius + height]],
        vec![[0.0; 3]],
        vec![radius],
        vec![1.3e-3],
        vec![0],
    )
    .unwrap();
    let domain = Domain {
        walls: vec![emdstar_system::Wall {
            normal: [0.0, 0.0, 1.0],
            point: [0.0; 3],
            vibration: None,
        }],
        gravity: [0.0, 0.0, -g],
        ..Domain::default()
    };
    let mut e: EventEngine<Crossings> =
        EventEngine::crossings(&p, &domain, Physics::hard_spheres(eps), 0.0).unwrap();
    let err = e.run_until(100.0).unwrap_err().to_string();
    assert!(
        err.contains("inelastic collapse") && err.contains("--engine hybrid"),
        "{err}"
    );
    // It comes to rest after the fall and the geometric series of bounces:
    // t = √(2h/g) (1 + 2ε/(1 − ε)).
    let t_rest = (2.0 * height / g).sqrt() * (1.0 + 2.0 * eps / (1.0 - eps));
    assert!(
        (e.time() - t_rest).abs() < 1e-8 * t_rest,
        "{} vs {t_rest}",
        e.time()
    );
}
