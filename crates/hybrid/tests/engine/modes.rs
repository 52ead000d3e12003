//! The hybrid engine against independent references: the exact two-body solution,
//! the eMD* engine on a dilute gas, the MD engine on a dense gas and on collisions
//! where particles switch modes, and conservation laws.

use crate::common::{elastic_spheres, hybrid_with, max_difference, md, step, system};
use emdstar_contact::Vec3;
use emdstar_edmd::detect::sphere_sphere;
use emdstar_edmd::rules::ExactMor;
use emdstar_hybrid::{Hybrid, HybridOptions, Mode};
use emdstar_mor::rule::{Body, exact_collision};
use emdstar_system::System;

fn hybrid(system: &System, dt: f64, adaptive: bool, t_end: f64) -> Hybrid {
    let opts = HybridOptions {
        adaptive,
        ..HybridOptions::with_dt(dt)
    };
    hybrid_with(system, opts, t_end)
}

const TWO_BODY: &str = r#"
t_end = 0.4
[material]
model = "linear"
stiffness = 2000.0
damping = 0.5
density = 1140.0
[[particles]]
radius = 0.1
position = [0.0, -0.3, 0.0]
velocity = [1.25, 2.5, 0.0]
[[particles]]
radius = 0.1
position = [0.06, 0.3, 0.0]
velocity = [1.25, -2.5, 0.0]
"#;

#[test]
fn an_event_driven_collision_equals_the_exact_two_body_solution() {
    let sys = system(TWO_BODY);
    let t_end = 0.4;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let mut h = hybrid(&sys, dt, false, t_end);
    h.set_mode(0, Mode::Event).unwrap();
    h.set_mode(1, Mode::Event).unwrap();
    h.advance(steps).unwrap();
    let got = h.particles();
    assert_eq!(h.count(Mode::Event), 2);
    assert_eq!(h.stats().ed.pair_collisions, 1);
    assert_eq!(h.stats().td_particle_steps, 0);

    // Reference: touch time from the free flight, exact collision, free flight on.
    let p = &sys.particles;
    let r: [f64; 3] = std::array::from_fn(|k| p.position[0][k] - p.position[1][k]);
    let v: [f64; 3] = std::array::from_fn(|k| p.velocity[0][k] - p.velocity[1][k]);
    let t_touch = sphere_sphere(r, v, 0.2);
    assert!(t_touch.is_finite());
    let bodies = [0, 1].map(|i| Body {
        position: Vec3::from(p.position[i]) + Vec3::from(p.velocity[i]) * t_touch,
        velocity: Vec3::from(p.velocity[i]),
        mass: p.mass[i],
    });
    let contact = *sys.interactions().pair(0, 0);
    let (law, props) = (contact.model.normal, contact.props);
    let (out, _) = exact_collision(&law, &props, &bodies).unwrap();
    let rest = t_end - t_touch - out.duration;
    assert!(rest > 0.0, "the collision must be over by t_end");
    for i in 0..2 {
        let x = out.after[i].position + out.after[i].velocity * rest;
        let dx = (Vec3::from(got.position[i]) - x).norm();
        let dv = (Vec3::from(got.velocity[i]) - out.after[i].velocity).norm();
        assert!(
            dx < 1e-12 && dv < 1e-12,
            "particle {i}: |dx| = {dx:e}, |dv| = {dv:e}"
        );
    }
}

const HEAD_ON: &str = r#"
t_end = 0.5
[material]
model = "linear"
stiffness = 2000.0
damping = 1.0
density = 1140.0
[[particles]]
radius = 0.1
position = [0.0, 0.0, 0.0]
[[particles]]
radius = 0.1
position = [0.6, 0.05, 0.0]
velocity = [-2.0, 0.0, 0.0]
"#;

