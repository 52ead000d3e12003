//! Swept boxes for the event engine's epoch broad phase: instead of a cell-crossing
//! event every cell width of flight, time is cut into epochs and each particle is
//! filed once per epoch under every cell its swept box (the bounding box of the sphere
//! over the rest of the epoch) touches. Two particles can only meet within the epoch
//! if their boxes share a cell, so one pass over the cells finds every candidate pair
//! (a swept-volume broad phase, as in continuous collision detection, on a uniform
//! grid). A particle whose trajectory changes in mid-epoch files its new box in
//! per-cell mid-epoch lists.
//!
//! In a dilute gas this replaces about three crossing events per unit of flight by a
//! share of one sequential rebuild per epoch, with no queue operation for particles
//! that meet nobody.

use crate::cells::{NONE, cells_per_axis};
use emdstar_system::SimBox;
use serde::{Deserialize, Serialize};

mod check;

/// ⌊x⌋ as an integer for |x| < 2³⁰, saturating beyond (boxes beyond the grid are
/// clamped or wrapped by the caller). Without a libm call or a float-to-integer
/// conversion (their latency chain was a third of the rebuild's box pass): adding
/// 1.5·2⁵² rounds x to the integer nearest, which then sits in the low bits.
#[inline(always)]
fn floor_to_int(x: f64) -> i64 {
    const LIMIT: f64 = 1_073_741_824.0;
    const ROUND: f64 = 6_755_399_441_055_744.0;
    // Not `clamp`, which keeps a NaN: this maps it to −2³⁰.
    #[allow(clippy::manual_clamp)]
    let x = x.max(-LIMIT).min(LIMIT);
    let shifted = x + ROUND;
    let nearest = shifted - ROUND;
    i64::from(shifted.to_bits() as u32 as i32) - i64::from(nearest > x)
}

/// A box's cells along one axis: the first (wrapped into the grid) and how many.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub(crate) struct Span {
    first: u32,
    count: u32,
}

/// Runs up to this long are listed by [`SMALL_RUN_PAIRS`] (longer: slower; docs/performance.md).
const SMALL_RUN: usize = 3;

/// The pairs among a run's first three entries, ordered so that those among the
/// first k come first for every k.
const SMALL_RUN_PAIRS: [[usize; 2]; 3] = [[0, 1], [0, 2], [1, 2]];

/// Entries a cell holds in the rebuild's array (more go to an overflow list; why eight:
/// docs/performance.md).
const CELL_ROOM: usize = 8;

/// A cell's room in the rebuild's array, in one aligned half cache line.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[repr(C, align(32))]
struct Room([u32; CELL_ROOM]);

/// [`SweepGrid::filed_pairs`] writes a small run's pairs into a chunk this long (a
/// power of two, so that the cursor wraps by a mask).
const OUT_CHUNK: usize = SMALL_RUN_PAIRS.len().next_power_of_two();

/// The cells of one swept box.
pub(crate) type Spans = [Span; 3];

/// A particle filed in a cell at the rebuild, with the cell's place in the particle's
/// box: bit k set unless the cell is the box's first along axis k. Along each axis the
/// cells two boxes share start where one of the boxes starts, so the first shared cell
/// has no bit set in both, and every other cell they share repeats the pair (see
/// [`SweepGrid::filed_pairs`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Filing;

impl Filing {
    const SLOT_BITS: u32 = 3;
    /// Particles a grid can file.
    pub const MAX_PARTICLES: usize = 1 << (32 - Self::SLOT_BITS);

    #[inline(always)]
    fn pack(particle: usize, slot: usize) -> u32 {
        ((particle as u32) << Self::SLOT_BITS) | slot as u32
    }

    #[inline(always)]
    fn particle(entry: u32) -> u32 {
        entry >> Self::SLOT_BITS
    }

    #[inline(always)]
    fn slot(entry: u32) -> u32 {
        entry & ((1 << Self::SLOT_BITS) - 1)
    }
}

