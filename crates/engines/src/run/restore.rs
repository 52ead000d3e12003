//! Resuming a run: the checkpoint read, checked against the engine and the config,
//! and restored.

use crate::AnyEngine;
use anyhow::{Result, anyhow, bail};
use emdstar_system::{Checkpoint, Config};
use std::path::Path;

/// Restores `engine` from the checkpoint at `path`, refusing one of another engine,
/// options or config; returns its time.
pub fn restore(engine: &mut AnyEngine, path: &Path, config: &Config) -> Result<f64> {
    let ckpt = Checkpoint::read(path)?;
    let sim = engine.sim();
    if ckpt.engine != sim.engine() {
        bail!(
            "{} was written by the {} engine; resume it with --engine {} (this run uses {})",
            path.display(),
            ckpt.engine,
            ckpt.engine,
            sim.engine()
        );
    }
    if ckpt.options != engine.options_tag() {
        bail!(
            "{} was written with the MoR source '{}', this run uses '{}'; give the same --mor \
             and --table as the run that wrote it",
            path.display(),
            ckpt.options,
            engine.options_tag()
        );
    }
    if ckpt.config_digest != config.digest() {
        bail!(
            "{} belongs to another system than this config describes (the particles, \
             material, box, walls, gravity or [md] differ); resume it with the config it was \
             written from (only t_end and [output] may change)",
            path.display()
        );
    }
    engine
        .sim_mut()
        .restore_state(&ckpt.state)
        .map_err(|e| anyhow!("restoring {}: {e}", path.display()))?;
    Ok(ckpt.time)
}
