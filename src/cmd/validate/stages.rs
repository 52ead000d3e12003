//! The scenarios of `emdstar validate`, quick and full settings, and their report parts.

use super::{StageOutput, ValidateArgs, bar};
use anyhow::{Result, anyhow};
use emdstar_harness::Check;
use emdstar_harness::pair_summary::{checks, plots, summarise};
use emdstar_harness::pairs::{PairSettings, sweep};
use serde_json::json;

pub fn run(name: &str, args: &ValidateArgs) -> Result<StageOutput> {
    match name {
        "pairs" => pairs(args),
        "fig6" => fig6(args),
        "fig7" => fig7(args),
        "cooling" => cooling(args),
        "diffusion" => super::diffusion::run(args),
        "speed" => super::speed::run(args),
        "friction-pairs" => super::friction::pairs(args),
        "friction-cooling" => super::friction::cooling(args),
        "theory" => super::theory::run(args),
        other => Err(anyhow!("scenario {other} is not built yet")),
    }
}

fn pairs(args: &ValidateArgs) -> Result<StageOutput> {
    let settings = PairSettings {
        impacts_per_model: if args.full { 5000 } else { 1000 },
        md_steps_per_contact: vec![25, 50, 100, 200, 400],
        unequal_fraction: 0.3,
        seed: args.seed,
    };
    let b = bar("pairs", 2 * settings.impacts_per_model as u64);
    b.set_message("impacts through MD (5 dt), eMD, eMD* (table, exact)");
    let result = sweep(&settings, &|| b.inc(1))?;
    b.finish();
    let mut out_checks = Vec::new();
    let mut markdown = vec![
        "## 1. Pair sweep".to_string(),
        String::new(),
        format!(
            "{} impacts per force law over Tab. I/II, {:.0}% with unequal radii; {} skipped \
             (no exact reference). Errors after the collision: positions in units of \
             l = R1 + R2, velocities in units of the impact speed.",
            settings.impacts_per_model,
            100.0 * settings.unequal_fraction,
            result.skipped.len()
        ),
        String::new(),
        "| law | engine | median | p90 | p99 | max |".to_string(),
        "|---|---|---|---|---|---|".to_string(),
    ];
    let mut summaries = Vec::new();
    for (n, model) in ["linear", "hertz"].iter().enumerate() {
        let s = summarise(&result, model);
        out_checks.extend(checks(&s, n + 1));
        let mut row = |name: String, q: &emdstar_harness::pair_summary::Spread| {
            markdown.push(format!(
                "| {model} | {name} | {:.2e} | {:.2e} | {:.2e} | {:.2e} |",
                q.median, q.p90, q.p99, q.max
            ))
        };
        row("eMD* (exact MoR)".into(), &s.emdstar_exact);
        row("eMD* (table, in box)".into(), &s.emdstar_table);
        row("table MoR rel. error".into(), &s.table_mor_error);
        row("eMD".into(), &s.emd);
        row(
            "velocity error / speed: eMD* (exact MoR)".into(),
            &s.emdstar_exact_velocity,
        );
        row(
            "velocity error / speed: eMD* (table, in box)".into(),
            &s.emdstar_table_velocity,
        );
        row("velocity error / speed: eMD".into(), &s.emd_velocity);
        if let Some(q) = s.md_velocity.last() {
            row(
                format!(
                    "velocity error / speed: MD dt = τ/{}",
                    s.md_steps_per_contact.last().unwrap_or(&0)
                ),
                q,
            );
        }
        for (k, q) in s.md.iter().enumerate() {
            row(format!("MD dt = τ/{}", s.md_steps_per_contact[k]), q);
        }
        markdown.push(format!(
            "| {model} | notes | {} in table box, {} fallbacks, {} unequal, MD failed on {}, MD order {:.2} | | | |",
            s.in_table_box, s.table_fallbacks, s.unequal_radii, s.md_failures, s.md_order
        ));
        summaries.push(s);
    }
    let figures = plots(&result, &args.out).map_err(|e| anyhow!(e))?;
    Ok(StageOutput {
        checks: out_checks,
        markdown,
        json: json!({"summaries": summaries, "skipped": result.skipped, "settings": settings}),
        figures,
        info: Vec::new(),
    })
}

