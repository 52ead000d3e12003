//! The LAMMPS deck of a config: a data file (`atom_style sphere`) and an input script
//! that reproduce the system under `pair_style granular`, each LAMMPS atom type one
//! species (radius, mass, material) so that every per-pair constant is exact.
//!
//! The mapping of each contact law (docs/physics.md, "Materials and their pairs";
//! LAMMPS `pair_style granular`, its `PairGranular::compute` as of 29 Sep 2021):
//! - linear F = kξ + γξ̇: `hooke k γ damping velocity` (η_n = γ);
//! - Hertz F = ρ√ξ (ξ + (3/2) A ξ̇), ρ = (4/3) E* √R_eff: `hertz k_n η_n0 damping
//!   viscoelastic` with k_n = (4/3) E* (LAMMPS F_ne = k_n a ξ, a = √(R_eff ξ)) and
//!   η_n0 = 2 A E* / m_eff (LAMMPS F_damp = η_n0 a m_eff ξ̇), exact for the type pair's
//!   m_eff;
//! - the history spring (k_t, γ_t, µ): `tangential linear_history k_t x_γt µ` with
//!   x_γt = γ_t / η_n (LAMMPS damps the slip with x_γt times the normal damping
//!   prefactor), exact for the linear law; for Hertz the normal prefactor grows with
//!   the contact radius, so only γ_t = 0 maps exactly;
//! - frictionless: `tangential linear_nohistory 0 0`;
//! - F = max(0, …) (contact_end "force", the default): `limit_damping`.
//!
//! Coulomb sliding and Walton's rule have no `pair granular` counterpart: refused.

use emdstar_contact::{PairLaw, Tangential};
use emdstar_system::{Interaction, Particles, SimBox, System};
use std::fmt::Write;

/// The `pair granular` keywords of one contact (a pair of types or a type and a wall),
/// or why it has none.
pub fn granular_keywords(i: &Interaction, limit_damping: bool) -> Result<String, String> {
    let props = &i.props;
    let (normal, damping_prefactor) = match *i.law() {
        PairLaw::Linear { stiffness, damping } => (
            format!("hooke {stiffness:e} {damping:e} damping velocity"),
            Some(damping),
        ),
        PairLaw::Hertz {
            rho_el,
            dissipation,
        } => {
            let k_n = rho_el / props.r_eff.sqrt();
            let e_star = 0.75 * k_n;
            let eta_n0 = 2.0 * dissipation * e_star / props.m_eff;
            (
                format!("hertz {k_n:e} {eta_n0:e} damping viscoelastic"),
                // The normal damping prefactor varies with the contact radius.
                if dissipation == 0.0 { Some(0.0) } else { None },
            )
        }
    };
    let tangential = match i.tangential() {
        Tangential::None => "tangential linear_nohistory 0 0".to_string(),
        Tangential::History(h) => {
            let x_gammat = if h.damping == 0.0 {
                0.0
            } else {
                match damping_prefactor {
                    Some(eta) if eta > 0.0 => h.damping / eta,
                    Some(_) => {
                        return Err(format!(
                            "its tangential damping γ_t = {} kg/s has no LAMMPS counterpart \
                             without normal damping (LAMMPS damps the slip with a multiple of \
                             the normal damping); set tangential_damping = 0 or give the \
                             normal law a damping",
                            h.damping
                        ));
                    }
                    None => {
                        return Err(format!(
                            "its tangential damping γ_t = {} kg/s has no exact LAMMPS \
                             counterpart with the viscoelastic Hertz law (LAMMPS damps the \
                             slip with a multiple of the normal damping prefactor, which \
                             grows with the contact radius); set tangential_damping = 0",
                            h.damping
                        ));
                    }
                }
            };
            format!(
                "tangential linear_history {:e} {x_gammat:e} {:e}",
                h.stiffness, h.friction
            )
        }
        Tangential::Coulomb { .. } => {
            return Err(
                "pure Coulomb sliding (tangential = \"coulomb\") has no `pair granular` \
                        counterpart; use the history spring (tangential_stiffness)"
                    .into(),
            );
        }
        Tangential::Walton(_) => {
            return Err(
                "Walton's rule (tangential_restitution) belongs to the event engines; \
                        LAMMPS has no counterpart: give the history spring's keys instead"
                    .into(),
            );
        }
    };
    let limit = if limit_damping { " limit_damping" } else { "" };
    Ok(format!("{normal} {tangential}{limit}"))
}

/// The box LAMMPS gets: the config's, or in free space the particles' bounding box
/// grown by two diameters (shrink-wrapped then, `boundary m`).
pub fn lammps_box(system: &System) -> SimBox {
    match system.domain.sim_box {
        Some(b) => b,
        None => {
            let p = &system.particles;
            let (lo, extent) = emdstar_system::bounding_box(&p.position);
            let pad = 4.0 * system.max_radius();
            SimBox {
                lo: lo.map(|c| c - pad),
                size: extent.map(|e| e + 2.0 * pad),
                periodic: [false; 3],
            }
        }
    }
}

