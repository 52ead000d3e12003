//! Vibrated walls: the motion A sin(2π f t + φ) of a wall along its normal, its config
//! keys and their checks.

use crate::domain_config::WallConfig;
use crate::error::{Result, invalid, positive};
use crate::geometry::{SimBox, Wall};

/// A sinusoidal motion of a wall along its normal: s(t) = A sin(2π f t + φ).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Vibration {
    /// A in m.
    pub amplitude: f64,
    /// f in Hz.
    pub frequency: f64,
    /// φ in rad.
    pub phase: f64,
}

impl Vibration {
    /// ω = 2π f in rad/s.
    #[inline]
    pub fn omega(&self) -> f64 {
        std::f64::consts::TAU * self.frequency
    }

    /// s(t) = A sin(ω t + φ), the displacement along the normal, in m.
    #[inline]
    pub fn displacement(&self, t: f64) -> f64 {
        self.amplitude * (self.omega() * t + self.phase).sin()
    }

    /// ṡ(t) = A ω cos(ω t + φ), in m/s.
    #[inline]
    pub fn speed(&self, t: f64) -> f64 {
        let w = self.omega();
        self.amplitude * w * (w * t + self.phase).cos()
    }

    /// The largest |s̈| = A ω², in m/s².
    #[inline]
    pub fn max_acceleration(&self) -> f64 {
        let w = self.omega();
        self.amplitude * w * w
    }
}

impl WallConfig {
    /// The wall's vibration, if it has one: amplitude and frequency finite and
    /// positive, the phase finite.
    pub(crate) fn vibration(&self, i: usize) -> Result<Option<Vibration>> {
        let (amplitude, frequency) = match (self.amplitude, self.frequency) {
            (None, None) => {
                if self.phase.is_some() {
                    return invalid!(
                        "walls[{i}].phase is given without walls[{i}].amplitude and \
                         walls[{i}].frequency: a phase belongs to a vibrated wall; add both \
                         or remove the phase"
                    );
                }
                return Ok(None);
            }
            (Some(_), None) => {
                return invalid!(
                    "walls[{i}].amplitude is given without walls[{i}].frequency: a vibrated \
                     wall needs both (in m and Hz)"
                );
            }
            (None, Some(_)) => {
                return invalid!(
                    "walls[{i}].frequency is given without walls[{i}].amplitude: a vibrated \
                     wall needs both (in m and Hz)"
                );
            }
            (Some(a), Some(f)) => (a, f),
        };
        let amplitude = positive(&format!("walls[{i}].amplitude"), amplitude)?;
        let frequency = positive(&format!("walls[{i}].frequency"), frequency)?;
        let phase = self.phase.unwrap_or(0.0);
        if !phase.is_finite() {
            return invalid!("walls[{i}].phase = {phase} must be finite (in rad)");
        }
        Ok(Some(Vibration {
            amplitude,
            frequency,
            phase,
        }))
    }
}

/// Refuses a vibrated wall that moves along a periodic axis of `sim_box` (its periodic
/// images would sweep through the box), or whose plane leaves the box by half the
/// `smallest` radius or more over its stroke (spheres on it would leave the box).
pub(crate) fn vibrated_walls_fit(
    walls: &[Wall],
    sim_box: Option<&SimBox>,
    smallest: f64,
) -> Result<()> {
    let Some(b) = sim_box else { return Ok(()) };
    for (i, w) in walls.iter().enumerate() {
        let Some(vib) = w.vibration else { continue };
        if let Some(k) = (0..3).find(|&k| b.periodic[k] && w.normal[k].abs() > 1e-12) {
            return invalid!(
                "walls[{i}].amplitude: a vibrated wall moves along its normal {:?}, which has \
                 a component along the periodic {} axis; make that axis closed \
                 (box.periodic) or turn the wall",
                w.normal,
                ["x", "y", "z"][k]
            );
        }
        let a = vib.amplitude;
        let slack = if smallest.is_finite() {
            0.5 * smallest
        } else {
            0.0
        };
        let (lo, hi) = (b.lo, b.hi());
        let outside = (0..3).find(|&k| {
            let reach = a * w.normal[k].abs();
            reach > 0.0
                && (w.point[k] - reach < lo[k] - slack || w.point[k] + reach > hi[k] + slack)
        });
        if let Some(k) = outside {
            return invalid!(
                "walls[{i}].amplitude = {a:e} m takes the wall out of the box along {}: its \
                 plane (through {:?} at rest) must stay within half the smallest radius of \
                 the box faces {:e} and {:e}; move the wall inside by the amplitude, enlarge \
                 the box or lower the amplitude",
                ["x", "y", "z"][k],
                w.point,
                lo[k],
                hi[k]
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::Config;

    /// A ball of radius 0.01 at height `z` over a floor at 0.02 vibrating with
    /// amplitude 5 mm and phase `phase`.
    fn ball(z: f64, phase: f64) -> crate::Result<crate::System> {
        Config::from_toml(&format!(
            "t_end = 0.1\n[material]\nmodel = \"linear\"\nstiffness = 1e4\ndensity = 1000.0\n\
             [box]\nsize = [1.0, 1.0, 1.0]\nperiodic = [true, true, false]\n\
             [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.5, 0.5, 0.02]\n\
             amplitude = 5e-3\nfrequency = 10.0\nphase = {phase:e}\n\
             [[walls]]\nnormal = [0.0, 0.0, -1.0]\npoint = [0.5, 0.5, 1.0]\n\
             [[particles]]\nradius = 0.01\nposition = [0.5, 0.5, {z:e}]\n"
        ))?
        .build()
    }

    #[test]
    fn a_particle_must_start_in_front_of_the_wall_where_it_is_at_t_0() {
        // 3 mm above contact with the plane at rest: in front of it at phase 0, behind
        // it at phase π/2 (the wall 5 mm up).
        ball(0.033, 0.0).unwrap();
        let err = ball(0.033, std::f64::consts::FRAC_PI_2)
            .unwrap_err()
            .to_string();
        assert!(err.contains("behind wall 0"), "{err}");
    }

    #[test]
    fn the_wall_s_motion_follows_its_keys() {
        let s = ball(0.5, 0.3).unwrap();
        let w = s.domain.walls[0];
        let v = w.vibration.unwrap();
        let omega = 2.0 * std::f64::consts::PI * 10.0;
        let t = 0.0123;
        let s_t = 5e-3 * (omega * t + 0.3).sin();
        assert!((w.point_at(t)[2] - (0.02 + s_t)).abs() < 1e-15);
        assert!((w.velocity_at(t)[2] - 5e-3 * omega * (omega * t + 0.3).cos()).abs() < 1e-15);
        assert!((v.max_acceleration() - 5e-3 * omega * omega).abs() < 1e-12);
        assert!((w.distance_at([0.5, 0.5, 0.5], t) - (0.48 - s_t)).abs() < 1e-15);
    }
}
