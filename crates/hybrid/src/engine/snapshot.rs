//! Saving the hybrid's whole state and putting it back (checkpoints).

use super::Hybrid;
use crate::options::HybridError;

impl Hybrid {
    /// The whole state (everything but the pair physics and the collision rules,
    /// which the engine was built with), in the checkpoint encoding.
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
        // Wall motion is config, not state: the saved walls take this engine's.
        let walls = saved.system.domain.walls.iter_mut();
        for (wall, built) in walls.zip(&self.system.domain.walls) {
            wall.vibration = built.vibration;
        }
        saved.ed.take_wall_motion(&self.ed);
        let same_system = saved.system.species == self.system.species
            && saved.system.domain == self.system.domain
            && saved.modes.len() == self.modes.len();
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
        saved.check_restored(self).map_err(|why| {
            HybridError::Invalid(format!(
                "the checkpoint's hybrid state does not fit this config ({why}); resume with \
                 the config and the version of emdstar that wrote it"
            ))
        })?;
        std::mem::swap(
            &mut saved.system.interactions,
            &mut self.system.interactions,
        );
        saved.ed.swap_rules(&mut self.ed);
        saved.td.restored(&saved.system.particles);
        saved.td.set_wall_time(saved.time());
        *self = saved;
        Ok(())
    }

    /// Errors unless `self`, decoded from a checkpoint, fits `built`, the engine of
    /// the same config: the same bodies, one entry per particle in every array, indices
    /// in range, a whole driver and event core.
    fn check_restored(&self, built: &Self) -> Result<(), String> {
        let n = built.modes.len();
        let indices = |v: &[u32]| v.iter().all(|&i| (i as usize) < n);
        let same_bodies = self.system.particles.same_bodies(&built.system.particles);
        let whole = same_bodies
            && self.modes.is_whole(n)
            && self.book.is_whole(n)
            && indices(&self.boundary);
        if !whole {
            return Err("its particles or their records differ".into());
        }
        // Without TD particles the list is not kept (it is rebuilt before a switch to TD).
        self.td.check_restored(&built.td, n, self.upkeep.list)?;
        self.ed.check_restored_members(&built.ed)
    }
}
