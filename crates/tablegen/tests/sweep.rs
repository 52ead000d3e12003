//! Determinism across thread counts, shard + merge, and the table against the exact
//! solver, on tiny specs (fast).

use emdstar_table::{Table, TableError};
use emdstar_tablegen::{Spec, build, build_shard, exact_solver, merge};

const TINY_HERTZ: &str = "model = \"hertz\"\nbox = \"paper_table_2\"\ncells = [1, 1, 2]\n\
     degree = 4\ntolerance = 1e-3\nmax_depth = 2\n";
const TINY_LINEAR: &str = "model = \"linear\"\nbox = \"paper_table_1\"\ncells = [1, 2, 2]\n\
     degree = 4\ntolerance = 1e-3\nmax_depth = 2\n";

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn output_is_bitwise_identical_for_any_thread_count() {
    for text in [TINY_LINEAR, TINY_HERTZ] {
        let spec = Spec::parse(text).unwrap();
        let one = in_pool(1, || build(&spec, &exact_solver, false))
            .unwrap()
            .to_bytes();
        let three = in_pool(3, || build(&spec, &exact_solver, false))
            .unwrap()
            .to_bytes();
        assert!(
            one == three,
            "{} table differs between 1 and 3 threads",
            spec.model
        );
    }
}

#[test]
fn shards_merge_into_the_bytes_of_a_single_run() {
    let spec = Spec::parse(TINY_LINEAR).unwrap();
    let single = build(&spec, &exact_solver, false).unwrap().to_bytes();
    let n = 4;
    // Shards given out of order, as a job array may finish them.
    let parts: Vec<Vec<u8>> = [2, 0, 3, 1]
        .iter()
        .map(|&i| build_shard(&spec, &exact_solver, i, n, false).unwrap())
        .collect();
    assert!(merge(&parts).unwrap().to_bytes() == single);
    let err = merge(&parts[..3]).unwrap_err();
    assert!(err.contains("missing"), "{err}");
    let other = Spec::parse(&TINY_LINEAR.replace("1e-3", "2e-3")).unwrap();
    let foreign = build_shard(&other, &exact_solver, 1, n, false).unwrap();
    let mixed = vec![
        parts[0].clone(),
        foreign,
        parts[2].clone(),
        parts[3].clone(),
    ];
    assert!(merge(&mixed).unwrap_err().contains("different spec"));
    assert!(build_shard(&spec, &exact_solver, 4, 4, false).is_err());
}

#[test]
fn table_patches_fit_exact_solves_and_files_reload() {
    let spec = Spec::parse(
        "model = \"hertz\"\ncells = [1, 1, 1]\ndegree = 6\ntolerance = 1e-6\nmax_depth = 5\n\
         [box]\nyoung = [1e9, 2e9]\npoisson = [0.3, 0.35]\nradius = [0.01, 0.02]\n\
         density = [1000.0, 2000.0]\ndissipation = [1e-5, 2e-5]\nspeed = [0.5, 1.0]\n\
         eccentricity = [0.01, 0.5]\n",
    )
    .unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    // (NaN marks central patches without a limit, so compare bytes, not values.)
    let bytes = table.to_bytes();
    assert!(Table::from_bytes(&bytes).unwrap().to_bytes() == bytes);
    // Within the estimate of its patches: the MoR at random points against independent
    // exact solves.
    let r = table.rect();
    let mut seed = 7u64;
    let mut uniform = |lo: f64, hi: f64| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let bound = table
        .info()
        .estimated_error
        .iter()
        .fold(0.0f64, |m, e| m.max(*e));
    assert!(bound > 0.0 && bound <= 1e-5, "{bound}");
    for _ in 0..20 {
        let x = emdstar_contact::RectCoords {
            a: uniform(r[0].min, r[0].max),
            b: uniform(r[1].min, r[1].max),
            c: uniform(r[2].min, r[2].max),
        };
        let exact = exact_solver(spec.model, &table.bounds().from_rect(&x)).unwrap();
        let got = table.lookup_rect(&x).unwrap();
        for (g, e) in [
            (got.one_minus_eps_r, exact.one_minus_eps_r),
            (got.eps_rdot, exact.eps_rdot),
            (got.eps_phi, exact.eps_phi),
            (got.eps_t, exact.eps_t),
        ] {
            assert!((g / e).ln().abs() < 3.0 * bound + 1e-9, "{x:?}: {g} vs {e}");
        }
    }
    assert!(matches!(
        table.expect_model(emdstar_contact::Model::Linear),
        Err(TableError::WrongModel { .. })
    ));
}
