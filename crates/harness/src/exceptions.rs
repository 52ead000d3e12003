//! Fig. 7 of Müller & Pöschel 2013 (Sec. VI B 6): how often eMD* meets its exceptions in
//! a free gas of elastic viscoelastic-Hertz spheres (A = 0, ρ = 1140 kg/m³, R = 0.1 m,
//! ν = 0.4), started on a lattice with thermal speed about 2 m/s, in a periodic box:
//! (a) the rotation of E^φ would overlap a third particle (eMD fallback), and (b) a third
//! particle hits one in its transient between E^φ and E^v. The frequencies are per
//! collision; the paper finds "about 0.1 %" for typical parameters.

use crate::Result;
use crate::engines::{EventKind, event_engine, lattice_gas, on_independent_gases};
use crate::plot::{Annotation, Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::stats::{mean_and_standard_error, poisson_interval};
use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use serde::Serialize;
use std::path::Path;

pub const RADIUS: f64 = 0.1;
pub const DENSITY: f64 = 1140.0;
pub const POISSON: f64 = 0.4;
/// Root-mean-square speed of the initial Maxwell velocities, m/s.
pub const RMS_SPEED: f64 = 2.0;

/// How long each gas of the figure runs: at least `min_per_particle` collisions per
/// particle, then on until `target_exceptions` exceptions (a + b) have been counted or
/// `max_per_particle` collisions per particle have been done. Counting to a target keeps
/// the Poisson error of the rare points near 1/√target; the stop rule biases f upwards
/// by about 1/target.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Effort {
    pub min_per_particle: f64,
    pub max_per_particle: f64,
    pub target_exceptions: u64,
}

/// One gas of the figure.
#[derive(Debug, Clone, Serialize)]
pub struct ExceptionPoint {
    pub packing_fraction: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    pub particles: usize,
    pub collisions: u64,
    /// Exception (a): rotation impossible, eMD rule used instead.
    pub rotation: u64,
    /// Exception (b): interference of a third particle.
    pub interference: u64,
    /// Impacts outside the table's box, solved exactly instead (counted).
    pub table_fallbacks: u64,
    /// Exception frequencies per 1000 collisions (the paper's unit).
    pub per_mille_a: f64,
    pub per_mille_b: f64,
    /// f_a + f_b per 1000 collisions, and its 68 % Poisson interval.
    pub per_mille_total: f64,
    pub per_mille_total_interval: (f64, f64),
}

impl ExceptionPoint {
    /// The point with these counts, its frequencies per 1000 collisions and the interval.
    fn from_counts(
        (packing_fraction, young, particles): (f64, f64, usize),
        collisions: u64,
        (rotation, interference): (u64, u64),
        table_fallbacks: u64,
    ) -> Self {
        let n = collisions.max(1) as f64;
        let exceptions = rotation + interference;
        Self {
            packing_fraction,
            young,
            particles,
            collisions,
            rotation,
            interference,
            table_fallbacks,
            per_mille_a: 1000.0 * rotation as f64 / n,
            per_mille_b: 1000.0 * interference as f64 / n,
            per_mille_total: 1000.0 * exceptions as f64 / n,
            per_mille_total_interval: per_mille_interval(exceptions, collisions),
        }
    }

    /// The 68 % Poisson interval of a frequency per 1000 collisions for `count` events.
    pub fn per_mille_interval(&self, count: u64) -> (f64, f64) {
        per_mille_interval(count, self.collisions)
    }
}

fn per_mille_interval(count: u64, collisions: u64) -> (f64, f64) {
    let (lo, hi) = poisson_interval(count);
    let n = collisions.max(1) as f64;
    (1000.0 * lo / n, 1000.0 * hi / n)
}

/// Runs one gas for the collisions `effort` asks for.
pub fn run_point(
    eta: f64,
    young: f64,
    count: usize,
    effort: Effort,
    seed: u64,
) -> Result<ExceptionPoint> {
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(young, POISSON, 0.0)?);
    let system = lattice_gas(&law, DENSITY, RADIUS, count, eta, RMS_SPEED, seed)?;
    let mut engine = event_engine(&system, EventKind::EmdStarTable)?;
    let collisions = |per_particle: f64| (per_particle * count as f64 / 2.0).ceil() as u64;
    let (min, max) = (
        collisions(effort.min_per_particle),
        collisions(effort.max_per_particle.max(effort.min_per_particle)),
    );
    let chunk = (count as u64 / 2).max(1);
    engine.run_collisions(min)?;
    loop {
        let s = engine.stats();
        let done = s.pair_collisions;
        if done >= max
            || s.exception_rotation + s.exception_interference >= effort.target_exceptions
        {
            break;
        }
        engine.run_collisions(chunk.min(max - done))?;
    }
    let s = engine.stats();
    Ok(ExceptionPoint::from_counts(
        (eta, young, count),
        s.pair_collisions,
        (s.exception_rotation, s.exception_interference),
        s.mor_fallbacks,
    ))
}

