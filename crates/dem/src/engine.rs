//! The MD engine: state, velocity-Verlet steps, neighbour-list upkeep, thermo.

use crate::forces::{Kernel, PairForce};
use crate::neighbour::{INDEX_BITS, INDEX_MASK, NeighbourList};
use crate::options::{MAX_DT_FRACTION, MdError, MdOptions, shortest_contact_time};
use emdstar_contact::PairLaw;
use emdstar_system::{Particles, System, Thermo, permute};
use rayon::prelude::*;

/// Particles per chunk of the force loop. Fixed, so that the order in which forces are
/// summed does not depend on the number of threads.
const CHUNK: usize = 1024;
/// Particles per cell the neighbour grid aims at (cells never get smaller than the
/// list cut-off).
const PER_CELL: f64 = 2.0;

/// A force-based simulation of one [`System`].
pub struct Md {
    system: System,
    opts: MdOptions,
    skin: f64,
    steps: u64,
    t_start: f64,
    inv_mass: Vec<f64>,
    acc: Vec<[f64; 3]>,
    acc_new: Vec<[f64; 3]>,
    pair_laws: Vec<PairLaw>,
    wall_laws: Vec<PairLaw>,
    list: NeighbourList,
    buffers: Vec<Vec<PairForce>>,
    drift_bound: f64,
    rebuilds: u64,
}

impl Md {
    /// Prepares `system` for integration with `opts` up to `t_end` (which only enters
    /// the check of the time step against the shortest expected contact time).
    pub fn new(mut system: System, opts: MdOptions, t_end: f64) -> Result<Self, MdError> {
        system.validate()?;
        if !(opts.dt.is_finite() && opts.dt > 0.0) {
            return Err(MdError::BadDt(opts.dt));
        }
        if let Some(tc) = shortest_contact_time(&system, t_end)? {
            let bound = MAX_DT_FRACTION * tc;
            if opts.dt > bound {
                return Err(MdError::DtTooCoarse {
                    dt: opts.dt,
                    contact_time: tc,
                    bound,
                });
            }
        }
        let skin = opts.skin.unwrap_or_else(|| system.max_radius());
        if !(skin.is_finite() && skin >= 0.0) {
            return Err(MdError::BadSkin(skin));
        }
        let ns = system.species.len();
        let mut pair_laws = Vec::with_capacity(ns * ns);
        for a in 0..ns {
            for b in 0..ns {
                pair_laws.push(system.pair(a, b)?.0);
            }
        }
        let wall_laws = (0..ns)
            .map(|a| system.wall_pair(a).map(|p| p.0))
            .collect::<Result<_, _>>()?;
        // Every particle starts on the right side of closed axes; wrap periodic ones.
        if let Some(b) = system.sim_box {
            for x in &mut system.particles.position {
                *x = b.wrap(*x);
            }
        }
        let n = system.particles.len();
        let inv_mass = system.particles.mass.iter().map(|m| 1.0 / m).collect();
        let mut md = Self {
            system,
            opts,
            skin,
            steps: 0,
            t_start: 0.0,
            inv_mass,
            acc: vec![[0.0; 3]; n],
            acc_new: vec![[0.0; 3]; n],
            pair_laws,
            wall_laws,
            list: NeighbourList::default(),
            buffers: vec![Vec::new(); n.div_ceil(CHUNK)],
            drift_bound: 0.0,
            rebuilds: 0,
        };
        md.rebuild()?;
        // Forces at t = 0 with the velocities themselves (h = 0).
        md.compute_forces(0.0);
        std::mem::swap(&mut md.acc, &mut md.acc_new);
        Ok(md)
    }

    /// Time in s.
    pub fn time(&self) -> f64 {
        self.t_start + self.steps as f64 * self.opts.dt
    }

    /// Steps done.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Neighbour-list rebuilds done (the first included).
    pub fn rebuilds(&self) -> u64 {
        self.rebuilds
    }

    /// The options in use.
    pub fn options(&self) -> &MdOptions {
        &self.opts
    }

    /// The Verlet-list skin in use, in m.
    pub fn skin(&self) -> f64 {
        self.skin
    }

