//! The event-driven engines' counters (`--engine emd|emdstar`), as `pair` and `run`
//! print them.

use emdstar_edmd::Stats;
use serde_json::{Value, json};

/// The counters of an event-driven run, as `pair` and `run` print them.
pub fn stats_json(s: &Stats) -> Value {
    json!({
        "events": s.events,
        "collisions": s.pair_collisions,
        "wall_collisions": s.wall_collisions,
        "stabilising_collisions": s.stabilising,
        "cell_crossings": s.crossings,
        "epochs": s.epochs,
        "stale_events": s.stale,
        "velocity_events": s.velocity_events,
        "exceptions": {
            "rotation_impossible": s.exception_rotation,
            "interference": s.exception_interference,
            "interference_partner_updates": s.early_partner_updates,
            "interference_no_longer_approaching": s.interference_resolved,
        },
        "fallbacks": {
            "emd_rule": s.exception_rotation,
            "exact_mor": s.mor_fallbacks,
            "frictional_kick_without_friction": s.frictional_fallback_kicks,
        },
        "frictional_solves": s.frictional_solves,
        "tc_elastic_collisions": s.tc_elastic,
        "max_impact_overlap": s.max_impact_overlap,
        "recontacts": {
            "count": s.recontacts,
            "max_overlap": s.max_recontact_overlap,
            "max_overlap_over_placed": s.max_recontact_overlap_ratio,
        },
    })
}