#[test]
fn an_event_driven_particle_turns_time_driven_before_it_touches_and_matches_md() {
    let sys = system(HEAD_ON);
    let t_end = 0.5;
    let (dt, steps) = step(&sys, t_end, 0.02);
    // A skin wide enough that no rebuild comes before the contact: the guard must know
    // of the switch made by hand.
    let opts = HybridOptions {
        adaptive: false,
        skin: Some(1.0),
        ..HybridOptions::with_dt(dt)
    };
    let mut h = hybrid_with(&sys, opts, t_end);
    h.set_mode(1, Mode::Event).unwrap();
    let rebuilds = h.stats().rebuilds;
    let mut m = md(&sys, dt, h.skin(), t_end);
    let e0 = h.thermo();
    let mut rebuilds_at_switch = None;
    for _ in 0..steps {
        h.advance(1).unwrap();
        if rebuilds_at_switch.is_none() && h.stats().guard_conversions > 0 {
            rebuilds_at_switch = Some(h.stats().rebuilds);
        }
    }
    m.advance(steps).unwrap();
    let s = h.stats();
    eprintln!("head-on: {s:?}");
    assert_eq!(
        rebuilds_at_switch,
        Some(rebuilds),
        "the switch must come before any rebuild"
    );
    assert_eq!(s.guard_conversions, 1);
    assert_eq!(s.late_conversions, 0);
    assert_eq!(h.count(Mode::Time), 2);
    let (dx, dv) = max_difference(&h.particles(), &m.particles_in_config_order(), &sys);
    assert!(
        dx < 1e-12 && dv < 1e-12,
        "|dx| = {dx:e} m, |dv| = {dv:e} m/s"
    );
    // Momentum is conserved by the switch and the MD contact.
    let (p0, p1) = (e0.momentum, h.thermo().momentum);
    for k in 0..3 {
        assert!((p1[k] - p0[k]).abs() < 1e-12 * 10.0, "{p0:?} {p1:?}");
    }
    // The collision dissipates as in MD: same kinetic energy.
    let (eh, em) = (h.thermo().total_energy(), m.thermo().total_energy());
    assert!((eh - em).abs() < 1e-12 * e0.total_energy(), "{eh} {em}");
}

/// 64 elastic spheres in a 4 × 4 × 4 block with gaps of 5 % of a radius, flying apart
/// with random velocities of zero total momentum into a large periodic box.
fn expanding_cluster() -> System {
    let mut seed: u64 = 12345;
    let mut uniform = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut v: Vec<[f64; 3]> = (0..64).map(|_| [uniform(), uniform(), uniform()]).collect();
    let mean: [f64; 3] = std::array::from_fn(|k| v.iter().map(|w| w[k]).sum::<f64>() / 64.0);
    for w in &mut v {
        *w = std::array::from_fn(|k| 2.0 * (w[k] - mean[k]));
    }
    let bodies: Vec<([f64; 3], [f64; 3])> = v
        .iter()
        .enumerate()
        .map(|(n, w)| {
            (
                [n % 4, (n / 4) % 4, n / 16].map(|c| (c as f64 - 1.5) * 0.205),
                *w,
            )
        })
        .collect();
    elastic_spheres(
        1.5,
        "[box]\nsize = [4.0, 4.0, 4.0]\nlo = [-2.0, -2.0, -2.0]\n",
        &bodies,
    )
}

#[test]
fn a_dense_cluster_that_dilutes_switches_to_events_conserving_energy_and_momentum() {
    let sys = expanding_cluster();
    let t_end = 1.5;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let mut h = hybrid(&sys, dt, true, t_end);
    assert!(h.count(Mode::Time) > 32, "the block must start dense");
    let mut m = md(&sys, dt, h.skin(), t_end);
    let e0 = h.thermo().total_energy();
    h.advance(steps).unwrap();
    m.advance(steps).unwrap();
    let s = *h.stats();
    let (eh, em) = (h.thermo().total_energy(), m.thermo().total_energy());
    let (dh, dm) = ((eh - e0).abs() / e0, (em - e0).abs() / e0);
    let p = h.thermo().momentum;
    eprintln!(
        "cluster: ΔE/E hybrid {dh:e}, MD {dm:e}, P {p:?}, {} ED, {s:?}",
        h.count(Mode::Event)
    );
    assert!(
        s.to_event > 32,
        "the particles must turn event-driven as the block dilutes"
    );
    assert!(
        s.ed.pair_collisions > 0,
        "some collisions must be event-driven"
    );
    assert!(m.thermo().contacts == 0 && h.thermo().contacts == 0);
    // Energy to the accuracy of the force law's integration (MD's own error at this dt).
    assert!(
        dh <= 2.0 * dm + 1e-9,
        "hybrid ΔE/E = {dh:e}, MD ΔE/E = {dm:e}"
    );
    let p_scale = sys.particles.total_mass() * 1.0;
    assert!(p.iter().all(|c| c.abs() < 1e-12 * p_scale), "{p:?}");
}

const INCLINE: &str = r#"
t_end = 0.45
gravity = [0.0, 0.0, -9.81]
[material]
model = "linear"
stiffness = 2e6
damping = 50.0
density = 1140.0
[[walls]]
normal = [0.29552020666133955, 0.0, 0.955336489125606]
point = [0.0, 0.0, 0.0]
[[particles]]
radius = 0.1
position = [0.0, 0.0, 0.5]
velocity = [0.2, 0.1, 0.0]
"#;

