//! One piecewise-polynomial function of the four stored quantities over a box: a
//! uniform grid of top cells, each refined by bisection into a binary tree whose
//! leaves (patches) carry a polynomial of bounded total degree in the patch's
//! coordinates t ∈ [−1, 1]³.
//!
//! A lookup is O(1) to the top cell, a few steps down its tree (each one compare and
//! one load from a small array), and one polynomial: the patch's coefficients are one
//! contiguous block.

use crate::error::TableError;
use crate::poly::{NQ, Terms};

/// Marks a leaf in [`PieceParts::tree`].
pub const LEAF: i64 = -1;

/// A piece as stored in a file (and as the generator builds it).
#[derive(Debug, Clone, PartialEq)]
pub struct PieceParts {
    /// Top cells per axis (1 along an axis the piece does not depend on).
    pub cells: [usize; 3],
    /// Root node of each top cell, in C order over (a, b, c).
    pub roots: Vec<usize>,
    /// Per node: [axis, first child] of a split (children at first, first + 1: below
    /// and above `split`), or [[`LEAF`], patch].
    pub tree: Vec<[i64; 2]>,
    /// Per node: the split coordinate (unused for leaves).
    pub split: Vec<f64>,
    /// Chebyshev coefficients, `[patch][term][quantity]`; an all-NaN patch is not
    /// tabulated (only where the piece allows it). Rounded to multiples of the table's
    /// quantum (as the file stores them).
    pub cheb: Vec<[f64; NQ]>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    split: f64,
    /// 0, 1, 2: the split axis; 3: a leaf.
    axis: u8,
    /// First child, or the patch of a leaf.
    next: u32,
}

const LEAF_AXIS: u8 = 3;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Patch {
    centre: [f64; 3],
    inv_half: [f64; 3],
}

/// A validated piece, ready for lookups.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    parts: PieceParts,
    lo: [f64; 3],
    hi: [f64; 3],
    /// Cells of the start grid per axis and their number per unit length.
    grid: [usize; 3],
    grid_scale: [f64; 3],
    /// Per start-grid cell, the deepest node whose box holds the whole cell: a lookup
    /// starts there, one load instead of the top levels of its tree.
    start: Vec<u32>,
    nodes: Vec<Node>,
    patches: Vec<Patch>,
    /// Patch boxes [lo, hi] per axis.
    boxes: Vec<[[f64; 2]; 3]>,
    terms: Terms,
    /// Monomial coefficients of total degree ≤ 1, float64, `[patch][low term]`, and
    /// the axis of each low term (None: the constant).
    low: Vec<[f64; NQ]>,
    low_axes: Vec<Option<usize>>,
    /// Monomial coefficients of total degree ≥ 2 (zero in the low slots), float32:
    /// small next to the linear part, they halve the bytes a lookup reads.
    high: Vec<[f32; NQ]>,
}

/// Start-grid cells per top cell along an axis at most (2^5), and start-grid cells in
/// all at most.
const GRID_REFINE: usize = 5;
const GRID_MAX: usize = 1 << 15;

