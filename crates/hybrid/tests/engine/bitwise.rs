//! The hybrid is a composition of MD's Verlet driver and the eMD* engine's event core,
//! so with every particle in one mode it is that engine to the bit: every particle
//! time-driven, MD (smooth and frictional, with walls and gravity); every particle
//! event-driven, the eMD* engine on cell crossings (smooth with walls and gravity,
//! frictional), with the same counts of collisions, exceptions and exact frictional
//! solves.

use crate::common::{
    dense_hertz_gas, emdstar_reference, gas_under_gravity, hybrid_with, md, steps_to, system,
};
use emdstar_edmd::Stats;
use emdstar_hybrid::{EventRule, HybridOptions, Mode};
use emdstar_system::{Particles, System};

/// Every counter of the collisions.
fn counts(s: &Stats) -> [u64; 9] {
    [
        s.pair_collisions,
        s.wall_collisions,
        s.velocity_events,
        s.exception_rotation,
        s.exception_interference,
        s.interference_resolved,
        s.mor_fallbacks,
        s.frictional_solves,
        s.stale,
    ]
}

fn assert_same(a: &Particles, b: &Particles) {
    assert_eq!(a.position, b.position, "positions");
    assert_eq!(a.velocity, b.velocity, "velocities");
    assert_eq!(a.angular_velocity, b.angular_velocity, "spins");
}

/// The hybrid with every particle TD against MD over `t_end`, its events (never run)
/// by `events`: TD by the volume fraction (the default thresholds, decided at every
/// rebuild) if `dense`, else by thresholds 0. Returns the particles at the end.
fn time_driven_against_md(sys: &System, t_end: f64, dense: bool, events: EventRule) -> Particles {
    let (dt, steps, _) = steps_to(sys, t_end, 0.02);
    let mut opts = HybridOptions {
        events,
        ..HybridOptions::with_dt(dt)
    };
    if !dense {
        (opts.phi_time, opts.phi_event) = (0.0, 0.0);
    }
    let mut h = hybrid_with(sys, opts, t_end);
    let mut m = md(sys, dt, h.skin(), t_end);
    // In two pieces, as a run with output between does.
    h.advance(steps / 2).unwrap();
    h.advance(steps - steps / 2).unwrap();
    m.stride(steps).unwrap();
    assert_eq!(h.count(Mode::Time), sys.particles.len());
    let s = h.stats();
    assert_eq!((s.to_event, s.ed.events), (0, 0));
    assert!(
        m.rebuilds() > 2,
        "too few rebuilds to test: {}",
        m.rebuilds()
    );
    assert_eq!(s.rebuilds, m.rebuilds());
    let end = m.particles_in_config_order();
    assert_same(&h.particles(), &end);
    assert_eq!(h.thermo(), m.thermo());
    end
}

/// The hybrid with every particle ED (adaptive, dilute) against the eMD* engine over
/// `t_end`; returns the hybrid's counts.
fn event_driven_against_emdstar(sys: &System, t_end: f64) -> Stats {
    let (dt, steps, t) = steps_to(sys, t_end, 0.02);
    let mut h = hybrid_with(sys, HybridOptions::with_dt(dt), t_end);
    assert_eq!(h.count(Mode::Event), sys.particles.len());
    h.advance(steps).unwrap();
    let s = *h.stats();
    assert_eq!(
        (s.to_time, s.td_particle_steps, s.rebuilds),
        (0, 0, 0),
        "{s:?}"
    );
    assert!(s.cell_passes > 0 && s.ed.crossings > 0, "{s:?}");
    let (reference, es) = emdstar_reference(sys, t);
    eprintln!("hybrid {:?}\nengine {:?}", counts(&s.ed), counts(&es));
    assert_eq!(counts(&s.ed), counts(&es));
    assert_same(&h.particles(), &reference);
    s.ed
}

#[test]
fn every_particle_time_driven_is_md_to_the_bit() {
    let hertz = dense_hertz_gas();
    let end = time_driven_against_md(&hertz, 0.1, true, EventRule::EmdStar);
    assert!(
        end.kinetic_energy() < 0.95 * hertz.particles.kinetic_energy(),
        "no collisions"
    );
}

