//! A pair's own table ([`PairTable`]): the table restricted to the impacts of one
//! pair and law.
//!
//! For a fixed pair the rectangular coordinates of an impact are a = ln(v_t/v_n) − g_min
//! and, with u = ln |v|², b and c affine in u (linear dashpot: c constant; Hertz: both
//! vary, Eqs. 48, 56, 59). Every impact of the pair lies on the plane {(a, b(u), c(u))}
//! through the rectangle, so each patch polynomial of the main piece that the plane
//! crosses, p(x, y, z) of total degree n, restricted to it is a polynomial of total
//! degree n in the two local coordinates (x, s): 36 terms instead of 120 at degree 7,
//! 66 instead of 286 at degree 10. The restriction is exact up to rounding (the
//! expansion in float64, the terms of degree ≥ 2 kept in float32 as in the table), and
//! the few hundred patches the plane crosses are small enough to stay in cache.
//!
//! The plane's patches keep the tree of the main piece: a split in a stays a split in
//! a, a split in b or c becomes a split in u where the line crosses it (or, where c does
//! not vary, chooses the side the pair lies on). Impacts outside the main piece (the
//! near-central and nearly elastic extensions, and everything out of the box) go
//! through the full table, with its errors.

use crate::error::TableError;
use crate::pair_map::PairMap;
use crate::patch_set::{LEAF_AXIS, Node, PatchSet, StartGrid, Tree, patch_frame};
use crate::piece::{Piece, top_cell_edge};
use crate::poly::{NQ, Terms};
use crate::table::{PhysicalLookup, Table, mor_from_logs};
use emdstar_contact::{Impact, PairLaw, PairProperties};
use std::ops::Deref;

/// A lookup handle for one pair and law that holds the table's restriction to the
/// pair's impacts (see the module documentation): built once (about a millisecond),
/// then each lookup evaluates a two-dimensional patch from cache. Its results agree
/// with [`Table::lookup`] to rounding (the tests bound the difference of every stored
/// logarithm by 1e-7, within the table's accuracy); where the table's own extensions
/// apply, or the impact is out of the box, it answers exactly as [`Table::lookup`].
///
/// `T` holds the table: a `&Table` ([`Table::pair_table`]), or an owner such as
/// `Arc<Table>` or [`SharedTable`](crate::SharedTable) ([`PairTable::new`]).
/// Immutable once built, `Send + Sync` with its holder: share it between threads.
#[derive(Debug, Clone)]
pub struct PairTable<T: Deref<Target = Table>> {
    table: T,
    map: PairMap,
    /// The restriction over (a, u); None where the pair's line misses the main piece or
    /// the table stores b through a knee map (then b is not affine in u).
    slice: Option<PatchSet>,
}

impl<T: Deref<Target = Table>> PairTable<T> {
    /// Checks the law and the pair and restricts `table` to them.
    pub fn new(table: T, law: &PairLaw, pair: &PairProperties) -> Result<Self, TableError> {
        table.expect_model(law.model())?;
        let map = PairMap::new(law, pair)?;
        let slice = if table.b_map.knee == 0.0 {
            restrict(&table, &map)
        } else {
            None
        };
        Ok(Self { table, map, slice })
    }

    /// The table this handle looks up.
    pub fn table(&self) -> &Table {
        &self.table
    }

    /// The pair's constants.
    pub fn map(&self) -> &PairMap {
        &self.map
    }

    /// Number of two-dimensional patches of the restriction (0: every lookup goes
    /// through the full table).
    pub fn patch_count(&self) -> usize {
        self.slice.as_ref().map_or(0, PatchSet::patch_count)
    }

    /// Bytes the restriction holds in memory.
    pub fn bytes(&self) -> usize {
        self.slice.as_ref().map_or(0, PatchSet::bytes)
    }

    /// MoR, time and length scale of one impact of the pair.
    #[inline]
    pub fn lookup(&self, impact: &Impact) -> Result<PhysicalLookup, TableError> {
        let (x, time, u) = self.map.coords_and_u(&self.table.bounds, impact)?;
        let mor = match &self.slice {
            Some(slice) if self.table.in_main_piece(&x) => mor_from_logs(slice.eval([x.a, u, 0.0])),
            _ => self.table.lookup_rect(&x)?,
        };
        Ok(PhysicalLookup {
            mor,
            time,
            length: impact.normal_speed * time,
        })
    }
}

/// A rectangle coordinate along the pair's line: offset + slope·u.
#[derive(Debug, Clone, Copy)]
struct Affine {
    offset: f64,
    slope: f64,
}

impl Affine {
    fn at(self, u: f64) -> f64 {
        self.offset + self.slope * u
    }

    /// u where the coordinate equals `value` (slope ≠ 0).
    fn solve(self, value: f64) -> f64 {
        (value - self.offset) / self.slope
    }
}

