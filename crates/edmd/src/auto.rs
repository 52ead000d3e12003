//! [`Engine`]: the event engine with its broad phase chosen at run time. Each
//! variant runs its own monomorphised event loop; the choice is made once.

use crate::broad_phase::{Crossings, Epochs, Neighbours};
use crate::calendar::CalendarQueue;
use crate::engine::build::{EPOCHS_DO_NOT_FIT, NEIGHBOURS_DO_NOT_FIT, Prepared};
use crate::engine::{Event, EventEngine};
use crate::error::{EngineError, Result};
use crate::physics::{BroadPhaseKind, Physics};
use crate::queue::EventQueue;
use crate::stats::Stats;
use emdstar_system::{Domain, Particles};

/// The event-driven engine for hard spheres, eMD and eMD*, on the broad phase
/// [`BroadPhaseKind`] chose.
// An engine is built once and lives for the run: its size on the stack is no concern.
#[allow(clippy::large_enum_variant)]
pub enum Engine<Q: EventQueue = CalendarQueue> {
    Crossings(EventEngine<Crossings, Q>),
    Epochs(EventEngine<Epochs, Q>),
    Neighbours(EventEngine<Neighbours, Q>),
}

impl<Q: EventQueue> Engine<Q> {
    /// Checks the particles against their domain and builds an engine at time 0 with
    /// every first event predicted, on the broad phase [`BroadPhaseKind::Auto`]
    /// chooses. Particle numbers are the particles' indices.
    ///
    /// Errors: the shared checks of [`Domain::check`] (non-finite input, overlapping
    /// particles, particles outside the box or cut by walls), an impossible packing
    /// fraction, a periodic box too small, species without materials.
    pub fn new(particles: &Particles, domain: &Domain, physics: Physics) -> Result<Self> {
        Self::with_broad_phase(particles, domain, physics, BroadPhaseKind::Auto)
    }

    /// As [`Engine::new`] on cell crossings, with cells at least `min_width` wide
    /// instead of the automatic choice (never narrower than the largest contact
    /// distance; wider cells mean fewer crossings but more pair tests). `min_width` = 0
    /// is the automatic choice.
    pub fn with_cell_width(
        particles: &Particles,
        domain: &Domain,
        physics: Physics,
        min_width: f64,
    ) -> Result<Self> {
        EventEngine::crossings(particles, domain, physics, min_width).map(Self::Crossings)
    }

    /// As [`Engine::new`], with the broad phase chosen. Errors as [`Engine::new`], and
    /// for [`BroadPhaseKind::Epochs`] under gravity or in a periodic box too small for
    /// it.
    pub fn with_broad_phase(
        particles: &Particles,
        domain: &Domain,
        physics: Physics,
        kind: BroadPhaseKind,
    ) -> Result<Self> {
        if kind == BroadPhaseKind::Crossings {
            return Self::with_cell_width(particles, domain, physics, 0.0);
        }
        let p = Prepared::new(particles, domain, physics, 0.0)?;
        if domain.shear_rate != 0.0 && kind != BroadPhaseKind::Auto {
            return Err(EngineError::Invalid(format!(
                "Lees–Edwards boundaries (box.shear_rate) run on the crossings broad phase \
                 only, not on {kind:?}; use BroadPhase::Crossings"
            )));
        }
        if kind == BroadPhaseKind::Epochs && !p.epochs_fit() {
            return Err(EngineError::Invalid(EPOCHS_DO_NOT_FIT.into()));
        }
        if kind == BroadPhaseKind::Neighbours && !p.neighbours_fit() {
            return Err(EngineError::Invalid(NEIGHBOURS_DO_NOT_FIT.into()));
        }
        let auto = kind == BroadPhaseKind::Auto;
        Ok(
            if kind == BroadPhaseKind::Neighbours || auto && p.prefers_neighbours() {
                Self::Neighbours(EventEngine::from_neighbours(p))
            } else if kind == BroadPhaseKind::Epochs || p.prefers_epochs() {
                Self::Epochs(EventEngine::from_prepared(p))
            } else {
                Self::Crossings(EventEngine::from_crossings(p))
            },
        )
    }

