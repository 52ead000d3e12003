//! The pressure tensor, collision rate and a₂ every engine reports, against
//! independent references: the ideal gas (p = Σ m v²/3V exactly, no collisions),
//! Carnahan–Starling's equation of state of elastic hard spheres, and MD against eMD*
//! on the same dilute inelastic gas (Müller & Pöschel 2013: eMD* reproduces the
//! contacts' end points, so the pressure tensors agree within the noise).

use emdstar_engines::observe::{reading, since};
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions};
use emdstar_system::{Config, Observables, Simulation};

fn engine(text: &str, kind: EngineKind) -> AnyEngine {
    let config = Config::from_toml(text).unwrap();
    let system = config.build().unwrap();
    let options = EngineOptions {
        engine: kind,
        ..Default::default()
    };
    AnyEngine::build(&options, &config, system, 1.0 / 50.0).unwrap()
}

/// Runs `sim` from `t0` to `t1` and returns the observables of that interval.
fn measure(sim: &mut dyn Simulation, t0: f64, t1: f64) -> Observables {
    sim.advance_to(t0).unwrap();
    let from = reading(sim);
    sim.advance_to(t1).unwrap();
    since(sim, Some(&from))
}

fn gas(model: &str, count: usize, eta: f64, t_end: f64) -> String {
    format!(
        "t_end = {t_end}
[material]
{model}
density = 1000.0
[gas]
count = {count}
radius = 0.01
arrangement = \"random\"
packing_fraction = {eta}
rms_speed = 1.0
seed = 3
"
    )
}

const HERTZ_ELASTIC: &str = "model = \"hertz\"\nyoung = 1e8\npoisson = 0.4";
const HERTZ_DAMPED: &str = "model = \"hertz\"\nyoung = 1e8\npoisson = 0.4\ndissipation = 1.5e-5";

#[test]
fn ideal_gas_pressure_is_n_k_t_exactly() {
    // 20 spheres at η = 1e-6 for 10 ms: a collision is vanishingly rare (checked).
    let text = gas(HERTZ_ELASTIC, 20, 1e-6, 0.01);
    for kind in [
        EngineKind::Md,
        EngineKind::Emd,
        EngineKind::EmdStar,
        EngineKind::Hybrid,
    ] {
        let mut e = engine(&text, kind);
        let sim = e.sim_mut();
        let obs = measure(sim, 0.0, 0.01);
        let p = sim.particles();
        let volume = sim.domain().sim_box.unwrap().volume();
        let expect: [f64; 6] = std::array::from_fn(|c| {
            let (a, b) = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)][c];
            p.mass
                .iter()
                .zip(&p.velocity)
                .map(|(m, v)| m * v[a] * v[b])
                .sum::<f64>()
                / volume
        });
        assert_eq!(obs.collision_rate, 0.0, "{kind:?}: a collision happened");
        for c in 0..6 {
            let scale = expect[0] + expect[1] + expect[2];
            assert!(
                (obs.tensor[c] - expect[c]).abs() <= 1e-12 * scale,
                "{kind:?} component {c}: {} against Σ m v v / V = {}",
                obs.tensor[c],
                expect[c]
            );
        }
        // p = n k T with T the granular temperature (zero total momentum).
        let n_t = p.len() as f64 * p.granular_temperature() / volume;
        assert!((obs.pressure - n_t).abs() <= 1e-9 * n_t, "{kind:?}");
    }
}

/// Carnahan & Starling 1969: Z = pV/(NkT) = (1 + η + η² − η³)/(1 − η)³.
fn carnahan_starling(eta: f64) -> f64 {
    (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3)
}

