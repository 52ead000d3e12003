//! Quick versions of the validation scenarios, run by `cargo test`. Every bar comes from
//! an independent reference: the exact two-body solution (MoR solver) for the engines,
//! MD's convergence to it (MD shares no code with the MoR solver), conservation laws,
//! and the paper's figures.

use emdstar_contact::{ForceLaw, LinearDashpot, ViscoelasticHertz};
use emdstar_harness::cooling::{CoolingSettings, run as cool};
use emdstar_harness::diffusion::{DiffusionSettings, run as diffuse};
use emdstar_harness::engines::{EventKind, event_engine, lattice_gas};
use emdstar_harness::pair_summary::summarise;
use emdstar_harness::pairs::{PairSettings, sweep};

#[test]
fn pair_sweep_engines_against_the_exact_solution() {
    let settings = PairSettings {
        impacts_per_model: 24,
        md_steps_per_contact: vec![50, 100, 200, 400],
        unequal_fraction: 0.5,
        seed: 7,
    };
    let result = sweep(&settings, &|| {}).unwrap();
    assert!(result.skipped.is_empty(), "{:?}", result.skipped);
    for model in ["linear", "hertz"] {
        let s = summarise(&result, model);
        assert_eq!(s.impacts, 24);
        assert!(s.unequal_radii > 0);
        // eMD* with the exact MoR reproduces the exact outcome up to round-off.
        assert!(s.emdstar_exact.max < 1e-8, "{model}: {:?}", s.emdstar_exact);
        // MD converges to the same solution, at second order (linear) or about 1.5
        // (Hertz: √ξ at touch and strong damping).
        assert!(s.md_order > 1.4, "{model}: MD order {}", s.md_order);
        assert!(s.md.last().unwrap().median < 1e-6, "{model}: {:?}", s.md);
        // The table only adds its own interpolation error.
        assert!(s.table_ratio_max < 2.0, "{model}: {}", s.table_ratio_max);
        // Classic eMD misses the rotation and the duration (Sec. VI A).
        assert!(
            s.emd.median > 100.0 * s.emdstar_table.median,
            "{model}: {:?}",
            s.emd
        );
    }
}

#[test]
fn fig6_emdstar_follows_md_and_emd_does_not() {
    let f = emdstar_harness::fig6::run(100).unwrap();
    assert!(
        f.emdstar_exact_deviation_after < 1e-5,
        "{}",
        f.emdstar_exact_deviation_after
    );
    assert!(
        f.emdstar_deviation_after < 1e-3,
        "{}",
        f.emdstar_deviation_after
    );
    assert!(f.emd_deviation_after > 1e-2, "{}", f.emd_deviation_after);
}

#[test]
fn elastic_emdstar_gas_conserves_energy_and_momentum() {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 0.0).unwrap());
    let system = lattice_gas(&law, 1140.0, 0.1, 1000, 0.05, 2.0, 3).unwrap();
    let e0 = system.particles.kinetic_energy();
    let mut e = event_engine(&system, EventKind::EmdStarTable).unwrap();
    e.run_collisions(2000).unwrap();
    let drift = (e.kinetic_energy() - e0) / e0;
    assert!(drift.abs() < 1e-9, "energy drift {drift}");
    let p = e.momentum();
    let scale = system.particles.total_mass() * 2.0;
    assert!(p.iter().all(|c| c.abs() < 1e-9 * scale), "momentum {p:?}");
}

#[test]
fn cooling_linear_gas_follows_haff_and_md() {
    let s = CoolingSettings {
        name: "linear".into(),
        law: ForceLaw::Linear(LinearDashpot::new(1e4, 0.6).unwrap()),
        particles: 343,
        packing_fraction: 0.05,
        radius: 0.01,
        density: 1140.0,
        rms_speed: 2.0,
        t_end: 1.5,
        samples: 31,
        seed: 2,
    };
    let c = cool(&s, &|_| {}).unwrap();
    // Haff's law: T ∝ (1 + t/t0)^-2 for a constant coefficient of restitution.
    for (curve, fit) in c.curves.iter().zip(&c.fits) {
        assert!(
            (fit.exponent - 2.0).abs() < 0.4,
            "{}: p = {}",
            curve.engine,
            fit.exponent
        );
    }
    let t = &c.curves[0].temperature;
    assert!(t.last().unwrap() / t[0] < 0.2, "the gas cooled too little");
    // eMD* against MD, small gas: within 10 %.
    let worst = c.agreement[1].iter().copied().fold(0.0, f64::max);
    assert!(worst < 0.1, "eMD* vs MD {worst}");
}

