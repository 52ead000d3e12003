//! A ball on a vibrated plate: the period-1 orbit of the bouncing ball against its
//! analytic impact phase and apex height, through any engine.
//!
//! The period-1 orbit (e.g. Luck & Mehta, Phys. Rev. E 48, 3988 (1993)): the ball meets
//! the plate s(t) = A sin(ωt + φ) once per period T = 2π/ω at the same plate phase ψ, so
//! at the same height: it leaves upwards at gT/2 relative to the ground and comes back
//! at −gT/2. Restitution e relative to the plate velocity u = Aω cos ψ gives
//! gT/2 − u = e (gT/2 + u), so u = (1 − e) gT / (2(1 + e)) and
//! cos ψ = π (1 − e) / (Γ (1 + e)) with Γ = Aω²/g. The branch sin ψ > 0 (the plate
//! decelerating at impact) is the stable one for π(1 − e)/(1 + e) < Γ below the period
//! doubling; Γ = 1.3, e = 0.5 lies inside. The apex comes T/2 after the impact (plate
//! phase ψ + π), g T²/8 above it.

use crate::plot::{Axis, PALETTE, Panel, Series, Style, write_png};
use crate::theory::build;
use crate::{HarnessError, Result};
use emdstar_engines::EngineKind;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;

/// The plate, the ball and its contacts; the ball starts at an apex `lift` times the
/// orbit's flight height above its takeoff, at the plate phase of the orbit's apex.
#[derive(Debug, Clone, Serialize)]
pub struct OrbitSettings {
    pub gravity: f64,
    pub frequency: f64,
    /// Γ = Aω²/g.
    pub gamma: f64,
    pub restitution: f64,
    pub radius: f64,
    /// The duration of a linear contact with the plate (sets the stiffness).
    pub contact_time: f64,
    /// MD's step.
    pub md_dt: f64,
    pub lift: f64,
    /// The apexes between these times are compared with the orbit's.
    pub from: f64,
    pub to: f64,
}

impl Default for OrbitSettings {
    fn default() -> Self {
        Self {
            gravity: 9.81,
            frequency: 10.0,
            gamma: 1.3,
            restitution: 0.5,
            radius: 0.002,
            contact_time: 1e-4,
            md_dt: 2e-6,
            lift: 1.2,
            from: 1.2,
            to: 1.6,
        }
    }
}

/// The plate's plane at rest.
const FLOOR: f64 = 0.01;

impl OrbitSettings {
    pub fn omega(&self) -> f64 {
        2.0 * PI * self.frequency
    }

    pub fn amplitude(&self) -> f64 {
        self.gamma * self.gravity / (self.omega() * self.omega())
    }

    /// ψ of the stable period-1 orbit (NaN where there is none).
    pub fn impact_phase(&self) -> f64 {
        let e = self.restitution;
        (PI * (1.0 - e) / (self.gamma * (1.0 + e))).acos()
    }

    /// The flight height g T²/8 above the takeoff.
    pub fn flight_height(&self) -> f64 {
        self.gravity / (8.0 * self.frequency * self.frequency)
    }

    /// The height of the ball's centre at the orbit's apex.
    pub fn apex_height(&self) -> f64 {
        FLOOR + self.amplitude() * self.impact_phase().sin() + self.radius + self.flight_height()
    }

    /// The config of the ball on the plate for `kind` (MD's step where it runs MD).
    pub fn config(&self, kind: EngineKind) -> String {
        let r = self.radius;
        let mass = 4.0 / 3.0 * PI * r.powi(3) * 2500.0;
        let k = mass * PI * PI / (self.contact_time * self.contact_time);
        // Without a period-1 orbit (Γ below π(1 − e)/(1 + e)): from the plate's top.
        let psi = self.impact_phase();
        let (takeoff, phase) = match psi.is_finite() {
            true => (FLOOR + self.amplitude() * psi.sin() + r, psi + PI),
            false => (FLOOR + self.amplitude() + r, 0.0),
        };
        let z0 = takeoff + self.lift * self.flight_height();
        let md = match kind {
            EngineKind::Md => format!("[md]\ndt = {:e}\n", self.md_dt),
            _ => String::new(),
        };
        let e = self.restitution;
        format!(
            "t_end = {t_end:e}\ngravity = [0.0, 0.0, {g:e}]\n\
             [[materials]]\nname = \"ball\"\nmodel = \"linear\"\nstiffness = {k:e}\n\
             restitution = {e}\ndensity = 2500.0\n\
             [[materials]]\nname = \"plate\"\nmodel = \"linear\"\nstiffness = {k:e}\n\
             [[interactions]]\nmaterials = [\"ball\", \"plate\"]\nrestitution = {e}\n\
             [box]\nsize = [0.1, 0.1, 0.2]\nperiodic = [true, true, false]\n\
             [[walls]]\nnormal = [0.0, 0.0, 1.0]\npoint = [0.05, 0.05, {FLOOR}]\n\
             material = \"plate\"\namplitude = {a:e}\nfrequency = {f:e}\nphase = {phase:e}\n\
             [[walls]]\nnormal = [0.0, 0.0, -1.0]\npoint = [0.05, 0.05, 0.2]\n\
             material = \"plate\"\n\
             [[particles]]\nradius = {r:e}\nposition = [0.05, 0.05, {z0:e}]\n\
             material = \"ball\"\n{md}",
            t_end = self.to,
            g = -self.gravity,
            a = self.amplitude(),
            f = self.frequency,
        )
    }
}

