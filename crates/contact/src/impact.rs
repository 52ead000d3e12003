//! Impact geometry at first touch (Müller & Pöschel 2013, Sec. II and Fig. 2).

use crate::Vec3;
use crate::error::{ContactError, Result, finite, positive};

/// The relative motion of a pair at the moment of contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    /// Normal approach speed v_n = −ṙ⁰ > 0, in m/s.
    pub normal_speed: f64,
    /// Tangential speed v_t ≥ 0, in m/s.
    pub tangential_speed: f64,
}

impl Impact {
    /// From the relative position r = r₁ − r₂ and velocity v = v₁ − v₂ at contact.
    ///
    /// Fails unless the pair approaches (v_n > 0).
    pub fn from_relative(r: &Vec3, v: &Vec3) -> Result<Self> {
        for x in r.iter().chain(v.iter()) {
            finite("relative position or velocity", *x)?;
        }
        let dist = positive("centre distance", r.norm())?;
        let n = r / dist;
        let vr = v.dot(&n);
        let v_t = (v - n * vr).norm();
        let impact = Self {
            normal_speed: -vr,
            tangential_speed: v_t,
        };
        impact.check()
    }

    /// From the relative speed |v| and the eccentricity e = d/l = v_t/|v| (Fig. 2).
    pub fn from_speed_eccentricity(speed: f64, eccentricity: f64) -> Result<Self> {
        let speed = positive("speed", speed)?;
        let e = finite("eccentricity", eccentricity)?;
        if !(0.0..1.0).contains(&e) {
            return Err(ContactError::OutOfRange {
                name: "eccentricity",
                value: e,
                allowed: "[0, 1)",
            });
        }
        Self {
            normal_speed: speed * (1.0 - e * e).sqrt(),
            tangential_speed: speed * e,
        }
        .check()
    }

    fn check(self) -> Result<Self> {
        if self.normal_speed > 0.0 {
            Ok(self)
        } else {
            Err(ContactError::NotApproaching {
                normal_speed: self.normal_speed,
            })
        }
    }

    /// |v| = √(v_n² + v_t²).
    pub fn speed(&self) -> f64 {
        self.normal_speed.hypot(self.tangential_speed)
    }

    /// e = v_t/√(v_n² + v_t²), in [0, 1).
    pub fn eccentricity(&self) -> f64 {
        self.tangential_speed / self.speed()
    }

    /// L/m_eff = l·v_t for a pair touching at distance l.
    pub fn specific_angular_momentum(&self, l: f64) -> f64 {
        l * self.tangential_speed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn oblique_impact_geometry() {
        // Fig. 6 of the paper: v1 = (v/4, v/2, 0), v2 = (v/4, −v/2, 0); contact along a
        // direction with sin(angle to v) = e.
        let e: f64 = 0.3;
        let v = Vec3::new(0.0, 5.0, 0.0);
        let r = Vec3::new(e, -(1.0 - e * e).sqrt(), 0.0) * 0.2;
        let imp = Impact::from_relative(&r, &v).unwrap();
        assert_relative_eq!(imp.eccentricity(), e, max_relative = 1e-14);
        assert_relative_eq!(imp.speed(), 5.0, max_relative = 1e-14);
        assert_relative_eq!(
            imp.normal_speed,
            5.0 * (1.0 - e * e).sqrt(),
            max_relative = 1e-14
        );
        let again = Impact::from_speed_eccentricity(5.0, e).unwrap();
        assert_relative_eq!(
            again.tangential_speed,
            imp.tangential_speed,
            max_relative = 1e-14
        );
    }

    #[test]
    fn receding_or_bad_impacts_are_rejected() {
        let r = Vec3::new(0.2, 0.0, 0.0);
        assert!(matches!(
            Impact::from_relative(&r, &Vec3::new(1.0, 0.0, 0.0)),
            Err(ContactError::NotApproaching { .. })
        ));
        assert!(Impact::from_relative(&Vec3::zeros(), &Vec3::new(-1.0, 0.0, 0.0)).is_err());
        assert!(Impact::from_speed_eccentricity(1.0, 1.0).is_err());
        assert!(Impact::from_speed_eccentricity(1.0, -0.1).is_err());
        assert!(Impact::from_speed_eccentricity(0.0, 0.1).is_err());
        assert!(Impact::from_speed_eccentricity(f64::NAN, 0.1).is_err());
    }
}