fn fig6(args: &ValidateArgs) -> Result<StageOutput> {
    use emdstar_harness::fig6;
    let b = bar("fig6", 1);
    b.set_message("MD, eMD, eMD* traces of the paper's Fig. 6");
    let f = fig6::run(if args.full { 1000 } else { 100 })?;
    b.inc(1);
    b.finish();
    let path = args.out.join("fig6_trajectories.png");
    fig6::plot(&f, &path).map_err(|e| anyhow!(e))?;
    let checks = vec![
        Check::at_most(
            "2a",
            "Fig. 6: eMD* (table) distance from MD at markers 7-11 (collision over), units of 2R",
            f.emdstar_deviation_after,
            1e-3,
        ),
        Check::at_most(
            "2b",
            "Fig. 6: eMD* (exact MoR) distance from MD at markers 7-11, units of 2R",
            f.emdstar_exact_deviation_after,
            1e-5,
        ),
        Check::at_least(
            "2c",
            "Fig. 6: eMD distance from MD at markers 7-11, units of 2R (the paper: differs significantly)",
            f.emd_deviation_after,
            1e-2,
        ),
    ];
    let markdown = vec![
        "## 2. Fig. 6 (linear dashpot, k = 2 kN/m, γ = 0, R = 0.1 m, v = 5 m/s, e = 0.3)".into(),
        String::new(),
        format!(
            "Collision duration τ = {:.5} s, MD dt = {:.3e} s. After the collision, eMD* stays \
             within {:.2e}·2R of MD with the default table ({:.2e}·2R with the exact MoR, which \
             is MD's own error), eMD is off by {:.3}·2R.",
            f.duration,
            f.md_dt,
            f.emdstar_deviation_after,
            f.emdstar_exact_deviation_after,
            f.emd_deviation_after
        ),
    ];
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({
            "duration_s": f.duration,
            "md_dt_s": f.md_dt,
            "emd_deviation_after": f.emd_deviation_after,
            "emdstar_deviation_after": f.emdstar_deviation_after,
            "emdstar_exact_deviation_after": f.emdstar_exact_deviation_after,
        }),
        figures: vec![path],
        info: Vec::new(),
    })
}

