//! The hybrid with friction and rotation against independent references: MD's own
//! collisions for its event-driven collisions (eMD*'s exact frictional contact, linear
//! and Hertz; Walton's rule with β₀ derived from MD's law when chosen), the guard with
//! spins, and an exact restart. (Every particle TD is frictional MD to the bit:
//! bitwise.rs.)

use crate::common::{hybrid_with, max_difference, md, step, system};
use emdstar_contact::Vec3;
use emdstar_hybrid::{EventRule, Hybrid, HybridOptions, Mode};
use emdstar_system::{Particles, System};

/// `count` frictional linear spheres at random at `packing` fraction, spinning.
fn frictional_gas(count: usize, packing: f64) -> System {
    let mut sys = system(&format!(
        r#"
t_end = 0.05
gravity = [0.0, 0.0, -9.81]
[material]
model = "linear"
stiffness = 20000.0
damping = 2.0
density = 1140.0
friction = 0.3
tangential_stiffness = 5714.0
tangential_damping = 0.5
[gas]
count = {count}
radius = 0.1
arrangement = "random"
packing_fraction = {packing}
rms_speed = 1.0
seed = 4
"#
    ));
    for (i, w) in sys.particles.angular_velocity.iter_mut().enumerate() {
        *w = [(i % 3) as f64 - 1.0, 2.0 - (i % 5) as f64, 0.5];
    }
    sys
}

/// Largest difference of spins.
fn spin_difference(a: &Particles, b: &Particles) -> f64 {
    (0..a.len())
        .map(|i| (Vec3::from(a.angular_velocity[i]) - Vec3::from(b.angular_velocity[i])).norm())
        .fold(0.0, f64::max)
}

/// Two spheres in an oblique impact (impact parameter `offset`, relative speed 0.5
/// m/s), spinning; linear contacts of restitution ≈ 0.9 with the tangential spring
/// k_t = (2/7) k and γ_t = (2/7) γ, and friction `mu`.
fn oblique_pair(mu: f64, offset: f64) -> System {
    let law = format!(
        "model = \"linear\"\nstiffness = 200000.0\ndamping = 30.0\n\
         tangential_damping = {gt}\ntangential_stiffness = {kt}\n",
        kt = 200000.0 * 2.0 / 7.0,
        gt = 30.0 * 2.0 / 7.0,
    );
    oblique_pair_of(&law, mu, offset)
}

/// The same impact with a damped Hertz law (restitution about 0.9 at 0.5 m/s) and a
/// tangential spring and dashpot.
fn oblique_hertz_pair(mu: f64, offset: f64) -> System {
    let law = "model = \"hertz\"\nyoung = 1e7\npoisson = 0.3\ndissipation = 2e-4\n\
               tangential_stiffness = 60000.0\ntangential_damping = 8.0\n";
    oblique_pair_of(law, mu, offset)
}

fn oblique_pair_of(law: &str, mu: f64, offset: f64) -> System {
    system(&format!(
        r#"
t_end = 0.2
[material]
{law}
density = 1140.0
friction = {mu}
[[particles]]
radius = 0.1
position = [0.0, -{y}, 0.0]
velocity = [0.0, 0.25, 0.0]
angular_velocity = [0.0, 0.0, 3.0]
[[particles]]
radius = 0.1
position = [{offset}, {y}, 0.0]
velocity = [0.0, -0.25, 0.0]
"#,
        // 0.03 m apart along y from touch: it comes at t = 0.06 s.
        y = 0.5 * (0.04 - offset * offset).sqrt() + 0.015,
    ))
}

/// The pair's velocities and spins after the collision: by the hybrid's event-driven
/// part (its collisions by `events`) and by MD.
fn after_collision(sys: &System, events: EventRule) -> (Particles, Particles, Hybrid) {
    let t_end = 0.2;
    let (dt, steps) = step(sys, t_end, 0.01);
    let opts = HybridOptions {
        adaptive: false,
        events,
        ..HybridOptions::with_dt(dt)
    };
    let mut h = hybrid_with(sys, opts, t_end);
    h.set_mode(0, Mode::Event).unwrap();
    h.set_mode(1, Mode::Event).unwrap();
    h.advance(steps).unwrap();
    assert_eq!(h.count(Mode::Event), 2, "{:?}", h.stats());
    assert_eq!(h.stats().ed.pair_collisions, 1);
    let mut m = md(sys, dt, h.skin(), t_end);
    m.advance(steps).unwrap();
    assert_eq!(m.thermo().contacts, 0, "the MD contact must be over");
    (h.particles(), m.particles_in_config_order(), h)
}

