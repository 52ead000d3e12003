//! `emdstar mor`: the matrix of restitution of one collision.

mod curve;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ParameterBox, RectBounds,
    ScaledParams, Sphere, ViscoelasticHertz, scale,
};
use emdstar_mor::{Mor, solve, with_restitution};
use serde_json::{Value, json};
use std::path::PathBuf;

/// Force model on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModelArg {
    /// Linear spring-dashpot: F = kξ + γξ̇ (needs --stiffness, and --damping or
    /// --restitution).
    Linear,
    /// Viscoelastic Hertz: F = ρ_el ξ^{3/2} + (3/2)Aρ_el √ξ ξ̇ (needs --young, --poisson,
    /// and --dissipation or --restitution with --speed).
    Hertz,
}

impl From<ModelArg> for Model {
    fn from(m: ModelArg) -> Self {
        match m {
            ModelArg::Linear => Model::Linear,
            ModelArg::Hertz => Model::Hertz,
        }
    }
}

/// Matrix of restitution (MoR) of one collision, solved exactly or from a table.
///
/// The MoR of Müller & Pöschel 2013 (Sec. III).
///
/// Give either physical parameters (two spheres of one material, equal unless
/// --radius2 is set, meeting at relative speed --speed with eccentricity --eccentricity
/// = d/l) or the three scaled parameters with --scaled.
///
/// The material's dissipation is either given (--damping γ, --dissipation A) or
/// computed from --restitution E: the γ or A with which a central impact of these two
/// spheres has normal restitution E (at normal speed --speed for Hertz, whose
/// restitution falls with the speed), by the exact solver to 1e-10. The value used is
/// printed ("damping" or "dissipation" in the JSON).
///
/// --restitution-curve prints the restitution of central impacts against the impact
/// speed instead, so you see what a material gives over the speeds of your gas.
///
/// Examples:
///   emdstar mor --model linear --stiffness 2000 --damping 0 --radius 0.1 --density 1140 --speed 5 --eccentricity 0.3
///   emdstar mor --model hertz --young 1e9 --poisson 0.4 --dissipation 1e-4 --radius 0.01 --density 2500 --speed 1 --eccentricity 0.5 --json
///   emdstar mor --model hertz --young 1e9 --poisson 0.4 --restitution 0.8 --radius 0.1 --density 1140 --speed 1 --eccentricity 0 --json
///   emdstar mor --model hertz --young 1e9 --poisson 0.4 --restitution 0.8 --speed 1 --radius 0.1 --density 1140 --restitution-curve --plot eps.png
///   emdstar mor --model hertz --scaled 100 50 0.1
#[derive(Args, Debug)]
#[command(verbatim_doc_comment, allow_negative_numbers = true)]
pub struct MorArgs {
    /// Force model.
    #[arg(long, value_enum)]
    pub model: ModelArg,
    /// Spring constant k in N/m (linear).
    #[arg(long, value_name = "K")]
    pub stiffness: Option<f64>,
    /// Dashpot constant γ in kg/s (linear).
    #[arg(long, value_name = "GAMMA")]
    pub damping: Option<f64>,
    /// Young's modulus Y in Pa (hertz).
    #[arg(long, value_name = "Y")]
    pub young: Option<f64>,
    /// Poisson's ratio ν (hertz).
    #[arg(long, value_name = "NU")]
    pub poisson: Option<f64>,
    /// Dissipative constant A in s (hertz), the A of Brilliantov et al. 1996.
    #[arg(long, value_name = "A")]
    pub dissipation: Option<f64>,
    /// Coefficient of normal restitution E in (0, 1] of a central impact, instead of
    /// --damping or --dissipation (hertz: at normal speed --speed).
    #[arg(long, value_name = "E")]
    pub restitution: Option<f64>,
    /// Sphere radius R in m (both spheres unless --radius2 is given).
    #[arg(long, value_name = "R")]
    pub radius: Option<f64>,
    /// Radius of the second sphere in m, same material.
    #[arg(long, value_name = "R2")]
    pub radius2: Option<f64>,
    /// Material density ρ in kg/m³; each sphere has mass (4/3)πR³ρ.
    #[arg(long, value_name = "RHO")]
    pub density: Option<f64>,
    /// Magnitude of the relative velocity at contact in m/s.
    #[arg(long, value_name = "V")]
    pub speed: Option<f64>,
    /// Eccentricity e = d/l in [0, 1): 0 is a central impact.
    #[arg(long, value_name = "E")]
    pub eccentricity: Option<f64>,
    /// Scaled parameters l̃, c_φ, c_dis instead of physical ones.
    #[arg(long, num_args = 3, value_names = ["L_TILDE", "C_PHI", "C_DIS"], allow_negative_numbers = true)]
    pub scaled: Option<Vec<f64>>,
    /// Print JSON instead of a readable summary.
    #[arg(long)]
    pub json: bool,
    /// Answer from a MoR table instead of an exact solve: a table file, or `default`
    /// for the table embedded in the program (tables/<model>.npz). Points outside the
    /// table's box are an error, never extrapolated.
    #[arg(long, value_name = "FILE|default")]
    pub table: Option<String>,
    /// Print the normal restitution ε_n and the duration of central impacts against
    /// the impact speed (exact solves) instead of one MoR.
    #[arg(long)]
    pub restitution_curve: bool,
    /// Speed range of the curve in m/s [default: --speed/100 to 100·--speed, or 0.01
    /// to 100].
    #[arg(long, num_args = 2, value_names = ["LO", "HI"])]
    pub curve_speeds: Option<Vec<f64>>,
    /// Speeds on the curve, evenly spaced in log(speed) [default: 21].
    #[arg(long, value_name = "N")]
    pub curve_points: Option<usize>,
    /// Also draw the curve as a PNG.
    #[arg(long, value_name = "FILE.png")]
    pub plot: Option<PathBuf>,
}

