//! Self-diffusion in a free elastic gas, by MD, eMD and eMD* from one initial state: the
//! measurable fingerprint of trajectory accuracy the paper's outlook names (Müller &
//! Pöschel 2013, Sec. VII). With A = 0 the gas keeps its temperature, so D is a steady
//! transport coefficient. eMD collides hard spheres of diameter 2R at contact; MD and
//! eMD* follow the soft Hertz contact, whose finite duration and rotation of e_r change
//! the scattering.
//!
//! D comes from the slope of the mean-square displacement, MSD(t) = 6·D·t at times well
//! beyond the mean free time, averaged over time origins. The reference is Enskog's
//! first approximation for hard spheres (Chapman & Cowling, The Mathematical Theory of
//! Non-Uniform Gases, 3rd ed., 1970, Ch. 16):
//! D_E = 3 / (8 n σ² χ) · √(kT / (π m)), with the Carnahan–Starling contact value
//! χ = (1 − η/2) / (1 − η)³.

use crate::engines::{
    AnyEngine, AnyKind, ENGINE_STYLES, EventKind, default_md_dt, lattice_gas, on_independent_gases,
    sample_at,
};
use crate::exceptions::{DENSITY, POISSON, RADIUS, RMS_SPEED};
use crate::plot::{Axis, LegendAt, PALETTE, Panel, Series, Style, write_png};
use crate::stats::{linear_fit, mean_and_standard_error};
use crate::{HarnessError, Result};
use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use emdstar_system::SimBox;
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;

/// The gas and the measurement.
#[derive(Debug, Clone, Serialize)]
pub struct DiffusionSettings {
    pub particles: usize,
    pub packing_fraction: f64,
    /// Young's modulus, Pa.
    pub young: f64,
    /// Run length and the start of the time origins, in Enskog mean free times.
    pub free_times: f64,
    pub equilibration_free_times: f64,
    /// The MSD slope is fitted over lags in this range, in mean free times.
    pub fit_lags: (f64, f64),
    pub seed: u64,
}

/// D of one engine, with its standard error from independent groups of particles (a
/// lower bound: see [`run_replicas`]).
#[derive(Debug, Clone, Serialize)]
pub struct EngineDiffusion {
    pub engine: String,
    /// m²/s.
    pub coefficient: f64,
    pub standard_error: f64,
    /// MSD at each lag, m².
    pub msd: Vec<f64>,
    pub collisions: u64,
    /// eMD*'s exceptions (a) rotation impossible, eMD rule used, and (b) interference.
    pub exceptions: [u64; 2],
    pub wall_seconds: f64,
}

/// The three engines on one gas.
#[derive(Debug, Clone, Serialize)]
pub struct Diffusion {
    pub settings: DiffusionSettings,
    /// Enskog mean free time 1/ω_E and the sampling interval, s.
    pub free_time: f64,
    pub sample_interval: f64,
    pub md_dt: f64,
    /// kT/m of the initial velocities, m²/s².
    pub kt_over_m: f64,
    /// Enskog's D_E, m²/s.
    pub enskog: f64,
    /// Lag times of the MSD, s.
    pub lags: Vec<f64>,
    pub engines: Vec<EngineDiffusion>,
}

/// Carnahan–Starling pair correlation at contact.
pub fn contact_value(eta: f64) -> f64 {
    (1.0 - 0.5 * eta) / (1.0 - eta).powi(3)
}

/// Enskog's self-diffusion coefficient D_E and collision frequency ω_E of hard spheres
/// of diameter `sigma` at number density `n` and kT/m = `kt_over_m` (Chapman &
/// Cowling 1970, Chs. 5 and 16): the dilute values divided and multiplied by χ.
pub fn enskog(n: f64, sigma: f64, eta: f64, kt_over_m: f64) -> (f64, f64) {
    let chi = contact_value(eta);
    let d = 3.0 / (8.0 * n * sigma * sigma * chi) * (kt_over_m / std::f64::consts::PI).sqrt();
    let omega = 4.0 * n * sigma * sigma * chi * (std::f64::consts::PI * kt_over_m).sqrt();
    (d, omega)
}

