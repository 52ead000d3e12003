//! `emdstar mor --restitution-curve`: the normal restitution of central impacts against
//! the impact speed, for one material and pair of spheres.

use super::{MorArgs, material};
use anyhow::{Context, Result, anyhow, bail};
use emdstar_contact::{ForceLaw, Impact, Model, PairLaw, scale};
use emdstar_mor::solve;
use emdstar_plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use serde_json::json;

/// One speed of the curve.
struct Point {
    speed: f64,
    restitution: f64,
    duration: f64,
}

pub fn run(args: &MorArgs, model: Model) -> Result<()> {
    if args.scaled.is_some() {
        bail!(
            "--restitution-curve needs physical parameters (a material and two spheres), not --scaled"
        );
    }
    for (flag, given) in [
        ("--eccentricity", args.eccentricity.is_some()),
        ("--table", args.table.is_some()),
    ] {
        if given {
            bail!("--restitution-curve solves central impacts exactly; remove {flag}");
        }
    }
    let (lo, hi) = match (&args.curve_speeds, args.speed) {
        (Some(v), _) => (v[0], v[1]),
        (None, Some(v)) => (v / 100.0, v * 100.0),
        (None, None) => (0.01, 100.0),
    };
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        bail!("--curve-speeds LO HI needs 0 < LO < HI (m/s), got {lo} and {hi}");
    }
    let n = args.curve_points.unwrap_or(21);
    if n < 2 {
        bail!("--curve-points must be at least 2");
    }
    let (law, pair, fitted) = material(args, model)?;
    let pair_law = PairLaw::same_material(&law, pair.r_eff)?;
    let mut points = Vec::with_capacity(n);
    for k in 0..n {
        let speed = lo * (hi / lo).powf(k as f64 / (n - 1) as f64);
        let impact = Impact::from_speed_eccentricity(speed, 0.0)?;
        let s = scale(&pair_law, &pair, &impact)?;
        let mor = solve(model, &s.params).with_context(|| {
            format!("at {speed:.4e} m/s (lower the upper speed with --curve-speeds)")
        })?;
        points.push(Point {
            speed,
            restitution: -mor.eps_rdot,
            duration: mor.eps_t * s.time,
        });
    }
    let (dissipation_name, dissipation) = match law {
        ForceLaw::Linear(l) => ("damping", l.damping),
        ForceLaw::Hertz(h) => ("dissipation", h.dissipation),
    };
    let unit = if model == Model::Linear { "kg/s" } else { "s" };
    // The point asked for with --restitution, marked on the plot.
    let target = fitted
        .and(args.restitution)
        .map(|e| (args.speed.unwrap_or(lo), e));
    if let Some(path) = &args.plot {
        let title =
            format!("central impacts, {model}, {dissipation_name} = {dissipation:.4e} {unit}");
        plot(&points, target, title, path)?;
    }
    if args.json {
        let curve: Vec<_> = points
            .iter()
            .map(|p| json!({"speed": p.speed, "eps_n": p.restitution, "duration": p.duration}))
            .collect();
        let mut v = json!({"model": model.name(), "curve": curve});
        v[dissipation_name] = json!(dissipation);
        if fitted.is_some() {
            v["restitution"] = json!(args.restitution);
            v["restitution_speed"] = json!(args.speed);
        }
        println!("{}", serde_json::to_string_pretty(&v)?);
        return Ok(());
    }
    println!(
        "central impacts, {model}, {dissipation_name} = {dissipation:.6e} {unit}{}",
        match fitted {
            Some(_) => format!(
                " (from --restitution {}{})",
                args.restitution.unwrap_or(f64::NAN),
                args.speed.map_or(String::new(), |v| format!(" at {v} m/s"))
            ),
            None => String::new(),
        }
    );
    println!(
        "{:>14}  {:>14}  {:>14}",
        "speed (m/s)", "ε_n", "duration (s)"
    );
    for p in &points {
        println!(
            "{:>14.6e}  {:>14.10}  {:>14.6e}",
            p.speed, p.restitution, p.duration
        );
    }
    Ok(())
}

fn plot(
    points: &[Point],
    target: Option<(f64, f64)>,
    title: String,
    path: &std::path::Path,
) -> Result<()> {
    let mut panel = Panel::new(
        title,
        Axis::log("impact speed (m/s)"),
        Axis::linear("normal restitution ε_n").with_range(0.0, 1.0),
    );
    panel.legend = LegendAt::LowerLeft;
    panel.series.push(Series::new(
        "exact solve",
        points.iter().map(|p| (p.speed, p.restitution)).collect(),
        PALETTE[3],
        Style::LinePoints(3),
    ));
    if let Some((v, e)) = target {
        panel.series.push(Series::new(
            format!("--restitution {e} at {v} m/s"),
            vec![(v, e)],
            PALETTE[1],
            Style::Points(7),
        ));
    }
    write_png(path, (900, 600), 1, 1, &[panel]).map_err(|e| anyhow!(e))
}
