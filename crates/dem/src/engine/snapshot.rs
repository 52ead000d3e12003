//! Saving MD's whole state and putting it back (checkpoints).

use super::Md;
use crate::driver::Verlet;
use emdstar_system::Particles;
use serde::{Deserialize, Serialize};

/// What MD keeps from step to step, besides what its config gives, as saved.
#[derive(Serialize)]
struct SavedRef<'a> {
    particles: &'a Particles,
    steps: u64,
    t_start: f64,
    verlet: &'a Verlet,
}

/// The same, as read back.
#[derive(Deserialize)]
struct Saved {
    particles: Particles,
    steps: u64,
    t_start: f64,
    verlet: Verlet,
}

impl Md {
    /// The whole state in the checkpoint encoding.
    pub fn save_state(&self) -> Vec<u8> {
        let saved = SavedRef {
            particles: &self.system.particles,
            steps: self.steps,
            t_start: self.t_start,
            verlet: &self.verlet,
        };
        postcard::to_allocvec(&saved).expect("an MD state serialises")
    }

    /// Replaces the state by one [`Md::save_state`] gave; this engine must have been
    /// built from the same config and options.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let saved: Saved = postcard::from_bytes(bytes).map_err(|e| {
            format!(
                "the checkpoint's MD state cannot be read ({e}); it was written by another \
                 version or another engine"
            )
        })?;
        let n = self.system.particles.len();
        if saved.particles.len() != n {
            return Err(format!(
                "the checkpoint holds {} particles, the config {n}: resume with the config \
                 the checkpoint was written from",
                saved.particles.len(),
            ));
        }
        let bodies = saved
            .particles
            .same_bodies(&self.system.particles)
            .then_some(())
            .ok_or_else(|| "its particles differ".to_string());
        bodies
            .and_then(|()| saved.verlet.check_restored(&self.verlet, n, true))
            .map_err(|why| {
                format!(
                    "the checkpoint's MD state does not fit this config ({why}); resume with \
                     the config and the version of emdstar that wrote it"
                )
            })?;
        let Saved {
            particles,
            steps,
            t_start,
            mut verlet,
        } = saved;
        verlet.restored(&particles);
        self.system.particles = particles;
        self.verlet = verlet;
        self.steps = steps;
        self.t_start = t_start;
        Ok(())
    }
}
