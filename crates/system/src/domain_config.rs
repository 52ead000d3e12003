//! `[box]` and `[[walls]]`: the keys that give the domain, and their checks.

use crate::error::{Result, finite3, invalid, num, positive};
use crate::geometry::{SimBox, Wall};
use serde::{Deserialize, Serialize};

/// `[box]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoxConfig {
    pub size: [f64; 3],
    #[serde(default)]
    pub lo: [f64; 3],
    #[serde(default = "all_periodic")]
    pub periodic: [bool; 3],
    /// Lees–Edwards shear rate γ̇ in 1/s: flow along x, gradient along y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shear_rate: Option<f64>,
}

fn all_periodic() -> [bool; 3] {
    [true; 3]
}

/// One `[[walls]]` entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct WallConfig {
    pub normal: [f64; 3],
    pub point: [f64; 3],
    /// The material's name (required with several materials).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    /// A vibrated wall: amplitude A in m, frequency f in Hz and phase φ in rad of its
    /// motion A sin(2π f t + φ) along the normal (amplitude and frequency together).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub phase: Option<f64>,
}

impl BoxConfig {
    /// `box.shear_rate`, checked: finite, x and y periodic (flow and gradient), no
    /// gravity along them (0 where not given).
    pub(crate) fn shear_rate(&self, gravity: [f64; 3]) -> Result<f64> {
        let b = self;
        let Some(rate) = b.shear_rate else {
            return Ok(0.0);
        };
        if !rate.is_finite() {
            return invalid!(
                "box.shear_rate = {} must be a finite number (1/s)",
                num(rate)
            );
        }
        if rate != 0.0 {
            if !(b.periodic[0] && b.periodic[1]) {
                return invalid!(
                    "box.shear_rate = {rate} needs Lees–Edwards boundaries, periodic along x \
                     (the flow) and y (the gradient), but box.periodic = {:?}; make x and y \
                     periodic or drop the shear rate",
                    b.periodic
                );
            }
            if gravity[0] != 0.0 || gravity[1] != 0.0 {
                return invalid!(
                    "box.shear_rate = {rate} with gravity {gravity:?}: gravity along the flow \
                     (x) or the gradient (y) breaks the homogeneous shear flow; give gravity \
                     along z only, or drop the shear rate"
                );
            }
        }
        Ok(rate)
    }
}

impl BoxConfig {
    pub(crate) fn sim_box(&self) -> Result<SimBox> {
        for k in 0..3 {
            positive(&format!("box.size[{k}]"), self.size[k])?;
        }
        let lo = finite3("box.lo", self.lo)?;
        for k in 0..3 {
            resolvable(k, lo[k], self.size[k])?;
        }
        Ok(SimBox {
            lo,
            size: self.size,
            periodic: self.periodic,
        })
    }
}

/// Positions across the box along axis `k` must be resolved: at least 2²⁴ doubles
/// between its faces (with fewer, cell faces and positions round together and a
/// particle could cross a face without moving).
fn resolvable(k: usize, lo: f64, size: f64) -> Result<()> {
    let far = lo.abs().max((lo + size).abs());
    // The gap to the next double up (NaN where `far` overflowed, which is refused too).
    let spacing = f64::from_bits(far.to_bits() + 1) - far;
    if size / spacing >= f64::from(1u32 << 24) {
        return Ok(());
    }
    invalid!(
        "box.lo[{k}] = {lo:e} is too far from the origin for box.size[{k}] = {size:e}: double \
         precision resolves positions there only to {spacing:.1e} m, fewer than 2^24 steps \
         across the box; move the box nearer the origin (or make it larger)"
    )
}

impl WallConfig {
    pub(crate) fn wall(&self, i: usize) -> Result<Wall> {
        let n = finite3(&format!("walls[{i}].normal"), self.normal)?;
        let point = finite3(&format!("walls[{i}].point"), self.point)?;
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len == 0.0 {
            return invalid!("walls[{i}].normal must not be the zero vector");
        }
        Ok(Wall {
            normal: n.map(|c| c / len),
            point,
            vibration: self.vibration(i)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use crate::Config;
    use crate::error::Result;

    fn build(lo: f64, size: f64) -> Result<crate::System> {
        Config::from_toml(&format!(
            "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 55.0\ndensity = 2500.0\n\
             [box]\nlo = [{lo:e}, 0.0, 0.0]\nsize = [{size:e}, 10.0, 10.0]\n\
             [[particles]]\nradius = 0.1\nposition = [{x:e}, 5.0, 5.0]\n",
            x = lo + 0.5 * size
        ))?
        .build()
    }

    #[test]
    fn a_box_too_far_from_the_origin_to_resolve_is_refused() {
        // Found by fuzzing: a box 4000 m wide at x = 2e164 m, where doubles are 3e148 m
        // apart. Its cell faces all rounded to one number and the hybrid's event part
        // crossed them at one instant for ever.
        let err = build(2.066e164, 4000.0).unwrap_err().to_string();
        assert!(
            err.contains("box.lo[0]") && err.contains("nearer the origin"),
            "{err}"
        );
        // 2^24 steps across the box is the bar: 1 m at 1e9 m (0.12 µm apart) is refused,
        // at 1e6 m (0.12 nm apart) it is not.
        assert!(build(1e9, 1.0).is_err());
        build(1e6, 1.0).unwrap();
    }
}
