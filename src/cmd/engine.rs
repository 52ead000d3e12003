//! What `pair` and `run` share: the engine choice and its options, and building the
//! engine a config and those options describe.

use anyhow::{Context, Result, bail};
use clap::Args;
use emdstar_dem::{ContactEnd, MdOptions, shortest_contact_time};
use emdstar_system::{Config, System, SystemError, Thermo};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};
use std::path::Path;

/// The simulation engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EngineKind {
    /// Force-based DEM (time steps).
    Md,
    /// Classic event-driven MD with the force law's central restitution ε(v_n).
    Emd,
    /// eMD*: event-driven MD with the matrix of restitution (three events per collision).
    EmdStar,
    /// MD where the gas is dense, eMD* where it is dilute (emdstar-hybrid).
    Hybrid,
}

/// Parses `--engine`.
pub fn parse_engine(s: &str) -> Result<EngineKind, String> {
    match s {
        "md" => Ok(EngineKind::Md),
        "emd" => Ok(EngineKind::Emd),
        "emdstar" => Ok(EngineKind::EmdStar),
        "hybrid" => Ok(EngineKind::Hybrid),
        other => Err(format!(
            "unknown engine '{other}': the engines are 'md', 'emd', 'emdstar' and 'hybrid'"
        )),
    }
}

/// Options of the MD engine (they override the config's `[md]` section).
#[derive(Args, Debug, Clone)]
pub struct MdArgs {
    /// Time step in s [default: 1/2000 (pair) or 1/50 (run) of the shortest expected
    /// contact time; steps above 1/10 of it are refused].
    #[arg(long, value_name = "S")]
    pub dt: Option<f64>,
    /// When a contact ends: "force" (F = 0, the default) or "overlap" (ξ = 0, as LAMMPS
    /// without limit_damping; the force may then attract).
    #[arg(long, value_name = "RULE")]
    pub contact_end: Option<String>,
    /// Verlet-list skin in m [default: the largest radius].
    #[arg(long, value_name = "M")]
    pub skin: Option<f64>,
}

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
    if let Some(reference) = system.species.first()
        && let Some(note) = config
            .material
            .restitution_note(&system.material, reference)
    {
        eprintln!("{note}");
    }
    Ok((config, system))
}

/// The MD options (the command line over the config's `[md]`). Without an explicit dt
/// the step is `default_fraction` × the shortest contact time expected up to the
/// config's `t_end`, shortened so that the config's `t_end` is a whole number of steps
/// (a run stopped earlier or resumed later keeps this step).
pub fn md_options(
    config: &Config,
    system: &System,
    args: &MdArgs,
    default_fraction: f64,
) -> Result<MdOptions> {
    let section = config.md.clone().unwrap_or_default();
    let contact_end: ContactEnd = match args.contact_end.as_ref().or(section.contact_end.as_ref()) {
        Some(s) => s.parse().map_err(anyhow::Error::msg)?,
        None => ContactEnd::ForceZero,
    };
    let t_end = config.t_end;
    let dt = match args.dt.or(section.dt) {
        Some(dt) => {
            if !(dt.is_finite() && dt > 0.0) {
                bail!("dt = {dt} must be a finite number greater than zero");
            }
            dt
        }
        None => match shortest_contact_time(system, t_end)? {
            Some(tc) => default_fraction * tc,
            None => t_end,
        },
    };
    let steps = (t_end / dt).ceil().max(1.0);
    if steps > 1e13 {
        bail!("t_end / dt = {steps:e} steps is too many; raise dt or lower t_end");
    }
    Ok(MdOptions {
        dt: t_end / steps,
        contact_end,
        skin: args.skin.or(section.skin),
    })
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
