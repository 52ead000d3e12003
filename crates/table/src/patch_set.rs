//! The evaluator of a piecewise polynomial: a uniform grid of top cells over a box,
//! each refined by bisection into a binary tree whose leaves (patches) carry a
//! polynomial of bounded total degree in the patch's coordinates t ∈ [−1, 1]³.
//!
//! A lookup is O(1) to a start node (a fine grid over the top cells remembers the
//! deepest node holding each of its cells), a few steps down the tree (each one
//! compare and one load from a small array), and one polynomial: the patch's
//! coefficients are one contiguous block. A stored [`Piece`](crate::Piece) and a
//! pair's own slice ([`PairTable`](crate::PairTable)) evaluate through it.

use crate::poly::{NQ, Terms};

/// A tree node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Node {
    pub split: f64,
    /// 0, 1, 2: the split axis; [`LEAF_AXIS`]: a leaf.
    pub axis: u8,
    /// First child (the second follows it), or the patch of a leaf.
    pub next: u32,
}

pub(crate) const LEAF_AXIS: u8 = 3;

/// A checked tree: the root of each top cell (`cells` per axis, C order) and the nodes,
/// children after their parent.
pub(crate) struct Tree<'a> {
    pub cells: [usize; 3],
    pub roots: &'a [u32],
    pub nodes: Vec<Node>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Patch {
    centre: [f64; 3],
    inv_half: [f64; 3],
}

/// Patch centre and 2/width per axis (0 along an axis the polynomial lacks): t =
/// (x − centre)·inv_half.
pub(crate) fn patch_frame(b: &[[f64; 2]; 3], active: [bool; 3]) -> ([f64; 3], [f64; 3]) {
    (
        std::array::from_fn(|k| 0.5 * (b[k][0] + b[k][1])),
        std::array::from_fn(|k| {
            if active[k] {
                2.0 / (b[k][1] - b[k][0])
            } else {
                0.0
            }
        }),
    )
}

/// A piecewise polynomial ready for lookups (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PatchSet {
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
    terms: Terms,
    /// Monomial coefficients of total degree ≤ 1, float64, `[patch][low term]`, and
    /// the axis of each low term (None: the constant).
    low: Vec<[f64; NQ]>,
    low_axes: Vec<Option<usize>>,
    /// Monomial coefficients of total degree ≥ 2 (zero in the low slots), float32:
    /// small next to the linear part, they halve the bytes a lookup reads.
    high: Vec<[f32; NQ]>,
}

/// How fine a start grid may be: its cells per top cell along an axis at most
/// (2^`refine`), and per tree node at most (`per_node`; all told at most
/// [`GRID_MAX`]). A stored piece takes [`StartGrid::PIECE`]: about eight per patch,
/// beyond which the grid only costs memory. A pair's own table, small and read for
/// every lookup of the pair, takes [`StartGrid::SLICE`]: 64 per node, so that most
/// lookups start at their leaf or one split above it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StartGrid {
    refine: usize,
    per_node: usize,
}

impl StartGrid {
    pub(crate) const PIECE: Self = Self {
        refine: 5,
        per_node: 8,
    };
    pub(crate) const SLICE: Self = Self {
        refine: 7,
        per_node: 64,
    };
}

const GRID_MAX: usize = 1 << 15;

/// The start grid of a piece: each top cell cut into 2^r equal parts along its axes
/// (r as large as `fineness` allows), and for each part the deepest node whose box
/// holds it. Splits within a tiny margin of a part's faces stop the descent, so a
/// lookup that rounding puts into the neighbouring part still compares against them.
fn start_grid(
    tree: &Tree,
    lo: [f64; 3],
    hi: [f64; 3],
    active: [bool; 3],
    fineness: StartGrid,
) -> ([usize; 3], Vec<u32>) {
    let (cells, roots, nodes) = (&tree.cells, tree.roots, &tree.nodes);
    let dims = active.iter().filter(|a| **a).count().max(1);
    let top: usize = cells.iter().product();
    let limit = GRID_MAX.min(fineness.per_node * nodes.len().max(1));
    let mut r = 0;
    while r < fineness.refine && top << (dims * (r + 1)) <= limit {
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

impl PatchSet {
    /// A patch set over `span` = (lo, hi) (lo = hi along an axis the polynomials lack)
    /// from its tree, each patch's box and its monomial coefficients
    /// `[patch][term]` in the order of `terms`; its start grid as fine as `fineness`.
    pub(crate) fn new(
        tree: Tree,
        boxes: &[[[f64; 2]; 3]],
        mono: &[[f64; NQ]],
        (lo, hi): ([f64; 3], [f64; 3]),
        terms: Terms,
        fineness: StartGrid,
    ) -> Self {
        let active: [bool; 3] = std::array::from_fn(|k| hi[k] > lo[k]);
        let nt = terms.len();
        let low_terms: Vec<usize> = (0..nt).filter(|&k| terms.is_low(k)).collect();
        let low_axes = low_terms
            .iter()
            .map(|&k| terms.powers[k].iter().position(|&e| e == 1))
            .collect();
        let mut low = Vec::with_capacity(boxes.len() * low_terms.len());
        let mut high = Vec::with_capacity(boxes.len() * nt);
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
            .map(|b| {
                let (centre, inv_half) = patch_frame(b, active);
                Patch { centre, inv_half }
            })
            .collect();
        let (grid, start) = start_grid(&tree, lo, hi, active, fineness);
        let nodes = tree.nodes;
        let grid_scale = std::array::from_fn(|k| {
            if active[k] {
                grid[k] as f64 / (hi[k] - lo[k])
            } else {
                0.0
            }
        });
        Self {
            lo,
            hi,
            grid,
            grid_scale,
            start,
            nodes,
            patches,
            terms,
            low,
            low_axes,
            high,
        }
    }

    /// The four quantities at `x`, which must lie in the box (NaN where the
    /// piece is not tabulated).
    #[inline(always)]
    pub(crate) fn eval(&self, x: [f64; 3]) -> [f64; NQ] {
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

    /// The monomial coefficients of `patch` as a lookup evaluates them (the terms of
    /// degree ≥ 2 rounded to float32), `[term]` in the order of [`PatchSet::terms`].
    pub(crate) fn monomials(&self, patch: usize) -> Vec<[f64; NQ]> {
        let nt = self.terms.len();
        let nl = self.low_axes.len();
        let mut low = self.low[patch * nl..(patch + 1) * nl].iter();
        self.high[patch * nt..(patch + 1) * nt]
            .iter()
            .enumerate()
            .map(|(k, c)| {
                if self.terms.is_low(k) {
                    *low.next().expect("one low coefficient per low term")
                } else {
                    c.map(f64::from)
                }
            })
            .collect()
    }

    /// The range per axis.
    pub(crate) fn range(&self) -> [[f64; 2]; 3] {
        std::array::from_fn(|k| [self.lo[k], self.hi[k]])
    }

    /// The polynomial terms of every patch.
    pub(crate) fn terms(&self) -> &Terms {
        &self.terms
    }

    /// Number of patches.
    pub(crate) fn patch_count(&self) -> usize {
        self.patches.len()
    }

    /// Bytes of the coefficients and the tree.
    pub(crate) fn bytes(&self) -> usize {
        use std::mem::size_of_val;
        size_of_val(&self.low[..])
            + size_of_val(&self.high[..])
            + size_of_val(&self.nodes[..])
            + size_of_val(&self.patches[..])
            + size_of_val(&self.start[..])
    }
}