#[test]
fn elastic_hard_spheres_follow_carnahan_starling() {
    // 1000 elastic hard spheres at η = 0.25 (eMD's rule at ε = 1), about 300
    // collisions per particle after 30 to equilibrate: the collisional part's
    // statistical error is about 1/√(1.5·10⁵) ≈ 0.3 % of Z − 1.
    let eta = 0.25;
    let mut e = engine(&gas(HERTZ_ELASTIC, 1000, eta, 10.0), EngineKind::Emd);
    let sim = e.sim_mut();
    let obs = measure(sim, 0.1, 1.1);
    let p = sim.particles();
    let volume = sim.domain().sim_box.unwrap().volume();
    let z = obs.pressure * volume / (p.len() as f64 * p.granular_temperature());
    let cs = carnahan_starling(eta);
    assert!(
        (z / cs - 1.0).abs() < 0.01,
        "Z = {z} against Carnahan–Starling's {cs} (rate {} /s)",
        obs.collision_rate
    );
    // Elastic: a₂ of the equilibrium Maxwellian is zero (±√(8/(3N)) noise).
    assert!(obs.sonine_a2.abs() < 0.2, "a2 = {}", obs.sonine_a2);
}

#[test]
fn emdstar_and_md_agree_on_the_pressure_tensor_of_a_dilute_inelastic_gas() {
    // 2000 viscoelastic spheres at η = 0.05, ε ≈ 0.85 at 1 m/s: the same initial state,
    // the pressure over the same 0.2 s (≈ 6 collisions per particle, the gas cooling).
    let text = gas(HERTZ_DAMPED, 2000, 0.05, 0.2);
    let mut observed = Vec::new();
    for kind in [EngineKind::Md, EngineKind::EmdStar] {
        let mut e = engine(&text, kind);
        observed.push(measure(e.sim_mut(), 0.0, 0.2));
    }
    let (md, star) = (&observed[0], &observed[1]);
    eprintln!("MD {md:?}\neMD* {star:?}");
    // The diagonal agrees to the noise of ~6000 collisions in the collisional part
    // (≈ 20 % of p here, so ≈ 0.3 %) plus the trajectories' divergence: 1 %.
    for c in 0..3 {
        let rel = star.tensor[c] / md.tensor[c] - 1.0;
        assert!(rel.abs() < 0.01, "p_{c}{c}: eMD* {star:?} MD {md:?}");
    }
    // Off-diagonal components: both engines start from the same velocities, whose
    // Σ m v_x v_y is of order p/√N ≈ 2 % of p and decays over a few collision times;
    // the two agree within 1 % of p.
    for c in 3..6 {
        let diff = star.tensor[c] - md.tensor[c];
        assert!(diff.abs() < 0.01 * md.pressure, "{star:?} {md:?}");
    }
    let rate = star.collision_rate / md.collision_rate - 1.0;
    assert!(rate.abs() < 0.02, "collision rates {star:?} {md:?}");
}

#[test]
fn driven_runs_do_not_depend_on_the_thread_count() {
    // 2000 spheres: MD's force loop runs in two parallel chunks on two threads, in one
    // fused pass on one; the kicks come from the seed in config order either way.
    let text = gas(HERTZ_DAMPED, 2000, 0.05, 0.05)
        + "[driving]\nkind = \"white_noise\"\nstrength = 5.0\nrate = 1000.0\nseed = 11\n";
    for kind in [EngineKind::Md, EngineKind::EmdStar] {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let mut e = engine(&text, kind);
                let drive = Config::from_toml(&text)
                    .unwrap()
                    .driving
                    .unwrap()
                    .drive()
                    .unwrap();
                let sim = e.sim_mut();
                emdstar_engines::drive::advance(sim, Some(&drive), 0.05).unwrap();
                (sim.particles().velocity, sim.stress_sums())
            })
        };
        let (one, two) = (run(1), run(2));
        assert!(one.0 == two.0, "{kind:?}: velocities differ");
        assert!(one.1 == two.1, "{kind:?}: {:?} against {:?}", one.1, two.1);
        // The gas collided and took 50 ticks: the comparison is not empty.
        assert!(one.1.collisions > 100, "{kind:?}: {:?}", one.1);
    }
}