#[test]
fn pair_sweep_does_not_depend_on_the_thread_count() {
    let settings = PairSettings {
        impacts_per_model: 6,
        md_steps_per_contact: vec![25, 50],
        unequal_fraction: 0.5,
        seed: 11,
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| sweep(&settings, &|| {}).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let key = |s: &emdstar_harness::pairs::PairSweep| {
        s.impacts
            .iter()
            .map(|r| (r.emd, r.emdstar_table, r.emdstar_exact, r.md.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(key(&one), key(&two));
}

#[test]
fn diffusion_of_hard_spheres_is_enskogs_and_emdstar_keeps_the_soft_contact() {
    let s = DiffusionSettings {
        particles: 1000,
        packing_fraction: 0.05,
        young: 1e7,
        free_times: 60.0,
        equilibration_free_times: 5.0,
        fit_lags: (5.0, 20.0),
        seed: 1,
    };
    let d = diffuse(&s, &|_| {}).unwrap();
    let (md, emd, star) = (&d.engines[0], &d.engines[1], &d.engines[2]);
    // eMD collides hard spheres (ε = 1 for A = 0): Enskog's theory within 10 %.
    let hard = emd.coefficient / d.enskog;
    assert!((hard - 1.0).abs() < 0.1, "hard spheres D/D_E = {hard}");
    // The soft contact makes MD diffuse faster than hard spheres; eMD* follows MD
    // (small gas: within 10 %) and is closer to it than eMD.
    let (soft, emdstar) = (
        md.coefficient / emd.coefficient,
        star.coefficient / md.coefficient,
    );
    assert!(soft > 1.05, "MD / eMD = {soft}");
    assert!((emdstar - 1.0).abs() < 0.1, "eMD* / MD = {emdstar}");
    assert!(
        (emdstar - 1.0).abs() < (1.0 / soft - 1.0).abs(),
        "{emdstar} {soft}"
    );
}

#[test]
fn fig7_exceptions_grow_with_density_and_the_count_reaches_its_target() {
    use emdstar_harness::exceptions::{Effort, run_point};
    let effort = Effort {
        min_per_particle: 10.0,
        max_per_particle: 60.0,
        target_exceptions: 30,
    };
    let dense = run_point(0.2, 1e9, 500, effort, 3).unwrap();
    let dilute = run_point(0.003, 1e9, 500, effort, 3).unwrap();
    // The dense gas meets its target within the minimum; the dilute one runs on.
    assert_eq!(dense.collisions, 2500, "{dense:?}");
    assert!(
        dilute.collisions > 2500 && dilute.collisions <= 15_000,
        "{dilute:?}"
    );
    assert!(
        dilute.rotation + dilute.interference >= 30 || dilute.collisions == 15_000,
        "{dilute:?}"
    );
    // Paper, Fig. 7a: exceptions are rare when dilute, common when dense (> 10×).
    let (lo_dense, _) = dense.per_mille_total_interval;
    let (_, hi_dilute) = dilute.per_mille_total_interval;
    assert!(lo_dense > 10.0 * hi_dilute, "{dense:?} {dilute:?}");
}

#[test]
fn fig7_gases_pool_their_counts_and_run_as_they_would_alone() {
    use emdstar_harness::exceptions::{Effort, run_point, run_replicas};
    let effort = Effort {
        min_per_particle: 10.0,
        max_per_particle: 30.0,
        target_exceptions: 10,
    };
    let pooled = run_replicas(0.01, 1e9, 400, effort, 5, 3).unwrap();
    assert_eq!(pooled.gases.len(), 3);
    // Run in parallel, each gas is the gas of its seed run alone.
    for (k, gas) in pooled.gases.iter().enumerate() {
        let alone = run_point(0.01, 1e9, 400, effort, 5 + k as u64).unwrap();
        assert_eq!(
            (gas.collisions, gas.rotation, gas.interference),
            (alone.collisions, alone.rotation, alone.interference)
        );
    }
    let p = &pooled.pooled;
    let sum = |f: fn(&emdstar_harness::exceptions::ExceptionPoint) -> u64| {
        pooled.gases.iter().map(f).sum::<u64>()
    };
    assert_eq!(p.collisions, sum(|g| g.collisions));
    assert_eq!(
        p.rotation + p.interference,
        sum(|g| g.rotation + g.interference)
    );
    let f = 1000.0 * (p.rotation + p.interference) as f64 / p.collisions as f64;
    assert!((p.per_mille_total - f).abs() < 1e-12 * f);
    let (lo, hi) = p.per_mille_total_interval;
    assert!(lo < f && f < hi);
    // The mean over gases lies between the smallest and largest gas.
    let fs: Vec<f64> = pooled.gases.iter().map(|g| g.per_mille_total).collect();
    let (min, max) = fs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!(min <= pooled.mean && pooled.mean <= max && pooled.standard_error >= 0.0);
    assert!(run_replicas(0.01, 1e9, 400, effort, 5, 0).is_err());
}