/// Largest difference of velocities and of the contact-point speed of the spins (Rω),
/// relative to the impact speed 0.5 m/s.
fn relative_differences(a: &Particles, b: &Particles) -> (f64, f64) {
    let (mut dv, mut dw) = (0.0f64, 0.0f64);
    for i in 0..2 {
        dv = dv.max((Vec3::from(a.velocity[i]) - Vec3::from(b.velocity[i])).norm() / 0.5);
        let w = Vec3::from(a.angular_velocity[i]) - Vec3::from(b.angular_velocity[i]);
        dw = dw.max(a.radius[i] * w.norm() / 0.5);
    }
    (dv, dw)
}

#[test]
fn event_driven_frictional_collisions_are_mds_through_the_exact_contact() {
    // eMD*'s exact frictional contact against MD at 100 steps per contact, for both
    // laws, sticking (µ = 10) and sliding (µ = 0.2, offset 0.12): MD's truncation error,
    // 1e-7 to 3e-5 of the impact speed. (Sticking Hertz contacts with a tangential
    // dashpot are left out: there MD's outcome jumps by up to 5e-3 between step sizes,
    // 1e-6 at some, 3e-3 at others, while it converges smoothly without the dashpot.)
    let hertz_sticking = "model = \"hertz\"\nyoung = 1e7\npoisson = 0.3\ndissipation = 2e-4\n\
                          tangential_stiffness = 60000.0\ntangential_damping = 0.0\n";
    for (name, sys) in [
        ("linear, sticking", oblique_pair(10.0, 0.08)),
        ("linear, sliding", oblique_pair(0.2, 0.12)),
        (
            "Hertz, sticking",
            oblique_pair_of(hertz_sticking, 10.0, 0.08),
        ),
        ("Hertz, sliding", oblique_hertz_pair(0.2, 0.12)),
    ] {
        let (ed, reference, h) = after_collision(&sys, EventRule::EmdStar);
        assert_eq!(h.stats().ed.frictional_solves, 1, "{name}");
        let (dv, dw) = relative_differences(&ed, &reference);
        let turned = spin_difference(&reference, &sys.particles) * 0.1 / 0.5;
        eprintln!("{name}: dv = {dv:e}, dw = {dw:e} (spins changed by {turned} of 0.5 m/s)");
        assert!(
            turned > 0.1,
            "{name}: friction must turn the spins: {turned}"
        );
        assert!(dv < 1e-4 && dw < 1e-4, "{name}: dv = {dv:e}, dw = {dw:e}");
    }
}

#[test]
fn a_sticking_walton_collision_matches_md_through_the_derived_tangential_restitution() {
    // µ large: the contact sticks throughout, the regime β₀ describes.
    let sys = oblique_pair(10.0, 0.08);
    let (ed, reference, _) = after_collision(&sys, EventRule::Emd);
    let (dv, dw) = relative_differences(&ed, &reference);
    let turned = spin_difference(&reference, &sys.particles) * 0.1 / 0.5;
    eprintln!("sticking: dv = {dv:e}, dw = {dw:e} (spins changed by {turned} of 0.5 m/s)");
    assert!(turned > 0.1, "friction must turn the spins: {turned}");
    assert!(dv < 0.005 && dw < 0.005, "dv = {dv:e}, dw = {dw:e}");
}

#[test]
fn a_sliding_walton_collision_matches_md() {
    // An oblique impact with µ = 0.2 whose slip is too fast to stop: Walton's impulse
    // sits on Coulomb's bound, |P_t| = µ|P_n|.
    let offset = 0.12;
    let sys = oblique_pair(0.2, offset);
    let (ed, reference, _) = after_collision(&sys, EventRule::Emd);
    let n = Vec3::new(-offset, -(0.04 - offset * offset).sqrt(), 0.0) / 0.2;
    let impulse = (Vec3::from(ed.velocity[0]) - Vec3::from(sys.particles.velocity[0]))
        * sys.particles.mass[0];
    let normal = impulse.dot(&n);
    let tangential = (impulse - n * normal).norm();
    assert!(
        (tangential / normal - 0.2).abs() < 1e-9,
        "the collision must slide: |P_t|/|P_n| = {}",
        tangential / normal
    );
    let (dv, dw) = relative_differences(&ed, &reference);
    eprintln!("sliding: dv = {dv:e}, dw = {dw:e}");
    assert!(dv < 0.01 && dw < 0.01, "dv = {dv:e}, dw = {dw:e}");
}

