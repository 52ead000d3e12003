//! Interpolation against smooth synthetic functions with the same limit structure as
//! the MoR (so these tests do not need the solver).

use emdstar_contact::{ParameterBox, RectBounds, RectCoords};
use emdstar_table::{NQ, Stretch, Table, TableError, TableInfo, TableParts, grid_axes};

/// Synthetic logs at (a, b, c) with s² = e^{2(a+g_min)}, u = e^c:
/// 1−ε_r = u·A, −ε_ṙ = e^{−u·B/100}, ε_φ = s·C, ε_t = D, with A..D smooth in (s², b, u).
fn logs(bounds: &RectBounds, x: &RectCoords) -> [f64; NQ] {
    let ln_s = x.a + bounds.g.min;
    let s2 = (2.0 * ln_s).exp();
    let u = x.c.exp();
    let f = s2 / (1.0 + s2);
    let g = u / (1.0 + u);
    let a = (1.0 + 0.3 * f) * (1.0 + 0.2 * g) / (1.0 + 0.1 * x.b);
    let b = 0.5 + 0.1 * (0.3 * x.b).sin() + 0.2 * f;
    let c = (1.0 + f) * (0.7 + 0.1 * (0.4 * x.b).cos()) * (1.0 - 0.1 * g);
    let d = 3.0 + f - 0.5 * g + 0.05 * x.b;
    [x.c + a.ln(), -0.01 * u * b, ln_s + c.ln(), d.ln()]
}

pub fn synthetic_table(n: [usize; 3], order: [usize; 3]) -> Table {
    stretched_table(n, order, [Stretch::NONE; 3])
}

pub fn stretched_table(n: [usize; 3], order: [usize; 3], stretch: [Stretch; 3]) -> Table {
    let bounds = ParameterBox::paper_table_1().bounds().unwrap();
    let [ax, bx, cx] = grid_axes(&bounds, n, order, stretch);
    let mut main = vec![];
    let mut elastic = vec![];
    let mut central = vec![];
    let mut central_elastic = vec![];
    let at = |a, b, c| logs(&bounds, &RectCoords { a, b, c });
    for i in 0..ax.n {
        for j in 0..bx.n {
            for k in 0..cx.n {
                main.extend(at(ax.node(i), bx.node(j), cx.node(k)));
            }
            let mut q = at(ax.node(i), bx.node(j), -200.0);
            q[0] -= -200.0; // (1−ε_r)/u at u → 0
            elastic.extend(q);
        }
    }
    let tiny = -300.0;
    for j in 0..bx.n {
        for k in 0..cx.n {
            let mut q = at(tiny, bx.node(j), cx.node(k));
            q[2] -= tiny + bounds.g.min; // ε_φ/s at s → 0
            central.extend(q);
        }
        let mut q = at(tiny, bx.node(j), -200.0);
        q[0] -= -200.0;
        q[2] -= tiny + bounds.g.min;
        central_elastic.extend(q);
    }
    Table::from_parts(TableParts {
        bounds,
        n,
        order,
        stretch,
        main,
        elastic,
        central,
        central_elastic,
        info: TableInfo {
            generator: "synthetic".into(),
            spec: "test".into(),
            box_names: vec!["x".into()],
            box_ranges: vec![[1.0, 2.0]],
        },
    })
    .unwrap()
}

/// Largest |error| of the logs over a fixed pseudo-random set of points.
fn max_error(t: &Table, a_lo: f64, c_lo: f64) -> f64 {
    let [ax, bx, cx] = *t.axes();
    let mut seed = 12345u64;
    let mut uniform = |lo: f64, hi: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut worst: f64 = 0.0;
    for _ in 0..2000 {
        let x = RectCoords {
            a: uniform(a_lo, ax.max),
            b: uniform(bx.min, bx.max),
            c: uniform(c_lo, cx.max),
        };
        let got = t.logs_at(&x).unwrap();
        let want = logs(t.bounds(), &x);
        for q in 0..NQ {
            worst = worst.max((got[q] - want[q]).abs());
        }
    }
    worst
}

#[test]
fn error_falls_with_the_interpolation_order_and_the_grid() {
    let (lo_a, lo_c) = (0.0, ParameterBox::paper_table_1().bounds().unwrap().c.min);
    let coarse4 = max_error(&synthetic_table([12, 24, 24], [4; 3]), lo_a, lo_c);
    let fine4 = max_error(&synthetic_table([23, 47, 47], [4; 3]), lo_a, lo_c);
    let fine6 = max_error(&synthetic_table([23, 47, 47], [6; 3]), lo_a, lo_c);
    // Cubic: error ∝ h⁴, so halving h gains about 16 (allow 8 for the sample).
    assert!(fine4 < coarse4 / 8.0, "cubic: {coarse4:e} -> {fine4:e}");
    assert!(fine6 < fine4 / 4.0, "quintic {fine6:e} vs cubic {fine4:e}");
    assert!(fine6 < 1e-4, "{fine6:e}");
}

