//! The cost floor of cell crossings: free spheres fly through the engine's own
//! [`CellGrid`] and [`CalendarQueue`], and every crossing does what the engine's
//! crossing does (move on, change cell, test the new layer, predict the next crossing,
//! file the particle) — with no collisions, no eMD* transients and no statistics.
//! In a dilute gas almost every event is a crossing, so this bounds from below what any
//! engine built on these structures can cost per event.
//!
//! ```text
//! cargo run --release -p emdstar-edmd --example crossing_floor -- [ETA] [N] [SECONDS] [WIDTH]
//! ```
//!
//! Defaults: η = 0.001, N = 2000, 3 s per variant; spheres of radius 0.1 m, rms speed
//! 2 m/s, cells as wide as the engine's automatic width (or WIDTH metres, if given). Four variants run one after
//! another, each dropping one part of the work, so their differences give the cost of
//! each part: the pair tests, the reads of the new layer's cells, and the queue. A
//! last row runs the full crossing on the 4-ary heap instead of the calendar queue.

use emdstar_edmd::cells::{CellGrid, NONE, auto_cell_width};
use emdstar_edmd::detect::sphere_sphere;
use emdstar_edmd::{CalendarQueue, EventQueue, IndexedHeap};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

const RADIUS: f64 = 0.1;
const RMS_SPEED: f64 = 2.0;

/// What a variant leaves out.
#[derive(Clone, Copy, PartialEq)]
enum Variant {
    Full,
    NoPairTests,
    NoLayerScan,
    NoQueue,
}

impl Variant {
    fn label(self) -> &'static str {
        match self {
            Self::Full => "full crossing",
            Self::NoPairTests => "without pair tests",
            Self::NoLayerScan => "without the layer scan",
            Self::NoQueue => "without layer scan and queue",
        }
    }
}

/// A position and velocity valid at `stamp`, as the engine's `Kin`.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Kin {
    pos: [f64; 3],
    stamp: f64,
    vel: [f64; 3],
}

struct Gas<Q: EventQueue> {
    kin: Vec<Kin>,
    grid: CellGrid,
    cross: Vec<[f64; 3]>,
    queue: Q,
    /// Earliest collision found by the pair tests (kept so they are not optimised out).
    earliest: Vec<f64>,
}

impl<Q: EventQueue> Gas<Q> {
    fn new(eta: f64, n: usize, width: Option<f64>, seed: u64) -> Self {
        let volume = n as f64 * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3) / eta;
        let l = volume.cbrt();
        let width = width.unwrap_or_else(|| auto_cell_width(2.0 * RADIUS, volume, n));
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sigma = RMS_SPEED / 3f64.sqrt();
        let mut normal = || {
            let (a, b): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
            sigma * (-2.0 * a.ln()).sqrt() * (std::f64::consts::TAU * b).cos()
        };
        let vel: Vec<[f64; 3]> = (0..n).map(|_| [normal(), normal(), normal()]).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed + 1);
        let kin: Vec<Kin> = vel
            .into_iter()
            .map(|v| Kin {
                pos: std::array::from_fn(|_| rng.random::<f64>() * l),
                stamp: 0.0,
                vel: v,
            })
            .collect();
        let mut grid = CellGrid::new([0.0; 3], [l; 3], [true; 3], width, n);
        let mut gas = Self {
            cross: vec![[f64::INFINITY; 3]; n],
            queue: Q::new(n),
            earliest: vec![f64::INFINITY; n],
            grid: {
                for (i, k) in kin.iter().enumerate() {
                    let c = grid.coords_of(k.pos);
                    grid.insert(i, c);
                }
                grid
            },
            kin,
        };
        for i in 0..n {
            for axis in 0..3 {
                gas.predict_axis(i, axis, 0.0);
            }
            gas.queue.set(i, gas.next_crossing(i).0);
        }
        gas
    }

    fn predict_axis(&mut self, i: usize, axis: usize, now: f64) {
        let c = self.grid.coords[i][axis];
        let k = self.kin[i];
        let (dt, _) = self
            .grid
            .axis_crossing(axis, c, k.pos[axis], k.vel[axis], 0.0);
        self.cross[i][axis] = now + dt;
    }

    fn next_crossing(&self, i: usize) -> (f64, usize) {
        let c = self.cross[i];
        let mut axis = 0;
        for k in 1..3 {
            if c[k] < c[axis] {
                axis = k;
            }
        }
        (c[axis], axis)
    }

    /// Runs crossings for `seconds` of wall time: (crossings, pair tests, wall s,
    /// simulated s).
    fn run(&mut self, variant: Variant, seconds: f64) -> (u64, u64, f64, f64) {
        let n = self.kin.len();
        let (mut events, mut pairs, mut now) = (0u64, 0u64, 0.0);
        let start = Instant::now();
        while events % 4096 != 0 || start.elapsed().as_secs_f64() < seconds {
            let i = if variant == Variant::NoQueue {
                // Round robin: the same work per crossing, out of time order.
                (events as usize).wrapping_mul(7919) % n
            } else {
                self.queue.peek().0
            };
            let (t, axis) = self.next_crossing(i);
            now = t;
            events += 1;
            let k = &mut self.kin[i];
            let dt = now - k.stamp;
            k.pos = std::array::from_fn(|m| k.pos[m] + k.vel[m] * dt);
            k.stamp = now;
            let dir = if k.vel[axis] > 0.0 { 1 } else { -1 };
            let mut c = self.grid.coords[i];
            let (next, shift) = self.grid.step(axis, c[axis], dir);
            c[axis] = next;
            k.pos[axis] += shift;
            self.grid.relocate(i, c);
            if matches!(variant, Variant::Full | Variant::NoPairTests) {
                pairs += self.scan_layer(i, c, axis, dir, variant == Variant::Full, now);
            }
            self.predict_axis(i, axis, now);
            if variant != Variant::NoQueue {
                self.queue.set(i, self.next_crossing(i).0);
            }
        }
        (events, pairs, start.elapsed().as_secs_f64(), now)
    }

    /// Tests `i` against the new layer of cells (the engine's `scan_new_layer`).
    fn scan_layer(
        &mut self,
        i: usize,
        c: [u32; 3],
        axis: usize,
        dir: i64,
        test: bool,
        now: f64,
    ) -> u64 {
        let (pi, vi) = (self.kin[i].pos, self.kin[i].vel);
        let mut best = self.earliest[i];
        let mut pairs = 0;
        let mut visit = |cell: u32, shift: [f64; 3]| {
            let mut j = self.grid.first(cell);
            if !test {
                best = best.min(f64::from(j));
                return;
            }
            while j != NONE {
                let kj = self.kin[j as usize];
                let dt = now - kj.stamp;
                let r = std::array::from_fn(|m| pi[m] - shift[m] - kj.pos[m] - kj.vel[m] * dt);
                let v = std::array::from_fn(|m| vi[m] - kj.vel[m]);
                best = best.min(now + sphere_sphere(r, v, 2.0 * RADIUS));
                pairs += 1;
                j = self.grid.next(j);
            }
        };
        // As the engine: interior cells by fixed offsets, border cells with shifts.
        if let Some(base) = self.grid.interior(c) {
            for cell in self.grid.interior_layer(base, axis, dir) {
                visit(cell, [0.0; 3]);
            }
        } else {
            for (cell, shift) in self.grid.new_layer(c, axis, dir).iter() {
                visit(cell, shift);
            }
        }
        self.earliest[i] = best;
        pairs
    }
}

