//! The MD engine: state, velocity-Verlet steps, neighbour-list upkeep, thermo.

mod rotation;
mod snapshot;

use crate::forces::{Accelerations, ContactRecord, ForceKernel, ForceModel, apply_contacts};
use crate::frictional::Rotation;
use crate::neighbour::NeighbourList;
use crate::options::{MdError, MdOptions, prepare_system};
use crate::verlet::{kick_contacts, kick_drift, max_nan};
use emdstar_system::{Method, Particles, SimBox, System, Thermo, permute};
use rayon::prelude::*;
use rotation::{Buffers, FrictionalKind, SlotKind, SmoothKind};

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
    /// Contact (pair and wall) accelerations at the current time; gravity is added
    /// where they are used. Non-zero only for the particles listed in `touched`.
    contact_acc: Vec<[f64; 3]>,
    touched: Vec<u32>,
    list: NeighbourList,
    buffers: Buffers,
    drift_bound: f64,
    /// Largest speed after the last sweep.
    v_max: f64,
    rebuilds: u64,
    /// The velocities lag half a kick (contacts and gravity) behind the positions: the
    /// first half kick of the next step is fused with the last one of the previous
    /// (see [`Md::synchronise`]).
    lagging: bool,
    /// Friction: spins, torques and springs. `None` where every contact is
    /// frictionless: the steps then never touch the spins.
    rotation: Option<Box<Rotation>>,
}

/// v + g·dt/2, component by component (the gravity half kick of a synchronisation).
#[inline]
fn half_kick_gravity(v: [f64; 3], g: [f64; 3], dt: f64) -> [f64; 3] {
    [
        v[0] + g[0] * 0.5 * dt,
        v[1] + g[1] * 0.5 * dt,
        v[2] + g[2] * 0.5 * dt,
    ]
}

