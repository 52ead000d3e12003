//! The modes and the switches between them: the mode rule at list rebuilds (crate
//! docs, "Modes"), the hand-over of a particle between the event core and the Verlet
//! driver, and modes set by hand.

use super::Hybrid;
use crate::options::{HybridError, Mode};
use crate::phi::{region, volume_fractions};

/// Every particle's mode, and the TD ones as the Verlet driver's mask.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct Modes {
    mode: Vec<Mode>,
    time_driven: Vec<bool>,
    counts: [usize; 3],
    /// Whether the modes have been decided once (before, there is no hysteresis: every
    /// particle is TD from `phi_time` on, ED below).
    decided: bool,
}

impl Modes {
    /// `n` particles in `mode`, decided already if they are ED.
    pub(crate) fn new(n: usize, mode: Mode) -> Self {
        let mut counts = [0; 3];
        counts[mode as usize] = n;
        Self {
            mode: vec![mode; n],
            time_driven: vec![mode == Mode::Time; n],
            counts,
            decided: mode == Mode::Event,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.mode.len()
    }

    #[inline]
    pub(crate) fn of(&self, i: usize) -> Mode {
        self.mode[i]
    }

    pub(crate) fn set(&mut self, i: usize, mode: Mode) {
        self.counts[self.mode[i] as usize] -= 1;
        self.counts[mode as usize] += 1;
        self.mode[i] = mode;
        self.time_driven[i] = mode == Mode::Time;
    }

    /// The TD particles as a mask.
    #[inline]
    pub(crate) fn time_driven(&self) -> &[bool] {
        &self.time_driven
    }

    pub(crate) fn count(&self, mode: Mode) -> usize {
        self.counts[mode as usize]
    }

    pub(crate) fn any(&self, mode: Mode) -> bool {
        self.count(mode) > 0
    }

    /// After the particles were renumbered by `order` (new k is old `order[k]`).
    pub(crate) fn permute(&mut self, order: &[u32]) {
        self.mode = order.iter().map(|&k| self.mode[k as usize]).collect();
        self.time_driven = order
            .iter()
            .map(|&k| self.time_driven[k as usize])
            .collect();
    }

    /// Whether a decoded set (a checkpoint's) is whole for `n` particles.
    pub(crate) fn is_whole(&self, n: usize) -> bool {
        let mut counts = [0; 3];
        for m in &self.mode {
            counts[*m as usize] += 1;
        }
        self.mode.len() == n
            && self.time_driven.len() == n
            && counts == self.counts
            && (0..n).all(|i| self.time_driven[i] == (self.mode[i] == Mode::Time))
    }
}

impl Hybrid {
    /// The mode rule of the crate docs (volume fraction with hysteresis, contacts,
    /// buffer), applied at a rebuild at time `t` (the list just built, every particle's
    /// entry holding its state now). The first decision has no hysteresis: the particles
    /// start TD, and those below `phi_time` become ED.
    pub(super) fn decide_modes(&mut self, t: f64) -> Result<(), HybridError> {
        let p = &self.system.particles;
        let n = p.len();
        let min_cell = 2.0 * self.system.max_radius() + self.td.skin();
        let removed = |i: usize| self.modes.of(i) == Mode::Removed;
        let radius: Vec<f64> = (0..n)
            .map(|i| if removed(i) { 0.0 } else { p.radius[i] })
            .collect();
        let area = region(&p.position, self.system.domain.sim_box.as_ref());
        let mut scratch = std::mem::take(&mut self.scratch.phi);
        let phi = volume_fractions(&p.position, &radius, area, min_cell, &mut scratch);
        let leave_below = match self.modes.decided {
            true => self.opts.phi_event,
            false => self.opts.phi_time,
        };
        self.modes.decided = true;
        let sparse = |i: usize| self.modes.of(i) == Mode::Time && phi[i] < leave_below;
        // Contacts only matter for TD particles sparse enough to become ED.
        let touching = if (0..n).any(sparse) {
            self.touching(&radius)
        } else {
            Vec::new()
        };
        let mut target: Vec<Mode> = (0..n)
            .map(|i| match self.modes.of(i) {
                Mode::Time if sparse(i) && !touching[i] => Mode::Event,
                Mode::Event if phi[i] >= self.opts.phi_time => Mode::Time,
                m => m,
            })
            .collect();
        self.scratch.phi = scratch;
        // The buffer: an ED particle within the list's reach of a TD one becomes TD.
        if target.contains(&Mode::Event) && target.contains(&Mode::Time) {
            let list = self.td.list();
            let mut buffered = vec![false; n];
            for i in 0..n {
                for &e in list.of(i) {
                    let j = list.split(e).0;
                    match (target[i], target[j]) {
                        (Mode::Event, Mode::Time) => buffered[i] = true,
                        (Mode::Time, Mode::Event) => buffered[j] = true,
                        _ => {}
                    }
                }
            }
            for i in 0..n {
                if buffered[i] {
                    target[i] = Mode::Time;
                }
            }
        }
        let to_event: Vec<u32> = (0..n as u32)
            .filter(|&i| {
                target[i as usize] == Mode::Event && self.modes.of(i as usize) == Mode::Time
            })
            .collect();
        let to_time: Vec<usize> = (0..n)
            .filter(|&i| target[i] == Mode::Time && self.modes.of(i) == Mode::Event)
            .collect();
        if to_event.is_empty() && to_time.is_empty() {
            return Ok(());
        }
        self.in_step(t)?;
        for i in to_time {
            self.switch_to_time(i);
        }
        self.switch_to_event(&to_event);
        Ok(())
    }

