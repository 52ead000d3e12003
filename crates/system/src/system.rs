//! A complete, validated system: particles, species, the material, box, walls, gravity.

use crate::error::{Result, SystemError, invalid};
use crate::geometry::{CellGrid, SimBox, Stencil, Wall, bounding_box};
use crate::state::{Particles, Species};
use emdstar_contact::{ForceLaw, PairLaw, PairProperties};

/// Everything an engine needs besides its own options.
#[derive(Debug, Clone)]
pub struct System {
    pub particles: Particles,
    pub species: Vec<Species>,
    /// The force law of the one material all particles and walls are made of.
    pub material: ForceLaw,
    /// `None` means free space.
    pub sim_box: Option<SimBox>,
    pub walls: Vec<Wall>,
    /// Uniform acceleration in m/s².
    pub gravity: [f64; 3],
}

impl System {
    /// The pair law and pair properties of species `a` against species `b`.
    pub fn pair(&self, a: usize, b: usize) -> Result<(PairLaw, PairProperties)> {
        let props = PairProperties::spheres(&self.species[a].sphere(), &self.species[b].sphere());
        Ok((PairLaw::same_material(&self.material, props.r_eff)?, props))
    }

    /// The law and properties of species `a` against a flat wall.
    pub fn wall_pair(&self, a: usize) -> Result<(PairLaw, PairProperties)> {
        let props = PairProperties::sphere_wall(&self.species[a].sphere());
        Ok((PairLaw::same_material(&self.material, props.r_eff)?, props))
    }

    /// Largest particle radius (0 if there are none).
    pub fn max_radius(&self) -> f64 {
        self.species.iter().map(|s| s.radius).fold(0.0, f64::max)
    }

    /// Checks what every engine relies on: walls parallel to the periodic axes, finite
    /// state, particles inside the box along closed axes, in front of every wall, and no
    /// two particles overlapping.
    pub fn validate(&self) -> Result<()> {
        if let Some(b) = &self.sim_box {
            for (w_index, w) in self.walls.iter().enumerate() {
                if let Some(k) = (0..3).find(|&k| b.periodic[k] && w.normal[k].abs() > 1e-12) {
                    return invalid!(
                        "wall {w_index} (normal {:?}) is not parallel to the periodic axis {}: \
                         its periodic images would cut the box; make that axis closed \
                         (box.periodic) or turn the wall",
                        w.normal,
                        ["x", "y", "z"][k]
                    );
                }
            }
        }
        let p = &self.particles;
        for i in 0..p.len() {
            let (x, v) = (p.position[i], p.velocity[i]);
            if !x.iter().chain(&v).all(|c| c.is_finite()) {
                return invalid!("particle {i}: position {x:?} and velocity {v:?} must be finite");
            }
            if let Some(b) = &self.sim_box
                && let Some(k) = b.outside_closed_axis(x)
            {
                return Err(SystemError::Misplaced {
                    i,
                    position: x,
                    why: format!(
                        "lies outside the box along the closed axis {} ([{}, {}]); move it \
                         inside or make that axis periodic",
                        ["x", "y", "z"][k],
                        b.lo[k],
                        b.lo[k] + b.size[k]
                    ),
                });
            }
            for (w_index, w) in self.walls.iter().enumerate() {
                let d = w.distance(x);
                if d < p.radius[i] {
                    return Err(SystemError::Misplaced {
                        i,
                        position: x,
                        why: format!(
                            "cuts through or lies behind wall {w_index} (distance {d:e} m < \
                             radius {} m); place it on the side the wall normal points to",
                            p.radius[i]
                        ),
                    });
                }
            }
        }
        self.check_overlaps()
    }

    /// The first overlapping pair (in config numbering), found with a cell grid.
    fn check_overlaps(&self) -> Result<()> {
        let p = &self.particles;
        if p.len() < 2 {
            return Ok(());
        }
        let (lo, extent, periodic) = self.search_region();
        let mut grid = CellGrid::new(lo, extent, periodic, 2.0 * self.max_radius());
        grid.bin(&p.position);
        let mut worst: Option<(usize, usize, f64, f64)> = None;
        for i in 0..p.len() {
            let c = grid.coords(p.position[i]);
            grid.for_each_neighbour(c, Stencil::Full, |cell, _| {
                for &j in grid.items(cell) {
                    let j = j as usize;
                    if j <= i {
                        continue;
                    }
                    let d = std::array::from_fn(|k| p.position[i][k] - p.position[j][k]);
                    let d = self.sim_box.map_or(d, |b| b.min_image(d));
                    let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    let contact = p.radius[i] + p.radius[j];
                    let (a, b) = (p.id[i].min(p.id[j]) as usize, p.id[i].max(p.id[j]) as usize);
                    if dist < contact && worst.is_none_or(|w| (a, b) < (w.0, w.1)) {
                        worst = Some((a, b, dist, contact));
                    }
                }
            });
        }
        match worst {
            Some((i, j, distance, contact)) => Err(SystemError::Overlap {
                i,
                j,
                distance,
                contact,
            }),
            None => Ok(()),
        }
    }

    /// The region a cell grid must cover: the box, or the particles' bounding box.
    pub fn search_region(&self) -> ([f64; 3], [f64; 3], [bool; 3]) {
        match &self.sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let (lo, extent) = bounding_box(&self.particles.position);
                (lo, extent, [false; 3])
            }
        }
    }
}
