//! `emdstar bench edmd`: collisions per second of the event-driven engine.

use super::engine::progress_bar;
use anyhow::{Result, bail};
use clap::{Args, ValueEnum};
use emdstar_contact::Tangential;
use emdstar_contact::{ForceLaw, Model, Sphere, ViscoelasticHertz};
use emdstar_edmd::rules::{ExactMor, MorSource, TableMorSource};
use emdstar_edmd::{
    BroadPhaseKind, CalendarQueue, Engine, EventQueue, IndexedHeap, Interference, Physics,
};
use emdstar_engines::BroadPhaseChoice;
use emdstar_system::Interactions;
use emdstar_system::{Domain, Particles, fcc_gas};
use indicatif::ProgressBar;
use serde_json::{Value, json};
use std::time::Instant;

/// Where the eMD* benchmark takes its MoR from.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MorArg {
    /// The default table (embedded), out-of-box impacts solved exactly and counted.
    Table,
    /// The exact solver, one ODE solve per collision.
    Exact,
}

/// The event queue of the benchmarked engine.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum QueueArg {
    /// Indexed 4-ary min-heap.
    Heap,
    /// Calendar queue (Paul 2007).
    Calendar,
}

#[derive(Args, Debug)]
pub struct BenchEdmdArgs {
    /// Event queue.
    #[arg(long, value_enum, default_value_t = QueueArg::Calendar)]
    pub queue: QueueArg,
    /// Runs of each benchmark; the best is reported (the machine may be shared).
    #[arg(long, default_value_t = 1)]
    pub rounds: usize,
    /// Collisions per particle to time (after as many to equilibrate).
    #[arg(long, default_value_t = 20.0)]
    pub per_particle: f64,
    /// FCC cells per side of the hard-sphere benchmark (N = 4·cells³).
    #[arg(long, default_value_t = 20)]
    pub hs_cells: usize,
    /// Packing fraction of the hard-sphere benchmark.
    #[arg(long, default_value_t = 0.10)]
    pub hs_eta: f64,
    /// Also measure the rates for N = 864 … 1 000 188 (hard spheres at --hs-eta unless
    /// --emdstar-only, the eMD* gas at η = 0.01 unless --hard-spheres-only;
    /// --per-particle up to 10 collisions per particle, and at least 2·10⁵ collisions per
    /// run).
    #[arg(long)]
    pub scaling: bool,
    /// With --scaling: also draw the rates against N into this PNG (log-log).
    #[arg(long, value_name = "FILE.png", requires = "scaling")]
    pub plot: Option<std::path::PathBuf>,
    /// Skip the eMD* gas.
    #[arg(long)]
    pub hard_spheres_only: bool,
    /// Skip the hard-sphere gases (for profiling the eMD* gas alone).
    #[arg(long, conflicts_with = "hard_spheres_only")]
    pub emdstar_only: bool,
    /// MoR source of the eMD* gas.
    #[arg(long, value_enum, default_value_t = MorArg::Table)]
    pub mor: MorArg,
    /// How the engine finds candidate pairs (run twice with different values to
    /// compare them on this machine).
    #[arg(long, value_enum, default_value_t = BroadPhaseChoice::Auto)]
    pub broad_phase: BroadPhaseChoice,
    /// Events per particle between spatial re-sorts of the particle order (0: never)
    /// [default: the engine's, 20 from N = 1000 on].
    #[arg(long, value_name = "EVENTS_PER_PARTICLE")]
    pub resort_every: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Runs `collisions` after `warmup` and returns (collisions/s, stats JSON).
fn time_run<Q: EventQueue>(
    mut engine: Engine<Q>,
    resort_every: Option<f64>,
    warmup: u64,
    collisions: u64,
) -> Result<(f64, Value)> {
    if let Some(per_particle) = resort_every {
        engine.set_resort_interval((per_particle * engine.len() as f64).round() as u64);
    }
    engine.run_collisions(warmup)?;
    let before = *engine.stats();
    let (start, cpu_start) = (Instant::now(), super::cpu_time::thread_seconds());
    engine.run_collisions(collisions)?;
    let seconds = start.elapsed().as_secs_f64();
    let cpu = super::cpu_time::thread_seconds()
        .zip(cpu_start)
        .map(|(b, a)| b - a);
    let s = engine.stats();
    let done = s.collisions() - before.collisions();
    let events = s.events - before.events;
    Ok((
        done as f64 / seconds,
        json!({
            "particles": engine.len(),
            "collisions": done,
            "events": events,
            "seconds": seconds,
            "cpu_seconds": cpu,
            "collisions_per_cpu_second": cpu.map(|c| done as f64 / c),
            "collisions_per_second": done as f64 / seconds,
            "events_per_second": events as f64 / seconds,
            "exceptions_rotation": s.exception_rotation - before.exception_rotation,
            "exceptions_interference": s.exception_interference - before.exception_interference,
            "mor_fallbacks": s.mor_fallbacks - before.mor_fallbacks,
            "crossings": s.crossings - before.crossings,
            "epochs": s.epochs - before.epochs,
            "stale": s.stale - before.stale,
            "velocity_events": s.velocity_events - before.velocity_events,
            "resorts": s.resorts - before.resorts,
        }),
    ))
}

/// The engine's queue and broad phase.
#[derive(Clone, Copy, Debug)]
struct Build {
    queue: QueueArg,
    broad_phase: BroadPhaseKind,
    resort_every: Option<f64>,
}

impl Build {
    /// Builds the engine and times `collisions` after `warmup`.
    fn time(
        self,
        (particles, domain): (Particles, Domain),
        physics: Physics,
        warmup: u64,
        collisions: u64,
    ) -> Result<(f64, Value)> {
        match self.queue {
            QueueArg::Heap => time_run(
                Engine::<IndexedHeap>::with_broad_phase(
                    &particles,
                    &domain,
                    physics,
                    self.broad_phase,
                )?,
                self.resort_every,
                warmup,
                collisions,
            ),
            QueueArg::Calendar => time_run(
                Engine::<CalendarQueue>::with_broad_phase(
                    &particles,
                    &domain,
                    physics,
                    self.broad_phase,
                )?,
                self.resort_every,
                warmup,
                collisions,
            ),
        }
    }
}

fn hard_spheres(cells: usize, eta: f64, per_particle: f64, build: Build) -> Result<(f64, Value)> {
    // σ = 1, m = 1, kT = 1: rms speed √3.
    let setup = fcc_gas(cells, eta, 0.5, 1.0, 3f64.sqrt(), 1)?;
    let n = setup.0.len() as f64;
    let physics = Physics::hard_spheres(1.0);
    let count = (per_particle * n * 0.5) as u64;
    build.time(setup, physics, count, count)
}

/// FCC cells per side of the eMD* gas (N = 4·14³ = 10 976) and its packing fraction.
const EMDSTAR_CELLS: usize = 14;
const EMDSTAR_ETA: f64 = 0.01;
/// FCC cells per side of the scaling runs: N = 864 … 1 000 188.
const SCALING_CELLS: [usize; 5] = [6, 10, 22, 46, 63];

/// The largest --hs-cells: 4·500³ = 5·10⁸ spheres, within the 2²⁹ the epoch grid files.
const MAX_HS_CELLS: usize = 500;
/// Collisions each scaling run times at least: a few milliseconds at small N varied by
/// half from run to run.
const SCALING_MIN_COLLISIONS: f64 = 2e5;

/// Collisions per particle of a scaling run on `cells` FCC cells per side: the asked
/// number up to 10, more where that would time fewer than [`SCALING_MIN_COLLISIONS`].
fn scaling_per_particle(per_particle: f64, cells: usize) -> f64 {
    let n = 4.0 * (cells as f64).powi(3);
    per_particle
        .min(10.0)
        .max(SCALING_MIN_COLLISIONS / (0.5 * n))
}

/// Müller & Pöschel 2013, Sec. VI B 6: elastic Hertz spheres, R = 0.1 m,
/// ρ = 1140 kg/m³, ν = 0.4, thermal speed ≈ 2 m/s; here Y = 1 GPa and η = 0.01.
fn emdstar_gas(
    cells: usize,
    per_particle: f64,
    mor: Box<dyn MorSource>,
    build: Build,
) -> Result<(f64, Value)> {
    let sphere = Sphere::from_density(0.1, 1140.0)?;
    let eta = EMDSTAR_ETA;
    // kT = (4/3)·m: rms speed 2 m/s.
    let setup = fcc_gas(cells, eta, 0.1, sphere.mass, 2.0, 1)?;
    let n = setup.0.len() as f64;
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.4, 0.0)?);
    let physics = Physics::EmdStar {
        interactions: Interactions::of_spheres(&law, Tangential::None, &[sphere])?,
        mor,
        interference: Interference::HitOnly,
    };
    let count = (per_particle * n * 0.5) as u64;
    build.time(setup, physics, count / 4, count)
}

