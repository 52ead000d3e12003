//! Building an engine: input checks with clear errors, the cell grid, first predictions.

use crate::cells::{CellGrid, NONE, auto_cell_width};
use crate::engine::{Engine, EventRec, Kin, Slot, dot, sub};
use crate::epoch::Epochs;
use crate::error::{EngineError, Result};
use crate::queue::EventQueue;
use crate::rules::HertzRestitution;
use crate::setup::{BroadPhase, Physics, Region, Setup, Wall};
use crate::stats::Stats;

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

fn check_particles(s: &Setup) -> Result<()> {
    let n = s.position.len();
    let lens = [
        s.velocity.len(),
        s.radius.len(),
        s.mass.len(),
        s.species.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return invalid(format!(
            "position, velocity, radius, mass and species need one entry per particle; \
             got {n}, {}, {}, {} and {}",
            lens[0], lens[1], lens[2], lens[3]
        ));
    }
    if n + s.walls.len() >= NONE as usize {
        return invalid(format!("{n} particles are more than this engine can index"));
    }
    for i in 0..n {
        let (x, v) = (s.position[i], s.velocity[i]);
        if !x.iter().chain(&v).all(|c| c.is_finite()) {
            return invalid(format!(
                "particle {i}: position {x:?} and velocity {v:?} must be finite"
            ));
        }
        if !(s.radius[i] > 0.0 && s.radius[i].is_finite()) {
            return invalid(format!(
                "particle {i}: radius {} must be positive",
                s.radius[i]
            ));
        }
        if !(s.mass[i] > 0.0 && s.mass[i].is_finite()) {
            return invalid(format!("particle {i}: mass {} must be positive", s.mass[i]));
        }
    }
    if !s.gravity.iter().all(|g| g.is_finite()) {
        return invalid(format!("gravity {:?} must be finite", s.gravity));
    }
    Ok(())
}

fn normalised_walls(s: &Setup) -> Result<Vec<Wall>> {
    let mut walls = Vec::with_capacity(s.walls.len());
    for (w, wall) in s.walls.iter().enumerate() {
        let len = dot(wall.normal, wall.normal).sqrt();
        if !(len > 0.0 && len.is_finite() && wall.point.iter().all(|x| x.is_finite())) {
            return invalid(format!(
                "wall {w}: normal {:?} must be a finite non-zero vector and point {:?} finite",
                wall.normal, wall.point
            ));
        }
        let normal = wall.normal.map(|x| x / len);
        for i in 0..s.position.len() {
            let distance = dot(normal, sub(s.position[i], wall.point));
            if distance < s.radius[i] {
                return Err(EngineError::WallCut {
                    wall: w,
                    i,
                    distance,
                    radius: s.radius[i],
                });
            }
        }
        walls.push(Wall {
            normal,
            point: wall.point,
        });
    }
    Ok(walls)
}

/// Whether walls normal to every closed axis hold the gas from both sides. A gas free
/// to spread along an axis leaves the epoch grid for its border cells, which reach to
/// infinity, and every epoch then tests all pairs piled there: an expanding cluster
/// of 1728 spheres in free space ran 100 times slower on epochs than on crossings.
fn confined(region: &Region, walls: &[Wall]) -> bool {
    let bounded = |k: usize, sign: f64| {
        walls
            .iter()
            .any(|w| (0..3).all(|m| w.normal[m] == if m == k { sign } else { 0.0 }))
    };
    (0..3).all(|k| region.periodic[k] || bounded(k, 1.0) && bounded(k, -1.0))
}

