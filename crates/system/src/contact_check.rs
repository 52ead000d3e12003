//! The check every engine relies on before it starts: the approaches a run can
//! plausibly see keep every derived quantity finite (energies, contact times and
//! lengths) and compress no contact so deeply that the centres pass through each
//! other.
//!
//! The approach speed is an estimate of a typical impact, not a bound: for two
//! spheres the rms relative speed of the particles, √(2⟨|v − ⟨v⟩|²⟩), plus the speed
//! gained by falling (one sphere falling onto another at rest); against a wall the
//! rms speed √⟨|v|²⟩ plus the fall (plus A ω of a vibrated wall). A particle falls at most for `t_end` and at most
//! across the region it moves in (the diagonal of the box or of the particles'
//! bounding box, or its height above a wall). Impacts much faster than these are
//! rare in a gas; a bound such as twice the fastest speed refuses sound runs (a
//! contracting cloud whose neighbours approach slowly). The extreme approach, twice
//! the fastest speed plus twice the fall, must still keep the kinetic energy finite.
//!
//! The maximal compression of a central impact at normal speed v follows from the
//! law's scales (Müller & Pöschel 2013, Eqs. 41 and 53): ξ_max = ξ̃·vT, with ξ̃ = 1
//! for the linear spring (T = 1/ω) and ξ̃ = (5/4)^{2/5} for Hertz's law
//! (T = κ^{−2/5} v^{−1/5}, from energy conservation, Eq. 54); dissipation only lowers
//! it. The centres meet at ξ = R₁ + R₂ (R at a wall).

use crate::error::{Result, invalid};
use crate::interactions::Interaction;
use crate::system::System;
use emdstar_contact::vec3::{dot, norm, norm2, sub};
use emdstar_contact::{Impact, PairLaw, Tangential};

/// The typical approaches of a run to `t_end` (module docs): of two spheres and of a
/// sphere and a wall, in m/s, with what makes them up for messages.
struct Approach {
    pair: f64,
    wall: f64,
    /// Twice the fastest speed plus twice the fall.
    extreme: f64,
    relative_rms: f64,
    rms: f64,
    fastest: f64,
    fall: f64,
    /// The fastest vibrated wall's speed A ω.
    wall_speed: f64,
}

impl Approach {
    fn of(system: &System, t_end: f64) -> Self {
        let p = &system.particles;
        let n = p.velocity.len().max(1) as f64;
        let fastest = p.velocity.iter().map(|v| norm(*v)).fold(0.0, f64::max);
        let mean: [f64; 3] =
            std::array::from_fn(|k| p.velocity.iter().map(|v| v[k]).sum::<f64>() / n);
        let square = |c: [f64; 3]| p.velocity.iter().map(|v| norm2(sub(*v, c))).sum::<f64>() / n;
        let relative_rms = (2.0 * square(mean)).sqrt();
        let rms = square([0.0; 3]).sqrt();
        let [gx, gy, gz] = system.domain.gravity;
        let g = gx.hypot(gy).hypot(gz);
        let (_, extent, _) = system.search_region();
        let mut height = norm(extent);
        for w in &system.domain.walls {
            for x in &p.position {
                height = height.max(dot(sub(*x, w.point), w.normal));
            }
        }
        let fall = if g > 0.0 {
            (g * t_end).min((2.0 * g * height).sqrt())
        } else {
            0.0
        };
        // A vibrated wall meets the spheres at up to its own speed A ω more.
        let wall_speed = system
            .domain
            .walls
            .iter()
            .filter_map(|w| w.vibration.map(|v| v.amplitude * v.omega()))
            .fold(0.0, f64::max);
        Self {
            pair: relative_rms + fall,
            wall: rms + fall + wall_speed,
            extreme: 2.0 * (fastest + fall) + wall_speed,
            relative_rms,
            rms,
            fastest,
            fall,
            wall_speed,
        }
    }

    fn describe(&self, wall: bool) -> String {
        let fall = if self.fall > 0.0 {
            format!(" plus {:.3e} m/s gained by falling", self.fall)
        } else {
            String::new()
        };
        match wall {
            true if self.wall_speed > 0.0 => format!(
                "the particles' rms speed {:.3e} m/s{fall} plus the vibrated walls' speed \
                 {:.3e} m/s",
                self.rms, self.wall_speed
            ),
            true => format!("the particles' rms speed {:.3e} m/s{fall}", self.rms),
            false => format!(
                "the particles' rms relative speed {:.3e} m/s{fall}",
                self.relative_rms
            ),
        }
    }
}

/// The key of the law's elastic constant.
fn name_of(law: &PairLaw) -> &'static str {
    match law {
        PairLaw::Linear { .. } => "stiffness",
        PairLaw::Hertz { .. } => "young",
    }
}

/// Maximal compression of an elastic central impact in units of vT (module docs).
fn scaled_compression(law: &PairLaw) -> f64 {
    match law {
        PairLaw::Linear { .. } => 1.0,
        PairLaw::Hertz { .. } => 1.25f64.powf(0.4),
    }
}

