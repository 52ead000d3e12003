//! eMD* and eMD pair collisions against the exact two-body solution
//! (`emdstar_mor::rule::exact_collision`: scaling, exact MoR, lab-frame rule).

use emdstar_contact::Tangential;
use emdstar_contact::{
    ForceLaw, LinearDashpot, PairLaw, PairProperties, Sphere, Vec3, ViscoelasticHertz,
};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{Engine, Event, Interference, Physics};
use emdstar_mor::rule::{Body, exact_collision};
use emdstar_system::Interactions;
use emdstar_system::{Domain, Particles};

use emdstar_contact::vec3::from_na as arr;

/// Two spheres whose relative velocity has eccentricity `e` at contact, started a
/// gap `gap` before it; returns the setup and the contact time (textbook root,
/// independent of the engine's Algorithm 1).
fn approach(spheres: [Sphere; 2], speed: f64, e: f64, gap: f64) -> (Particles, f64) {
    let l = spheres[0].radius + spheres[1].radius;
    // At contact: r = l·x̂, v_rel = speed·(−√(1−e²), e, 0); run backwards by t0.
    let v_rel = [-speed * (1.0 - e * e).sqrt(), speed * e, 0.0];
    let t0 = gap / speed;
    let r_contact = [l, 0.0, 0.0];
    let r_start: [f64; 3] = std::array::from_fn(|k| r_contact[k] - v_rel[k] * t0);
    let total = spheres[0].mass + spheres[1].mass;
    let drift = [0.3, -0.1, 0.2];
    let (w1, w2) = (spheres[1].mass / total, -spheres[0].mass / total);
    let origin = [1.0, 2.0, 3.0];
    let setup = Particles::from_columns(
        vec![
            std::array::from_fn(|k| origin[k] + w1 * r_start[k]),
            std::array::from_fn(|k| origin[k] + w2 * r_start[k]),
        ],
        vec![
            std::array::from_fn(|k| drift[k] + w1 * v_rel[k]),
            std::array::from_fn(|k| drift[k] + w2 * v_rel[k]),
        ],
        vec![spheres[0].radius, spheres[1].radius],
        vec![spheres[0].mass, spheres[1].mass],
        vec![0, 1],
    )
    .unwrap();
    // Textbook first root of |r + v t| = l.
    let (a, b, c) = (
        v_rel.iter().map(|x| x * x).sum::<f64>(),
        2.0 * (0..3).map(|k| r_start[k] * v_rel[k]).sum::<f64>(),
        r_start.iter().map(|x| x * x).sum::<f64>() - l * l,
    );
    let t_contact = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    (setup, t_contact)
}

/// The exact state at `t_end` after the collision starting at `t_contact`.
fn exact_after(
    law: &ForceLaw,
    spheres: [Sphere; 2],
    setup: &Particles,
    t_contact: f64,
    t_end: f64,
) -> ([[f64; 3]; 2], [[f64; 3]; 2], f64) {
    let pair = PairProperties::spheres(&spheres[0], &spheres[1]);
    let pair_law = PairLaw::same_material(law, pair.r_eff).unwrap();
    let bodies = [0, 1].map(|i| Body {
        position: Vec3::from(setup.position[i]) + Vec3::from(setup.velocity[i]) * t_contact,
        velocity: Vec3::from(setup.velocity[i]),
        mass: setup.mass[i],
    });
    let (out, _) = exact_collision(&pair_law, &pair, &bodies).unwrap();
    let free = t_end - t_contact - out.duration;
    assert!(free > 0.0);
    (
        [0, 1].map(|i| arr(&(out.after[i].position + out.after[i].velocity * free))),
        [0, 1].map(|i| arr(&out.after[i].velocity)),
        out.duration,
    )
}

fn emdstar_with(law: &ForceLaw, spheres: [Sphere; 2], mor: Box<dyn MorSource>) -> Physics {
    Physics::EmdStar {
        interactions: Interactions::of_spheres(law, Tangential::None, &spheres).unwrap(),
        mor,
        interference: Interference::HitOnly,
    }
}

fn laws() -> Vec<(ForceLaw, f64)> {
    vec![
        // Müller & Pöschel 2013, Fig. 6: k = 2 kN/m, R = 0.1 m, ρ = 1140 kg/m³, v = 5 m/s.
        (
            ForceLaw::Linear(LinearDashpot::new(2000.0, 0.0).unwrap()),
            5.0,
        ),
        (
            ForceLaw::Linear(LinearDashpot::new(2000.0, 2.0).unwrap()),
            5.0,
        ),
        (
            ForceLaw::Hertz(ViscoelasticHertz::new(1e7, 0.4, 1e-4).unwrap()),
            2.0,
        ),
    ]
}

fn spheres(unequal: bool) -> [Sphere; 2] {
    let a = Sphere::from_density(0.1, 1140.0).unwrap();
    let b = if unequal {
        Sphere::from_density(0.07, 2500.0).unwrap()
    } else {
        a
    };
    [a, b]
}

