//! The simulation box and plane walls (the cell grid is in `cell_grid`).

pub use crate::cell_grid::{
    CellGrid, Stencil, bounded_cell_width, cell_along, cells_per_axis, sparse_cell_limit,
    sparse_cell_width,
};

/// A cuboid box `[lo, lo + size)`; each axis is periodic or closed.
///
/// Along a closed axis particles must stay inside (walls keep them there); along a
/// periodic axis positions wrap and distances follow the minimum-image convention.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SimBox {
    pub lo: [f64; 3],
    pub size: [f64; 3],
    pub periodic: [bool; 3],
}

impl SimBox {
    /// The upper corner lo + size.
    pub fn hi(&self) -> [f64; 3] {
        std::array::from_fn(|k| self.lo[k] + self.size[k])
    }

    /// Box volume in m³.
    pub fn volume(&self) -> f64 {
        self.size.iter().product()
    }

    /// `p` with its periodic components wrapped into [lo, lo + size).
    #[inline]
    pub fn wrap(&self, mut p: [f64; 3]) -> [f64; 3] {
        for k in 0..3 {
            if self.periodic[k] {
                let l = self.size[k];
                let mut x = p[k] - self.lo[k];
                x -= l * (x / l).floor();
                // Round-off can give x == l for tiny negative inputs.
                if x >= l {
                    x -= l;
                }
                p[k] = self.lo[k] + x;
            }
        }
        p
    }

    /// [`SimBox::wrap`], adding the number of box lengths each periodic component was
    /// moved down by to `image` (its image flags: the unwrapped position is
    /// `wrap + image · size`, exactly as many crossings as happened).
    #[inline]
    pub fn wrap_counting(&self, p: [f64; 3], image: &mut [i32; 3]) -> [f64; 3] {
        let w = self.wrap(p);
        for k in 0..3 {
            if w[k] != p[k] {
                image[k] += ((p[k] - w[k]) / self.size[k]).round() as i32;
            }
        }
        w
    }

    /// The shortest image of a separation vector `d` (minimum-image convention).
    #[inline]
    pub fn min_image(&self, mut d: [f64; 3]) -> [f64; 3] {
        for k in 0..3 {
            if self.periodic[k] {
                let l = self.size[k];
                d[k] -= l * (d[k] / l).round();
            }
        }
        d
    }

    /// The closed axes along which `p` lies outside the box, if any.
    pub fn outside_closed_axis(&self, p: [f64; 3]) -> Option<usize> {
        (0..3).find(|&k| {
            !(self.periodic[k] || (p[k] >= self.lo[k] && p[k] <= self.lo[k] + self.size[k]))
        })
    }
}

/// The lower corner and extent of the smallest box holding `positions` (zero extent
/// and infinite corner if there are none).
pub fn bounding_box(positions: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for x in positions {
        for k in 0..3 {
            lo[k] = lo[k].min(x[k]);
            hi[k] = hi[k].max(x[k]);
        }
    }
    (lo, std::array::from_fn(|k| (hi[k] - lo[k]).max(0.0)))
}

/// A plane wall: an infinitely heavy flat partner filling the half-space behind it.
///
/// Particles live on the side the unit `normal` points to; a sphere of radius R at
/// signed distance d = n·(x − point) overlaps the wall by ξ = R − d.
///
/// A vibrated wall ([`Vibration`]) moves along its normal: its plane passes through
/// `point + s(t) normal` at time t. Its motion is a function of time fixed by the
/// config, so saved states do not hold it (the config digest ties a checkpoint to it).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Wall {
    pub normal: [f64; 3],
    /// A point of the plane (at rest, s = 0, for a vibrated wall).
    pub point: [f64; 3],
    #[serde(skip)]
    pub vibration: Option<crate::vibration::Vibration>,
}

impl Wall {
    /// A wall at rest.
    pub fn fixed(normal: [f64; 3], point: [f64; 3]) -> Self {
        Self {
            normal,
            point,
            vibration: None,
        }
    }

    /// Signed distance of `p` from the wall plane (at rest), positive on the particles'
    /// side.
    #[inline]
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        (0..3)
            .map(|k| self.normal[k] * (p[k] - self.point[k]))
            .sum()
    }

    /// Signed distance of `p` from the plane where the wall is at time `t` (the plane
    /// at rest for a wall that does not vibrate).
    #[inline]
    pub fn distance_at(&self, p: [f64; 3], t: f64) -> f64 {
        match &self.vibration {
            None => self.distance(p),
            Some(v) => self.distance(p) - v.displacement(t),
        }
    }

    /// A point of the plane at time `t`.
    #[inline]
    pub fn point_at(&self, t: f64) -> [f64; 3] {
        match &self.vibration {
            None => self.point,
            Some(v) => {
                let s = v.displacement(t);
                std::array::from_fn(|k| self.point[k] + s * self.normal[k])
            }
        }
    }

    /// The wall's velocity at time `t` (zero for a wall at rest).
    #[inline]
    pub fn velocity_at(&self, t: f64) -> [f64; 3] {
        match &self.vibration {
            None => [0.0; 3],
            Some(v) => {
                let u = v.speed(t);
                self.normal.map(|c| u * c)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_and_min_image() {
        let b = SimBox {
            lo: [-1.0, 0.0, 0.0],
            size: [2.0, 1.0, 1.0],
            periodic: [true, true, false],
        };
        assert_eq!(b.wrap([1.5, -0.25, 3.0]), [-0.5, 0.75, 3.0]);
        assert_eq!(b.min_image([1.5, 0.75, 0.9]), [-0.5, -0.25, 0.9]);
        assert_eq!(b.outside_closed_axis([0.0, 0.0, 1.5]), Some(2));
        assert_eq!(b.outside_closed_axis([5.0, 0.0, 0.5]), None);
    }
}