impl System {
    /// Refuses a system whose extreme approach up to `t_end` overflows the kinetic
    /// energy, or whose typical approach (module docs) overflows a contact's scales or
    /// compresses a contact until the centres meet; the message names the key to
    /// change.
    pub fn check_contacts(&self, t_end: f64) -> Result<()> {
        let approach = Approach::of(self, t_end);
        let gravity = self.domain.gravity;
        let m_max = self.species.iter().map(|s| s.mass).fold(0.0, f64::max);
        let v = approach.extreme;
        if !(v.is_finite() && (0.5 * m_max * v * v).is_finite()) {
            if approach.fall > 0.0 {
                return invalid!(
                    "gravity = {gravity:?} m/s² is too large: a particle falling in it \
                     reaches {:.3e} m/s, whose kinetic energy overflows double precision; give \
                     it a physical size",
                    approach.fall
                );
            }
            return invalid!(
                "the particles are too fast: two meeting head on at twice the fastest \
                 speed, {:.3e} m/s, have a kinetic energy that overflows double precision; \
                 give speeds of a physical size",
                2.0 * approach.fastest
            );
        }
        let interactions = self.interactions();
        let n = self.species.len();
        for a in 0..n {
            for b in a..n {
                let i = interactions.pair(a as u32, b as u32);
                let (ra, rb) = (self.species[a].radius, self.species[b].radius);
                let what = if ra == rb {
                    format!("two spheres of radius {ra:e} m")
                } else {
                    format!("spheres of radius {ra:e} m and {rb:e} m")
                };
                self.check_contact(i, &what, approach.pair, &approach.describe(false))?;
            }
            for w in 0..self.domain.walls.len() {
                let i = interactions.wall(a as u32, w);
                let what = format!(
                    "a sphere of radius {:e} m and walls[{w}]",
                    self.species[a].radius
                );
                self.check_contact(i, &what, approach.wall, &approach.describe(true))?;
            }
        }
        Ok(())
    }

    /// One kind of contact at normal speed `v` (`why`: how `v` was estimated).
    fn check_contact(&self, i: &Interaction, what: &str, v: f64, why: &str) -> Result<()> {
        if v == 0.0 {
            return Ok(());
        }
        let interactions = self.interactions();
        let [a, b] = i.materials;
        let name = name_of(i.law());
        let key = if a == b {
            format!("{}.{name}", interactions.material_key(a))
        } else {
            format!(
                "{}.{name} (with {}.{name})",
                interactions.material_key(a),
                interactions.material_key(b)
            )
        };
        let scaled = Impact::from_speed_eccentricity(v, 0.0)
            .and_then(|impact| emdstar_contact::scale(i.law(), &i.props, &impact));
        let scales = scaled.ok().filter(|s| {
            s.time.is_finite() && s.time > 0.0 && s.length.is_finite() && s.length > 0.0
        });
        let Some(scales) = scales else {
            return invalid!(
                "{key} gives {what} ({}) a contact whose time or length scale at the impact \
                 speed {v:.3e} m/s ({why}) is not a finite number greater than zero in double \
                 precision; give it a physical size",
                interactions.describe(i)
            );
        };
        // The tangential spring's and dashpot's rates over the contact's time scale.
        if let Tangential::History(h) = i.tangential() {
            let m = i.props.m_eff;
            for (name, rate) in [
                (
                    "tangential_stiffness",
                    h.stiffness / m * scales.time * scales.time,
                ),
                ("tangential_damping", h.damping / m * scales.time),
            ] {
                if !rate.is_finite() {
                    let key = key.replace(&format!(".{}", name_of(i.law())), &format!(".{name}"));
                    return invalid!(
                        "{key} is out of range: over the time scale {:.3e} s of the contact of \
                         {what} ({}) it gives a rate that double precision cannot hold; give \
                         it a physical size",
                        scales.time,
                        interactions.describe(i)
                    );
                }
            }
        }
        let compression = scaled_compression(i.law()) * scales.length;
        let contact = i.props.l;
        if compression < contact {
            return Ok(());
        }
        // ξ_max ∝ k^{-1/2} (linear), ∝ Y^{-2/5} (Hertz).
        let factor = match i.law() {
            PairLaw::Linear { .. } => (compression / contact).powi(2),
            PairLaw::Hertz { .. } => (compression / contact).powf(2.5),
        };
        invalid!(
            "{key} is too soft for the speeds of this run: {what} ({}) meeting at \
             {v:.3e} m/s ({why}) would be compressed by {compression:.3e} m, more than \
             their contact distance {contact:.3e} m, so that their centres pass through \
             each other; raise it by a factor of at least {factor:.3e} or lower the speeds",
            interactions.describe(i)
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::Config;

    /// Two linear spheres at ±v: rms relative speed √2·v, ξ_max = √2·v·√(m_eff/k)
    /// (the undamped spring, Müller & Pöschel 2013, Eq. 41). The stiffness that puts
    /// ξ_max at the contact distance 2R is the bar, within a percent either side.
    #[test]
    fn the_stiffness_at_which_typical_impacts_reach_the_centres_is_the_bar() {
        let (r, rho, v) = (0.01f64, 1000.0, 1.0);
        let m = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3) * rho;
        let k_bar = 2.0 * v * v * (m / 2.0) / (2.0 * r).powi(2);
        let build = |k: f64| {
            Config::from_toml(&format!(
                "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = {k:e}\n\
                 density = {rho}\n[[particles]]\nradius = {r}\nposition = [0.0, 0.0, 0.0]\n\
                 velocity = [{v}, 0.0, 0.0]\n[[particles]]\nradius = {r}\n\
                 position = [0.03, 0.0, 0.0]\nvelocity = [-{v}, 0.0, 0.0]\n"
            ))
            .unwrap()
            .build()
            .map(|_| ())
            .map_err(|e| e.to_string())
        };
        let err = build(0.99 * k_bar).unwrap_err();
        assert!(
            err.contains("line 4: material.stiffness") && err.contains("pass through"),
            "{err}"
        );
        build(1.01 * k_bar).unwrap();
        // At rest and without gravity nothing collides: any stiffness goes.
        let still = Config::from_toml(
            "t_end = 1.0\n[material]\nmodel = \"linear\"\nstiffness = 1e-9\ndensity = 1.0\n\
             [[particles]]\nradius = 0.1\nposition = [0.0, 0.0, 0.0]\n",
        )
        .unwrap();
        still.build().unwrap();
    }
}