    /// The system; particles are in the engine's (cell-sorted) order, see
    /// [`Particles::id`].
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The particles in config order.
    pub fn particles_in_config_order(&self) -> Particles {
        let mut p = self.system.particles.clone();
        let mut order = vec![0u32; p.len()];
        for (k, &id) in p.id.iter().enumerate() {
            order[id as usize] = k as u32;
        }
        p.permute(&order);
        p
    }

    /// Advances `n` steps of velocity Verlet (see the crate docs). Velocities are
    /// synchronised with positions before and after.
    pub fn advance(&mut self, n: u64) -> Result<(), MdError> {
        let dt = self.opts.dt;
        for s in 0..n {
            // The first half-kick of this step fused with the last one of the previous.
            let kick = if s == 0 { 0.5 * dt } else { dt };
            let v_max = self.kick_drift(kick, dt);
            self.steps += 1;
            self.drift_bound += v_max * dt;
            // Pairs approach by at most 2·drift since the last build (NaN rebuilds too).
            if !(2.0 * self.drift_bound <= self.skin) {
                self.rebuild()?;
            }
            self.compute_forces(0.5 * dt);
            std::mem::swap(&mut self.acc, &mut self.acc_new);
        }
        if n > 0 {
            self.kick(0.5 * dt);
        }
        Ok(())
    }