/// Unwrapped positions: adds each sample's minimum-image displacement to the last.
struct Tracker {
    sim_box: SimBox,
    last: Vec<[f64; 3]>,
    unwrapped: Vec<[f64; 3]>,
    samples: Vec<Vec<[f64; 3]>>,
}

impl Tracker {
    fn new(sim_box: SimBox, start: &[[f64; 3]]) -> Self {
        Self {
            sim_box,
            last: start.to_vec(),
            unwrapped: start.to_vec(),
            samples: Vec::new(),
        }
    }

    /// Errors if a particle moved so far between samples that its image is ambiguous.
    fn observe(&mut self, positions: &[[f64; 3]], keep: bool) -> Result<()> {
        for ((u, last), &x) in self.unwrapped.iter_mut().zip(&mut self.last).zip(positions) {
            let d = self
                .sim_box
                .min_image(std::array::from_fn(|k| x[k] - last[k]));
            for k in 0..3 {
                if d[k].abs() > 0.4 * self.sim_box.size[k] {
                    return Err(HarnessError::Invalid(format!(
                        "diffusion: a particle moved {:.3} m along axis {k} between two \
                         samples, too close to half the box ({:.3} m) to unwrap; sample \
                         more often",
                        d[k].abs(),
                        self.sim_box.size[k]
                    )));
                }
                u[k] += d[k];
            }
            *last = x;
        }
        if keep {
            self.samples.push(self.unwrapped.clone());
        }
        Ok(())
    }
}

/// Time origins of the MSD are this many samples apart (one per mean free time).
const ORIGIN_STRIDE: usize = 4;

/// MSD at lags 0..=max_lag (in samples), averaged over the time origins and the
/// particles `members`. Lags are independent sums in a fixed order, so the result does
/// not depend on the thread count.
fn msd(samples: &[Vec<[f64; 3]>], members: &[usize], max_lag: usize) -> Vec<f64> {
    (0..=max_lag)
        .into_par_iter()
        .map(|lag| {
            let origins: Vec<usize> = (0..samples.len() - lag).step_by(ORIGIN_STRIDE).collect();
            let mut sum = 0.0;
            for &k in &origins {
                let (a, b) = (&samples[k], &samples[k + lag]);
                for &i in members {
                    let d: [f64; 3] = std::array::from_fn(|c| b[i][c] - a[i][c]);
                    sum += d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                }
            }
            sum / (origins.len() * members.len()) as f64
        })
        .collect()
}

/// D = slope / 6 of MSD against lag time over the fit range.
fn slope_coefficient(lags: &[f64], msd: &[f64], range: (f64, f64)) -> f64 {
    let pts: Vec<(f64, f64)> = lags
        .iter()
        .zip(msd)
        .filter(|(t, _)| (range.0..=range.1).contains(*t))
        .map(|(&t, &m)| (t, m))
        .collect();
    linear_fit(&pts).1 / 6.0
}

/// Groups of particles for the standard error of D.
const GROUPS: usize = 8;

fn analyse(
    engine: &str,
    samples: &[Vec<[f64; 3]>],
    lags: &[f64],
    range: (f64, f64),
    stats: Option<&emdstar_edmd::Stats>,
    wall_seconds: f64,
) -> EngineDiffusion {
    let n = samples[0].len();
    let all: Vec<usize> = (0..n).collect();
    let max_lag = lags.len() - 1;
    let curve = msd(samples, &all, max_lag);
    let coefficient = slope_coefficient(lags, &curve, range);
    let per_group: Vec<f64> = (0..GROUPS)
        .map(|g| {
            let members: Vec<usize> = (g..n).step_by(GROUPS).collect();
            slope_coefficient(lags, &msd(samples, &members, max_lag), range)
        })
        .collect();
    let (_, standard_error) = mean_and_standard_error(&per_group);
    EngineDiffusion {
        engine: engine.into(),
        coefficient,
        standard_error,
        msd: curve,
        collisions: stats.map_or(0, |s| s.pair_collisions),
        exceptions: stats.map_or([0; 2], |s| [s.exception_rotation, s.exception_interference]),
        wall_seconds,
    }
}