/// The best (highest rate) of `rounds` runs, with every round's rate under "rounds";
/// `bar` counts the runs and names the case.
fn best_of(
    rounds: usize,
    bar: &ProgressBar,
    case: String,
    mut run: impl FnMut() -> Result<(f64, Value)>,
) -> Result<(f64, Value)> {
    bar.set_message(case);
    let mut best: Option<(f64, Value)> = None;
    let mut rates = vec![];
    for _ in 0..rounds {
        let (rate, v) = run()?;
        bar.inc(1);
        rates.push(rate);
        if best.as_ref().is_none_or(|b| rate > b.0) {
            best = Some((rate, v));
        }
    }
    let (rate, mut v) = best.expect("at least one round");
    v["rounds"] = json!(rates);
    Ok((rate, v))
}

/// How many timed runs `a` asks for.
fn runs_planned(a: &BenchEdmdArgs) -> u64 {
    let (hs, star) = (!a.emdstar_only as usize, !a.hard_spheres_only as usize);
    let cases = hs + star + hs * star + usize::from(a.scaling) * SCALING_CELLS.len() * (hs + star);
    (cases * a.rounds) as u64
}

/// Prints a line of the report without tearing the progress bar.
fn say(bar: &ProgressBar, line: String) {
    bar.suspend(|| println!("{line}"));
}

