//! Engine options, the time-step rule and the engine's errors.

use emdstar_system::{System, SystemError};

/// When a contact ends, and so whether the normal force may attract.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub enum ContactEnd {
    /// F = max(0, …): the contact ends when the force reaches zero, while the spheres
    /// may still overlap geometrically (Schwager & Pöschel, Granular Matter 9, 465,
    /// 2007; Müller & Pöschel 2013). The physics of this project.
    #[default]
    ForceZero,
    /// The force is not clipped and may attract; the contact ends when the overlap
    /// reaches zero. This is LAMMPS's `pair_style granular` without `limit_damping`;
    /// use it only to compare with peers. A damped force then jumps to zero at the end
    /// of the contact, which is not corrected: first order in dt there.
    OverlapZero,
}

impl std::str::FromStr for ContactEnd {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "force" => Ok(Self::ForceZero),
            "overlap" => Ok(Self::OverlapZero),
            other => Err(format!(
                "unknown contact_end '{other}': expected \"force\" (F = 0 ends a contact, the \
                 default) or \"overlap\" (ξ = 0 ends it, as LAMMPS without limit_damping)"
            )),
        }
    }
}

/// Options of the MD engine.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MdOptions {
    /// Time step in s; must not exceed [`MAX_DT_FRACTION`] × the shortest expected
    /// contact time.
    pub dt: f64,
    pub contact_end: ContactEnd,
    /// Verlet-list skin in m; `None` means [`default_skin`].
    pub skin: Option<f64>,
}

/// The default time step as a fraction of the shortest expected contact time, for gases.
pub const DEFAULT_DT_FRACTION: f64 = 1.0 / 50.0;
/// Coarser steps are refused.
pub const MAX_DT_FRACTION: f64 = 1.0 / 10.0;

/// Errors of the MD engine.
#[derive(Debug, thiserror::Error)]
pub enum MdError {
    #[error(transparent)]
    System(#[from] SystemError),
    #[error(transparent)]
    Contact(#[from] emdstar_contact::ContactError),
    #[error(
        "time step dt = {dt:e} s is too coarse: the shortest expected contact time is \
         {contact_time:e} s, and dt must not exceed 1/10 of it ({bound:e} s); the default is \
         1/50 of it"
    )]
    DtTooCoarse {
        dt: f64,
        contact_time: f64,
        bound: f64,
    },
    #[error("time step dt = {0} must be a finite number greater than zero")]
    BadDt(f64),
    #[error(
        "box.shear_rate = {0}: the hybrid engine does not run Lees–Edwards boundaries; use \
         --engine md, emd or emdstar"
    )]
    Sheared(f64),
    #[error("skin = {0} must be a finite number ≥ 0")]
    BadSkin(f64),
    #[error(
        "the box is too small for the cell list: along {axis} it is {length} m long, but a \
         periodic axis needs at least 3 cells of 2·R_max + skin = {cell} m; enlarge the box \
         or reduce the skin"
    )]
    BoxTooSmall {
        axis: &'static str,
        length: f64,
        cell: f64,
    },
    #[error(
        "skin = {skin:e} m is too thin: particles may move {step:e} m in one step, and the \
         skin must exceed twice that; raise the skin or lower dt"
    )]
    SkinTooThin { skin: f64, step: f64 },
    #[error(
        "particle {id} left the box along the closed axis {axis} at t = {t:e} s (position \
         {position:?}); add walls at the box faces or make the axis periodic"
    )]
    LeftBox {
        id: u32,
        axis: &'static str,
        t: f64,
        position: [f64; 3],
    },
    #[error(
        "particle {id} has a non-finite position or velocity at t = {t:e} s: the integration \
         blew up; reduce the time step"
    )]
    BlewUp { id: u32, t: f64 },
}

