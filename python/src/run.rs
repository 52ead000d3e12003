//! Whole runs through the engines crate's run loop (`emdstar_engines::run`), the one of
//! `emdstar run`: its outputs (log, trajectory, checkpoints), resumption and clean stops,
//! plus two records kept in memory (frames and the thermo log) for the Python caller.

use emdstar_engines::run::{Observer, Run, RunFiles};
use emdstar_engines::{AnyEngine, EngineKind, EngineOptions, EventChoice, MdChoice, MorChoice};
use emdstar_system::Config;
use numpy::IntoPyArray;
use pyo3::exceptions::{PyKeyboardInterrupt, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// `emdstar run`'s default time step: 1/50 of the shortest expected contact time.
const DT_FRACTION: f64 = 1.0 / 50.0;

fn error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn mor_choice(name: &str) -> PyResult<MorChoice> {
    match name.to_ascii_lowercase().as_str() {
        "table-or-exact" => Ok(MorChoice::TableOrExact),
        "table" => Ok(MorChoice::Table),
        "exact" => Ok(MorChoice::Exact),
        other => Err(PyValueError::new_err(format!(
            "unknown mor '{other}': expected 'table-or-exact' (the default), 'table' or 'exact'"
        ))),
    }
}

/// While it lives, SIGINT (Ctrl-C) also raises the stop request that every engine reads
/// at each event or step; Python's own handler still runs (the registration chains to
/// it), so that `check_signals` then raises `KeyboardInterrupt`.
struct StopOnInterrupt(Option<signal_hook::SigId>);

impl StopOnInterrupt {
    fn install() -> Self {
        emdstar_system::stop::clear();
        #[cfg(unix)]
        {
            let sigint = signal_hook::consts::SIGINT;
            // SAFETY: the action is one atomic store, which is async-signal-safe.
            let id = unsafe {
                signal_hook::low_level::register(sigint, move || {
                    emdstar_system::stop::request(sigint)
                })
            };
            Self(id.ok())
        }
        #[cfg(not(unix))]
        Self(None)
    }
}

impl Drop for StopOnInterrupt {
    fn drop(&mut self) {
        if let Some(id) = self.0.take() {
            signal_hook::low_level::unregister(id);
        }
        emdstar_system::stop::clear();
    }
}

/// Hands the fraction done to a Python callable at most ten times a second (taking
/// the interpreter's lock for the call: the run goes on without it).
struct Progress {
    callback: Option<Py<PyAny>>,
    last: Instant,
    failed: Option<PyErr>,
}

impl Progress {
    fn call(&mut self, fraction: f64) {
        if let Some(cb) = &self.callback
            && let Err(e) = Python::attach(|py| cb.bind(py).call1((fraction,)).map(drop))
        {
            self.failed = Some(e);
            emdstar_system::stop::request(0);
        }
    }
}

impl Observer for Progress {
    fn progress(&mut self, _engine: &AnyEngine, fraction: f64) {
        if self.last.elapsed().as_secs_f64() < 0.1 || self.failed.is_some() {
            return;
        }
        self.last = Instant::now();
        self.call(fraction);
    }

    fn note(&mut self, message: &str) {
        eprintln!("note: {message}");
    }
}

/// The config: a file (read relative to its directory), TOML text or JSON text (a
/// Python dict), exactly one of them.
fn config_of(path: Option<PathBuf>, toml: Option<&str>, json: Option<&str>) -> PyResult<Config> {
    let parsed = match (path, toml, json) {
        (Some(p), None, None) => Config::from_file(&p),
        (None, Some(t), None) => Config::from_toml(t),
        (None, None, Some(j)) => {
            let value: toml::Value = serde_json::from_str(j).map_err(|e| {
                error(format!(
                    "config dict: {e} (TOML has no null: leave such keys out)"
                ))
            })?;
            let text = toml::to_string(&value).map_err(|e| error(format!("config dict: {e}")))?;
            Config::from_toml(&text)
        }
        _ => return Err(error("give the config as one path, TOML text or dict")),
    };
    parsed.map_err(|e| error(e.to_string()))
}

/// Runs a config through the engines crate's run loop and returns the records.
#[pyfunction]
#[pyo3(signature = (path, toml, json, engine, t_end, dt, threads, skin, mor, checkpoint, resume, trajectory, log, frames, progress))]
#[allow(clippy::too_many_arguments)]
pub fn run_config<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    toml: Option<&str>,
    json: Option<&str>,
    engine: &str,
    t_end: Option<f64>,
    dt: Option<f64>,
    threads: Option<usize>,
    skin: Option<f64>,
    mor: &str,
    checkpoint: Option<PathBuf>,
    resume: Option<PathBuf>,
    trajectory: Option<PathBuf>,
    log: Option<PathBuf>,
    frames: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let kind: EngineKind = engine.to_ascii_lowercase().parse().map_err(error)?;
    let config = config_of(path.clone(), toml, json)?;
    if let Some(t) = t_end
        && !(t.is_finite() && t > 0.0)
    {
        return Err(error(format!(
            "t_end = {t} must be a finite number greater than zero"
        )));
    }
    if frames < 2 {
        return Err(error(format!(
            "frames = {frames}: at least 2 (the start and t_end)"
        )));
    }
    let mut pool = rayon::ThreadPoolBuilder::new();
    if let Some(n) = threads {
        if n == 0 {
            return Err(error("threads must be at least 1"));
        }
        pool = pool.num_threads(n);
    }
    let pool = pool.build().map_err(error)?;
    let _stop = StopOnInterrupt::install();
    py.check_signals()?;
    let system = config.build().map_err(|e| error(e.to_string()))?;
    let species = system.species.clone();
    let materials: Vec<String> = (0..species.iter().map(|s| s.material + 1).max().unwrap_or(0))
        .map(|m| system.interactions().material_name(m).to_string())
        .collect();
    let options = EngineOptions {
        engine: kind,
        md: MdChoice {
            dt,
            skin,
            contact_end: None,
        },
        edmd: EventChoice {
            mor: mor_choice(mor)?,
            ..Default::default()
        },
        ..Default::default()
    };
    let engine = AnyEngine::build(&options, &config, system, DT_FRACTION)
        .map_err(|e| error(format!("{e:#}")))?;
    // A stopped run saves its state: to the checkpoint named, else to a scratch file
    // removed afterwards.
    let scratch = std::env::temp_dir().join(format!(
        "emdstar-python-{}-{:p}.ckpt",
        std::process::id(),
        &config
    ));
    let files = RunFiles {
        trajectory,
        log,
        stop_checkpoint: checkpoint.clone().unwrap_or_else(|| scratch.clone()),
        checkpoint: checkpoint.clone(),
    };
    let mut inputs: Vec<(&str, &Path)> = Vec::new();
    if let Some(p) = &path {
        inputs.push(("the config", p.as_path()));
    }
    let outcome = py.detach(|| {
        pool.install(|| -> PyResult<_> {
            let mut run = Run::prepare(engine, &config, &files, &inputs, resume.as_deref(), t_end)
                .map_err(|e| error(format!("{e:#}")))?;
            for note in run.notes() {
                eprintln!("note: {note}");
            }
            let t0 = run.engine().sim().time();
            let frame_rec = run
                .record(
                    (run.t_end() - t0).max(f64::MIN_POSITIVE) / (frames - 1) as f64,
                    true,
                )
                .map_err(error)?;
            let log_interval = config
                .output
                .as_ref()
                .and_then(|o| o.log_interval)
                .unwrap_or(config.t_end / 100.0);
            let log_rec = run.record(log_interval, false).map_err(error)?;
            run.start().map_err(|e| error(format!("{e:#}")))?;
            let mut observer = Progress {
                callback: progress,
                last: Instant::now(),
                failed: None,
            };
            let outcome = run
                .drive(&mut observer)
                .map_err(|e| error(format!("{e:#}")));
            if observer.failed.is_none() && outcome.as_ref().is_ok_and(|o| o.stopped_by.is_none()) {
                observer.call(1.0);
            }
            if let Some(e) = observer.failed {
                return Err(e);
            }
            Ok((run, outcome?, frame_rec, log_rec))
        })
    });
    if checkpoint.is_none() {
        let _ = std::fs::remove_file(&scratch);
    }
    let (run, outcome, frame_rec, log_rec) = outcome?;
    if outcome.stopped_by.is_some() {
        py.check_signals()?;
        return Err(PyKeyboardInterrupt::new_err(match &checkpoint {
            Some(p) => format!(
                "stopped at t = {:e} s; the state is in {} (resume=...)",
                run.engine().sim().time(),
                p.display()
            ),
            None => format!("stopped at t = {:e} s", run.engine().sim().time()),
        }));
    }
    results(
        py,
        &run,
        &outcome,
        (frame_rec, frames),
        log_rec,
        &species,
        &materials,
    )
}

