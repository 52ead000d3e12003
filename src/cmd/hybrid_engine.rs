//! The hybrid engine's counters (`--engine hybrid`), as `run` prints them.

use emdstar_hybrid::{EventRule, HybridStats};
use serde_json::{Value, json};

/// The counters of a hybrid run whose events ran by `events`, as `run` prints them.
pub fn stats_json(s: &HybridStats, events: EventRule) -> Value {
    json!({
        "events_by": events.name(),
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
        "frictional_solves": s.ed.frictional_solves,
        "frictional_fallback_kicks": s.ed.frictional_fallback_kicks,
        "switches": {
            "to_time_driven": s.to_time,
            "to_event_driven": s.to_event,
            "guard": s.guard_conversions,
            "guard_late": s.late_conversions,
            "guard_late_max_overlap": s.max_late_overlap,
            "event_budget": s.budget_conversions,
            "events_over_budget": s.vetoed_events,
            "transients_ended_early": s.early_transient_ends,
        },
        "time_driven_particle_steps": s.td_particle_steps,
    })
}
