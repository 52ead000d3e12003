//! The neighbour-list broad phase for dense gases: every particle keeps a list of the
//! particles whose shell centres lie within `range` of its own, and may move up to
//! `reach` = (range − σ_max)/2 from its centre; reaching that sphere is its own event,
//! which re-centres the shell and rebuilds its list (Verlet 1967's lists in event-driven
//! form; Smallenburg, EPJE 45, 22 (2022), Sec. 2.3).
//!
//! Invariants:
//! - every particle `i` lies within `reach` of its centre `centre[i]` until its shell
//!   event, and its centre is its wrapped position at its last shell event;
//! - the lists are symmetric: `j` is on `i`'s list, with the periodic image that is
//!   nearest between the centres, exactly when `i` is on `j`'s, exactly when the two
//!   centres lie within `range`. Two spheres in contact (|x_i − x_j| ≤ σ_max) both
//!   inside their shells have centres within σ_max + 2·reach = range, so no collision
//!   before both shell events is missed.
//!
//! The centres are filed in cells at least `range` wide (`CentreCells`), which only a
//! shell event moves; there are no cell crossings. Only hard spheres and eMD run here:
//! eMD*'s transients and rotations need the crossing cells.

use super::BroadPhase;
use super::centre_cells::CentreCells;
use crate::cells::NONE;
use crate::queue::EventQueue;
use crate::state::{State, morton_order, prefetch, same_encoding};
use emdstar_contact::vec3::{dot, sub};
use emdstar_system::SimBox;

/// List range between shell centres in units of the largest contact distance: 1.6 ran
/// 7-15 % faster than the peer's 1.5 (Smallenburg 2022) at η = 0.35-0.5, and 1.7 only at
/// 0.35 (docs/performance.md has the measurement).
pub(crate) const SHELL_RANGE: f64 = 1.6;

/// A list entry packs the partner's index above `IMAGE_BITS` bits of image code.
const IMAGE_BITS: u32 = 5;
const IMAGE_MASK: u32 = (1 << IMAGE_BITS) - 1;
/// The code of the image without shift: (0 + 1)·(1 + 3 + 9).
pub(crate) const NO_SHIFT: u32 = 13;

/// Neighbour lists in shells (see the module documentation).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Neighbours {
    /// Shell centres filed in cells at least `range` wide.
    cells: CentreCells,
    centre: Vec<[f64; 3]>,
    range: f64,
    reach: f64,
    /// The shift of each image code, x_j's image = x_j + shift (32 rows, so that a
    /// masked code needs no bounds check).
    shifts: [[f64; 3]; 32],
    lists: Lists,
    /// Rebuilds so far, and for each particle the last rebuild whose old list held it.
    rebuilds: u64,
    listed_at: Vec<u64>,
    /// The entries new to a rebuilt list (scratch).
    #[serde(skip)]
    fresh: Vec<u32>,
}

/// Every particle's list in one array.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
struct Lists {
    /// Capacity of each list; `list[i * stride..][..count[i]]` holds `i`'s entries.
    stride: usize,
    count: Vec<u32>,
    list: Vec<u32>,
}

impl Lists {
    /// Whether decoded lists hold one list per particle `0..n`, each within its
    /// capacity and naming particles `0..n` only.
    fn are_whole(&self, n: usize) -> bool {
        self.count.len() == n
            && self.stride > 0
            && n.checked_mul(self.stride) == Some(self.list.len())
            && self.count.iter().all(|&c| c as usize <= self.stride)
            && (0..n).all(|i| self.of(i).iter().all(|&e| ((e >> IMAGE_BITS) as usize) < n))
    }

    /// `i`'s entries.
    #[inline(always)]
    fn of(&self, i: usize) -> &[u32] {
        &self.list[i * self.stride..i * self.stride + self.count[i] as usize]
    }

    /// Appends `j` with image `code` to `i`'s list, growing every list if `i`'s is full.
    #[inline]
    fn push(&mut self, i: usize, j: u32, code: u32) {
        if self.count[i] as usize == self.stride {
            self.grow();
        }
        self.list[i * self.stride + self.count[i] as usize] = j << IMAGE_BITS | code;
        self.count[i] += 1;
    }

    /// Doubles the capacity of every list (a crowded neighbourhood).
    #[cold]
    fn grow(&mut self) {
        let (old, new) = (self.stride, 2 * self.stride);
        let mut list = vec![0; self.count.len() * new];
        for (i, &c) in self.count.iter().enumerate() {
            list[i * new..][..c as usize].copy_from_slice(&self.list[i * old..][..c as usize]);
        }
        self.list = list;
        self.stride = new;
    }