    /// v += a·kick, then x += v·dt; returns max |v| after the kick.
    fn kick_drift(&mut self, kick: f64, dt: f64) -> f64 {
        let p = &mut self.system.particles;
        let one = |x: &mut [[f64; 3]], v: &mut [[f64; 3]], a: &[[f64; 3]]| {
            let mut v2_max: f64 = 0.0;
            for ((x, v), a) in x.iter_mut().zip(v.iter_mut()).zip(a) {
                for k in 0..3 {
                    v[k] += a[k] * kick;
                    x[k] += v[k] * dt;
                }
                v2_max = v2_max.max(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            }
            v2_max
        };
        let v2 = if p.len() <= CHUNK {
            one(&mut p.position, &mut p.velocity, &self.acc)
        } else {
            p.position
                .par_chunks_mut(CHUNK)
                .zip(p.velocity.par_chunks_mut(CHUNK))
                .zip(self.acc.par_chunks(CHUNK))
                .map(|((x, v), a)| one(x, v, a))
                .reduce(|| 0.0, f64::max)
        };
        if v2.is_nan() { f64::NAN } else { v2.sqrt() }
    }

    /// v += a·h.
    fn kick(&mut self, h: f64) {
        let one = |v: &mut [[f64; 3]], a: &[[f64; 3]]| {
            for (v, a) in v.iter_mut().zip(a) {
                for k in 0..3 {
                    v[k] += a[k] * h;
                }
            }
        };
        let v = &mut self.system.particles.velocity;
        if v.len() <= CHUNK {
            one(v, &self.acc);
        } else {
            v.par_chunks_mut(CHUNK)
                .zip(self.acc.par_chunks(CHUNK))
                .for_each(|(v, a)| one(v, a));
        }
    }

    /// Accelerations at the current positions into `acc_new`; `h` predicts the
    /// velocities at this time from the stored ones (see [`Kernel`]).
    fn compute_forces(&mut self, h: f64) {
        let p = &self.system.particles;
        let kernel = Kernel {
            position: &p.position,
            velocity: &p.velocity,
            acc_old: &self.acc,
            radius: &p.radius,
            inv_mass: &self.inv_mass,
            species: &p.species,
            list: &self.list,
            pair_laws: &self.pair_laws,
            n_species: self.system.species.len(),
            wall_laws: &self.wall_laws,
            walls: &self.system.walls,
            gravity: self.system.gravity,
            h,
            contact_end: self.opts.contact_end,
        };
        if p.len() <= CHUNK {
            for (c, (acc, buf)) in self
                .acc_new
                .chunks_mut(CHUNK)
                .zip(self.buffers.iter_mut())
                .enumerate()
            {
                kernel.chunk(c * CHUNK, acc, buf);
            }
        } else {
            self.acc_new
                .par_chunks_mut(CHUNK)
                .zip(self.buffers.par_iter_mut())
                .enumerate()
                .for_each(|(c, (acc, buf))| kernel.chunk(c * CHUNK, acc, buf));
        }
        // Phase 2, in a fixed order: chunk by chunk, pair by pair.
        for buf in &self.buffers {
            for pf in buf {
                let (i, j) = (pf.i as usize, pf.j as usize);
                let (mi, mj) = (self.inv_mass[i], self.inv_mass[j]);
                for k in 0..3 {
                    self.acc_new[i][k] += pf.f[k] * mi;
                    self.acc_new[j][k] -= pf.f[k] * mj;
                }
            }
        }
    }

    /// Checks the state, wraps periodic positions, sorts particles by cell and
    /// rebuilds the neighbour list.
    fn rebuild(&mut self) -> Result<(), MdError> {
        let t = self.time();
        let min_cell = 2.0 * self.system.max_radius() + self.skin;
        let p = &mut self.system.particles;
        for i in 0..p.len() {
            let (x, v) = (p.position[i], p.velocity[i]);
            if !x.iter().chain(&v).all(|c| c.is_finite()) {
                return Err(MdError::BlewUp { id: p.id[i], t });
            }
            if let Some(b) = &self.system.sim_box {
                if let Some(k) = b.outside_closed_axis(x) {
                    return Err(MdError::LeftBox {
                        id: p.id[i],
                        axis: ["x", "y", "z"][k],
                        t,
                        position: x,
                    });
                }
                p.position[i] = b.wrap(x);
            }
        }
        let order = self
            .list
            .sort_order(
                &p.position,
                self.system.sim_box.as_ref(),
                min_cell,
                PER_CELL,
            )
            .map_err(|e| MdError::BoxTooSmall {
                axis: ["x", "y", "z"][e.axis],
                length: e.length,
                cell: e.cell,
            })?;
        p.permute(&order);
        permute(&mut self.inv_mass, &order);
        permute(&mut self.acc, &order);
        self.list.build(&p.position, &p.radius, self.skin);
        self.drift_bound = 0.0;
        self.rebuilds += 1;
        Ok(())
    }

    /// Energies, temperature, momentum and contacts now. The potential energy is the
    /// elastic energy of the contacts, ∫F_el dξ: ½kξ² (linear) or (2/5)ρ_el ξ^{5/2}
    /// (Hertz, Müller & Pöschel 2013, Eq. 51), plus −Σ m g·x.
    pub fn thermo(&self) -> Thermo {
        let p = &self.system.particles;
        let ns = self.system.species.len();
        let mut potential = 0.0;
        let mut contacts = 0;
        for i in 0..p.len() {
            let xi = p.position[i];
            for &entry in self.list.of(i) {
                let j = (entry & INDEX_MASK) as usize;
                let s = self.list.shifts[(entry >> INDEX_BITS) as usize];
                let d: [f64; 3] = std::array::from_fn(|k| xi[k] - p.position[j][k] - s[k]);
                let overlap =
                    p.radius[i] + p.radius[j] - (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                if overlap > 0.0 {
                    contacts += 1;
                    let law = &self.pair_laws[p.species[i] as usize * ns + p.species[j] as usize];
                    potential += elastic_energy(law, overlap);
                }
            }
            for w in &self.system.walls {
                let overlap = p.radius[i] - w.distance(xi);
                if overlap > 0.0 {
                    contacts += 1;
                    potential += elastic_energy(&self.wall_laws[p.species[i] as usize], overlap);
                }
            }
            let g = self.system.gravity;
            potential -= p.mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: p.kinetic_energy(),
            potential_energy: potential,
            granular_temperature: p.granular_temperature(),
            momentum: p.momentum(),
            contacts,
        }
    }
}

/// Elastic energy stored at overlap ξ: ½kξ² or (2/5)ρ_el ξ^{5/2}.
fn elastic_energy(law: &PairLaw, overlap: f64) -> f64 {
    match *law {
        PairLaw::Linear { stiffness, .. } => 0.5 * stiffness * overlap * overlap,
        PairLaw::Hertz { rho_el, .. } => 0.4 * rho_el * overlap * overlap * overlap.sqrt(),
    }
}
