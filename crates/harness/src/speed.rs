//! Speed: wall time of MD and of eMD* (default table) per simulated second, on the same
//! elastic Hertz gas (the gas of [`crate::exceptions`]: R = 0.1 m, ρ = 1140 kg/m³,
//! ν = 0.4, A = 0, rms speed 2 m/s, from a lattice). The paper promises "orders of
//! magnitude" (Müller & Pöschel 2013, Sec. VI B 5).
//!
//! The two engines take turns: each round runs MD, then eMD*, for an equal share of the
//! wall-time budget, continuing the same two gases, and each engine's cost is its best
//! round, the one least disturbed by other load on the machine. MD's cost is the
//! measured rate of its steps (not a run over the whole simulated time eMD* covers), so
//! the ratio is a ratio of measured rates. Wall times depend on the thread pool the
//! caller runs this in.

use crate::Result;
use crate::engines::{EventKind, default_md_dt, event_engine, lattice_gas, md_engine};
use crate::exceptions::{DENSITY, POISSON, RADIUS, RMS_SPEED};
use crate::plot::{Annotation, Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// The gas of the speed claim: packing fraction and Young's modulus (Pa).
pub const GOAL_GAS: (f64, f64) = (1e-3, 1e9);
/// The paper's claim, "orders of magnitude": MD / eMD* ≥ 10² on [`GOAL_GAS`]. This is the
/// bar of the check.
pub const CLAIM_RATIO: f64 = 1e2;
/// The project's own goal on [`GOAL_GAS`], reported beside the check for information.
pub const GOAL_RATIO: f64 = 2e3;

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
    /// Wall seconds per simulated second: the best round.
    pub md_cost: f64,
    /// MD's cost in each round.
    pub md_rounds: Vec<f64>,
    /// Simulated seconds and wall seconds of eMD* over all rounds.
    pub emdstar_simulated: f64,
    pub emdstar_wall: f64,
    pub emdstar_collisions: u64,
    /// All of eMD*'s events over the same run, and the cell crossings among them.
    pub emdstar_events: u64,
    pub emdstar_crossings: u64,
    /// Epochs of the epoch broad phase over the run (0: eMD* ran on cell crossings).
    pub emdstar_epochs: u64,
    /// Wall seconds per simulated second: the best round.
    pub emdstar_cost: f64,
    /// eMD*'s cost in each round.
    pub emdstar_rounds: Vec<f64>,
    /// md_cost / emdstar_cost.
    pub ratio: f64,
}

/// How long each engine is timed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Timing {
    /// Wall seconds per engine, shared out over the rounds.
    pub budget: f64,
    /// Rounds, alternating MD and eMD*.
    pub rounds: usize,
}

/// Measures one gas: `timing.rounds` rounds, each timing MD and then eMD* for
/// budget/rounds wall seconds (eMD* also for at least count/rounds collisions, so at
/// least one per particle over all rounds).
pub fn measure(
    eta: f64,
    young: f64,
    count: usize,
    timing: Timing,
    seed: u64,
) -> Result<SpeedPoint> {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(young, POISSON, 0.0)?);
    let system = lattice_gas(&law, DENSITY, RADIUS, count, eta, RMS_SPEED, seed)?;
    // Cap on eMD*'s simulated time (s) per round: a gas that hardly collides cannot
    // loop for ever.
    let horizon = 1e3;
    let rounds = timing.rounds.max(1);
    let share = timing.budget / rounds as f64;
    let md_dt = default_md_dt(&system, 0.0)?;
    let mut md = md_engine(system.clone(), md_dt, 0.0)?;
    md.advance(20)?;
    let mut e = event_engine(&system, EventKind::EmdStarTable)?;
    e.run_collisions((count / 10) as u64)?;
    let (c0, ev0) = (e.stats().pair_collisions, e.stats().events);
    let (x0, p0) = (e.stats().crossings, e.stats().epochs);
    let (mut md_rounds, mut emdstar_rounds) = (Vec::new(), Vec::new());
    let (mut md_steps, mut simulated, mut wall) = (0, 0.0, 0.0);
    let per_round = (count / rounds).max(1) as u64;
    for _ in 0..rounds {
        let start = Instant::now();
        let mut steps = 0;
        while start.elapsed().as_secs_f64() < share {
            md.advance(50)?;
            steps += 50;
        }
        md_rounds.push(start.elapsed().as_secs_f64() / (steps as f64 * md_dt));
        md_steps += steps;

        let (t0, c_start) = (e.time(), e.stats().pair_collisions);
        let start = Instant::now();
        while start.elapsed().as_secs_f64() < share
            || e.stats().pair_collisions - c_start < per_round
        {
            e.run_collisions((count / 10).max(1) as u64)?;
            if e.time() - t0 > horizon {
                break;
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        emdstar_rounds.push(seconds / (e.time() - t0));
        simulated += e.time() - t0;
        wall += seconds;
    }
    let best = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let (md_cost, emdstar_cost) = (best(&md_rounds), best(&emdstar_rounds));
    Ok(SpeedPoint {
        packing_fraction: eta,
        young,
        particles: count,
        md_dt,
        md_skin: md.skin(),
        md_steps,
        md_cost,
        md_rounds,
        emdstar_simulated: simulated,
        emdstar_wall: wall,
        emdstar_collisions: e.stats().pair_collisions - c0,
        emdstar_events: e.stats().events - ev0,
        emdstar_crossings: e.stats().crossings - x0,
        emdstar_epochs: e.stats().epochs - p0,
        emdstar_cost,
        emdstar_rounds,
        ratio: md_cost / emdstar_cost,
    })
}

impl SpeedPoint {
    /// eMD*'s wall time per event over all rounds, ns.
    pub fn emdstar_ns_per_event(&self) -> f64 {
        self.emdstar_wall / self.emdstar_events.max(1) as f64 * 1e9
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
    // The claim and the goal are for one gas (η = 0.001, Y = 1 GPa): markers, and a bar
    // spanning the gap from the measured ratio to the goal when it falls short.
    let ((goal_eta, goal_young), goal_ratio) = (GOAL_GAS, GOAL_RATIO);
    p.series.push(Series::new(
        "check 5a: ≥ 10² at η = 0.001, Y = 1 GPa (the paper's orders of magnitude)",
        vec![(goal_eta, CLAIM_RATIO)],
        PALETTE[0],
        Style::Points(7),
    ));
    p.series.push(Series::new(
        "the project's goal 2·10³ (for information)",
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