/// The start grid of a piece: each top cell cut into 2^r equal parts along its axes
/// (r as large as [`GRID_MAX`] and the tree's size allow), and for each part the deepest node whose box
/// holds it. Splits within a tiny margin of a part's faces stop the descent, so a
/// lookup that rounding puts into the neighbouring part still compares against them.
fn start_grid(
    cells: &[usize; 3],
    roots: &[u32],
    nodes: &[Node],
    lo: [f64; 3],
    hi: [f64; 3],
    active: [bool; 3],
) -> ([usize; 3], Vec<u32>) {
    let dims = active.iter().filter(|a| **a).count().max(1);
    let top: usize = cells.iter().product();
    // No finer than about eight grid cells per patch: beyond, it only costs memory.
    let limit = GRID_MAX.min(8 * nodes.len().max(1));
    let mut r = 0;
    while r < GRID_REFINE && top << (dims * (r + 1)) <= limit {
        r += 1;
    }
    let grid: [usize; 3] = std::array::from_fn(|k| if active[k] { cells[k] << r } else { 1 });
    let width: [f64; 3] = std::array::from_fn(|k| (hi[k] - lo[k]) / grid[k] as f64);
    let mut start = Vec::with_capacity(grid.iter().product());
    for i in 0..grid[0] {
        for j in 0..grid[1] {
            for k in 0..grid[2] {
                let idx = [i, j, k];
                // (Along a missing axis the index is 0 and stays 0.)
                let root = roots[((i >> r) * cells[1] + (j >> r)) * cells[2] + (k >> r)];
                let mut n = root as usize;
                loop {
                    let node = nodes[n];
                    if node.axis == LEAF_AXIS {
                        break;
                    }
                    let a = node.axis as usize;
                    let (cell_lo, cell_hi) = (
                        lo[a] + width[a] * idx[a] as f64,
                        lo[a] + width[a] * (idx[a] + 1) as f64,
                    );
                    let margin = 1e-9 * width[a];
                    if node.split >= cell_hi + margin {
                        n = node.next as usize;
                    } else if node.split <= cell_lo - margin {
                        n = node.next as usize + 1;
                    } else {
                        break;
                    }
                }
                start.push(n as u32);
            }
        }
    }
    (grid, start)
}

/// [`Terms::eval`] compiled with 256-bit AVX registers: the four quantities of a
/// term are one load and one multiply-add pair. Separate multiplies and adds (no FMA)
/// keep the results bitwise equal to the portable path.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn eval_avx(terms: &Terms, block: &[[f32; NQ]], t: [f64; 3]) -> [f64; NQ] {
    terms.eval(block, t)
}

