//! Fixed-work lookup loop for instruction counts on a shared machine:
//!
//! ```sh
//! cargo build --release -p emdstar-table --example profile_lookup
//! valgrind --tool=callgrind target/release/examples/profile_lookup tables/hertz.npz 20000 table
//! ```
//!
//! MODE `table` (`Table::lookup` from physical parameters), `pair` (pair handles),
//! `rect` (precomputed rectangular coordinates) or `none` (only the setup: subtract its
//! count). 4096 impacts of the table's box, cycled. A fifth argument R times R rounds
//! instead (best of R, thread CPU time; MODE `one` repeats one impact).
use emdstar_contact::*;
use emdstar_table::Table;
use std::hint::black_box;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn log_uniform(&mut self, r: [f64; 2]) -> f64 {
        (r[0].ln() + (r[1].ln() - r[0].ln()) * self.next()).exp()
    }
}

fn cpu_ns() -> f64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: clock_gettime writes one timespec.
    unsafe { clock_gettime(3, &mut ts) };
    ts.sec as f64 * 1e9 + ts.nsec as f64
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let table = Table::open(&args[1]).unwrap();
    let n: usize = args[2].parse().unwrap();
    let mode = args[3].as_str();
    let info = table.info();
    let mut rng = Rng(1);
    let mut cases = Vec::new();
    while cases.len() < 4096 {
        let mut get = |name: &str| {
            let k = info.box_names.iter().position(|x| x == name).unwrap();
            rng.log_uniform(info.box_ranges[k])
        };
        let law = match table.model() {
            Model::Linear => {
                ForceLaw::Linear(LinearDashpot::new(get("stiffness"), get("damping")).unwrap())
            }
            Model::Hertz => ForceLaw::Hertz(
                ViscoelasticHertz::new(get("young"), get("poisson"), get("dissipation")).unwrap(),
            ),
        };
        let s = Sphere::from_density(get("radius"), get("density")).unwrap();
        let impact = Impact::from_speed_eccentricity(get("speed"), get("eccentricity")).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        if table.lookup(&law, &pair, &impact).is_ok() {
            cases.push((law, pair, impact));
        }
    }
    let handles: Vec<_> = cases
        .iter()
        .map(|(l, p, i)| (table.pair(l, p).unwrap(), *i))
        .collect();
    let rects: Vec<_> = cases
        .iter()
        .map(|(l, p, i)| table.bounds().to_rect(&scale(l, p, i).unwrap().params))
        .collect();
    let mut sum = 0.0;
    if let Some(rounds) = args.get(4) {
        let rounds: usize = rounds.parse().unwrap();
        let mut best = f64::INFINITY;
        for _ in 0..rounds {
            let t0 = cpu_ns();
            for k in 0..n {
                let i = k % cases.len();
                match mode {
                    "table" => {
                        let (l, p, im) = &cases[i];
                        sum += black_box(table.lookup(black_box(l), p, im))
                            .unwrap()
                            .mor
                            .eps_t;
                    }
                    "pair" => {
                        let (h, im) = &handles[i];
                        sum += black_box(h.lookup(black_box(im))).unwrap().mor.eps_t;
                    }
                    "one" => {
                        let (l, p, im) = &cases[0];
                        sum += black_box(table.lookup(black_box(l), p, im))
                            .unwrap()
                            .mor
                            .eps_t;
                    }
                    _ => {
                        sum += black_box(table.lookup_rect(black_box(&rects[i])))
                            .unwrap()
                            .eps_t
                    }
                }
            }
            best = best.min((cpu_ns() - t0) / n as f64);
        }
        println!("{mode}: {best:.1} ns/lookup (best of {rounds}) {sum}");
        return;
    }
    for k in 0..n {
        let i = k % cases.len();
        match mode {
            "table" => {
                let (l, p, im) = &cases[i];
                sum += black_box(table.lookup(black_box(l), p, im))
                    .unwrap()
                    .mor
                    .eps_t;
            }
            "pair" => {
                let (h, im) = &handles[i];
                sum += black_box(h.lookup(black_box(im))).unwrap().mor.eps_t;
            }
            "rect" => {
                sum += black_box(table.lookup_rect(black_box(&rects[i])))
                    .unwrap()
                    .eps_t
            }
            _ => {}
        }
    }
    println!("{sum}");
}
