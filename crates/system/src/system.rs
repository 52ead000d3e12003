//! A complete, validated system: particles, species, their contacts and the domain.

use crate::domain::Domain;
use crate::error::Result;
use crate::interactions::Interactions;
use crate::state::{Particles, Species};
use emdstar_contact::{ForceLaw, Tangential};

/// Everything an engine of soft spheres needs besides its own options.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct System {
    pub particles: Particles,
    pub species: Vec<Species>,
    /// The contact model of every species pair and of every species against each wall
    /// (not saved: a restored engine keeps the one its config gives).
    #[serde(skip)]
    pub interactions: Interactions,
    /// The box, walls and gravity.
    pub domain: Domain,
}

impl System {
    /// A system of one material, `law` with `tangential`, for particles and walls.
    pub fn one_material(
        particles: Particles,
        species: Vec<Species>,
        law: &ForceLaw,
        tangential: Tangential,
        domain: Domain,
    ) -> Result<Self> {
        let interactions = Interactions::one_material(law, tangential, &species)?;
        Ok(Self {
            particles,
            species,
            interactions,
            domain,
        })
    }

    /// The contact model of every species pair and of every species against a wall.
    pub fn interactions(&self) -> &Interactions {
        &self.interactions
    }

    /// Largest particle radius (0 if there are none).
    pub fn max_radius(&self) -> f64 {
        self.species.iter().map(|s| s.radius).fold(0.0, f64::max)
    }

    /// What the user should know about this system but that is not an error: spins
    /// without friction (no torque ever acts, so they stay as given).
    pub fn warnings(&self) -> Vec<String> {
        let spinning = self
            .particles
            .angular_velocity
            .iter()
            .filter(|w| **w != [0.0; 3])
            .count();
        if spinning > 0 && !self.interactions.is_frictional() {
            vec![format!(
                "{spinning} particles spin, but every contact is frictionless (no friction in \
                 the materials): no torque acts, so their spins stay as given and do not \
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