#[test]
fn every_particle_time_driven_is_frictional_md_to_the_bit_with_walls_and_gravity() {
    // Spinning frictional spheres settling on a floor under gravity.
    let mut sys = system(
        r#"
t_end = 0.2
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
count = 100
radius = 0.1
arrangement = "random"
rms_speed = 1.0
seed = 4
[box]
size = [2.0, 2.0, 2.0]
periodic = [true, true, false]
[[walls]]
normal = [0.0, 0.0, 1.0]
point = [0.0, 0.0, 0.0]
[[walls]]
normal = [0.0, 0.0, -1.0]
point = [0.0, 0.0, 2.0]
"#,
    );
    for (i, w) in sys.particles.angular_velocity.iter_mut().enumerate() {
        *w = [(i % 3) as f64 - 1.0, 2.0 - (i % 5) as f64, 0.5];
    }
    let end = time_driven_against_md(&sys, 0.2, false, EventRule::EmdStar);
    let turned = (0..end.len())
        .filter(|&i| {
            let (a, b) = (end.angular_velocity[i], sys.particles.angular_velocity[i]);
            (0..3).any(|k| (a[k] - b[k]).abs() > 0.1)
        })
        .count();
    assert!(turned > 20, "friction must turn the spins: {turned}");
}

#[test]
fn every_particle_event_driven_is_the_emdstar_engine_to_the_bit_with_walls_and_gravity() {
    // Elastic spheres under gravity between a floor and a lid, periodic sideways.
    let sys = gas_under_gravity(0.0);
    let s = event_driven_against_emdstar(&sys, 0.6);
    assert!(s.wall_collisions > 50 && s.pair_collisions > 20, "{s:?}");
}

/// A dilute frictional gas of spinning spheres (linear law, or Hertz), periodic, or
/// `walls` between a floor and a lid under gravity (stiff enough that gravity changes
/// a speed little over a contact, g·τ ≈ 0.1 m/s: eMD*'s condition).
fn frictional_gas(hertz: bool, walls: bool) -> System {
    let law = if hertz {
        "model = \"hertz\"\nyoung = 1e9\npoisson = 0.3\ndissipation = 2e-5\n\
         tangential_stiffness = 50000.0\ntangential_damping = 3.0\n"
    } else {
        "model = \"linear\"\nstiffness = 2e5\ndamping = 10.0\n\
         tangential_stiffness = 57000.0\ntangential_damping = 3.0\n"
    };
    // η = 0.02 periodic; between the walls η = 0.016 in a box of 3 m.
    let (domain, size) = if walls {
        (
            "gravity = [0.0, 0.0, -9.81]\n[box]\nsize = [3.0, 3.0, 3.0]\n\
             periodic = [true, true, false]\n[[walls]]\nnormal = [0.0, 0.0, 1.0]\n\
             point = [0.0, 0.0, 0.0]\n[[walls]]\nnormal = [0.0, 0.0, -1.0]\n\
             point = [0.0, 0.0, 3.0]\n",
            "count = 100\n",
        )
    } else {
        ("", "count = 125\npacking_fraction = 0.02\n")
    };
    let mut sys = system(&format!(
        "t_end = 2.0\n{domain}[material]\n{law}density = 1140.0\nfriction = 0.3\n\
         [gas]\n{size}radius = 0.1\narrangement = \"random\"\nrms_speed = 1.0\nseed = 7\n"
    ));
    for (i, w) in sys.particles.angular_velocity.iter_mut().enumerate() {
        *w = [(i % 3) as f64 - 1.0, 2.0 - (i % 5) as f64, 0.5];
    }
    sys
}

#[test]
fn every_particle_event_driven_is_the_frictional_emdstar_engine_to_the_bit() {
    // Every collision an exact frictional solve, with pairs and with walls.
    for hertz in [false, true] {
        let s = event_driven_against_emdstar(&frictional_gas(hertz, false), 2.0);
        assert!(s.pair_collisions > 20, "too few collisions to test: {s:?}");
        assert_eq!(s.frictional_solves, s.pair_collisions);
        // Long enough for hundreds of wall collisions, too short for a sphere to come
        // to rest on the floor (which the event budget would hand to MD).
        let s = event_driven_against_emdstar(&frictional_gas(hertz, true), 0.8);
        assert!(s.pair_collisions > 20 && s.wall_collisions > 50, "{s:?}");
        assert_eq!(s.frictional_solves, s.pair_collisions + s.wall_collisions);
    }
}
