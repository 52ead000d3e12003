//! `[driving]`: energy fed to a gas at regular ticks, so that it reaches a steady
//! state.
//!
//! - **White noise** (Williams & MacKintosh, Phys. Rev. E 54, R9 (1996); van Noije &
//!   Ernst, Granular Matter 1, 57 (1998)): a random force on every particle,
//!   ⟨F_ik(t) F_jl(t')⟩ = m² ξ₀² δ_ij δ_kl δ(t − t'), applied as the event-driven codes
//!   do, as random kicks at a fixed rate f: every velocity component takes Δv drawn
//!   from N(0, ξ₀²/f). The mass-weighted mean kick is then taken off, so a tick
//!   changes no momentum (zero in a periodic box, the theory's frame; under gravity
//!   and walls the centre of mass moves as without the kicks); the power fed is
//!   (3/2) m ξ₀² (1 − 1/N) per particle of equal masses.
//! - **Andersen** (Andersen, J. Chem. Phys. 72, 2384 (1980)), for elastic reference
//!   runs: at every tick every particle takes a velocity drawn from the Maxwell
//!   distribution at temperature T (components N(0, T/m)); the mass-weighted mean is
//!   taken off (the mean temperature is then T(1 − 1/N)).
//!
//! Tick k ≥ 1 falls at t = k/f. Its random numbers come from the ChaCha8 stream k of
//! the seed, drawn in particle order: a tick depends on the seed, its number and the
//! velocities only, so runs are the same whatever the thread count, and a run resumed
//! from a checkpoint (its time gives the ticks done) draws what the run that went
//! through drew.

use crate::error::{Result, SystemError};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// `[driving]` as written.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct DrivingConfig {
    /// "white_noise" or "andersen".
    pub kind: String,
    /// White noise: ξ₀² in m²/s³, the variance per second of each velocity component.
    pub strength: Option<f64>,
    /// Andersen: the temperature kT in J.
    pub temperature: Option<f64>,
    /// Ticks per second.
    pub rate: f64,
    /// Seed of the random kicks.
    #[serde(default)]
    pub seed: u64,
}

/// What a tick does.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum DriveKind {
    /// Kicks of variance ξ₀²/f per component (`strength` = ξ₀² in m²/s³).
    WhiteNoise { strength: f64 },
    /// New Maxwell velocities at `temperature` (J).
    Andersen { temperature: f64 },
}

/// A checked `[driving]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Drive {
    pub kind: DriveKind,
    /// Ticks per second.
    pub rate: f64,
    pub seed: u64,
}

fn bad(why: String) -> SystemError {
    SystemError::Invalid(why)
}

fn positive(key: &str, value: Option<f64>, kind: &str) -> Result<f64> {
    match value {
        Some(v) if v.is_finite() && v > 0.0 => Ok(v),
        Some(v) => Err(bad(format!(
            "driving.{key} = {v}: must be finite and positive"
        ))),
        None => Err(bad(format!(
            "driving.{key} is required with kind = \"{kind}\""
        ))),
    }
}

impl DrivingConfig {
    /// The drive, or an error naming the key that is wrong.
    pub fn drive(&self) -> Result<Drive> {
        let rate = positive("rate", Some(self.rate), &self.kind)?;
        let refuse = |key: &str, other: &str| {
            Err(bad(format!(
                "driving.{key} does not belong to kind = \"{}\" (it takes {other})",
                self.kind
            )))
        };
        let kind = match self.kind.as_str() {
            "white_noise" => {
                if self.temperature.is_some() {
                    return refuse("temperature", "strength");
                }
                DriveKind::WhiteNoise {
                    strength: positive("strength", self.strength, &self.kind)?,
                }
            }
            "andersen" => {
                if self.strength.is_some() {
                    return refuse("strength", "temperature");
                }
                DriveKind::Andersen {
                    temperature: positive("temperature", self.temperature, &self.kind)?,
                }
            }
            other => {
                return Err(bad(format!(
                    "driving.kind = \"{other}\": use \"white_noise\" or \"andersen\""
                )));
            }
        };
        Ok(Drive {
            kind,
            rate,
            seed: self.seed,
        })
    }
}

impl Drive {
    /// The time of tick `k`.
    pub fn tick_time(&self, k: u64) -> f64 {
        k as f64 / self.rate
    }

    /// How many ticks fall at or before `t` (ticks 1, 2, …).
    pub fn ticks_until(&self, t: f64) -> u64 {
        if t.is_nan() || t <= 0.0 {
            return 0;
        }
        let mut k = (t * self.rate).floor() as u64;
        while self.tick_time(k + 1) <= t {
            k += 1;
        }
        while k > 0 && self.tick_time(k) > t {
            k -= 1;
        }
        k
    }