#[test]
fn a_stretched_axis_interpolates_and_round_trips() {
    let (lo_a, lo_c) = (0.0, ParameterBox::paper_table_1().bounds().unwrap().c.min);
    let stretch = Stretch {
        amount: 1.3,
        knee: 0.7,
    };
    let t = stretched_table([23, 47, 47], [6; 3], [Stretch::NONE, stretch, stretch]);
    let b = t.axes()[1];
    // Nodes crowd towards b = 0: the first spacing is about d/(d + λ) of the last.
    let (first, last) = (b.node(1) - b.node(0), b.node(b.n - 1) - b.node(b.n - 2));
    assert!(first < 0.45 * last, "{first} vs {last}");
    assert!(max_error(&t, lo_a, lo_c) < 1e-4);
    let again = Table::from_bytes(&t.to_bytes()).unwrap();
    assert_eq!(again, t);
}

#[test]
fn near_central_and_nearly_elastic_points_interpolate_the_limit_slices() {
    let t = synthetic_table([23, 47, 47], [6; 3]);
    let inside = max_error(&t, 0.0, t.axes()[2].min);
    // Below the box on a and c: linear in s² (s0² = 1e-4) and in u (u0 = 4e-6).
    let outside = max_error(&t, -8.0, t.axes()[2].min - 10.0);
    assert!(
        outside < inside.max(1e-7) * 2.0,
        "{outside:e} vs {inside:e}"
    );
    // Exact limits: c_φ = 0 gives ε_φ = 0, c_dis = 0 gives ε_r = 1 and ε_ṙ = −1.
    let central = t
        .lookup_rect(&RectCoords {
            a: f64::NEG_INFINITY,
            b: 3.0,
            c: f64::NEG_INFINITY,
        })
        .unwrap();
    assert_eq!(central.eps_phi, 0.0);
    assert_eq!(central.eps_r, 1.0);
    assert_eq!(central.eps_rdot, -1.0);
    let want = logs(
        t.bounds(),
        &RectCoords {
            a: -300.0,
            b: 3.0,
            c: -300.0,
        },
    );
    assert!((central.eps_t.ln() - want[3]).abs() < 1e-7);
}

#[test]
fn points_beyond_the_box_are_rejected_not_clamped() {
    let t = synthetic_table([8, 8, 8], [4; 3]);
    let [ax, bx, cx] = *t.axes();
    for (x, axis) in [
        (
            RectCoords {
                a: ax.max + 1e-9,
                b: 1.0,
                c: 0.0,
            },
            "a",
        ),
        (
            RectCoords {
                a: 1.0,
                b: -1e-9,
                c: 0.0,
            },
            "b",
        ),
        (
            RectCoords {
                a: 1.0,
                b: bx.max * 1.001,
                c: 0.0,
            },
            "b",
        ),
        (
            RectCoords {
                a: 1.0,
                b: 1.0,
                c: cx.max + 0.1,
            },
            "c",
        ),
        (
            RectCoords {
                a: f64::NAN,
                b: 1.0,
                c: 0.0,
            },
            "a",
        ),
    ] {
        match t.logs_at(&x) {
            Err(TableError::OutOfBox { axis: got, .. }) => assert_eq!(got, axis),
            other => panic!("{x:?}: expected OutOfBox, got {other:?}"),
        }
    }
    let err = t
        .logs_at(&RectCoords {
            a: 1.0,
            b: -1.0,
            c: 0.0,
        })
        .unwrap_err();
    assert!(
        err.to_string().contains("outside the table's box: b = -1"),
        "{err}"
    );
}

#[test]
fn files_round_trip_bit_for_bit() {
    let t = synthetic_table([6, 7, 8], [4, 6, 4]);
    let bytes = t.to_bytes();
    let back = Table::from_bytes(&bytes).unwrap();
    assert_eq!(back, t);
    assert_eq!(back.to_bytes(), bytes);
}

#[test]
fn an_independent_npz_reader_sees_the_same_arrays() {
    use ndarray::{Array1, Array4};
    use ndarray_npy::NpzReader;
    let t = synthetic_table([6, 7, 8], [4, 4, 4]);
    let mut npz = NpzReader::new(std::io::Cursor::new(t.to_bytes())).unwrap();
    let values: Array4<f64> = npz.by_name("values").unwrap();
    assert_eq!(values.shape(), &[6, 7, 8, 4]);
    assert_eq!(values[[2, 3, 4, 1]], t.node_value(2, 3, 4, 1));
    let b: Array1<f64> = npz.by_name("axis_b").unwrap();
    assert_eq!(b.len(), 7);
    assert_eq!(b[6], t.axes()[1].max);
}

