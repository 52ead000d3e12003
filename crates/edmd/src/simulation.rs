//! The event engine behind the workspace's one simulation interface.

use crate::auto::Engine;
use crate::physics::BroadPhaseKind;
use crate::queue::EventQueue;
use emdstar_system::{
    Domain, Particles, Simulation, SimulationError, StressMark, StressSums, Thermo, VelocityChange,
};
use serde::Serialize;
use serde::de::DeserializeOwned;

impl<Q: EventQueue + Serialize + DeserializeOwned> Simulation for Engine<Q> {
    fn engine(&self) -> &'static str {
        self.rules().method()
    }

    fn time(&self) -> f64 {
        Engine::time(self)
    }

    fn time_step(&self) -> Option<f64> {
        None
    }

    fn steps_done(&self) -> u64 {
        self.stats().events
    }

    /// Runs every event up to `t` (particles keep their states of their last event).
    fn advance_to(&mut self, t: f64) -> Result<(), SimulationError> {
        Ok(self.run_until(t)?)
    }

    fn synchronise(&mut self) -> Result<(), SimulationError> {
        self.sync();
        Ok(())
    }

    fn thermo(&self) -> Thermo {
        on_engine!(self, e => e.thermo())
    }

    fn stress_sums(&self) -> StressSums {
        on_engine!(self, e => e.stress_sums(|_| true))
    }

    fn stress_mark(&self) -> Option<StressMark> {
        on_engine!(self, e => e.stress_mark())
    }

    fn mark_stress(&mut self) {
        on_engine!(self, e => e.mark_stress(e.time(), e.stress_sums(|_| true)))
    }

    fn change_velocities(
        &mut self,
        change: &mut VelocityChange<'_>,
    ) -> Result<(), SimulationError> {
        on_engine!(self, e => e.change_velocities(change));
        Ok(())
    }

    fn particles(&self) -> Particles {
        on_engine!(self, e => e.particles_now())
    }

    fn domain(&self) -> &Domain {
        on_engine!(self, e => e.domain())
    }

    /// The broad phase (one byte) and the engine's state.
    fn save_state(&self) -> Vec<u8> {
        let (tag, mut state) = match self {
            Engine::Crossings(e) => (0u8, e.save_state()),
            Engine::Epochs(e) => (1u8, e.save_state()),
            Engine::Neighbours(e) => (2u8, e.save_state()),
        };
        state.insert(0, tag);
        state
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SimulationError> {
        let tag = match self.broad_phase() {
            BroadPhaseKind::Epochs => 1,
            BroadPhaseKind::Neighbours => 2,
            _ => 0,
        };
        if bytes.first() != Some(&tag) {
            return Err(format!(
                "the checkpoint was written on another broad phase than this run's ({:?}); \
                 resume with the --broad-phase of the run that wrote it",
                self.broad_phase()
            )
            .into());
        }
        Ok(on_engine!(self, e => e.restore_state(&bytes[1..]))?)
    }
}