fn cpu_rate(v: &Value) -> String {
    match v["collisions_per_cpu_second"].as_f64() {
        Some(r) => format!(", {r:.3e} per CPU second"),
        None => String::new(),
    }
}

pub fn run(a: &BenchEdmdArgs) -> Result<()> {
    if a.per_particle.is_nan() || a.per_particle <= 0.0 {
        bail!("--per-particle must be positive");
    }
    if !(1..=MAX_HS_CELLS).contains(&a.hs_cells) {
        bail!(
            "--hs-cells must be 1 to {MAX_HS_CELLS} (N = 4·cells³ up to {} spheres)",
            4 * MAX_HS_CELLS.pow(3)
        );
    }
    if a.rounds == 0 {
        bail!("--rounds must be at least 1");
    }
    let build = Build {
        queue: a.queue,
        broad_phase: a.broad_phase.into(),
        resort_every: a.resort_every,
    };
    if a.resort_every.is_some_and(|r| r.is_nan() || r < 0.0) {
        bail!("--resort-every must be ≥ 0 events per particle");
    }
    // On stderr, drawn only on a terminal; it moves between runs, never within one.
    let bar = progress_bar(
        false,
        runs_planned(a),
        "{prefix} {bar:30} {pos}/{len} runs {elapsed} {msg}",
    );
    bar.set_prefix("bench edmd");
    let (hs_rate, hs) = if a.emdstar_only {
        (f64::NAN, Value::Null)
    } else {
        let case = format!(
            "hard spheres, N = {}",
            a.hs_cells.saturating_pow(3).saturating_mul(4)
        );
        best_of(a.rounds, &bar, case, || {
            hard_spheres(a.hs_cells, a.hs_eta, a.per_particle, build)
        })?
    };
    if !a.json && !a.emdstar_only {
        say(
            &bar,
            format!(
                "elastic hard spheres, N = {}, η = {}: {hs_rate:.3e} collisions/s{}",
                hs["particles"],
                a.hs_eta,
                cpu_rate(&hs)
            ),
        );
    }
    let mut out = json!({ "hard_spheres": hs });
    let mor_source = || -> Result<Box<dyn MorSource>> {
        Ok(match a.mor {
            MorArg::Exact => Box::new(ExactMor),
            MorArg::Table => Box::new(TableMorSource::new(
                emdstar_table::default_table(Model::Hertz)?,
                true,
            )),
        })
    };
    if !a.hard_spheres_only {
        let case = format!("eMD* gas, N = {}", 4 * EMDSTAR_CELLS.pow(3));
        let (rate, v) = best_of(a.rounds, &bar, case, || {
            emdstar_gas(EMDSTAR_CELLS, a.per_particle, mor_source()?, build)
        })?;
        // The same gas as hard spheres (same N, η and FCC start; units do not matter):
        // what eMD*'s three events and MoR lookup cost over a plain collision.
        let (same_rate, same) = if a.emdstar_only {
            (f64::NAN, Value::Null)
        } else {
            let case = "hard spheres, the eMD* gas".to_string();
            best_of(a.rounds, &bar, case, || {
                hard_spheres(EMDSTAR_CELLS, EMDSTAR_ETA, a.per_particle, build)
            })?
        };
        if !a.json {
            say(
                &bar,
                format!(
                    "eMD* Hertz gas, N = {}, η = {EMDSTAR_ETA}, Y = 1 GPa ({} MoR): {rate:.3e} collisions/s{}",
                    v["particles"],
                    format!("{:?}", a.mor).to_lowercase(),
                    cpu_rate(&v),
                ),
            );
            if !a.emdstar_only {
                say(
                    &bar,
                    format!(
                        "  hard spheres, same gas (N = {}, η = {EMDSTAR_ETA}): {same_rate:.3e} collisions/s{}",
                        same["particles"],
                        cpu_rate(&same)
                    ),
                );
                say(
                    &bar,
                    format!(
                        "  eMD* is {:.2}× slower than hard spheres in the same gas, {:.2}× slower \
                         than hard spheres at η = {}",
                        same_rate / rate,
                        hs_rate / rate,
                        a.hs_eta
                    ),
                );
            }
        }
        out["emdstar_hertz"] = v;
        out["hard_spheres_same_gas"] = same;
        out["emdstar_slowdown"] = json!(hs_rate / rate);
        out["emdstar_slowdown_same_gas"] = json!(same_rate / rate);
    }
    if a.scaling {
        let mut rows = vec![];
        let mut emdstar_rows = vec![];
        for cells in SCALING_CELLS {
            let mut line = format!("  N = {:>8}:", 4 * cells.pow(3));
            if !a.emdstar_only {
                let case = format!("scaling: hard spheres, N = {}", 4 * cells.pow(3));
                let (rate, v) = best_of(a.rounds, &bar, case, || {
                    hard_spheres(
                        cells,
                        a.hs_eta,
                        scaling_per_particle(a.per_particle, cells),
                        build,
                    )
                })?;
                line += &format!(
                    " hard spheres (η = {}) {rate:.3e} collisions/s{}",
                    a.hs_eta,
                    cpu_rate(&v)
                );
                rows.push(v);
            }
            if a.hard_spheres_only {
                if !a.json {
                    say(&bar, line);
                }
                continue;
            }
            let case = format!("scaling: eMD* gas, N = {}", 4 * cells.pow(3));
            let (star, w) = best_of(a.rounds, &bar, case, || {
                let per_particle = scaling_per_particle(a.per_particle, cells);
                emdstar_gas(cells, per_particle, mor_source()?, build)
            })?;
            if !a.json {
                let sep = if a.emdstar_only { "" } else { ";" };
                say(
                    &bar,
                    format!(
                        "{line}{sep} eMD* gas (η = {EMDSTAR_ETA}) {star:.3e} collisions/s{}",
                        cpu_rate(&w)
                    ),
                );
            }
            emdstar_rows.push(w);
        }
        if let Some(path) = &a.plot {
            scaling_plot(path, a.hs_eta, &rows, &emdstar_rows)?;
            if !a.json {
                say(&bar, format!("wrote {}", path.display()));
            }
        }
        out["scaling"] = json!(rows);
        out["scaling_emdstar"] = json!(emdstar_rows);
    }
    bar.finish_and_clear();
    if a.json {
        println!("{out}");
    }
    Ok(())
}