/// Part of the main piece: a block of top cells [from, to) per axis, or a tree node.
#[derive(Debug, Clone, Copy)]
enum Part {
    Cells([[usize; 2]; 3]),
    Node(usize),
}

/// Deepest restriction tree built (levels of top-cell blocks and splits): the shipped
/// tables need about 20, a file's tree may be as deep as it has nodes. Deeper trees are
/// not restricted (their pairs look up through the full table), so that building one
/// never exhausts a thread's stack.
const MAX_DEPTH: usize = 128;

/// Builds the restriction of the main piece to the plane of the pair's impacts.
struct Restriction<'a> {
    piece: &'a Piece,
    /// b and c along the line.
    line: [Affine; 2],
    terms: Terms,
    nodes: Vec<Node>,
    boxes: Vec<[[f64; 2]; 3]>,
    mono: Vec<[f64; NQ]>,
    /// Set when a branch went deeper than [`MAX_DEPTH`].
    too_deep: bool,
}

/// The table's main piece restricted to the plane of the pair of `map` (None where the
/// plane misses it).
fn restrict(table: &Table, map: &PairMap) -> Option<PatchSet> {
    let [b, c] = map
        .line(&table.bounds)
        .map(|[offset, slope]| Affine { offset, slope });
    let piece = &table.main;
    let range = piece.range();
    // The u over which b and c stay in the piece, widened by a hair so that every
    // impact the lookup's own test admits lies inside (rounding of b and c).
    let mut u = [b.solve(range[1][1]), b.solve(range[1][0])];
    if c.slope != 0.0 {
        u = [
            u[0].max(c.solve(range[2][0])),
            u[1].min(c.solve(range[2][1])),
        ];
    } else if !(c.offset >= range[2][0] && c.offset <= range[2][1]) {
        return None;
    }
    let margin = 1e-9 * (u[1] - u[0]).abs().max(1.0);
    let u = [u[0] - margin, u[1] + margin];
    if !(u[1] > u[0] && u.iter().all(|x| x.is_finite())) {
        return None;
    }
    let degree = table.degree;
    let mut r = Restriction {
        piece,
        line: [b, c],
        terms: Terms::new(degree, [degree, degree, 0]),
        nodes: vec![Node {
            split: 0.0,
            axis: LEAF_AXIS,
            next: 0,
        }],
        boxes: Vec::new(),
        mono: Vec::new(),
        too_deep: false,
    };
    let cells = piece.parts().cells;
    let all = Part::Cells(std::array::from_fn(|k| [0, cells[k]]));
    r.fill(0, all, range, u, 0);
    if r.too_deep {
        return None;
    }
    let lo = [range[0][0], u[0], 0.0];
    let hi = [range[0][1], u[1], 0.0];
    let tree = Tree {
        cells: [1, 1, 1],
        roots: &[0],
        nodes: r.nodes,
    };
    Some(PatchSet::new(
        tree,
        &r.boxes,
        &r.mono,
        (lo, hi),
        r.terms,
        StartGrid::SLICE,
    ))
}

