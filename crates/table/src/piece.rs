//! One piecewise-polynomial function of the four stored quantities over a box: a
//! uniform grid of top cells, each refined by bisection into a binary tree whose
//! leaves (patches) carry a polynomial of bounded total degree in the patch's
//! coordinates t ∈ [−1, 1]³.
//!
//! A `Piece` checks what a file holds and evaluates through a
//! [`PatchSet`](crate::patch_set::PatchSet), which says how a lookup finds its patch.

use crate::error::TableError;
use crate::patch_set::{LEAF_AXIS, Node, PatchSet, StartGrid, Tree};
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

/// Edge `idx` (0..=cells) of `cells` equal top cells over [lo, hi]: the last is hi.
pub(crate) fn top_cell_edge(lo: f64, hi: f64, cells: usize, idx: usize) -> f64 {
    if idx == cells {
        hi
    } else {
        lo + (hi - lo) / cells as f64 * idx as f64
    }
}

/// A validated piece, ready for lookups.
#[derive(Debug, Clone, PartialEq)]
pub struct Piece {
    parts: PieceParts,
    /// Patch boxes [lo, hi] per axis.
    boxes: Vec<[[f64; 2]; 3]>,
    set: PatchSet,
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
        let mut roots = Vec::with_capacity(ncells);
        for (cell, &root) in parts.roots.iter().enumerate() {
            let idx = [
                cell / (parts.cells[1] * parts.cells[2]),
                cell / parts.cells[2] % parts.cells[1],
                cell % parts.cells[2],
            ];
            let cell_box: [[f64; 2]; 3] = std::array::from_fn(|k| {
                let edge = |i| top_cell_edge(lo[k], hi[k], parts.cells[k], i);
                [edge(idx[k]), edge(idx[k] + 1)]
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
        let tree = Tree {
            cells: parts.cells,
            roots: &roots,
            nodes,
        };
        let set = PatchSet::new(tree, &boxes, &mono, (lo, hi), terms, StartGrid::PIECE);
        Ok(Self { parts, boxes, set })
    }

    /// The four quantities at `x`, which must lie in the piece's box (NaN where the
    /// piece is not tabulated).
    #[inline(always)]
    pub fn eval(&self, x: [f64; 3]) -> [f64; NQ] {
        self.set.eval(x)
    }

    /// The evaluator.
    pub(crate) fn set(&self) -> &PatchSet {
        &self.set
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
        self.set.range()
    }

    /// The polynomial terms of every patch.
    pub fn terms(&self) -> &Terms {
        self.set.terms()
    }
}
