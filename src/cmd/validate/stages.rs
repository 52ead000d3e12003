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
        other => Err(anyhow!("scenario {other} is not built yet")),
    }
}

fn pairs(args: &ValidateArgs) -> Result<StageOutput> {
    let settings = PairSettings {
        impacts_per_model: if args.full { 3000 } else { 300 },
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
             (no exact reference). Position errors in units of l = R1 + R2 after the collision.",
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
            "2c",
            "Fig. 6: eMD* (exact MoR) distance from MD at markers 7-11, units of 2R",
            f.emdstar_exact_deviation_after,
            1e-5,
        ),
        Check::at_least(
            "2b",
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
    })
}
