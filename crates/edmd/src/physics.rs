//! What the event engine is told besides the particles and their domain: the method
//! and the contacts it runs ([`Physics`]; the engine makes the rules of
//! `collision::Rules` of them once), the variant of eMD*'s exception (b) and the broad
//! phase to use.

use crate::rules::MorSource;
use emdstar_contact::Walton;
use emdstar_system::Interactions;

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
    /// [`BroadPhaseKind::Auto`] takes epochs below this packing fraction. Measured on the
    /// elastic Hertz gas (wall time per simulated second, epochs against crossings,
    /// `speed_probe`, two interleaved runs each): at N = 2000, 0.88 at η = 0.015, 0.97
    /// at 0.02, 1.04 at 0.025, 1.14 at 0.03; at N = 10⁴, 1.00 at 0.02 and 1.13 at 0.025.
    pub const AUTO_EPOCHS_BELOW: f64 = 0.02;
    /// [`BroadPhaseKind::Auto`] takes neighbour lists from this packing fraction on
    /// (hard spheres and eMD). Measured on elastic hard spheres, N = 32 000, collisions
    /// per CPU second, best of three interleaved runs on a shared machine: cells 6.1e5
    /// and lists 4.9e5 at η = 0.3, 6.1e5 and 5.7e5 at 0.34, 6.0e5 and 5.9e5 at 0.37;
    /// lists 7.1e5 at 0.4 (docs/performance.md).
    pub const AUTO_NEIGHBOURS_FROM: f64 = 0.38;
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

/// The method of a run and the contacts it runs.
pub enum Physics {
    /// Instantaneous hard-sphere collisions with one constant ε (1 = elastic), walls
    /// included, smooth or with Walton's rule.
    HardSpheres {
        restitution: f64,
        walton: Option<Walton>,
    },
    /// Classic eMD: instantaneous collisions with the force law's central restitution
    /// at the actual normal impact speed (Walton's rule where a contact has it).
    Emd(Interactions),
    /// eMD*: three events per collision with the matrix of restitution (the exact
    /// frictional contact where a contact has the history spring).
    EmdStar {
        interactions: Interactions,
        mor: Box<dyn MorSource>,
        interference: Interference,
    },
}

impl Physics {
    /// Smooth hard spheres of restitution `restitution`.
    pub fn hard_spheres(restitution: f64) -> Self {
        Self::HardSpheres {
            restitution,
            walton: None,
        }
    }

    /// The contacts (none for hard spheres).
    pub fn interactions(&self) -> Option<&Interactions> {
        match self {
            Self::HardSpheres { .. } => None,
            Self::Emd(i)
            | Self::EmdStar {
                interactions: i, ..
            } => Some(i),
        }
    }
}
