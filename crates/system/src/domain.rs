//! Where the particles move — the box, the plane walls and gravity — and the checks
//! of a state against it that every engine relies on.

use crate::error::{Result, SystemError, invalid};
use crate::geometry::{CellGrid, SimBox, Stencil, Wall, bounded_cell_width, bounding_box};
use crate::shear::LeesEdwards;
use crate::state::Particles;
use emdstar_contact::vec3::{norm, norm2, sub};

/// The surroundings of the particles.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Domain {
    /// `None` means free space.
    pub sim_box: Option<SimBox>,
    pub walls: Vec<Wall>,
    /// Uniform acceleration in m/s².
    pub gravity: [f64; 3],
    /// Lees–Edwards shear rate γ̇ in 1/s (x flow, y gradient; 0: none). Set from the
    /// config at every build, so not saved.
    #[serde(skip)]
    pub shear_rate: f64,
}

impl Domain {
    /// A periodic cube or cuboid without walls or gravity.
    pub fn periodic(sim_box: SimBox) -> Self {
        Self {
            sim_box: Some(sim_box),
            ..Self::default()
        }
    }

    /// The sliding images of a sheared box, if the box is sheared.
    #[inline]
    pub fn lees_edwards(&self) -> Option<LeesEdwards> {
        match &self.sim_box {
            Some(b) if self.shear_rate != 0.0 => Some(LeesEdwards::new(b, self.shear_rate)),
            _ => None,
        }
    }

    /// The shortest image of a separation `d` (itself in free space).
    #[inline]
    pub fn min_image(&self, d: [f64; 3]) -> [f64; 3] {
        self.sim_box.map_or(d, |b| b.min_image(d))
    }

    /// The region a cell grid over `positions` must cover: the box, or in free space
    /// the positions' bounding box (all axes closed).
    pub fn search_region(&self, positions: &[[f64; 3]]) -> ([f64; 3], [f64; 3], [bool; 3]) {
        match &self.sim_box {
            Some(b) => (b.lo, b.size, b.periodic),
            None => {
                let (lo, extent) = bounding_box(positions);
                (lo, extent, [false; 3])
            }
        }
    }

