//! Driven runs (`[driving]`, ticks applied at step boundaries through
//! `change_velocities`): with every particle in one mode the hybrid is that engine to
//! the bit, kicks included (MD; the eMD* engine on cell crossings); with both modes
//! present, the energy white noise feeds is (3/2) m ξ₀² (1 − 1/N) per particle and
//! second, within its sampling error.

use crate::common::{
    dense_hertz_gas, emdstar_engine, gas_under_gravity, hybrid_with, md, steps_to, system,
};
use emdstar_edmd::Engine;
use emdstar_hybrid::{Hybrid, HybridOptions, Mode};
use emdstar_system::{Drive, DriveKind, Simulation, System};

const WHITE_NOISE: DriveKind = DriveKind::WhiteNoise { strength: 50.0 };
const ANDERSEN: DriveKind = DriveKind::Andersen { temperature: 5.0 };

/// A drive of `kind` ticking every `steps` steps of `dt` (its rate in ticks per
/// second), so that its ticks fall on step boundaries up to rounding.
fn drive(kind: DriveKind, dt: f64, steps: u64) -> Drive {
    Drive {
        kind,
        rate: 1.0 / (steps as f64 * dt),
        seed: 11,
    }
}

/// Tick `k` on the hybrid.
fn tick(h: &mut Hybrid, d: &Drive, k: u64) {
    h.change_velocities(&mut |v, m| d.apply(k, v, m)).unwrap();
}

#[test]
fn driven_with_every_particle_time_driven_is_md_to_the_bit() {
    let gas = dense_hertz_gas();
    for kind in [WHITE_NOISE, ANDERSEN] {
        let (dt, steps, _) = steps_to(&gas, 0.1, 0.02);
        let mut h = hybrid_with(&gas, HybridOptions::with_dt(dt), 0.1);
        let mut m = md(&gas, dt, h.skin(), 0.1);
        let every = 20;
        let d = drive(kind, dt, every);
        for k in 1..=steps / every {
            h.advance(every).unwrap();
            m.stride(every).unwrap();
            tick(&mut h, &d, k);
            m.change_velocities(&mut |v, mass| d.apply(k, v, mass))
                .unwrap();
        }
        assert_eq!(h.count(Mode::Time), gas.particles.len());
        assert!(m.rebuilds() > 2, "too few rebuilds: {}", m.rebuilds());
        assert_eq!(h.stats().rebuilds, m.rebuilds());
        assert_eq!(h.particles(), m.particles_in_config_order(), "{kind:?}");
        assert_eq!(h.thermo(), m.thermo(), "{kind:?}");
        // The kinetic tensor summed by step (the hybrid) or by particle (MD without
        // gravity): the same sums, rounded otherwise.
        let (a, b) = (h.stress_sums(), Simulation::stress_sums(&m));
        assert_eq!((a.collisional, a.collisions), (b.collisional, b.collisions));
        for k in 0..6 {
            let scale = a.kinetic[0] + a.kinetic[1] + a.kinetic[2];
            assert!(
                (a.kinetic[k] - b.kinetic[k]).abs() < 1e-12 * scale,
                "{a:?}\n{b:?}"
            );
        }
    }
}

/// The eMD* engine on cell crossings (the hybrid's event core), driven at the same
/// step boundaries: its state and counts after `ticks` ticks every `every` steps.
fn emdstar_driven(sys: &System, d: &Drive, dt: f64, every: u64, ticks: u64) -> Engine {
    let mut e = emdstar_engine(sys);
    for k in 1..=ticks {
        e.run_until((k * every) as f64 * dt).unwrap();
        e.change_velocities(&mut |v, m| d.apply(k, v, m)).unwrap();
    }
    e
}

#[test]
fn driven_with_every_particle_event_driven_is_the_emdstar_engine_to_the_bit() {
    // Elastic spheres under gravity between a floor and a lid, periodic sideways.
    let gas = gas_under_gravity(0.0);
    for kind in [WHITE_NOISE, ANDERSEN] {
        let (dt, steps, _) = steps_to(&gas, 0.6, 0.02);
        let every = 50;
        let ticks = steps / every;
        let d = drive(kind, dt, every);
        let mut h = hybrid_with(&gas, HybridOptions::with_dt(dt), 0.6);
        for k in 1..=ticks {
            h.advance(every).unwrap();
            tick(&mut h, &d, k);
        }
        let s = *h.stats();
        assert_eq!((s.to_time, s.td_particle_steps), (0, 0), "{s:?}");
        let mut e = emdstar_driven(&gas, &d, dt, every, ticks);
        assert_eq!(s.ed, *e.stats(), "{kind:?}");
        assert!(
            s.ed.pair_collisions > 20 && s.ed.wall_collisions > 20,
            "{s:?}"
        );
        let mut reference = gas.particles.clone();
        e.write_state(&mut reference);
        let p = h.particles();
        assert_eq!(p.position, reference.position, "{kind:?}");
        assert_eq!(p.velocity, reference.velocity, "{kind:?}");
    }
    // Undriven, the hybrid ends elsewhere: the kicks did act.
    let (dt, steps, _) = steps_to(&gas, 0.6, 0.02);
    let mut h = hybrid_with(&gas, HybridOptions::with_dt(dt), 0.6);
    h.advance(steps - steps % 50).unwrap();
    let d = drive(WHITE_NOISE, dt, 50);
    let driven = emdstar_driven(&gas, &d, dt, 50, steps / 50);
    assert_ne!(driven.velocities(), h.particles().velocity);
}

