//! Options, modes, counters and errors of the hybrid engine.

use emdstar_system::SystemError;

/// How a particle is moved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Mode {
    /// Event-driven: free (parabolic) flight between eMD* events.
    Event,
    /// Time-driven: velocity Verlet with contact forces.
    Time,
    /// Left through the outlet ([`HybridOptions::outlet`]); no longer simulated.
    Removed,
}

/// How the event-driven particles collide.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum EventRule {
    /// eMD*, as the eMD* engine runs it: three events per collision with the matrix of
    /// restitution (a table, an exact solve outside it), and the exact frictional
    /// contact where a contact has the history spring.
    #[default]
    EmdStar,
    /// Classic eMD: instantaneous collisions with the law's central restitution, and
    /// where a contact has friction Walton's rule with β₀ derived from the
    /// time-driven law (linear law only; HAET, Eqs. 1.1a-b).
    Emd,
}

impl EventRule {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::EmdStar => "emdstar",
            Self::Emd => "emd",
        }
    }
}

/// Options of the hybrid engine.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HybridOptions {
    /// The MD time step in s (bounded like [`emdstar_dem::MdOptions::dt`]).
    pub dt: f64,
    /// Verlet-list skin in m; `None` means [`emdstar_dem::default_skin`].
    pub skin: Option<f64>,
    /// A particle becomes TD where the local volume fraction reaches this.
    pub phi_time: f64,
    /// A TD particle may return to ED only where the local volume fraction is below
    /// this (hysteresis; must not exceed `phi_time`).
    pub phi_event: f64,
    /// Whether modes are re-decided at rebuilds. When false, modes change only by the
    /// guard and the event budget (ED → TD); useful to set modes by hand
    /// ([`crate::Hybrid::set_mode`]).
    pub adaptive: bool,
    /// Events of one ED particle within one step above which it becomes TD.
    pub max_events_per_step: u32,
    /// An outlet: particles whose centre has passed behind this plane (distance < 0)
    /// leave the system at the next list rebuild or mode check (a hopper's discharge).
    pub outlet: Option<emdstar_system::Wall>,
    /// How the ED particles collide.
    pub events: EventRule,
    /// eMD*'s exception (b): which pending E^v events run early when a third particle
    /// hits a particle in its transient.
    pub interference: emdstar_edmd::Interference,
}

impl HybridOptions {
    /// Defaults around a time step: φ_TD = 0.2, φ_ED = 0.1 (eMD*'s exceptions are rare
    /// up to η ≈ 0.1, Müller & Pöschel 2013, Fig. 7), adaptive, 50 events per step,
    /// eMD* events with the paper's exception (b) (only the particle hit).
    pub fn with_dt(dt: f64) -> Self {
        Self {
            dt,
            skin: None,
            phi_time: 0.2,
            phi_event: 0.1,
            adaptive: true,
            max_events_per_step: 50,
            outlet: None,
            events: EventRule::EmdStar,
            interference: emdstar_edmd::Interference::HitOnly,
        }
    }
}

/// Counters of a hybrid run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HybridStats {
    /// Time steps done.
    pub steps: u64,
    /// Neighbour-list rebuilds (each one also decides the modes).
    pub rebuilds: u64,
    /// Mode checks while no particle is TD that found nothing to switch (no list was
    /// built).
    pub cell_passes: u64,
    /// The ED events, counted as the eMD* engine counts them (every event taken from
    /// the queue, cell crossings included; collisions, E^v events, exceptions, MoR
    /// fallbacks, exact frictional solves).
    pub ed: emdstar_edmd::Stats,
    /// ED → TD switches (all causes).
    pub to_time: u64,
    /// TD → ED switches.
    pub to_event: u64,
    /// ED → TD switches made by the per-step guard.
    pub guard_conversions: u64,
    /// Guard switches of a particle already overlapping and approaching a TD particle
    /// (the guard came too late; should be 0).
    pub late_conversions: u64,
    /// Largest overlap (m) found at a late guard switch.
    pub max_late_overlap: f64,
    /// ED → TD switches because of the event budget per step.
    pub budget_conversions: u64,
    /// Events of ED particles over their budget, held back until the particle became
    /// TD at the end of the step.
    pub vetoed_events: u64,
    /// Transients ended early by a switch (exception (b) at a switch).
    pub early_transient_ends: u64,
    /// Particle-steps done by TD particles (Σ over steps of N_TD).
    pub td_particle_steps: u64,
    /// Particles removed through the outlet.
    pub removed: u64,
}

/// Errors of the hybrid engine.
#[derive(Debug, thiserror::Error)]
pub enum HybridError {
    #[error(transparent)]
    System(#[from] SystemError),
    #[error(transparent)]
    Contact(#[from] emdstar_contact::ContactError),
    #[error(transparent)]
    Md(#[from] emdstar_dem::MdError),
    #[error(transparent)]
    Event(#[from] emdstar_edmd::EngineError),
    #[error("hybrid options: {0}")]
    Invalid(String),
}
