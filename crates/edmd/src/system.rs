//! Building the engine's input from the shared [`emdstar_system::System`] (the config,
//! state and writers that MD uses too), and writing the state back.

use crate::engine::Engine;
use crate::error::Result;
use crate::queue::EventQueue;
use crate::setup::{Materials, Region, Setup, Wall};
use emdstar_system::{Particles, System};

impl Setup {
    /// The particles, box, walls and gravity of `system`, in the system's particle order.
    pub fn from_system(system: &System) -> Self {
        let p = &system.particles;
        Self {
            position: p.position.clone(),
            velocity: p.velocity.clone(),
            radius: p.radius.clone(),
            mass: p.mass.clone(),
            species: p.species.clone(),
            region: system.sim_box.map(|b| Region {
                lo: b.lo,
                size: b.size,
                periodic: b.periodic,
            }),
            walls: system
                .walls
                .iter()
                .map(|w| Wall {
                    normal: w.normal,
                    point: w.point,
                })
                .collect(),
            gravity: system.gravity,
        }
    }
}

impl Materials {
    /// Pair and wall laws of every species of `system` (one material for all).
    pub fn from_system(system: &System) -> Result<Self> {
        let spheres: Vec<_> = system.species.iter().map(|s| s.sphere()).collect();
        Self::of_spheres(&system.material, &spheres)
    }
}

impl<Q: EventQueue> Engine<Q> {
    /// Copies the current state (pending E^v velocities applied) into `particles`,
    /// which must be the particles the engine was built from (same order).
    pub fn write_state(&mut self, particles: &mut Particles) {
        self.sync();
        particles.position = self.positions();
        particles.velocity = self.settled_velocities();
    }
}