/// One point of the figure run on several independent gases (seeds `seed`, `seed + 1`,
/// …) and pooled.
#[derive(Debug, Clone, Serialize)]
pub struct PooledPoint {
    /// The gases, in seed order.
    pub gases: Vec<ExceptionPoint>,
    /// All counts summed (collisions, a, b, fallbacks); its interval is the Poisson
    /// interval of the pooled count.
    pub pooled: ExceptionPoint,
    /// f_a + f_b per 1000 collisions: mean over the gases and the standard error of the
    /// mean. This error includes what a Poisson interval leaves out: the scatter between
    /// starts, the stop rule and exceptions that come in clusters.
    pub mean: f64,
    pub standard_error: f64,
}

/// [`run_point`] on `gases` independent gases in parallel, pooled.
pub fn run_replicas(
    eta: f64,
    young: f64,
    count: usize,
    effort: Effort,
    seed: u64,
    gases: usize,
) -> Result<PooledPoint> {
    let runs = on_independent_gases("Fig. 7", seed, gases, |s| {
        run_point(eta, young, count, effort, s)
    })?;
    Ok(pool(runs))
}

/// Sums the counts of independent gases of one point.
fn pool(gases: Vec<ExceptionPoint>) -> PooledPoint {
    let sum = |f: fn(&ExceptionPoint) -> u64| gases.iter().map(f).sum::<u64>();
    let first = &gases[0];
    let pooled = ExceptionPoint::from_counts(
        (first.packing_fraction, first.young, first.particles),
        sum(|p| p.collisions),
        (sum(|p| p.rotation), sum(|p| p.interference)),
        sum(|p| p.table_fallbacks),
    );
    let totals: Vec<f64> = gases.iter().map(|p| p.per_mille_total).collect();
    let (mean, standard_error) = mean_and_standard_error(&totals);
    PooledPoint {
        gases,
        pooled,
        mean,
        standard_error,
    }
}

/// Writes the two panels: against η at Y = `young_a`, and against Y at η = `eta_b`.
pub fn plot(
    by_eta: &[ExceptionPoint],
    by_young: &[ExceptionPoint],
    path: &Path,
) -> std::result::Result<(), String> {
    // A zero count cannot go on a log axis: it is left out of the line and named in
    // a note under the lowest point.
    type Pick<'a> = &'a dyn Fn(&ExceptionPoint) -> f64;
    let pts = |v: &[ExceptionPoint], x: Pick, y: Pick| {
        v.iter()
            .filter(|p| y(p) > 0.0)
            .map(|p| (x(p), y(p)))
            .collect::<Vec<_>>()
    };
    let young = by_eta.first().map_or(0.0, |p| p.young);
    let eta = by_young.first().map_or(0.0, |p| p.packing_fraction);
    let mut a = Panel::new(
        format!("a) against packing fraction, Y = {young:.0e} Pa (bars: 68 % Poisson)"),
        Axis::log("packing fraction η"),
        Axis::log("exception frequency f_e (per 1000 collisions)"),
    );
    let mut b = Panel::new(
        format!("b) against Young's modulus, η = {eta} (bars: 68 % Poisson)"),
        Axis::log("Young's modulus Y (Pa)"),
        Axis::log("exception frequency f_e (per 1000 collisions)"),
    );
    a.legend = LegendAt::UpperLeft;
    b.legend = LegendAt::UpperRight;
    for (panel, v, x) in [
        (
            &mut a,
            by_eta,
            &(|p: &ExceptionPoint| p.packing_fraction) as &dyn Fn(&ExceptionPoint) -> f64,
        ),
        (&mut b, by_young, &|p: &ExceptionPoint| p.young),
    ] {
        panel.series.push(Series::new(
            "type a: rotation impossible",
            pts(v, x, &|p| p.per_mille_a),
            PALETTE[1],
            Style::LinePoints(5),
        ));
        panel.series.push(Series::new(
            "type b: third particle in the transient",
            pts(v, x, &|p| p.per_mille_b),
            PALETTE[3],
            Style::LinePoints(5),
        ));
        for p in v {
            for (count, color) in [(p.rotation, PALETTE[1]), (p.interference, PALETTE[3])] {
                let (lo, hi) = p.per_mille_interval(count);
                panel.annotations.push(Annotation::ErrorBar {
                    x: x(p),
                    lo,
                    hi,
                    color,
                });
            }
        }
        let lowest = v
            .iter()
            .map(|p| p.per_mille_a.min(p.per_mille_b))
            .filter(|f| *f > 0.0)
            .fold(1.0, f64::min);
        for p in v.iter().filter(|p| p.rotation == 0 || p.interference == 0) {
            let which = match (p.rotation, p.interference) {
                (0, 0) => "a, b",
                (0, _) => "a",
                _ => "b",
            };
            panel.annotations.push(Annotation::Text {
                // Left of the point (both x axes are logarithmic), so it stays inside.
                at: (x(p) / 20.0, lowest / 2.0),
                text: format!("at {:.0e}: no {which} in {} collisions", x(p), p.collisions),
                color: PALETTE[0],
            });
        }
        let xs: Vec<f64> = v.iter().map(x).collect();
        let (lo, hi) = (
            xs.iter().copied().fold(f64::MAX, f64::min),
            xs.iter().copied().fold(f64::MIN, f64::max),
        );
        panel.series.push(Series::new(
            "paper: about 1 per 1000",
            vec![(lo, 1.0), (hi, 1.0)],
            PALETTE[7],
            Style::Dashed,
        ));
    }
    write_png(path, (1000, 1300), 2, 1, &[a, b])
}
