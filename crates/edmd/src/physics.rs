//! What the event engine is told besides the particles and their domain: the collision
//! rule ([`Physics`]), the pair physics it needs ([`Materials`]), the variant of eMD*'s
//! exception (b) and the broad phase to use.

use crate::error::Result;
use crate::rules::{CentralRestitution, MorSource};
use emdstar_contact::{ForceLaw, Sphere};
use emdstar_system::{Interaction, Interactions, Species, System};

/// How the event engine finds the pairs to test.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BroadPhaseKind {
    /// Epochs where they fit (see [`BroadPhaseKind::Epochs`]) in a gas below the packing
    /// fraction [`BroadPhaseKind::AUTO_EPOCHS_BELOW`] that is periodic or held by
    /// axis-aligned walls from both sides along every axis; cell crossings otherwise.
    /// (A gas spreading into free space leaves the epoch grid for its unbounded border
    /// cells, where every epoch tests all pairs.) Neighbour lists for hard spheres and
    /// eMD at and above the packing fraction [`BroadPhaseKind::AUTO_NEIGHBOURS_FROM`]
    /// where they fit (see [`BroadPhaseKind::Neighbours`]), held the same way.
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
    /// A neighbour list per particle, of the particles whose shell centres lie within
    /// 1.5 largest contact distances of its own, rebuilt when the particle has moved a
    /// quarter of the largest contact distance from its centre (Smallenburg 2022). For
    /// hard spheres and eMD without gravity, radii within a factor of two, and along
    /// periodic axes a box at least 4.5 largest contact distances wide.
    Neighbours,
}

impl BroadPhaseKind {
    /// [`BroadPhaseKind::Auto`] takes epochs below this packing fraction, where they beat
    /// crossings on the elastic Hertz gas (the measurements: commit history, docs/performance.md).
    pub const AUTO_EPOCHS_BELOW: f64 = 0.02;
    /// [`BroadPhaseKind::Auto`] takes neighbour lists from this packing fraction on
    /// (hard spheres and eMD), where they beat cells (measurements: docs/performance.md).
    pub const AUTO_NEIGHBOURS_FROM: f64 = 0.38;
}

/// The pair physics of every kind of contact ([`Interactions`], shared with the other
/// engines) and, for eMD, the central restitution of each.
#[derive(Debug, Clone, Default)]
pub struct Materials {
    interactions: Interactions,
    /// The central restitution of each interaction, in the order of `Interactions`:
    /// `pairs[a * species + b]`, then one per species against a wall.
    pairs: Vec<CentralRestitution>,
    walls: Vec<CentralRestitution>,
}

/// The physics of one kind of pair: its interaction and its central restitution.
#[derive(Debug, Clone, Copy)]
pub struct PairEntry<'a> {
    pub interaction: &'a Interaction,
    pub central: &'a CentralRestitution,
}

impl Materials {
    /// The materials of `interactions`.
    pub fn new(interactions: Interactions) -> Result<Self> {
        let n = interactions.species() as u32;
        let central = |i: &Interaction| CentralRestitution::of(&i.law, &i.props);
        let pairs = (0..n)
            .flat_map(|a| (0..n).map(move |b| (a, b)))
            .map(|(a, b)| central(interactions.pair(a, b)))
            .collect::<Result<Vec<_>>>()?;
        let walls = (0..n)
            .map(|a| central(interactions.wall(a)))
            .collect::<Result<Vec<_>>>()?;
        Ok(Self {
            interactions,
            pairs,
            walls,
        })
    }

    /// Materials of spheres `species` (one material `law` for all, walls included).
    pub fn of_spheres(law: &ForceLaw, species: &[Sphere]) -> Result<Self> {
        let species: Vec<Species> = species
            .iter()
            .map(|s| Species {
                radius: s.radius,
                mass: s.mass,
            })
            .collect();
        Self::new(Interactions::of(law, &species)?)
    }

    /// The materials of every species of `system`.
    pub fn from_system(system: &System) -> Result<Self> {
        Self::new(system.interactions()?)
    }

    /// Species `a` against species `b`.
    #[inline]
    pub fn pair(&self, a: u32, b: u32) -> PairEntry<'_> {
        PairEntry {
            interaction: self.interactions.pair(a, b),
            central: &self.pairs[a as usize * self.interactions.species() + b as usize],
        }
    }

    /// Species `a` against a wall.
    #[inline]
    pub fn wall(&self, a: u32) -> PairEntry<'_> {
        PairEntry {
            interaction: self.interactions.wall(a),
            central: &self.walls[a as usize],
        }
    }

    /// The interactions (laws and pair properties) alone.
    pub fn interactions(&self) -> &Interactions {
        &self.interactions
    }

    pub fn species(&self) -> usize {
        self.interactions.species()
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