/// Largest error of eMD* pair collisions against the exact solution, relative to the
/// radius (positions) and the impact speed (velocities), over laws, masses and
/// eccentricities.
fn largest_pair_error(
    source: impl Fn(&ForceLaw) -> Box<dyn MorSource>,
    include: impl Fn(&ForceLaw, f64) -> bool,
) -> f64 {
    let mut worst: f64 = 0.0;
    for (law, speed) in laws() {
        for unequal in [false, true] {
            for e in [0.0, 0.3, 0.8] {
                if !include(&law, e) {
                    continue;
                }
                let sp = spheres(unequal);
                let (setup, t_contact) = approach(sp, speed, e, 0.01);
                let physics = emdstar_with(&law, sp, source(&law));
                let mut engine: Engine = Engine::new(&setup, &Domain::default(), physics).unwrap();
                let mut kinds = vec![];
                while engine.stats().velocity_events < 2 {
                    match engine.step().unwrap() {
                        Event::Crossing(_) => {}
                        ev => kinds.push((ev, engine.time())),
                    }
                }
                // E^φ at contact, then two E^v at t* + τ.
                assert!(matches!(kinds[0].0, Event::Collision(..)), "{kinds:?}");
                assert!((kinds[0].1 - t_contact).abs() < 1e-12);
                let t_end = kinds[2].1 + 0.05;
                engine.run_until(t_end).unwrap();
                engine.sync();
                let (x, v, tau) = exact_after(&law, sp, &setup, t_contact, t_end);
                worst = worst.max((kinds[2].1 - t_contact - tau).abs() / tau);
                for i in 0..2 {
                    for k in 0..3 {
                        let dx = (engine.positions()[i][k] - x[i][k]).abs();
                        let dv = (engine.velocities()[i][k] - v[i][k]).abs() / speed;
                        worst = worst.max(dx / 0.1).max(dv);
                    }
                }
            }
        }
    }
    worst
}

#[test]
fn emdstar_pair_collisions_equal_the_exact_solution() {
    // Round-off: both use the same exact MoR; the engine adds detection and the
    // delayed free flights.
    let worst = largest_pair_error(|_| Box::new(ExactMor), |_, _| true);
    assert!(worst < 1e-12, "largest relative error {worst:e}");
    eprintln!("largest eMD* pair error, exact MoR (relative to R and v): {worst:e}");
}

/// The default tables hold the MoR to 1e-6 over their physical boxes (`emdstar table
/// check`). The linear table stops short of the pass-through limit l̃ → 1 of
/// near-central impacts (lω/v < 1.05): those are solved exactly and counted.
#[test]
fn emdstar_pair_collisions_with_tables_are_within_table_accuracy() {
    let table = |law: &ForceLaw| -> Box<dyn MorSource> {
        Box::new(TableMorSource::new(
            emdstar_table::default_table(law.model()).unwrap(),
            true,
        ))
    };
    let worst = largest_pair_error(table, |_, _| true);
    assert!(worst < 1e-5, "largest relative error {worst:e}");
    eprintln!("largest eMD* pair error, default tables (relative to R and v): {worst:e}");
}

#[test]
fn impacts_outside_the_table_are_errors_unless_the_exact_fallback_is_chosen() {
    // A very slow, very stiff impact: l̃ far beyond the Hertz box.
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e11, 0.3, 1e-6).unwrap());
    let sp = spheres(false);
    let (setup, _) = approach(sp, 1e-4, 0.5, 1e-6);
    let table = |fallback| {
        Box::new(TableMorSource::new(
            emdstar_table::default_table(law.model()).unwrap(),
            fallback,
        ))
    };
    let mut strict: Engine = Engine::new(
        &setup,
        &Domain::default(),
        emdstar_with(&law, sp, table(false)),
    )
    .unwrap();
    let err = strict
        .run_collisions(1)
        .expect_err("outside the table's box");
    assert!(err.to_string().contains("--mor exact"), "{err}");
    let mut lenient: Engine = Engine::new(
        &setup,
        &Domain::default(),
        emdstar_with(&law, sp, table(true)),
    )
    .unwrap();
    lenient.run_collisions(1).unwrap();
    assert_eq!(lenient.stats().mor_fallbacks, 1);
}

#[test]
fn emd_agrees_with_the_exact_velocities_only_for_central_impacts() {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e7, 0.4, 1e-4).unwrap());
    let sp = spheres(true);
    let materials = Interactions::of_spheres(&law, Tangential::None, &sp).unwrap();
    for (e, central) in [(0.0, true), (0.5, false)] {
        let (setup, t_contact) = approach(sp, 2.0, e, 0.01);
        let mut engine: Engine =
            Engine::new(&setup, &Domain::default(), Physics::Emd(materials.clone())).unwrap();
        engine.run_collisions(1).unwrap();
        engine.sync();
        let (_, v, _) = exact_after(&law, sp, &setup, t_contact, t_contact + 1.0);
        let err = (0..2)
            .flat_map(|i| (0..3).map(move |k| (i, k)))
            .map(|(i, k)| (engine.velocities()[i][k] - v[i][k]).abs() / 2.0)
            .fold(0.0, f64::max);
        if central {
            // ε(v_n) from the cached central solution: interpolation accuracy.
            assert!(err < 1e-7, "central eMD velocity error {err:e}");
            eprintln!("central eMD velocity error {err:e}");
        } else {
            // The contact normal turns during an oblique collision; eMD ignores that.
            assert!(err > 1e-2, "oblique eMD velocity error {err:e}");
            eprintln!("oblique eMD velocity error {err:e}");
        }
    }
}