/// The epoch grid: cells filed by swept box, rebuilt every epoch.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct SweepGrid {
    lo: [f64; 3],
    periodic: [bool; 3],
    dims: [u32; 3],
    inv_width: [f64; 3],
    /// How many particles were filed in each cell at the rebuild: the first
    /// [`CELL_ROOM`] in `filed[c]`, the rest in `overflow`, each a [`Filing`]. Eight
    /// trash cells follow the grid's, for the blocks' missing cells.
    count: Vec<u32>,
    filed: Vec<Room>,
    /// (cell, filing) beyond a cell's room, by cell.
    overflow: Vec<[u32; 2]>,
    /// The cells of each particle's box at the rebuild.
    pub spans: Vec<Spans>,
    /// Boxes filed in mid-epoch: list heads per cell, and (particle, next) nodes.
    extra_head: Vec<u32>,
    extra: Vec<[u32; 2]>,
    /// Per particle: the query that last visited it (each candidate is visited once).
    seen: Vec<u32>,
    query: u32,
    /// Scratch: the cells of a query, a crowded cell's entries.
    #[serde(skip)]
    scratch: Vec<u32>,
}

impl SweepGrid {
    /// A grid over `region` with cells at least `min_width` wide, for `n` particles.
    /// Along closed axes the border cells reach to ±∞.
    pub fn new(region: &SimBox, min_width: f64, n: usize) -> Self {
        let dims = cells_per_axis(region.size, min_width).map(|d| d as u32);
        let cells = dims.iter().map(|&d| d as usize).product::<usize>();
        Self {
            lo: region.lo,
            periodic: region.periodic,
            dims,
            inv_width: std::array::from_fn(|k| f64::from(dims[k]) / region.size[k]),
            count: vec![0; cells + 8],
            filed: vec![Room([0; CELL_ROOM]); cells + 8],
            overflow: Vec::new(),
            spans: vec![[Span::default(); 3]; n],
            extra_head: vec![NONE; cells],
            extra: Vec::new(),
            seen: vec![0; n],
            query: 0,
            scratch: Vec::new(),
        }
    }

    /// The cells that the box `[lo, hi]` touches.
    #[inline(always)]
    pub fn spans(&self, lo: [f64; 3], hi: [f64; 3]) -> Spans {
        [
            self.span(0, lo[0], hi[0]),
            self.span(1, lo[1], hi[1]),
            self.span(2, lo[2], hi[2]),
        ]
    }

    /// The cells of `[lo, hi]` along axis `k`.
    #[inline(always)]
    fn span(&self, k: usize, lo: f64, hi: f64) -> Span {
        let d = i64::from(self.dims[k]);
        let a = floor_to_int((lo - self.lo[k]) * self.inv_width[k]);
        let b = floor_to_int((hi - self.lo[k]) * self.inv_width[k]);
        if self.periodic[k] {
            // Boxes start within a period of the grid, unless given nonsense.
            let mut first = a;
            if !(-d..2 * d).contains(&first) {
                first = first.rem_euclid(d);
            }
            if first < 0 {
                first += d;
            } else if first >= d {
                first -= d;
            }
            Span {
                first: first as u32,
                count: (b - a + 1).min(d) as u32,
            }
        } else {
            let (a, b) = (a.clamp(0, d - 1), b.clamp(0, d - 1));
            Span {
                first: a as u32,
                count: (b - a + 1) as u32,
            }
        }
    }

    /// Calls `f(cell index)` for every cell of `s`.
    #[inline]
    fn for_cells(&self, s: &Spans, mut f: impl FnMut(usize)) {
        self.for_cells_in_place(s, |c, _| f(c));
    }