mod rejections {
    use super::synthetic_table;
    use emdstar_contact::{ForceLaw, Impact, PairLaw, PairProperties, Sphere, ViscoelasticHertz};
    use emdstar_table::npz::{Array, Data, read_npz, write_npz};
    use emdstar_table::{Table, TableError};

    fn rewrite(bytes: &[u8], edit: impl Fn(&str, &mut Array)) -> Vec<u8> {
        let mut members = read_npz(bytes).unwrap();
        for (name, a) in members.iter_mut() {
            edit(name, a);
        }
        let refs: Vec<(&str, Array)> = members
            .iter()
            .map(|(n, a)| (n.as_str(), a.clone()))
            .collect();
        write_npz(&refs)
    }

    /// Recomputes the content checksum after an edit, so that only the edit is wrong.
    fn reseal(bytes: &[u8]) -> Vec<u8> {
        let members = read_npz(bytes).unwrap();
        let npys: Vec<Vec<u8>> = members[..members.len() - 1]
            .iter()
            .map(|(_, a)| a.to_npy())
            .collect();
        let refs: Vec<&[u8]> = npys.iter().map(Vec::as_slice).collect();
        let sum = emdstar_table::fnv1a64(&refs);
        rewrite(bytes, |name, a| {
            if name == "checksum" {
                *a = Array::u64_scalar(sum);
            }
        })
    }

    fn message(r: Result<Table, TableError>) -> String {
        r.expect_err("must be rejected").to_string()
    }

    #[test]
    fn wrong_model() {
        let t = synthetic_table([6, 6, 6], [4; 3]);
        let s = Sphere::from_density(0.01, 2000.0).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = PairLaw::same_material(
            &ForceLaw::Hertz(ViscoelasticHertz::new(1e9, 0.3, 1e-5).unwrap()),
            pair.r_eff,
        )
        .unwrap();
        let err = t
            .lookup(
                &law,
                &pair,
                &Impact::from_speed_eccentricity(1.0, 0.5).unwrap(),
            )
            .unwrap_err();
        assert_eq!(
            err.to_string(),
            "wrong model: the table is for the linear model but the hertz model was requested; \
             load a hertz table"
        );
    }

    #[test]
    fn truncated_file() {
        let bytes = synthetic_table([6, 6, 6], [4; 3]).to_bytes();
        for cut in [bytes.len() - 1, bytes.len() / 2, 100] {
            let msg = message(Table::from_bytes(&bytes[..cut]));
            assert!(
                msg.starts_with("the table file is truncated"),
                "{cut}: {msg}"
            );
        }
        let msg = message(Table::from_bytes(b"hello"));
        assert!(msg.starts_with("not an emdstar MoR table"), "{msg}");
    }

    #[test]
    fn checksum_mismatch() {
        let bytes = synthetic_table([6, 6, 6], [4; 3]).to_bytes();
        // Flip one bit in the middle of the data (inside the `values` member).
        let mut bad = bytes.clone();
        let i = bytes.len() / 2;
        bad[i] ^= 0x10;
        let msg = message(Table::from_bytes(&bad));
        assert!(
            msg.starts_with("checksum mismatch") && msg.contains("CRC-32"),
            "{msg}"
        );
        // A consistent archive whose content checksum does not match.
        let edited = rewrite(&bytes, |name, a| {
            if name == "values"
                && let Data::F64(v) = &mut a.data
            {
                v[7] += 1e-3;
            }
        });
        let msg = message(Table::from_bytes(&edited));
        assert!(
            msg.starts_with("checksum mismatch") && msg.contains("content checksum stored"),
            "{msg}"
        );
    }

    #[test]
    fn corrupt_data() {
        let bytes = synthetic_table([6, 6, 6], [4; 3]).to_bytes();
        let nan = reseal(&rewrite(&bytes, |name, a| {
            if name == "values"
                && let Data::F64(v) = &mut a.data
            {
                v[11] = f64::NAN;
            }
        }));
        let msg = message(Table::from_bytes(&nan));
        assert!(
            msg.contains("corrupt table data: values holds a non-finite value at flat index 11"),
            "{msg}"
        );
        let shape = reseal(&rewrite(&bytes, |name, a| {
            if name == "elastic" {
                a.shape = vec![a.len()];
            }
        }));
        let msg = message(Table::from_bytes(&shape));
        assert!(
            msg.contains("corrupt table data: elastic should be a float64 array"),
            "{msg}"
        );
    }

    #[test]
    fn unknown_version() {
        let bytes = synthetic_table([6, 6, 6], [4; 3]).to_bytes();
        let v1 = rewrite(&bytes, |name, a| {
            if name == "format_version" {
                *a = Array::i64(vec![], vec![1]);
            }
        });
        assert_eq!(
            message(Table::from_bytes(&v1)),
            "unknown table format version 1 (this reader supports version 2); use a matching \
             emdstar release or rebuild the table"
        );
    }
}