impl Piece {
    /// Checks a piece over the box `lo..hi` (lo = hi on an axis the piece does not
    /// depend on) with polynomials of total degree `degree`.
    pub fn new(
        name: &str,
        mut parts: PieceParts,
        lo: [f64; 3],
        hi: [f64; 3],
        degree: usize,
        quantum: f64,
        nan_ok: bool,
    ) -> Result<Self, TableError> {
        let bad = |why: String| TableError::Corrupt(format!("{name}: {why}"));
        let active: [bool; 3] = std::array::from_fn(|k| hi[k] > lo[k]);
        for k in 0..3 {
            if !(lo[k].is_finite() && hi[k].is_finite() && hi[k] >= lo[k]) {
                return Err(bad(format!("axis {k} spans [{}, {}]", lo[k], hi[k])));
            }
            let n = parts.cells[k];
            if n == 0 || n > 1 << 16 || (!active[k] && n != 1) {
                return Err(bad(format!("{n} top cells along axis {k}")));
            }
        }
        let ncells: usize = parts.cells.iter().product();
        if parts.roots.len() != ncells {
            return Err(bad(format!(
                "{} roots for {ncells} top cells",
                parts.roots.len()
            )));
        }
        let nn = parts.tree.len();
        if parts.split.len() != nn || nn > u32::MAX as usize / 2 {
            return Err(bad("tree and split lengths differ".into()));
        }
        let max = std::array::from_fn(|k| if active[k] { degree } else { 0 });
        let terms = Terms::new(degree, max);
        let nt = terms.len();
        if nt == 0 || parts.cheb.len() % nt != 0 {
            return Err(bad(format!(
                "{} coefficient rows are not a whole number of patches of {nt} terms",
                parts.cheb.len()
            )));
        }
        let np = parts.cheb.len() / nt;
        // The file holds multiples of the quantum: round here, so that a table in
        // memory equals its file.
        for c in parts.cheb.iter_mut() {
            *c = c.map(|x| crate::pack::quantize(x, quantum));
        }
        let mut nodes = Vec::with_capacity(nn);
        for (t, &s) in parts.tree.iter().zip(&parts.split) {
            let [axis, next] = *t;
            let ok_axis = axis == LEAF || (0..3).contains(&axis) && active[axis as usize];
            if !ok_axis || next < 0 || next > u32::MAX as i64 - 1 || s.is_nan() {
                return Err(bad(format!("malformed tree node {t:?}")));
            }
            nodes.push(Node {
                split: s,
                axis: if axis == LEAF { LEAF_AXIS } else { axis as u8 },
                next: next as u32,
            });
        }
        // Walk every tree from its top cell: each node and each patch is reached once,
        // children lie after their parent (so walks end), splits fall inside their box.
        let mut seen = vec![false; nn];
        let mut boxes: Vec<Option<[[f64; 2]; 3]>> = vec![None; np];
        let width: [f64; 3] = std::array::from_fn(|k| (hi[k] - lo[k]) / parts.cells[k] as f64);
        let mut roots = Vec::with_capacity(ncells);
        for (cell, &root) in parts.roots.iter().enumerate() {
            let idx = [
                cell / (parts.cells[1] * parts.cells[2]),
                cell / parts.cells[2] % parts.cells[1],
                cell % parts.cells[2],
            ];
            let cell_box: [[f64; 2]; 3] = std::array::from_fn(|k| {
                let a = lo[k] + width[k] * idx[k] as f64;
                let b = if idx[k] + 1 == parts.cells[k] {
                    hi[k]
                } else {
                    lo[k] + width[k] * (idx[k] + 1) as f64
                };
                [a, b]
            });
            if root >= nn {
                return Err(bad(format!("root {root} of cell {cell} does not exist")));
            }
            roots.push(root as u32);
            let mut stack = vec![(root, cell_box)];
            while let Some((n, bx)) = stack.pop() {
                if std::mem::replace(&mut seen[n], true) {
                    return Err(bad(format!("node {n} is reached twice")));
                }
                let node = nodes[n];
                let next = node.next as usize;
                if node.axis == LEAF_AXIS {
                    match boxes.get_mut(next) {
                        Some(slot @ None) => *slot = Some(bx),
                        _ => {
                            return Err(bad(format!(
                                "leaf {n} names patch {next}, which is missing or taken"
                            )));
                        }
                    }
                    continue;
                }
                let k = node.axis as usize;
                if next <= n || next + 1 >= nn {
                    return Err(bad(format!("node {n} has children {next}, {}", next + 1)));
                }
                if !(node.split > bx[k][0] && node.split < bx[k][1]) {
                    return Err(bad(format!(
                        "node {n} splits axis {k} at {} outside its box {:?}",
                        node.split, bx[k]
                    )));
                }
                let (mut below, mut above) = (bx, bx);
                below[k][1] = node.split;
                above[k][0] = node.split;
                stack.push((next, below));
                stack.push((next + 1, above));
            }
        }
        if let Some(n) = seen.iter().position(|s| !s) {
            return Err(bad(format!("node {n} is not reachable from any top cell")));
        }
        let boxes: Vec<[[f64; 2]; 3]> = boxes
            .into_iter()
            .enumerate()
            .map(|(p, b)| b.ok_or_else(|| bad(format!("patch {p} belongs to no leaf"))))
            .collect::<Result<_, _>>()?;
        let mut mono = Vec::with_capacity(parts.cheb.len());
        for (p, c) in parts.cheb.chunks_exact(nt).enumerate() {
            let all_nan = c.iter().flatten().all(|x| x.is_nan());
            if all_nan && nan_ok {
                mono.extend(std::iter::repeat_n([f64::NAN; NQ], nt));
                continue;
            }
            if let Some(x) = c.iter().flatten().find(|x| !x.is_finite()) {
                return Err(bad(format!("patch {p} holds a non-finite coefficient {x}")));
            }
            if let Some(x) = c
                .iter()
                .flatten()
                .find(|&&x| !crate::pack::packable(x, quantum))
            {
                return Err(bad(format!(
                    "patch {p} holds a coefficient {x} beyond 2^53 quanta of {quantum}"
                )));
            }
            mono.extend(terms.chebyshev_to_monomial(c));
        }
        let low_terms: Vec<usize> = (0..nt).filter(|&k| terms.is_low(k)).collect();
        let low_axes = low_terms
            .iter()
            .map(|&k| terms.powers[k].iter().position(|&e| e == 1))
            .collect();
        let mut low = Vec::with_capacity(np * low_terms.len());
        let mut high = Vec::with_capacity(np * nt);
        for block in mono.chunks_exact(nt) {
            low.extend(low_terms.iter().map(|&k| block[k]));
            high.extend(block.iter().enumerate().map(|(k, c)| {
                if terms.is_low(k) {
                    [0.0; NQ]
                } else {
                    c.map(|x| x as f32)
                }
            }));
        }
        let patches = boxes
            .iter()
            .map(|b| Patch {
                centre: std::array::from_fn(|k| 0.5 * (b[k][0] + b[k][1])),
                inv_half: std::array::from_fn(|k| {
                    if active[k] {
                        2.0 / (b[k][1] - b[k][0])
                    } else {
                        0.0
                    }
                }),
            })
            .collect();
        let (grid, start) = start_grid(&parts.cells, &roots, &nodes, lo, hi, active);
        let grid_scale = std::array::from_fn(|k| {
            if active[k] {
                grid[k] as f64 / (hi[k] - lo[k])
            } else {
                0.0
            }
        });
        Ok(Self {
            parts,
            lo,
            hi,
            grid,
            grid_scale,
            start,
            nodes,
            patches,
            boxes,
            terms,
            low,
            low_axes,
            high,
        })
    }