    /// Calls `f(cell index, place)` for every cell of `s`, where bit k of the place is
    /// set unless the cell is the box's first along axis k (see [`Filing`]).
    #[inline]
    fn for_cells_in_place(&self, s: &Spans, mut f: impl FnMut(usize, usize)) {
        let d = self.dims;
        let wrap = |k: usize, c: u32| if c >= d[k] { c - d[k] } else { c };
        for z in 0..s[2].count {
            let cz = wrap(2, s[2].first + z);
            let place_z = usize::from(z > 0) << 2;
            for y in 0..s[1].count {
                let cy = wrap(1, s[1].first + y);
                let place_yz = place_z | usize::from(y > 0) << 1;
                let row = (cz * d[1] + cy) * d[0];
                for x in 0..s[0].count {
                    let cx = wrap(0, s[0].first + x);
                    f((row + cx) as usize, place_yz | usize::from(x > 0));
                }
            }
        }
    }

    /// The cells of a box at most two cells long along every axis, as a 2 × 2 × 2
    /// block whose missing cells are the trash cells `cells + slot`, computed
    /// without branches (loops over one or two cells per axis mispredict); `None`
    /// for a longer box.
    #[inline(always)]
    fn block(&self, s: &Spans) -> Option<[u32; 8]> {
        // Counts are at least 1, so `count - 1` is 0 or 1 only for one or two cells.
        if ((s[0].count - 1) | (s[1].count - 1) | (s[2].count - 1)) > 1 {
            return None;
        }
        let d = self.dims;
        let trash = d[0] * d[1] * d[2];
        let axis = |k: usize| {
            let next = s[k].first + 1;
            let next = if next >= d[k] { next - d[k] } else { next };
            (s[k].first, next, s[k].count == 2)
        };
        let (x0, x1, two_x) = axis(0);
        let (y0, y1, two_y) = axis(1);
        let (z0, z1, two_z) = axis(2);
        Some(std::array::from_fn(|slot| {
            let (bx, by, bz) = (slot & 1 != 0, slot & 2 != 0, slot & 4 != 0);
            let x = if bx { x1 } else { x0 };
            let y = if by { y1 } else { y0 };
            let z = if bz { z1 } else { z0 };
            let real = (!bx | two_x) & (!by | two_y) & (!bz | two_z);
            if real {
                (z * d[1] + y) * d[0] + x
            } else {
                trash + slot as u32
            }
        }))
    }

    /// Files every particle under the cells of its box (`spans`, set beforehand)
    /// and empties the mid-epoch lists. One pass: each cell has room for
    /// [`CELL_ROOM`] entries, which saves counting them first.
    pub fn file_all(&mut self) {
        let cells = self.extra_head.len();
        let mut count = std::mem::take(&mut self.count);
        count.iter_mut().for_each(|k| *k = 0);
        let mut filed = std::mem::take(&mut self.filed);
        let mut overflow = std::mem::take(&mut self.overflow);
        overflow.clear();
        for (i, s) in self.spans.iter().enumerate() {
            // A trash cell's count stays 0: its entries overwrite each other.
            let mut file = |c: usize, slot: usize, real: bool| {
                let k = count[c] as usize;
                let entry = Filing::pack(i, slot);
                if k < CELL_ROOM {
                    filed[c].0[k] = entry;
                } else {
                    overflow.push([c as u32, entry]);
                }
                count[c] += u32::from(real);
            };
            match self.block(s) {
                Some(b) => b
                    .iter()
                    .enumerate()
                    .for_each(|(slot, &c)| file(c as usize, slot, (c as usize) < cells)),
                None => self.for_cells_in_place(s, |c, slot| file(c, slot, true)),
            }
        }
        // By cell, and within a cell in filing order (the sort is stable).
        overflow.sort_by_key(|&[c, _]| c);
        self.count = count;
        self.filed = filed;
        self.overflow = overflow;
        self.extra_head.iter_mut().for_each(|h| *h = NONE);
        self.extra.clear();
    }