    /// Which particles touch another (not removed) particle or a wall now: centre
    /// distance below the contact distance, so also a contact whose force has dropped
    /// to zero (HAET (6.1)-(6.2)). `radius` is 0 for removed particles.
    fn touching(&self, radius: &[f64]) -> Vec<bool> {
        let p = &self.system.particles;
        let list = self.td.list();
        let mut touching = vec![false; p.len()];
        for i in 0..p.len() {
            if radius[i] == 0.0 {
                continue;
            }
            let xi = p.position[i];
            if self
                .system
                .domain
                .walls
                .iter()
                .any(|w| w.distance_at(xi, self.time()) < radius[i])
            {
                touching[i] = true;
            }
            for &e in list.of(i) {
                let (j, s) = list.split(e);
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
                let l = radius[i] + radius[j];
                if radius[j] > 0.0 && d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < l * l {
                    touching[i] = true;
                    touching[j] = true;
                }
            }
        }
        touching
    }

    /// Brings the TD velocities in step with the positions at time `t` (before a
    /// switch, which hands over or takes in a velocity now): the step's contact kick
    /// undone if it was taken, the pending half kick applied.
    pub(super) fn in_step(&mut self, t: f64) -> Result<(), HybridError> {
        if let Some(kick) = self.td_kick.take() {
            self.td.kick(&mut self.system.particles, -kick);
        }
        let g = self.system.domain.gravity;
        let members = self.modes.time_driven();
        Ok(self
            .td
            .synchronise(&mut self.system.particles, members, g, t)?)
    }

    /// ED → TD now (the TD velocities in step): the particle leaves the event core with
    /// its state now. A transient is ended first, for both partners, and a partner
    /// particle switches too (crate docs, "Switching without jumps"). Its forces come
    /// in with [`Hybrid::add_fresh_forces`].
    pub(super) fn switch_to_time(&mut self, i: usize) {
        if self.modes.of(i) != Mode::Event {
            return;
        }
        let partner = self.ed.transient_partner(i);
        let mut both = None;
        if partner.is_some() {
            self.ed.end_transient(i);
            self.stats.early_transient_ends += 1;
            if let Some(j) = partner.map(|j| j as usize)
                && j < self.modes.len()
                && self.ed.transient_partner(j) == Some(i as u32)
            {
                self.ed.end_transient(j);
                both = Some(j);
            }
        }
        self.take_from_events(i);
        if let Some(j) = both {
            self.take_from_events(j);
        }
    }

    /// Moves ED particle `i` (outside a transient) into the TD set.
    fn take_from_events(&mut self, i: usize) {
        let (x, v, w) = self.ed.leave(i);
        let p = &mut self.system.particles;
        p.position[i] = x;
        p.velocity[i] = v;
        p.angular_velocity[i] = w;
        p.image[i] = self.ed.stored_image(i);
        self.modes.set(i, Mode::Time);
        self.scratch.fresh.push(i as u32);
        self.boundary.push(i as u32);
        self.stats.to_time += 1;
    }

    /// TD → ED now for particles `ids` without contacts (no force acts on them; the TD
    /// velocities in step): they join the event core.
    pub(super) fn switch_to_event(&mut self, ids: &[u32]) {
        if ids.is_empty() {
            return;
        }
        self.td.release(ids);
        for &i in ids {
            self.modes.set(i as usize, Mode::Event);
            let v = self.system.particles.velocity[i as usize];
            self.book.note_speed(v);
        }
        self.ed.join(ids, &self.system.particles);
        self.stats.to_event += ids.len() as u64;
    }

    /// Takes particle `i` out through the outlet now (the TD velocities in step; a
    /// transient it shares is finished for both partners first).
    pub(super) fn remove(&mut self, i: usize) {
        if self.modes.of(i) == Mode::Event {
            self.switch_to_time(i);
            self.scratch.fresh.retain(|&f| f as usize != i);
        }
        self.td.release(&[i as u32]);
        self.modes.set(i, Mode::Removed);
        self.stats.removed += 1;
    }

    /// Sets the mode of particle `i` (config number) now, between steps. A switch to
    /// ED is refused while the particle touches another particle or a wall (HAET,
    /// condition (6.2)): it would start an event-driven flight inside a contact.
    pub fn set_mode(&mut self, id: usize, mode: Mode) -> Result<(), HybridError> {
        let n = self.modes.len();
        let Some(i) = self
            .system
            .particles
            .id
            .iter()
            .position(|&k| k as usize == id)
        else {
            return Err(HybridError::Invalid(format!(
                "particle {id} does not exist: there are {n} particles"
            )));
        };
        let now = self.modes.of(i);
        if mode == now {
            return Ok(());
        }
        if mode == Mode::Removed || now == Mode::Removed {
            return Err(HybridError::Invalid(format!(
                "particle {id}: only the outlet removes particles, and they do not come back"
            )));
        }
        let t = self.time();
        if mode == Mode::Event {
            let radius: Vec<f64> = (0..n)
                .map(|k| match self.modes.of(k) {
                    Mode::Removed => 0.0,
                    _ => self.system.particles.radius[k],
                })
                .collect();
            self.refresh_event_copies(t);
            if !self.upkeep.list {
                self.rebuild(false)?;
            }
            if self.touching(&radius)[i] {
                return Err(HybridError::Invalid(format!(
                    "particle {id} touches another particle or a wall at t = {t:e} s; it \
                     can become event-driven only without contacts"
                )));
            }
        }
        self.in_step(t)?;
        match mode {
            Mode::Time => self.switch_to_time(i),
            _ => self.switch_to_event(&[i as u32]),
        }
        // A mixed state lives on the list, with every neighbour known.
        self.rebuild(false)?;
        self.add_fresh_forces();
        Ok(())
    }
}