/// The records and counters of a finished run, as a dict of numpy arrays and numbers.
fn results<'py>(
    py: Python<'py>,
    run: &Run,
    outcome: &emdstar_engines::run::Outcome,
    (frame_rec, count): (usize, usize),
    log_rec: usize,
    species: &[emdstar_system::Species],
    materials: &[String],
) -> PyResult<Bound<'py, PyDict>> {
    let engine = run.engine();
    let out = PyDict::new(py);
    let rec = run.recorder(frame_rec);
    // `count` samples: a step engine's ticks fall on whole steps, so the last tick may
    // come just before the end, which is recorded too; that tick is dropped.
    let keep: Vec<usize> = if rec.particles.len() > count {
        (0..count - 1).chain([rec.particles.len() - 1]).collect()
    } else {
        (0..rec.particles.len()).collect()
    };
    let frames: Vec<&emdstar_system::Particles> = keep.iter().map(|&k| &rec.particles[k]).collect();
    let first = frames[0];
    let n = first.len();
    let flat = |f: &dyn Fn(&emdstar_system::Particles) -> &Vec<[f64; 3]>| -> Vec<f64> {
        frames
            .iter()
            .flat_map(|p| f(p).iter().flatten().copied())
            .collect()
    };
    out.set_item("engine", engine.sim().engine())?;
    let times: Vec<f64> = keep.iter().map(|&k| rec.thermo[k].t).collect();
    out.set_item("t", times.into_pyarray(py))?;
    out.set_item("id", first.id.clone().into_pyarray(py))?;
    out.set_item("species", first.species.clone().into_pyarray(py))?;
    let material: Vec<u32> = first
        .species
        .iter()
        .map(|&s| species[s as usize].material)
        .collect();
    out.set_item("material", material.into_pyarray(py))?;
    out.set_item("materials", materials.to_vec())?;
    out.set_item("radius", first.radius.clone().into_pyarray(py))?;
    out.set_item("mass", first.mass.clone().into_pyarray(py))?;
    out.set_item("position", flat(&|p| &p.position).into_pyarray(py))?;
    out.set_item("velocity", flat(&|p| &p.velocity).into_pyarray(py))?;
    out.set_item(
        "angular_velocity",
        flat(&|p| &p.angular_velocity).into_pyarray(py),
    )?;
    let image: Vec<i32> = frames
        .iter()
        .flat_map(|p| p.image.iter().flatten().copied())
        .collect();
    out.set_item("image", image.into_pyarray(py))?;
    out.set_item("n", n)?;
    let log = PyDict::new(py);
    let th = &run.recorder(log_rec).thermo;
    let col = |f: &dyn Fn(&emdstar_system::Thermo) -> f64| th.iter().map(f).collect::<Vec<f64>>();
    log.set_item("t", col(&|t| t.t).into_pyarray(py))?;
    log.set_item(
        "step",
        th.iter()
            .map(|t| t.step)
            .collect::<Vec<u64>>()
            .into_pyarray(py),
    )?;
    log.set_item(
        "kinetic_energy",
        col(&|t| t.kinetic_energy).into_pyarray(py),
    )?;
    log.set_item(
        "potential_energy",
        col(&|t| t.potential_energy).into_pyarray(py),
    )?;
    log.set_item("total_energy", col(&|t| t.total_energy()).into_pyarray(py))?;
    log.set_item(
        "granular_temperature",
        col(&|t| t.granular_temperature).into_pyarray(py),
    )?;
    for (k, name) in ["px", "py", "pz"].iter().enumerate() {
        log.set_item(*name, col(&|t| t.momentum[k]).into_pyarray(py))?;
    }
    log.set_item(
        "contacts",
        th.iter()
            .map(|t| t.contacts as u64)
            .collect::<Vec<u64>>()
            .into_pyarray(py),
    )?;
    log.set_item(
        "rotational_energy",
        col(&|t| t.rotational_energy).into_pyarray(py),
    )?;
    log.set_item(
        "rotational_temperature",
        col(&|t| t.rotational_temperature).into_pyarray(py),
    )?;
    out.set_item("log", log)?;
    let mut summary = serde_json::json!({
        "engine": engine.sim().engine(),
        "particles": n,
        "t": engine.sim().time(),
        "wall_time_s": outcome.wall_seconds,
        "work": outcome.work,
        "resumed_from": run.resumed_at(),
        "checkpoint": run.checkpoint_written(),
        "mor_fallbacks": engine.mor_fallbacks(),
    });
    let extra = match engine {
        AnyEngine::Md(e) => serde_json::json!({
            "steps": e.steps(), "dt": e.options().dt, "skin": e.skin(),
            "neighbour_rebuilds": e.rebuilds(),
        }),
        AnyEngine::Event(e) => serde_json::json!({ "stats": e.stats() }),
        AnyEngine::Hybrid(e) => serde_json::json!({
            "steps": e.steps(), "dt": e.options().dt, "skin": e.skin(), "stats": e.stats(),
        }),
    };
    if let (Some(s), serde_json::Value::Object(e)) = (summary.as_object_mut(), extra) {
        s.extend(e);
    }
    out.set_item("summary_json", summary.to_string())?;
    Ok(out)
}
