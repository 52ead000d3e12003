//! A complete, validated system: particles, species, the material and the domain.

use crate::domain::Domain;
use crate::error::Result;
use crate::interactions::Interactions;
use crate::state::{Particles, Species};
use emdstar_contact::ForceLaw;

/// Everything an engine of soft spheres needs besides its own options.
#[derive(Debug, Clone)]
pub struct System {
    pub particles: Particles,
    pub species: Vec<Species>,
    /// The force law of the one material all particles and walls are made of.
    pub material: ForceLaw,
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

    /// Checks the state against the domain (see [`Domain::check`]).
    pub fn validate(&self) -> Result<()> {
        self.domain.check(&self.particles)
    }

    /// The region a cell grid must cover: the box, or the particles' bounding box.
    pub fn search_region(&self) -> ([f64; 3], [f64; 3], [bool; 3]) {
        self.domain.search_region(&self.particles.position)
    }
}
