//! MD behind the workspace's one simulation interface.

use crate::engine::Md;
use emdstar_system::{
    Domain, Particles, Simulation, SimulationError, StressMark, StressSums, Thermo, VelocityChange,
};

impl Simulation for Md {
    fn engine(&self) -> &'static str {
        "md"
    }

    fn time(&self) -> f64 {
        Md::time(self)
    }

    fn time_step(&self) -> Option<f64> {
        Some(self.options().dt)
    }

    fn steps_done(&self) -> u64 {
        self.steps()
    }

    /// Steps to the step nearest `t`, the last half kick left pending (see
    /// [`Md::stride`]).
    fn advance_to(&mut self, t: f64) -> Result<(), SimulationError> {
        let target = (t / self.options().dt).round().max(0.0) as u64;
        Ok(self.stride(target.saturating_sub(self.steps()))?)
    }

    fn synchronise(&mut self) -> Result<(), SimulationError> {
        Ok(Md::synchronise(self)?)
    }

    fn thermo(&self) -> Thermo {
        Md::thermo(self)
    }

    fn stress_sums(&self) -> StressSums {
        self.verlet().stress_sums(&self.system().particles)
    }

    fn stress_mark(&self) -> Option<StressMark> {
        self.verlet().stress_mark()
    }

    fn mark_stress(&mut self) {
        Md::mark_stress(self);
    }

    fn change_velocities(
        &mut self,
        change: &mut VelocityChange<'_>,
    ) -> Result<(), SimulationError> {
        Ok(Md::change_velocities(self, change)?)
    }

    fn particles(&self) -> Particles {
        self.particles_in_config_order()
    }

    fn domain(&self) -> &Domain {
        &self.system().domain
    }

    fn save_state(&self) -> Vec<u8> {
        Md::save_state(self)
    }

    fn restore_state(&mut self, state: &[u8]) -> Result<(), SimulationError> {
        Ok(Md::restore_state(self, state)?)
    }
}
