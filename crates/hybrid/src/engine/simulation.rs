//! The hybrid engine behind the workspace's one simulation interface.

use super::Hybrid;
use emdstar_system::{
    Domain, Particles, Simulation, SimulationError, StressMark, StressSums, Thermo, VelocityChange,
};

impl Simulation for Hybrid {
    fn engine(&self) -> &'static str {
        "hybrid"
    }

    fn time(&self) -> f64 {
        Hybrid::time(self)
    }

    fn time_step(&self) -> Option<f64> {
        Some(self.options().dt)
    }

    fn steps_done(&self) -> u64 {
        self.steps()
    }

    fn advance_to(&mut self, t: f64) -> Result<(), SimulationError> {
        let target = (t / self.options().dt).round().max(0.0) as u64;
        Ok(self.advance(target.saturating_sub(self.steps()))?)
    }

    /// Brings the TD velocities in step with the positions (as MD's); ED particles stay
    /// at their last events.
    fn synchronise(&mut self) -> Result<(), SimulationError> {
        let t = self.time();
        Ok(self.in_step(t)?)
    }

    fn thermo(&self) -> Thermo {
        Hybrid::thermo(self)
    }

    fn stress_sums(&self) -> StressSums {
        Hybrid::stress_sums(self)
    }

    fn stress_mark(&self) -> Option<StressMark> {
        self.ed_stress_mark()
    }

    fn mark_stress(&mut self) {
        Hybrid::mark_stress(self);
    }

    fn change_velocities(
        &mut self,
        change: &mut VelocityChange<'_>,
    ) -> Result<(), SimulationError> {
        Ok(Hybrid::change_velocities(self, change)?)
    }

    fn particles(&self) -> Particles {
        Hybrid::particles(self)
    }

    fn domain(&self) -> &Domain {
        &self.system().domain
    }

    fn save_state(&self) -> Vec<u8> {
        Hybrid::save_state(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), SimulationError> {
        Ok(Hybrid::restore_state(self, state)?)
    }
}
