//! Re-contacts: impacts of two spheres that eMD* left overlapping at their last
//! collision and that meet again before they have separated.
//!
//! The E^φ event puts a pair at the separation l·ε_r in which the contact ends
//! (Müller & Pöschel 2013, Sec. VI B 2, item 3, Eq. 28); a viscoelastic contact ends
//! before the overlap is gone, so ε_r < 1 and the pair overlaps by l(1 − ε_r) until it
//! has separated. If a third particle turns one of them back in that time (exceptions
//! of Sec. VI B 5), the pair meets again while still overlapping: a three-body contact
//! that eMD* does not resolve, and which the event engine executes at once as a
//! stabilising collision (Bannerman et al. 2014, Sec. 4.1). Such an impact is no
//! failure of event detection, so it is counted apart from the impacts of pairs that
//! meet from outside contact, whose overlap stays at round-off. Its overlap never
//! exceeds the one the pair was placed at, which the counters check.

use serde::{Deserialize, Serialize};

use super::NONE;

/// A particle's last pair collision: the partner (or [`NONE`]) and the overlap
/// l(1 − ε_r) at which that collision left the pair (0 unless an eMD* E^φ placed it);
/// and the time of its last collision with a particle or a wall (−∞ before the first),
/// which the TC model reads ([`super::Rules::pair`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LastContact {
    pub partner: u32,
    pub overlap: f64,
    pub time: f64,
}

impl LastContact {
    /// No collision yet.
    pub const NONE: Self = Self {
        partner: NONE,
        overlap: 0.0,
        time: f64::NEG_INFINITY,
    };
}

impl Default for LastContact {
    fn default() -> Self {
        Self::NONE
    }
}

/// Whether the impact of `i` and `j` at `overlap` > 0 is a re-contact, given each
/// one's last collision: the overlap the pair was placed at if so (the larger one if
/// both name each other).
#[inline]
pub fn recontact(i: usize, j: usize, last: [LastContact; 2], overlap: f64) -> Option<f64> {
    if overlap <= 0.0 {
        return None;
    }
    let named = |c: LastContact, other: usize| {
        (c.partner == other as u32 && c.overlap > 0.0).then_some(c.overlap)
    };
    match (named(last[0], j), named(last[1], i)) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_pair_that_met_last_and_still_overlaps_is_a_recontact() {
        let placed = |partner: u32, overlap: f64| LastContact {
            partner,
            overlap,
            time: 0.0,
        };
        // i = 3 and j = 7 met last; 7 has met 9 since.
        let last = [placed(7, 2e-5), placed(9, 1e-5)];
        assert_eq!(recontact(3, 7, last, 1e-5), Some(2e-5));
        // Touching from outside contact is never a re-contact.
        assert_eq!(recontact(3, 7, last, 0.0), None);
        assert_eq!(recontact(3, 7, last, -1e-16), None);
        // Strangers are not, nor a pair that no E^φ left overlapping.
        assert_eq!(recontact(3, 8, last, 1e-5), None);
        assert_eq!(
            recontact(3, 7, [placed(7, 0.0), placed(3, 0.0)], 1e-16),
            None
        );
        // Either side naming the other suffices.
        let last = [placed(9, 1e-5), placed(3, 4e-5)];
        assert_eq!(recontact(3, 7, last, 1e-5), Some(4e-5));
        assert_eq!(
            recontact(3, 7, [LastContact::NONE, LastContact::NONE], 1e-5),
            None
        );
    }
}
