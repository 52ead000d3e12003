//! The epoch broad phase of the event engine (see [`crate::sweep`]): which particles
//! to test is decided once per epoch from swept boxes, so a particle that meets
//! nobody costs no event at all between rebuilds. The collision events themselves are
//! the same as with cell crossings: Bannerman et al. 2014, Algorithm 1, for each
//! candidate pair, with the earliest kept per particle.
//!
//! Invariants:
//! - every particle is filed under the cells of a box holding its sphere from its last
//!   change of course until its horizon (the epoch's end, or earlier for a particle
//!   so fast that it would reach a quarter of a periodic box, which then renews its
//!   box at that time);
//! - a predicted pair collision lies before both horizons, where the minimum image at
//!   the time of prediction is the only image in reach.

use super::BroadPhase;
use super::epoch_pairs::PairTests;
use crate::cells::{CellShape, NONE};
use crate::detect::{on_collision_course, sphere_sphere};
use crate::queue::EventQueue;
use crate::state::{State, morton_order, same_encoding};
use crate::sweep::{Filing, Spans, SweepGrid};
use emdstar_contact::vec3::{dot, sub};
use emdstar_system::SimBox;

/// A particle's state at the start of an epoch and the end of its box: what a pair
/// test reads, in one cache line.
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
#[repr(C, align(64))]
pub(super) struct Motion {
    pub pos: [f64; 3],
    pub radius: f64,
    pub vel: [f64; 3],
    pub horizon: f64,
}

/// The epoch broad phase's grid and state.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Epochs {
    pub(crate) grid: SweepGrid,
    /// End of the running epoch.
    pub(crate) end: f64,
    /// An epoch lasts `flight` cell widths of flight at the rms speed.
    flight: f64,
    width: f64,
    /// Largest flight along each periodic axis in one box (∞ along closed axes).
    reach: [f64; 3],
    /// Each particle at the rebuild: its motion and its eMD* transient partner.
    motion: Vec<Motion>,
    partner: Vec<u32>,
    /// The rebuild's best pair per particle.
    best: Vec<(f64, u32)>,
    /// The rebuild's candidate pairs (scratch).
    #[serde(skip)]
    pairs: Vec<[u32; 2]>,
    /// A prediction's candidates (scratch).
    #[serde(skip)]
    candidates: Vec<u32>,
    /// The cells whose Morton order the particles are re-sorted in (those the
    /// crossing broad phase would use).
    keys: CellShape,
}

/// Cell width of the epoch grid in units of the mean spacing (V/N)^(1/3), and the
/// flight per epoch in cell widths at the rms speed: the measured optimum for the
/// elastic Hertz gas at η = 0.001 (widths 0.6-1.6, flights 0.3-2.2 tried; within 5 %
/// of the best from 0.8 to 1.0 and 0.6 to 1.2).
pub(crate) const EPOCH_CELL: f64 = 0.8;
pub(crate) const EPOCH_FLIGHT: f64 = 1.0;

/// Relative margin on every swept box, far above the round-off of its corners.
const BOX_MARGIN: f64 = 1e-9;

impl Epochs {
    /// Epochs over `region` for `n` particles whose largest contact distance is
    /// `max_contact`, re-sorting them by cells at least `key_width` wide.
    pub(crate) fn new(region: &SimBox, max_contact: f64, n: usize, key_width: f64) -> Self {
        let width = Self::cell_width(region.size, max_contact, n);
        Self {
            grid: SweepGrid::new(region, width, n),
            end: 0.0,
            flight: EPOCH_FLIGHT,
            width,
            reach: std::array::from_fn(|k| {
                if region.periodic[k] {
                    0.25 * region.size[k] - max_contact
                } else {
                    f64::INFINITY
                }
            }),
            motion: vec![Motion::default(); n],
            partner: vec![NONE; n],
            best: vec![(f64::INFINITY, 0); n],
            pairs: Vec::new(),
            candidates: Vec::new(),
            keys: CellShape::new(region.lo, region.size, region.periodic, key_width),
        }
    }