    /// Takes `i` off the lists of its neighbours and empties its own.
    fn unlink(&mut self, i: usize) {
        for m in 0..self.count[i] as usize {
            let j = (self.list[i * self.stride + m] >> IMAGE_BITS) as usize;
            let row = j * self.stride;
            let len = self.count[j] as usize;
            if let Some(at) = self.list[row..row + len]
                .iter()
                .position(|&e| e >> IMAGE_BITS == i as u32)
            {
                self.list[row + at] = self.list[row + len - 1];
                self.count[j] -= 1;
            }
        }
        self.count[i] = 0;
    }

    /// Renumbers: new number k is old number `order[k]`.
    fn renumber(&mut self, order: &[u32], new_index: &[u32]) {
        let stride = self.stride;
        let mut list = vec![0; self.list.len()];
        let mut count = vec![0; order.len()];
        for (new, &old) in order.iter().enumerate() {
            let old = old as usize;
            count[new] = self.count[old];
            for m in 0..self.count[old] as usize {
                let e = self.list[old * stride + m];
                let j = new_index[(e >> IMAGE_BITS) as usize];
                list[new * stride + m] = j << IMAGE_BITS | (e & IMAGE_MASK);
            }
        }
        self.list = list;
        self.count = count;
    }
}

/// The image code of shifts in units of the box size (each −1, 0 or 1).
pub(crate) fn image_code(image: [i8; 3]) -> u32 {
    (image[0] + 1) as u32 + 3 * (image[1] + 1) as u32 + 9 * (image[2] + 1) as u32
}

/// The code of the opposite image.
fn opposite(code: u32) -> u32 {
    26 - code
}

impl Neighbours {
    /// Lists over `region` for `n` particles whose largest contact distance is
    /// `max_contact`.
    pub(crate) fn new(region: &SimBox, max_contact: f64, n: usize) -> Self {
        let range = SHELL_RANGE * max_contact;
        let volume: f64 = region.size.iter().product();
        let expected = n as f64 / volume * 4.0 / 3.0 * std::f64::consts::PI * range.powi(3);
        // Lists grow (all of them) when one fills.
        let stride = ((2.0 * expected).ceil() as usize + 8).clamp(16, 64);
        Self {
            cells: CentreCells::new(region, range, n),
            centre: vec![[0.0; 3]; n],
            range,
            reach: 0.5 * (range - max_contact),
            shifts: std::array::from_fn(|c| {
                let image = [c % 3, c / 3 % 3, c / 9].map(|m| m as f64 - 1.0);
                std::array::from_fn(|k| {
                    if c < 27 {
                        image[k] * region.size[k]
                    } else {
                        0.0
                    }
                })
            }),
            lists: Lists {
                stride,
                count: vec![0; n],
                list: vec![0; n * stride],
            },
            rebuilds: 0,
            listed_at: vec![0; n],
            fresh: Vec::new(),
        }
    }

    /// Whether every periodic axis holds three cells at least the list range wide, so
    /// that a pair within range has one nearest image.
    pub(crate) fn fit(region: &SimBox, max_contact: f64) -> bool {
        (0..3).all(|k| !region.periodic[k] || region.size[k] >= 3.0 * SHELL_RANGE * max_contact)
    }

    /// Lists `i` with every particle whose centre lies within range of its own (and
    /// `i` on theirs if `both`), from the cells around its centre.
    fn link(&mut self, i: usize, both: bool) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU supports AVX (checked just above).
            return unsafe { self.link_avx(i, both) };
        }
        self.link_in(i, both)
    }

    /// [`Neighbours::link_in`] compiled with AVX, as [`earliest_avx`].
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn link_avx(&mut self, i: usize, both: bool) {
        self.link_in(i, both)
    }

    /// See [`Neighbours::link`].
    #[inline(always)]
    fn link_in(&mut self, i: usize, both: bool) {
        let ci = self.centre[i];
        let range2 = self.range * self.range;
        let lists = &mut self.lists;
        // Inlined into the scan over the cells (a call per cell cost about as much as
        // the tests of its three centres).
        self.cells.around(
            i,
            #[inline(always)]
            |members, code, shift| {
                let c = sub(ci, shift);
                for m in members {
                    let d = [c[0] - m.centre[0], c[1] - m.centre[1], c[2] - m.centre[2]];
                    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < range2 && m.index != i as u32 {
                        lists.push(i, m.index, code);
                        if both {
                            lists.push(m.index as usize, i as u32, opposite(code));
                        }
                    }
                }
            },
        );
    }
}

