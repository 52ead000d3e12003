//! The hopper of the HAET paper (Sec. 7) as a quasi-2-D slab, with friction µ = 0.2 and
//! rotating particles, run with pure MD and with the hybrid engine; writes PNG maps and
//! curves and a JSON of the figures.
//!
//! ```sh
//! cargo run --release --example hopper -- [--seeds 3] [--t-end 0.025] [--out DIR] [--law linear|hertz] [--events emdstar|emd] [--frictionless] [--font FILE.ttf (default: the embedded font)]
//! ```
//!
//! See README.md beside this file for the set-up and what the figures mean.

mod plot;

use emdstar_contact::{
    ForceLaw, HistorySpring, LinearDashpot, Model, PairLaw, PairProperties, Sphere, Tangential,
    ViscoelasticHertz,
};
use emdstar_edmd::rules::TableMorSource;
use emdstar_hybrid::{EventRule, Hybrid, HybridOptions, Mode};
use emdstar_system::{Domain, Particles, SimBox, Species, System, Wall};
use std::path::PathBuf;
use std::time::Instant;

/// Particle radius (diameter 0.5 mm), density (glass) in SI units.
const RADIUS: f64 = 0.25e-3;
const DENSITY: f64 = 2500.0;
const COUNT: usize = 1200;
/// Hopper width and height, outlet width, funnel height (45° walls).
const WIDTH: f64 = 0.06;
const HEIGHT: f64 = 0.25;
const OUTLET: f64 = 5.0e-3;
/// Slab thickness: 1.1 diameters, a monolayer.
const THICKNESS: f64 = 1.1 * 2.0 * RADIUS;
/// Duration of a central particle–particle contact and its restitution (for Hertz
/// contacts: at the impact speed `HERTZ_SPEED`).
const CONTACT_TIME: f64 = 1.0e-5;
const RESTITUTION: f64 = 0.8;
const HERTZ_SPEED: f64 = 1.0;
/// Poisson's ratio of the Hertz material (glass).
const POISSON: f64 = 0.22;
/// Coulomb's µ (HAET, Sec. 7); the tangential spring and dashpot are 2/7 of the normal
/// ones, so that a sticking contact oscillates as the normal one does.
const FRICTION: f64 = 0.2;
const TANGENTIAL_RATIO: f64 = 2.0 / 7.0;
/// Field bins (m) and the window the fields are averaged over (s).
const BIN: f64 = 2.0e-3;
const SAMPLE: f64 = 5.0e-4;

/// A deterministic uniform generator on [0, 1) (64-bit LCG, Knuth's MMIX constants).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The linear dashpot with the wanted contact time and restitution of a central
/// particle–particle impact (Schwager & Pöschel 2007: ε = exp(−β t_c) with
/// t_c ≈ π/√(ω0² − β²) for weak damping).
fn material(m_eff: f64) -> LinearDashpot {
    let beta_over_omega = -RESTITUTION.ln() / std::f64::consts::PI;
    let omega = std::f64::consts::PI / CONTACT_TIME;
    let beta = beta_over_omega * omega;
    let stiffness = m_eff * (omega * omega + beta * beta);
    LinearDashpot::new(stiffness, 2.0 * m_eff * beta).expect("valid dashpot")
}

/// One particle (diameter 0.5 mm, glass).
fn sphere() -> Sphere {
    Sphere::from_density(RADIUS, DENSITY).expect("valid sphere")
}

/// The viscoelastic Hertz material whose central particle–particle impact at
/// `HERTZ_SPEED` lasts `CONTACT_TIME` (elastic duration, Müller & Pöschel 2013, Eq. 53)
/// and has the restitution `RESTITUTION` (solved exactly, `emdstar_mor::with_restitution`).
fn hertz_material(pair: &PairProperties) -> ViscoelasticHertz {
    // The elastic duration scales as Y^(-2/5): one evaluation at Y = 1 fixes Y.
    let unit = ForceLaw::Hertz(ViscoelasticHertz::new(1.0, POISSON, 0.0).expect("valid"));
    let duration = PairLaw::same_material(&unit, pair.r_eff)
        .and_then(|l| l.elastic_duration(pair.m_eff, HERTZ_SPEED))
        .expect("elastic duration");
    let young = (duration / CONTACT_TIME).powf(2.5);
    let elastic = ForceLaw::Hertz(ViscoelasticHertz::new(young, POISSON, 0.0).expect("valid"));
    match emdstar_mor::with_restitution(&elastic, pair, HERTZ_SPEED, RESTITUTION) {
        Ok(ForceLaw::Hertz(h)) => h,
        other => panic!("the Hertz material's restitution: {other:?}"),
    }
}

