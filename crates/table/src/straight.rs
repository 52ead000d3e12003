//! Evaluation of the degree-7 and degree-10 term sets (the default tables use 7 for the
//! linear model and 10 for Hertz), written out term by term: every loop bound is a constant, so the compiler emits straight-line code (no
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

/// Σ_k v[k]·t^k for up to sixteen terms by Estrin's scheme (pairs, then pairs of
/// pairs, ...), with p = [t, t², t⁴, t⁸]: for eight terms a dependency chain of three
/// multiply-adds instead of Horner's seven.
#[inline(always)]
fn estrin(v: &[[f64; NQ]], p: [f64; 4]) -> [f64; NQ] {
    match v.len() {
        n @ 0..=8 => estrin8(v, n, p),
        n => ma(estrin8(v, 8, p), p[3], estrin8(&v[8..], n - 8, p)),
    }
}

/// Σ_{k<n} v[k]·t^k for n ≤ 8.
#[inline(always)]
fn estrin8(v: &[[f64; NQ]], n: usize, p: [f64; 4]) -> [f64; NQ] {
    match n {
        0 => [0.0; NQ],
        1..=4 => quad(v, 0, n, p),
        _ => ma(quad(v, 0, 4, p), p[2], quad(v, 4, n - 4, p)),
    }
}

/// Σ_{k<n} v[at + k]·t^k for n ≤ 4.
#[inline(always)]
fn quad(v: &[[f64; NQ]], at: usize, n: usize, p: [f64; 4]) -> [f64; NQ] {
    let [t, t2, _, _] = p;
    match n {
        1 => v[at],
        2 => ma(v[at], t, v[at + 1]),
        3 => ma(ma(v[at], t, v[at + 1]), t2, v[at + 2]),
        _ => ma(ma(v[at], t, v[at + 1]), t2, ma(v[at + 2], t, v[at + 3])),
    }
}

/// Σ_k c[OFF + k]·z^k.
#[inline(always)]
fn line<K: Coef, const OFF: usize, const NK: usize>(c: &[K], p: [f64; 4]) -> [f64; NQ] {
    let mut v = [[0.0; NQ]; NK];
    for (k, v) in v.iter_mut().enumerate() {
        *v = c[OFF + k].wide();
    }
    estrin(&v, p)
}

/// Σ_j v[j]·y^j.
#[inline(always)]
fn outer<const M: usize>(v: [[f64; NQ]; M], p: [f64; 4]) -> [f64; NQ] {
    estrin(&v, p)
}

/// [t, t², t⁴, t⁸].
#[inline(always)]
fn powers(t: f64) -> [f64; 4] {
    let t2 = t * t;
    let t4 = t2 * t2;
    [t, t2, t4, t4 * t4]
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

/// Degree 10 over the axes xyz (286 terms).
#[inline(always)]
pub fn eval10_xyz<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 286] = c[..286].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 11), (11, 10), (21, 9), (30, 8), (38, 7), (45, 6), (51, 5), (56, 4), (60, 3), (63, 2), (65, 1)],
            [(66, 10), (76, 9), (85, 8), (93, 7), (100, 6), (106, 5), (111, 4), (115, 3), (118, 2), (120, 1)],
            [(121, 9), (130, 8), (138, 7), (145, 6), (151, 5), (156, 4), (160, 3), (163, 2), (165, 1)],
            [(166, 8), (174, 7), (181, 6), (187, 5), (192, 4), (196, 3), (199, 2), (201, 1)],
            [(202, 7), (209, 6), (215, 5), (220, 4), (224, 3), (227, 2), (229, 1)],
            [(230, 6), (236, 5), (241, 4), (245, 3), (248, 2), (250, 1)],
            [(251, 5), (256, 4), (260, 3), (263, 2), (265, 1)],
            [(266, 4), (270, 3), (273, 2), (275, 1)],
            [(276, 3), (279, 2), (281, 1)],
            [(282, 2), (284, 1)],
            [(285, 1)])
}

/// Degree 10 over the axes xy (66 terms).
#[inline(always)]
pub fn eval10_xy<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 66] = c[..66].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1), (5, 1), (6, 1), (7, 1), (8, 1), (9, 1), (10, 1)],
            [(11, 1), (12, 1), (13, 1), (14, 1), (15, 1), (16, 1), (17, 1), (18, 1), (19, 1), (20, 1)],
            [(21, 1), (22, 1), (23, 1), (24, 1), (25, 1), (26, 1), (27, 1), (28, 1), (29, 1)],
            [(30, 1), (31, 1), (32, 1), (33, 1), (34, 1), (35, 1), (36, 1), (37, 1)],
            [(38, 1), (39, 1), (40, 1), (41, 1), (42, 1), (43, 1), (44, 1)],
            [(45, 1), (46, 1), (47, 1), (48, 1), (49, 1), (50, 1)],
            [(51, 1), (52, 1), (53, 1), (54, 1), (55, 1)],
            [(56, 1), (57, 1), (58, 1), (59, 1)],
            [(60, 1), (61, 1), (62, 1)],
            [(63, 1), (64, 1)],
            [(65, 1)])
}

/// Degree 10 over the axes yz (66 terms).
#[inline(always)]
pub fn eval10_yz<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 66] = c[..66].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 11), (11, 10), (21, 9), (30, 8), (38, 7), (45, 6), (51, 5), (56, 4), (60, 3), (63, 2), (65, 1)])
}

/// Degree 10 over the axes y (11 terms).
#[inline(always)]
pub fn eval10_y<K: Coef>(c: &[K], t: [f64; 3]) -> [f64; NQ] {
    let c: &[K; 11] = c[..11].try_into().expect("a whole patch");
    let [x, y, z] = t;
    nested!(c, x, y, z;
            [(0, 1), (1, 1), (2, 1), (3, 1), (4, 1), (5, 1), (6, 1), (7, 1), (8, 1), (9, 1), (10, 1)])
}
