//! Keeping the list and the modes up to date: list rebuilds (which also decide the
//! modes) while some particle is TD, and mode checks while none is (crate docs, "All-ED
//! phases").

use super::Hybrid;
use crate::options::{HybridError, Mode};
use crate::phi::{any_dense, region};
use emdstar_contact::vec3::norm;

/// When the list is rebuilt or the modes are checked.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Upkeep {
    /// Whether the Verlet driver's list is kept (some particle is TD). Without it,
    /// the modes are checked when the ED particles may have moved one `event_skin`.
    pub list: bool,
    /// The mean particle spacing, at least the list skin (and small enough for three
    /// cells along every periodic axis).
    pub event_skin: f64,
    /// How far an ED particle may have flown since the last rebuild or check (its
    /// jumps apart).
    pub ed_drift: f64,
}

impl Upkeep {
    /// Whether a mode check is due before a step of `dt` at ED speeds up to `v_ed`,
    /// after jumps of up to `jump` (NaN, a blow-up, makes it due).
    pub fn check_due(&self, v_ed: f64, jump: f64, dt: f64) -> bool {
        let reach = self.ed_drift + jump + v_ed * dt;
        reach.is_nan() || reach > self.event_skin
    }
}

impl Hybrid {
    /// Writes every ED particle's position and velocity at time `t` into its entry
    /// (the event core keeps its own state; nothing is moved there).
    pub(super) fn refresh_event_copies(&mut self, t: f64) {
        let p = &mut self.system.particles;
        for i in 0..p.len() {
            if self.modes.of(i) == Mode::Event {
                (p.position[i], p.velocity[i]) = self.ed.motion_at(i, t);
            }
        }
    }

    /// The list rebuild at the current step boundary: removes the particles behind
    /// the outlet, checks the state, sorts the particles by cell (the event core and the
    /// modes renumbered alike), rebuilds the list and, if `decide`, decides the modes.
    /// Without TD particles afterwards, mode checks take over from the list.
    pub(super) fn rebuild(&mut self, decide: bool) -> Result<(), HybridError> {
        let t = self.time();
        self.refresh_event_copies(t);
        if let Some(outlet) = self.opts.outlet {
            let p = &self.system.particles;
            let gone: Vec<usize> = (0..p.len())
                .filter(|&i| self.modes.of(i) != Mode::Removed)
                .filter(|&i| outlet.distance(p.position[i]) < 0.0)
                .collect();
            if !gone.is_empty() {
                self.in_step(t)?;
            }
            for i in gone {
                self.remove(i);
            }
        }
        let modes = &self.modes;
        let order = self
            .td
            .rebuild(&mut self.system, t, |i| modes.of(i) == Mode::Removed)?;
        self.modes.permute(&order);
        self.ed.renumber(&order);
        let mut new_index = vec![0u32; order.len()];
        for (k, &old) in order.iter().enumerate() {
            new_index[old as usize] = k as u32;
        }
        for i in &mut self.scratch.fresh {
            *i = new_index[*i as usize];
        }
        self.book.restart();
        self.upkeep.ed_drift = 0.0;
        if decide {
            self.decide_modes(t)?;
        }
        self.stats.rebuilds += 1;
        if !self.modes.any(Mode::Time) {
            self.events_only();
            return Ok(());
        }
        self.upkeep.list = true;
        self.book.v_max = self.ed_speeds();
        self.boundary.clear();
        if self.modes.any(Mode::Event) {
            self.td.complete_list();
            let list = self.td.list();
            for i in 0..self.modes.len() {
                let mixed = self.modes.of(i) == Mode::Time
                    && list
                        .neighbours(i)
                        .any(|e| self.modes.of(list.split(e).0) == Mode::Event);
                if mixed {
                    self.boundary.push(i as u32);
                }
            }
        }
        Ok(())
    }