    /// The four quantities at `x`, which must lie in the piece's box (NaN where the
    /// piece is not tabulated).
    #[inline(always)]
    pub fn eval(&self, x: [f64; 3]) -> [f64; NQ] {
        let (patch, t) = self.locate(x);
        let nt = self.terms.len();
        // (Asking for the block's cache lines ahead, a prefetch of each, made random
        // lookups 3-8 % slower: the hardware's own prefetcher follows the evaluation.)
        let block = &self.high[patch * nt..(patch + 1) * nt];
        let nl = self.low_axes.len();
        let mut q = self.linear_part(&self.low[patch * nl..(patch + 1) * nl], t);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU supports AVX (checked just above).
            let h = unsafe { eval_avx(&self.terms, block, t) };
            for i in 0..NQ {
                q[i] += h[i];
            }
            return q;
        }
        let h = self.terms.eval(block, t);
        for i in 0..NQ {
            q[i] += h[i];
        }
        q
    }

    /// The terms of degree ≤ 1 at t.
    #[inline(always)]
    fn linear_part(&self, low: &[[f64; NQ]], t: [f64; 3]) -> [f64; NQ] {
        let mut q = [0.0; NQ];
        for (c, axis) in low.iter().zip(&self.low_axes) {
            let w = axis.map_or(1.0, |a| t[a]);
            for i in 0..NQ {
                q[i] += c[i] * w;
            }
        }
        q
    }

    /// The patch holding `x` and the local coordinates there.
    #[inline(always)]
    fn locate(&self, x: [f64; 3]) -> (usize, [f64; 3]) {
        let g = self.grid;
        let idx: [usize; 3] = std::array::from_fn(|k| {
            // x ≥ lo up to rounding; `as` saturates, so a hair below lo gives cell 0.
            (((x[k] - self.lo[k]) * self.grid_scale[k]) as usize).min(g[k] - 1)
        });
        let mut n = self.start[(idx[0] * g[1] + idx[1]) * g[2] + idx[2]] as usize;
        let mut node = self.nodes[n];
        while node.axis != LEAF_AXIS {
            n = node.next as usize + (x[node.axis as usize] >= node.split) as usize;
            node = self.nodes[n];
        }
        let p = &self.patches[node.next as usize];
        let t = std::array::from_fn(|k| (x[k] - p.centre[k]) * p.inv_half[k]);
        (node.next as usize, t)
    }

    /// What the file stores.
    pub fn parts(&self) -> &PieceParts {
        &self.parts
    }

    /// Number of patches.
    pub fn patch_count(&self) -> usize {
        self.boxes.len()
    }

    /// The box [lo, hi] per axis of every patch.
    pub fn patch_boxes(&self) -> &[[[f64; 2]; 3]] {
        &self.boxes
    }

    /// The piece's range per axis.
    pub fn range(&self) -> [[f64; 2]; 3] {
        std::array::from_fn(|k| [self.lo[k], self.hi[k]])
    }

    /// The polynomial terms of every patch.
    pub fn terms(&self) -> &Terms {
        &self.terms
    }
}
