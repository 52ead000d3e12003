//! Scenario 8 of `emdstar validate`: gases against kinetic theory through the
//! observables of the thermo log (pressure tensor, collision rate, Sonine a₂).

use super::{StageOutput, ValidateArgs, bar};
use anyhow::{Result, anyhow};
use emdstar_engines::EngineKind;
use emdstar_harness::Check;
use emdstar_harness::driven::{DrivenSettings, apart, driven_a2, driven_state};
use emdstar_harness::shear::{ShearSettings, plot_viscosity, sheared_viscosity};
use emdstar_harness::sheared_pair::{ShearPairSettings, largest_deviation, sheared_state};
use emdstar_harness::theory::{
    CoolingSettings, EosSettings, cooling_state_a2, hard_sphere_eos, plot_a2, plot_eos,
};
use emdstar_harness::vibrated::{OrbitSettings, orbit};
use serde_json::json;

/// Elastic hard spheres against Carnahan–Starling, and the homogeneous cooling state's
/// a₂ against van Noije & Ernst.
pub fn run(args: &ValidateArgs) -> Result<StageOutput> {
    let eos = EosSettings {
        etas: vec![0.1, 0.2, 0.3, 0.4],
        count: if args.full { 4000 } else { 864 },
        equilibrate: 20.0,
        measure: if args.full { 500.0 } else { 100.0 },
        seed: args.seed,
    };
    let cooling = CoolingSettings {
        restitution: 0.8,
        eta: 0.1,
        count: if args.full { 20_000 } else { 4000 },
        transient: 5.0,
        measure: if args.full { 100.0 } else { 40.0 },
        seed: args.seed,
    };
    let driven = DrivenSettings {
        restitution: 0.8,
        eta: 0.05,
        count: if args.full { 8000 } else { 2000 },
        stiffness: 1e7,
        strength: 2.0,
        rate: 400.0,
        relax: 10.0,
        measure: if args.full { 200.0 } else { 60.0 },
        seed: args.seed,
    };
    let pair = DrivenSettings {
        count: if args.full { 8000 } else { 2000 },
        stiffness: 1e4,
        measure: if args.full { 200.0 } else { 60.0 },
        ..driven.clone()
    };
    // Denser: clusters reach the hybrid's φ_TD, so both of its modes run.
    let mixed = DrivenSettings {
        eta: 0.1,
        count: if args.full { 4000 } else { 1000 },
        stiffness: 1e4,
        measure: if args.full { 200.0 } else { 60.0 },
        ..driven.clone()
    };
    let plate = OrbitSettings::default();
    let shear = ShearSettings {
        phi: 0.15,
        count: if args.full { 8000 } else { 4000 },
        rate: 0.2,
        blocks: 21,
        block: 2.5,
        seeds: if args.full {
            (0..4).map(|k| args.seed + k).collect()
        } else {
            vec![args.seed, args.seed + 1]
        },
    };
    let shear_pair = ShearPairSettings {
        restitution: 0.9,
        stiffness: 1e5,
        phi: 0.15,
        count: if args.full { 2000 } else { 500 },
        rate: 1.0,
        start_kt: 3.0,
        relax: 2.0,
        blocks: if args.full { 10 } else { 3 },
        block: 3.0,
        samples: 10,
        seeds: (0..6).map(|k| args.seed + k).collect(),
    };
    let b = bar("theory", eos.etas.len() as u64 + 7);
    b.set_message(format!(
        "eMD: hard spheres at η = 0.1–0.4 (N = {}), a cooling state (N = {})",
        eos.count, cooling.count
    ));
    let points = hard_sphere_eos(&eos, &|| b.inc(1))?;
    let hcs = cooling_state_a2(&cooling)?;
    b.inc(1);
    let hard = driven_state(&driven, EngineKind::Emd)?;
    b.inc(1);
    let md = driven_state(&pair, EngineKind::Md)?;
    b.inc(1);
    let star = driven_state(&pair, EngineKind::EmdStar)?;
    b.inc(1);
    let mixed_md = driven_state(&mixed, EngineKind::Md)?;
    let mixed_hybrid = driven_state(&mixed, EngineKind::Hybrid)?;
    b.inc(1);
    let orbits = [EngineKind::Emd, EngineKind::EmdStar, EngineKind::Md]
        .map(|kind| orbit(&plate, kind).map_err(|e| anyhow!(e)));
    let [plate_emd, plate_star, plate_md] = orbits;
    let (plate_emd, plate_star, plate_md) = (plate_emd?, plate_star?, plate_md?);
    b.inc(1);
    let sheared = sheared_viscosity(&shear)?;
    b.inc(1);
    let (shear_md, shear_star) = rayon::join(
        || sheared_state(&shear_pair, EngineKind::Md),
        || sheared_state(&shear_pair, EngineKind::EmdStar),
    );
    let (shear_md, shear_star) = (shear_md?, shear_star?);
    let (worst_name, worst_z) = largest_deviation(&shear_star, &shear_md);
    b.inc(1);
    b.finish();
    let plate_png = args.out.join("theory_vibrated_plate.png");
    emdstar_harness::vibrated::plot(&[&plate_emd, &plate_star, &plate_md], &plate, &plate_png)
        .map_err(|e| anyhow!(e))?;
    let driven_png = args.out.join("theory_driven_temperature.png");
    emdstar_harness::driven::plot(&[&hard], driven.theory_temperature(), &driven_png)
        .map_err(|e| anyhow!(e))?;
    let pair_png = args.out.join("theory_driven_emdstar_md.png");
    emdstar_harness::driven::plot(&[&md, &star], pair.theory_temperature(), &pair_png)
        .map_err(|e| anyhow!(e))?;
    let mixed_png = args.out.join("theory_driven_hybrid_md.png");
    emdstar_harness::driven::plot(
        &[&mixed_md, &mixed_hybrid],
        mixed.theory_temperature(),
        &mixed_png,
    )
    .map_err(|e| anyhow!(e))?;
    let [(t_off, t_bar), (p_off, p_bar), (a_off, a_bar)] = apart(&star, &md);
    let hybrid_apart = apart(&mixed_hybrid, &mixed_md);
    let time_driven = mixed_hybrid.time_driven_fraction.unwrap_or(f64::NAN);
    let speed = (md.wall_seconds / md.time) / (star.wall_seconds / star.time);
    let shear_png = args.out.join("theory_shear_viscosity.png");
    plot_viscosity(&shear, &sheared, &shear_png).map_err(|e| anyhow!(e))?;
    let shear_pair_png = args.out.join("theory_sheared_emdstar_md.png");
    emdstar_harness::sheared_pair::plot(&shear_pair, &[&shear_md, &shear_star], &shear_pair_png)
        .map_err(|e| anyhow!(e))?;
    let eos_png = args.out.join("theory_carnahan_starling.png");
    plot_eos(&points, &eos_png).map_err(|e| anyhow!(e))?;
    let a2_png = args.out.join("theory_cooling_a2.png");
    plot_a2(&[("Homogeneous cooling state (eMD)", &hcs)], &a2_png).map_err(|e| anyhow!(e))?;
    let worst = points
        .iter()
        .map(|p| (p.z / p.carnahan_starling - 1.0).abs())
        .fold(0.0, f64::max);
    let mut checks = vec![
        Check::at_most(
            "8a",
            "elastic hard spheres (eMD): max |Z/Z_CS − 1| at η = 0.1, 0.2, 0.3, 0.4 (pressure from Σ r⊗Δp)",
            worst,
            0.01,
        ),
        Check::at_most(
            "8b",
            format!(
                "cooling state ε = {}: |a₂ − a₂(van Noije & Ernst)| within 3 standard errors ({:.4} ± {:.4} against {:.4})",
                hcs.restitution, hcs.a2, hcs.a2_error, hcs.theory
            ),
            (hcs.a2 - hcs.theory).abs(),
            3.0 * hcs.a2_error,
        ),
        Check::at_most(
            "8c",
            format!(
                "white-noise driven hard spheres (eMD, ε = {}, η = {}): |T/T_balance − 1| (energy balance with Enskog's collision rate; T = {:.4e} ± {:.1e} J)",
                driven.restitution, driven.eta, hard.temperature, hard.temperature_error
            ),
            (hard.temperature / driven.theory_temperature() - 1.0).abs(),
            0.03,
        ),
        Check::at_most(
            "8d",
            format!(
                "white-noise driven state: |a₂ − a₂(van Noije & Ernst, driven)| within 3 standard errors ({:.4} ± {:.4} against {:.4})",
                hard.a2,
                hard.a2_error,
                driven_a2(driven.restitution)
            ),
            (hard.a2 - driven_a2(driven.restitution)).abs(),
            3.0 * hard.a2_error,
        ),
        Check::at_most(
            "8e",
            format!(
                "driven state, eMD* against MD (N = {}, same kicks): |ΔT| within 3 standard errors ({:.4e} against {:.4e} J)",
                pair.count, star.temperature, md.temperature
            ),
            t_off,
            t_bar,
        ),
        Check::at_most(
            "8f",
            format!(
                "driven state, eMD* against MD: |Δp| within 3 standard errors ({:.4} against {:.4} Pa)",
                star.pressure, md.pressure
            ),
            p_off,
            p_bar,
        ),
        Check::at_most(
            "8g",
            format!(
                "driven state, eMD* against MD: |Δa₂| within 3 standard errors ({:.4} against {:.4})",
                star.a2, md.a2
            ),
            a_off,
            a_bar,
        ),
    ];
    let plate_check = |id: &str, run: &emdstar_harness::vibrated::OrbitRun, bar: f64| {
        Check::at_most(
            id,
            format!(
                "ball on a vibrated plate (Γ = {}, e = {}), {}: plate phase at the apex within {bar} rad of the period-1 orbit's ψ + π over {}–{} s (height {:.1e} of gT²/8)",
                plate.gamma, plate.restitution, run.engine, plate.from, plate.to, run.height_error
            ),
            run.phase_error,
            bar,
        )
    };
    checks.push(plate_check("8h", &plate_emd, 1e-3));
    checks.push(plate_check("8i", &plate_star, 1e-2));
    checks.push(plate_check("8j", &plate_md, 1e-2));
    checks.push(
        Check::at_most(
            "8k",
            format!(
                "sheared elastic hard spheres (eMD, Lees–Edwards, φ = {}, γ̇ = {} /s): |η/η_Enskog − 1| (η = −P_xy/γ̇ per block at its T; {:.4} ± {:.4})",
                shear.phi, shear.rate, sheared.ratio, sheared.ratio_error
            ),
            (sheared.ratio - 1.0).abs(),
            0.05,
        ),
    );
    for ((id, what), (off, bar)) in [("8l", "T"), ("8m", "p"), ("8n", "a₂")]
        .into_iter()
        .zip(hybrid_apart)
    {
        checks.push(Check::at_most(
            id,
            format!(
                "driven state at η = {} (N = {}, same kicks), the hybrid ({:.0} % of its particle-steps time-driven) against MD: |Δ{what}| within 3 standard errors",
                mixed.eta,
                mixed.count,
                100.0 * time_driven
            ),
            off,
            bar,
        ));
    }
    checks.push(Check::at_most(
        "8o",
        format!(
            "driven state at η = {}: the hybrid runs both modes (time-driven fraction of its particle-steps {time_driven:.3}, within 0.1–0.9)",
            mixed.eta
        ),
        (time_driven - 0.5).abs(),
        0.4,
    ));
    checks.push(Check::at_most(
        "8p",
        format!(
            "sheared inelastic gas (ε = {}, φ = {}, γ̇ = {} /s, N = {}), eMD* against MD: largest |Δ| in standard errors over kT, P_xx, P_yy, P_zz, P_xy, a₂ ({worst_name}; kT {:.3} against {:.3} J, P_xy {:.4} against {:.4} Pa)",
            shear_pair.restitution,
            shear_pair.phi,
            shear_pair.rate,
            shear_pair.count,
            shear_star.temperature,
            shear_md.temperature,
            shear_star.tensor[3],
            shear_md.tensor[3]
        ),
        worst_z,
        3.0,
    ));
    let mut markdown = vec![
        "## 8. Gases against kinetic theory".to_string(),
        String::new(),
        format!(
            "Elastic hard spheres (eMD, Hertz without dissipation: ε = 1), N = {} from an fcc \
             lattice, melted over {} collisions per particle, then Z = pV/(NkT) over {} in 10 \
             blocks (errors: standard errors of the blocks). The cooling state: eMD with a \
             stiff linear dashpot of restitution ε = {} (the same at every speed), N = {}, η = \
             {}, random start; a₂ sampled every half collision per particle after {}, over {} \
             (errors from 8 blocks).",
            eos.count,
            eos.equilibrate,
            eos.measure,
            cooling.restitution,
            cooling.count,
            cooling.eta,
            cooling.transient,
            cooling.measure
        ),
        String::new(),
        "| η | Z | ± | Carnahan–Starling | deviation | collisions per particle |".to_string(),
        "|---|---|---|---|---|---|".to_string(),
    ];
    for p in &points {
        markdown.push(format!(
            "| {} | {:.4} | {:.4} | {:.4} | {:+.2} % | {:.0} |",
            p.eta,
            p.z,
            p.z_error,
            p.carnahan_starling,
            100.0 * (p.z / p.carnahan_starling - 1.0),
            p.collisions_per_particle
        ));
    }
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({
            "eos": points, "eos_settings": eos, "cooling": hcs, "cooling_settings": cooling,
            "driven": hard, "driven_settings": driven, "driven_theory_temperature": driven.theory_temperature(),
            "driven_md": md, "driven_emdstar": star, "driven_pair_settings": pair,
            "driven_mixed_md": mixed_md, "driven_mixed_hybrid": mixed_hybrid, "driven_mixed_settings": mixed,
            "emdstar_speed_over_md": speed,
            "vibrated_plate": [plate_emd, plate_star, plate_md], "vibrated_plate_settings": plate,
            "shear": sheared, "shear_settings": shear,
            "shear_md": shear_md, "shear_emdstar": shear_star, "shear_pair_settings": shear_pair,
        }),
        figures: vec![
            eos_png,
            a2_png,
            driven_png,
            pair_png,
            mixed_png,
            plate_png,
            shear_png,
            shear_pair_png,
        ],
        info: vec![
            format!(
                "driven dilute steady state (η = {}, N = {}): eMD* {speed:.2}× as fast as MD ({:.2} s against {:.2} s of wall time per simulated second)",
                pair.eta,
                pair.count,
                star.wall_seconds / star.time,
                md.wall_seconds / md.time
            ),
            format!(
                "driven steady state at η = {} (N = {}): the hybrid {:.2} s, MD {:.2} s of wall time per simulated second",
                mixed.eta,
                mixed.count,
                mixed_hybrid.wall_seconds / mixed_hybrid.time,
                mixed_md.wall_seconds / mixed_md.time
            ),
            format!(
                "sheared steady state (φ = {}, N = {}): eMD* {:.1}× as fast as MD ({:.2} s against {:.2} s of wall time per seed, run side by side)",
                shear_pair.phi,
                shear_pair.count,
                shear_md.wall_seconds / shear_star.wall_seconds,
                shear_star.wall_seconds,
                shear_md.wall_seconds
            ),
        ],
    })
}