/// The data file: atom types are the species (1-based), atom ids the particle numbers
/// plus one; numbers in the shortest form that reads back to the same double.
pub fn data_file(system: &System, source: &str) -> String {
    let p: &Particles = &system.particles;
    let b = lammps_box(system);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "LAMMPS data file (atom_style sphere) written by emdstar export lammps from {source}\n"
    );
    let _ = writeln!(
        s,
        "{} atoms\n{} atom types\n",
        p.len(),
        system.species.len()
    );
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let _ = writeln!(
            s,
            "{:e} {:e} {axis}lo {axis}hi",
            b.lo[k],
            b.lo[k] + b.size[k]
        );
    }
    let mut order: Vec<usize> = (0..p.len()).collect();
    order.sort_by_key(|&i| p.id[i]);
    let _ = writeln!(s, "\nAtoms # sphere\n");
    for &i in &order {
        let (r, m) = (p.radius[i], p.mass[i]);
        let density = m / (4.0 / 3.0 * std::f64::consts::PI * r * r * r);
        let x = p.position[i];
        let image = p.image[i];
        let _ = writeln!(
            s,
            "{} {} {:e} {density:e} {:e} {:e} {:e} {} {} {}",
            p.id[i] + 1,
            p.species[i] + 1,
            2.0 * r,
            x[0],
            x[1],
            x[2],
            image[0],
            image[1],
            image[2]
        );
    }
    let _ = writeln!(s, "\nVelocities\n");
    for &i in &order {
        let (v, w) = (p.velocity[i], p.angular_velocity[i]);
        let _ = writeln!(
            s,
            "{} {:e} {:e} {:e} {:e} {:e} {:e}",
            p.id[i] + 1,
            v[0],
            v[1],
            v[2],
            w[0],
            w[1],
            w[2]
        );
    }
    s
}

/// What the input script needs besides the system.
pub struct Run {
    pub source: String,
    pub dt: f64,
    pub steps: u64,
    pub skin: f64,
    pub limit_damping: bool,
    /// Steps between log lines and between dump frames.
    pub log_every: u64,
    pub dump_every: u64,
}

/// The first twelve columns of emdstar's thermo log (`emdstar_system::ThermoLog`); the
/// pressure tensor, collision rate and a₂ that follow have no counterpart in the deck.
const LOG_HEADER: &str = "# t[s] step kinetic_energy[J] potential_energy[J] total_energy[J] \
                          granular_temperature[J] px[kg*m/s] py pz contacts \
                          rotational_energy[J] rotational_temperature[J]";

