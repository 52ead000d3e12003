//! Saving an engine's whole state and putting it back (checkpoints).

use super::EventEngine;
use crate::broad_phase::BroadPhase;
use crate::error::{EngineError, Result};
use crate::queue::EventQueue;
use serde::Serialize;
use serde::de::DeserializeOwned;

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// Gives a state decoded from a checkpoint the wall motion of `built`, the engine
    /// of its config: wall motion is config, not state, and checkpoints do not hold it.
    pub fn take_wall_motion(&mut self, built: &Self) {
        let walls = self.state.domain.walls.iter_mut();
        for (wall, built) in walls.zip(&built.state.domain.walls) {
            wall.vibration = built.vibration;
        }
    }
}

impl<B, Q> EventEngine<B, Q>
where
    B: BroadPhase + Serialize + DeserializeOwned,
    Q: EventQueue + Serialize + DeserializeOwned,
{
    /// The whole state (everything but the rules, which the engine was built with),
    /// in the checkpoint encoding.
    pub fn save_state(&self) -> Vec<u8> {
        postcard::to_allocvec(self).expect("an engine state serialises")
    }

    /// Replaces the state by one [`EventEngine::save_state`] gave, keeping this engine's
    /// rules (the same config and options must have built both).
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<()> {
        let mut saved: Self = postcard::from_bytes(bytes).map_err(|e| {
            EngineError::Invalid(format!(
                "the checkpoint's event-engine state cannot be read ({e}); it was written by \
                 another version or another engine"
            ))
        })?;
        if saved.len() != self.len() {
            return Err(EngineError::Invalid(format!(
                "the checkpoint holds {} particles, the config {}: resume with the config \
                 the checkpoint was written from",
                saved.len(),
                self.len()
            )));
        }
        saved.take_wall_motion(self);
        // The shear rate is the config's, not saved.
        saved.state.domain.shear_rate = self.state.domain.shear_rate;
        saved
            .state
            .check_restored(&self.state, self.len() + B::OWN_EVENTS)
            .and_then(|()| saved.broad.check_restored(&self.broad, self.len()))
            .map_err(|why| {
                EngineError::Invalid(format!(
                    "the checkpoint's event-engine state does not fit this config ({why}); \
                     resume with the config and the version of emdstar that wrote it"
                ))
            })?;
        std::mem::swap(&mut saved.rules, &mut self.rules);
        *self = saved;
        Ok(())
    }
}