/// The region, or for free space the particles' bounding box (closed axes).
fn region_of(s: &Setup, max_contact: f64) -> Result<Region> {
    if let Some(r) = s.region {
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
        let spheres = sphere_volume(&s.radius);
        let volume = r.size.iter().product::<f64>();
        if spheres > MAX_PACKING * volume {
            return Err(EngineError::Packing {
                eta: spheres / volume,
                spheres,
                volume,
            });
        }
        for (i, x) in s.position.iter().enumerate() {
            if let Some(k) =
                (0..3).find(|&k| !r.periodic[k] && !(r.lo[k]..=r.lo[k] + r.size[k]).contains(&x[k]))
            {
                return invalid(format!(
                    "particle {i} at {x:?} lies outside the box along the closed axis {}; \
                     move it inside or make that axis periodic",
                    ["x", "y", "z"][k]
                ));
            }
        }
        return Ok(r);
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in &s.position {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    if s.position.is_empty() {
        (lo, hi) = ([0.0; 3], [1.0; 3]);
    }
    Ok(Region {
        lo,
        size: std::array::from_fn(|k| (hi[k] - lo[k]).max(max_contact)),
        periodic: [false; 3],
    })
}

impl<Q: EventQueue> Engine<Q> {
    /// Below this many particles the order is left as given.
    const RESORT_MIN_PARTICLES: usize = 1000;

    /// Checks `setup` and builds an engine at time 0 with every first event predicted.
    ///
    /// Errors: inconsistent or non-finite input, overlapping particles, an impossible
    /// packing fraction, walls cutting particles, a periodic box too small, species
    /// without materials.
    pub fn new(setup: Setup, physics: Physics) -> Result<Self> {
        Self::build(setup, physics, 0.0, BroadPhase::Auto)
    }

    /// As [`Engine::new`] on cell crossings, with cells at least `min_width` wide
    /// instead of the automatic choice (never narrower than the largest contact
    /// distance; wider cells mean fewer crossings but more pair tests). `min_width` = 0
    /// is the automatic choice.
    pub fn with_cell_width(setup: Setup, physics: Physics, min_width: f64) -> Result<Self> {
        Self::build(setup, physics, min_width, BroadPhase::Crossings)
    }

    /// As [`Engine::new`], with the broad phase chosen (see [`BroadPhase`]). Errors as
    /// [`Engine::new`], and for [`BroadPhase::Epochs`] under gravity or in a periodic
    /// box too small for it.
    pub fn with_broad_phase(
        setup: Setup,
        physics: Physics,
        broad_phase: BroadPhase,
    ) -> Result<Self> {
        Self::build(setup, physics, 0.0, broad_phase)
    }

    fn build(
        setup: Setup,
        physics: Physics,
        min_width: f64,
        broad_phase: BroadPhase,
    ) -> Result<Self> {
        check_particles(&setup)?;
        if let Some(m) = physics.materials()
            && let Some((i, s)) = setup
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
        if let Physics::HardSpheres { restitution } = physics
            && !(0.0..=1.0).contains(&restitution)
        {
            return invalid(format!(
                "coefficient of restitution {restitution} must lie in [0, 1]"
            ));
        }
        let walls = normalised_walls(&setup)?;
        let max_contact = 2.0 * setup.radius.iter().copied().fold(0.0, f64::max);
        let region = region_of(&setup, max_contact)?;
        let n = setup.position.len();
        let width = if min_width > 0.0 {
            max_contact.max(min_width)
        } else {
            auto_cell_width(max_contact, region.size.iter().product(), n)
        };
        let grid = CellGrid::new(region.lo, region.size, region.periodic, width, n);
        let has_gravity = setup.gravity.iter().any(|&g| g != 0.0);
        let use_epochs = match broad_phase {
            BroadPhase::Crossings => false,
            BroadPhase::Epochs | BroadPhase::Auto => {
                let fit = !has_gravity && Epochs::fit(&region, max_contact, n);
                if broad_phase == BroadPhase::Epochs && !fit {
                    return invalid(
                        "the epoch broad phase needs no gravity and, along periodic axes, a \
                         box at least four times the sum of the largest contact distance and \
                         a cell width (a cell is 0.8 mean spacings); use BroadPhase::Crossings"
                            .into(),
                    );
                }
                let volume = region.size.iter().product::<f64>();
                let dilute = sphere_volume(&setup.radius) < BroadPhase::AUTO_EPOCHS_BELOW * volume;
                fit && (broad_phase == BroadPhase::Epochs || dilute && confined(&region, &walls))
            }
        };
        let epochs = use_epochs.then(|| Box::new(Epochs::new(&region, max_contact, n)));
        let mut engine = Self {
            slot: (0..n)
                .map(|i| Slot {
                    kin: Kin {
                        pos: setup.position[i],
                        stamp: 0.0,
                        vel: setup.velocity[i],
                        radius: setup.radius[i],
                    },
                    ev: EventRec::default(),
                })
                .collect(),
            mass: setup.mass,
            id: (0..n as u32).collect(),
            resort_every: if n >= Self::RESORT_MIN_PARTICLES {
                20 * n as u64
            } else {
                0
            },
            since_resort: 0,
            species: setup.species,
            pending_vel: vec![[0.0; 3]; n],
            grid,
            epochs,
            queue: Q::new(n + usize::from(use_epochs)),
            time: 0.0,
            walls,
            gravity: setup.gravity,
            has_gravity,
            physics,
            hertz: HertzRestitution::default(),
            stats: Stats::default(),
            zero_streak: 0,
            probe: None,
        };
        for i in 0..n {
            let x = engine.wrap(engine.slot[i].kin.pos);
            engine.slot[i].kin.pos = x;
            let c = engine.grid.coords_of(x);
            engine.grid.insert(i, c);
        }
        engine.check_overlaps()?;
        if engine.resort_every > 0 {
            engine.resort();
        }
        if engine.epochs.is_some() {
            for i in 0..n {
                engine.predict_walls(i);
                engine.schedule(i);
            }
            engine.rebuild_epoch();
        } else {
            for i in 0..n {
                engine.predict(i);
            }
        }
        Ok(engine)
    }

    fn check_overlaps(&self) -> Result<()> {
        for i in 0..self.len() {
            let cells = self.grid.neighbourhood(self.grid.coords[i]);
            for &cell in cells.as_slice() {
                for j in self.grid.particles(cell).filter(|&j| j > i) {
                    let r = self.min_image(sub(self.slot[i].kin.pos, self.slot[j].kin.pos));
                    let distance = dot(r, r).sqrt();
                    let contact = self.slot[i].kin.radius + self.slot[j].kin.radius;
                    if distance < contact {
                        return Err(EngineError::Overlap {
                            i,
                            j,
                            distance,
                            contact,
                        });
                    }
                }
            }
        }
        Ok(())
    }
}
