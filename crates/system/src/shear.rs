//! Lees–Edwards boundaries (Lees & Edwards 1972, J. Phys. C 5, 1921): homogeneous
//! shear flow with the flow along x and the gradient along y. The periodic images of
//! the box above and below in y slide along x by ±Δ(t) = γ̇ L_y t (taken modulo L_x)
//! and move with ±γ̇ L_y along x; the streaming velocity is u_x(y) = γ̇ (y − y_mid).

use crate::geometry::SimBox;
use crate::state::Particles;

/// The sliding images of a box sheared at `rate` (x flow, y gradient).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeesEdwards {
    /// γ̇ in 1/s.
    pub rate: f64,
    pub lo: [f64; 3],
    pub size: [f64; 3],
    /// Whether z is periodic (x and y are).
    pub periodic_z: bool,
}

impl LeesEdwards {
    /// The shear of `b` at `rate` (x and y must be periodic; the config checks it).
    pub fn new(b: &SimBox, rate: f64) -> Self {
        Self {
            rate,
            lo: b.lo,
            size: b.size,
            periodic_z: b.periodic[2],
        }
    }

    /// γ̇ L_y: the x-velocity of the image above relative to the box (m/s).
    #[inline]
    pub fn image_speed(&self) -> f64 {
        self.rate * self.size[1]
    }

    /// Δ(t) = γ̇ L_y t modulo L_x, in [0, L_x): how far the image above has slid along x.
    #[inline]
    pub fn offset(&self, t: f64) -> f64 {
        (self.image_speed() * t).rem_euclid(self.size[0])
    }

    /// Δ(t) taken in [−L_x/2, L_x/2): with it the nearest image of a pair across the
    /// face is at most one box away along x.
    #[inline]
    pub fn centred_offset(&self, t: f64) -> f64 {
        let lx = self.size[0];
        let d = self.offset(t);
        if d >= 0.5 * lx { d - lx } else { d }
    }

    /// The streaming velocity u_x(y) = γ̇ (y − y_mid) of the steady profile.
    #[inline]
    pub fn streaming(&self, y: f64) -> f64 {
        self.rate * (y - self.lo[1] - 0.5 * self.size[1])
    }

    /// The particles' velocities made peculiar: v_x − u_x(y) (positions in the box).
    pub fn peculiar(&self, p: &mut Particles) {
        for (v, x) in p.velocity.iter_mut().zip(&p.position) {
            v[0] -= self.streaming(x[1]);
        }
    }

    /// The nearest image of particle j seen from i at time `t`, for d = x_i − x_j:
    /// the separation to it and how many boxes up (n_y) it lies, its x-velocity being
    /// v_j,x + n_y γ̇ L_y. With n_y = round(d_y/L_y), d_x − n_y Δ(t) and then the
    /// ordinary minimum image along x (and z where periodic).
    #[inline]
    pub fn image(&self, mut d: [f64; 3], t: f64) -> ([f64; 3], i32) {
        let [lx, ly, lz] = self.size;
        let n = (d[1] / ly).round();
        d[1] -= n * ly;
        d[0] -= n * self.offset(t);
        d[0] -= lx * (d[0] / lx).round();
        if self.periodic_z {
            d[2] -= lz * (d[2] / lz).round();
        }
        (d, n as i32)
    }

    /// The x-velocity of the image `up` boxes above relative to the particle (m/s).
    #[inline]
    pub fn image_velocity(&self, up: i32) -> f64 {
        f64::from(up) * self.image_speed()
    }

