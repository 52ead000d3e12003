//! The neighbour list under Lees–Edwards shear (Lees & Edwards 1972; see
//! `emdstar_system::LeesEdwards`): the pairs across the sliding y face, and the images'
//! shifts and velocities as the offset moves on.

use crate::neighbour::{INDEX_BITS, NeighbourList, within};
use emdstar_system::{LeesEdwards, Stencil};

impl NeighbourList {
    /// Adds the partners j < i of particle i (in cell `c`, cut-off radius `ri` + R_j)
    /// across the sliding face: the whole border row opposite, each j under its image
    /// nearest now (the shifts as [`Self::slide`] set them).
    pub(crate) fn push_across(
        &mut self,
        le: &LeesEdwards,
        c: [usize; 3],
        (i, ri): (usize, f64),
        positions: &[[f64; 3]],
        radius: &[f64],
    ) {
        let grid = &self.grid;
        let dims = grid.dims;
        let mut rows = [(0usize, 0usize, 0i8, 0i8); 9];
        let mut n_rows = 0;
        grid.for_each_neighbour(c, Stencil::Full, |other, shift| {
            let x = other % dims[0];
            if shift[1] != 0 && shift[0] == 0 && x == c[0] {
                let (y, z) = ((other / dims[0]) % dims[1], other / (dims[0] * dims[1]));
                rows[n_rows] = (y, z, shift[1], shift[2]);
                n_rows += 1;
            }
        });
        let (lx, delta) = (le.size[0], self.shifts[16][0]);
        let xi = positions[i];
        for &(y, z, up, sz) in &rows[..n_rows] {
            let first = grid.index([0, y, z]);
            let (from, to) = (
                grid.cell_start[first] as usize,
                grid.cell_start[first + dims[0]] as usize,
            );
            for j in from..to.min(i) {
                // The image `up` boxes up at x + up·Δ, then the nearest along x.
                let dx = xi[0] - positions[j][0] - f64::from(up) * delta;
                let sx = (dx / lx).round().clamp(-1.0, 1.0);
                let code = (sx + 1.0) as usize + 3 * (up + 1) as usize + 9 * (sz + 1) as usize;
                if within(xi, positions[j], self.shifts[code], ri + radius[j]) {
                    self.entries.push(j as u32 | (code as u32) << INDEX_BITS);
                }
            }
        }
    }

    /// Moves the images across the sliding face on to time `t` (Lees & Edwards 1972):
    /// the shifts of the images one box up or down become s_x L_x ± Δ, with Δ the
    /// offset continued from where the last slide (or build) left it, so that it never
    /// jumps by L_x while a list lives.
    pub fn slide(&mut self, le: &LeesEdwards, t: f64) {
        let lx = le.size[0];
        let travelled = le.image_speed() * t;
        let wraps = ((travelled - self.shifts[16][0]) / lx).round();
        self.slide_to(le, travelled - wraps * lx);
    }

    /// Sets the shifts of the images one box up or down for the offset `delta`.
    pub(crate) fn slide_to(&mut self, le: &LeesEdwards, delta: f64) {
        for (code, shift) in self.shifts.iter_mut().enumerate() {
            let (sx, up) = ((code % 3) as f64 - 1.0, ((code / 3) % 3) as f64 - 1.0);
            if up != 0.0 {
                shift[0] = sx * le.size[0] + up * delta;
            }
        }
        self.image_speed = le.image_speed();
    }

    /// The image of j nearest to i for d = x_i − x_j in a sheared box, with the offset
    /// of the last [`Self::slide`]: the separation and the image's x-velocity relative
    /// to j.
    pub fn sheared_image(&self, le: &LeesEdwards, mut d: [f64; 3]) -> ([f64; 3], f64) {
        let [lx, ly, lz] = le.size;
        let up = (d[1] / ly).round();
        d[1] -= up * ly;
        d[0] -= up * self.shifts[16][0];
        d[0] -= lx * (d[0] / lx).round();
        if le.periodic_z {
            d[2] -= lz * (d[2] / lz).round();
        }
        (d, up * self.image_speed)
    }

    /// The x-velocity of the image an entry names relative to the particle it stands
    /// for: ±γ̇ L_y across the sliding face, else 0.
    #[inline(always)]
    pub fn image_vx(&self, entry: u32) -> f64 {
        let up = ((entry >> INDEX_BITS) / 3) % 3;
        (up as f64 - 1.0) * self.image_speed
    }
}
