//! Fig. 6 of Müller & Pöschel 2013 (Sec. VI A and VI B 4): the traces of two colliding
//! spheres by MD (Newton's equations), by eMD (instantaneous collision with the
//! coefficient of restitution) and by eMD* (matrix of restitution), with positions marked
//! at equal time steps τ/7 (0 = first touch, 7 = end of the collision).
//!
//! Parameters from the paper's text: linear dashpot k = 2 kN/m, γ = 0, R = 0.1 m,
//! ρ = 1140 kg/m³, relative speed v = 5 m/s, eccentricity e = 0.3, v₁ = (v/4, v/2, 0),
//! v₂ = (v/4, −v/2, 0).

use crate::engines::{EventKind, event_engine, free_spheres, md_engine, md_state};
use crate::plot::{Annotation, Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::{HarnessError, Result};
use emdstar_contact::{ForceLaw, LinearDashpot, PairLaw, PairProperties, Sphere, Vec3};
use emdstar_mor::rule::{Body, exact_collision};
use serde::Serialize;
use std::path::Path;

/// The paper's values.
pub const STIFFNESS: f64 = 2000.0;
pub const RADIUS: f64 = 0.1;
pub const DENSITY: f64 = 1140.0;
pub const SPEED: f64 = 5.0;
pub const ECCENTRICITY: f64 = 0.3;

/// Marker steps before the touch and after it (the paper marks 0…7).
const BEFORE: i32 = 3;
const AFTER: i32 = 11;

/// Positions of both spheres at a list of times (s, 0 = first touch).
#[derive(Debug, Clone, Default, Serialize)]
pub struct Trace {
    pub times: Vec<f64>,
    pub positions: Vec<[[f64; 3]; 2]>,
}

/// The figure's data and its two numbers.
#[derive(Debug, Clone, Serialize)]
pub struct Fig6 {
    /// Collision duration τ (s), from the exact MoR.
    pub duration: f64,
    /// MD time step (s).
    pub md_dt: f64,
    pub md: Trace,
    pub emd: Trace,
    pub emdstar: Trace,
    /// Marker times k·τ/7, k = −3…11, and the positions there; eMD* has k = 0 twice
    /// (before and after its E^φ event), stored as an extra last entry.
    pub markers: Vec<i32>,
    pub md_markers: Trace,
    pub emd_markers: Trace,
    pub emdstar_markers: Trace,
    /// Largest distance from MD over the markers k ≥ 7 (collision over), units of 2R.
    pub emd_deviation_after: f64,
    pub emdstar_deviation_after: f64,
    /// The same for eMD* with the exact MoR instead of the table (not drawn).
    pub emdstar_exact_deviation_after: f64,
}

fn start_state(duration: f64) -> Vec<(f64, [f64; 3], [f64; 3])> {
    let l = 2.0 * RADIUS;
    let e = ECCENTRICITY;
    // r = r1 − r2 at touch: approaching along y with impact parameter e·l along x.
    let r = [l * e, -l * (1.0 - e * e).sqrt(), 0.0];
    let v1 = [SPEED / 4.0, SPEED / 2.0, 0.0];
    let v2 = [SPEED / 4.0, -SPEED / 2.0, 0.0];
    let t0 = BEFORE as f64 * duration / 7.0;
    let at = |sign: f64, v: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|k| sign * r[k] / 2.0 - v[k] * t0)
    };
    vec![(RADIUS, at(1.0, v1), v1), (RADIUS, at(-1.0, v2), v2)]
}

/// τ = ε_t·T of this impact from the exact MoR (Müller & Pöschel 2013, Eq. 20): soft
/// oblique contacts last much shorter than the central π/ω.
fn exact_duration(law: &ForceLaw) -> Result<f64> {
    let touch = start_state(0.0);
    let sphere = Sphere::from_density(RADIUS, DENSITY)?;
    let pair = PairProperties::spheres(&sphere, &sphere);
    let pair_law = PairLaw::same_material(law, pair.r_eff)?;
    let bodies = [0, 1].map(|i| Body {
        position: Vec3::from(touch[i].1),
        velocity: Vec3::from(touch[i].2),
        mass: sphere.mass,
    });
    Ok(exact_collision(&pair_law, &pair, &bodies)?.0.duration)
}