/// The gas and the sampling derived from it.
struct Plan {
    system: emdstar_system::System,
    sim_box: SimBox,
    kt_over_m: f64,
    enskog: f64,
    free_time: f64,
    /// Sampling interval (s) and number of samples.
    interval: f64,
    total: usize,
}

fn plan(s: &DiffusionSettings) -> Result<Plan> {
    if !(s.fit_lags.0 > 0.0
        && s.fit_lags.0 < s.fit_lags.1
        && s.equilibration_free_times >= 0.0
        && s.fit_lags.1 + s.equilibration_free_times < s.free_times)
    {
        return Err(HarnessError::Invalid(format!(
            "diffusion: need 0 < fit lags {:?} and equilibration {} + the longest lag < run \
             length {} (mean free times)",
            s.fit_lags, s.equilibration_free_times, s.free_times
        )));
    }
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(s.young, POISSON, 0.0)?);
    let system = lattice_gas(
        &law,
        DENSITY,
        RADIUS,
        s.particles,
        s.packing_fraction,
        RMS_SPEED,
        s.seed,
    )?;
    let sim_box = system
        .domain
        .sim_box
        .ok_or_else(|| HarnessError::Invalid("the lattice gas has no box".into()))?;
    let speed2: Vec<f64> = system
        .particles
        .velocity
        .iter()
        .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        .collect();
    let kt_over_m = speed2.iter().sum::<f64>() / (3 * speed2.len()) as f64;
    let v_max = speed2.iter().copied().fold(0.0, f64::max).sqrt();
    let n = s.particles as f64 / sim_box.volume();
    let (enskog, omega) = enskog(n, 2.0 * RADIUS, s.packing_fraction, kt_over_m);
    let free_time = 1.0 / omega;
    // Four samples per free time, and never more than a quarter box between samples
    // for the fastest particle (twice the initial fastest speed) so unwrapping is safe.
    let side = sim_box.size.iter().copied().fold(f64::INFINITY, f64::min);
    let interval = (0.25 * free_time).min(0.25 * side / (2.0 * v_max));
    let total = (s.free_times * free_time / interval).ceil() as usize;
    Ok(Plan {
        system,
        sim_box,
        kt_over_m,
        enskog,
        free_time,
        interval,
        total,
    })
}

/// Number of samples each engine takes (for a progress bar).
pub fn sample_count(s: &DiffusionSettings) -> Result<u64> {
    Ok(plan(s)?.total as u64)
}

/// A ratio of diffusion coefficients in each independent gas, with its mean and the
/// standard error of the mean over the gases.
#[derive(Debug, Clone, Serialize)]
pub struct Ratio {
    pub name: String,
    pub values: Vec<f64>,
    pub mean: f64,
    pub standard_error: f64,
}

impl Ratio {
    fn over(name: &str, values: Vec<f64>) -> Self {
        let (mean, standard_error) = mean_and_standard_error(&values);
        Self {
            name: name.into(),
            mean,
            standard_error,
            values,
        }
    }
}

/// Independent gases (seeds `seed`, `seed + 1`, …) and the ratios the checks use.
#[derive(Debug, Clone, Serialize)]
pub struct Replicas {
    pub runs: Vec<Diffusion>,
    pub emdstar_over_md: Ratio,
    pub emd_over_md: Ratio,
    pub emd_over_enskog: Ratio,
}

