//! Building an engine: input checks with clear errors, the state, first predictions.

use super::EventEngine;
use crate::broad_phase::{BroadPhase, Crossings, Epochs, Neighbours};
use crate::cells::{NONE, auto_cell_width};
use crate::collision::{LastContact, Rules};
use crate::error::{EngineError, Result};
use crate::physics::{BroadPhaseKind, Physics};
use crate::queue::EventQueue;
use crate::state::{EventRec, Kin, Slot, State};
use crate::stats::Stats;
use emdstar_contact::vec3::dot;
use emdstar_system::{Domain, Particles, SimBox, Wall};

fn invalid<T>(msg: String) -> Result<T> {
    Err(EngineError::Invalid(msg))
}

/// The volume of spheres with these radii.
fn sphere_volume(radius: &[f64]) -> f64 {
    radius
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
        .sum()
}

/// Densest packing of equal spheres, π/√18 (Kepler, Hales 2005).
const MAX_PACKING: f64 = 0.740_480_489_693_061;

/// What the shared checks of `Domain::check` do not cover: positive radii and masses,
/// species the materials know, finite gravity, and numbers the engine can index.
fn check_particles(p: &Particles, domain: &Domain, physics: &Physics) -> Result<()> {
    let n = p.len();
    if n + domain.walls.len() >= NONE as usize {
        return invalid(format!("{n} particles are more than this engine can index"));
    }
    for i in 0..n {
        if !(p.radius[i] > 0.0 && p.radius[i].is_finite()) {
            return invalid(format!(
                "particle {i}: radius {} must be positive",
                p.radius[i]
            ));
        }
        if !(p.mass[i] > 0.0 && p.mass[i].is_finite()) {
            return invalid(format!("particle {i}: mass {} must be positive", p.mass[i]));
        }
    }
    if let Some(m) = physics.interactions()
        && let Some((i, s)) = p
            .species
            .iter()
            .enumerate()
            .find(|(_, s)| **s as usize >= m.species())
    {
        return invalid(format!(
            "particle {i} has species {s}, but materials were given for {} species",
            m.species()
        ));
    }
    if !domain.gravity.iter().all(|g| g.is_finite()) {
        return invalid(format!("gravity {:?} must be finite", domain.gravity));
    }
    Ok(())
}

/// The walls with unit normals.
fn normalised_walls(walls: &[Wall]) -> Result<Vec<Wall>> {
    walls
        .iter()
        .enumerate()
        .map(|(w, wall)| {
            let len = dot(wall.normal, wall.normal).sqrt();
            if !(len > 0.0 && len.is_finite() && wall.point.iter().all(|x| x.is_finite())) {
                return invalid(format!(
                    "wall {w}: normal {:?} must be a finite non-zero vector and point {:?} \
                     finite",
                    wall.normal, wall.point
                ));
            }
            Ok(Wall {
                normal: wall.normal.map(|x| x / len),
                point: wall.point,
                vibration: wall.vibration,
            })
        })
        .collect()
}

/// Whether walls normal to every closed axis hold the gas from both sides. A gas free
/// to spread along an axis leaves the epoch grid for its border cells, which reach to
/// infinity, and every epoch then tests all pairs piled there: an expanding cluster
/// of 1728 spheres in free space ran 100 times slower on epochs than on crossings.
fn confined(region: &SimBox, walls: &[Wall]) -> bool {
    let bounded = |k: usize, sign: f64| {
        walls
            .iter()
            .any(|w| (0..3).all(|m| w.normal[m] == if m == k { sign } else { 0.0 }))
    };
    (0..3).all(|k| region.periodic[k] || bounded(k, 1.0) && bounded(k, -1.0))
}

