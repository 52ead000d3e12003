//! What the hybrid keeps per event-driven particle: its event record, and its state
//! before an E^φ (for exception (a)'s undo).

use emdstar_edmd::collision::{LastContact, NONE};

/// The event state of one particle (meaningful while it is ED).
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(crate) struct EdRec {
    /// Time at which the stored position and velocity hold.
    pub stamp: f64,
    pub coll_time: f64,
    /// Partner particle, or `n + w` for wall w.
    pub coll_partner: u32,
    /// The partner's counter at the prediction.
    pub coll_counter: u32,
    /// eMD*: time of the pending E^v event (+∞ if none) and the velocity it applies.
    pub pending_time: f64,
    pub pending_vel: [f64; 3],
    /// eMD*: who shares the transient (particle, `n + w`, or NONE).
    pub partner: u32,
    /// Incremented whenever the particle's trajectory jumps.
    pub counter: u32,
    /// The step whose events `events` counts.
    pub budget_step: u64,
    pub events: u32,
    /// Over its event budget: no own events until the end of the step (on the cell
    /// path it still crosses cells).
    pub frozen: bool,
    /// Cell path: time of the next cell crossing (+∞ on the list path) and the face
    /// (axis·2 + 1 if moving up).
    pub cross_time: f64,
    pub cross_face: u8,
    /// eMD*: the last pair collision.
    pub last_contact: LastContact,
}

impl Default for EdRec {
    fn default() -> Self {
        Self {
            stamp: 0.0,
            coll_time: f64::INFINITY,
            coll_partner: NONE,
            coll_counter: 0,
            pending_time: f64::INFINITY,
            pending_vel: [0.0; 3],
            partner: NONE,
            counter: 0,
            budget_step: 0,
            events: 0,
            frozen: false,
            cross_time: f64::INFINITY,
            cross_face: 0,
            last_contact: LastContact::NONE,
        }
    }
}

/// An ED particle's state before an E^φ: position, velocity, their time, and its cell
/// on the cell path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saved {
    pub(crate) position: [f64; 3],
    pub(crate) velocity: [f64; 3],
    pub(crate) stamp: f64,
    pub(crate) cell: Option<[u32; 3]>,
}
