//! Nested Horner evaluation of the degree-7 term sets (the default tables'), written
//! out term by term: every loop bound is a constant, so the compiler emits straight-line
//! code (no loop counters) and overlaps the independent z-lines. The arithmetic and its
//! order are those of [`Terms::eval`](crate::Terms::eval)'s general path, so the results are bitwise
//! the same. The term lists ((offset, length) of each (i, j) line, grouped by i) follow
//! the storage order of [`Terms`](crate::Terms).

use crate::poly::{Coef, NQ, fmadd};

/// Σ_k c[OFF + k]·z^k by Horner.
#[inline(always)]
fn line<K: Coef, const OFF: usize, const NK: usize>(c: &[K], z: f64) -> [f64; NQ] {
    let mut r = c[OFF + NK - 1].wide();
    let mut k = NK - 1;
    while k > 0 {
        k -= 1;
        r = fmadd(r, z, &c[OFF + k]);
    }
    r
}

/// Σ_j v[j]·y^j by Horner, from a zero start (as the general path).
#[inline(always)]
fn outer<const M: usize>(v: [[f64; NQ]; M], y: f64) -> [f64; NQ] {
    let mut p = [0.0; NQ];
    let mut j = M;
    while j > 0 {
        j -= 1;
        p = fmadd(p, y, &v[j]);
    }
    p
}

macro_rules! nested {
    ($c:ident, $x:ident, $y:ident, $z:ident; $([$(($off:literal, $nk:literal)),*]),*) => {
        outer([$(outer([$(line::<K, $off, $nk>(&$c[..], $z)),*], $y)),*], $x)
    };
}

/// Degree 7 over the axes xyz (120 terms).
#[inline(always)]
pub fn eval7_xyz<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 120] = c[..120].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 8), (8, 7), (15, 6), (21, 5), (26, 4), (30, 3), (33, 2), (35, 1)],
            [(36, 7), (43, 6), (49, 5), (54, 4), (58, 3), (61, 2), (63, 1)],
            [(64, 6), (70, 5), (75, 4), (79, 3), (82, 2), (84, 1)],
            [(85, 5), (90, 4), (94, 3), (97, 2), (99, 1)],
            [(100, 4), (104, 3), (107, 2), (109, 1)],
            [(110, 3), (113, 2), (115, 1)],
            [(116, 2), (118, 1)],
            [(119, 1)])
}

/// Degree 7 over the axes xy (36 terms).
#[inline(always)]
pub fn eval7_xy<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 36] = c[..36].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1), (5, 1), (6, 1), (7, 1)],
            [(8, 1), (9, 1), (10, 1), (11, 1), (12, 1), (13, 1), (14, 1)],
            [(15, 1), (16, 1), (17, 1), (18, 1), (19, 1), (20, 1)],
            [(21, 1), (22, 1), (23, 1), (24, 1), (25, 1)],
            [(26, 1), (27, 1), (28, 1), (29, 1)],
            [(30, 1), (31, 1), (32, 1)],
            [(33, 1), (34, 1)],
            [(35, 1)])
}

/// Degree 7 over the axes yz (36 terms).
#[inline(always)]
pub fn eval7_yz<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 36] = c[..36].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 8), (8, 7), (15, 6), (21, 5), (26, 4), (30, 3), (33, 2), (35, 1)])
}

/// Degree 7 over the axes y (8 terms).
#[inline(always)]
pub fn eval7_y<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 8] = c[..8].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1), (5, 1), (6, 1), (7, 1)])
}