impl Restriction<'_> {
    /// Fills node `at` with the restriction of `part` (whose box is `bx`) to the
    /// stretch `u` of the line inside it; `depth` levels below the top.
    fn fill(&mut self, at: usize, part: Part, bx: [[f64; 2]; 3], u: [f64; 2], depth: usize) {
        if depth > MAX_DEPTH || self.too_deep {
            self.too_deep = true;
            return;
        }
        match part {
            Part::Cells(block) => {
                let Some(k) = (0..3).find(|&k| block[k][1] - block[k][0] > 1) else {
                    let cells = self.piece.parts().cells;
                    let cell = (block[0][0] * cells[1] + block[1][0]) * cells[2] + block[2][0];
                    let root = self.piece.parts().roots[cell];
                    return self.fill(at, Part::Node(root), bx, u, depth);
                };
                let mid = (block[k][0] + block[k][1]) / 2;
                let [lo, hi] = self.piece.range()[k];
                let split = top_cell_edge(lo, hi, self.piece.parts().cells[k], mid);
                let (mut below, mut above) = (block, block);
                below[k][1] = mid;
                above[k][0] = mid;
                let parts = (Part::Cells(below), Part::Cells(above));
                self.split(at, k, split, parts, bx, u, depth + 1);
            }
            Part::Node(n) => {
                let [axis, next] = self.piece.parts().tree[n];
                let next = next as usize;
                if axis < 0 {
                    return self.leaf(at, next, u);
                }
                let split = self.piece.parts().split[n];
                let parts = (Part::Node(next), Part::Node(next + 1));
                self.split(at, axis as usize, split, parts, bx, u, depth + 1);
            }
        }
    }

    /// Fills node `at` with a split of axis `k` at `split` into `(below, above)`.
    #[allow(clippy::too_many_arguments)]
    fn split(
        &mut self,
        at: usize,
        k: usize,
        split: f64,
        (below, above): (Part, Part),
        bx: [[f64; 2]; 3],
        u: [f64; 2],
        depth: usize,
    ) {
        let (mut bx_below, mut bx_above) = (bx, bx);
        bx_below[k][1] = split;
        bx_above[k][0] = split;
        if k == 0 {
            return self.fork(
                at,
                [0, depth],
                split,
                (below, bx_below, u),
                (above, bx_above, u),
            );
        }
        let line = self.line[k - 1];
        if line.slope == 0.0 {
            // The same test as a lookup's descent (x ≥ split: above).
            return if line.offset >= split {
                self.fill(at, above, bx_above, u, depth)
            } else {
                self.fill(at, below, bx_below, u, depth)
            };
        }
        let us = line.solve(split);
        let ((lo, bx_lo), (hi, bx_hi)) = if line.slope > 0.0 {
            ((below, bx_below), (above, bx_above))
        } else {
            ((above, bx_above), (below, bx_below))
        };
        if us <= u[0] {
            self.fill(at, hi, bx_hi, u, depth)
        } else if us >= u[1] {
            self.fill(at, lo, bx_lo, u, depth)
        } else {
            let (lo, hi) = ((lo, bx_lo, [u[0], us]), (hi, bx_hi, [us, u[1]]));
            self.fork(at, [1, depth], us, lo, hi);
        }
    }

    /// Node `at` splits axis `axis` (0: a, 1: u) at `split` into two new children, at
    /// `depth`.
    fn fork(
        &mut self,
        at: usize,
        [axis, depth]: [usize; 2],
        split: f64,
        below: (Part, [[f64; 2]; 3], [f64; 2]),
        above: (Part, [[f64; 2]; 3], [f64; 2]),
    ) {
        let first = self.nodes.len();
        let leaf = self.nodes[at];
        self.nodes.extend([leaf, leaf]);
        self.nodes[at] = Node {
            split,
            axis: axis as u8,
            next: first as u32,
        };
        self.fill(first, below.0, below.1, below.2, depth);
        self.fill(first + 1, above.0, above.1, above.2, depth);
    }

    /// Node `at` is the restriction of patch `patch` to the stretch `u` of the line.
    fn leaf(&mut self, at: usize, patch: usize, u: [f64; 2]) {
        let bx = self.piece.patch_boxes()[patch];
        let (centre, inv_half) = patch_frame(&bx, [true; 3]);
        let (u_centre, u_inv_half) = (0.5 * (u[0] + u[1]), 2.0 / (u[1] - u[0]));
        // Along the stretch, with u = u_centre + s/u_inv_half: the patch's local y and z
        // are affine in s, y = y₀ + y₁s and z = z₀ + z₁s.
        let local = |k: usize| {
            let line = self.line[k - 1];
            [
                (line.at(u_centre) - centre[k]) * inv_half[k],
                line.slope * inv_half[k] / u_inv_half,
            ]
        };
        let degree = self.terms.degree;
        let (y, z) = (
            binomial_powers(local(1), degree),
            binomial_powers(local(2), degree),
        );
        let mut out = vec![[0.0; NQ]; self.terms.len()];
        let set = self.piece.set();
        for (c, p) in set.monomials(patch).iter().zip(&set.terms().powers) {
            let [i, j, k] = *p;
            for (m, yc) in y[j].iter().enumerate() {
                for (l, zc) in z[k].iter().enumerate() {
                    let w = yc * zc;
                    if w == 0.0 {
                        continue;
                    }
                    let slot = &mut out[self.terms.index([i, m + l, 0]).expect("i + m + l ≤ n")];
                    for q in 0..NQ {
                        slot[q] += w * c[q];
                    }
                }
            }
        }
        self.nodes[at] = Node {
            split: 0.0,
            axis: LEAF_AXIS,
            next: self.boxes.len() as u32,
        };
        self.boxes.push([bx[0], u, [0.0, 0.0]]);
        self.mono.extend(out);
    }
}

/// The coefficients of (c₀ + c₁s)^j in s, for j = 0..=n (binomial expansion).
fn binomial_powers(c: [f64; 2], n: usize) -> Vec<Vec<f64>> {
    let mut out = vec![vec![1.0]];
    for j in 1..=n {
        let prev = &out[j - 1];
        let next = (0..=j)
            .map(|m| {
                let keep = if m < j { c[0] * prev[m] } else { 0.0 };
                let raise = if m > 0 { c[1] * prev[m - 1] } else { 0.0 };
                keep + raise
            })
            .collect();
        out.push(next);
    }
    out
}