    /// Tick `k` on the velocities `v` of particles of `mass` (in config order).
    pub fn apply(&self, k: u64, v: &mut [[f64; 3]], mass: &[f64]) {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(k);
        let mut gauss = || {
            let u1: f64 = 1.0 - rng.random::<f64>(); // in (0, 1]
            let u2: f64 = rng.random();
            (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
        };
        // The mass-weighted mean of what the tick changed is taken off, so that the tick
        // changes no momentum: the kicks' mean for white noise (gravity and walls keep
        // acting on the centre of mass), the new velocities' mean for Andersen.
        let total: f64 = mass.iter().sum();
        let mut mean = [0.0; 3];
        for (w, &m) in v.iter_mut().zip(mass) {
            match self.kind {
                DriveKind::WhiteNoise { strength } => {
                    let s = (strength / self.rate).sqrt();
                    for (c, mc) in w.iter_mut().zip(&mut mean) {
                        let kick = s * gauss();
                        *c += kick;
                        *mc += m * kick / total;
                    }
                }
                DriveKind::Andersen { temperature } => {
                    let s = (temperature / m).sqrt();
                    for (c, mc) in w.iter_mut().zip(&mut mean) {
                        *c = s * gauss();
                        *mc += m * *c / total;
                    }
                }
            }
        }
        for w in v.iter_mut() {
            for c in 0..3 {
                w[c] -= mean[c];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config(kind: &str) -> DrivingConfig {
        DrivingConfig {
            kind: kind.into(),
            rate: 100.0,
            ..Default::default()
        }
    }

    #[test]
    fn bad_keys_are_named() {
        let err = |c: DrivingConfig| c.drive().unwrap_err().to_string();
        assert!(err(config("white_noise")).contains("driving.strength is required"));
        assert!(err(config("andersen")).contains("driving.temperature is required"));
        assert!(err(config("shaker")).contains("driving.kind"));
        let mut c = config("white_noise");
        c.strength = Some(f64::NAN);
        assert!(err(c.clone()).contains("driving.strength = NaN"));
        c.strength = Some(1.0);
        c.rate = 0.0;
        assert!(err(c.clone()).contains("driving.rate = 0"));
        c.rate = 1.0;
        c.temperature = Some(1.0);
        assert!(err(c).contains("driving.temperature does not belong"));
    }

    #[test]
    fn ticks_are_counted_exactly() {
        let d = Drive {
            kind: DriveKind::WhiteNoise { strength: 1.0 },
            rate: 3.0,
            seed: 0,
        };
        assert_eq!(d.ticks_until(0.0), 0);
        assert_eq!(d.ticks_until(d.tick_time(7)), 7);
        assert_eq!(d.ticks_until(d.tick_time(7) * (1.0 - 1e-15)), 6);
        assert_eq!(d.ticks_until(-1.0), 0);
    }

    #[test]
    fn kicks_keep_momentum_zero_and_have_the_variance_of_the_noise() {
        let n = 20_000;
        let d = Drive {
            kind: DriveKind::WhiteNoise { strength: 2.0 },
            rate: 4.0,
            seed: 9,
        };
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
        let mut v = vec![[0.0; 3]; n];
        d.apply(5, &mut v, &mass);
        let p: f64 = (0..3)
            .map(|c| {
                v.iter()
                    .zip(&mass)
                    .map(|(w, m)| m * w[c])
                    .sum::<f64>()
                    .abs()
            })
            .sum();
        assert!(p < 1e-9, "momentum {p}");
        // Variance ξ₀²/f = 0.5 per component, to its sampling error (√(2/3n) ≈ 0.6 %).
        let var = v.iter().flatten().map(|x| x * x).sum::<f64>() / (3 * n) as f64;
        assert!((var / 0.5 - 1.0).abs() < 0.03, "variance {var}");
        // The same tick draws the same numbers; another tick others.
        let mut again = vec![[0.0; 3]; n];
        d.apply(5, &mut again, &mass);
        assert_eq!(v, again);
        d.apply(6, &mut again, &mass);
        assert_ne!(v, again);
    }

    #[test]
    fn a_white_noise_tick_leaves_the_momentum_a_falling_gas_has_gained() {
        // Under gravity the centre of mass falls: a tick must not take that momentum off
        // (it would cancel gravity at every tick), only the kicks' own mean.
        let n = 1000;
        let d = Drive {
            kind: DriveKind::WhiteNoise { strength: 2.0 },
            rate: 4.0,
            seed: 3,
        };
        let mass: Vec<f64> = (0..n).map(|i| 1.0 + (i % 2) as f64).collect();
        let mut v: Vec<[f64; 3]> = (0..n).map(|i| [0.1 * (i % 5) as f64, 0.0, -2.0]).collect();
        let momentum = |v: &[[f64; 3]]| -> [f64; 3] {
            std::array::from_fn(|c| v.iter().zip(&mass).map(|(w, m)| m * w[c]).sum())
        };
        let before = momentum(&v);
        d.apply(1, &mut v, &mass);
        let after = momentum(&v);
        for c in 0..3 {
            assert!(
                (after[c] - before[c]).abs() < 1e-9 * n as f64,
                "{before:?} → {after:?}"
            );
        }
        assert!(before[2] < -2000.0);
    }

    #[test]
    fn andersen_draws_maxwell_velocities_at_its_temperature() {
        let n = 20_000;
        let d = Drive {
            kind: DriveKind::Andersen { temperature: 3.0 },
            rate: 1.0,
            seed: 1,
        };
        let mass = vec![2.0; n];
        let mut v = vec![[5.0, 0.0, 0.0]; n];
        d.apply(1, &mut v, &mass);
        // ⟨m v_c²⟩ = T (1 − 1/N).
        let t = v.iter().flatten().map(|x| 2.0 * x * x).sum::<f64>() / (3 * n) as f64;
        assert!((t / 3.0 - 1.0).abs() < 0.03, "T = {t}");
    }
}
