//! A complete, validated system: particles, species, the material and the domain.

use crate::domain::Domain;
use crate::error::Result;
use crate::interactions::Interactions;
use crate::state::{Particles, Species};
use emdstar_contact::{ForceLaw, Friction};

/// Everything an engine of soft spheres needs besides its own options.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct System {
    pub particles: Particles,
    pub species: Vec<Species>,
    /// The force law of the one material all particles and walls are made of.
    pub material: ForceLaw,
    /// The friction of that material (none by default).
    #[serde(default)]
    pub friction: Friction,
    /// The box, walls and gravity.
    pub domain: Domain,
}

impl System {
    /// The pair physics of every species pair and of every species against a wall.
    pub fn interactions(&self) -> Result<Interactions> {
        Interactions::of(&self.material, &self.species)
    }

    /// Largest particle radius (0 if there are none).
    pub fn max_radius(&self) -> f64 {
        self.species.iter().map(|s| s.radius).fold(0.0, f64::max)
    }

    /// What the user should know about this system but that is not an error: spins on
    /// a frictionless material (no torque ever acts, so they stay as given).
    pub fn warnings(&self) -> Vec<String> {
        let spinning = self
            .particles
            .angular_velocity
            .iter()
            .filter(|w| **w != [0.0; 3])
            .count();
        if spinning > 0 && !self.friction.is_active() {
            vec![format!(
                "{spinning} particles spin, but the material is frictionless (no \
                 material.friction): no torque acts, so their spins stay as given and do not \
                 affect the motion"
            )]
        } else {
            Vec::new()
        }
    }

    /// Checks the state against the domain (see [`Domain::check`]).
    pub fn validate(&self) -> Result<()> {
        self.domain.check(&self.particles)
    }

    /// The region a cell grid must cover: the box, or the particles' bounding box.
    pub fn search_region(&self) -> ([f64; 3], [f64; 3], [bool; 3]) {
        self.domain.search_region(&self.particles.position)
    }
}