    /// The grid's cell width: [`EPOCH_CELL`] mean spacings, at least one contact.
    fn cell_width(size: [f64; 3], max_contact: f64, n: usize) -> f64 {
        let spacing = (size.iter().product::<f64>() / n.max(1) as f64).cbrt();
        (EPOCH_CELL * spacing).max(max_contact)
    }

    /// The swept box of a sphere at `p` moving with `v` from `t0` to `end`, cut short
    /// where it would reach too far along a periodic axis: (cells, horizon).
    #[inline(always)]
    fn sweep(&self, p: [f64; 3], v: [f64; 3], radius: f64, t0: f64, end: f64) -> (Spans, f64) {
        let mut span = end - t0;
        for (vk, reach) in v.iter().zip(self.reach) {
            if vk.abs() * span > reach {
                span = reach / vk.abs();
            }
        }
        let horizon = if span < end - t0 { t0 + span } else { end };
        // Not v·span: 0·∞ for a particle at rest when the epoch never ends.
        let d = v.map(|vk| if vk == 0.0 { 0.0 } else { vk * span });
        (self.box_cells(p, d, radius), horizon)
    }

    /// [`Self::sweep`] in a tame epoch, where no box is cut: `end` is finite and no
    /// |v_k|·(end − t0) reaches too far (see [`Self::is_tame`]). The same cells, with
    /// the horizon at `end`, without the cut tests.
    #[inline(always)]
    fn uncut_sweep(&self, p: [f64; 3], v: [f64; 3], radius: f64, t0: f64, end: f64) -> Spans {
        let span = end - t0;
        self.box_cells(p, v.map(|vk| vk * span), radius)
    }

    /// Whether an epoch from `t0` to `end` is tame for particles whose velocity
    /// components are at most `v_max` in magnitude (see [`Self::uncut_sweep`]).
    fn is_tame(&self, v_max: [f64; 3], t0: f64, end: f64) -> bool {
        end.is_finite() && (0..3).all(|k| v_max[k] * (end - t0) <= self.reach[k])
    }

    /// The cells of the box of a sphere at `p` displaced by up to `d`.
    #[inline(always)]
    fn box_cells(&self, p: [f64; 3], d: [f64; 3], radius: f64) -> Spans {
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        for k in 0..3 {
            let margin = radius + BOX_MARGIN * (radius + p[k].abs() + d[k].abs());
            lo[k] = p[k] + d[k].min(0.0) - margin;
            hi[k] = p[k] + d[k].max(0.0) + margin;
        }
        self.grid.spans(lo, hi)
    }
}