/// The earliest collision of `i` (advanced to now) with the list `entries` before
/// `best`: (time, partner or NONE, whether it is a stabilising collision now).
#[inline]
fn earliest<Q: EventQueue>(
    s: &State<Q>,
    i: usize,
    entries: &[u32],
    shifts: &[[f64; 3]; 32],
    best: f64,
) -> (f64, u32, bool) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU supports AVX (checked just above).
        return unsafe { earliest_avx(s, i, entries, shifts, best) };
    }
    earliest_in(s, i, entries, shifts, best)
}

/// [`earliest_in`] compiled with AVX's three-operand instructions (fewer register
/// copies). Separate multiplies and adds (no FMA) keep the results bitwise those of
/// the portable path.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
unsafe fn earliest_avx<Q: EventQueue>(
    s: &State<Q>,
    i: usize,
    entries: &[u32],
    shifts: &[[f64; 3]; 32],
    best: f64,
) -> (f64, u32, bool) {
    earliest_in(s, i, entries, shifts, best)
}

/// See [`earliest`].
#[inline(always)]
fn earliest_in<Q: EventQueue>(
    s: &State<Q>,
    i: usize,
    entries: &[u32],
    shifts: &[[f64; 3]; 32],
    mut best: f64,
) -> (f64, u32, bool) {
    let now = s.time;
    let (pi, vi) = (s.slot[i].kin.pos, s.slot[i].kin.vel);
    let ri = s.slot[i].kin.radius;
    let mut best_j = NONE;
    let mut best_now = false;
    for &e in entries {
        s.prefetch_motion((e >> IMAGE_BITS) as usize);
    }
    let mut horizon = crate::detect::widen(best - now);
    for &e in entries {
        let j = (e >> IMAGE_BITS) as usize;
        // No gravity here: straight flights. Written per component, which the compiler
        // keeps scalar (its two-lane packing of the array form cost more shuffles).
        let kj = &s.slot[j].kin;
        let dt = now - kj.stamp;
        let shift = &shifts[(e & IMAGE_MASK) as usize];
        let r = [
            pi[0] - shift[0] - (kj.pos[0] + kj.vel[0] * dt),
            pi[1] - shift[1] - (kj.pos[1] + kj.vel[1] * dt),
            pi[2] - shift[2] - (kj.pos[2] + kj.vel[2] * dt),
        ];
        let v = [vi[0] - kj.vel[0], vi[1] - kj.vel[1], vi[2] - kj.vel[2]];
        let sigma = ri + kj.radius;
        if crate::detect::on_collision_course_before(r, v, sigma, horizon) {
            let dt = crate::detect::sphere_sphere(r, v, sigma);
            if now + dt < best {
                best = now + dt;
                horizon = crate::detect::widen(best - now);
                best_j = j as u32;
                best_now = dt == 0.0;
                // Keeping the prediction reads the partner's collision counter.
                prefetch(&s.slot[j].ev);
            }
        }
    }
    (best, best_j, best_now)
}

impl BroadPhase for Neighbours {
    const OWN_EVENTS: usize = 0;

    fn check_restored(&self, built: &Self, n: usize) -> Result<(), String> {
        self.cells.check_restored(&built.cells, n)?;
        let geometry = |b: &Self| (b.range, b.reach, b.shifts);
        let whole = same_encoding(&geometry(self), &geometry(built))
            && self.centre.len() == n
            && self.listed_at.len() == n
            && self.lists.are_whole(n);
        whole
            .then_some(())
            .ok_or_else(|| "the neighbour lists are not those of the config's particles".into())
    }

    fn fits(region: &SimBox, max_contact: f64, n: usize) -> bool {
        Self::fit(region, max_contact) && n < (1 << (32 - IMAGE_BITS))
    }

    fn file<Q: EventQueue>(&mut self, s: &State<Q>) {
        for i in 0..s.len() {
            let x = s.slot[i].kin.pos;
            self.centre[i] = x;
            self.cells.insert(i, x);
        }
    }

