//! Which method runs which contact model: the one place that decides it, so that every
//! engine refuses a model it cannot run with the same message, before anything runs.

use crate::error::{Result, SystemError};
use crate::interactions::{Interaction, Interactions};
use emdstar_contact::{PairLaw, Tangential};

/// The simulation methods, as far as contact models go.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Force-based MD: the history spring and Coulomb sliding.
    Md,
    /// eMD (instantaneous collisions with the central restitution): Walton's rule.
    Emd,
    /// eMD*: the history spring, solved exactly per collision.
    EmdStar,
    /// The hybrid: MD's laws in its time-driven part, Walton's rule with β₀ derived
    /// from them in its event-driven part (linear normal law only).
    Hybrid,
}

impl Method {
    /// The engine's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Self::Md => "md",
            Self::Emd => "emd",
            Self::EmdStar => "emdstar",
            Self::Hybrid => "hybrid",
        }
    }
}

/// Why `method` cannot run the contact `i` (with a wall if `wall`), or `None` if it
/// can.
fn refusal(method: Method, i: &Interaction, wall: bool) -> Option<&'static str> {
    let walton = "tangential_restitution (Walton's rule) is the friction of the \
                  event-driven engines (--engine emd); MD's friction is a tangential spring: \
                  give tangential_stiffness (and tangential_damping), or tangential = \
                  \"coulomb\"";
    match (method, i.tangential()) {
        (_, Tangential::None) => None,
        (Method::Md, Tangential::Walton(_)) => Some(walton),
        (Method::Md, _) => None,
        (Method::Emd, Tangential::Walton(_)) => None,
        (Method::Emd, _) => Some(
            "--engine emd runs friction by Walton's rule: give tangential_restitution, the \
             tangential restitution β₀ ∈ [-1, 1] of sticking impacts (-1 smooth, 1 perfectly \
             rough), instead of MD's tangential_stiffness, tangential_damping and tangential; \
             or run --engine md or emdstar",
        ),
        (Method::EmdStar, Tangential::History(_)) if wall => Some(
            "eMD* has no frictional wall contact yet: give the walls' contacts no friction, \
             or run friction with walls on --engine md",
        ),
        (Method::EmdStar, Tangential::History(_)) => None,
        (Method::EmdStar, Tangential::Coulomb { .. }) => Some(
            "eMD* solves the history spring exactly per collision; pure Coulomb sliding \
             (tangential = \"coulomb\") has no exact solve: give tangential_stiffness (and \
             tangential_damping), or run --engine md",
        ),
        (Method::EmdStar, Tangential::Walton(_)) => Some(
            "eMD* solves MD's history spring exactly, not Walton's rule: give \
             tangential_stiffness (and tangential_damping) instead of tangential_restitution, \
             or run --engine emd",
        ),
        (Method::Hybrid, Tangential::Walton(_)) => Some(
            "the hybrid's time-driven part is MD, whose friction is a tangential spring \
             (its event-driven part derives β₀ from that spring): give tangential_stiffness \
             (and tangential_damping), or tangential = \"coulomb\", instead of \
             tangential_restitution",
        ),
        (Method::Hybrid, _) if matches!(i.law(), PairLaw::Hertz { .. }) => Some(
            "the hybrid runs friction with the linear law only, not with model = \"hertz\": \
             the tangential restitution β₀ of its event-driven collisions is derived from the \
             contact time, which for Hertz contacts depends on the impact speed; use model = \
             \"linear\", or run --engine md or emdstar",
        ),
        (Method::Hybrid, _) => None,
    }
}

impl Interactions {
    /// Errors unless `method` runs every contact of this system (wall contacts only
    /// with `walls` > 0 walls), naming the first material (or pair) it cannot run and
    /// what to do.
    pub fn check_runs_on(&self, method: Method, walls: usize) -> Result<()> {
        let pairs = self.distinct_pairs().map(|i| (i, false));
        let walls = self
            .wall_contacts()
            .take(if walls > 0 { usize::MAX } else { 0 });
        for (i, wall) in pairs.chain(walls.map(|i| (i, true))) {
            if let Some(why) = refusal(method, i, wall) {
                return Err(SystemError::Invalid(format!(
                    "{} has friction = {} with the tangential law \"{}\", which --engine {} \
                     cannot run: {why}",
                    self.describe(i),
                    i.tangential().friction(),
                    i.tangential().name(),
                    method.name()
                )));
            }
        }
        Ok(())
    }
}