    /// The broad phase in use.
    pub fn broad_phase(&self) -> BroadPhaseKind {
        match self {
            Self::Crossings(_) => BroadPhaseKind::Crossings,
            Self::Epochs(_) => BroadPhaseKind::Epochs,
            Self::Neighbours(_) => BroadPhaseKind::Neighbours,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        on_engine!(self, e => e.len())
    }

    /// True without particles.
    pub fn is_empty(&self) -> bool {
        on_engine!(self, e => e.is_empty())
    }

    /// Current simulation time.
    pub fn time(&self) -> f64 {
        on_engine!(self, e => e.time())
    }

    /// Event and exception counters.
    pub fn stats(&self) -> &Stats {
        on_engine!(self, e => e.stats())
    }

    /// Processes the next event.
    pub fn step(&mut self) -> Result<Event> {
        on_engine!(self, e => e.step())
    }

    /// Turns the TC model on with duration `tc` in s, or off
    /// ([`crate::collision::Rules::set_tc`]).
    pub fn set_tc(&mut self, tc: Option<f64>) -> Result<()> {
        on_engine!(self, e => e.set_tc(tc))
    }

    /// Runs until time `t_end` (all events before it), leaving every particle's
    /// stored state at its last event.
    pub fn run_until(&mut self, t_end: f64) -> Result<()> {
        on_engine!(self, e => e.run_until(t_end))
    }

    /// Runs until `count` more pair and wall collisions have been executed.
    pub fn run_collisions(&mut self, count: u64) -> Result<()> {
        on_engine!(self, e => e.run_collisions(count))
    }

    /// Sets how many events pass between spatial re-sorts of the particle order
    /// (0 switches re-sorting off).
    pub fn set_resort_interval(&mut self, events: u64) {
        on_engine!(self, e => e.set_resort_interval(events))
    }

    /// Brings every particle to the current time (see [`EventEngine::sync`]).
    pub fn sync(&mut self) {
        on_engine!(self, e => e.sync())
    }

    /// Positions at the current time, by particle number (see
    /// [`EventEngine::positions`]).
    pub fn positions(&self) -> Vec<[f64; 3]> {
        on_engine!(self, e => e.positions())
    }

    /// Stored velocities, by particle number (see [`EventEngine::velocities`]).
    pub fn velocities(&self) -> Vec<[f64; 3]> {
        on_engine!(self, e => e.velocities())
    }

    /// Velocities with pending E^v velocities applied, by particle number.
    pub fn settled_velocities(&self) -> Vec<[f64; 3]> {
        on_engine!(self, e => e.settled_velocities())
    }

    /// Kinetic energy Σ ½ m v² with pending E^v velocities applied.
    pub fn kinetic_energy(&self) -> f64 {
        on_engine!(self, e => e.kinetic_energy())
    }

    /// Momentum Σ m v with pending E^v velocities applied.
    pub fn momentum(&self) -> [f64; 3] {
        on_engine!(self, e => e.momentum())
    }

    /// Copies the current state into `particles` (see [`EventEngine::write_state`]).
    pub fn write_state(&mut self, particles: &mut Particles) {
        on_engine!(self, e => e.write_state(particles))
    }

    /// Radii, by particle number.
    pub fn radii(&self) -> Vec<f64> {
        on_engine!(self, e => e.radii())
    }

    /// Masses, by particle number.
    pub fn masses(&self) -> Vec<f64> {
        on_engine!(self, e => e.masses())
    }

    /// The collision rules.
    pub fn rules(&self) -> &crate::collision::Rules {
        on_engine!(self, e => e.rules())
    }

    /// Angular velocities in rad/s, by particle number.
    pub fn angular_velocities(&self) -> Vec<[f64; 3]> {
        on_engine!(self, e => e.angular_velocities())
    }
}
