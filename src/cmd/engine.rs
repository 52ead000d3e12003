//! What `pair` and `run` share: reading a config, progress bars, the conservation
//! figures of the summary.

use anyhow::{Context, Result};
use emdstar_system::{Config, System, SystemError, Thermo};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};
use std::path::Path;

/// Reads and builds a config, refusing one whose particles would not fit into memory
/// unless `force`.
pub fn load(path: &Path, force: bool) -> Result<(Config, System)> {
    let config = Config::from_file(path).map_err(|e| match e {
        // Names the path already.
        SystemError::Io { .. } => anyhow::Error::new(e),
        e => anyhow::Error::new(e).context(format!("reading {}", path.display())),
    })?;
    super::resources::check_memory(&config, force)
        .with_context(|| format!("in {}", path.display()))?;
    let system = config
        .build()
        .with_context(|| format!("in {}", path.display()))?;
    for note in system.interactions().notes() {
        eprintln!("{note}");
    }
    for warning in system.warnings() {
        eprintln!("warning: {warning}");
    }
    Ok((config, system))
}

/// A progress bar of `len` units drawn with `template` (hidden with --quiet).
pub fn progress_bar(quiet: bool, len: u64, template: &str) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(len)
    };
    bar.set_style(ProgressStyle::with_template(template).expect("valid progress template"));
    bar
}

/// The conservation figures of every `run` summary, as JSON fields: the energy drift
/// relative to |K| + |U| at the start, and the momentum drift absolute and relative to
/// M·√(2K/M), the momentum scale of the thermal motion (0 where a scale is 0).
pub fn drift_fields(first: &Thermo, last: &Thermo, total_mass: f64) -> Value {
    let scale = first.kinetic_energy.abs() + first.potential_energy.abs();
    let p_scale = total_mass * (2.0 * first.kinetic_energy / total_mass).sqrt();
    let dp: Vec<f64> = (0..3)
        .map(|k| last.momentum[k] - first.momentum[k])
        .collect();
    let dp_norm = dp.iter().map(|x| x * x).sum::<f64>().sqrt();
    let relative = |x: f64, scale: f64| if scale > 0.0 { x / scale } else { 0.0 };
    json!({
        "energy_initial": first.total_energy(),
        "energy_final": last.total_energy(),
        "energy_drift": relative(last.total_energy() - first.total_energy(), scale),
        "momentum_drift": dp,
        "momentum_drift_relative": relative(dp_norm, p_scale),
        "granular_temperature_final": last.granular_temperature,
    })
}

/// `summary` with the fields of `extra` (both JSON objects) added.
pub fn with_fields(mut summary: Value, extra: Value) -> Value {
    if let (Some(s), Value::Object(e)) = (summary.as_object_mut(), extra) {
        s.extend(e);
    }
    summary
}