/// What was computed, in the shape of the JSON output.
struct Answer {
    model: Model,
    params: ScaledParams,
    /// (T, X) in s and m, for physical input.
    scales: Option<(f64, f64)>,
    mor: Mor,
    /// "exact" or "table".
    source: &'static str,
    fitted: Option<Fitted>,
}

pub fn run(args: &MorArgs) -> Result<()> {
    let model = Model::from(args.model);
    if args.restitution_curve {
        return curve::run(args, model);
    }
    for (flag, given) in [
        ("--curve-speeds", args.curve_speeds.is_some()),
        ("--curve-points", args.curve_points.is_some()),
        ("--plot", args.plot.is_some()),
    ] {
        if given {
            bail!("{flag} belongs to --restitution-curve; add that flag or remove {flag}");
        }
    }
    let (params, scales, fitted) = match &args.scaled {
        Some(v) => {
            reject_physical(args)?;
            let p = ScaledParams::new(v[0], v[1], v[2]).context("bad --scaled parameters")?;
            (p, None, None)
        }
        None => {
            let (law, pair, fitted) = material(args, model)?;
            let pair_law = PairLaw::same_material(&law, pair.r_eff)?;
            let impact = Impact::from_speed_eccentricity(
                required(args.speed, "--speed", model)?,
                required(args.eccentricity, "--eccentricity", model)?,
            )?;
            let s = scale(&pair_law, &pair, &impact)?;
            (s.params, Some((s.time, s.length)), fitted)
        }
    };
    let (mor, source) = match &args.table {
        None => (
            solve(model, &params).context("the collision ODE could not be solved")?,
            "exact",
        ),
        Some(src) => (table_lookup(src, model, &params)?, "table"),
    };
    let answer = Answer {
        model,
        params,
        scales,
        mor,
        source,
        fitted,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&answer.to_json())?);
    } else {
        print!("{}", answer.summary());
    }
    Ok(())
}

