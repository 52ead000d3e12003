//! Unwrapped positions (position + image flags × box size) are exact across periodic
//! crossings in every engine and broad phase: free particles that cross the box
//! dozens of times along each axis, both ways, are where x₀ + v t puts them, within
//! round-off, at every readout; and a run saved and restored on the way ends with the
//! same flags. In a colliding gas (collisions across the periodic faces move a sphere
//! to where its partner's image puts it), no sphere's unwrapped position jumps between
//! readouts by more than its flight could take it.

use emdstar_engines::{AnyEngine, BroadPhaseChoice, EngineKind, EngineOptions};
use emdstar_system::{Config, Particles, SimBox};

/// 72 spheres in lanes along the three axes (three per lane, at one speed per axis):
/// the lanes along different axes pass each other more than a diameter apart, so no
/// two spheres ever touch; each crosses the unit box 73 (x), 51 (y, downwards) or 33
/// (z) times in 10 s.
fn config() -> String {
    let mut text = String::from(
        "t_end = 10.0\n[material]\nmodel = \"hertz\"\nyoung = 1e7\npoisson = 0.3\n\
         dissipation = 1e-4\ndensity = 1000.0\n[box]\nsize = [1.0, 1.0, 1.0]\n",
    );
    let mut sphere = |x: [f64; 3], v: [f64; 3]| {
        text.push_str(&format!(
            "[[particles]]\nradius = 0.01\nposition = {x:?}\nvelocity = {v:?}\n"
        ));
    };
    let along = [0.1, 0.43, 0.76];
    for a in [0.1, 0.3, 0.5, 0.7, 0.9] {
        for b in [0.1, 0.35] {
            for &s in &along {
                sphere([s, a, b], [7.3, 0.0, 0.0]);
                sphere([a, s + 0.05, b + 0.5], [0.0, -5.1, 0.0]);
            }
        }
    }
    for a in [0.2, 0.4] {
        for b in [0.2, 0.4] {
            for &s in &along {
                sphere([a, b, s], [0.0, 0.0, 3.3]);
            }
        }
    }
    text
}

fn engines() -> Vec<(String, EngineOptions)> {
    let mut out = Vec::new();
    for engine in [EngineKind::Md, EngineKind::Hybrid] {
        out.push((
            format!("{engine:?}"),
            EngineOptions {
                engine,
                ..Default::default()
            },
        ));
    }
    for engine in [EngineKind::Emd, EngineKind::EmdStar] {
        for broad in [
            BroadPhaseChoice::Crossings,
            BroadPhaseChoice::Epochs,
            BroadPhaseChoice::Neighbours,
        ] {
            // Neighbour lists run eMD and hard spheres only.
            if engine == EngineKind::EmdStar && broad == BroadPhaseChoice::Neighbours {
                continue;
            }
            let mut o = EngineOptions {
                engine,
                ..Default::default()
            };
            o.edmd.broad_phase = broad;
            out.push((format!("{engine:?} {broad:?}"), o));
        }
    }
    out
}

fn check(name: &str, p: &Particles, b: &SimBox, x0: &[[f64; 3]], v: &[[f64; 3]], t: f64) {
    for i in 0..p.len() {
        let u = p.unwrapped(i, Some(b));
        for k in 0..3 {
            let expected = x0[i][k] + v[i][k] * t;
            assert!(
                (u[k] - expected).abs() < 1e-9,
                "{name}: particle {i} at t = {t}: unwrapped {u:?}, x0 + v t = {expected} along {k} \
                 (image {:?})",
                p.image[i]
            );
        }
    }
}

#[test]
fn unwrapped_positions_follow_free_flight_in_every_engine() {
    let config = Config::from_toml(&config()).unwrap();
    let system = config.build().unwrap();
    let b = system.domain.sim_box.unwrap();
    let (x0, v) = (
        system.particles.position.clone(),
        system.particles.velocity.clone(),
    );
    for (name, options) in engines() {
        let mut engine = AnyEngine::build(&options, &config, config.build().unwrap(), 1.0 / 50.0)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let mut saved = None;
        for step in 1..=20 {
            let t = 0.5 * f64::from(step);
            let sim = engine.sim_mut();
            sim.advance_to(t).unwrap();
            sim.synchronise().unwrap();
            // A step engine ends on its step nearest t.
            let now = sim.time();
            check(&name, &sim.particles(), &b, &x0, &v, now);
            if step == 7 {
                saved = Some(sim.save_state());
            }
        }
        let end = engine.sim().particles();
        assert!(
            end.image[0][0] >= 70 && end.image[1][1] <= -50,
            "{name}: {:?}",
            end.image
        );
        // Restored at t = 3.5 and run on: the same flags and positions at the end.
        let mut again =
            AnyEngine::build(&options, &config, config.build().unwrap(), 1.0 / 50.0).unwrap();
        again.sim_mut().restore_state(&saved.unwrap()).unwrap();
        for step in 8..=20 {
            again.sim_mut().advance_to(0.5 * f64::from(step)).unwrap();
            again.sim_mut().synchronise().unwrap();
        }
        assert_eq!(again.sim().particles(), end, "{name}: restored run");
    }
}

/// A gas of 400 spheres at packing fraction 0.1 in a periodic box of about 1.3 m,
/// colliding elastically (many pairs across the faces).
const GAS: &str = "t_end = 4.0
[material]
model = \"hertz\"
young = 1e7
poisson = 0.3
dissipation = 0.0
density = 1000.0
[gas]
count = 400
radius = 0.05
arrangement = \"random\"
packing_fraction = 0.1
rms_speed = 1.0
seed = 5
";

#[test]
fn unwrapped_positions_never_jump_in_a_colliding_gas() {
    let config = Config::from_toml(GAS).unwrap();
    let b = config.build().unwrap().domain.sim_box.unwrap();
    let mut runs = engines();
    runs.retain(|(name, _)| !name.contains("Neighbours"));
    for (name, options) in runs {
        let mut engine = AnyEngine::build(&options, &config, config.build().unwrap(), 1.0 / 50.0)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let sim = engine.sim_mut();
        let mut before = sim.particles();
        let mut crossings = 0;
        for step in 1..=40 {
            let dt = 0.1;
            sim.advance_to(dt * f64::from(step)).unwrap();
            sim.synchronise().unwrap();
            let now = sim.particles();
            for i in 0..now.len() {
                let (a, c) = (before.unwrapped(i, Some(&b)), now.unwrapped(i, Some(&b)));
                let d = ((0..3).map(|k| (c[k] - a[k]).powi(2)).sum::<f64>()).sqrt();
                // Elastic: no sphere is faster than √(2K/m) of the whole gas.
                let v_max = (2.0 * sim.thermo().kinetic_energy / now.mass[i]).sqrt();
                assert!(
                    d <= v_max * dt + 1e-9,
                    "{name}: sphere {i} jumped {d} m at step {step}"
                );
                crossings += (0..3)
                    .filter(|&k| now.image[i][k] != before.image[i][k])
                    .count();
            }
            before = now;
        }
        assert!(crossings > 100, "{name}: {crossings} crossings");
    }
}