fn p_max_speed(p: &Particles) -> f64 {
    p.velocity
        .iter()
        .map(|v| v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        .fold(0.0, max_nan)
        .sqrt()
}

impl Md {
    /// Prepares `system` for integration with `opts` up to `t_end` (which only enters
    /// the check of the time step against the shortest expected contact time).
    pub fn new(mut system: System, opts: MdOptions, t_end: f64) -> Result<Self, MdError> {
        let walls = system.domain.walls.len();
        system.interactions.check_runs_on(Method::Md, walls)?;
        let skin = prepare_system(&mut system, opts.dt, opts.skin, t_end)?;
        let n = system.particles.len();
        let inv_mass = system.particles.mass.iter().map(|m| 1.0 / m).collect();
        let rotation = system
            .interactions
            .is_frictional()
            .then(|| Box::new(Rotation::new(&system.particles)));
        let chunks = n.div_ceil(CHUNK);
        let mut md = Self {
            system,
            opts,
            skin,
            steps: 0,
            t_start: 0.0,
            inv_mass,
            contact_acc: vec![[0.0; 3]; n],
            touched: Vec::new(),
            list: NeighbourList::default(),
            buffers: Buffers {
                smooth: vec![Vec::new(); chunks],
                frictional: vec![Vec::new(); chunks],
            },
            drift_bound: 0.0,
            v_max: 0.0,
            rebuilds: 0,
            lagging: false,
            rotation,
        };
        md.rebuild()?;
        // Forces at t = 0 with the velocities themselves (h = 0).
        if md.rotation.is_some() {
            md.find_contacts_parallel::<FrictionalKind>(0.0);
            md.apply::<FrictionalKind>();
        } else {
            md.find_contacts_parallel::<SmoothKind>(0.0);
            md.apply::<SmoothKind>();
        }
        md.v_max = p_max_speed(&md.system.particles);
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
    /// [`Particles::id`]. Their velocities lag half a kick behind after
    /// [`Md::stride`]; [`Md::particles_in_config_order`] and [`Md::thermo`] show them
    /// in step.
    pub fn system(&self) -> &System {
        &self.system
    }

    /// The particles in config order, velocities in step with the positions.
    pub fn particles_in_config_order(&self) -> Particles {
        let mut p = self.system.particles.clone();
        p.velocity = self.velocities_now();
        p.angular_velocity = self.spins_now();
        let mut order = vec![0u32; p.len()];
        for (k, &id) in p.id.iter().enumerate() {
            order[id as usize] = k as u32;
        }
        p.permute(&order);
        p
    }

    /// Advances `n` steps of velocity Verlet (see the crate docs), velocities in step
    /// with the positions afterwards.
    pub fn advance(&mut self, n: u64) -> Result<(), MdError> {
        self.stride(n)?;
        self.synchronise()
    }

    /// Advances `n` steps of velocity Verlet (fewer when a stop is requested,
    /// [`emdstar_system::stop`]) leaving the last half kick pending: the
    /// trajectory does not depend on how a run is cut into strides (a run stopped,
    /// read or saved between strides goes on bitwise as one that ran through).
    pub fn stride(&mut self, n: u64) -> Result<(), MdError> {
        let dt = self.opts.dt;
        for s in 0..n {
            if emdstar_system::stop::is_requested() {
                // Between steps: the state is whole, and a later stride goes on as
                // this one would have (the pending half kick is fused either way).
                break;
            }
            // The first half-kick of this step fused with the last one of the previous.
            let kick = if s == 0 && !self.lagging {
                0.5 * dt
            } else {
                dt
            };
            self.step(kick, dt)?;
            self.lagging = true;
        }
        Ok(())
    }

    /// Applies the pending half kick, if any (velocities then in step with the
    /// positions), and reports a blow-up.
    pub fn synchronise(&mut self) -> Result<(), MdError> {
        if !self.lagging {
            return Ok(());
        }
        self.lagging = false;
        let dt = self.opts.dt;
        self.kick_contacts(0.5 * dt);
        self.kick_spins(0.5 * dt);
        let g = self.system.domain.gravity;
        let mut v2_max: f64 = 0.0;
        for v in &mut self.system.particles.velocity {
            *v = half_kick_gravity(*v, g, dt);
            v2_max = max_nan(v2_max, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        }
        self.v_max = v2_max.sqrt();
        if self.v_max.is_nan() {
            let p = &self.system.particles;
            let bad = (0..p.len()).find(|&i| {
                !p.velocity[i]
                    .iter()
                    .chain(&p.position[i])
                    .all(|c| c.is_finite())
            });
            return Err(MdError::BlewUp {
                id: bad.map_or(0, |i| p.id[i]),
                t: self.time(),
            });
        }
        Ok(())
    }

    /// The velocities now, in the engine's order: the stored ones with the pending
    /// half kick applied (the arithmetic of [`Md::synchronise`]).
    fn velocities_now(&self) -> Vec<[f64; 3]> {
        let mut v = self.system.particles.velocity.clone();
        if self.lagging {
            kick_contacts(&mut v, &self.contact_acc, &self.touched, 0.5 * self.opts.dt);
            let g = self.system.domain.gravity;
            v.iter_mut()
                .for_each(|w| *w = half_kick_gravity(*w, g, self.opts.dt));
        }
        v
    }

    /// One step: v += a·kick, x += v·dt, forces at the new positions.
    ///
    /// The neighbour list is rebuilt *before* the drift when the particles might
    /// otherwise have moved by more than half the skin by its end; the speed bound
    /// uses the largest speed of the last sweep, the kicked particles in contact and
    /// gravity, so it holds for every particle.
    fn step(&mut self, kick: f64, dt: f64) -> Result<(), MdError> {
        let touched_v2 = self.kick_contacts(kick);
        self.kick_spins(kick);
        let g = self.system.domain.gravity;
        let g_kick = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * kick;
        let v_bound = max_nan(self.v_max, touched_v2.sqrt()) + g_kick;
        // Written so that NaN (a blow-up) rebuilds, where it is reported.
        let list_holds = 2.0 * (self.drift_bound + v_bound * dt) <= self.skin;
        if !list_holds {
            self.rebuild()?;
            let step_fits = 2.0 * v_bound * dt <= self.skin;
            if !step_fits {
                return Err(MdError::SkinTooThin {
                    skin: self.skin,
                    step: v_bound * dt,
                });
            }
        }
        let gk = [g[0] * kick, g[1] * kick, g[2] * kick];
        self.steps += 1;
        let h = 0.5 * self.opts.dt;
        let v2 = if self.rotation.is_some() {
            self.sweep::<FrictionalKind>(gk, dt, h)
        } else {
            self.sweep::<SmoothKind>(gk, dt, h)
        };
        self.v_max = v2.sqrt();
        self.drift_bound += self.v_max * dt;
        Ok(())
    }

    /// The drift and the contacts of one step, in one pass on one thread or in two
    /// parallel passes over fixed chunks (the same numbers in the same order), then the
    /// contacts applied. Returns max |v|².
    fn sweep<K: SlotKind>(&mut self, gk: [f64; 3], dt: f64, h: f64) -> f64 {
        let v2 = if rayon::current_num_threads() == 1 || self.system.particles.len() <= CHUNK {
            self.sweep_fused::<K>(gk, dt, h)
        } else {
            let v2 = self.drift_all(gk, dt);
            self.find_contacts_parallel::<K>(h);
            v2
        };
        self.apply::<K>();
        v2
    }

    /// v += a_contact·`by` for the particles in contact; returns their largest |v|².
    fn kick_contacts(&mut self, by: f64) -> f64 {
        kick_contacts(
            &mut self.system.particles.velocity,
            &self.contact_acc,
            &self.touched,
            by,
        )
    }

    /// What the forces depend on besides the motion.
    fn model(&self) -> ForceModel<'_> {
        let p = &self.system.particles;
        ForceModel::new(
            &p.radius,
            &p.species,
            &self.system.interactions,
            &self.system.domain,
            self.opts.contact_end,
        )
    }

    /// The force kernel of the current step over the slot of kind `K`.
    fn kernel<K: SlotKind>(&self, h: f64) -> ForceKernel<'_, K::Slot<'_>> {
        ForceKernel {
            model: self.model(),
            list: &self.list,
            contact_acc: &self.contact_acc,
            h,
            slot: K::slot(self),
        }
    }

    /// One pass in particle order: kick and drift particle i, then find its contacts
    /// (its listed partners j < i have already moved). Returns max |v|².
    fn sweep_fused<K: SlotKind>(&mut self, gk: [f64; 3], dt: f64, h: f64) -> f64 {
        let mut position = std::mem::take(&mut self.system.particles.position);
        let mut velocity = std::mem::take(&mut self.system.particles.velocity);
        let mut buffers = std::mem::take(K::chunks(&mut self.buffers));
        let kernel = self.kernel::<K>(h);
        let start = &self.list.start;
        let walls = !self.system.domain.walls.is_empty();
        let mut v2_max: f64 = 0.0;
        let n = position.len();
        // Without gravity the velocities need not be written back (less memory traffic).
        let gravity = gk != [0.0; 3];
        for (c, buf) in buffers.iter_mut().enumerate() {
            buf.clear();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                let (y, w) = kick_drift(position[i], velocity[i], gk, dt, gravity);
                if gravity {
                    velocity[i] = w;
                }
                position[i] = y;
                let w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                // NaN is ignored here; a blown-up particle is caught at the next rebuild.
                if w2 > v2_max {
                    v2_max = w2;
                }
                if walls || start[i] != start[i + 1] {
                    let entries = kernel.list.of(i).iter().copied();
                    kernel.particle(i, y, w, entries, &position, &velocity, buf);
                }
            }
        }
        drop(kernel);
        self.system.particles.position = position;
        self.system.particles.velocity = velocity;
        *K::chunks(&mut self.buffers) = buffers;
        v2_max
    }

    /// The gravity kick and the drift of every particle, in parallel over fixed chunks.
    /// Returns max |v|².
    fn drift_all(&mut self, gk: [f64; 3], dt: f64) -> f64 {
        let gravity = gk != [0.0; 3];
        let p = &mut self.system.particles;
        p.position
            .par_chunks_mut(CHUNK)
            .zip(p.velocity.par_chunks_mut(CHUNK))
            .map(|(x, v)| {
                let mut v2_max: f64 = 0.0;
                for (x, v) in x.iter_mut().zip(v.iter_mut()) {
                    // Copies: re-reading just-stored components stalls the CPU.
                    let w;
                    (*x, w) = kick_drift(*x, *v, gk, dt, gravity);
                    if gravity {
                        *v = w;
                    }
                    let w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
                    if w2 > v2_max {
                        v2_max = w2;
                    }
                }
                v2_max
            })
            .reduce(|| 0.0, f64::max)
    }

    /// The contacts at the current positions, in parallel over fixed chunks (the second
    /// pass of [`Self::sweep`]).
    fn find_contacts_parallel<K: SlotKind>(&mut self, h: f64) {
        let mut buffers = std::mem::take(K::chunks(&mut self.buffers));
        let kernel = self.kernel::<K>(h);
        let (position, velocity) = (
            &self.system.particles.position,
            &self.system.particles.velocity,
        );
        let n = position.len();
        let (start, walls) = (&self.list.start, !self.system.domain.walls.is_empty());
        buffers.par_iter_mut().enumerate().for_each(|(c, buf)| {
            buf.clear();
            for i in c * CHUNK..((c + 1) * CHUNK).min(n) {
                if walls || start[i] != start[i + 1] {
                    let (x, v, entries) = (position[i], velocity[i], kernel.list.of(i).iter());
                    kernel.particle(i, x, v, entries.copied(), position, velocity, buf);
                }
            }
        });
        drop(kernel);
        *K::chunks(&mut self.buffers) = buffers;
    }

    /// Replaces the contact accelerations (and angular accelerations and springs, with
    /// friction) by those of the contacts just found, chunk by chunk and contact by
    /// contact (a fixed order).
    fn apply<K: SlotKind>(&mut self) {
        let mut rotation = self.rotation.as_deref_mut();
        for &i in &self.touched {
            self.contact_acc[i as usize] = [0.0; 3];
            if let Some(rot) = rotation.as_deref_mut() {
                rot.angular_acc[i as usize] = [0.0; 3];
            }
        }
        self.touched.clear();
        let buffers = K::chunks(&mut self.buffers);
        let mut to = Accelerations {
            inv_mass: &self.inv_mass,
            acc: &mut self.contact_acc,
            angular: rotation
                .as_deref_mut()
                .map(|r| (&r.inv_inertia[..], &mut r.angular_acc[..])),
        };
        apply_contacts(buffers.iter().flatten(), &mut to, Some(&mut self.touched));
        self.touched.sort_unstable();
        self.touched.dedup();
        if let Some(rot) = rotation {
            let records = buffers.iter().flatten().filter_map(ContactRecord::spring);
            rot.springs.replace(records);
        }
    }

    /// Checks the state, wraps periodic positions, sorts particles by cell and
    /// rebuilds the neighbour list.
    fn rebuild(&mut self) -> Result<(), MdError> {
        let t = self.time();
        let min_cell = 2.0 * self.system.max_radius() + self.skin;
        check_and_wrap(
            &mut self.system.particles,
            self.system.domain.sim_box.as_ref(),
            t,
            |_| false,
        )?;
        let p = &mut self.system.particles;
        let order = self.list.sort_order(
            &p.position,
            self.system.domain.sim_box.as_ref(),
            min_cell,
            PER_CELL,
        )?;
        p.permute(&order);
        permute(&mut self.inv_mass, &order);
        permute(&mut self.contact_acc, &order);
        if let Some(rot) = self.rotation.as_mut() {
            rot.permute(&order);
        }
        self.touched.clear();
        for (i, a) in self.contact_acc.iter().enumerate() {
            let spun = self
                .rotation
                .as_ref()
                .is_some_and(|r| r.angular_acc[i] != [0.0; 3]);
            if *a != [0.0; 3] || spun {
                self.touched.push(i as u32);
            }
        }
        self.list.build_half(&p.position, &p.radius, self.skin);
        self.drift_bound = 0.0;
        self.rebuilds += 1;
        Ok(())
    }

    /// Energies, temperature, momentum and contacts now. The potential energy is the
    /// elastic energy of the contacts, ∫F_el dξ: ½kξ² (linear) or (2/5)ρ_el ξ^{5/2}
    /// (Hertz, Müller & Pöschel 2013, Eq. 51), plus −Σ m g·x.
    pub fn thermo(&self) -> Thermo {
        let synced;
        let p = if self.lagging {
            synced = Particles {
                velocity: self.velocities_now(),
                angular_velocity: self.spins_now(),
                ..self.system.particles.clone()
            };
            &synced
        } else {
            &self.system.particles
        };
        let model = self.model();
        let interactions = &self.system.interactions;
        let mut potential = self
            .rotation
            .as_ref()
            .map_or(0.0, |r| r.spring_energy(interactions, p));
        let mut contacts = 0;
        for i in 0..p.len() {
            let xi = p.position[i];
            let sums = (&mut contacts, &mut potential);
            let entries = self.list.of(i).iter().copied();
            model.add_elastic(i, xi, entries, &self.list, &p.position, sums);
            let g = self.system.domain.gravity;
            potential -= p.mass[i] * (g[0] * xi[0] + g[1] * xi[1] + g[2] * xi[2]);
        }
        Thermo {
            t: self.time(),
            step: self.steps,
            kinetic_energy: p.kinetic_energy(),
            rotational_energy: p.rotational_energy(),
            potential_energy: potential,
            granular_temperature: p.granular_temperature(),
            rotational_temperature: p.rotational_temperature(),
            momentum: p.momentum(),
            contacts,
        }
    }
}

/// Checks that every particle (but those `skip` names) has a finite state and stays
/// inside the closed axes of `sim_box`, and wraps positions along the periodic ones.
pub fn check_and_wrap(
    p: &mut Particles,
    sim_box: Option<&SimBox>,
    t: f64,
    skip: impl Fn(usize) -> bool,
) -> Result<(), MdError> {
    for i in 0..p.len() {
        if skip(i) {
            continue;
        }
        let (x, v) = (p.position[i], p.velocity[i]);
        if !x.iter().chain(&v).all(|c| c.is_finite()) {
            return Err(MdError::BlewUp { id: p.id[i], t });
        }
        if let Some(b) = sim_box {
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
    Ok(())
}
