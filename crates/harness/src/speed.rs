//! Speed: wall time of MD and of eMD* (default table) per simulated second, on the same
//! elastic Hertz gas (the gas of [`crate::exceptions`]: R = 0.1 m, ρ = 1140 kg/m³,
//! ν = 0.4, A = 0, rms speed 2 m/s, from a lattice). The paper promises "orders of
//! magnitude" (Müller & Pöschel 2013, Sec. VI B 5).
//!
//! Both engines run for at least a wall-time budget; MD's cost is the measured rate of a
//! run of steps (not of the whole simulated time eMD* covers), so the ratio is a ratio
//! of measured rates. Wall times depend on the thread pool the caller runs this in.

use crate::Result;
use crate::engines::{EventKind, default_md_dt, event_engine, lattice_gas, md_engine};
use crate::exceptions::{DENSITY, POISSON, RADIUS, RMS_SPEED};
use crate::plot::{Annotation, Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// The speed goal: MD / eMD* ≥ [`GOAL_RATIO`] on the gas at packing fraction
/// and Young's modulus [`GOAL_GAS`].
pub const GOAL_GAS: (f64, f64) = (1e-3, 1e9);
pub const GOAL_RATIO: f64 = 1e3;

/// One gas, both engines.
#[derive(Debug, Clone, Serialize)]
pub struct SpeedPoint {
    pub packing_fraction: f64,
    pub young: f64,
    pub particles: usize,
    pub md_dt: f64,
    /// MD's Verlet skin, m.
    pub md_skin: f64,
    pub md_steps: u64,
    /// Wall seconds per simulated second.
    pub md_cost: f64,
    pub emdstar_simulated: f64,
    pub emdstar_collisions: u64,
    /// All of eMD*'s events over the same run, and the cell crossings among them.
    pub emdstar_events: u64,
    pub emdstar_crossings: u64,
    /// Epochs of the epoch broad phase over the run (0: eMD* ran on cell crossings).
    pub emdstar_epochs: u64,
    pub emdstar_cost: f64,
    /// md_cost / emdstar_cost.
    pub ratio: f64,
}

/// Measures one gas, each engine for at least `budget` wall seconds (eMD* also for at
/// least one collision per particle).
pub fn measure(eta: f64, young: f64, count: usize, budget: f64, seed: u64) -> Result<SpeedPoint> {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(young, POISSON, 0.0)?);
    let system = lattice_gas(&law, DENSITY, RADIUS, count, eta, RMS_SPEED, seed)?;
    // Cap on eMD*'s simulated time (s): a gas that hardly collides cannot loop for ever.
    let horizon = 1e3;
    let md_dt = default_md_dt(&system, 0.0)?;
    let mut md = md_engine(system.clone(), md_dt, 0.0)?;
    md.advance(20)?;
    let start = Instant::now();
    let mut steps = 0;
    while start.elapsed().as_secs_f64() < budget {
        md.advance(50)?;
        steps += 50;
    }
    let md_cost = start.elapsed().as_secs_f64() / (steps as f64 * md_dt);

    let mut e = event_engine(&system, EventKind::EmdStarTable)?;
    e.run_collisions((count / 10) as u64)?;
    let (t0, c0) = (e.time(), e.stats().pair_collisions);
    let (ev0, x0, p0) = (e.stats().events, e.stats().crossings, e.stats().epochs);
    let start = Instant::now();
    while start.elapsed().as_secs_f64() < budget || e.stats().pair_collisions - c0 < count as u64 {
        e.run_collisions((count / 10).max(1) as u64)?;
        if e.time() - t0 > horizon {
            break;
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let simulated = e.time() - t0;
    let emdstar_cost = wall / simulated;
    Ok(SpeedPoint {
        packing_fraction: eta,
        young,
        particles: count,
        md_dt,
        md_skin: md.skin(),
        md_steps: steps,
        md_cost,
        emdstar_simulated: simulated,
        emdstar_collisions: e.stats().pair_collisions - c0,
        emdstar_events: e.stats().events - ev0,
        emdstar_crossings: e.stats().crossings - x0,
        emdstar_epochs: e.stats().epochs - p0,
        emdstar_cost,
        ratio: md_cost / emdstar_cost,
    })
}

impl SpeedPoint {
    /// eMD*'s wall time per event, ns.
    pub fn emdstar_ns_per_event(&self) -> f64 {
        self.emdstar_cost * self.emdstar_simulated / self.emdstar_events.max(1) as f64 * 1e9
    }

    /// How eMD* found its candidate pairs: "epochs" or "crossings".
    pub fn broad_phase(&self) -> &'static str {
        if self.emdstar_epochs > 0 {
            "epochs"
        } else {
            "crossings"
        }
    }

    /// The share of eMD*'s events that are cell crossings (with epochs: early renewals
    /// of swept boxes).
    pub fn crossing_share(&self) -> f64 {
        self.emdstar_crossings as f64 / self.emdstar_events.max(1) as f64
    }
}

/// Speed-up against packing fraction, one line per Young's modulus.
pub fn plot(points: &[SpeedPoint], path: &Path) -> std::result::Result<(), String> {
    let mut p = Panel::new(
        format!(
            "eMD* speed-up over MD, same gas, N = {}",
            points.first().map_or(0, |q| q.particles)
        ),
        Axis::log("packing fraction η"),
        Axis::log("wall-time ratio MD / eMD* per simulated second"),
    );
    p.legend = LegendAt::UpperRight;
    let mut youngs: Vec<f64> = points.iter().map(|q| q.young).collect();
    youngs.dedup();
    youngs.sort_by(f64::total_cmp);
    youngs.dedup();
    for (k, y) in youngs.iter().enumerate() {
        let pts = points
            .iter()
            .filter(|q| q.young == *y)
            .map(|q| (q.packing_fraction, q.ratio))
            .collect();
        p.series.push(Series::new(
            format!("Y = {y:.0e} Pa"),
            pts,
            PALETTE[k + 1],
            Style::LinePoints(5),
        ));
    }
    // The goal is one point (η = 0.001, Y = 1 GPa): a marker, and a bar spanning the gap
    // from the measured ratio when it falls short.
    let ((goal_eta, goal_young), goal_ratio) = (GOAL_GAS, GOAL_RATIO);
    p.series.push(Series::new(
        "goal 10³ at η = 0.001, Y = 1 GPa",
        vec![(goal_eta, goal_ratio)],
        PALETTE[7],
        Style::Points(7),
    ));
    if let Some(q) = points
        .iter()
        .find(|q| q.packing_fraction == goal_eta && q.young == goal_young && q.ratio < goal_ratio)
    {
        p.annotations.push(Annotation::ErrorBar {
            x: goal_eta,
            lo: q.ratio,
            hi: goal_ratio,
            color: PALETTE[7],
        });
    }
    write_png(path, (1000, 700), 1, 1, &[p])
}
