//! Error distributions of the pair sweep per force law and engine, the checks drawn from
//! them, and their figures.

use crate::check::Check;
use crate::pairs::{Errors, ImpactResult, PairSweep};
use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::stats::{linear_fit, quantile};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Quantiles of one error sample.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Spread {
    pub count: usize,
    pub median: f64,
    pub p90: f64,
    pub p99: f64,
    pub max: f64,
}

impl Spread {
    pub fn of(v: &[f64]) -> Self {
        Self {
            count: v.iter().filter(|x| x.is_finite()).count(),
            median: quantile(v, 0.5),
            p90: quantile(v, 0.9),
            p99: quantile(v, 0.99),
            max: v
                .iter()
                .copied()
                .filter(|x| !x.is_nan())
                .fold(f64::NAN, f64::max),
        }
    }
}

/// The sweep of one force law, summarised.
#[derive(Debug, Clone, Serialize)]
pub struct ModelSummary {
    pub model: String,
    pub impacts: usize,
    pub unequal_radii: usize,
    pub in_table_box: usize,
    pub table_fallbacks: u64,
    /// Relative error of the table's MoR components against the exact solve.
    pub table_mor_error: Spread,
    /// Position errors (units of l).
    pub emdstar_exact: Spread,
    pub emdstar_table: Spread,
    pub table_implied: Spread,
    /// Worst ratio of eMD* (table) error to the error its table MoR implies
    /// (in-box impacts; the 1e-12 floor is round-off).
    pub table_ratio_max: f64,
    pub emd: Spread,
    /// Velocity errors (units of the impact speed |v₁ − v₂|).
    pub emd_velocity: Spread,
    pub emdstar_exact_velocity: Spread,
    pub emdstar_table_velocity: Spread,
    /// MD's velocity error at each time step.
    pub md_velocity: Vec<Spread>,
    /// MD: steps per contact, and the position-error spread at each.
    pub md_steps_per_contact: Vec<u32>,
    pub md: Vec<Spread>,
    /// Impacts where MD failed or was not run at some level.
    pub md_failures: usize,
    /// Observed order of MD: the median over impacts of the least-squares slope of
    /// log(position error) against log(dt) over the three finest levels.
    pub md_order: f64,
    /// The same slope for the medians of the levels.
    pub md_order_of_medians: f64,
}

fn positions(rs: &[&ImpactResult], f: impl Fn(&ImpactResult) -> Errors) -> Vec<f64> {
    rs.iter().map(|r| f(r).position).collect()
}

/// Slope of log(error) against log(dt) over one impact's three finest MD levels (the
/// coarse ones are not yet asymptotic for strongly damped Hertz contacts), ignoring
/// errors at the round-off floor (1e-13 l); NaN with fewer than three usable levels.
fn impact_order(r: &ImpactResult, steps: &[u32]) -> f64 {
    let skip = steps.len().saturating_sub(3);
    let pts: Vec<(f64, f64)> = steps
        .iter()
        .zip(&r.md)
        .skip(skip)
        .filter_map(|(&n, e)| {
            let e = (*e)?.position;
            (e > 1e-13).then(|| ((1.0 / n as f64).ln(), e.ln()))
        })
        .collect();
    if pts.len() < 3 {
        f64::NAN
    } else {
        linear_fit(&pts).1
    }
}