impl Epochs {
    /// Starts a new epoch now: files every particle's swept box and predicts the pair
    /// collisions within the epoch (walls were predicted when each particle last
    /// changed course; pair predictions never reach past an epoch's end).
    fn rebuild<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        s.stats.epochs += 1;
        let t0 = s.time;
        let n = s.len();
        if s.resort_every > 0 && s.since_resort >= s.resort_every {
            s.since_resort = 0;
            self.resort(s);
        }
        let (mut v2, mut v_max) = (0.0, [0.0f64; 3]);
        for slot in &s.slot {
            v2 += dot(slot.kin.vel, slot.kin.vel);
            v_max = std::array::from_fn(|k| v_max[k].max(slot.kin.vel[k].abs()));
        }
        let v_rms = (v2 / n.max(1) as f64).sqrt();
        let end = if v_rms > 0.0 {
            t0 + self.flight * self.width / v_rms
        } else {
            f64::INFINITY
        };
        self.end = end;
        if self.is_tame(v_max, t0, end) {
            self.sweep_all::<true, Q>(s, t0);
        } else {
            self.sweep_all::<false, Q>(s, t0);
        }
        self.grid.file_all();
        let mut pairs = std::mem::take(&mut self.pairs);
        let listed = self.grid.filed_pairs(&mut pairs);
        let period = s.period;
        PairTests {
            motion: &self.motion,
            partner: &self.partner,
            best: &mut self.best,
            t0,
            period,
        }
        .run(listed);
        self.pairs = pairs;
        // Only particles with a pair collision or an early horizon touch the queue.
        for i in 0..n {
            let (t, j) = self.best[i];
            let collides = t < s.slot[i].ev.coll_time;
            if collides {
                s.keep_earliest(i, (t, j, t == t0));
            }
            if collides || self.motion[i].horizon < end {
                s.schedule(i);
            }
        }
        s.queue.set(n, end);
    }

    /// The rebuild's boxes: each particle's motion at `t0` and the cells of its box
    /// until the epoch's end (`TAME`: the epoch is tame, see [`Epochs::uncut_sweep`]).
    fn sweep_all<const TAME: bool, Q: EventQueue>(&mut self, s: &mut State<Q>, t0: f64) {
        let end = self.end;
        for i in 0..s.len() {
            let (mut p, v) = s.state_at(i, t0);
            let wrapped = s.wrap(p);
            if wrapped != p {
                s.advance(i, t0);
                let wrapped = s.wrap_slot(i, s.slot[i].kin.pos);
                s.slot[i].kin.pos = wrapped;
                p = wrapped;
            }
            let radius = s.slot[i].kin.radius;
            // A particle in an eMD* transient changes course at its E^v.
            let stop = end.min(s.slot[i].ev.pending_time);
            let (spans, horizon) = if TAME {
                (self.uncut_sweep(p, v, radius, t0, stop), stop)
            } else {
                self.sweep(p, v, radius, t0, stop)
            };
            self.grid.spans[i] = spans;
            self.motion[i] = Motion {
                pos: p,
                radius,
                vel: v,
                horizon,
            };
            self.partner[i] = s.slot[i].ev.partner;
            self.best[i] = (f64::INFINITY, 0);
            if horizon < end {
                s.slot[i].ev.cross[0] = horizon;
            }
        }
    }
}

impl BroadPhase for Epochs {
    /// The end of the epoch.
    const OWN_EVENTS: usize = 1;

    fn check_restored(&self, built: &Self, n: usize) -> Result<(), String> {
        self.grid.check_restored(&built.grid, n)?;
        let geometry = |e: &Self| (e.flight, e.width, e.reach, e.keys);
        let whole = same_encoding(&geometry(self), &geometry(built))
            && !self.end.is_nan()
            && [self.motion.len(), self.partner.len(), self.best.len()] == [n; 3];
        whole
            .then_some(())
            .ok_or_else(|| "the epochs are not those of the config's particles".into())
    }

    /// Whether epochs fit: a quarter of each periodic axis must exceed the largest
    /// contact distance by a cell width, and the grid must be able to file `n`.
    fn fits(region: &SimBox, max_contact: f64, n: usize) -> bool {
        let width = Self::cell_width(region.size, max_contact, n);
        n < Filing::MAX_PARTICLES
            && (0..3).all(|k| !region.periodic[k] || 0.25 * region.size[k] - max_contact >= width)
    }

    /// Nothing to file before the first epoch.
    fn file<Q: EventQueue>(&mut self, _: &State<Q>) {}

