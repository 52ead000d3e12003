//! The cost floor of cell crossings. Free spheres fly through the event engine's own
//! [`LinkedCells`] and event queue, and every crossing does what the engine's crossing does
//! (move on, change cell, test the new layer, predict the next crossing, file the
//! particle) with no collisions, no eMD* transients and no statistics. In a dilute gas
//! almost every event of an engine on crossings is a crossing, so this bounds from
//! below what any engine built on these structures can cost there; eMD*'s epoch broad
//! phase, the default in dilute gases, has no crossings and goes below it.
//!
//! The gas is that of [`crate::speed`] for the same packing fraction, size and seed
//! (the same lattice start and Maxwell velocities, radius 0.1 m, rms speed 2 m/s, in a
//! periodic cube), with cells of the engine's automatic width unless another is given.

use crate::engines::lattice_gas;
use crate::exceptions::{DENSITY, POISSON, RADIUS, RMS_SPEED};
use crate::speed::GOAL_GAS;
use crate::{HarnessError, Result};
use emdstar_contact::{ForceLaw, ViscoelasticHertz};
use emdstar_edmd::cells::{LinkedCells, NONE, auto_cell_width};
use emdstar_edmd::detect::sphere_sphere;
use emdstar_edmd::{CalendarQueue, EventQueue, IndexedHeap};
use emdstar_system::System;
use serde::Serialize;
use std::time::Instant;

/// What a run leaves out of each crossing; the differences between variants give the
/// cost of each part.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Variant {
    /// The whole crossing.
    Full,
    /// Reads the new layer's cells but tests no pair.
    NoPairTests,
    /// Leaves out the new layer.
    NoLayerScan,
    /// Leaves out the layer and the queue: particles are taken round robin, out of time
    /// order, so only the cost per crossing is meaningful.
    NoQueue,
}

impl Variant {
    pub const ALL: [Variant; 4] = [
        Variant::Full,
        Variant::NoPairTests,
        Variant::NoLayerScan,
        Variant::NoQueue,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Self::Full => "full crossing",
            Self::NoPairTests => "without pair tests",
            Self::NoLayerScan => "without the layer scan",
            Self::NoQueue => "without layer scan and queue",
        }
    }
}

/// The event queue a run files its crossings in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum QueueKind {
    /// The engine's default [`CalendarQueue`].
    Calendar,
    /// The 4-ary [`IndexedHeap`].
    Heap,
}

/// The gas of a floor run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FloorGas {
    pub packing_fraction: f64,
    pub particles: usize,
    /// Cell width (m); `None` takes the engine's automatic width.
    pub cell_width: Option<f64>,
    pub seed: u64,
}

/// One timed run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct FloorRun {
    pub variant: Variant,
    pub queue: QueueKind,
    pub cells_per_axis: usize,
    pub cell_width: f64,
    pub crossings: u64,
    pub pair_tests: u64,
    pub wall_s: f64,
    pub simulated_s: f64,
}

impl FloorRun {
    /// Wall time per crossing, ns.
    pub fn ns_per_crossing(&self) -> f64 {
        self.wall_s / self.crossings.max(1) as f64 * 1e9
    }

    /// Pair tests per crossing.
    pub fn pair_tests_per_crossing(&self) -> f64 {
        self.pair_tests as f64 / self.crossings.max(1) as f64
    }

    /// Wall seconds per simulated second; `None` for [`Variant::NoQueue`], which runs
    /// out of time order.
    pub fn cost(&self) -> Option<f64> {
        (self.variant != Variant::NoQueue).then(|| self.wall_s / self.simulated_s)
    }
}

/// Runs `variant` on `gas` for `seconds` of wall time.
pub fn run(gas: &FloorGas, variant: Variant, queue: QueueKind, seconds: f64) -> Result<FloorRun> {
    if !(gas.packing_fraction > 0.0 && gas.packing_fraction < 0.5) {
        return Err(HarnessError::Invalid(format!(
            "packing fraction {} is outside (0, 0.5)",
            gas.packing_fraction
        )));
    }
    if gas.particles < 2 || !(seconds > 0.0 && seconds.is_finite()) {
        return Err(HarnessError::Invalid(format!(
            "need at least 2 particles and a positive time (got {} and {seconds} s)",
            gas.particles
        )));
    }
    if let Some(w) = gas
        .cell_width
        .filter(|w| !(*w >= 2.0 * RADIUS && w.is_finite()))
    {
        return Err(HarnessError::Invalid(format!(
            "cell width {w} m is below the contact distance {} m",
            2.0 * RADIUS
        )));
    }
    // The speed check's gas: the same lattice start and Maxwell velocities for the same
    // seed (the contact law does not enter free flight).
    let law = ForceLaw::Hertz(ViscoelasticHertz::new(GOAL_GAS.1, POISSON, 0.0)?);
    let system = lattice_gas(
        &law,
        DENSITY,
        RADIUS,
        gas.particles,
        gas.packing_fraction,
        RMS_SPEED,
        gas.seed,
    )?;
    Ok(match queue {
        QueueKind::Calendar => {
            Flight::<CalendarQueue>::new(&system, gas.cell_width)?.run(variant, queue, seconds)
        }
        QueueKind::Heap => {
            Flight::<IndexedHeap>::new(&system, gas.cell_width)?.run(variant, queue, seconds)
        }
    })
}