    fn start<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        for i in 0..s.len() {
            self.lists.count[i] = 0;
        }
        for i in 0..s.len() {
            self.link(i, false);
        }
        for i in 0..s.len() {
            self.predict(s, i);
        }
    }

    #[inline]
    fn predict_pairs<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize) {
        debug_assert!(s.probe.is_none() && s.slot[i].ev.partner == NONE);
        let found = earliest(s, i, self.lists.of(i), &self.shifts, s.slot[i].ev.coll_time);
        s.keep_earliest(i, found);
    }

    /// The time `i` (advanced to now) reaches the surface of its shell, in `cross[0]`.
    #[inline]
    fn predict_crossing<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize) {
        let (x, v) = (s.slot[i].kin.pos, s.slot[i].kin.vel);
        let d = sub(x, self.centre[i]);
        let (b, v2) = (dot(d, v), dot(v, v));
        let inside = self.reach * self.reach - dot(d, d);
        // The positive root of |d + v t|² = reach²: (−b + √(b² + v²·inside)) / v².
        let dt = if v2 > 0.0 {
            ((-b + (b * b + v2 * inside).max(0.0).sqrt()) / v2).max(0.0)
        } else {
            f64::INFINITY
        };
        s.slot[i].ev.cross[0] = s.time + dt;
    }

    /// `i` reached the surface of its shell: re-centre it there and rebuild its list.
    /// Its trajectory is unchanged, so its prediction stands and only the particles new
    /// to its list are tested (as a crossing tests only the new layer of cells).
    fn crossing<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize, _: usize, _: i64) {
        let now = s.time;
        s.advance(i, now);
        let x = s.wrap_slot(i, s.slot[i].kin.pos);
        s.slot[i].kin.pos = x;
        self.centre[i] = x;
        self.cells.remove(i);
        self.cells.insert(i, x);
        self.rebuilds += 1;
        for &e in self.lists.of(i) {
            self.listed_at[(e >> IMAGE_BITS) as usize] = self.rebuilds;
        }
        self.lists.unlink(i);
        self.link(i, true);
        let mut fresh = std::mem::take(&mut self.fresh);
        fresh.clear();
        let old = |e: &&u32| self.listed_at[(**e >> IMAGE_BITS) as usize] == self.rebuilds;
        fresh.extend(self.lists.of(i).iter().filter(|e| !old(e)));
        let found = earliest(s, i, &fresh, &self.shifts, s.slot[i].ev.coll_time);
        s.keep_earliest(i, found);
        self.fresh = fresh;
        self.predict_crossing(s, i);
        s.schedule(i);
    }

    fn own_event<Q: EventQueue>(&mut self, _: &mut State<Q>) {
        unreachable!("neighbour lists have no events of their own")
    }

    fn placed(&mut self, _: usize, _: [f64; 3]) {
        unreachable!("neighbour lists run without eMD* jumps")
    }

    fn cell_of(&self, i: usize) -> [u32; 3] {
        self.cells.coords[i]
    }

    fn return_to(&mut self, _: usize, _: [u32; 3]) {
        unreachable!("neighbour lists run without eMD* jumps")
    }

    fn resorts_between_events(&self) -> bool {
        true
    }

    /// An event of `i` reads its count and its list: its first two lines, all of a
    /// list of up to 16 entries.
    #[inline(always)]
    fn prefetch(&self, i: usize) {
        let row = self.lists.list.as_ptr().wrapping_add(i * self.lists.stride);
        prefetch(self.lists.count.as_ptr().wrapping_add(i));
        prefetch(row);
        prefetch(row.wrapping_add(16));
    }

    /// Renumbers centres, lists and their entries; nothing is predicted again.
    fn resort<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        let order = morton_order(self.cells.coords.iter().copied());
        s.permute(&order);
        let mut new_index = vec![0u32; order.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        self.cells.renumber(&order, &new_index);
        let mut centre = Vec::new();
        crate::state::permute(&mut self.centre, &order, &mut centre);
        self.lists.renumber(&order, &new_index);
        s.refile();
        s.stats.resorts += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_codes_name_their_shift_and_its_opposite() {
        let region = SimBox {
            lo: [0.0; 3],
            size: [10.0, 20.0, 30.0],
            periodic: [true; 3],
        };
        let nb = Neighbours::new(&region, 1.0, 4);
        assert_eq!(image_code([0, 0, 0]), NO_SHIFT);
        assert_eq!(nb.shifts[NO_SHIFT as usize], [0.0; 3]);
        for image in [[1, 0, -1], [-1, 1, 1], [0, -1, 0]] {
            let code = image_code(image);
            let expect: [f64; 3] = std::array::from_fn(|k| f64::from(image[k]) * region.size[k]);
            assert_eq!(nb.shifts[code as usize], expect);
            assert_eq!(nb.shifts[opposite(code) as usize], expect.map(|x| -x));
        }
    }
}