    /// Enters the phase without TD particles (every particle's entry holds its state
    /// now): no list, mode checks after one event skin of flight.
    pub(super) fn events_only(&mut self) {
        self.upkeep.list = false;
        self.upkeep.ed_drift = 0.0;
        self.boundary.clear();
        self.book.restart();
        self.book.v_max = self.ed_speeds();
        self.upkeep.event_skin = self.event_skin(&self.system.particles.position);
    }

    /// The largest speed of an ED particle now, pending E^v velocities included.
    pub(super) fn ed_speeds(&self) -> f64 {
        let t = self.time();
        let mut v_max: f64 = 0.0;
        for i in 0..self.modes.len() {
            if self.modes.of(i) == Mode::Event {
                v_max = v_max.max(norm(self.ed.motion_at(i, t).1));
                if let Some(v) = self.ed.pending_velocity(i) {
                    v_max = v_max.max(norm(v));
                }
            }
        }
        v_max
    }

    /// The skin of the mode checks while every particle is ED: the mean particle
    /// spacing (a dilute gas gains little from checking more often), at least the
    /// list skin, and small enough for 3 cells along every periodic axis.
    fn event_skin(&self, positions: &[[f64; 3]]) -> f64 {
        let active = self.modes.len() - self.modes.count(Mode::Removed);
        let (_, extent, periodic) = region(positions, self.system.domain.sim_box.as_ref());
        let r2 = 2.0 * self.system.max_radius();
        let volume: f64 = extent.iter().map(|e| e.max(r2)).product();
        let skin = self.td.skin();
        let mut event_skin = skin.max((volume / active.max(1) as f64).cbrt());
        for k in 0..3 {
            if periodic[k] {
                event_skin = event_skin.min(extent[k] / 3.0 - r2);
            }
        }
        event_skin.max(skin)
    }

    /// The mode check while no particle is TD: moves nothing. If no ED particle reaches
    /// φ ≥ `phi_time` (the only switch possible without TD particles), nothing happens
    /// but the check's cadence and speed bound; otherwise, and for the rebuild's checks
    /// (outlet, blow-up, leaving the box), the full rebuild decides the modes on the
    /// list.
    pub(super) fn mode_check(&mut self) -> Result<(), HybridError> {
        let t = self.time();
        let mut v_max: f64 = 0.0;
        let mut rebuild = false;
        let p = &self.system.particles;
        let mut positions = std::mem::take(&mut self.scratch.positions);
        let mut radius = std::mem::take(&mut self.scratch.radius);
        positions.clear();
        radius.clear();
        for i in 0..self.modes.len() {
            if self.modes.of(i) != Mode::Event {
                positions.push(p.position[i]);
                radius.push(0.0);
                continue;
            }
            let (x, v) = self.ed.motion_at(i, t);
            positions.push(x);
            radius.push(p.radius[i]);
            let outside = self
                .system
                .domain
                .sim_box
                .is_some_and(|b| b.outside_closed_axis(x).is_some());
            let gone = self.opts.outlet.is_some_and(|o| o.distance(x) < 0.0);
            if outside || gone || !x.iter().chain(&v).all(|c| c.is_finite()) {
                rebuild = true;
                break;
            }
            v_max = v_max.max(norm(v));
            if let Some(v) = self.ed.pending_velocity(i) {
                v_max = v_max.max(norm(v));
            }
        }
        let dense = !rebuild
            && self.opts.adaptive
            && any_dense(
                &positions,
                &radius,
                region(&positions, self.system.domain.sim_box.as_ref()),
                2.0 * self.system.max_radius() + self.td.skin(),
                self.opts.phi_time,
                &mut self.scratch.phi,
            );
        self.scratch.positions = positions;
        self.scratch.radius = radius;
        if rebuild || dense {
            return self.rebuild(self.opts.adaptive);
        }
        // The cadence follows the gas (a cloud in open space may contract or spread).
        self.upkeep.event_skin = self.event_skin(&self.scratch.positions);
        self.book.v_max = v_max;
        self.book.restart();
        self.upkeep.ed_drift = 0.0;
        self.stats.cell_passes += 1;
        Ok(())
    }
}