/// A position and velocity valid at `stamp`, as the engine's own per-particle line.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Kin {
    pos: [f64; 3],
    stamp: f64,
    vel: [f64; 3],
}

struct Flight<Q: EventQueue> {
    kin: Vec<Kin>,
    grid: LinkedCells,
    cross: Vec<[f64; 3]>,
    queue: Q,
    /// Earliest collision found by the pair tests (kept so they are not optimised out).
    earliest: Vec<f64>,
}

impl<Q: EventQueue> Flight<Q> {
    fn new(system: &System, cell_width: Option<f64>) -> Result<Self> {
        let sim_box = system
            .domain
            .sim_box
            .ok_or_else(|| HarnessError::Invalid("the lattice gas has no box".into()))?;
        let n = system.particles.len();
        let width =
            cell_width.unwrap_or_else(|| auto_cell_width(2.0 * RADIUS, sim_box.volume(), n));
        let kin: Vec<Kin> = system
            .particles
            .position
            .iter()
            .zip(&system.particles.velocity)
            .map(|(&pos, &vel)| Kin {
                pos,
                stamp: 0.0,
                vel,
            })
            .collect();
        let mut grid = LinkedCells::new(sim_box.lo, sim_box.size, sim_box.periodic, width, n);
        for (i, k) in kin.iter().enumerate() {
            let c = grid.coords_of(k.pos);
            grid.insert(i, c);
        }
        let mut flight = Self {
            kin,
            grid,
            cross: vec![[f64::INFINITY; 3]; n],
            queue: Q::new(n),
            earliest: vec![f64::INFINITY; n],
        };
        for i in 0..n {
            for axis in 0..3 {
                flight.predict_axis(i, axis, 0.0);
            }
            flight.queue.set(i, flight.next_crossing(i).0);
        }
        Ok(flight)
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

    fn run(&mut self, variant: Variant, queue: QueueKind, seconds: f64) -> FloorRun {
        let n = self.kin.len();
        let (mut crossings, mut pair_tests, mut now) = (0u64, 0u64, 0.0);
        let start = Instant::now();
        while crossings % 4096 != 0 || start.elapsed().as_secs_f64() < seconds {
            let i = if variant == Variant::NoQueue {
                (crossings as usize).wrapping_mul(7919) % n
            } else {
                self.queue.peek().0
            };
            let (t, axis) = self.next_crossing(i);
            now = t;
            crossings += 1;
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
                let test = variant == Variant::Full;
                pair_tests += self.scan_layer(i, c, axis, dir, test, now);
            }
            self.predict_axis(i, axis, now);
            if variant != Variant::NoQueue {
                self.queue.set(i, self.next_crossing(i).0);
            }
        }
        FloorRun {
            variant,
            queue,
            cells_per_axis: self.grid.shape.dims[0],
            cell_width: self.grid.shape.width[0],
            crossings,
            pair_tests,
            wall_s: start.elapsed().as_secs_f64(),
            simulated_s: now,
        }
    }

    /// Tests `i` against the new layer of cells, as the engine's `scan_new_layer`:
    /// interior cells by fixed offsets, border cells with their image shifts. Returns
    /// the number of pair tests.
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossings_follow_the_kinetic_rate_and_pair_tests_the_density() {
        // Free flight at rms speed v: each particle crosses cell faces along axis k at
        // the rate ⟨|v_k|⟩/w = v·√(2/(3π))/w, so N particles give 3N·that per second.
        // Each crossing meets the 9 cells of its layer, holding 9·w³·n particles.
        let gas = FloorGas {
            packing_fraction: 0.01,
            particles: 1000,
            cell_width: None,
            seed: 3,
        };
        let r = run(&gas, Variant::Full, QueueKind::Calendar, 0.2).unwrap();
        let w = r.cell_width;
        let rate =
            3.0 * gas.particles as f64 * RMS_SPEED * (2.0 / (3.0 * std::f64::consts::PI)).sqrt()
                / w;
        let measured = r.crossings as f64 / r.simulated_s;
        assert!((measured / rate - 1.0).abs() < 0.05, "{measured} vs {rate}");
        let n = gas.packing_fraction / (4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3));
        let expected = 9.0 * w.powi(3) * n;
        let got = r.pair_tests_per_crossing();
        assert!((got / expected - 1.0).abs() < 0.1, "{got} vs {expected}");
        // The other queue and the out-of-order variant run too.
        let h = run(&gas, Variant::Full, QueueKind::Heap, 0.05).unwrap();
        assert!(h.crossings > 0 && h.cost().is_some());
        assert!(
            run(&gas, Variant::NoQueue, QueueKind::Calendar, 0.05)
                .unwrap()
                .cost()
                .is_none()
        );
    }

    #[test]
    fn bad_gases_are_errors() {
        let mut gas = FloorGas {
            packing_fraction: 0.6,
            particles: 100,
            cell_width: None,
            seed: 1,
        };
        assert!(run(&gas, Variant::Full, QueueKind::Calendar, 0.01).is_err());
        gas.packing_fraction = 0.01;
        gas.cell_width = Some(0.05);
        assert!(run(&gas, Variant::Full, QueueKind::Calendar, 0.01).is_err());
        gas.cell_width = None;
        assert!(run(&gas, Variant::Full, QueueKind::Calendar, f64::NAN).is_err());
    }
}