#[test]
fn both_modes_bounce_off_an_inclined_wall_under_gravity_like_md() {
    let sys = system(INCLINE);
    let t_end = 0.45;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let mut td = hybrid(&sys, dt, false, t_end);
    let mut ed = hybrid(&sys, dt, false, t_end);
    ed.set_mode(0, Mode::Event).unwrap();
    let mut m = md(&sys, dt, td.skin(), t_end);
    td.advance(steps).unwrap();
    ed.advance(steps).unwrap();
    m.advance(steps).unwrap();
    let reference = m.particles_in_config_order();
    let (dx_td, dv_td) = max_difference(&td.particles(), &reference, &sys);
    let (dx_ed, dv_ed) = max_difference(&ed.particles(), &reference, &sys);
    eprintln!(
        "incline: TD {dx_td:e} {dv_td:e}; ED {dx_ed:e} {dv_ed:e}; {:?}",
        ed.stats()
    );
    assert_eq!(ed.stats().ed.wall_collisions, 1);
    assert_eq!(ed.stats().ed.exception_rotation, 0);
    assert_eq!(ed.count(Mode::Event), 1);
    assert!(dx_td < 1e-12 && dv_td < 1e-12);
    // eMD* leaves out how gravity deforms the contact itself. With the wall carrying
    // the normal part of g during the contact, what remains is of second order in
    // g·τ/v_n (τ the contact duration, v_n ≥ 2 m/s the impact speed here) in velocity,
    // plus the sinking ½·g·τ² during the transient in position.
    let contact = *sys.interactions().wall(0, 0);
    let (law, props) = (contact.model.normal, contact.props);
    let tau = law.elastic_duration(props.m_eff, 2.0).unwrap();
    let g_tau = 9.81 * tau;
    let dv_bound = g_tau * g_tau / 2.0;
    assert!(dv_ed < dv_bound, "|dv| = {dv_ed:e} ≥ {dv_bound:e}");
    assert!(dx_ed < dv_bound * t_end + g_tau * tau, "|dx| = {dx_ed:e}");
}

const FALLING: &str = r#"
t_end = 0.3
gravity = [0.0, -9.81, 0.0]
[material]
model = "linear"
stiffness = 2000.0
damping = 1.0
density = 1140.0
[[particles]]
radius = 0.1
position = [0.0, 0.2, 0.0]
velocity = [0.0, -1.0, 0.0]
[[particles]]
radius = 0.1
position = [2.0, 2.0, 0.0]
"#;

#[test]
fn particles_behind_the_outlet_leave_and_the_rest_falls_freely() {
    let sys = system(FALLING);
    let t_end = 0.3;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions {
        outlet: Some(emdstar_system::Wall {
            normal: [0.0, 1.0, 0.0],
            point: [0.0, 0.0, 0.0],
            vibration: None,
        }),
        ..HybridOptions::with_dt(dt)
    };
    let mut h = hybrid_with(&sys, opts, t_end);
    h.advance(steps).unwrap();
    assert_eq!(h.modes()[0], Mode::Removed);
    assert_ne!(h.modes()[1], Mode::Removed);
    assert_eq!(h.stats().removed, 1);
    // Only the remaining particle counts, in free fall from rest: p = m·g·t.
    let th = h.thermo();
    let expect = sys.particles.mass[1] * -9.81 * t_end;
    assert!(
        (th.momentum[1] - expect).abs() < 1e-12 * expect.abs(),
        "{th:?}"
    );
    assert_eq!(th.momentum[0], 0.0);
    let bad = Hybrid::new(
        sys,
        HybridOptions {
            phi_event: 0.5,
            phi_time: 0.2,
            ..HybridOptions::with_dt(dt)
        },
        Box::new(ExactMor),
        t_end,
    );
    assert!(matches!(bad, Err(e) if e.to_string().contains("phi_event")));
}

#[test]
fn a_mixed_run_is_deterministic() {
    let sys = system(
        r#"
t_end = 0.01
[material]
model = "hertz"
young = 1e9
poisson = 0.4
dissipation = 1e-4
density = 1140.0
[gas]
count = 300
radius = 0.1
arrangement = "random"
packing_fraction = 0.2
rms_speed = 1.0
seed = 9
"#,
    );
    let t_end = 0.01;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions {
        phi_time: 0.25,
        phi_event: 0.2,
        ..HybridOptions::with_dt(dt)
    };
    let run = || {
        let mut h = hybrid_with(&sys, opts, t_end);
        h.advance(steps).unwrap();
        (h.particles(), *h.stats())
    };
    let (a, sa) = run();
    let (b, sb) = run();
    assert!(
        sa.ed.pair_collisions > 0 && sa.td_particle_steps > 0,
        "{sa:?}"
    );
    assert_eq!(sa, sb);
    assert_eq!(a, b);
}