    /// Brings a position and velocity at time `t` into the box: across a y face the
    /// particle becomes its image, x shifted by ∓Δ(t) and v_x by ∓γ̇ L_y; x and z
    /// then wrap as usual. Returns the number of boxes it moved down in y.
    pub fn wrap(&self, p: &mut [f64; 3], v: &mut [f64; 3], t: f64) -> i32 {
        let [lx, ly, lz] = self.size;
        let n = ((p[1] - self.lo[1]) / ly).floor();
        if n != 0.0 {
            p[1] -= n * ly;
            if p[1] >= self.lo[1] + ly {
                p[1] -= ly;
            }
            if p[1] < self.lo[1] {
                p[1] = self.lo[1];
            }
            p[0] -= n * self.offset(t);
            v[0] -= n * self.image_speed();
        }
        p[0] = wrap_axis(p[0], self.lo[0], lx);
        if self.periodic_z {
            p[2] = wrap_axis(p[2], self.lo[2], lz);
        }
        n as i32
    }
}

/// `x` wrapped into [lo, lo + l).
#[inline]
fn wrap_axis(x: f64, lo: f64, l: f64) -> f64 {
    let mut r = (x - lo).rem_euclid(l);
    if r >= l {
        r -= l;
    }
    lo + r
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheared(rate: f64) -> LeesEdwards {
        LeesEdwards::new(
            &SimBox {
                lo: [0.0; 3],
                size: [4.0, 2.0, 3.0],
                periodic: [true; 3],
            },
            rate,
        )
    }

    #[test]
    fn a_particle_leaving_through_the_top_enters_at_the_bottom_shifted_back() {
        // γ̇ = 0.5/s, L_y = 2 m: the image above moves at 1 m/s; at t = 1.5 s it has
        // slid Δ = 1.5 m. A particle at y = 2.1, x = 1.0 becomes (1.0 − 1.5 + 4, 0.1).
        let s = sheared(0.5);
        let (mut p, mut v) = ([1.0, 2.1, 1.0], [0.3, 0.2, 0.0]);
        assert_eq!(s.wrap(&mut p, &mut v, 1.5), 1);
        assert!(
            (p[0] - 3.5).abs() < 1e-12 && (p[1] - 0.1).abs() < 1e-12,
            "{p:?}"
        );
        assert!((v[0] - (0.3 - 1.0)).abs() < 1e-12, "{v:?}");
        // And back through the bottom: the inverse.
        let (mut q, mut w) = ([3.5, -0.1, 1.0], [v[0], -0.2, 0.0]);
        assert_eq!(s.wrap(&mut q, &mut w, 1.5), -1);
        assert!(
            (q[0] - 1.0).abs() < 1e-12 && (q[1] - 1.9).abs() < 1e-12,
            "{q:?}"
        );
        assert!((w[0] - 0.3).abs() < 1e-12, "{w:?}");
    }

    #[test]
    fn the_nearest_image_across_the_sheared_face_is_slid_by_the_offset() {
        let s = sheared(0.5);
        // i near the bottom, j near the top: j's image below lies at x_j − Δ.
        let (xi, xj) = ([1.0, 0.1, 1.0], [2.0, 1.9, 1.0]);
        let t = 1.5; // Δ = 1.5
        let d = std::array::from_fn(|k| xi[k] - xj[k]);
        let (r, up) = s.image(d, t);
        assert_eq!(up, -1);
        // x_j − Δ = 0.5: r_x = 1.0 − 0.5.
        assert!(
            (r[0] - 0.5).abs() < 1e-12 && (r[1] - 0.2).abs() < 1e-12,
            "{r:?}"
        );
        assert_eq!(s.image_velocity(up), -1.0);
        // Seen from j, the image of i above lies at x_i + Δ = 2.5.
        let (r, up) = s.image(std::array::from_fn(|k| xj[k] - xi[k]), t);
        assert_eq!(up, 1);
        assert!(
            (r[0] + 0.5).abs() < 1e-12 && (r[1] + 0.2).abs() < 1e-12,
            "{r:?}"
        );
        // Without shear it is the ordinary minimum image.
        let (r, _) = sheared(0.0).image(d, t);
        assert!((r[0] + 1.0).abs() < 1e-12, "{r:?}");
    }
}