#[test]
fn a_restored_frictional_run_continues_bitwise() {
    let sys = frictional_gas(300, 0.2);
    let t_end = 0.05;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions {
        phi_time: 0.25,
        phi_event: 0.2,
        ..HybridOptions::with_dt(dt)
    };
    let mut straight = hybrid_with(&sys, opts, t_end);
    straight.advance(steps).unwrap();
    let mut first = hybrid_with(&sys, opts, t_end);
    first.advance(steps / 2).unwrap();
    let saved = first.save_state();
    let mut resumed = hybrid_with(&sys, opts, t_end);
    resumed.restore_state(&saved).unwrap();
    resumed.advance(steps - steps / 2).unwrap();
    assert_eq!(resumed.particles(), straight.particles());
    assert_eq!(resumed.stats(), straight.stats());
    let s = straight.stats();
    eprintln!("frictional restart: {s:?}");
    assert!(
        s.td_particle_steps > 0 && s.ed.pair_collisions + s.ed.wall_collisions > 0,
        "both parts must run: {s:?}"
    );
}

#[test]
fn friction_the_hybrid_cannot_run_is_refused_with_what_to_do() {
    let build = |text: &str, events: EventRule| {
        let opts = HybridOptions {
            events,
            ..HybridOptions::with_dt(1e-5)
        };
        let mor = Box::new(emdstar_edmd::rules::ExactMor);
        Hybrid::new(system(text), opts, mor, 0.01)
    };
    let refuse = |text: &str, events: EventRule| match build(text, events) {
        Ok(_) => panic!("accepted: {text}"),
        Err(e) => e.to_string(),
    };
    let particles = "[[particles]]\nradius = 0.1\nposition = [0.0, 0.0, 0.0]\n";
    let linear = "t_end = 0.01\n[material]\nmodel = \"linear\"\nstiffness = 2000.0\n\
                  density = 1140.0\nfriction = 0.2\n";
    for events in [EventRule::EmdStar, EventRule::Emd] {
        let walton = refuse(
            &format!("{linear}tangential_restitution = 0.4\n{particles}"),
            events,
        );
        assert!(
            walton.contains("tangential_restitution") && walton.contains("tangential_stiffness"),
            "{walton}"
        );
    }
    let coulomb = format!("{linear}tangential = \"coulomb\"\n{particles}");
    let refused = refuse(&coulomb, EventRule::EmdStar);
    assert!(
        refused.contains("coulomb") && refused.contains("--events emd"),
        "{refused}"
    );
    assert!(build(&coulomb, EventRule::Emd).is_ok());
    let hertz = format!(
        "t_end = 0.01\n[material]\nmodel = \"hertz\"\nyoung = 1e9\npoisson = 0.4\n\
         dissipation = 1e-4\ndensity = 1140.0\nfriction = 0.2\ntangential_stiffness = 1e4\n\
         {particles}"
    );
    let refused = refuse(&hertz, EventRule::Emd);
    assert!(
        refused.contains("hertz") && refused.contains("linear"),
        "{refused}"
    );
    assert!(build(&hertz, EventRule::EmdStar).is_ok());
}

#[test]
fn a_spinning_event_driven_particle_turns_time_driven_before_it_touches_and_matches_md() {
    // Particle 1 flies event-driven at particle 0, off-centre; the guard makes it
    // time-driven before the contact, keeping its spin, and MD takes over.
    let sys = system(
        r#"
t_end = 0.5
[material]
model = "linear"
stiffness = 2000.0
damping = 1.0
density = 1140.0
friction = 0.4
tangential_stiffness = 571.0
tangential_damping = 0.2
[[particles]]
radius = 0.1
position = [0.0, 0.0, 0.0]
[[particles]]
radius = 0.1
position = [0.6, 0.08, 0.0]
velocity = [-2.0, 0.0, 0.0]
angular_velocity = [0.0, 0.0, 15.0]
"#,
    );
    let t_end = 0.5;
    let (dt, steps) = step(&sys, t_end, 0.02);
    let opts = HybridOptions {
        adaptive: false,
        skin: Some(1.0),
        ..HybridOptions::with_dt(dt)
    };
    let mut h = hybrid_with(&sys, opts, t_end);
    h.set_mode(1, Mode::Event).unwrap();
    let mut m = md(&sys, dt, h.skin(), t_end);
    h.advance(steps).unwrap();
    m.advance(steps).unwrap();
    assert_eq!(h.stats().guard_conversions, 1, "{:?}", h.stats());
    assert_eq!(h.count(Mode::Time), 2);
    let (got, reference) = (h.particles(), m.particles_in_config_order());
    assert!(
        reference.angular_velocity[0][2].abs() > 1.0,
        "friction must spin particle 0 up: {:?}",
        reference.angular_velocity[0]
    );
    let (dx, dv) = max_difference(&got, &reference, &sys);
    let dw = spin_difference(&got, &reference);
    assert!(
        dx < 1e-12 && dv < 1e-12 && dw < 1e-10,
        "|dx| = {dx:e} m, |dv| = {dv:e} m/s, |dw| = {dw:e} rad/s"
    );
}