#[test]
fn white_noise_feeds_its_power_to_both_modes() {
    // An elastic gas (linear springs, no damping) at a packing fraction between the
    // thresholds: dense spots run TD, the rest ED. Between ticks the energy is
    // conserved; at each tick of kicks Δv ~ N(0, s²) per component (s² = ξ₀²/f), the
    // mean kick taken off, it gains (3/2)(N − 1) m s² on average, with a variance
    // s² Σ m²|v|² + (3/2)(N − 1) m² s⁴ given the velocities before it.
    let gas = system(
        r#"
t_end = 1.0
[material]
model = "linear"
stiffness = 1e4
density = 1140.0
[gas]
count = 500
radius = 0.1
arrangement = "random"
packing_fraction = 0.12
rms_speed = 1.0
seed = 3
"#,
    );
    let (dt, _, _) = steps_to(&gas, 1.0, 0.02);
    let every = 20;
    let (strength, rate) = (4.5, 1.0 / (every as f64 * dt));
    let d = Drive {
        kind: DriveKind::WhiteNoise { strength },
        rate,
        seed: 5,
    };
    let (n, m) = (gas.particles.len() as f64, gas.particles.mass[0]);
    let s2 = strength / rate;
    let mut h = hybrid_with(&gas, HybridOptions::with_dt(dt), 1.0);
    let energy = |h: &Hybrid| {
        let t = h.thermo();
        t.kinetic_energy + t.potential_energy
    };
    let start = energy(&h);
    let (mut last, mut drift, mut variance) = (start, 0.0f64, 0.0);
    let mut mixed_ticks = 0;
    let ticks = 50;
    for k in 1..=ticks {
        h.advance(every).unwrap();
        let before = energy(&h);
        drift = drift.max((before - last).abs());
        if h.count(Mode::Time) >= 20 && h.count(Mode::Event) >= 20 {
            mixed_ticks += 1;
        }
        variance += s2 * m * 2.0 * h.thermo().kinetic_energy + 1.5 * (n - 1.0) * (m * s2).powi(2);
        // What the thermostat changed, as it saw the velocities: the engine shows it.
        let mut changed = 0.0;
        h.change_velocities(&mut |v, mass| {
            let kinetic = |v: &[[f64; 3]]| -> f64 {
                v.iter()
                    .zip(mass)
                    .map(|(w, m)| 0.5 * m * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]))
                    .sum()
            };
            changed = -kinetic(v);
            d.apply(k, v, mass);
            changed += kinetic(v);
        })
        .unwrap();
        last = energy(&h);
        assert!(
            (last - before - changed).abs() < 1e-9 * last,
            "tick {k}: the energy changed by {:e} J, the kicks by {changed:e} J",
            last - before
        );
    }
    eprintln!("{:?}", h.stats());
    let s = h.stats();
    // The gas starts event-driven; dense spots turn time-driven within ten ticks.
    assert!(
        mixed_ticks >= 30,
        "both modes at only {mixed_ticks} of {ticks} ticks"
    );
    assert!(
        s.ed.pair_collisions > 300 && s.to_time > 0 && s.to_event > 0,
        "{s:?}"
    );
    // The power: (3/2) m ξ₀² (1 − 1/N) per particle.
    let expected = ticks as f64 / rate * 1.5 * m * strength * (1.0 - 1.0 / n) * n;
    let gained = last - start;
    let sigma = variance.sqrt();
    eprintln!("gained {gained:e} J, expected {expected:e} ± {sigma:e} J");
    assert!(
        (gained - expected).abs() < 4.0 * sigma,
        "gained {gained:e} J, expected {expected:e} ± {sigma:e} J"
    );
    assert!(sigma < 0.05 * expected, "too noisy to tell: {sigma:e} J");
    // Between ticks the elastic gas keeps its energy (MD's steps up to O(dt²)).
    assert!(
        drift < 1e-3 * last,
        "energy changed by {drift:e} J between ticks"
    );
}
