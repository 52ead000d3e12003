//! Sphere and pair properties (Müller & Pöschel 2013, Eq. 5).

use crate::error::{Result, positive};
use std::f64::consts::PI;

/// A sphere's size and mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Radius in m.
    pub radius: f64,
    /// Mass in kg.
    pub mass: f64,
}

impl Sphere {
    /// A sphere of given radius and mass, both > 0.
    pub fn new(radius: f64, mass: f64) -> Result<Self> {
        Ok(Self {
            radius: positive("radius", radius)?,
            mass: positive("mass", mass)?,
        })
    }

    /// A homogeneous sphere of mass (4/3)πR³ρ.
    pub fn from_density(radius: f64, density: f64) -> Result<Self> {
        let radius = positive("radius", radius)?;
        let density = positive("density", density)?;
        Ok(Self {
            radius,
            mass: 4.0 / 3.0 * PI * radius.powi(3) * density,
        })
    }
}

/// What the collision of two bodies depends on besides the force law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairProperties {
    /// Centre distance at first touch, l = R₁ + R₂ (R against a wall), in m.
    pub l: f64,
    /// Reduced mass m₁m₂/(m₁+m₂) (m against a wall), in kg.
    pub m_eff: f64,
    /// Effective radius R₁R₂/(R₁+R₂) (R against a wall), in m.
    pub r_eff: f64,
}

impl PairProperties {
    /// Two spheres; unequal radii and masses are fine.
    pub fn spheres(a: &Sphere, b: &Sphere) -> Self {
        Self {
            l: a.radius + b.radius,
            m_eff: a.mass * b.mass / (a.mass + b.mass),
            r_eff: a.radius * b.radius / (a.radius + b.radius),
        }
    }

    /// A sphere against an infinitely heavy flat wall (R₂, m₂ → ∞).
    pub fn sphere_wall(s: &Sphere) -> Self {
        Self {
            l: s.radius,
            m_eff: s.mass,
            r_eff: s.radius,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn unequal_spheres() {
        let a = Sphere::new(0.1, 2.0).unwrap();
        let b = Sphere::new(0.3, 6.0).unwrap();
        let p = PairProperties::spheres(&a, &b);
        assert_relative_eq!(p.l, 0.4);
        assert_relative_eq!(p.m_eff, 1.5);
        assert_relative_eq!(p.r_eff, 0.075);
    }

    #[test]
    fn a_wall_is_the_limit_of_a_huge_sphere() {
        let a = Sphere::new(0.1, 2.0).unwrap();
        let huge = Sphere::new(1e12, 1e30).unwrap();
        let w = PairProperties::sphere_wall(&a);
        let p = PairProperties::spheres(&a, &huge);
        assert_relative_eq!(p.m_eff, w.m_eff, max_relative = 1e-12);
        assert_relative_eq!(p.r_eff, w.r_eff, max_relative = 1e-12);
    }

    #[test]
    fn density_gives_the_mass_of_a_ball() {
        let s = Sphere::from_density(0.1, 1140.0).unwrap();
        assert_relative_eq!(s.mass, 4.775_220_833_456_485, max_relative = 1e-12);
        assert!(Sphere::from_density(-0.1, 1140.0).is_err());
        assert!(Sphere::new(0.1, f64::NAN).is_err());
    }
}
