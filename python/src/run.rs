//! Whole runs: a config simulated by any engine, sampled at evenly spaced times.

use emdstar_engines::{AnyEngine, EngineKind, EngineOptions, EventChoice, MorChoice};
use emdstar_system::Config;
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// `emdstar run`'s default time step: 1/50 of the shortest expected contact time.
const DT_FRACTION: f64 = 1.0 / 50.0;

fn error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn mor_choice(name: &str) -> PyResult<MorChoice> {
    match name {
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

/// Advances `engine` to `time`; a Ctrl-C on the way stops it at its next event or step
/// and raises `KeyboardInterrupt` (unless a Python handler of SIGINT chooses otherwise:
/// then the run goes on).
fn advance(
    py: Python<'_>,
    engine: &mut AnyEngine,
    drive: Option<&emdstar_system::Drive>,
    time: f64,
) -> PyResult<()> {
    loop {
        emdstar_engines::drive::advance(engine.sim_mut(), drive, time)
            .map_err(|e| error(format!("at t = {time:e} s: {e}")))?;
        if !emdstar_system::stop::is_requested() {
            return Ok(());
        }
        emdstar_system::stop::clear();
        py.check_signals()?;
    }
}

/// Runs the config `toml` (its text) with `engine` to `t_end` (the config's if None)
/// and samples `frames` evenly spaced times from 0 to `t_end`. Returns flat arrays:
/// t, id, radius, position and velocity (frames × n × 3), the thermo columns, and the
/// counted exact MoR fallbacks.
#[pyfunction]
#[pyo3(signature = (toml, engine, t_end, frames, mor))]
pub fn run_config<'py>(
    py: Python<'py>,
    toml: &str,
    engine: &str,
    t_end: Option<f64>,
    frames: usize,
    mor: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let kind: EngineKind = engine.parse().map_err(error)?;
    let mut config = Config::from_toml(toml).map_err(|e| error(format!("config: {e}")))?;
    if let Some(t) = t_end {
        if !(t.is_finite() && t > 0.0) {
            return Err(error(format!(
                "t_end = {t} must be a finite number greater than zero"
            )));
        }
        config.t_end = t;
    }
    if frames < 2 {
        return Err(error(format!(
            "frames = {frames}: at least 2 (the start and t_end)"
        )));
    }
    let _stop = StopOnInterrupt::install();
    py.check_signals()?;
    let system = config.build().map_err(|e| error(format!("config: {e}")))?;
    py.check_signals()?;
    let options = EngineOptions {
        engine: kind,
        edmd: EventChoice {
            mor: mor_choice(mor)?,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut engine = AnyEngine::build(&options, &config, system, DT_FRACTION)
        .map_err(|e| error(format!("{e:#}")))?;
    py.check_signals()?;
    // The config's thermostat, if any.
    let drive = (config.driving.as_ref().map(|d| d.drive()))
        .transpose()
        .map_err(|e| error(format!("{e}")))?;

    let first = engine.sim().particles();
    let n = first.len();
    let mut t = Vec::with_capacity(frames);
    let mut position: Vec<f64> = Vec::with_capacity(frames * n * 3);
    let mut velocity: Vec<f64> = Vec::with_capacity(frames * n * 3);
    let (mut kinetic, mut potential, mut temperature) = (vec![], vec![], vec![]);
    let (mut momentum, mut contacts) = (vec![], vec![]);
    for k in 0..frames {
        let time = config.t_end * k as f64 / (frames - 1) as f64;
        if k > 0 {
            advance(py, &mut engine, drive.as_ref(), time)?;
        }
        let sim = engine.sim();
        let p = sim.particles();
        let th = sim.thermo();
        t.push(sim.time());
        position.extend(p.position.iter().flatten());
        velocity.extend(p.velocity.iter().flatten());
        kinetic.push(th.kinetic_energy);
        potential.push(th.potential_energy);
        temperature.push(th.granular_temperature);
        momentum.extend(th.momentum);
        contacts.push(th.contacts as u64);
    }
    let out = PyDict::new(py);
    out.set_item("engine", kind.name())?;
    out.set_item("t", t.into_pyarray(py))?;
    out.set_item("id", first.id.clone().into_pyarray(py))?;
    out.set_item("radius", first.radius.clone().into_pyarray(py))?;
    out.set_item("mass", first.mass.clone().into_pyarray(py))?;
    out.set_item("position", position.into_pyarray(py))?;
    out.set_item("velocity", velocity.into_pyarray(py))?;
    out.set_item("kinetic_energy", kinetic.into_pyarray(py))?;
    out.set_item("potential_energy", potential.into_pyarray(py))?;
    out.set_item("granular_temperature", temperature.into_pyarray(py))?;
    out.set_item("momentum", momentum.into_pyarray(py))?;
    out.set_item("contacts", contacts.into_pyarray(py))?;
    out.set_item("mor_fallbacks", engine.mor_fallbacks())?;
    Ok(out)
}