fn fig7(args: &ValidateArgs) -> Result<StageOutput> {
    use emdstar_harness::exceptions::{Effort, ExceptionPoint, plot, run_point, run_replicas};
    use rayon::prelude::*;
    /// Independent gases at η = 0.001, Y = 1 GPa (check 3a).
    const TYPICAL_GASES: usize = 4;
    let etas = [0.001, 0.003, 0.01, 0.03, 0.1, 0.2];
    let youngs = [1e7, 1e8, 1e9, 1e10, 1e11];
    let (count, effort) = if args.full {
        (
            10_000,
            Effort {
                min_per_particle: 20.0,
                max_per_particle: 100.0,
                target_exceptions: 100,
            },
        )
    } else {
        (
            2_000,
            Effort {
                min_per_particle: 20.0,
                max_per_particle: 150.0,
                target_exceptions: 40,
            },
        )
    };
    // The gas at η = 0.001, Y = 1 GPa is in both panels and is the paper's "typical"
    // point: it runs on TYPICAL_GASES independent gases, pooled; the others on one.
    let typical_gas = |&(eta, y): &(f64, f64)| eta == 0.001 && y == 1e9;
    let mut jobs: Vec<(f64, f64)> = etas.iter().map(|&eta| (eta, 1e9)).collect();
    jobs.extend(youngs.iter().map(|&y| (0.001, y)));
    jobs.retain(|job| !typical_gas(job));
    let b = bar("fig7", (jobs.len() + TYPICAL_GASES) as u64);
    b.set_message(format!(
        "elastic Hertz gases, N = {count}, {}-{} collisions per particle",
        effort.min_per_particle, effort.max_per_particle
    ));
    let typical = run_replicas(0.001, 1e9, count, effort, args.seed, TYPICAL_GASES)?;
    b.inc(TYPICAL_GASES as u64);
    let others: Vec<ExceptionPoint> = jobs
        .par_iter()
        .map(|&(eta, y)| {
            let p = run_point(eta, y, count, effort, args.seed)?;
            b.inc(1);
            Ok(p)
        })
        .collect::<Result<_>>()?;
    b.finish();
    let point = |eta: f64, y: f64| -> ExceptionPoint {
        if typical_gas(&(eta, y)) {
            return typical.pooled.clone();
        }
        let k = jobs
            .iter()
            .position(|&job| job == (eta, y))
            .expect("every gas of the figure ran");
        others[k].clone()
    };
    let by_eta: Vec<ExceptionPoint> = etas.iter().map(|&eta| point(eta, 1e9)).collect();
    let by_young: Vec<ExceptionPoint> = youngs.iter().map(|&y| point(0.001, y)).collect();
    let path = args.out.join("fig7_exceptions.png");
    plot(&by_eta, &by_young, &path).map_err(|e| anyhow!(e))?;
    let total = |p: &ExceptionPoint| p.per_mille_total;
    let typical_total = total(&typical.pooled);
    let mut markdown = vec![
        format!(
            "## 3. Fig. 7: eMD* exceptions in a free elastic Hertz gas (N = {count}, from a lattice)"
        ),
        String::new(),
        format!(
            "Each gas runs {} collisions per particle, then on until {} exceptions or {} collisions per particle. The interval is the 68 % Poisson interval of f_a + f_b. The row at η = 0.001, Y = 1 GPa pools {TYPICAL_GASES} independent gases (seeds {}…{}).",
            effort.min_per_particle,
            effort.target_exceptions,
            effort.max_per_particle,
            args.seed,
            args.seed + TYPICAL_GASES as u64 - 1
        ),
        String::new(),
        "| η | Y (Pa) | collisions | a (rotation) | b (interference) | f_a (‰) | f_b (‰) | f_a + f_b (‰), 68 % | exact fallbacks |".into(),
        "|---|---|---|---|---|---|---|---|---|".into(),
    ];
    for p in by_eta
        .iter()
        .chain(by_young.iter().filter(|p| p.young != 1e9))
    {
        let (lo, hi) = p.per_mille_total_interval;
        markdown.push(format!(
            "| {} | {:.0e} | {} | {} | {} | {:.3} | {:.3} | {:.3} ({lo:.3}-{hi:.3}) | {} |",
            p.packing_fraction,
            p.young,
            p.collisions,
            p.rotation,
            p.interference,
            p.per_mille_a,
            p.per_mille_b,
            p.per_mille_total,
            p.table_fallbacks
        ));
    }
    let scatter = format!(
        "At η = 0.001, Y = 1 GPa the {TYPICAL_GASES} gases give f_a + f_b = {} ‰: mean {:.3} ± {:.3} (standard error over the gases). The pooled value, {:.3} ‰ (68 % Poisson {:.3}-{:.3}), goes into check 3a and the figure.",
        typical
            .gases
            .iter()
            .map(|p| format!("{:.3}", p.per_mille_total))
            .collect::<Vec<_>>()
            .join(", "),
        typical.mean,
        typical.standard_error,
        typical.pooled.per_mille_total,
        typical.pooled.per_mille_total_interval.0,
        typical.pooled.per_mille_total_interval.1
    );
    markdown.push(String::new());
    markdown.push(scatter.clone());
    markdown.push(String::new());
    markdown.push("The paper (Sec. VI B 6): \"exceptions of both types are rare events (about 0.1%)\" for typical parameters, vanishing for hard or dilute systems.".into());
    // A zero count is bounded by one count: f ≤ 1000/collisions.
    let at_least_one = |p: &ExceptionPoint| total(p).max(1000.0 / p.collisions.max(1) as f64);
    let first_last = |v: &[ExceptionPoint]| (at_least_one(&v[0]), at_least_one(&v[v.len() - 1]));
    let (dilute, dense) = first_last(&by_eta);
    let (soft, hard) = first_last(&by_young);
    let checks = vec![
        Check::at_most(
            "3a",
            "Fig. 7: f_a + f_b at η = 0.001, Y = 1 GPa, per 1000 collisions (paper: about 1)",
            typical_total,
            2.0,
        ),
        Check::at_least(
            "3b",
            "Fig. 7a: f_e(η = 0.2) / f_e(η = 0.001) at Y = 1 GPa (exceptions vanish when dilute)",
            dense / dilute.max(1e-9),
            10.0,
        ),
        Check::at_least(
            "3c",
            "Fig. 7b: f_e(Y = 1e7) / f_e(Y = 1e11) at η = 0.001, a zero count taken as one (exceptions vanish when hard)",
            soft / hard.max(1e-9),
            10.0,
        ),
    ];
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({"by_packing_fraction": by_eta, "by_young": by_young, "typical": typical, "particles": count, "effort": effort}),
        figures: vec![path],
        info: vec![scatter],
    })
}