    /// The entries filed in cell `c` at the rebuild: those in its room, and those
    /// beyond it.
    #[inline(always)]
    fn filed_in(&self, c: usize) -> (&[u32], &[[u32; 2]]) {
        let k = self.count[c] as usize;
        let room = &self.filed[c].0[..k.min(CELL_ROOM)];
        if k <= CELL_ROOM {
            return (room, &[]);
        }
        let from = self.overflow.partition_point(|&[d, _]| (d as usize) < c);
        (room, &self.overflow[from..from + k - CELL_ROOM])
    }

    /// Every pair of particles whose boxes share a cell, listed in `pairs`: in the
    /// first cell they share along every axis ([`Filing`]), so once, unless along a
    /// periodic axis the two boxes wrap round to meet in two separate runs of cells
    /// (then once per run; never with the epochs' boxes, each under a quarter period
    /// long). Runs of up to [`SMALL_RUN`] entries are listed without branches: nested
    /// loops over runs of random length cost a branch misprediction or two per cell,
    /// more than the pair tests themselves.
    pub fn filed_pairs<'a>(&mut self, pairs: &'a mut Vec<[u32; 2]>) -> &'a [[u32; 2]] {
        let count = |k: usize| (k * k - k) / 2;
        let first_shared = |a: u32, b: u32| Filing::slot(a) & Filing::slot(b) == 0;
        let cells = self.extra_head.len();
        let mut crowded = std::mem::take(&mut self.scratch);
        // `pairs` only grows: its stale tail is scratch, never read.
        let mut w = 0;
        for (c, &k) in self.count[..cells].iter().enumerate() {
            let k = k as usize;
            let needed = w + OUT_CHUNK.max(count(k));
            if pairs.len() < needed {
                pairs.resize(needed.max(2 * pairs.len()), [0; 2]);
            }
            if k <= SMALL_RUN {
                // One bounds check per cell: candidates are written in place and
                // kept by advancing the cursor.
                let run: &[u32; SMALL_RUN] = self.filed[c].0[..SMALL_RUN].try_into().expect("room");
                let out: &mut [[u32; 2]; OUT_CHUNK] =
                    (&mut pairs[w..w + OUT_CHUNK]).try_into().expect("room");
                let mut kept = 0;
                for (n, &[p, q]) in SMALL_RUN_PAIRS.iter().enumerate() {
                    let (e, f) = (run[p], run[q]);
                    out[kept % OUT_CHUNK] = [Filing::particle(e), Filing::particle(f)];
                    kept += usize::from((n < count(k)) & first_shared(e, f));
                }
                w += kept;
            } else {
                let (in_room, beyond) = self.filed_in(c);
                crowded.clear();
                crowded.extend_from_slice(in_room);
                crowded.extend(beyond.iter().map(|&[_, e]| e));
                for (m, &e) in crowded.iter().enumerate() {
                    for &f in &crowded[m + 1..] {
                        pairs[w] = [Filing::particle(e), Filing::particle(f)];
                        w += usize::from(first_shared(e, f));
                    }
                }
            }
        }
        self.scratch = crowded;
        &pairs[..w]
    }

    /// Calls `f(j)` once for every particle filed (at the rebuild or since) in a cell
    /// of `s`, then files `i` there.
    pub fn scan_and_file(&mut self, i: usize, s: &Spans, mut f: impl FnMut(usize)) {
        self.query = self.query.wrapping_add(1);
        if self.query == 0 {
            self.seen.iter_mut().for_each(|q| *q = 0);
            self.query = 1;
        }
        let q = self.query;
        self.seen[i] = q;
        let mut cells = std::mem::take(&mut self.scratch);
        cells.clear();
        let mut seen = std::mem::take(&mut self.seen);
        self.for_cells(s, |c| {
            let mut visit = |j: u32| {
                if seen[j as usize] != q {
                    seen[j as usize] = q;
                    f(j as usize);
                }
            };
            let (in_room, beyond) = self.filed_in(c);
            for &e in in_room.iter().chain(beyond.iter().map(|[_, e]| e)) {
                visit(Filing::particle(e));
            }
            let mut node = self.extra_head[c];
            while node != NONE {
                let [j, next] = self.extra[node as usize];
                visit(j);
                node = next;
            }
            cells.push(c as u32);
        });
        self.seen = seen;
        for &c in &cells {
            self.extra.push([i as u32, self.extra_head[c as usize]]);
            self.extra_head[c as usize] = (self.extra.len() - 1) as u32;
        }
        self.scratch = cells;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn grid() -> SweepGrid {
        let region = SimBox {
            lo: [0.0; 3],
            size: [10.0; 3],
            periodic: [true, true, false],
        };
        SweepGrid::new(&region, 1.0, 4)
    }

    #[test]
    fn floor_to_int_is_the_floor() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let edges = [0.0, -0.0, 1.0, -1.0, 0.5, -0.5, 2.5, -2.5, 1e-300, -1e-300];
        let near_integers = (-40..40).flat_map(|k| {
            let k = f64::from(k);
            [k, k.next_up(), k.next_down()]
        });
        let random = (0..10_000).map(|_| (rng.random::<f64>() - 0.5) * 4e9);
        for x in edges.into_iter().chain(near_integers).chain(random) {
            let expected = x.floor().clamp(-1_073_741_824.0, 1_073_741_824.0) as i64;
            assert_eq!(floor_to_int(x), expected, "x = {x:e}");
        }
        assert_eq!(floor_to_int(f64::INFINITY), 1 << 30);
        assert_eq!(floor_to_int(f64::NEG_INFINITY), -(1 << 30));
        assert_eq!(floor_to_int(f64::NAN), -(1 << 30));
    }

    #[test]
    fn spans_wrap_periodic_axes_and_clamp_closed_ones() {
        let g = grid();
        let s = g.spans([-0.5, 9.2, -3.0], [0.5, 10.7, 20.0]);
        assert_eq!((s[0].first, s[0].count), (9, 2));
        assert_eq!((s[1].first, s[1].count), (9, 2));
        assert_eq!((s[2].first, s[2].count), (0, 10));
        // A box longer than the period visits each cell once.
        let s = g.spans([0.5, 0.0, 0.0], [25.0, 0.5, 0.5]);
        assert_eq!(s[0].count, 10);
    }

    #[test]
    fn boxes_up_to_two_cells_long_are_blocks_of_their_own_cells() {
        let g = grid();
        let trash = 10 * 10 * 10;
        for counts in (0..27).map(|m| [1 + m % 3, 1 + m / 3 % 3, 1 + m / 9]) {
            // Starting in the last cell, so periodic axes wrap.
            let s: Spans = std::array::from_fn(|k| Span {
                first: 9,
                count: counts[k],
            });
            let block = g.block(&s);
            assert_eq!(
                block.is_some(),
                counts.iter().all(|&c| c <= 2),
                "{counts:?}"
            );
            if let Some(block) = block {
                let mut real: Vec<u32> = block.into_iter().filter(|&c| c < trash).collect();
                let mut expected = Vec::new();
                g.for_cells(&s, |c| expected.push(c as u32));
                real.sort_unstable();
                expected.sort_unstable();
                assert_eq!(real, expected, "{counts:?}");
            }
        }
    }

    #[test]
    fn every_pair_of_touching_boxes_is_reported_once_per_run_of_shared_cells() {
        // Brute force over random boxes: the pairs whose cell sets intersect.
        let region = SimBox {
            lo: [0.0; 3],
            size: [6.0; 3],
            periodic: [true, false, true],
        };
        let mut g = SweepGrid::new(&region, 1.0, 40);
        let mut rng = ChaCha8Rng::seed_from_u64(12345);
        let mut rand = || rng.random::<f64>();
        let mut cells: Vec<Vec<usize>> = Vec::new();
        for i in 0..40 {
            let lo: [f64; 3] = std::array::from_fn(|_| rand() * 8.0 - 1.0);
            // Every other box under a cell long (a block), the rest up to three.
            let longest = if i % 2 == 0 { 0.99 } else { 3.0 };
            let hi: [f64; 3] = std::array::from_fn(|k| lo[k] + rand() * longest);
            // Ten crowd one cell beyond its room; the last two wrap round the
            // periodic x axis to meet in cells 0 and 3.
            let (lo, hi) = match i {
                28..=37 => ([2.2; 3], [2.4; 3]),
                38 => ([0.5, 2.5, 2.5], [3.5, 2.6, 2.6]),
                39 => ([3.5, 2.5, 2.5], [6.5, 2.6, 2.6]),
                _ => (lo, hi),
            };
            let s = g.spans(lo, hi);
            g.spans[i] = s;
            let mut mine = Vec::new();
            g.for_cells(&s, |c| mine.push(c));
            cells.push(mine);
        }
        g.file_all();
        let runs = g.count[..g.extra_head.len()].to_vec();
        assert!(
            runs.iter().any(|&k| k as usize > CELL_ROOM),
            "an overflowing cell"
        );
        assert!(runs.iter().any(|&k| k as usize > SMALL_RUN), "a long run");
        for k in 2..=SMALL_RUN as u32 {
            assert!(runs.contains(&k), "a run of {k}");
        }
        let mut buffer = vec![[7, 7]; 3];
        let pairs = g.filed_pairs(&mut buffer);
        let reported: Vec<_> = pairs
            .iter()
            .map(|&[i, j]| (i.min(j) as usize, i.max(j) as usize))
            .collect();
        let mut expected = Vec::new();
        for i in 0..40 {
            for j in i + 1..40 {
                if cells[i].iter().any(|c| cells[j].contains(c)) {
                    expected.push((i, j));
                }
            }
        }
        let unique: std::collections::BTreeSet<_> = reported.iter().copied().collect();
        assert_eq!(unique.into_iter().collect::<Vec<_>>(), expected);
        // Once per run of shared cells along each axis: once, unless two boxes wrap
        // round a periodic axis to meet twice.
        let coords = |s: &Span, k: usize| -> Vec<u32> {
            (0..s.count).map(|o| (s.first + o) % g.dims[k]).collect()
        };
        let runs = |a: &Span, b: &Span, k: usize| {
            let (a, b) = (coords(a, k), coords(b, k));
            let shared = |c: u32| a.contains(&c) && b.contains(&c);
            let d = g.dims[k];
            let before = |c: u32| {
                if c == 0 {
                    g.periodic[k].then_some(d - 1)
                } else {
                    Some(c - 1)
                }
            };
            (0..d)
                .filter(|&c| shared(c) && !before(c).is_some_and(shared))
                .count()
                .max(1)
        };
        let (mut long_in_several_cells, mut twice) = (0, 0);
        for &(i, j) in &expected {
            let times = reported.iter().filter(|&&p| p == (i, j)).count();
            let (si, sj) = (g.spans[i], g.spans[j]);
            let once_per: usize = (0..3).map(|k| runs(&si[k], &sj[k], k)).product();
            assert_eq!(times, once_per, "{i}, {j}");
            let shared = cells[i].iter().filter(|c| cells[j].contains(c)).count();
            let long = g.block(&si).is_none() || g.block(&sj).is_none();
            long_in_several_cells += usize::from(long && shared > 1);
            twice += usize::from(once_per > 1);
        }
        assert!(long_in_several_cells > 0);
        assert_eq!(
            twice, 1,
            "boxes 38 and 39 meet twice round the periodic x axis"
        );
        // Mid-epoch scans see filed particles once and file the scanning one.
        let s = g.spans([0.0; 3], [6.0, 6.0, 6.0]);
        let mut seen = Vec::new();
        g.scan_and_file(0, &s, |j| seen.push(j));
        seen.sort_unstable();
        assert_eq!(seen, (1..40).collect::<Vec<_>>());
        let mut again = Vec::new();
        g.scan_and_file(1, &g.spans([0.5; 3], [0.6; 3]), |j| again.push(j));
        assert!(again.contains(&0), "the box filed in mid-epoch is found");
    }
}
