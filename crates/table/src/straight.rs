//! Evaluation of the degree-7 term sets (the default tables'), written out term by
//! term: every loop bound is a constant, so the compiler emits straight-line code (no
//! loop counters). Each (i, j) line is a polynomial in z, each i-group one in y of the
//! lines, the whole one in x of the groups; all three by Estrin's scheme, whose short
//! dependency chains let the processor overlap the work (a lookup waits on latency, not
//! on the number of operations). The term lists ((offset, length) of each (i, j) line,
//! grouped by i) follow the storage order of [`Terms`](crate::Terms). The results
//! agree with [`Terms::horner`](crate::Terms::horner) to rounding.

use crate::poly::{Coef, NQ};

/// a + t·b per quantity (a multiply and an add: no FMA, the same bits everywhere).
#[inline(always)]
fn ma(a: [f64; NQ], t: f64, b: [f64; NQ]) -> [f64; NQ] {
    [
        a[0] + t * b[0],
        a[1] + t * b[1],
        a[2] + t * b[2],
        a[3] + t * b[3],
    ]
}

/// Σ_k v[k]·t^k for up to eight terms by Estrin's scheme (pairs, then pairs of pairs),
/// with p = [t, t², t⁴]: a dependency chain of three multiply-adds instead of
/// Horner's seven.
#[inline(always)]
fn estrin(v: &[[f64; NQ]], p: [f64; 3]) -> [f64; NQ] {
    match v.len() {
        0 => [0.0; NQ],
        n @ 1..=4 => quad(v, 0, n, p),
        n => ma(quad(v, 0, 4, p), p[2], quad(v, 4, n - 4, p)),
    }
}

/// Σ_{k<n} v[at + k]·t^k for n ≤ 4.
#[inline(always)]
fn quad(v: &[[f64; NQ]], at: usize, n: usize, p: [f64; 3]) -> [f64; NQ] {
    let [t, t2, _] = p;
    match n {
        1 => v[at],
        2 => ma(v[at], t, v[at + 1]),
        3 => ma(ma(v[at], t, v[at + 1]), t2, v[at + 2]),
        _ => ma(ma(v[at], t, v[at + 1]), t2, ma(v[at + 2], t, v[at + 3])),
    }
}

/// Σ_k c[OFF + k]·z^k.
#[inline(always)]
fn line<K: Coef, const OFF: usize, const NK: usize>(c: &[K], p: [f64; 3]) -> [f64; NQ] {
    let mut v = [[0.0; NQ]; NK];
    for (k, v) in v.iter_mut().enumerate() {
        *v = c[OFF + k].wide();
    }
    estrin(&v, p)
}

/// Σ_j v[j]·y^j.
#[inline(always)]
fn outer<const M: usize>(v: [[f64; NQ]; M], p: [f64; 3]) -> [f64; NQ] {
    estrin(&v, p)
}

/// [t, t², t⁴].
#[inline(always)]
fn powers(t: f64) -> [f64; 3] {
    let t2 = t * t;
    [t, t2, t2 * t2]
}

macro_rules! nested {
    ($c:ident, $x:ident, $y:ident, $z:ident; $([$(($off:literal, $nk:literal)),*]),*) => {{
        let (px, py, pz) = (powers($x), powers($y), powers($z));
        outer([$(outer([$(line::<K, $off, $nk>(&$c[..], pz)),*], py)),*], px)
    }};
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