    /// Checks what every engine relies on: walls parallel to the periodic axes, walls
    /// that close every closed axis on both sides, finite state, particles inside the
    /// box along closed axes, in front of every wall, and no two particles overlapping.
    /// Particles are named by their config number.
    pub fn check(&self, p: &Particles) -> Result<()> {
        self.check_closed_axes(p)?;
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
        for i in 0..p.len() {
            let (x, v) = (p.position[i], p.velocity[i]);
            let id = p.id[i] as usize;
            if !x.iter().chain(&v).all(|c| c.is_finite()) {
                return invalid!("particle {id}: position {x:?} and velocity {v:?} must be finite");
            }
            // Every engine squares speeds (energies, impact speeds, event times).
            if !(0.5 * p.mass[i] * norm2(v)).is_finite() {
                return invalid!(
                    "particle {id}: velocity {v:?} m/s is too large: its kinetic energy \
                     overflows double precision; give speeds of a physical size"
                );
            }
            let w = p.angular_velocity[i];
            if !w.iter().all(|c| c.is_finite()) {
                return invalid!("particle {id}: angular velocity {w:?} must be finite");
            }
            if !(0.5 * p.inertia(i) * norm2(w)).is_finite() {
                return invalid!(
                    "particle {id}: angular velocity {w:?} rad/s is too large: its rotational \
                     energy overflows double precision; give spins of a physical size"
                );
            }
            if let Some(b) = &self.sim_box
                && let Some(k) = b.outside_closed_axis(x)
            {
                return Err(SystemError::Misplaced {
                    i: id,
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
                let d = w.distance_at(x, 0.0);
                if d < p.radius[i] {
                    return Err(SystemError::Misplaced {
                        i: id,
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
        let kinetic: f64 = (0..p.len())
            .map(|i| 0.5 * p.mass[i] * norm2(p.velocity[i]))
            .sum();
        if !kinetic.is_finite() {
            return invalid!(
                "the particles' total kinetic energy overflows double precision; give speeds \
                 of a physical size"
            );
        }
        if !(kinetic + p.rotational_energy()).is_finite() {
            return invalid!(
                "the particles' total kinetic energy (translation and rotation) overflows \
                 double precision; give speeds and spins of a physical size"
            );
        }
        self.check_overlaps(p)
    }

    /// Refuses a box axis that is closed (not periodic) without a wall on each side to
    /// hold the particles in: they would leave the box along it. A wall facing along the
    /// axis (normal ±e_k) must lie within the box, up to the smallest radius.
    fn check_closed_axes(&self, p: &Particles) -> Result<()> {
        let Some(b) = &self.sim_box else {
            return Ok(());
        };
        let r_min = p.radius.iter().copied().fold(f64::INFINITY, f64::min);
        let slack = if r_min.is_finite() { r_min } else { 0.0 };
        for k in (0..3).filter(|&k| !b.periodic[k]) {
            let axis = ["x", "y", "z"][k];
            let (lo, hi) = (b.lo[k], b.lo[k] + b.size[k]);
            for (sign, side, at) in [(1.0, "low", lo), (-1.0, "high", hi)] {
                let holds = self.walls.iter().any(|w| {
                    let facing = sign * w.normal[k] > 0.0;
                    let aligned = (1.0 - w.normal[k].abs()).abs() < 1e-12;
                    let inside = w.point[k] >= lo - slack && w.point[k] <= hi + slack;
                    facing && (!aligned || inside)
                });
                if !holds {
                    let normal: [f64; 3] = std::array::from_fn(|j| if j == k { sign } else { 0.0 });
                    let mut point = [0.0; 3];
                    point[k] = at;
                    return invalid!(
                        "box.periodic leaves the {axis} axis closed, but no wall holds the \
                         particles at its {side} end ({axis} = {at:e} m): they would leave the \
                         box; add a [[walls]] entry with normal = {normal:?} and point = \
                         {point:?}, or make the axis periodic"
                    );
                }
            }
        }
        Ok(())
    }

    /// The first overlapping pair (in config numbering), found with a cell grid.
    fn check_overlaps(&self, p: &Particles) -> Result<()> {
        if p.len() < 2 {
            return Ok(());
        }
        let (lo, extent, periodic) = self.search_region(&p.position);
        let max_radius = p.radius.iter().copied().fold(0.0, f64::max);
        let width = bounded_cell_width(extent, 2.0 * max_radius, 8.0 * p.len() as f64 + 64.0);
        let mut grid = CellGrid::new(lo, extent, periodic, width);
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
                    let dist = norm(self.min_image(sub(p.position[i], p.position[j])));
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{SimBox, Wall};
    use crate::state::Species;

    fn two(v: [f64; 3]) -> Particles {
        let s = [Species::new(0.1, 2.0)];
        let mut p = Particles::default();
        p.push(&s, 0, [0.0; 3], v);
        p.push(&s, 0, [1.0, 0.0, 0.0], [0.0; 3]);
        p
    }

    #[test]
    fn a_closed_axis_needs_a_wall_at_each_end_inside_the_box() {
        let mut p = Particles::default();
        let s = [Species::new(0.1, 1.0)];
        p.push(&s, 0, [0.5; 3], [0.0; 3]);
        let sim_box = SimBox {
            lo: [0.0; 3],
            size: [1.0; 3],
            periodic: [true, true, false],
        };
        let wall = |z: f64, n: f64| Wall {
            normal: [0.0, 0.0, n],
            point: [0.0, 0.0, z],
            vibration: None,
        };
        let mut d = Domain::periodic(sim_box);
        let err = d.check(&p).unwrap_err().to_string();
        assert!(
            err.contains("z axis closed") && err.contains("low end"),
            "{err}"
        );
        d.walls.push(wall(0.0, 1.0));
        let err = d.check(&p).unwrap_err().to_string();
        assert!(
            err.contains("high end") && err.contains("[0.0, 0.0, -1.0]"),
            "{err}"
        );
        // A lid far above the box holds nothing in.
        d.walls.push(wall(5.0, -1.0));
        assert!(d.check(&p).is_err());
        d.walls[1] = wall(1.0, -1.0);
        assert!(d.check(&p).is_ok());
        // A tilted floor holds the particles as well (its position is not checked).
        let sim_box = SimBox {
            lo: [0.0; 3],
            size: [1.0; 3],
            periodic: [true, false, false],
        };
        d.sim_box = Some(sim_box);
        let err = d.check(&p).unwrap_err().to_string();
        assert!(err.contains("y axis closed"), "{err}");
        let tilted = Wall {
            normal: [0.0, 0.6, 0.8],
            point: [0.0; 3],
            vibration: None,
        };
        d.walls.push(tilted);
        let err = d.check(&p).unwrap_err().to_string();
        assert!(
            err.contains("y axis closed") && err.contains("high end"),
            "{err}"
        );
    }

    #[test]
    fn far_apart_particles_are_checked_with_a_small_grid() {
        // Two spheres of 1 µm 1 km apart in free space: a cell of 2 µm each would be
        // 5e8 cells along x alone; the grid stays small and the check answers.
        let s = [Species::new(1e-6, 1.0)];
        let mut p = Particles::default();
        p.push(&s, 0, [0.0; 3], [0.0; 3]);
        p.push(&s, 0, [1e3, 1e3, 1e3], [0.0; 3]);
        p.push(&s, 0, [1e3, 1e3, 1e3 + 1e-6], [0.0; 3]);
        let err = Domain::default().check(&p).unwrap_err().to_string();
        assert!(err.contains("particles 1 and 2 overlap"), "{err}");
    }

    #[test]
    fn speeds_whose_energy_overflows_are_refused() {
        let free = Domain::default();
        assert!(free.check(&two([1e150, 0.0, 0.0])).is_ok());
        let err = free.check(&two([1e300, 0.0, 0.0])).unwrap_err().to_string();
        assert!(
            err.contains("particle 0") && err.contains("too large"),
            "{err}"
        );
        // Each particle's energy finite, their sum not.
        let mut p = two([1.2e154, 0.0, 0.0]);
        p.velocity[1] = [1.2e154, 0.0, 0.0];
        let err = free.check(&p).unwrap_err().to_string();
        assert!(err.contains("total kinetic energy"), "{err}");
    }

    #[test]
    fn spins_whose_energy_overflows_are_refused() {
        // I = (2/5) m R² = 8e-3 kg m²: ½ I ω² is finite up to ω ≈ 1.5e155 rad/s.
        let free = Domain::default();
        let mut p = two([0.0; 3]);
        p.angular_velocity[0] = [1e150, 0.0, 0.0];
        assert!(free.check(&p).is_ok());
        p.angular_velocity[0] = [1e308, 0.0, 0.0];
        let err = free.check(&p).unwrap_err().to_string();
        assert!(
            err.contains("particle 0")
                && err.contains("angular velocity")
                && err.contains("too large"),
            "{err}"
        );
        p.angular_velocity[0] = [f64::NAN, 0.0, 0.0];
        let err = free.check(&p).unwrap_err().to_string();
        assert!(err.contains("must be finite"), "{err}");
        // Each energy finite, translation and rotation together not: ½ m v² = 1.44e308
        // J, and a sphere of 10 m and 2 kg (I = 80 kg m²) at 1.5e153 rad/s has 9e307 J.
        let mut p = two([1.2e154, 0.0, 0.0]);
        p.radius[1] = 10.0;
        p.position[1] = [100.0, 0.0, 0.0];
        p.angular_velocity[1] = [0.0, 0.0, 1.5e153];
        let err = free.check(&p).unwrap_err().to_string();
        assert!(err.contains("translation and rotation"), "{err}");
    }
}
