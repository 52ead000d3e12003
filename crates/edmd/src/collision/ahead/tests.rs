use super::*;
use emdstar_mor::frictional::Spinning;

/// A gas-like impact of two spheres (R = 1 cm, Hertz, µ = 0.3): approaching at 1 m/s
/// along a direction turned by `k`, with a tangential velocity and spins.
fn contact(k: u32) -> PairContact {
    let a = 0.7 * f64::from(k);
    let n = [a.cos() * 0.6, a.sin() * 0.6, 0.8];
    let sphere = |s: f64| Spinning {
        radius: 0.01,
        mass: 4.775e-3,
        spin: [10.0 * s, -20.0 * a.sin(), 5.0],
    };
    PairContact {
        spheres: [sphere(1.0), sphere(-1.0)],
        separation: n.map(|x| 0.02 * x),
        velocity: [-n[0] + 0.3 * a.sin(), -n[1] - 0.3 * a.cos(), -n[2]],
    }
}

fn law() -> (PairLaw, HistorySpring) {
    (
        PairLaw::Hertz {
            rho_el: 5.6e7,
            dissipation: 9.5e-6,
        },
        HistorySpring::new(0.3, 1e5, 0.0).unwrap(),
    )
}

/// Particle 2k predicts meeting 2k + 1 at time k, both counters 0.
fn predicted(k: u32) -> Predicted {
    Predicted {
        time: f64::from(k),
        parties: [(2 * k, 0), (2 * k + 1, 0)],
        slot: 2 * k,
    }
}

#[test]
fn the_worker_gives_each_contact_the_solve_of_the_engines_thread_to_the_bit() {
    let (law, spring) = law();
    let mut ahead = SolveAhead::default();
    for k in 0..6 {
        ahead.submit(predicted(k), &law, &spring, contact(k));
    }
    for k in 0..8 {
        let alone = contact(k).solve(&law, &spring, &CONTACT_OPTIONS).unwrap();
        let got = ahead.solve(&law, &spring, &contact(k)).unwrap();
        assert_eq!(format!("{alone:?}"), format!("{got:?}"), "contact {k}");
    }
    // Each solve is counted once, from the worker or solved here (the two never
    // submitted among them).
    let (taken, inline) = ahead.counts();
    assert_eq!(taken + inline, 8);
    assert!(inline >= 2);
}

#[test]
fn the_board_keeps_the_pairs_earlier_prediction_and_skips_stale_ones() {
    let (law, spring) = law();
    let mut board = Board::default();
    assert!(board.insert(predicted(1), &law, &spring, contact(1)));
    assert!(!board.insert(predicted(1), &law, &spring, contact(1)));
    // The pair's collision predicted by its other particle, later: not filed; earlier:
    // it replaces the first.
    let other = |time| Predicted {
        time,
        parties: [(3, 0), (2, 0)],
        slot: 3,
    };
    assert!(!board.insert(other(1.5), &law, &spring, contact(2)));
    assert!(board.insert(other(0.5), &law, &spring, contact(3)));
    assert_eq!(board.jobs.len(), 1);
    // A particle's new prediction replaces its old one, even if later.
    assert!(board.insert(other(0.7), &law, &spring, contact(4)));
    assert_eq!(board.jobs.len(), 1);
    // Particle 5 collided since it was predicted to meet 4: that job is skipped and
    // dropped, and the next one claimed.
    assert!(board.insert(predicted(2), &law, &spring, contact(5)));
    assert!(board.insert(predicted(3), &law, &spring, contact(6)));
    board.set_counter(5, 1);
    let claimed: Vec<_> = std::iter::from_fn(|| board.claim().map(|c| c.3)).collect();
    assert_eq!(claimed, [contact(4), contact(6)]);
    assert_eq!(board.jobs.len(), 2);
}

#[test]
fn a_moved_partner_names_the_particles_whose_predictions_to_take_anew() {
    let (law, spring) = law();
    let ahead = SolveAhead::default();
    ahead
        .shared
        .lock()
        .insert(predicted(4), &law, &spring, contact(4));
    let mut again = Vec::new();
    // Particle 9 is the partner of 8's prediction; 8 is its owner.
    ahead.note(0.0, [(8, 0)].into_iter(), &mut again);
    assert!(again.is_empty());
    ahead.note(0.0, [(9, 0)].into_iter(), &mut again);
    assert_eq!(again, [8]);
    // Time passing the prediction drops it.
    ahead.note(4.5, std::iter::empty(), &mut again);
    assert!(ahead.shared.lock().jobs.is_empty());
}
