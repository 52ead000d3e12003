//! The hybrid engine (`--engine hybrid`, crate emdstar-hybrid: MD where the gas is
//! dense, eMD* where it is dilute): its options and its counters.

use clap::Args;
use emdstar_hybrid::HybridStats;
use serde_json::{Value, json};

/// Options of the hybrid engine.
#[derive(Args, Debug, Clone)]
pub struct HybridArgs {
    /// Hybrid: local volume fraction from which a particle is time-driven.
    #[arg(long, value_name = "PHI", default_value_t = 0.2)]
    pub phi_time: f64,
    /// Hybrid: local volume fraction below which a contact-free particle returns to
    /// event-driven (≤ --phi-time; 0 and 0 make every particle time-driven, i.e. MD).
    #[arg(long, value_name = "PHI", default_value_t = 0.1)]
    pub phi_event: f64,
    /// Hybrid: events of one particle within one time step above which it becomes
    /// time-driven (inelastic collapse, resting contacts).
    #[arg(long, value_name = "N", default_value_t = 50)]
    pub max_events_per_step: u32,
    /// Hybrid: keep the Verlet list and its rebuilds even while no particle is
    /// time-driven, instead of event-driven cell crossings (the same physics; slower in
    /// dilute phases; for comparisons).
    #[arg(long)]
    pub no_cells: bool,
}

/// The counters of a hybrid run, as `run` prints them.
pub fn stats_json(s: &HybridStats) -> Value {
    json!({
        "steps": s.steps,
        "neighbour_rebuilds": s.rebuilds,
        "cell_mode_checks": s.cell_passes,
        "cell_crossings": s.ed.crossings,
        "events": s.ed.events,
        "collisions": s.ed.pair_collisions,
        "wall_collisions": s.ed.wall_collisions,
        "velocity_events": s.ed.velocity_events,
        "exceptions": {
            "rotation_impossible": s.ed.exception_rotation,
            "interference": s.ed.exception_interference,
        },
        "mor_fallbacks": s.ed.mor_fallbacks,
        "switches": {
            "to_time_driven": s.to_time,
            "to_event_driven": s.to_event,
            "guard": s.guard_conversions,
            "guard_late": s.late_conversions,
            "guard_late_max_overlap": s.max_late_overlap,
            "event_budget": s.budget_conversions,
            "transients_ended_early": s.early_transient_ends,
        },
        "time_driven_particle_steps": s.td_particle_steps,
    })
}