/// One apex: its time, and how far it lies from the orbit's, in plate phase (rad,
/// signed, in (−π, π]) and in height (relative to the flight height, signed).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Apex {
    pub t: f64,
    pub phase_error: f64,
    pub height_error: f64,
}

/// The apexes of one engine's run and their largest deviations over [from, to].
#[derive(Debug, Clone, Serialize)]
pub struct OrbitRun {
    pub engine: String,
    pub apexes: Vec<Apex>,
    pub phase_error: f64,
    pub height_error: f64,
    /// Apexes within [from, to].
    pub compared: usize,
}

/// The ball on the plate through `kind` up to `settings.to`: every apex, each from the
/// first sample after it (every tenth of a period; in free flight, T/2 before the next
/// impact), exactly.
pub fn orbit(settings: &OrbitSettings, kind: EngineKind) -> Result<OrbitRun> {
    let mut engine = build(&settings.config(kind), kind)?;
    let sim = engine.sim_mut();
    let g = settings.gravity;
    let step = 0.1 / settings.frequency;
    let (mut apexes, mut rising, mut k) = (Vec::new(), false, 0u32);
    loop {
        k += 1;
        let t = f64::from(k) * step;
        if t > settings.to {
            break;
        }
        sim.advance_to(t)
            .map_err(|e| HarnessError::Invalid(format!("{kind:?}: {e}")))?;
        let p = sim.particles();
        let (z, vz) = (p.position[0][2], p.velocity[0][2]);
        if rising && vz <= 0.0 {
            let t_apex = sim.time() + vz / g;
            let off = (settings.omega() * t_apex).rem_euclid(2.0 * PI);
            apexes.push(Apex {
                t: t_apex,
                phase_error: if off > PI { off - 2.0 * PI } else { off },
                height_error: (z + vz * vz / (2.0 * g) - settings.apex_height())
                    / settings.flight_height(),
            });
        }
        rising = vz > 0.0;
    }
    let window: Vec<&Apex> = apexes
        .iter()
        .filter(|a| a.t >= settings.from && a.t <= settings.to)
        .collect();
    let worst = |f: fn(&Apex) -> f64| window.iter().map(|a| f(a).abs()).fold(0.0, f64::max);
    Ok(OrbitRun {
        engine: kind.name().to_string(),
        phase_error: worst(|a| a.phase_error),
        height_error: worst(|a| a.height_error),
        compared: window.len(),
        apexes,
    })
}

/// |phase error| of every apex against time, one series per run (log scale).
pub fn plot(
    runs: &[&OrbitRun],
    settings: &OrbitSettings,
    path: &Path,
) -> std::result::Result<(), String> {
    let mut p = Panel::new(
        format!(
            "Ball on a vibrated plate (Γ = {}, e = {}, f = {} Hz): apex phase against the period-1 orbit",
            settings.gamma, settings.restitution, settings.frequency
        ),
        Axis::linear("t [s]"),
        Axis::log("|plate phase at the apex − (ψ + π)| [rad]"),
    );
    for (k, r) in runs.iter().enumerate() {
        let points = r
            .apexes
            .iter()
            .map(|a| (a.t, a.phase_error.abs().max(1e-9)))
            .collect();
        p.series.push(Series::new(
            format!(
                "{}: {:.1e} rad, height {:.1e} of gT²/8 over {}–{} s",
                r.engine, r.phase_error, r.height_error, settings.from, settings.to
            ),
            points,
            PALETTE[1 + k],
            Style::LinePoints(3),
        ));
    }
    write_png(path, (900, 600), 1, 1, &[p])
}
