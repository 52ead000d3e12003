//! The cell path of the event part (crate docs, "All-ED phases"): while no particle is
//! TD, the ED particles live in the linked-list cells of [`emdstar_edmd::cells`] and
//! move between them by cell-crossing events, as in the eMD* engine (Alder &
//! Wainwright 1959; Rapaport 1980; `emdstar_edmd::Engine`): a full prediction scans the
//! 27 neighbour cells, a crossing only the 9 cells of the new layer, particles are
//! updated lazily, and nothing is rebuilt or re-predicted globally. The modes are
//! checked at the cadence of the list rebuilds, on the link cells of the list path
//! (the same φ), without synchronising or re-predicting anything.

use super::Hybrid;
use crate::options::{HybridError, Mode};
use crate::phi::{any_dense, region};
use emdstar_contact::vec3::{norm, sub};
use emdstar_edmd::cells::{LinkedCells, NONE, auto_cell_width};
use emdstar_edmd::detect::{on_collision_course, sphere_sphere};

impl Hybrid {
    /// The width of the event cells, as the eMD* engine chooses it: at least the
    /// largest contact distance 2R_max, and about half the mean spacing (V/N)^(1/3) in
    /// a dilute gas (fewer crossings for a few more pair tests).
    fn cell_width(&self, lo_extent: [f64; 3]) -> f64 {
        let active = self.mode.iter().filter(|&&m| m != Mode::Removed).count();
        auto_cell_width(
            2.0 * self.system.max_radius(),
            lo_extent.iter().product(),
            active,
        )
    }

    /// Enters the cell path at a rebuild (every particle synchronised and wrapped, no
    /// particle TD): bins the ED particles. Predictions follow (by the caller). The
    /// grid covers the box, or in open space the particles' bounding box with half its
    /// extent (and a cell) to spare on every side: its border cells reach to infinity,
    /// so particles beyond are still found, but crowd them (the mode checks re-grid
    /// then).
    pub(crate) fn enter_cells(&mut self) {
        let p = &self.system.particles;
        let (mut lo, mut extent, periodic) =
            region(&p.position, self.system.domain.sim_box.as_ref());
        let width = self.cell_width(extent);
        if self.system.domain.sim_box.is_none() {
            for k in 0..3 {
                let spare = 0.5 * extent[k] + width;
                lo[k] -= spare;
                extent[k] += 2.0 * spare;
            }
        }
        let mut grid = LinkedCells::new(lo, extent, periodic, width, p.len());
        for i in 0..p.len() {
            if self.mode[i] == Mode::Event {
                let c = grid.coords_of(p.position[i]);
                grid.insert(i, c);
            }
        }
        self.grid = Some(grid);
    }

    /// Full prediction of ED particle `i` on the cell path: the particles of its own
    /// and the neighbouring cells, the walls, and the next cell crossing.
    pub(crate) fn predict_in_cells(&mut self, i: usize, now: f64) {
        self.sync(i, now);
        let grid = self.grid.as_ref().expect("on the cell path");
        let c = grid.coords[i];
        let found = match grid.interior(c) {
            Some(base) => self.earliest_in(
                i,
                now,
                grid.interior_neighbours(base).map(|c| (c, [0.0; 3])),
            ),
            None => self.earliest_in(i, now, grid.neighbourhood(c).iter()),
        };
        let (found, blocked) = found;
        if blocked && let Some(probe) = &mut self.probe {
            probe.blocked = true;
        }
        let (best, best_j) = self.earliest_wall(i, now, found);
        self.keep_collision(i, best, best_j);
        self.predict_crossing(i, now);
        self.schedule(i);
    }

    /// The earliest collision of `i` (synchronised at `now`) with the particles of
    /// `cells` (each with the shift of its periodic image): (time, partner or NONE),
    /// and whether a particle met blocks the rotation of a running exception-(a) probe
    /// that `i` is a party of (the cells hold every particle within contact of `i`;
    /// none is TD on this path).
    #[inline(always)]
    fn earliest_in(
        &self,
        i: usize,
        now: f64,
        cells: impl Iterator<Item = (u32, [f64; 3])>,
    ) -> ((f64, u32), bool) {
        let grid = self.grid.as_ref().expect("on the cell path");
        let p = &self.system.particles;
        let (xi, vi, ri) = (p.position[i], p.velocity[i], p.radius[i]);
        let probe = self
            .probe
            .and_then(|probe| Some((probe, probe.slot_of(i)?)));
        let min_image = |d| self.system.domain.min_image(d);
        let mut blocked = false;
        let mut best = f64::INFINITY;
        let mut best_j = NONE;
        for (cell, s) in cells {
            let mut j = grid.first(cell);
            while j != NONE {
                let ju = j as usize;
                if ju != i && !self.in_shared_transient(i, ju) {
                    let (xj, vj) = self.state_at(ju, now);
                    let r: [f64; 3] = std::array::from_fn(|k| xi[k] - xj[k] - s[k]);
                    let sigma = ri + p.radius[ju];
                    if let Some((probe, slot)) = &probe {
                        blocked |= probe.blocks(*slot, ju, r, xj, sigma, min_image);
                    }
                    // Most candidates miss: one well-predicted test first.
                    let v = sub(vi, vj);
                    if on_collision_course(r, v, sigma) {
                        let dt = sphere_sphere(r, v, sigma);
                        if now + dt < best {
                            best = now + dt;
                            best_j = j;
                        }
                    }
                }
                j = grid.next(j);
            }
        }
        ((best, best_j), blocked)
    }

