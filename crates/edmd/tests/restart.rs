//! Exact restarts: an eMD* gas saved in mid-run (with collisions in flight) and
//! restored into a fresh engine continues bitwise as the uninterrupted run, on both
//! broad phases; the same state saves to the same bytes however it was reached.

mod common;

use common::fcc;
use emdstar_contact::Tangential;
use emdstar_contact::{ForceLaw, Sphere, ViscoelasticHertz};
use emdstar_edmd::rules::ExactMor;
use emdstar_edmd::{BroadPhaseKind, Engine, Event, Interference, Physics};
use emdstar_system::Interactions;
use emdstar_system::Simulation;

fn engine(kind: BroadPhaseKind) -> Engine {
    let sphere = Sphere::from_density(0.1, 1140.0).unwrap();
    let density = 0.05 / (4.0 / 3.0 * std::f64::consts::PI * 0.001);
    let (p, d) = fcc(4, density, 0.2, sphere.mass, sphere.mass * 4.0 / 3.0, 3);
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e7, 0.4, 1e-4).unwrap());
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, Tangential::None, &[sphere]).unwrap(),
        mor: Box::new(ExactMor),
        interference: Interference::HitOnly,
    };
    Engine::with_broad_phase(&p, &d, physics, kind).unwrap()
}

#[test]
fn a_restored_gas_continues_bitwise_as_the_uninterrupted_one() {
    for kind in [BroadPhaseKind::Crossings, BroadPhaseKind::Epochs] {
        let t_end = 2.0;
        let mut straight = engine(kind);
        straight.advance_to(t_end).unwrap();

        // Stop right after an E^φ half-way: the pair is in its transient.
        let mut first = engine(kind);
        first.advance_to(0.5 * t_end).unwrap();
        while !matches!(first.step().unwrap(), Event::Collision(..)) {}
        let stop = first.time();
        assert!(stop < t_end);
        let saved = first.save_state();
        assert_eq!(saved, first.save_state(), "saving changes nothing");

        let mut resumed = engine(kind);
        assert_eq!(resumed.broad_phase(), kind);
        resumed.restore_state(&saved).unwrap();
        assert_eq!(
            resumed.save_state(),
            saved,
            "{kind:?}: the same state, the same bytes"
        );
        resumed.advance_to(t_end).unwrap();
        first.advance_to(t_end).unwrap();

        let (a, b, c) = (straight.particles(), resumed.particles(), first.particles());
        assert_eq!(a, b, "{kind:?}: restored run differs from the straight one");
        assert_eq!(
            a, c,
            "{kind:?}: a run stopped and read differs from the straight one"
        );
        assert_eq!(straight.stats(), resumed.stats());
        assert_eq!(straight.save_state(), resumed.save_state());
        let s = straight.stats();
        assert!(
            s.pair_collisions > 100 && s.exceptions() > 0,
            "{kind:?}: {s:?}"
        );
    }
}

#[test]
fn a_state_of_another_broad_phase_or_size_is_refused() {
    let crossings = engine(BroadPhaseKind::Crossings).save_state();
    let mut epochs = engine(BroadPhaseKind::Epochs);
    let err = epochs.restore_state(&crossings).unwrap_err().to_string();
    assert!(err.contains("broad phase"), "{err}");
    let err = epochs.restore_state(&[1, 2, 3]).unwrap_err().to_string();
    assert!(err.contains("cannot be read"), "{err}");
}