    fn start<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        for i in 0..s.len() {
            s.predict_walls(i);
            s.schedule(i);
        }
        self.rebuild(s);
    }

    /// Pair predictions of `i` (advanced to now) for the rest of the epoch, filing its
    /// new swept box; sets its horizon.
    fn predict_pairs<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize) {
        let now = s.time;
        let p = s.wrap_slot(i, s.slot[i].kin.pos);
        s.slot[i].kin.pos = p;
        let (vi, ri) = (s.slot[i].kin.vel, s.slot[i].kin.radius);
        let stop = self.end.min(s.slot[i].ev.pending_time);
        let (spans, horizon) = self.sweep(p, vi, ri, now, stop);
        s.slot[i].ev.cross[0] = if horizon < self.end {
            horizon
        } else {
            f64::INFINITY
        };
        // The candidates first, asking for their records as they are found, so that
        // the tests below wait for memory about once (in a large gas each is a miss).
        let mut candidates = std::mem::take(&mut self.candidates);
        candidates.clear();
        let state = &*s;
        self.grid.scan_and_file(i, &spans, |j| {
            candidates.push(j as u32);
            // Both lines: the tests read its motion and its event record.
            state.prefetch_record(j);
        });
        let mut best = (s.slot[i].ev.coll_time, NONE);
        let probe = s.probe_slot(i);
        let mut blocked = false;
        let state = &*s;
        for &j in &candidates {
            let j = j as usize;
            if state.in_shared_transient(i, j) {
                continue;
            }
            let (pj, vj) = state.state_at(j, now);
            let r = state.min_image(sub(p, pj));
            let (v, sigma) = (sub(vi, vj), ri + state.slot[j].kin.radius);
            if let Some((probe, slot)) = &probe {
                blocked |= state.blocks_rotation(probe, *slot, j, r, pj, sigma);
            }
            if !on_collision_course(r, v, sigma) {
                continue;
            }
            let dt = sphere_sphere(r, v, sigma);
            let limit = horizon.min(state.slot[j].ev.cross[0]);
            if now + dt < limit && now + dt < best.0 {
                best = (now + dt, j as u32);
            }
        }
        self.candidates = candidates;
        s.keep_earliest(i, (best.0, best.1, best.0 == now));
        if blocked {
            s.block_probe();
        }
    }

    /// The horizon is set by the pair prediction.
    #[inline]
    fn predict_crossing<Q: EventQueue>(&mut self, _: &mut State<Q>, _: usize) {}

    /// The swept box reached its horizon before the epoch's end: renew it.
    fn crossing<Q: EventQueue>(&mut self, s: &mut State<Q>, i: usize, _: usize, _: i64) {
        self.predict(s, i);
    }

    fn own_event<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        self.rebuild(s);
    }

    /// Boxes are filed when the particle is predicted.
    fn placed(&mut self, _: usize, _: [f64; 3]) {}

    fn cell_of(&self, _: usize) -> [u32; 3] {
        [0; 3]
    }

    fn return_to(&mut self, _: usize, _: [u32; 3]) {}

    fn resorts_between_events(&self) -> bool {
        false
    }

    /// Re-sorts by the cells the particles are in now (the boxes are filed anew at
    /// every epoch, so nothing else is kept per particle between epochs).
    fn resort<Q: EventQueue>(&mut self, s: &mut State<Q>) {
        let t = s.time;
        let cells: Vec<[u32; 3]> = (0..s.len())
            .map(|i| self.keys.coords_of(s.wrap(s.state_at(i, t).0)))
            .collect();
        let order = morton_order(cells.into_iter());
        s.permute(&order);
        s.refile();
        s.stats.resorts += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn uncut_sweeps_of_a_tame_epoch_are_the_general_sweeps() {
        let region = SimBox {
            lo: [-3.0, 0.0, 5.0],
            size: [40.0, 30.0, 50.0],
            periodic: [true, true, false],
        };
        let ep = Epochs::new(&region, 1.0, 500, 1.0);
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let (t0, end) = (2.5, 4.0);
        let v_max = [2.0, 2.0, 2.0];
        assert!(ep.is_tame(v_max, t0, end));
        assert!(!ep.is_tame(v_max, t0, t0 + 10.0), "a long epoch cuts boxes");
        assert!(!ep.is_tame(v_max, t0, f64::INFINITY));
        for n in 0..2000 {
            let p = std::array::from_fn(|k| region.lo[k] + rng.random::<f64>() * region.size[k]);
            let mut v: [f64; 3] =
                std::array::from_fn(|k| (2.0 * rng.random::<f64>() - 1.0) * v_max[k]);
            if n % 10 == 0 {
                v[n / 10 % 3] = 0.0;
            }
            let stop = if n % 4 == 0 {
                t0 + rng.random::<f64>() * (end - t0)
            } else {
                end
            };
            let (spans, horizon) = ep.sweep(p, v, 0.5, t0, stop);
            assert_eq!(horizon, stop);
            let uncut = ep.uncut_sweep(p, v, 0.5, t0, stop);
            assert_eq!(uncut, spans, "p = {p:?}, v = {v:?}");
        }
    }
}