/// The MoR from a table file or the embedded default table.
fn table_lookup(source: &str, model: Model, params: &ScaledParams) -> Result<Mor> {
    let loaded;
    let table = if source == "default" {
        emdstar_table::default_table(model)?
    } else {
        loaded = emdstar_table::Table::open(source)
            .with_context(|| format!("cannot load table {source}"))?;
        &loaded
    };
    table.expect_model(model)?;
    let m = table.lookup_scaled(params)?;
    Ok(Mor {
        eps_r: m.eps_r,
        one_minus_eps_r: m.one_minus_eps_r,
        eps_rdot: m.eps_rdot,
        eps_phi: m.eps_phi,
        eps_t: m.eps_t,
    })
}

fn reject_physical(args: &MorArgs) -> Result<()> {
    let given = [
        ("--stiffness", args.stiffness),
        ("--damping", args.damping),
        ("--young", args.young),
        ("--poisson", args.poisson),
        ("--dissipation", args.dissipation),
        ("--restitution", args.restitution),
        ("--radius", args.radius),
        ("--radius2", args.radius2),
        ("--density", args.density),
        ("--speed", args.speed),
        ("--eccentricity", args.eccentricity),
    ];
    if let Some((name, _)) = given.iter().find(|(_, v)| v.is_some()) {
        bail!("{name} cannot be combined with --scaled: give either physical or scaled parameters");
    }
    Ok(())
}

fn required(value: Option<f64>, flag: &str, model: Model) -> Result<f64> {
    value.with_context(|| format!("--model {model} needs {flag}"))
}