/// Runs the three engines. `md_steps` per τ/7 marker interval (the paper's figure needs
/// little; 100 gives MD errors far below the line width).
pub fn run(md_steps: u32) -> Result<Fig6> {
    let law = ForceLaw::Linear(LinearDashpot::new(STIFFNESS, 0.0)?);
    let duration = exact_duration(&law)?;
    let system = free_spheres(&law, DENSITY, &start_state(duration))?;
    let step = duration / 7.0;
    let t0 = BEFORE as f64 * step;
    let markers: Vec<i32> = (-BEFORE..=AFTER).collect();
    let t_end = (BEFORE + AFTER) as f64 * step;

    // MD, recorded every tenth of a marker step.
    let dt = step / md_steps as f64;
    let mut md = md_engine(system.clone(), dt, t_end)?;
    let mut md_trace = Trace::default();
    let mut md_markers = Trace::default();
    let per_sample = (md_steps / 10).max(1);
    for k in 0..=(md_steps * (BEFORE + AFTER) as u32) {
        if k > 0 {
            md.advance(1)?;
        }
        let (x, _) = md_state(&md);
        if k % per_sample == 0 {
            md_trace.times.push(md.time() - t0);
            md_trace.positions.push([x[0], x[1]]);
        }
        if k % md_steps == 0 {
            md_markers.times.push(md.time() - t0);
            md_markers.positions.push([x[0], x[1]]);
        }
    }

    let event = |kind: EventKind| -> Result<(Trace, Trace)> {
        let mut e = event_engine(&system, kind)?;
        let mut trace = Trace::default();
        let mut marks = Trace::default();
        let samples = 10 * (BEFORE + AFTER);
        let touch = t0 * (1.0 - 1e-12);
        // (time, is a marker), in time order, the touch just before marker 0.
        let mut times: Vec<(f64, bool)> = (0..=samples)
            .map(|k| (k as f64 * step / 10.0, k % 10 == 0))
            .collect();
        times.insert(10 * BEFORE as usize, (touch, false));
        for &(t, marker) in &times {
            e.run_until(t)?;
            e.sync();
            let x = e.positions();
            trace.times.push(t - t0);
            trace.positions.push([x[0], x[1]]);
            if marker {
                marks.times.push(t - t0);
                marks.positions.push([x[0], x[1]]);
            }
        }
        // Just before the touch: the position eMD* shows at "0" before its E^φ event.
        let i = trace
            .times
            .iter()
            .position(|&t| t == touch - t0)
            .unwrap_or(0);
        marks.times.push(trace.times[i]);
        marks.positions.push(trace.positions[i]);
        Ok((trace, marks))
    };
    let (emd, emd_markers) = event(EventKind::Emd)?;
    let (emdstar, emdstar_markers) = event(EventKind::EmdStarTable)?;
    let (_, exact_markers) = event(EventKind::EmdStarExact)?;
    if md_markers.positions.len() != markers.len()
        || emd_markers.positions.len() != markers.len() + 1
    {
        return Err(HarnessError::Invalid(
            "Fig. 6: marker times were missed".into(),
        ));
    }
    let deviation = |m: &Trace| -> f64 {
        let mut worst: f64 = 0.0;
        for (j, &k) in markers.iter().enumerate() {
            if k >= 7 {
                for i in 0..2 {
                    let d: f64 = (0..3)
                        .map(|c| (m.positions[j][i][c] - md_markers.positions[j][i][c]).powi(2))
                        .sum();
                    worst = worst.max(d.sqrt() / (2.0 * RADIUS));
                }
            }
        }
        worst
    };
    Ok(Fig6 {
        duration,
        md_dt: dt,
        emd_deviation_after: deviation(&emd_markers),
        emdstar_deviation_after: deviation(&emdstar_markers),
        emdstar_exact_deviation_after: deviation(&exact_markers),
        md: md_trace,
        emd,
        emdstar,
        markers,
        md_markers,
        emd_markers,
        emdstar_markers,
    })
}

