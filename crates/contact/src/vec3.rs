//! The workspace's vector policy: engines keep 3-vectors as plain `[f64; 3]` (compact,
//! `Copy`, laid out as they are stored), with the few operations below; the pair
//! physics of this crate and of `emdstar-mor` computes with nalgebra's [`Vec3`], and
//! [`to_na`] and [`from_na`] are the one place where the two meet.
//!
//! Each function spells out its components in a fixed order, so results do not depend
//! on how a caller was compiled.

use crate::Vec3;

/// a · b.
#[inline(always)]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a − b.
#[inline(always)]
pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a + b.
#[inline(always)]
pub fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// s · a.
#[inline(always)]
pub fn scale(s: f64, a: [f64; 3]) -> [f64; 3] {
    [s * a[0], s * a[1], s * a[2]]
}

/// a + s · b.
#[inline(always)]
pub fn add_scaled(a: [f64; 3], s: f64, b: [f64; 3]) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// |a|².
#[inline(always)]
pub fn norm2(a: [f64; 3]) -> f64 {
    dot(a, a)
}

/// |a|.
#[inline(always)]
pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// a × b.
#[inline(always)]
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The nalgebra vector of `a`.
#[inline(always)]
pub fn to_na(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

/// The components of `v`.
#[inline(always)]
pub fn from_na(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn operations_agree_with_nalgebra() {
        let (a, b) = ([1.5, -2.0, 0.25], [0.5, 4.0, -3.0]);
        let (na, nb) = (to_na(a), to_na(b));
        assert_eq!(dot(a, b), na.dot(&nb));
        assert_eq!(from_na(&na.cross(&nb)), cross(a, b));
        assert_eq!(from_na(&(na - nb)), sub(a, b));
        assert_eq!(from_na(&(na + nb)), add(a, b));
        assert_eq!(norm(a), na.norm());
        assert_eq!(add_scaled(a, 2.0, b), add(a, scale(2.0, b)));
    }
}