/// The two cooling gases: viscoelastic Hertz (Tab. II material, ε ≈ 0.85 at 2 m/s) and a
/// linear dashpot (Tab. I, ε ≈ 0.83), both R = 1 cm, ρ = 1140 kg/m³, rms speed 2 m/s.
fn cooling_settings(args: &ValidateArgs) -> Result<Vec<emdstar_harness::cooling::CoolingSettings>> {
    use emdstar_contact::{ForceLaw, LinearDashpot, ViscoelasticHertz};
    use emdstar_harness::cooling::CoolingSettings;
    let (particles, scale) = if args.full { (8000, 3.0) } else { (1000, 1.0) };
    let gas = |name: &str, law: ForceLaw, t_end: f64| CoolingSettings {
        name: name.into(),
        law,
        particles,
        packing_fraction: 0.05,
        radius: 0.01,
        density: 1140.0,
        rms_speed: 2.0,
        t_end: t_end * scale,
        samples: 61,
        seed: args.seed,
    };
    Ok(vec![
        gas(
            "viscoelastic",
            ForceLaw::Hertz(ViscoelasticHertz::new(1e8, 0.4, 1.5e-5)?),
            4.0,
        ),
        gas(
            "linear",
            ForceLaw::Linear(LinearDashpot::new(1e4, 0.6)?),
            2.0,
        ),
    ])
}

fn cooling(args: &ValidateArgs) -> Result<StageOutput> {
    use emdstar_harness::cooling::{plot, run};
    let settings = cooling_settings(args)?;
    let total: usize = settings.iter().map(|s| 3 * s.samples).sum();
    let b = bar("cooling", total as u64);
    let mut gases = Vec::new();
    for s in &settings {
        b.set_message(format!(
            "{} gas, N = {}: MD, eMD, eMD*",
            s.name, s.particles
        ));
        gases.push(run(s, &|_| b.inc(1))?);
    }
    b.finish();
    let path = args.out.join("cooling_temperature.png");
    plot(&gases, &path).map_err(|e| anyhow!(e))?;
    let mut checks = Vec::new();
    let mut markdown = vec!["## 4. Freely cooling gases".to_string(), String::new()];
    for (n, g) in gases.iter().enumerate() {
        let id = |c: char| format!("4.{}{c}", n + 1);
        let star = g.agreement[1].iter().copied().fold(0.0, f64::max);
        let expected = if g.settings.name == "linear" {
            2.0
        } else {
            5.0 / 3.0
        };
        let bar = if args.full { 0.03 } else { 0.05 };
        checks.push(Check::at_most(
            &id('a'),
            format!(
                "{}: eMD* |T − T_MD|/T_MD, worst of t_end/4, t_end/2, t_end",
                g.settings.name
            ),
            star,
            bar,
        ));
        for (k, c) in g.curves.iter().enumerate() {
            checks.push(Check::at_most(
                &format!("4.{}{}", n + 1, ['b', 'c', 'd'][k]),
                format!(
                    "{}: {} fitted exponent p of T ∝ (1+t/t0)^-p, |p − {:.3}|",
                    g.settings.name, c.engine, expected
                ),
                (g.fits[k].exponent - expected).abs(),
                0.25,
            ));
        }
        markdown.push(format!(
            "{} gas: N = {}, η = {}, t_end = {} s, MD dt = {:.3e} s. T(t_end)/T(0) by MD = {:.4}.",
            g.settings.name,
            g.settings.particles,
            g.settings.packing_fraction,
            g.settings.t_end,
            g.md_dt,
            g.curves[0].temperature.last().unwrap() / g.curves[0].temperature[0]
        ));
        markdown.push(String::new());
        markdown.push(format!(
            "Classic eMD (not a check, for comparison): worst |T − T_MD|/T_MD = {:.3}.",
            g.agreement[0].iter().copied().fold(0.0, f64::max)
        ));
        markdown.push(String::new());
        markdown.push("| engine | fitted p | fitted t0 (s) | collisions | wall (s) | rel. T diff. at t_end/4, /2, 1 |".into());
        markdown.push("|---|---|---|---|---|---|".into());
        for (k, c) in g.curves.iter().enumerate() {
            let diff = if k == 0 {
                "reference".to_string()
            } else {
                g.agreement[k - 1]
                    .iter()
                    .map(|d| format!("{d:.2e}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            markdown.push(format!(
                "| {} | {:.3} | {:.3e} | {} | {:.1} | {diff} |",
                c.engine, g.fits[k].exponent, g.fits[k].t0, c.collisions, c.wall_seconds
            ));
        }
        markdown.push(String::new());
    }
    Ok(StageOutput {
        checks,
        markdown,
        json: json!({ "gases": gases }),
        figures: vec![path],
        info: Vec::new(),
    })
}