/// A flag and its value, if given.
type Flag = (&'static str, Option<f64>);

/// The dissipation computed from --restitution: ("damping", γ) or ("dissipation", A).
pub(super) type Fitted = (&'static str, f64);

/// The material (its dissipation given, or computed from --restitution), the pair of
/// spheres, and the dissipation computed, if it was.
pub(super) fn material(
    args: &MorArgs,
    model: Model,
) -> Result<(ForceLaw, PairProperties, Option<Fitted>)> {
    let (elastic, dissipative, foreign): (&[&str], Flag, Vec<Flag>) = match model {
        Model::Linear => (
            &["--stiffness"],
            ("--damping", args.damping),
            vec![
                ("--young", args.young),
                ("--poisson", args.poisson),
                ("--dissipation", args.dissipation),
            ],
        ),
        Model::Hertz => (
            &["--young", "--poisson"],
            ("--dissipation", args.dissipation),
            vec![("--stiffness", args.stiffness), ("--damping", args.damping)],
        ),
    };
    if let Some((flag, _)) = foreign.iter().find(|(_, v)| v.is_some()) {
        bail!(
            "{flag} does not belong to --model {model}, which takes {}, and {} or --restitution",
            elastic.join(", "),
            dissipative.0
        );
    }
    let (flag, value) = dissipative;
    let dissipation = match (value, args.restitution) {
        (Some(_), Some(_)) => {
            bail!("give either {flag} or --restitution, not both: --restitution computes {flag}")
        }
        (None, None) => bail!("--model {model} needs {flag} or --restitution"),
        (v, _) => v.unwrap_or(0.0),
    };
    let law = match model {
        Model::Linear => ForceLaw::Linear(LinearDashpot::new(
            required(args.stiffness, "--stiffness", model)?,
            dissipation,
        )?),
        Model::Hertz => ForceLaw::Hertz(ViscoelasticHertz::new(
            required(args.young, "--young", model)?,
            required(args.poisson, "--poisson", model)?,
            dissipation,
        )?),
    };
    let density = required(args.density, "--density", model)?;
    let r1 = required(args.radius, "--radius", model)?;
    let s1 = Sphere::from_density(r1, density)?;
    let s2 = match args.radius2 {
        Some(r2) => Sphere::from_density(r2, density).context("bad --radius2")?,
        None => s1,
    };
    let pair = PairProperties::spheres(&s1, &s2);
    let Some(e) = args.restitution else {
        return Ok((law, pair, None));
    };
    // The linear dashpot's restitution does not depend on the speed.
    let speed = match model {
        Model::Linear => args.speed.unwrap_or(1.0),
        Model::Hertz => args.speed.context(
            "--restitution with --model hertz needs --speed: the restitution of viscoelastic \
             spheres falls with the impact speed, so it is matched at one speed",
        )?,
    };
    let law = with_restitution(&law, &pair, speed, e).context("bad --restitution")?;
    let fitted = match law {
        ForceLaw::Linear(l) => ("damping", l.damping),
        ForceLaw::Hertz(h) => ("dissipation", h.dissipation),
    };
    Ok((law, pair, Some(fitted)))
}

impl Answer {
    /// The paper's rectangle for this model, if the point lies inside it.
    fn rect(&self) -> Option<(emdstar_contact::RectCoords, RectBounds)> {
        let bounds = ParameterBox::paper(self.model).bounds().ok()?;
        let x = bounds.to_rect(&self.params);
        bounds.contains(&x).then_some((x, bounds))
    }

    fn to_json(&self) -> Value {
        let (t, x) = match self.scales {
            Some((t, x)) => (json!(t), json!(x)),
            None => (Value::Null, Value::Null),
        };
        let rect = match self.rect() {
            Some((r, _)) => json!({"a": r.a, "b": r.b, "c": r.c}),
            None => Value::Null,
        };
        let m = &self.mor;
        let mut v = json!({
            "model": self.model.name(),
            "source": self.source,
            "scaled": {"l": self.params.l_tilde, "c_phi": self.params.c_phi,
                       "c_dis": self.params.c_dis, "T": t, "X": x},
            "rect": rect,
            "mor": {"eps_r": m.eps_r, "one_minus_eps_r": m.one_minus_eps_r,
                    "eps_rdot": m.eps_rdot, "eps_phi": m.eps_phi, "eps_t": m.eps_t},
        });
        if let Some((name, value)) = self.fitted {
            v[name] = json!(value);
        }
        v
    }

    fn summary(&self) -> String {
        let p = &self.params;
        let m = &self.mor;
        let mut s = format!(
            "{} collision, {} (Müller & Pöschel 2013)\n\
             scaled parameters   l̃ = {:.6e}   c_φ = {:.6e}   c_dis = {:.6e}\n",
            self.model,
            if self.source == "table" {
                "table lookup"
            } else {
                "exact solve of the scaled ODE"
            },
            p.l_tilde,
            p.c_phi,
            p.c_dis
        );
        match self.fitted {
            Some(("damping", g)) => {
                s += &format!("from --restitution  damping γ = {g:.10e} kg/s\n");
            }
            Some((_, a)) => s += &format!("from --restitution  dissipation A = {a:.10e} s\n"),
            None => {}
        }
        if let Some((t, x)) = self.scales {
            s += &format!("scales              T = {t:.6e} s   X = {x:.6e} m\n");
        }
        match self.rect() {
            Some((r, _)) => {
                s += &format!(
                    "paper-box coords    a = {:.6}   b = {:.6}   c = {:.6}\n",
                    r.a, r.b, r.c
                )
            }
            None => s += "paper-box coords    outside the paper's box for this model\n",
        }
        s += &format!(
            "matrix of restitution\n  ε_r   = {:.12}   (1 − ε_r = {:.6e})\n  ε_ṙ   = {:.12}   (normal restitution ε_n = {:.12})\n  ε_φ   = {:.12} rad = {:.6}°\n  ε_t   = {:.12}   (scaled contact duration)\n",
            m.eps_r,
            m.one_minus_eps_r,
            m.eps_rdot,
            -m.eps_rdot,
            m.eps_phi,
            m.eps_phi.to_degrees(),
            m.eps_t
        );
        if let Some((t, _)) = self.scales {
            s += &format!("contact duration    τ = ε_t·T = {:.6e} s\n", m.eps_t * t);
        }
        s
    }
}
