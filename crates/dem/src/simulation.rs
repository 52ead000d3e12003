//! MD behind the workspace's one simulation interface.

use crate::engine::Md;
use emdstar_system::{Domain, Particles, Simulation, SimulationError, Thermo};

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

    fn advance_to(&mut self, t: f64) -> Result<(), SimulationError> {
        let target = (t / self.options().dt).round().max(0.0) as u64;
        Ok(self.advance(target.saturating_sub(self.steps()))?)
    }

    fn thermo(&self) -> Thermo {
        Md::thermo(self)
    }

    fn particles(&self) -> Particles {
        self.particles_in_config_order()
    }

    fn domain(&self) -> &Domain {
        &self.system().domain
    }

    fn save_state(&self) -> Vec<u8> {
        Vec::new()
    }

    fn restore_state(&mut self, _: &[u8]) -> Result<(), SimulationError> {
        Err("MD checkpoints: pending".into())
    }
}
