//! Velocities changed from outside the steps (a thermostat's tick, `[driving]`): both
//! parts brought to the step boundary, the change applied to every particle in config
//! order, and what follows from the velocities made again.

use super::Hybrid;
use crate::options::{HybridError, Mode};
use emdstar_system::VelocityChange;

impl Hybrid {
    /// Changes the velocities now, at a step boundary (see
    /// [`emdstar_system::Simulation::change_velocities`]):
    /// - the TD particles as MD has them at a tick: the pending half kick applied, so
    ///   their velocities are in step with the positions; the step that follows starts
    ///   with a half kick from the forces at the boundary (MD's first step again);
    /// - the ED particles as the event engine has them: pending E^v events run first
    ///   (eMD*'s exception (b), Müller & Pöschel 2013, Sec. VI B 5), each particle
    ///   moved to now, its flight up to now in the kinetic sums;
    /// - `change` gets every velocity and mass in config order, so a thermostat draws
    ///   what it draws on the other engines;
    /// - the ED particles are predicted again, and the speed bounds of the list, the
    ///   mode checks and the guard follow the new velocities.
    ///
    /// The kinetic part of the stress stays exact around the tick: the TD part sums the
    /// drift velocities of its steps, the event core each flight up to its end.
    /// A run with removed particles (an outlet) is refused: a thermostat acts on the
    /// particles of a closed system.
    pub fn change_velocities(
        &mut self,
        change: &mut VelocityChange<'_>,
    ) -> Result<(), HybridError> {
        if self.modes.any(Mode::Removed) {
            return Err(HybridError::Invalid(format!(
                "{} particles left through the outlet: the velocities of a run with an outlet \
                 cannot be changed from outside (a thermostat needs a closed system)",
                self.modes.count(Mode::Removed)
            )));
        }
        let t = self.time();
        self.in_step(t)?;
        let modes = &self.modes;
        self.ed.bring_to_now(|i| modes.of(i) == Mode::Event);
        let p = &mut self.system.particles;
        let n = p.len();
        let (mut v, mut m) = (vec![[0.0; 3]; n], vec![0.0; n]);
        for k in 0..n {
            let id = p.id[k] as usize;
            v[id] = match modes.of(k) {
                Mode::Event => self.ed.motion_at(k, t).1,
                _ => p.velocity[k],
            };
            m[id] = p.mass[k];
        }
        change(&mut v, &m);
        for k in 0..n {
            if modes.of(k) == Mode::Time {
                p.velocity[k] = v[p.id[k] as usize];
            }
        }
        let id = &p.id;
        self.ed
            .set_velocities_now(|i| modes.of(i) == Mode::Event, |i| v[id[i] as usize]);
        self.td.speeds_changed(p, modes.time_driven());
        self.book.v_max = self.ed_speeds();
        Ok(())
    }
}
