//! Freely cooling granular gases: the granular temperature T(t) by MD, eMD and eMD* from
//! one initial state, and the asymptotic laws of homogeneous cooling:
//! - constant restitution (linear dashpot): Haff's law T = T₀ (1 + t/t₀)^(−2)
//!   (Haff, J. Fluid Mech. 134, 401, 1983);
//! - viscoelastic spheres, ε(v) = 1 − C₁v^(1/5) + …: T ∝ (1 + t/t₀)^(−5/3) (Schwager &
//!   Pöschel, Phys. Rev. E 57, 650, 1998; Brilliantov & Pöschel, Kinetic Theory of
//!   Granular Gases, 2004, Ch. 7).
//!
//! T = Σ m (v − v_cm)²/(3N) in J, as in `emdstar_system::Particles::granular_temperature`.

use crate::engines::{
    AnyEngine, AnyKind, ENGINE_STYLES, EventKind, default_md_dt, lattice_gas, sample_at,
};
use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::stats::{fit_rms, linear_fit};
use crate::{HarnessError, Result};
use emdstar_contact::ForceLaw;
use emdstar_system::System;
use serde::Serialize;
use std::path::Path;

/// One cooling run.
#[derive(Debug, Clone, Serialize)]
pub struct CoolingSettings {
    /// "viscoelastic" or "linear", for the report.
    pub name: String,
    #[serde(skip)]
    pub law: ForceLaw,
    pub particles: usize,
    pub packing_fraction: f64,
    pub radius: f64,
    pub density: f64,
    pub rms_speed: f64,
    /// Simulated time, s.
    pub t_end: f64,
    /// Temperature samples (equally spaced in t, t = 0 included).
    pub samples: usize,
    pub seed: u64,
}

/// T(t) of one engine.
#[derive(Debug, Clone, Serialize)]
pub struct Curve {
    pub engine: String,
    pub temperature: Vec<f64>,
    /// Collisions done (MD: not counted, 0).
    pub collisions: u64,
    pub wall_seconds: f64,
}

/// A fit T = T₀ (1 + t/t₀)^(−p) (least squares in ln T, t₀ by a search on a log grid).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct PowerFit {
    pub exponent: f64,
    pub t0: f64,
    /// RMS residual of ln T.
    pub rms: f64,
}

/// The runs of one gas.
#[derive(Debug, Clone, Serialize)]
pub struct Cooling {
    pub settings: CoolingSettings,
    pub times: Vec<f64>,
    pub md_dt: f64,
    pub curves: Vec<Curve>,
    /// Fits of each curve, same order.
    pub fits: Vec<PowerFit>,
    /// Relative differences |T − T_MD|/T_MD at t_end/4, t_end/2 and t_end, per event
    /// engine (same order as `curves[1..]`).
    pub agreement_times: Vec<f64>,
    pub agreement: Vec<Vec<f64>>,
}

/// Fits T = T₀(1 + t/t₀)^(−p) over t₀ ∈ [1e-3, 1e3]·t_end.
pub fn fit_power(times: &[f64], temps: &[f64]) -> PowerFit {
    let t_end = times.last().copied().unwrap_or(1.0);
    let mut best = PowerFit {
        exponent: f64::NAN,
        t0: f64::NAN,
        rms: f64::INFINITY,
    };
    for k in 0..=600 {
        let t0 = t_end * 10f64.powf(-3.0 + k as f64 / 100.0);
        let pts: Vec<(f64, f64)> = times
            .iter()
            .zip(temps)
            .filter(|(_, t)| **t > 0.0)
            .map(|(&t, &temp)| ((1.0 + t / t0).ln(), temp.ln()))
            .collect();
        let line = linear_fit(&pts);
        let rms = fit_rms(&pts, line);
        if rms < best.rms {
            best = PowerFit {
                exponent: -line.1,
                t0,
                rms,
            };
        }
    }
    best
}

fn build(s: &CoolingSettings) -> Result<System> {
    lattice_gas(
        &s.law,
        s.density,
        s.radius,
        s.particles,
        s.packing_fraction,
        s.rms_speed,
        s.seed,
    )
}

