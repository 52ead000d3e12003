//! eMD* gases: conservation with exceptions, both interference variants.

use emdstar_contact::Tangential;
use emdstar_contact::{ForceLaw, Sphere, ViscoelasticHertz};
use emdstar_edmd::rules::ExactMor;
use emdstar_system::Interactions;
mod common;

use common::fcc;
use emdstar_edmd::{BroadPhaseKind, Engine, Event, Interference, Physics};
use emdstar_system::{Domain, Particles};

/// A soft elastic Hertz gas (Y = 10 MPa so that exceptions are frequent), R = 0.1 m,
/// ρ = 1140 kg/m³, thermal speed ≈ 2 m/s (Müller & Pöschel 2013, Sec. VI B 6).
fn soft_gas(eta: f64, interference: Interference) -> ((Particles, Domain), Physics) {
    let sphere = Sphere::from_density(0.1, 1140.0).unwrap();
    let density = eta / (4.0 / 3.0 * std::f64::consts::PI * 0.001);
    let kt = sphere.mass * 4.0 / 3.0;
    let setup = fcc(5, density, 0.2, sphere.mass, kt, 21);
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e7, 0.4, 0.0).unwrap());
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, Tangential::None, &[sphere]).unwrap(),
        mor: Box::new(ExactMor),
        interference,
    };
    (setup, physics)
}

#[test]
fn elastic_emdstar_gas_conserves_energy_and_momentum_through_exceptions() {
    let variants = [
        (Interference::HitOnly, BroadPhaseKind::Crossings),
        (Interference::BothPartners, BroadPhaseKind::Crossings),
        (Interference::HitOnly, BroadPhaseKind::Epochs),
        (Interference::BothPartners, BroadPhaseKind::Epochs),
    ];
    for (interference, broad_phase) in variants {
        let (setup, physics) = soft_gas(0.2, interference);
        let mut e: Engine =
            Engine::with_broad_phase(&setup.0, &setup.1, physics, broad_phase).unwrap();
        let (e0, p0) = (e.kinetic_energy(), e.momentum());
        e.run_collisions(20_000).unwrap();
        let s = *e.stats();
        let (e1, p1) = (e.kinetic_energy(), e.momentum());
        assert!((e1 / e0 - 1.0).abs() < 1e-6, "energy {e0} -> {e1}");
        let scale = (2.0 * e0 * e.masses().iter().sum::<f64>()).sqrt();
        for k in 0..3 {
            assert!(
                (p1[k] - p0[k]).abs() < 1e-9 * scale,
                "momentum {p0:?} -> {p1:?}"
            );
        }
        // At η = 0.2 and 10 MPa collisions overlap in time: both exception types occur.
        assert!(s.exception_interference > 0, "{s:?}");
        assert!(s.exception_rotation > 0, "{s:?}");
        if interference == Interference::BothPartners {
            assert!(s.early_partner_updates > 0);
        } else {
            assert_eq!(s.early_partner_updates, 0);
        }
        eprintln!("{interference:?}, {broad_phase:?}: {s:?}");
    }
}

/// The first `count` events that change a particle, with their times.
fn events(mut e: Engine, count: usize) -> Vec<(Event, f64)> {
    let mut out = vec![];
    while out.len() < count {
        match e.step().unwrap() {
            Event::Crossing(_) | Event::Epoch | Event::Stale(_) => {}
            // Which partner's prediction comes first is not physics.
            Event::Collision(i, j) => out.push((Event::Collision(i.min(j), i.max(j)), e.time())),
            Event::Resolved(i, j) => out.push((Event::Resolved(i.min(j), i.max(j)), e.time())),
            ev => out.push((ev, e.time())),
        }
    }
    out
}

#[test]
fn epochs_and_crossings_run_the_same_emdstar_events() {
    // Soft and dense enough for both exceptions within the compared stretch: E^φ, E^v,
    // interference and eMD fallbacks must come in the same order at the same times.
    let (setup, physics) = soft_gas(0.2, Interference::HitOnly);
    let crossings =
        Engine::with_broad_phase(&setup.0, &setup.1, physics, BroadPhaseKind::Crossings);
    let (_, physics) = soft_gas(0.2, Interference::HitOnly);
    let epochs = Engine::with_broad_phase(&setup.0, &setup.1, physics, BroadPhaseKind::Epochs);
    let count = 600;
    let (a, b) = (
        events(crossings.unwrap(), count),
        events(epochs.unwrap(), count),
    );
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x.0, y.0, "event {k}: {x:?} vs {y:?}");
        assert!((x.1 - y.1).abs() <= 1e-9 * x.1, "event {k}: {x:?} vs {y:?}");
    }
    let resolved = a
        .iter()
        .filter(|e| matches!(e.0, Event::Resolved(..)))
        .count();
    assert!(resolved > 0, "no interference among the compared events");
}

/// A dissipative contact ends before the overlap is gone, so eMD* leaves each pair
/// overlapping by l(1 − ε_r) until it separates; when a third particle turns one of
/// them back in that time the pair meets again inside that overlap. Every other impact
/// must come from outside contact (overlap at round-off, Bannerman et al. 2014), and a
/// re-contact's overlap must never exceed the one the pair was left at.
#[test]
fn impacts_come_from_outside_contact_except_recontacts_within_the_placed_overlap() {
    let sphere = Sphere::from_density(0.1, 1140.0).unwrap();
    let (eta, sigma) = (0.05, 0.2);
    let density = eta / (4.0 / 3.0 * std::f64::consts::PI * 0.001);
    let setup = fcc(5, density, sigma, sphere.mass, sphere.mass * 4.0 / 3.0, 5);
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e8, 0.4, 1e-5).unwrap());
    for interference in [Interference::HitOnly, Interference::BothPartners] {
        let physics = Physics::EmdStar {
            interactions: Interactions::of_spheres(&law, Tangential::None, &[sphere]).unwrap(),
            mor: Box::new(ExactMor),
            interference,
        };
        let mut e: Engine = Engine::new(&setup.0, &setup.1, physics).unwrap();
        e.run_collisions(40_000).unwrap();
        let s = *e.stats();
        eprintln!("{interference:?}: {s:?}");
        assert!(s.recontacts > 0, "no re-contact to check: {s:?}");
        // The overlap eMD* places is far above round-off here (ε_r < 1 − 1e-5).
        assert!(s.max_recontact_overlap > 1e-7 * sigma, "{s:?}");
        assert!(s.max_recontact_overlap_ratio <= 1.0 + 1e-6, "{s:?}");
        assert!(s.max_impact_overlap < 1e-12 * sigma, "{s:?}");
    }
}