/// The input script (read next to `emdstar.data`), or why the config has no exact
/// LAMMPS counterpart.
pub fn input_script(system: &System, run: &Run) -> Result<String, String> {
    let b = lammps_box(system);
    let inter = system.interactions();
    let species = system.species.len();
    let boundary: Vec<&str> = (0..3)
        .map(|k| match (system.domain.sim_box, b.periodic[k]) {
            (_, true) => "p",
            (Some(_), false) => "f",
            (None, false) => "m",
        })
        .collect();
    let mut s = String::new();
    let w = &mut s;
    let _ = writeln!(
        w,
        "# The LAMMPS deck of {}, written by emdstar export lammps.",
        run.source
    );
    let _ = writeln!(
        w,
        "# Run it in this directory: lmp -in in.emdstar, or on MPI ranks:"
    );
    let _ = writeln!(w, "#   mpirun -np 4 lmp -in in.emdstar");
    let _ = writeln!(
        w,
        "# Atom types are emdstar's species (1-based): one radius, mass and material each,"
    );
    let _ = writeln!(
        w,
        "# so every pair_coeff below is exact for its pair (see docs/physics.md)."
    );
    let _ = writeln!(
        w,
        "# Writes emdstar.log (the first twelve columns of emdstar's log; potential_energy is the"
    );
    let _ = writeln!(
        w,
        "# gravitational part only, as pair granular reports no elastic energy, and"
    );
    let _ = writeln!(
        w,
        "# contacts counts overlapping pairs, not walls) and emdstar.lammpstrj (OVITO)."
    );
    let _ = writeln!(w, "units           si");
    let _ = writeln!(w, "atom_style      sphere");
    let _ = writeln!(w, "atom_modify     map array");
    let _ = writeln!(w, "boundary        {}", boundary.join(" "));
    let _ = writeln!(w, "comm_modify     vel yes");
    let _ = writeln!(w, "read_data       emdstar.data");
    let _ = writeln!(w, "pair_style      granular");
    for a in 0..species {
        for c in a..species {
            let keys = granular_keywords(inter.pair(a as u32, c as u32), run.limit_damping)
                .map_err(|why| {
                    format!(
                        "the contact of {}: {why}",
                        inter.describe(inter.pair(a as u32, c as u32))
                    )
                })?;
            let _ = writeln!(w, "pair_coeff      {} {} {keys}", a + 1, c + 1);
        }
    }
    let _ = writeln!(w, "neighbor        {:e} bin", run.skin);
    let _ = writeln!(w, "neigh_modify    delay 0 every 1 check yes");
    for t in 0..species {
        let _ = writeln!(w, "group           species{} type {}", t + 1, t + 1);
    }
    let walls = &system.domain.walls;
    if !walls.is_empty() {
        let _ = writeln!(
            w,
            "# Walls: fix wall/gran with each wall's contact per species. The LAMMPS of 29 Sep\n\
             # 2021 (Debian's) computes a wall contact's slip and lever arm otherwise than its\n\
             # pair styles and than emdstar (which follows the current GranularModel with\n\
             # contact_type WALL): frictional wall contacts differ there (docs/physics.md)."
        );
    }
    for (k, wall) in walls.iter().enumerate() {
        if wall.vibration.is_some() {
            return Err(format!(
                "walls[{k}].amplitude: the export writes walls at rest (fix wall/gran), so a \
                 vibrated wall would stand still in LAMMPS; export a config without the \
                 wall's amplitude and frequency"
            ));
        }
        let Some(axis) = (0..3).find(|&a| wall.normal[a].abs() == 1.0) else {
            return Err(format!(
                "walls[{k}] has normal {:?}: fix wall/gran takes planes normal to x, y or z only",
                wall.normal
            ));
        };
        let at = format!("{:e}", wall.point[axis]);
        let (lo, hi) = if wall.normal[axis] > 0.0 {
            (at.as_str(), "NULL")
        } else {
            ("NULL", at.as_str())
        };
        for t in 0..species {
            let keys =
                granular_keywords(inter.wall(t as u32, k), run.limit_damping).map_err(|why| {
                    format!(
                        "the contact of {}: {why}",
                        inter.describe(inter.wall(t as u32, k))
                    )
                })?;
            let _ = writeln!(
                w,
                "fix             wall{k}_{} species{} wall/gran granular {keys} {}plane {lo} {hi}",
                t + 1,
                t + 1,
                ["x", "y", "z"][axis]
            );
        }
    }
    let g = system.domain.gravity;
    let g_norm = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
    if g_norm > 0.0 {
        let _ = writeln!(
            w,
            "fix             gravity all gravity {g_norm:e} vector {:e} {:e} {:e}",
            g[0] / g_norm,
            g[1] / g_norm,
            g[2] / g_norm
        );
    }
    let _ = writeln!(w, "fix             integrate all nve/sphere");
    let _ = writeln!(w, "timestep        {:e}", run.dt);
    // emdstar's log columns.
    let _ = writeln!(w, "compute         ke all ke");
    let _ = writeln!(w, "compute         rke all erotate/sphere");
    let _ = writeln!(w, "compute         touching all contact/atom");
    let _ = writeln!(w, "compute         touches all reduce sum c_touching");
    let _ = writeln!(w, "variable        t equal time");
    let _ = writeln!(w, "variable        s equal step");
    let _ = writeln!(w, "variable        M equal mass(all)");
    let _ = writeln!(w, "variable        px equal v_M*vcm(all,x)");
    let _ = writeln!(w, "variable        py equal v_M*vcm(all,y)");
    let _ = writeln!(w, "variable        pz equal v_M*vcm(all,z)");
    let _ = writeln!(
        w,
        "variable        pe equal -v_M*({:e}*xcm(all,x)+{:e}*xcm(all,y)+{:e}*xcm(all,z))",
        g[0], g[1], g[2]
    );
    let _ = writeln!(w, "variable        etot equal c_ke+c_rke+v_pe");
    let _ = writeln!(
        w,
        "variable        T equal (2*c_ke-v_M*(vcm(all,x)^2+vcm(all,y)^2+vcm(all,z)^2))/(3*count(all))"
    );
    let _ = writeln!(w, "variable        Trot equal 2*c_rke/(3*count(all))");
    let _ = writeln!(w, "variable        contacts equal round(c_touches/2)");
    let line = "${t} ${s} $(c_ke:%.17g) ${pe} ${etot} ${T} ${px} ${py} ${pz} ${contacts} $(c_rke:%.17g) ${Trot}";
    let _ = writeln!(
        w,
        "thermo_style    custom step time c_ke c_rke c_touches v_T v_Trot"
    );
    let _ = writeln!(w, "thermo          {}", run.log_every.max(1));
    // `run 0` makes the computes current for the first line, which the fix prints
    // as the run sets up.
    let _ = writeln!(w, "run             0 post no");
    let every = run.log_every.max(1);
    let _ = writeln!(
        w,
        "fix             log all print {every} \"{line}\" file emdstar.log screen no title \"{LOG_HEADER}\""
    );
    let _ = writeln!(
        w,
        "dump            trajectory all custom {} emdstar.lammpstrj id type radius mass x y z ix iy iz vx vy vz omegax omegay omegaz",
        run.dump_every.max(1)
    );
    let _ = writeln!(w, "dump_modify     trajectory sort id");
    let _ = writeln!(w, "run             {}", run.steps);
    if run.steps % every != 0 {
        // A last line at the end, as emdstar writes one.
        let _ = writeln!(w, "print           \"{line}\" append emdstar.log screen no");
    }
    Ok(s)
}
