//! Phases without TD particles (mode checks without list rebuilds) and the way in and
//! out of them: a cloud that contracts into a dense cluster (events → MD with TD
//! particles → events again) and bounces apart, against the MD engine of emdstar-dem;
//! particles settling on a floor, handed to MD by the event budget.

use crate::common::{elastic_spheres, gas_under_gravity, hybrid_with, max_difference, md, step};
use emdstar_hybrid::{HybridOptions, Mode};
use emdstar_system::System;

/// 6 × 6 × 6 elastic spheres on a lattice of 1 m in open space, contracting
/// homologously (v = −x / 1 s): dilute at first (φ = 0.004 at lattice spacing 1 m), φ
/// = 0.1 to 0.2 from lattice spacing 0.35 m (t = 0.65 s; the value depends on how the
/// link cells fall on the lattice), all in contact at t = 0.8 s; they bounce and fly
/// apart again, beyond where they started.
fn contracting_lattice() -> System {
    let bodies: Vec<([f64; 3], [f64; 3])> = (0..216)
        .map(|n| {
            let x = [n % 6, (n / 6) % 6, n / 36].map(|c| c as f64 - 2.5);
            (x, x.map(|c| -c))
        })
        .collect();
    elastic_spheres(3.5, "", &bodies)
}

#[test]
fn a_cloud_contracting_into_a_cluster_leaves_the_cell_path_and_matches_md() {
    let sys = contracting_lattice();
    let t_end = 3.5;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions::with_dt(dt);
    let mut h = hybrid_with(&sys, opts, t_end);
    let mut m = md(&sys, dt, h.skin(), t_end);
    assert_eq!(h.count(Mode::Event), 216, "the cloud must start dilute");
    let e0 = h.thermo();
    let (mut first_td, mut max_td, mut passes_at_max) = (None, 0, 0);
    for n in 0..steps {
        h.advance(1).unwrap();
        let td = h.count(Mode::Time);
        if td > 0 && first_td.is_none() {
            first_td = Some((n + 1) as f64 * dt);
            // Nothing has touched yet: the lattice closes up at t = 0.8 s.
            assert_eq!(h.thermo().contacts, 0);
        }
        if td > max_td {
            (max_td, passes_at_max) = (td, h.stats().cell_passes);
        }
    }
    m.advance(steps).unwrap();
    let s = *h.stats();
    eprintln!("contracting: first TD at {first_td:?} s, {max_td} TD at most, {s:?}");
    // Events first (mode checks without rebuilds), then the list with every particle
    // TD through the contact, then events again.
    let t_switch = first_td.expect("the cluster must turn time-driven");
    assert!((0.5..0.8).contains(&t_switch), "{t_switch}");
    assert!(passes_at_max > 0 && s.rebuilds >= 2, "{s:?}");
    assert_eq!(max_td, 216);
    assert_eq!(h.count(Mode::Event), 216, "the cloud must be dilute again");
    assert!(s.cell_passes > passes_at_max, "{s:?}");
    assert!(s.td_particle_steps > 0 && s.to_time == 216 && s.to_event >= 216);
    // Every contact was MD's: no event-driven collision, no late guard switch.
    assert_eq!((s.ed.pair_collisions, s.late_conversions), (0, 0), "{s:?}");
    let (dx, dv) = max_difference(&h.particles(), &m.particles_in_config_order(), &sys);
    let (eh, em) = (h.thermo().total_energy(), m.thermo().total_energy());
    eprintln!("contracting vs MD: |dx| = {dx:e} m, |dv| = {dv:e} m/s, E {eh} {em}");
    assert!(dx < 1e-9 && dv < 1e-9, "|dx| = {dx:e} m, |dv| = {dv:e} m/s");
    assert!((eh - em).abs() < 1e-12 * em, "{eh} {em}");
    let (p0, p1) = (e0.momentum, h.thermo().momentum);
    let scale = sys.particles.total_mass() * 4.4;
    for k in 0..3 {
        assert!((p1[k] - p0[k]).abs() < 1e-13 * scale, "{p0:?} {p1:?}");
    }
}

#[test]
fn particles_settling_on_the_floor_leave_the_cell_path_through_the_event_budget() {
    // Damped: particles that come to rest on the floor exceed the event budget and are
    // handed to TD; the engine leaves the cell path for the list at that step.
    let sys = gas_under_gravity(20.0);
    let t_end = 1.0;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions::with_dt(dt);
    let mut h = hybrid_with(&sys, opts, t_end);
    let p0 = h.thermo().momentum;
    let e0 = h.thermo().total_energy();
    h.advance(steps).unwrap();
    let s = *h.stats();
    let th = h.thermo();
    eprintln!("settling: {s:?}, P {:?}", th.momentum);
    assert!(s.ed.crossings > 0 && s.cell_passes > 0, "{s:?}");
    assert!(s.budget_conversions > 0 && s.rebuilds > 1, "{s:?}");
    assert!(s.to_time > 0 && s.td_particle_steps > 0, "{s:?}");
    assert_eq!(s.late_conversions, 0);
    // Sideways (periodic, no walls, no gravity) momentum is conserved.
    let scale = sys.particles.total_mass() * 2.0;
    for k in 0..2 {
        assert!(
            (th.momentum[k] - p0[k]).abs() < 1e-12 * scale,
            "{p0:?} {th:?}"
        );
    }
    assert!(th.total_energy() < e0);
}
