//! The hybrid's event-driven part as a host of `emdstar_edmd`'s collision rules: the
//! same E^φ, E^v and exceptions as the event engine, applied to the ED particles.

use super::Hybrid;
use super::record::Saved;
use crate::options::Mode;
use emdstar_contact::vec3::{add, sub};
use emdstar_edmd::Stats;
use emdstar_edmd::collision::{Host, LastContact, NONE, RotationProbe};
use emdstar_system::Wall;

impl Host for Hybrid {
    type Saved = Saved;

    #[inline]
    fn now(&self) -> f64 {
        self.now
    }

    #[inline]
    fn particles(&self) -> usize {
        self.mode.len()
    }

    #[inline]
    fn sync(&mut self, i: usize) {
        self.sync(i, self.now);
    }

    #[inline]
    fn position(&self, i: usize) -> [f64; 3] {
        self.system.particles.position[i]
    }

    #[inline]
    fn velocity(&self, i: usize) -> [f64; 3] {
        self.system.particles.velocity[i]
    }

    /// Also keeps the bound on ED speeds that the guard and the list rely on.
    #[inline]
    fn set_velocity(&mut self, i: usize, v: [f64; 3]) {
        self.system.particles.velocity[i] = v;
        self.note_speed(v);
    }

    #[inline]
    fn spin(&self, i: usize) -> [f64; 3] {
        self.system.particles.angular_velocity[i]
    }

    #[inline]
    fn set_spin(&mut self, i: usize, w: [f64; 3]) {
        self.system.particles.angular_velocity[i] = w;
    }

    #[inline]
    fn radius(&self, i: usize) -> f64 {
        self.system.particles.radius[i]
    }

    #[inline]
    fn mass(&self, i: usize) -> f64 {
        self.system.particles.mass[i]
    }

    #[inline]
    fn species(&self, i: usize) -> u32 {
        self.system.particles.species[i]
    }

    #[inline]
    fn min_image(&self, d: [f64; 3]) -> [f64; 3] {
        self.system.domain.min_image(d)
    }

    #[inline]
    fn gravity(&self) -> [f64; 3] {
        self.system.domain.gravity
    }

    #[inline]
    fn walls(&self) -> &[Wall] {
        &self.system.domain.walls
    }

    #[inline]
    fn pending_time(&self, i: usize) -> f64 {
        self.ed[i].pending_time
    }

    #[inline]
    fn pending_velocity(&self, i: usize) -> [f64; 3] {
        self.ed[i].pending_vel
    }

    #[inline]
    fn partner(&self, i: usize) -> u32 {
        self.ed[i].partner
    }

    #[inline]
    fn begin_transient(&mut self, i: usize, end: f64, after: [f64; 3], partner: u32) {
        let rec = &mut self.ed[i];
        rec.pending_vel = after;
        rec.pending_time = end;
        rec.partner = partner;
        self.note_speed(after);
    }

    #[inline]
    fn clear_transient(&mut self, i: usize) {
        self.ed[i].pending_time = f64::INFINITY;
        self.ed[i].partner = NONE;
    }

    #[inline]
    fn changed(&mut self, i: usize) {
        self.ed[i].counter = self.ed[i].counter.wrapping_add(1);
    }

    #[inline]
    fn last_contact(&self, i: usize) -> LastContact {
        self.ed[i].last_contact
    }

    #[inline]
    fn set_last_contact(&mut self, i: usize, c: LastContact) {
        self.ed[i].last_contact = c;
    }

    /// Moves `i` by the jump to `x` in its own coordinates (the list's image shifts
    /// refer to them), counts the jump against the list's skin, and on the cell path
    /// wraps it into the box and files it in its new cell.
    fn place(&mut self, i: usize, x: [f64; 3]) {
        let old = self.system.particles.position[i];
        let d = self.system.domain.min_image(sub(x, old));
        self.system.particles.position[i] = add(old, d);
        self.ed[i].stamp = self.now;
        self.record_jump(i, d);
        self.file_in_cell(i);
    }

    fn save(&self, i: usize) -> Saved {
        Saved {
            position: self.system.particles.position[i],
            velocity: self.system.particles.velocity[i],
            stamp: self.ed[i].stamp,
            cell: self.grid.as_ref().map(|g| g.coords[i]),
        }
    }

    fn restore(&mut self, i: usize, saved: Saved) {
        self.system.particles.position[i] = saved.position;
        self.system.particles.velocity[i] = saved.velocity;
        self.ed[i].stamp = saved.stamp;
        if let (Some(grid), Some(cell)) = (self.grid.as_mut(), saved.cell) {
            grid.relocate(i, cell);
        }
    }

    #[inline]
    fn predict(&mut self, i: usize) {
        debug_assert_eq!(self.mode[i], Mode::Event);
        self.predict(i, self.now);
    }

    #[inline]
    fn probe(&mut self) -> &mut Option<RotationProbe<Saved>> {
        &mut self.probe
    }

    #[inline]
    fn stats(&mut self) -> &mut Stats {
        &mut self.stats.ed
    }
}
