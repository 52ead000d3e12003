//! What the table's lookup bench and its profiling example share: the thread CPU clock,
//! a deterministic generator and impacts drawn from a table's own box.

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, Sphere, ViscoelasticHertz,
};
use emdstar_table::Table;

/// Two spheres' pair law and properties, and their impact.
pub type Case = (PairLaw, PairProperties, Impact);

/// CPU time of the calling thread, in ns.
#[cfg(target_os = "linux")]
pub fn thread_cpu_ns() -> u64 {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: clock_gettime writes one timespec to a valid pointer.
    let ok = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(ok, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID) failed");
    ts.sec as u64 * 1_000_000_000 + ts.nsec as u64
}

#[cfg(not(target_os = "linux"))]
pub fn thread_cpu_ns() -> u64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_nanos() as u64
}

/// A small deterministic generator (xorshift64*), uniform in [0, 1).
pub struct Draw(pub u64);

impl Draw {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }

    pub fn log_uniform(&mut self, r: [f64; 2]) -> f64 {
        (r[0].ln() + (r[1].ln() - r[0].ln()) * self.next()).exp()
    }
}

/// `n` physical impacts of the table's box that the table answers.
pub fn impacts(table: &Table, n: usize, elastic: bool) -> Vec<Case> {
    let info = table.info();
    let range = |name: &str| {
        let k = info.box_names.iter().position(|x| x == name).unwrap();
        info.box_ranges[k]
    };
    let mut d = Draw(0x9e37_79b9_7f4a_7c15);
    let mut out = Vec::new();
    while out.len() < n {
        let law = match table.model() {
            Model::Linear => ForceLaw::Linear(
                LinearDashpot::new(
                    d.log_uniform(range("stiffness")),
                    if elastic {
                        0.0
                    } else {
                        d.log_uniform(range("damping"))
                    },
                )
                .unwrap(),
            ),
            Model::Hertz => ForceLaw::Hertz(
                ViscoelasticHertz::new(
                    d.log_uniform(range("young")),
                    d.log_uniform(range("poisson")),
                    if elastic {
                        0.0
                    } else {
                        d.log_uniform(range("dissipation"))
                    },
                )
                .unwrap(),
            ),
        };
        let s = Sphere::from_density(
            d.log_uniform(range("radius")),
            d.log_uniform(range("density")),
        )
        .unwrap();
        let impact = Impact::from_speed_eccentricity(
            d.log_uniform(range("speed")),
            d.log_uniform(range("eccentricity")),
        )
        .unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        if table.lookup(&law, &pair, &impact).is_ok() {
            out.push((law, pair, impact));
        }
    }
    out
}
