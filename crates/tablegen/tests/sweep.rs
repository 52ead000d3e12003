//! Determinism across thread counts, shard + merge, and the table against the exact
//! solver, on tiny specs (fast).

use emdstar_table::{Table, TableError};
use emdstar_tablegen::{Spec, build, build_shard, exact_solver, merge};

const TINY_HERTZ: &str =
    "model = \"hertz\"\nbox = \"paper_table_2\"\nnodes = [6, 7, 6]\norder = [4, 4, 4]\n";
const TINY_LINEAR: &str =
    "model = \"linear\"\nbox = \"paper_table_1\"\nnodes = [5, 6, 7]\norder = [4, 4, 4]\n";

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
    let other = Spec::parse(&TINY_LINEAR.replace("[5, 6, 7]", "[5, 6, 8]")).unwrap();
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
fn table_nodes_equal_exact_solves_and_files_reload() {
    let spec = Spec::parse(TINY_HERTZ).unwrap();
    let table = build(&spec, &exact_solver, false).unwrap();
    // (NaN marks central nodes without a limit, so compare bytes, not values.)
    let bytes = table.to_bytes();
    assert!(Table::from_bytes(&bytes).unwrap().to_bytes() == bytes);
    // At a node the interpolant reproduces the solver (independent call).
    let [ax, bx, cx] = *table.axes();
    let x = emdstar_contact::RectCoords {
        a: ax.node(2),
        b: bx.node(3),
        c: cx.node(4),
    };
    let exact = exact_solver(spec.model, &table.bounds().from_rect(&x)).unwrap();
    let got = table.lookup_rect(&x).unwrap();
    for (g, e) in [
        (got.one_minus_eps_r, exact.one_minus_eps_r),
        (got.eps_rdot, exact.eps_rdot),
        (got.eps_phi, exact.eps_phi),
        (got.eps_t, exact.eps_t),
    ] {
        assert!(((g - e) / e).abs() < 1e-12, "{g} vs {e}");
    }
    assert!(matches!(
        table.expect_model(emdstar_contact::Model::Linear),
        Err(TableError::WrongModel { .. })
    ));
}