/// The shortest contact time to expect in `system` up to `t_end`: the central-impact
/// duration of every species pair and of every species against a wall, at the
/// reference normal speed v = 2·max|v_i| + |g|·t_end (the largest relative speed two
/// particles can reach; the Hertz duration falls as v^(−1/5), Müller & Pöschel 2013,
/// Eq. 55), or, against a vibrated wall, max|v_i| plus the wall's speed A ω where that
/// is more. Linear laws take the shorter of the elastic and the damped duration (Schwager &
/// Pöschel 2007), Hertz laws the elastic one. `None` when nothing can collide (at rest and without gravity).
pub fn shortest_contact_time(system: &System, t_end: f64) -> Result<Option<f64>, MdError> {
    let p = &system.particles;
    let v_max = p
        .velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .fold(0.0, f64::max);
    let g = system.domain.gravity;
    let mut v_ref = 2.0 * v_max + (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt() * t_end;
    // A vibrated wall meets a sphere at up to its own speed A ω more.
    for w in &system.domain.walls {
        if let Some(vib) = w.vibration {
            v_ref = v_ref.max(v_max + vib.amplitude * vib.omega());
        }
    }
    if v_ref.is_nan() || v_ref <= 0.0 {
        return Ok(None);
    }
    let interactions = system.interactions();
    // The wall contacts count only where there are walls.
    let walls = (!system.domain.walls.is_empty()).then(|| interactions.wall_contacts());
    let mut t_min = f64::INFINITY;
    for i in interactions
        .distinct_pairs()
        .chain(walls.into_iter().flatten())
    {
        let (law, props) = (*i.law(), i.props);
        let mut t = law.elastic_duration(props.m_eff, v_ref)?;
        if let emdstar_contact::PairLaw::Linear { stiffness, damping } = law {
            let damped = emdstar_contact::LinearDashpot::new(stiffness, damping)?;
            t = t.min(damped.central_impact(props.m_eff)?.duration);
        }
        t_min = t_min.min(t);
    }
    Ok(Some(t_min))
}

/// The checks every force-based engine makes before it starts: `system` is valid, the
/// step `dt` is positive and at most [`MAX_DT_FRACTION`] of the shortest contact time
/// expected up to `t_end`, and the Verlet skin (`None`: [`default_skin`]) is finite and
/// not negative. Wraps positions along periodic axes; returns the skin.
pub fn prepare_system(
    system: &mut System,
    dt: f64,
    skin: Option<f64>,
    t_end: f64,
) -> Result<f64, MdError> {
    system.validate()?;
    if !(dt.is_finite() && dt > 0.0) {
        return Err(MdError::BadDt(dt));
    }
    if let Some(tc) = shortest_contact_time(system, t_end)? {
        let bound = MAX_DT_FRACTION * tc;
        if dt > bound {
            return Err(MdError::DtTooCoarse {
                dt,
                contact_time: tc,
                bound,
            });
        }
    }
    let skin = skin.unwrap_or_else(|| default_skin(system));
    if !(skin.is_finite() && skin >= 0.0) {
        return Err(MdError::BadSkin(skin));
    }
    if let Some(b) = system.domain.sim_box {
        let p = &mut system.particles;
        for (x, image) in p.position.iter_mut().zip(&mut p.image) {
            *x = b.wrap_counting(*x, image);
        }
    }
    Ok(skin)
}

/// The default Verlet skin: the largest radius R in free space and in dilute boxes,
/// shrinking as R·½·(0.1/η)^{1/3} above the packing fraction η = 0.0125, so that the
/// lists stay short in denser gases (measured best on the benchmark gas: skin R at
/// η = 0.01, R/2 at η = 0.1).
pub fn default_skin(system: &System) -> f64 {
    let r_max = system.max_radius();
    let Some(b) = &system.domain.sim_box else {
        return r_max;
    };
    let p = &system.particles;
    let solid: f64 = p
        .radius
        .iter()
        .map(|r| 4.0 / 3.0 * std::f64::consts::PI * r.powi(3))
        .sum();
    let eta = solid / b.volume();
    if eta > 0.0 {
        r_max * (0.5 * (0.1 / eta).cbrt()).min(1.0)
    } else {
        r_max
    }
}
