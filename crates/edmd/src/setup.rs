//! What the event engine is given: particles, region, walls, gravity, and physics.

use crate::error::{EngineError, Result};
use crate::rules::{CentralRestitution, MorSource};
use emdstar_contact::{ForceLaw, PairLaw, PairProperties, Sphere};

/// The simulated region: a cuboid `[lo, lo + size)`, each axis periodic or closed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    pub lo: [f64; 3],
    pub size: [f64; 3],
    pub periodic: [bool; 3],
}

/// How the event engine finds the pairs to test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BroadPhase {
    /// Epochs where they fit (see [`BroadPhase::Epochs`]) in a gas below the packing
    /// fraction [`BroadPhase::AUTO_EPOCHS_BELOW`] that is periodic or held by
    /// axis-aligned walls from both sides along every axis; cell crossings otherwise.
    /// (A gas spreading into free space leaves the epoch grid for its unbounded border
    /// cells, where every epoch tests all pairs.)
    #[default]
    Auto,
    /// A cell grid with a crossing event whenever a particle changes cell (Alder &
    /// Wainwright 1959; Rapaport 1980).
    Crossings,
    /// Swept boxes filed once per epoch (needs no gravity, and along periodic axes a
    /// box at least four times the sum of the largest contact distance and a cell
    /// width, a cell being 0.8 mean spacings). A gas that spreads into free space
    /// piles into the grid's border cells and runs far slower than on crossings.
    Epochs,
}

impl BroadPhase {
    /// [`BroadPhase::Auto`] takes epochs below this packing fraction. Measured on the
    /// elastic Hertz gas (wall time per simulated second, epochs against crossings,
    /// `speed_probe`, two interleaved runs each): at N = 2000, 0.88 at η = 0.015, 0.97
    /// at 0.02, 1.04 at 0.025, 1.14 at 0.03; at N = 10⁴, 1.00 at 0.02 and 1.13 at 0.025.
    pub const AUTO_EPOCHS_BELOW: f64 = 0.02;
}

/// A plane wall. Particles live on the side the unit `normal` points to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    pub normal: [f64; 3],
    pub point: [f64; 3],
}

/// Particles as a structure of arrays, plus their surroundings.
#[derive(Debug, Clone, Default)]
pub struct Setup {
    pub position: Vec<[f64; 3]>,
    pub velocity: Vec<[f64; 3]>,
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    /// Species index of each particle (into [`Materials`]); all 0 for hard spheres.
    pub species: Vec<u32>,
    /// `None` is free space.
    pub region: Option<Region>,
    pub walls: Vec<Wall>,
    pub gravity: [f64; 3],
}

/// Pair laws between species and against walls, with their central restitution.
#[derive(Debug, Clone)]
pub struct Materials {
    species: usize,
    pairs: Vec<PairEntry>,
    walls: Vec<PairEntry>,
}

/// The physics of one kind of pair.
#[derive(Debug, Clone)]
pub struct PairEntry {
    pub law: PairLaw,
    pub props: PairProperties,
    pub central: CentralRestitution,
}

impl PairEntry {
    pub fn new(law: PairLaw, props: PairProperties) -> Result<Self> {
        Ok(Self {
            central: CentralRestitution::of(&law, &props)?,
            law,
            props,
        })
    }
}

impl Materials {
    /// From the pair entries of every species pair (`pairs[a * species + b]`) and of
    /// every species against a wall.
    pub fn new(species: usize, pairs: Vec<PairEntry>, walls: Vec<PairEntry>) -> Result<Self> {
        if pairs.len() != species * species || walls.len() != species {
            return Err(EngineError::Invalid(format!(
                "materials for {species} species need {} pair entries and {species} wall \
                 entries, got {} and {}",
                species * species,
                pairs.len(),
                walls.len()
            )));
        }
        Ok(Self {
            species,
            pairs,
            walls,
        })
    }

    /// Materials of spheres `species` (one material `law` for all, walls included).
    pub fn of_spheres(law: &ForceLaw, species: &[Sphere]) -> Result<Self> {
        let mut pairs = Vec::with_capacity(species.len() * species.len());
        for a in species {
            for b in species {
                let props = PairProperties::spheres(a, b);
                pairs.push(PairEntry::new(
                    PairLaw::same_material(law, props.r_eff)?,
                    props,
                )?);
            }
        }
        let walls = species
            .iter()
            .map(|s| {
                let props = PairProperties::sphere_wall(s);
                PairEntry::new(PairLaw::same_material(law, props.r_eff)?, props)
            })
            .collect::<Result<Vec<_>>>()?;
        Self::new(species.len(), pairs, walls)
    }

    #[inline]
    pub fn pair(&self, a: u32, b: u32) -> &PairEntry {
        &self.pairs[a as usize * self.species + b as usize]
    }

    #[inline]
    pub fn wall(&self, a: u32) -> &PairEntry {
        &self.walls[a as usize]
    }

    pub fn species(&self) -> usize {
        self.species
    }
}

/// eMD* exception (b): which pending E^v events run early when a third particle hits
/// a particle in its transient (Müller & Pöschel 2013, Sec. VI B 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Interference {
    /// Only the particle that is hit (the paper's default; breaks angular momentum
    /// conservation by a tiny amount).
    HitOnly,
    /// Both partners of the interrupted collision ("post-collisional communication").
    BothPartners,
}

/// The collision rule of a run.
pub enum Physics {
    /// Instantaneous hard-sphere collisions with one constant ε (1 = elastic), walls
    /// included.
    HardSpheres { restitution: f64 },
    /// Classic eMD: instantaneous collisions with the force law's central restitution
    /// at the actual normal impact speed.
    Emd(Materials),
    /// eMD*: three events per collision with the matrix of restitution.
    EmdStar {
        materials: Materials,
        mor: Box<dyn MorSource>,
        interference: Interference,
    },
}

impl Physics {
    pub fn materials(&self) -> Option<&Materials> {
        match self {
            Self::HardSpheres { .. } => None,
            Self::Emd(m) | Self::EmdStar { materials: m, .. } => Some(m),
        }
    }
}
