//! eMD* exception (a) (Müller & Pöschel 2013, Sec. VI B 5) as a probe that the
//! predictions after an E^φ run through.

use emdstar_contact::vec3::{dot, sub};

/// No particle.
pub const NONE: u32 = u32::MAX;

/// The parties of an E^φ just executed, with their state before it, while the
/// predictions that follow look at every particle near them.
///
/// The parties already sit at their rotated positions. A prediction of a party that
/// meets a third particle within contact of the party's new position, and closer to
/// it than to the old one, marks the rotation blocked ([`RotationProbe::blocks`]); the
/// collision step then undoes the E^φ and applies the rule's kick instead.
/// The predictions must visit every particle that could be within contact (the
/// contract of [`crate::collision::Host::predict`]), so no scan of its own is needed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationProbe<S: Copy> {
    /// The parties (a wall collision has one: both entries name it).
    pub parties: [u32; 2],
    /// Each party's state before the rotation, as the host saved it.
    pub before: [S; 2],
    /// Each party's position before the rotation.
    pub old_position: [[f64; 3]; 2],
    pub blocked: bool,
}

impl<S: Copy> RotationProbe<S> {
    /// Which party `i` is, if it is one.
    #[inline]
    pub fn slot_of(&self, i: usize) -> Option<usize> {
        self.parties.iter().position(|&p| p as usize == i)
    }

    /// Whether third particle `k`, at `xk` now, with `r` = (new position of party
    /// `slot`) − `xk` (its image), blocks the rotation: within `contact` of the new
    /// position and closer to it than to the old one (the old separation taken through
    /// `min_image`).
    #[inline(always)]
    pub fn blocks(
        &self,
        slot: usize,
        k: usize,
        r: [f64; 3],
        xk: [f64; 3],
        contact: f64,
        min_image: impl Fn([f64; 3]) -> [f64; 3],
    ) -> bool {
        pushes_deeper(r, self.old_position[slot], xk, contact, min_image)
            && !self.parties.contains(&(k as u32))
    }
}

/// Whether a sphere moved from `old` to the point at `r` from `xk` (minimum image)
/// ends within `contact` of `xk` and closer than it was.
#[inline(always)]
pub fn pushes_deeper(
    r: [f64; 3],
    old: [f64; 3],
    xk: [f64; 3],
    contact: f64,
    min_image: impl Fn([f64; 3]) -> [f64; 3],
) -> bool {
    let d_new = dot(r, r);
    d_new < contact * contact && {
        let d_old = min_image(sub(old, xk));
        d_new < dot(d_old, d_old)
    }
}
