//! Saving the hybrid's whole state and putting it back (checkpoints).

use super::Hybrid;
use crate::options::HybridError;
use emdstar_edmd::EventQueue;
use emdstar_edmd::collision::NONE;

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
        std::mem::swap(&mut saved.rules, &mut self.rules);
        *self = saved;
        Ok(())
    }
}

impl Hybrid {
    /// Errors unless `self`, decoded from a checkpoint, fits `built`, the engine of
    /// the same config: the same bodies, one entry per particle in every array, indices
    /// and partners in range, whole lists, queue, cells and springs.
    fn check_restored(&self, built: &Self) -> Result<(), String> {
        let n = built.mode.len();
        let parties = n + built.system.domain.walls.len();
        let party = |j: u32| j == NONE || (j as usize) < parties;
        let indices = |v: &[u32]| v.iter().all(|&i| (i as usize) < n);
        let lengths = [
            self.inv_mass.len(),
            self.contact_acc.len(),
            self.new_acc.len(),
            self.ed.len(),
            self.jump.len(),
        ];
        let rotation = match (&self.rotation, &built.rotation) {
            (None, None) => true,
            (Some(r), Some(_)) => {
                r.inv_inertia.len() == n && r.angular_acc.len() == n && r.springs.are_whole(n)
            }
            _ => false,
        };
        let whole = self.system.particles.same_bodies(&built.system.particles)
            && lengths == [n; 5]
            && [&self.td, &self.converted, &self.boundary, &self.deferred]
                .into_iter()
                .all(|v| indices(v))
            && self
                .ed
                .iter()
                .all(|r| party(r.partner) && party(r.coll_partner))
            && rotation;
        if !whole {
            return Err("its particles or their records differ".into());
        }
        self.heap.check(n)?;
        self.list.check_restored(n)?;
        match &self.grid {
            Some(grid) => grid.check_restored(n, false),
            None => Ok(()),
        }
    }
}
