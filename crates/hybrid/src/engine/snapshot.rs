//! Saving the hybrid's whole state and putting it back (checkpoints).

use super::Hybrid;
use crate::options::HybridError;
use emdstar_edmd::Physics;

/// The physics of a state just read from a checkpoint, until the engine's own is put
/// back.
pub(super) fn unset_physics() -> Physics {
    Physics::HardSpheres { restitution: 1.0 }
}

impl Hybrid {
    /// The whole state (everything but the pair physics and the MoR source, which the
    /// engine was built with), in the checkpoint encoding.
    pub fn save_state(&self) -> Vec<u8> {
        postcard::to_allocvec(self).expect("a hybrid state serialises")
    }

    /// Replaces the state by one [`Hybrid::save_state`] gave; this engine must have been
    /// built from the same config and options.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), HybridError> {
        let mut saved: Self = postcard::from_bytes(bytes).map_err(|e| {
            HybridError::Invalid(format!(
                "the checkpoint's hybrid state cannot be read ({e}); it was written by another \
                 version or another engine"
            ))
        })?;
        let same_system = saved.system.species == self.system.species
            && saved.system.material == self.system.material
            && saved.system.friction == self.system.friction
            && saved.system.domain == self.system.domain
            && saved.mode.len() == self.mode.len();
        if !same_system {
            return Err(HybridError::Invalid(
                "the checkpoint holds another system than this config describes; resume with \
                 the config it was written from"
                    .into(),
            ));
        }
        if saved.opts != self.opts {
            return Err(HybridError::Invalid(format!(
                "the checkpoint was written with the hybrid options {:?}, this run has {:?}; \
                 resume with the --dt, --skin and hybrid options of the run that wrote it",
                saved.opts, self.opts
            )));
        }
        std::mem::swap(&mut saved.materials, &mut self.materials);
        std::mem::swap(&mut saved.physics, &mut self.physics);
        std::mem::swap(&mut saved.ed_friction, &mut self.ed_friction);
        *self = saved;
        Ok(())
    }
}