/// Summarises the impacts of `model` ("linear" or "hertz").
pub fn summarise(sweep: &PairSweep, model: &str) -> ModelSummary {
    let rs: Vec<&ImpactResult> = sweep.impacts.iter().filter(|r| r.model == model).collect();
    let boxed: Vec<&ImpactResult> = rs.iter().copied().filter(|r| r.in_table_box).collect();
    let steps = sweep.settings.md_steps_per_contact.clone();
    let full_md: Vec<&ImpactResult> = rs
        .iter()
        .copied()
        .filter(|r| r.md.iter().all(|m| m.is_some()))
        .collect();
    let md: Vec<Spread> = (0..steps.len())
        .map(|k| {
            Spread::of(
                &full_md
                    .iter()
                    .map(|r| r.md[k].unwrap().position)
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let points: Vec<(f64, f64)> = steps
        .iter()
        .zip(&md)
        .map(|(&n, s)| ((1.0 / n as f64).ln(), s.median.ln()))
        .collect();
    let ratio = boxed
        .iter()
        .map(|r| r.emdstar_table.position / (r.table_implied.position + 1e-12))
        .fold(0.0, f64::max);
    let orders: Vec<f64> = full_md.iter().map(|r| impact_order(r, &steps)).collect();
    ModelSummary {
        model: model.to_string(),
        impacts: rs.len(),
        unequal_radii: rs.iter().filter(|r| r.radii[0] != r.radii[1]).count(),
        in_table_box: boxed.len(),
        table_fallbacks: rs.iter().map(|r| r.table_fallbacks).sum(),
        table_mor_error: Spread::of(&boxed.iter().map(|r| r.table_mor_error).collect::<Vec<_>>()),
        emdstar_exact: Spread::of(&positions(&rs, |r| r.emdstar_exact)),
        emdstar_table: Spread::of(&positions(&boxed, |r| r.emdstar_table)),
        table_implied: Spread::of(&positions(&boxed, |r| r.table_implied)),
        table_ratio_max: ratio,
        emd: Spread::of(&positions(&rs, |r| r.emd)),
        emd_velocity: Spread::of(&rs.iter().map(|r| r.emd.velocity).collect::<Vec<_>>()),
        emdstar_exact_velocity: Spread::of(
            &rs.iter()
                .map(|r| r.emdstar_exact.velocity)
                .collect::<Vec<_>>(),
        ),
        emdstar_table_velocity: Spread::of(
            &boxed
                .iter()
                .map(|r| r.emdstar_table.velocity)
                .collect::<Vec<_>>(),
        ),
        md_velocity: (0..steps.len())
            .map(|k| {
                Spread::of(
                    &full_md
                        .iter()
                        .map(|r| r.md[k].map_or(f64::NAN, |e| e.velocity))
                        .collect::<Vec<_>>(),
                )
            })
            .collect(),
        md_steps_per_contact: steps.clone(),
        md,
        md_failures: rs.len() - full_md.len(),
        md_order: quantile(&orders, 0.5),
        md_order_of_medians: linear_fit(&points).1,
    }
}

/// Checks 1.x of one model (`n` is 1 for linear, 2 for Hertz, used in the numbering).
pub fn checks(s: &ModelSummary, n: usize) -> Vec<Check> {
    let m = &s.model;
    let finest = s.md.last().map_or(f64::NAN, |x| x.median);
    vec![
        Check::at_most(
            &format!("1.{n}a"),
            format!("{m}: eMD* (exact MoR) worst position error vs exact solution (units of l)"),
            s.emdstar_exact.max,
            1e-8,
        ),
        Check::at_most(
            &format!("1.{n}b"),
            format!(
                "{m}: eMD* (table) worst error / error implied by the table's own MoR accuracy"
            ),
            s.table_ratio_max,
            2.0,
        ),
        Check::at_most(
            &format!("1.{n}c"),
            format!(
                "{m}: eMD* (table) 99th-percentile position error, in-box impacts (units of l)"
            ),
            s.emdstar_table.p99,
            1e-4,
        ),
        Check::at_least(
            &format!("1.{n}d"),
            format!(
                "{m}: observed order of MD (median over impacts, slope of log error vs log dt, 3 finest dt)"
            ),
            s.md_order,
            1.4,
        ),
        Check::at_most(
            &format!("1.{n}e"),
            format!(
                "{m}: MD median position error at dt = τ/{} (units of l)",
                s.md_steps_per_contact.last().copied().unwrap_or(0)
            ),
            finest,
            1e-4,
        ),
        Check::at_least(
            &format!("1.{n}f"),
            format!(
                "{m}: eMD median position error / eMD* (table) median (eMD is wrong, Sec. VI A)"
            ),
            s.emd.median / s.emdstar_table.median,
            100.0,
        ),
    ]
}

/// Medians of y in ten bins of x (equal width, or equal in log x), bins with at least
/// five points.
fn binned_medians(pts: &[(f64, f64)], log_x: bool) -> Vec<(f64, f64)> {
    let f = |x: f64| if log_x { x.ln() } else { x };
    let xs: Vec<f64> = pts
        .iter()
        .map(|p| f(p.0))
        .filter(|x| x.is_finite())
        .collect();
    let (lo, hi) = (
        xs.iter().copied().fold(f64::INFINITY, f64::min),
        xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let width = (hi - lo) / 10.0;
    (0..10)
        .filter_map(|b| {
            let (a, z) = (lo + b as f64 * width, lo + (b + 1) as f64 * width);
            let ys: Vec<f64> = pts
                .iter()
                .filter(|p| {
                    let x = f(p.0);
                    x >= a && (x < z || (b == 9 && x <= z))
                })
                .map(|p| p.1)
                .collect();
            let mid = (a + z) / 2.0;
            (ys.len() >= 5).then(|| (if log_x { mid.exp() } else { mid }, quantile(&ys, 0.5)))
        })
        .collect()
}

/// A panel, its points, and whether its x axis is logarithmic.
type PanelPoints<'a> = (&'a mut Panel, Vec<(f64, f64)>, bool);

/// Picks one error of an impact (None: not part of the sample).
type Pick = Box<dyn Fn(&ImpactResult) -> Option<f64>>;

fn cdf(v: &[f64]) -> Vec<(f64, f64)> {
    let mut v: Vec<f64> = v
        .iter()
        .copied()
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    v.sort_by(f64::total_cmp);
    let n = v.len() as f64;
    v.iter()
        .enumerate()
        .map(|(i, &x)| (x, (i + 1) as f64 / n))
        .collect()
}

/// Writes the figures of the sweep into `dir`; returns their paths.
pub fn plots(sweep: &PairSweep, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let steps = &sweep.settings.md_steps_per_contact;
    // 1. Error distributions per engine and model.
    let mut panels = Vec::new();
    for model in ["linear", "hertz"] {
        let rs: Vec<&ImpactResult> = sweep.impacts.iter().filter(|r| r.model == model).collect();
        let mut p = Panel::new(
            format!(
                "{model}: position error after the collision, {} impacts",
                rs.len()
            ),
            Axis::log("position error |Δx|/l against the exact solution"),
            Axis::linear("fraction of impacts with smaller error").with_range(0.0, 1.0),
        );
        p.legend = LegendAt::LowerRight;
        let eng: [(&str, Pick, usize); 3] = [
            (
                "eMD* (exact MoR)",
                Box::new(|r| Some(r.emdstar_exact.position)),
                3,
            ),
            (
                "eMD* (table, in box)",
                Box::new(|r| r.in_table_box.then_some(r.emdstar_table.position)),
                2,
            ),
            (
                "eMD (restitution coefficient)",
                Box::new(|r| Some(r.emd.position)),
                1,
            ),
        ];
        for (name, f, c) in eng {
            let v: Vec<f64> = rs.iter().filter_map(|r| f(r)).collect();
            p.series
                .push(Series::new(name, cdf(&v), PALETTE[c], Style::Line));
        }
        for (k, &n) in steps.iter().enumerate() {
            let v: Vec<f64> = rs
                .iter()
                .filter_map(|r| r.md[k].map(|e| e.position))
                .collect();
            let grey = (200.0 * (1.0 - k as f64 / steps.len().max(1) as f64)) as u8;
            p.series.push(Series::new(
                format!("MD, dt = τ/{n}"),
                cdf(&v),
                crate::plot::RGBColor(grey, grey, grey),
                Style::Dashed,
            ));
        }
        panels.push(p);
    }
    let path = dir.join("pairs_error_distribution.png");
    write_png(&path, (1500, 650), 1, 2, &panels)?;
    written.push(path);

    // 2. eMD error against eccentricity and softness (the paper's central point):
    // each impact as a light dot, the median of each bin as a dark line.
    let mut vel = Panel::new(
        "eMD velocity error against eccentricity",
        Axis::linear("eccentricity e = v_t/|v| at contact"),
        Axis::log("eMD velocity error |Δv|/|v|"),
    );
    let mut by_e = Panel::new(
        "eMD position error per unit softness",
        Axis::linear("eccentricity e = v_t/|v| at contact"),
        Axis::log("eMD position error |Δx|/X (X: deformation scale)"),
    );
    let mut by_soft = Panel::new(
        "eMD position error against softness",
        Axis::log("softness X/l (deformation scale over contact distance)"),
        Axis::log("eMD position error |Δx|/l"),
    );
    for p in [&mut vel, &mut by_e, &mut by_soft] {
        p.legend = LegendAt::LowerRight;
    }
    let light = [
        crate::plot::RGBColor(160, 195, 225),
        crate::plot::RGBColor(240, 170, 170),
    ];
    for (k, (model, c)) in [("linear", 3), ("hertz", 1)].into_iter().enumerate() {
        let rs: Vec<&ImpactResult> = sweep.impacts.iter().filter(|r| r.model == model).collect();
        let sets: [PanelPoints; 3] = [
            (
                &mut vel,
                rs.iter()
                    .map(|r| (r.eccentricity, r.emd.velocity))
                    .collect(),
                false,
            ),
            (
                &mut by_e,
                rs.iter()
                    .map(|r| (r.eccentricity, r.emd.position * r.l_tilde))
                    .collect(),
                false,
            ),
            (
                &mut by_soft,
                rs.iter()
                    .map(|r| (1.0 / r.l_tilde, r.emd.position))
                    .collect(),
                true,
            ),
        ];
        for (panel, pts, log_x) in sets {
            let medians = binned_medians(&pts, log_x);
            panel
                .series
                .push(Series::new("", pts, light[k], Style::Points(2)));
            panel.series.push(Series::new(
                format!("{model}, median"),
                medians,
                PALETTE[c],
                Style::LinePoints(4),
            ));
        }
    }
    let path = dir.join("pairs_emd_error.png");
    write_png(&path, (1950, 650), 1, 3, &[vel, by_e, by_soft])?;
    written.push(path);

    // 3. MD convergence.
    let mut conv = Panel::new(
        "MD converges to the exact solution",
        Axis::log("time step dt/τ (τ: contact duration)"),
        Axis::log("median position error |Δx|/l"),
    );
    conv.legend = LegendAt::LowerRight;
    for (model, c) in [("linear", 3), ("hertz", 1)] {
        let s = summarise(sweep, model);
        let pts: Vec<(f64, f64)> = steps
            .iter()
            .zip(&s.md)
            .map(|(&n, q)| (1.0 / n as f64, q.median))
            .collect();
        conv.series.push(Series::new(
            format!("{model}: observed order {:.2}", s.md_order),
            pts,
            PALETTE[c],
            Style::LinePoints(5),
        ));
    }
    // Reference slopes through the finest linear-law point.
    if let (Some(&n), Some(first)) = (steps.last(), conv.series.first()) {
        let (x0, y0) = first
            .points
            .last()
            .copied()
            .unwrap_or((1.0 / n as f64, 1.0));
        for (order, c) in [(1.0, 4), (2.0, 7)] {
            let x1 = 1.0 / steps[0] as f64;
            conv.series.push(Series::new(
                format!("slope {order}"),
                vec![(x0, y0), (x1, y0 * (x1 / x0).powf(order))],
                PALETTE[c],
                Style::Dashed,
            ));
        }
    }
    let path = dir.join("pairs_md_convergence.png");
    write_png(&path, (900, 650), 1, 1, &[conv])?;
    written.push(path);
    Ok(written)
}