/// The friction of the hopper's material: µ = 0.2, a history spring and dashpot of 2/7
/// of the normal ones of the linear law `law` (for Hertz contacts, of the linear law
/// with their contact time and restitution).
fn friction(law: &LinearDashpot) -> Tangential {
    Tangential::History(
        HistorySpring::new(
            FRICTION,
            TANGENTIAL_RATIO * law.stiffness,
            TANGENTIAL_RATIO * law.damping,
        )
        .expect("valid friction"),
    )
}

/// The hopper: side walls, two 45° funnel walls meeting the outlet at y = 0, a lid,
/// two slab faces; 1200 particles at random above the funnel, 10 m/s downwards; with
/// the normal law `model` and friction unless `frictionless`.
fn hopper(seed: u64, model: Model, frictionless: bool) -> System {
    let sphere = sphere();
    let species = vec![Species::new(RADIUS, sphere.mass)];
    let m_eff = PairProperties::spheres(&sphere, &sphere).m_eff;
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let (left, right) = (0.5 * (WIDTH - OUTLET), 0.5 * (WIDTH + OUTLET));
    let wall = |normal: [f64; 3], point: [f64; 3]| Wall::fixed(normal, point);
    let walls = vec![
        wall([1.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
        wall([-1.0, 0.0, 0.0], [WIDTH, 0.0, 0.0]),
        wall([s, s, 0.0], [left, 0.0, 0.0]),
        wall([-s, s, 0.0], [right, 0.0, 0.0]),
        wall([0.0, -1.0, 0.0], [0.0, HEIGHT + 0.01, 0.0]),
        wall([0.0, 0.0, 1.0], [0.0, 0.0, 0.0]),
        wall([0.0, 0.0, -1.0], [0.0, 0.0, THICKNESS]),
    ];
    let mut rng = Lcg(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0x5DEE_CE66);
    let mut particles = Particles::default();
    let funnel_top = left + 2.0 * RADIUS;
    let min_gap2 = (2.0 * RADIUS * 1.01).powi(2);
    while particles.len() < COUNT {
        let x = [
            RADIUS * 1.01 + rng.next() * (WIDTH - 2.02 * RADIUS),
            funnel_top + rng.next() * (HEIGHT - funnel_top),
            0.5 * THICKNESS,
        ];
        let free = particles
            .position
            .iter()
            .all(|p: &[f64; 3]| (p[0] - x[0]).powi(2) + (p[1] - x[1]).powi(2) >= min_gap2);
        if free {
            particles.push(&species, 0, x, [0.0, -10.0, 0.0]);
        }
    }
    let law = material(m_eff);
    let tangential = if frictionless {
        Tangential::None
    } else {
        friction(&law)
    };
    let normal = match model {
        Model::Linear => ForceLaw::Linear(law),
        Model::Hertz => ForceLaw::Hertz(hertz_material(&PairProperties::spheres(&sphere, &sphere))),
    };
    let domain = Domain {
        sim_box: Some(SimBox {
            lo: [0.0, -0.01, 0.0],
            size: [WIDTH, HEIGHT + 0.02, THICKNESS],
            periodic: [false; 3],
        }),
        walls,
        gravity: [0.0, -9.81, 0.0],
        ..Domain::default()
    };
    System::one_material(particles, species, &normal, tangential, domain)
        .expect("the hopper's system")
}

/// CPU time of this process in s (user + system, from /proc/self/stat, in clock
/// ticks of 10 ms): robust against other processes sharing the cores, which wall
/// time is not. Falls back to 0 where /proc is missing.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which is in parentheses): state is field 3,
    // utime and stime are fields 14 and 15.
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |k: usize| {
        fields
            .get(k - 3)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(14) + ticks(15)) / 100.0
}

/// What one run records.
struct Run {
    /// (t, CPU s, ED particles, particles left) every [`SAMPLE`].
    series: Vec<(f64, f64, usize, usize)>,
    /// Bin sums over the sampling window: solid area, Σ|v|, ΣR|ω|, particle count.
    area: Vec<f64>,
    speed: Vec<f64>,
    spin: Vec<f64>,
    count: Vec<f64>,
    snapshots: usize,
    wall_s: f64,
    cpu_s: f64,
    stats: emdstar_hybrid::HybridStats,
}

const NX: usize = (WIDTH / BIN) as usize;
const NY: usize = (HEIGHT / BIN) as usize;

/// What a run is asked to do.
#[derive(Clone, Copy)]
struct Setup {
    model: Model,
    events: EventRule,
    frictionless: bool,
    t_end: f64,
    /// The time window the fields are averaged over.
    window: (f64, f64),
}

/// Runs the hopper of `seed`; `md` makes every particle time-driven.
fn run(seed: u64, md: bool, setup: Setup) -> Run {
    let Setup {
        model,
        events,
        frictionless,
        t_end,
        window,
    } = setup;
    let system = hopper(seed, model, frictionless);
    let tc = emdstar_dem::shortest_contact_time(&system, t_end)
        .expect("contact time")
        .expect("particles move");
    let dt = emdstar_dem::DEFAULT_DT_FRACTION * tc;
    let outlet = Wall {
        normal: [0.0, 1.0, 0.0],
        point: [0.0, -RADIUS, 0.0],
        vibration: None,
    };
    let mut opts = HybridOptions {
        outlet: Some(outlet),
        events,
        ..HybridOptions::with_dt(dt)
    };
    if md {
        (opts.phi_time, opts.phi_event) = (0.0, 0.0);
    }
    let mor = TableMorSource::new(emdstar_table::default_table(model).expect("table"), true);
    let mut h = Hybrid::new(system, opts, Box::new(mor), t_end).expect("hopper set-up");
    let per_sample = (SAMPLE / dt).round() as u64;
    let samples = (t_end / SAMPLE).round() as u64;
    let mut out = Run {
        series: vec![(0.0, 0.0, h.count(Mode::Event), 0)],
        area: vec![0.0; NX * NY],
        speed: vec![0.0; NX * NY],
        spin: vec![0.0; NX * NY],
        count: vec![0.0; NX * NY],
        snapshots: 0,
        wall_s: 0.0,
        cpu_s: 0.0,
        stats: *h.stats(),
    };
    let start = Instant::now();
    let cpu_start = cpu_seconds();
    for _ in 0..samples {
        h.advance(per_sample).expect("hopper run");
        let cpu = cpu_seconds() - cpu_start;
        let t = h.time();
        out.series
            .push((t, cpu, h.count(Mode::Event), h.count(Mode::Removed)));
        if t >= window.0 - 1e-12 && t <= window.1 + 1e-12 {
            let p = h.particles();
            out.snapshots += 1;
            for (i, mode) in h.modes().iter().enumerate() {
                let (x, v) = (p.position[i], p.velocity[i]);
                if *mode == Mode::Removed || x[1] < 0.0 {
                    continue;
                }
                let (bx, by) = ((x[0] / BIN) as usize, (x[1] / BIN) as usize);
                if bx < NX && by < NY {
                    let b = by * NX + bx;
                    out.area[b] += std::f64::consts::PI * RADIUS * RADIUS;
                    out.speed[b] += (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    let w = p.angular_velocity[i];
                    out.spin[b] += RADIUS * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                    out.count[b] += 1.0;
                }
            }
        }
    }
    out.wall_s = start.elapsed().as_secs_f64();
    out.cpu_s = cpu_seconds() - cpu_start;
    out.stats = *h.stats();
    out
}

/// The area-fraction and mean-speed maps of a run (NaN speed in empty bins).
fn fields(r: &Run) -> (Vec<f64>, Vec<f64>) {
    let n = r.snapshots.max(1) as f64;
    let phi = r.area.iter().map(|a| a / (BIN * BIN * n)).collect();
    (phi, bin_means(&r.speed, &r.count))
}

/// Per-bin means of `sums` over `count` (NaN in empty bins).
fn bin_means(sums: &[f64], count: &[f64]) -> Vec<f64> {
    sums.iter()
        .zip(count)
        .map(|(s, c)| if *c > 0.0 { s / c } else { f64::NAN })
        .collect()
}

/// CPU time spent between `t0` and `t1` (sample times of the series).
fn cpu_between(r: &Run, t0: f64, t1: f64) -> f64 {
    let at = |t: f64| {
        r.series
            .iter()
            .find(|s| s.0 >= t - 1e-12)
            .map_or(r.cpu_s, |s| s.1)
    };
    at(t1) - at(t0)
}

/// Root-mean-square difference of two maps over the bins where both are defined.
fn rms_difference(a: &[f64], b: &[f64]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for (x, y) in a.iter().zip(b) {
        if x.is_finite() && y.is_finite() {
            sum += (x - y) * (x - y);
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

fn main() {
    let mut seeds = 3u64;
    let mut t_end = 0.025;
    let mut out = PathBuf::from("examples/hopper/out");
    let mut font: Option<PathBuf> = None;
    let mut engines = vec![true, false];
    let mut frictionless = false;
    let mut model = Model::Linear;
    let mut events = EventRule::EmdStar;
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(k) = args.iter().position(|a| a == "--frictionless") {
        frictionless = true;
        args.remove(k);
    }
    for pair in args.chunks(2) {
        let value = pair
            .get(1)
            .unwrap_or_else(|| panic!("{} needs a value", pair[0]));
        match pair[0].as_str() {
            "--seeds" => seeds = value.parse().expect("--seeds N"),
            "--t-end" => t_end = value.parse().expect("--t-end SECONDS"),
            "--out" => out = value.into(),
            "--font" => font = Some(value.into()),
            "--law" => {
                model = match value.as_str() {
                    "linear" => Model::Linear,
                    "hertz" => Model::Hertz,
                    other => panic!("--law {other}: linear or hertz"),
                }
            }
            "--events" => {
                events = match value.as_str() {
                    "emdstar" => EventRule::EmdStar,
                    "emd" => EventRule::Emd,
                    other => panic!("--events {other}: emdstar or emd"),
                }
            }
            // Profiling aid: one engine only (no figures then).
            "--only" => engines = vec![value == "md"],
            other => panic!("unknown option {other}; see the doc comment of main.rs"),
        }
    }
    // One thread, as HAET's comparison (single-core; the CPU times below are the
    // process's).
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()
        .expect("a thread pool");
    std::fs::create_dir_all(&out).expect("output directory");
    let both = engines.len() == 2;
    match &font {
        Some(f) => emdstar_plot::register_font_file(f).unwrap_or_else(|e| panic!("{e}")),
        None => emdstar_plot::register_font(),
    }
    let window = (t_end - 4.0 * SAMPLE, t_end);
    let setup = Setup {
        model,
        events,
        frictionless,
        t_end,
        window,
    };
    let mut md_runs = Vec::new();
    let mut hybrid_runs = Vec::new();
    for seed in 1..=seeds {
        for &md in &engines {
            let r = run(seed, md, setup);
            eprintln!(
                "seed {seed} {}: {:.1} s CPU, {:.1} s wall, {} removed, {} ED at the end, {:?}",
                if md { "MD" } else { "hybrid" },
                r.cpu_s,
                r.wall_s,
                r.stats.removed,
                r.series.last().map_or(0, |s| s.2),
                r.stats
            );
            if md { &mut md_runs } else { &mut hybrid_runs }.push(r);
        }
    }
    if !both {
        return;
    }
    let (md_fields, hy_fields): (Vec<_>, Vec<_>) = (
        md_runs.iter().map(fields).collect(),
        hybrid_runs.iter().map(fields).collect(),
    );
    // Same seed, hybrid against MD; and MD against MD with another seed (the noise).
    let spins = |r: &Run| bin_means(&r.spin, &r.count);
    let mut same = (Vec::new(), Vec::new());
    let mut noise = (Vec::new(), Vec::new());
    let (mut same_spin, mut noise_spin) = (Vec::new(), Vec::new());
    for s in 0..seeds as usize {
        same.0
            .push(rms_difference(&hy_fields[s].0, &md_fields[s].0));
        same.1
            .push(rms_difference(&hy_fields[s].1, &md_fields[s].1));
        same_spin.push(rms_difference(&spins(&hybrid_runs[s]), &spins(&md_runs[s])));
        let o = (s + 1) % seeds as usize;
        if o != s {
            noise
                .0
                .push(rms_difference(&md_fields[o].0, &md_fields[s].0));
            noise
                .1
                .push(rms_difference(&md_fields[o].1, &md_fields[s].1));
            noise_spin.push(rms_difference(&spins(&md_runs[o]), &spins(&md_runs[s])));
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let md_wall: f64 = md_runs.iter().map(|r| r.wall_s).sum();
    let hy_wall: f64 = hybrid_runs.iter().map(|r| r.wall_s).sum();
    let md_cpu: f64 = md_runs.iter().map(|r| r.cpu_s).sum();
    let hy_cpu: f64 = hybrid_runs.iter().map(|r| r.cpu_s).sum();
    let md_steps: u64 = md_runs.iter().map(|r| r.stats.td_particle_steps).sum();
    let total = |f: fn(&emdstar_hybrid::HybridStats) -> u64| -> u64 {
        hybrid_runs.iter().map(|r| f(&r.stats)).sum()
    };
    let counts = format!(
        "{{\"pair_collisions\": {}, \"wall_collisions\": {}, \"frictional_solves\": {}, \
         \"exceptions\": {}, \"mor_fallbacks\": {}, \"late_guard_switches\": {}}}",
        total(|s| s.ed.pair_collisions),
        total(|s| s.ed.wall_collisions),
        total(|s| s.ed.frictional_solves),
        total(|s| s.ed.exceptions()),
        total(|s| s.ed.mor_fallbacks),
        total(|s| s.late_conversions),
    );
    let hy_steps: u64 = hybrid_runs.iter().map(|r| r.stats.td_particle_steps).sum();
    // HAET's Fig. 9(a) shows t_CPU/t of both methods against t: compare the ratio over
    // the first and the last quarter of the run.
    let quarter = |runs: &[Run], first: bool| -> f64 {
        let (t0, t1) = if first {
            (0.0, 0.25 * t_end)
        } else {
            (0.75 * t_end, t_end)
        };
        runs.iter().map(|r| cpu_between(r, t0, t1)).sum()
    };
    let early = quarter(&md_runs, true) / quarter(&hybrid_runs, true);
    let late = quarter(&md_runs, false) / quarter(&hybrid_runs, false);
    let summary = format!(
        "{{\n  \"seeds\": {seeds},\n  \"t_end\": {t_end},\n  \"friction\": {},\n  \
         \"law\": \"{}\",\n  \"events\": \"{}\",\n  \"hybrid_events\": {counts},\n  \
         \"cpu_ratio_md_over_hybrid_first_quarter\": {early:.3},\n  \
         \"cpu_ratio_md_over_hybrid_last_quarter\": {late:.3},\n  \
         \"rms_spin_hybrid_vs_md_same_seed\": {same_spin:?},\n  \
         \"rms_spin_md_vs_md_other_seed\": {noise_spin:?},\n  \
         \"md_wall_s\": {md_wall:.3},\n  \
         \"hybrid_wall_s\": {hy_wall:.3},\n  \"md_cpu_s\": {md_cpu:.2},\n  \
         \"hybrid_cpu_s\": {hy_cpu:.2},\n  \"cpu_ratio_md_over_hybrid\": {:.3},\n  \
         \"td_particle_steps_md\": {md_steps},\n  \"td_particle_steps_hybrid\": {hy_steps},\n  \
         \"speed_ratio_wall_md_over_hybrid\": {:.3},\n  \
         \"rms_phi_hybrid_vs_md_same_seed\": {:?},\n  \"rms_phi_md_vs_md_other_seed\": {:?},\n  \
         \"rms_speed_hybrid_vs_md_same_seed\": {:?},\n  \"rms_speed_md_vs_md_other_seed\": {:?},\n  \
         \"mean\": {{\"phi_same\": {:.4e}, \"phi_noise\": {:.4e}, \"speed_same\": {:.4e}, \
         \"speed_noise\": {:.4e}}}\n}}\n",
        if frictionless { 0.0 } else { FRICTION },
        model.name(),
        events.name(),
        md_cpu / hy_cpu,
        md_wall / hy_wall,
        same.0,
        noise.0,
        same.1,
        noise.1,
        mean(&same.0),
        mean(&noise.0),
        mean(&same.1),
        mean(&noise.1)
    );
    std::fs::write(out.join("summary.json"), &summary).expect("write summary");
    print!("{summary}");
    plot::maps(&out, &md_fields[0], &hy_fields[0], (NX, NY, BIN)).expect("maps");
    plot::curves(&out, &md_runs[0].series, &hybrid_runs[0].series).expect("curves");
}
