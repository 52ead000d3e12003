//! The driver in a checkpoint: saved whole but for its scratch and what its particles
//! give, checked against the driver the same config builds.

use super::Verlet;
use super::slots::Buffers;
use emdstar_system::Particles;

impl Verlet {
    /// Errors unless `self`, decoded from a checkpoint, fits `built`, the driver the
    /// same config and options build, for `n` particles: the same options and skin, one
    /// entry per particle in every array, a whole list (unless `list_in_use` is false:
    /// a driver without members, whose list is built before it is used) and springs,
    /// friction as `built`'s.
    pub fn check_restored(&self, built: &Self, n: usize, list_in_use: bool) -> Result<(), String> {
        if self.opts != built.opts || self.skin.to_bits() != built.skin.to_bits() {
            return Err(format!(
                "it was written with dt = {:e} s, contact end {:?} and skin {:e} m, this run \
                 has dt = {:e} s, {:?} and {:e} m; resume with the --dt, --contact-end and \
                 --skin of the run that wrote it",
                self.opts.dt,
                self.opts.contact_end,
                self.skin,
                built.opts.dt,
                built.opts.contact_end,
                built.skin
            ));
        }
        let rotation = match (&self.rotation, &built.rotation) {
            (None, None) => true,
            (Some(r), Some(_)) => r.angular_acc.len() == n && r.springs.are_whole(n),
            _ => {
                return Err(
                    "it was written with another friction than this config's: resume with the \
                     config the checkpoint was written from"
                        .into(),
                );
            }
        };
        let whole = self.contact_acc.len() == n
            && self.touched.iter().all(|&i| (i as usize) < n)
            && rotation;
        if list_in_use {
            self.list.check_restored(n)?;
        }
        whole
            .then_some(())
            .ok_or_else(|| "its particles differ".into())
    }

    /// Completes a decoded driver of `particles`: what they give and the scratch.
    pub fn restored(&mut self, particles: &Particles) {
        self.inv_mass = particles.mass.iter().map(|m| 1.0 / m).collect();
        self.buffers = Buffers::for_particles(particles.len());
        if let Some(rot) = self.rotation.as_mut() {
            rot.reset_inertia(particles);
        }
    }
}