    /// The earliest crossing of a face of its cell by ED particle `i` (synchronised
    /// at `now`).
    fn predict_crossing(&mut self, i: usize, now: f64) {
        let grid = self.grid.as_ref().expect("on the cell path");
        let p = &self.system.particles;
        let (dt, face) = grid.next_crossing(
            grid.coords[i],
            p.position[i],
            p.velocity[i],
            self.system.domain.gravity,
        );
        self.ed[i].cross_time = now + dt;
        self.ed[i].cross_face = face;
    }

    /// A cell crossing of ED particle `i` at `t`: it moves to the next cell (wrapping
    /// at a periodic face) and is tested against the layer of cells that became its
    /// neighbours; its earlier prediction stands otherwise.
    pub(crate) fn crossing(&mut self, i: usize, t: f64) {
        self.stats.ed.crossings += 1;
        self.sync(i, t);
        let face = self.ed[i].cross_face as usize;
        let (axis, dir) = (face / 2, if face % 2 == 1 { 1 } else { -1 });
        let grid = self.grid.as_mut().expect("on the cell path");
        let mut c = grid.coords[i];
        let (next, shift) = grid.step(axis, c[axis], dir);
        c[axis] = next;
        grid.relocate(i, c);
        self.system.particles.position[i][axis] += shift;
        if !self.ed[i].frozen {
            let grid = self.grid.as_ref().expect("on the cell path");
            let (best, j) = match grid.interior(c) {
                Some(base) => self.earliest_in(
                    i,
                    t,
                    grid.interior_layer(base, axis, dir).map(|c| (c, [0.0; 3])),
                ),
                None => self.earliest_in(i, t, grid.new_layer(c, axis, dir).iter()),
            }
            .0;
            if j != NONE && best < self.ed[i].coll_time {
                self.keep_collision(i, best, j);
            }
        }
        self.predict_crossing(i, t);
        self.schedule(i);
    }

    /// After an eMD* position jump of `i` (synchronised): on the cell path, wraps it
    /// into the box and moves it to the cell it now lies in.
    pub(crate) fn file_in_cell(&mut self, i: usize) {
        if let Some(grid) = self.grid.as_mut() {
            let x = self.system.particles.position[i];
            let x = self.system.domain.sim_box.map_or(x, |b| b.wrap(x));
            self.system.particles.position[i] = x;
            let c = grid.coords_of(x);
            grid.relocate(i, c);
        }
    }

    /// The mode check on the cell path, due when the particles may have moved one event
    /// skin: if no ED particle reaches φ ≥ `phi_time` (the only switch possible
    /// without TD particles), nothing is synchronised or re-predicted; otherwise, and
    /// for the rebuild's checks (outlet, blow-up, leaving the box) and a particle off
    /// the grid in open space, it falls back to the full rebuild, which decides the
    /// modes on the list (and re-enters the cell path with a new grid if all stay ED).
    #[inline(never)]
    pub(crate) fn cell_pass(&mut self) -> Result<(), HybridError> {
        let t = self.time();
        let mut v_max: f64 = 0.0;
        let mut rebuild = false;
        let p = &self.system.particles;
        let mut positions = std::mem::take(&mut self.positions_now);
        let mut radius = std::mem::take(&mut self.radius_now);
        positions.clear();
        radius.clear();
        for i in 0..self.mode.len() {
            if self.mode[i] != Mode::Event {
                positions.push(p.position[i]);
                radius.push(0.0);
                continue;
            }
            let (x, v) = self.state_at(i, t);
            positions.push(x);
            radius.push(p.radius[i]);
            let outside = self
                .system
                .domain
                .sim_box
                .is_some_and(|b| b.outside_closed_axis(x).is_some());
            let gone = self.opts.outlet.is_some_and(|o| o.distance(x) < 0.0);
            let grid = self.grid.as_ref().expect("on the cell path");
            let off_grid = self.system.domain.sim_box.is_none()
                && (0..3).any(|k| {
                    !(grid.shape.lo[k]..=grid.shape.lo[k] + grid.shape.size[k]).contains(&x[k])
                });
            if outside || gone || off_grid || !x.iter().chain(&v).all(|c| c.is_finite()) {
                rebuild = true;
                break;
            }
            v_max = v_max.max(norm(v));
            if self.ed[i].pending_time.is_finite() {
                v_max = v_max.max(norm(self.ed[i].pending_vel));
            }
        }
        let dense = !rebuild
            && self.opts.adaptive
            && any_dense(
                &positions,
                &radius,
                region(&positions, self.system.domain.sim_box.as_ref()),
                2.0 * self.system.max_radius() + self.skin,
                self.opts.phi_time,
                &mut self.dense,
            );
        self.positions_now = positions;
        self.radius_now = radius;
        if rebuild || dense {
            return self.rebuild(self.opts.adaptive);
        }
        // The cadence follows the gas (a cloud in open space may contract or spread).
        self.list_skin = self.event_skin(&self.positions_now);
        self.v_max_ed = v_max;
        self.drift_bound = 0.0;
        self.jump.iter_mut().for_each(|j| *j = 0.0);
        self.max_jump = 0.0;
        self.stats.cell_passes += 1;
        Ok(())
    }
}
