//! Counters of a run: events by type, eMD* exceptions and fallbacks, and the
//! separations at impact (Bannerman et al. 2014, Fig. 3).

/// Event and exception counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Every event taken from the queue.
    pub events: u64,
    /// Pair collisions executed (eMD*: E^φ events and eMD fallbacks).
    pub pair_collisions: u64,
    /// Wall collisions executed.
    pub wall_collisions: u64,
    /// Stabilising collisions: pairs found overlapping and approaching, collided at
    /// once (Bannerman 2014, Sec. 4.1), and wall events at the top of a flight inside
    /// the wall. Impacts that merely land a round-off inside σ are not counted (see
    /// `separation_histogram`).
    pub stabilising: u64,
    /// Cell crossings (with epochs: swept boxes renewed before the epoch's end).
    pub crossings: u64,
    /// Epochs begun by the epoch broad phase.
    pub epochs: u64,
    /// Predictions found stale by the collision counters.
    pub stale: u64,
    /// E^v events at their scheduled time.
    pub velocity_events: u64,
    /// eMD* exception (a): rotation impossible, eMD fallback used.
    pub exception_rotation: u64,
    /// eMD* exception (b): a collision with a particle in its transient.
    pub exception_interference: u64,
    /// E^v events run early for the partner of a hit particle (BothPartners).
    pub early_partner_updates: u64,
    /// Interfering collisions that no longer approached once the E^v had run.
    pub interference_resolved: u64,
    /// MoR taken from the exact solver because the table did not cover it.
    pub mor_fallbacks: u64,
    /// eMD* with friction: collisions solved by the exact frictional contact (every
    /// frictional pair collision).
    pub frictional_solves: u64,
    /// eMD* with friction: exceptions (a) whose exact impulse would not separate the
    /// pair at touch, given eMD's frictionless kick instead.
    pub frictional_fallback_kicks: u64,
    /// Collisions made elastic by the TC model (within t_c of a party's previous one).
    pub tc_elastic: u64,
    /// Spatial re-sorts of the particle order.
    pub resorts: u64,
    /// Largest overlap (contact distance − centre distance) at a pair impact, re-contacts
    /// apart.
    pub max_impact_overlap: f64,
    /// Impact separations (|r| − σ) in units of σ·2⁻⁵², bins −8..=8 (outer bins
    /// collect everything beyond), re-contacts apart.
    pub separation_histogram: [u64; 17],
    /// eMD*: impacts of two spheres that their last collision left overlapping and that
    /// meet again before separating (see `collision::recontact`).
    pub recontacts: u64,
    /// Largest overlap at a re-contact.
    pub max_recontact_overlap: f64,
    /// Largest ratio of a re-contact's overlap to the overlap l(1 − ε_r) its pair was
    /// left at (at most 1: the overlap never grew).
    pub max_recontact_overlap_ratio: f64,
    /// Σ r_ij ⊗ Δp_i over the pair impulses (xx, yy, zz, xy, xz, yz; kg·m²/s): the
    /// collisional part of the pressure tensor (see [`emdstar_system::StressSums`]).
    pub collisional_virial: emdstar_system::Sym3,
}

impl Stats {
    /// Records a re-contact at `overlap` of a pair left at overlap `placed`.
    #[inline]
    pub fn record_recontact(&mut self, overlap: f64, placed: f64) {
        self.recontacts += 1;
        self.max_recontact_overlap = self.max_recontact_overlap.max(overlap);
        self.max_recontact_overlap_ratio = self.max_recontact_overlap_ratio.max(overlap / placed);
    }

    /// Pair plus wall collisions.
    pub fn collisions(&self) -> u64 {
        self.pair_collisions + self.wall_collisions
    }

    /// Records the separation of a pair at impact.
    #[inline]
    pub fn record_impact(&mut self, distance: f64, contact: f64) {
        let gap = distance - contact;
        if gap < 0.0 {
            self.max_impact_overlap = self.max_impact_overlap.max(-gap);
        }
        let ulps = (gap / (contact * f64::EPSILON)).round().clamp(-8.0, 8.0);
        self.separation_histogram[(ulps + 8.0) as usize] += 1;
    }

    /// All eMD* exceptions: rotations refused plus interferences.
    pub fn exceptions(&self) -> u64 {
        self.exception_rotation + self.exception_interference
    }
}