fn lines(
    t: &Trace,
    particle: usize,
    label: &str,
    color: crate::plot::RGBColor,
    style: Style,
) -> Vec<Series> {
    // Split at the touch so that eMD*'s jump is not drawn as a line.
    let before: Vec<(f64, f64)> = t
        .times
        .iter()
        .zip(&t.positions)
        .filter(|(s, _)| **s < 0.0)
        .map(|(_, p)| (p[particle][0], p[particle][1]))
        .collect();
    let after: Vec<(f64, f64)> = t
        .times
        .iter()
        .zip(&t.positions)
        .filter(|(s, _)| **s >= 0.0)
        .map(|(_, p)| (p[particle][0], p[particle][1]))
        .collect();
    let name = if particle == 0 {
        label.to_string()
    } else {
        String::new()
    };
    vec![
        Series::new(name, before, color, style),
        Series::new("", after, color, style),
    ]
}

fn marks(panel: &mut Panel, t: &Trace, markers: &[i32], color: crate::plot::RGBColor, dy: f64) {
    for (j, p) in t.positions.iter().enumerate() {
        let k = markers.get(j).copied().unwrap_or(0);
        for q in p {
            panel
                .series
                .push(Series::new("", vec![(q[0], q[1])], color, Style::Points(4)));
            panel.annotations.push(Annotation::Text {
                at: (q[0] + 0.012, q[1] + dy),
                text: k.to_string(),
                color,
            });
        }
    }
}

/// Writes the figure: MD against eMD on top, MD against eMD* below.
pub fn plot(f: &Fig6, path: &Path) -> std::result::Result<(), String> {
    // One range for both panels, 1 m the same length along x and y.
    let all = [&f.md, &f.emd, &f.emdstar];
    let pts = all
        .iter()
        .flat_map(|t| t.positions.iter().flat_map(|p| p.iter()));
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for q in pts {
        (x0, x1, y0, y1) = (x0.min(q[0]), x1.max(q[0]), y0.min(q[1]), y1.max(q[1]));
    }
    let pad = 0.05;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (mut w, mut h) = (x1 - x0 + 2.0 * pad, y1 - y0 + 2.0 * pad);
    const ASPECT: f64 = 798.0 / 748.0; // plot area of one panel, pixels
    if w / h > ASPECT {
        h = w / ASPECT
    } else {
        w = h * ASPECT
    }
    let mut panels = Vec::new();
    for (title, trace, m, color) in [
        (
            "MD (black) against eMD (red): instantaneous collision",
            &f.emd,
            &f.emd_markers,
            PALETTE[1],
        ),
        (
            "MD (black) against eMD* (green): matrix of restitution",
            &f.emdstar,
            &f.emdstar_markers,
            PALETTE[2],
        ),
    ] {
        let mut p = Panel::new(
            title,
            Axis::linear("x (m)").with_range(cx - w / 2.0, cx + w / 2.0),
            Axis::linear("y (m)").with_range(cy - h / 2.0, cy + h / 2.0),
        );
        p.legend = LegendAt::UpperLeft;
        let name = if color == PALETTE[1] { "eMD" } else { "eMD*" };
        p.series.extend(lines(
            &f.md,
            0,
            "MD (Newton's equations)",
            PALETTE[0],
            Style::Line,
        ));
        p.series
            .extend(lines(&f.md, 1, "", PALETTE[0], Style::Line));
        p.series.extend(lines(trace, 0, name, color, Style::Dashed));
        p.series.extend(lines(trace, 1, "", color, Style::Dashed));
        marks(&mut p, &f.md_markers, &f.markers, PALETTE[0], 0.03);
        marks(&mut p, m, &f.markers, color, -0.0);
        // The spheres at the moment of impact.
        let j = f.markers.iter().position(|&k| k == 0).unwrap_or(0);
        for q in &f.md_markers.positions[j] {
            p.annotations.push(Annotation::Circle {
                centre: (q[0], q[1]),
                radius: RADIUS,
                color: PALETTE[7],
            });
        }
        panels.push(p);
    }
    write_png(path, (900, 1700), 2, 1, &panels)
}