/// Prints one row: ns per crossing, pair tests per crossing, wall s per simulated s.
fn report(label: &str, variant: Variant, (events, pairs, wall, simulated): (u64, u64, f64, f64)) {
    let per_sim = if variant == Variant::NoQueue {
        "(out of order)".to_string()
    } else {
        format!("{:.3e}", wall / simulated)
    };
    println!(
        "{:<30} {:>12.1} {:>16.2} {:>22}",
        label,
        wall / events as f64 * 1e9,
        pairs as f64 / events as f64,
        per_sim
    );
}

fn main() -> Result<(), String> {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{e}; usage: crossing_floor [ETA] [N] [SECONDS] [WIDTH]"))?;
    let eta = args.first().copied().unwrap_or(0.001);
    let n = args.get(1).copied().unwrap_or(2000.0) as usize;
    let seconds = args.get(2).copied().unwrap_or(3.0);
    let width = args.get(3).copied();
    if !(eta > 0.0 && eta < 0.5 && n >= 2 && seconds > 0.0) {
        return Err("need 0 < ETA < 0.5, N ≥ 2 and SECONDS > 0".into());
    }
    if width.is_some_and(|w| !(w >= 2.0 * RADIUS && w.is_finite())) {
        return Err(format!(
            "WIDTH must be at least the contact distance {} m",
            2.0 * RADIUS
        ));
    }
    let probe = Gas::<CalendarQueue>::new(eta, n, width, 7);
    println!(
        "η = {eta}, N = {n}: {:?} cells of {:.3} m",
        probe.grid.dims, probe.grid.width[0]
    );
    println!(
        "{:<30} {:>12} {:>16} {:>22}",
        "variant", "ns/crossing", "pairs/crossing", "wall s per simulated s"
    );
    for variant in [
        Variant::Full,
        Variant::NoPairTests,
        Variant::NoLayerScan,
        Variant::NoQueue,
    ] {
        let mut gas = Gas::<CalendarQueue>::new(eta, n, width, 7);
        report(variant.label(), variant, gas.run(variant, seconds));
    }
    let mut gas = Gas::<IndexedHeap>::new(eta, n, width, 7);
    let full = Variant::Full;
    report("full, 4-ary heap queue", full, gas.run(full, seconds));
    Ok(())
}