/// The box, or for free space the particles' bounding box (closed axes).
fn region_of(p: &Particles, sim_box: Option<SimBox>, max_contact: f64) -> Result<SimBox> {
    if let Some(r) = sim_box {
        for k in 0..3 {
            if !(r.size[k] > 0.0 && r.size[k].is_finite() && r.lo[k].is_finite()) {
                return invalid(format!("box size {:?} must be positive and finite", r.size));
            }
            if r.periodic[k] && r.size[k] <= 2.0 * max_contact {
                return invalid(format!(
                    "the periodic box is {} wide along {}, not more than twice the largest \
                     contact distance {max_contact}: a sphere would meet two images of \
                     another; enlarge the box",
                    r.size[k],
                    ["x", "y", "z"][k]
                ));
            }
        }
        let spheres = sphere_volume(&p.radius);
        let volume = r.size.iter().product::<f64>();
        if spheres > MAX_PACKING * volume {
            return Err(EngineError::Packing {
                eta: spheres / volume,
                spheres,
                volume,
            });
        }
        return Ok(r);
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in &p.position {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    if p.is_empty() {
        (lo, hi) = ([0.0; 3], [1.0; 3]);
    }
    Ok(SimBox {
        lo,
        size: std::array::from_fn(|k| (hi[k] - lo[k]).max(max_contact)),
        periodic: [false; 3],
    })
}

/// Below this many particles the order is left as given.
const RESORT_MIN_PARTICLES: usize = 1000;

/// A checked input, ready for a broad phase.
pub(crate) struct Prepared<Q: EventQueue> {
    pub state: State<Q>,
    pub rules: Rules,
    pub max_contact: f64,
    /// Cells the crossing broad phase would use (also the re-sorting's cells).
    pub cell_width: f64,
}

impl<Q: EventQueue> Prepared<Q> {
    /// Checks the particles against their domain (the shared checks of
    /// [`Domain::check`] and the engine's own) and lays out the engine's state at
    /// time 0. `min_width` > 0 asks for cells at least that wide (never narrower than
    /// the largest contact distance), 0 for the automatic width.
    pub fn new(
        particles: &Particles,
        domain: &Domain,
        physics: Physics,
        min_width: f64,
    ) -> Result<Self> {
        let walls = normalised_walls(&domain.walls)?;
        let domain = Domain {
            walls,
            ..domain.clone()
        };
        check_particles(particles, &domain, &physics)?;
        let rules = Rules::new(physics, domain.walls.len())?;
        let max_contact = 2.0 * particles.radius.iter().copied().fold(0.0, f64::max);
        // An impossible packing fraction first: it would also show as an overlap.
        let region = region_of(particles, domain.sim_box, max_contact)?;
        domain.check(particles)?;
        let gravity = domain.gravity;
        let n = particles.len();
        let cell_width = if min_width > 0.0 {
            max_contact.max(min_width)
        } else {
            auto_cell_width(max_contact, region.size.iter().product(), n)
        };
        let has_gravity = gravity.iter().any(|&g| g != 0.0);
        let mut state = State {
            slot: (0..n)
                .map(|i| Slot {
                    kin: Kin {
                        pos: particles.position[i],
                        stamp: 0.0,
                        vel: particles.velocity[i],
                        radius: particles.radius[i],
                    },
                    ev: EventRec::default(),
                })
                .collect(),
            mass: particles.mass.clone(),
            id: (0..n as u32).collect(),
            species: particles.species.clone(),
            pending_vel: vec![[0.0; 3]; n],
            last_contact: vec![LastContact::NONE; n],
            image: particles.image.clone(),
            spin: (0..n)
                .map(|i| {
                    particles
                        .angular_velocity
                        .get(i)
                        .copied()
                        .unwrap_or([0.0; 3])
                })
                .collect(),
            resort_every: if n >= RESORT_MIN_PARTICLES {
                20 * n as u64
            } else {
                0
            },
            since_resort: 0,
            // Sized for the broad phase when the engine starts.
            queue: Q::new(0),
            time: 0.0,
            region,
            period: std::array::from_fn(|k| {
                if region.periodic[k] {
                    region.size[k]
                } else {
                    0.0
                }
            }),
            domain,
            has_gravity,
            stats: Stats::default(),
            kinetic: [0.0; 6],
            stress_mark: None,
            zero_streak: 0,
            probe: None,
            anticipating: false,
            scheduled: Vec::new(),
        };
        state.anticipating = rules.solves_ahead().is_some() && state.domain.shear_rate == 0.0;
        for i in 0..n {
            let x = state.wrap_slot(i, state.slot[i].kin.pos);
            state.slot[i].kin.pos = x;
        }
        Ok(Self {
            state,
            rules,
            max_contact,
            cell_width,
        })
    }

    /// Whether the automatic choice takes epochs: no gravity, a gas dilute enough
    /// (below [`BroadPhaseKind::AUTO_EPOCHS_BELOW`]) and held along every axis, and a
    /// region epochs fit.
    pub fn prefers_epochs(&self) -> bool {
        let s = &self.state;
        let volume = s.region.size.iter().product::<f64>();
        let radii: Vec<f64> = s.slot.iter().map(|slot| slot.kin.radius).collect();
        let dilute = sphere_volume(&radii) < BroadPhaseKind::AUTO_EPOCHS_BELOW * volume;
        self.epochs_fit() && dilute && confined(&s.region, &s.domain.walls)
    }

    /// Whether the automatic choice takes neighbour lists: hard spheres or eMD without
    /// gravity, a gas dense enough (from [`BroadPhaseKind::AUTO_NEIGHBOURS_FROM`]) and
    /// held along every axis, and a region they fit.
    pub fn prefers_neighbours(&self) -> bool {
        let s = &self.state;
        let volume = s.region.size.iter().product::<f64>();
        let radii: Vec<f64> = s.slot.iter().map(|slot| slot.kin.radius).collect();
        let dense = sphere_volume(&radii) >= BroadPhaseKind::AUTO_NEIGHBOURS_FROM * volume;
        self.neighbours_fit() && dense && confined(&s.region, &s.domain.walls)
    }

    /// Whether neighbour lists can run here at all (hard spheres or eMD, no gravity,
    /// radii within a factor of two, a region they fit). Every list is as long as the
    /// largest: one large sphere among many small ones would make them all long.
    pub fn neighbours_fit(&self) -> bool {
        let s = &self.state;
        let smallest = s
            .slot
            .iter()
            .map(|p| p.kin.radius)
            .fold(f64::INFINITY, f64::min);
        !s.has_gravity
            && s.domain.shear_rate == 0.0
            && !self.rules.is_emdstar()
            && self.max_contact <= 4.0 * smallest
            && Neighbours::fits(&s.region, self.max_contact, s.len())
    }

    /// Whether epochs can run here at all (no gravity, a region they fit).
    pub fn epochs_fit(&self) -> bool {
        !self.state.has_gravity
            && self.state.domain.shear_rate == 0.0
            && Epochs::fits(&self.state.region, self.max_contact, self.state.len())
    }
}

impl<B: BroadPhase, Q: EventQueue> EventEngine<B, Q> {
    /// The engine on broad phase `broad` from a prepared input: files every particle,
    /// re-sorts them (large systems) and predicts every first event.
    pub(crate) fn start(
        Prepared {
            mut state, rules, ..
        }: Prepared<Q>,
        mut broad: B,
    ) -> Self {
        state.queue = Q::new(state.len() + B::OWN_EVENTS);
        broad.file(&state);
        if state.resort_every > 0 {
            broad.resort(&mut state);
        }
        broad.start(&mut state);
        Self {
            state,
            broad,
            rules,
        }
    }
}

impl<Q: EventQueue> EventEngine<Crossings, Q> {
    /// An engine on cell crossings; see [`crate::Engine::new`] for the checks and
    /// [`crate::Engine::with_cell_width`] for `min_width`.
    pub fn crossings(
        particles: &Particles,
        domain: &Domain,
        physics: Physics,
        min_width: f64,
    ) -> Result<Self> {
        Ok(Self::from_crossings(Prepared::new(
            particles, domain, physics, min_width,
        )?))
    }

    /// The engine on cell crossings from a prepared input.
    pub(crate) fn from_crossings(p: Prepared<Q>) -> Self {
        let grid = Crossings::new(&p.state.region, p.cell_width, p.state.len());
        Self::start(p, grid)
    }
}

impl<Q: EventQueue> EventEngine<Epochs, Q> {
    /// An engine on epochs; see [`crate::Engine::new`] for the checks. Errors also
    /// under gravity or in a periodic box too small for epochs.
    pub fn epochs(particles: &Particles, domain: &Domain, physics: Physics) -> Result<Self> {
        let p = Prepared::new(particles, domain, physics, 0.0)?;
        if !p.epochs_fit() {
            return invalid(EPOCHS_DO_NOT_FIT.into());
        }
        Ok(Self::from_prepared(p))
    }

    /// The engine on epochs from an input they fit.
    pub(crate) fn from_prepared(p: Prepared<Q>) -> Self {
        let epochs = Epochs::new(&p.state.region, p.max_contact, p.state.len(), p.cell_width);
        Self::start(p, epochs)
    }
}

impl<Q: EventQueue> EventEngine<Neighbours, Q> {
    /// The engine on neighbour lists from an input they fit.
    pub(crate) fn from_neighbours(p: Prepared<Q>) -> Self {
        let lists = Neighbours::new(&p.state.region, p.max_contact, p.state.len());
        Self::start(p, lists)
    }
}

/// Why [`BroadPhaseKind::Neighbours`] was refused.
pub(crate) const NEIGHBOURS_DO_NOT_FIT: &str = "the neighbour-list broad phase runs hard \
     spheres and eMD (not eMD*) without gravity, with radii within a factor of two and, \
     along periodic axes, in a box at least 4.5 largest contact distances wide; use \
     BroadPhase::Crossings";

/// Why [`BroadPhaseKind::Epochs`] was refused.
pub(crate) const EPOCHS_DO_NOT_FIT: &str = "the epoch broad phase needs no gravity and, along \
     periodic axes, a box at least four times the sum of the largest contact distance and a \
     cell width (a cell is 0.8 mean spacings); use BroadPhase::Crossings";