/// Collisions per second against N, log-log, one line per engine.
fn scaling_plot(path: &std::path::Path, hs_eta: f64, hs: &[Value], star: &[Value]) -> Result<()> {
    use emdstar_plot::{Axis, PALETTE, Panel, Series, Style, write_png};
    let points = |rows: &[Value]| -> Vec<(f64, f64)> {
        rows.iter()
            .filter_map(|r| {
                // The thread's CPU time where the platform gives it: a shared machine
                // inflates wall times.
                let rate = r["collisions_per_cpu_second"].as_f64();
                Some((
                    r["particles"].as_f64()?,
                    rate.or(r["collisions_per_second"].as_f64())?,
                ))
            })
            .collect()
    };
    let mut p = Panel::new(
        "Event-driven engine: collisions per second on one core",
        Axis::log("particles N"),
        Axis::log("collisions per CPU second"),
    );
    if !hs.is_empty() {
        p.series.push(Series::new(
            format!("elastic hard spheres, η = {hs_eta}"),
            points(hs),
            PALETTE[3],
            Style::LinePoints(5),
        ));
    }
    if !star.is_empty() {
        p.series.push(Series::new(
            format!("eMD* Hertz gas, η = {EMDSTAR_ETA}, Y = 1 GPa"),
            points(star),
            PALETTE[1],
            Style::LinePoints(5),
        ));
    }
    write_png(path, (900, 600), 1, 1, &[p]).map_err(|e| anyhow::anyhow!(e))
}