/// Runs MD, eMD and eMD* (table) from the same state; `progress(engine)` after each of
/// the `samples` temperature samples of each engine.
pub fn run(s: &CoolingSettings, progress: &dyn Fn(&str)) -> Result<Cooling> {
    if s.samples < 8 {
        return Err(HarnessError::Invalid(
            "cooling needs at least 8 samples".into(),
        ));
    }
    let system = build(s)?;
    let times: Vec<f64> = (0..s.samples)
        .map(|k| s.t_end * k as f64 / (s.samples - 1) as f64)
        .collect();
    let md_dt = default_md_dt(&system, s.t_end)?;
    let mut curves = Vec::new();

    let kinds = [
        AnyKind::Md { dt: md_dt },
        AnyKind::Event(EventKind::Emd),
        AnyKind::Event(EventKind::EmdStarTable),
    ];
    for kind in kinds {
        let start = std::time::Instant::now();
        let mut engine = AnyEngine::new(&system, kind, s.t_end)?;
        let mut temps = Vec::new();
        sample_at(engine.sim(), times.iter().copied(), |_, sim| {
            temps.push(sim.thermo().granular_temperature);
            progress(kind.name());
            Ok(())
        })?;
        curves.push(Curve {
            engine: kind.name().into(),
            temperature: temps,
            collisions: engine.collisions(),
            wall_seconds: start.elapsed().as_secs_f64(),
        });
    }
    let fits = curves
        .iter()
        .map(|c| fit_power(&times, &c.temperature))
        .collect();
    let picks: Vec<usize> = [4, 2, 1].iter().map(|d| (s.samples - 1) / d).collect();
    let reference = &curves[0].temperature;
    let agreement = curves[1..]
        .iter()
        .map(|c| {
            picks
                .iter()
                .map(|&k| ((c.temperature[k] - reference[k]) / reference[k]).abs())
                .collect()
        })
        .collect();
    Ok(Cooling {
        settings: s.clone(),
        agreement_times: picks.iter().map(|&k| times[k]).collect(),
        times,
        md_dt,
        curves,
        fits,
        agreement,
    })
}

/// T(t) of both gases, log-log, with the fitted laws.
pub fn plot(gases: &[Cooling], path: &Path) -> std::result::Result<(), String> {
    let mut panels = Vec::new();
    for g in gases {
        let law = if g.settings.name == "linear" {
            "Haff: p = 2"
        } else {
            "viscoelastic: p = 5/3"
        };
        let mut p = Panel::new(
            format!(
                "{} gas, N = {}, η = {}",
                g.settings.name, g.settings.particles, g.settings.packing_fraction
            ),
            Axis::linear("time t (s)"),
            Axis::log("granular temperature T (J)"),
        );
        p.legend = LegendAt::UpperRight;
        for ((c, fit), (color, style)) in g.curves.iter().zip(&g.fits).zip(ENGINE_STYLES) {
            let pts = g
                .times
                .iter()
                .copied()
                .zip(c.temperature.iter().copied())
                .collect();
            p.series.push(Series::new(
                format!("{} (fit p = {:.2})", c.engine, fit.exponent),
                pts,
                color,
                style,
            ));
        }
        // The expected law through MD's first point, with MD's fitted t0.
        let (t0_md, temp0) = (g.fits[0].t0, g.curves[0].temperature[0]);
        let expected = if g.settings.name == "linear" {
            2.0
        } else {
            5.0 / 3.0
        };
        let pts = g
            .times
            .iter()
            .map(|&t| (t, temp0 * (1.0 + t / t0_md).powf(-expected)))
            .collect();
        p.series.push(Series::new(
            format!("{law}, t0 of the MD fit"),
            pts,
            PALETTE[7],
            Style::Points(2),
        ));
        panels.push(p);
    }
    write_png(path, (1500, 650), 1, gases.len(), &panels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_recovers_a_known_power_law() {
        let times: Vec<f64> = (0..50).map(|k| k as f64 * 0.1).collect();
        let temps: Vec<f64> = times
            .iter()
            .map(|t| 3.0 * (1.0 + t / 0.7).powf(-5.0 / 3.0))
            .collect();
        let f = fit_power(&times, &temps);
        assert!((f.exponent - 5.0 / 3.0).abs() < 0.02, "{f:?}");
        assert!((f.t0 / 0.7 - 1.0).abs() < 0.03, "{f:?}");
    }
}