/// [`run`] on `count` independent gases in parallel; the scatter of the ratios between
/// them is their error (it includes what one gas's particle groups cannot see: the
/// start and the collision sequence).
pub fn run_replicas(
    s: &DiffusionSettings,
    count: usize,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Replicas> {
    let runs = on_independent_gases("diffusion", s.seed, count, |seed| {
        run(&DiffusionSettings { seed, ..s.clone() }, progress)
    })?;
    let ratio =
        |name: &str, f: &dyn Fn(&Diffusion) -> f64| Ratio::over(name, runs.iter().map(f).collect());
    let d = |r: &Diffusion, k: usize| r.engines[k].coefficient;
    Ok(Replicas {
        emdstar_over_md: ratio("eMD*/MD", &|r| d(r, 2) / d(r, 0)),
        emd_over_md: ratio("eMD/MD", &|r| d(r, 1) / d(r, 0)),
        emd_over_enskog: ratio("eMD/Enskog", &|r| d(r, 1) / r.enskog),
        runs,
    })
}

/// Runs MD, eMD and eMD* (table) from one lattice state; `progress(engine)` after each
/// of the [`sample_count`] samples of each engine.
pub fn run(s: &DiffusionSettings, progress: &(dyn Fn(&str) + Sync)) -> Result<Diffusion> {
    let p = plan(s)?;
    let (system, sim_box, free_time, interval, total) =
        (&p.system, p.sim_box, p.free_time, p.interval, p.total);
    let first_kept = (s.equilibration_free_times * free_time / interval).ceil() as usize;
    let max_lag = (s.fit_lags.1 * free_time / interval).ceil() as usize;
    let lags: Vec<f64> = (0..=max_lag).map(|k| k as f64 * interval).collect();
    let range = (s.fit_lags.0 * free_time, s.fit_lags.1 * free_time);
    let t_end = total as f64 * interval;
    let md_dt = default_md_dt(system, t_end)?;

    let mut engines = Vec::new();
    let kinds = [
        AnyKind::Md { dt: md_dt },
        AnyKind::Event(EventKind::Emd),
        AnyKind::Event(EventKind::EmdStarTable),
    ];
    for kind in kinds {
        let start = std::time::Instant::now();
        let mut engine = AnyEngine::new(system, kind, t_end)?;
        let mut track = Tracker::new(sim_box, &system.particles.position);
        let times = (1..=total).map(|k| k as f64 * interval);
        sample_at(engine.sim(), times, |k, sim| {
            track.observe(&sim.particles().position, k + 1 >= first_kept)?;
            progress(kind.name());
            Ok(())
        })?;
        let wall = start.elapsed().as_secs_f64();
        engines.push(analyse(
            kind.name(),
            &track.samples,
            &lags,
            range,
            engine.event_stats(),
            wall,
        ));
    }
    Ok(Diffusion {
        settings: s.clone(),
        free_time,
        sample_interval: interval,
        md_dt,
        kt_over_m: p.kt_over_m,
        enskog: p.enskog,
        lags,
        engines,
    })
}

/// MSD against lag time for the three engines with 6·D_E·t (left), and the running
/// coefficient MSD/(6t), which levels off at D (right; the fit range marked).
pub fn plot(d: &Diffusion, path: &Path) -> std::result::Result<(), String> {
    let title = format!(
        "elastic Hertz gas, N = {}, η = {}, Y = {:.0e} Pa, seed {}",
        d.settings.particles, d.settings.packing_fraction, d.settings.young, d.settings.seed
    );
    let mut msd = Panel::new(
        format!("mean-square displacement, {title}"),
        Axis::linear("lag time t (s)"),
        Axis::linear("mean-square displacement (m²)"),
    );
    msd.legend = LegendAt::UpperLeft;
    let mut running = Panel::new(
        "running coefficient MSD/(6t); dashed: the fit range of D".to_string(),
        Axis::linear("lag time t (s)"),
        Axis::linear("MSD / 6t (m²/s)"),
    );
    running.legend = LegendAt::LowerRight;
    for (e, (color, style)) in d.engines.iter().zip(ENGINE_STYLES) {
        let label = format!("{}: D = {:.4e} m²/s", e.engine, e.coefficient);
        let pts = d.lags.iter().copied().zip(e.msd.iter().copied()).collect();
        msd.series
            .push(Series::new(label.clone(), pts, color, style));
        let pts = d
            .lags
            .iter()
            .zip(&e.msd)
            .skip(1)
            .map(|(&t, &m)| (t, m / (6.0 * t)))
            .collect();
        running.series.push(Series::new(label, pts, color, style));
    }
    let label = format!("Enskog D_E = {:.4e} m²/s", d.enskog);
    let pts = d.lags.iter().map(|&t| (t, 6.0 * d.enskog * t)).collect();
    msd.series.push(Series::new(
        label.clone(),
        pts,
        PALETTE[7],
        Style::Points(2),
    ));
    let pts = d.lags.iter().skip(1).map(|&t| (t, d.enskog)).collect();
    running
        .series
        .push(Series::new(label, pts, PALETTE[7], Style::Points(2)));
    let (lo, hi) = d.settings.fit_lags;
    let top = d
        .engines
        .iter()
        .map(|e| e.coefficient)
        .fold(d.enskog, f64::max);
    for t in [lo * d.free_time, hi * d.free_time] {
        running.series.push(Series::new(
            String::new(),
            vec![(t, 0.0), (t, 1.1 * top)],
            PALETTE[7],
            Style::Dashed,
        ));
    }
    write_png(path, (1800, 700), 1, 2, &[msd, running])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_statistics_are_the_mean_and_its_standard_error() {
        let r = Ratio::over("x", vec![1.0, 2.0, 3.0, 4.0]);
        // Sample variance 5/3, so the standard error is √(5/12).
        assert!((r.mean - 2.5).abs() < 1e-15);
        assert!((r.standard_error - (5.0f64 / 12.0).sqrt()).abs() < 1e-15);
        assert!(Ratio::over("x", vec![1.0]).standard_error.is_nan());
        let s = DiffusionSettings {
            particles: 100,
            packing_fraction: 0.05,
            young: 1e7,
            free_times: 30.0,
            equilibration_free_times: 5.0,
            fit_lags: (5.0, 20.0),
            seed: 1,
        };
        assert!(run_replicas(&s, 0, &|_| {}).is_err());
    }

    #[test]
    fn enskog_mean_free_path_is_the_textbook_one() {
        // Dilute limit: mean free path v̄/ω = 1/(√2 π n σ²), v̄ = √(8kT/(πm)).
        let (n, sigma, kt_m) = (2.0, 0.3, 1.7);
        let (_, omega) = enskog(n, sigma, 0.0, kt_m);
        let v_mean = (8.0 * kt_m / std::f64::consts::PI).sqrt();
        let path = 1.0 / (2f64.sqrt() * std::f64::consts::PI * n * sigma * sigma);
        assert!((v_mean / omega / path - 1.0).abs() < 1e-12);
    }

    #[test]
    fn tracker_unwraps_periodic_crossings_and_refuses_ambiguous_jumps() {
        let b = SimBox {
            lo: [0.0; 3],
            size: [10.0; 3],
            periodic: [true; 3],
        };
        let mut t = Tracker::new(b, &[[9.5, 5.0, 0.5]]);
        // Crosses x = 10 (wraps to 0.5) and z = 0 (wraps to 9.7).
        t.observe(&[[0.5, 5.0, 9.7]], true).unwrap();
        let u = t.samples[0][0];
        assert!(
            (u[0] - 10.5).abs() < 1e-12 && (u[2] + 0.3).abs() < 1e-12,
            "{u:?}"
        );
        assert!(t.observe(&[[5.0, 5.0, 9.7]], true).is_err());
    }

    #[test]
    fn msd_of_uniform_motion_grows_as_t_squared() {
        let samples: Vec<Vec<[f64; 3]>> = (0..20)
            .map(|k| vec![[0.5 * k as f64, 0.0, 0.0], [0.0, -0.2 * k as f64, 0.0]])
            .collect();
        let m = msd(&samples, &[0, 1], 5);
        for (lag, v) in m.iter().enumerate() {
            let expect = 0.5 * ((0.5 * lag as f64).powi(2) + (0.2 * lag as f64).powi(2));
            assert!((v - expect).abs() < 1e-12, "{lag}: {v} {expect}");
        }
    }
}
