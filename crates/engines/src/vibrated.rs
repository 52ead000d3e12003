//! What eMD* makes of a vibrated wall: it runs each contact in the frame the wall moves
//! in at the impact, its velocity taken as constant over the contact. The wall's
//! velocity changes by up to A ω² t_c meanwhile, a fraction ω t_c of its speed scale
//! A ω; a warning says so where that fraction is not small.

use crate::options::EngineKind;
use emdstar_system::{Config, System};

/// ω t_c above which eMD*'s constant wall velocity over a contact gets a warning.
pub const VIBRATED_CONTACT_LIMIT: f64 = 0.05;

/// One line for each vibrated wall of `system` (built from `config`) whose contacts
/// last longer than [`VIBRATED_CONTACT_LIMIT`] / ω where `engine` runs eMD* (emdstar,
/// the hybrid's events): the key with its line, ω t_c and what to change.
pub fn vibrated_wall_warnings(config: &Config, system: &System, engine: EngineKind) -> Vec<String> {
    // The hybrid's events are eMD*'s (by default).
    if !matches!(engine, EngineKind::EmdStar | EngineKind::Hybrid) {
        return Vec::new();
    }
    let interactions = system.interactions();
    let mut out = Vec::new();
    for (w, wall) in system.domain.walls.iter().enumerate() {
        let Some(vib) = wall.vibration else { continue };
        let omega = vib.omega();
        let speed = vib.amplitude * omega;
        // The longest contact of any species with the wall at the wall's speed scale.
        let t_c = (0..system.species.len() as u32)
            .filter_map(|s| {
                let i = interactions.wall(s, w);
                i.law().elastic_duration(i.props.m_eff, speed).ok()
            })
            .fold(0.0, f64::max);
        let ratio = omega * t_c;
        if ratio > VIBRATED_CONTACT_LIMIT {
            let key = format!("walls[{w}].frequency");
            let line = config
                .keys
                .line(&key)
                .map_or(String::new(), |l| format!("line {l}: "));
            out.push(format!(
                "{line}{key}: eMD* takes the wall's velocity as constant over a contact, \
                 but a contact of {t_c:.3e} s spans ω·t_c = {ratio:.3} rad of the wall's phase \
                 (its velocity changes by up to A·ω²·t_c = {:.3e} m/s against a speed of \
                 A·ω = {speed:.3e} m/s); stiffer contacts or --engine md resolve the wall's \
                 motion within a contact",
                speed * ratio
            ));
        }
    }
    out
}
