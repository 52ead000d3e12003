//! A hand-made table of known polynomials: the reader's Chebyshev-to-monomial change
//! and evaluation against a direct sum of Chebyshev products, the tree walk, the limit
//! pieces, the file round trip (also through an independent `.npz` reader), and the
//! rejection of bad files and of points beyond the box.

use emdstar_contact::{ParameterBox, RectBounds, RectCoords};
use emdstar_table::{
    BMap, LEAF, NQ, PIECES, PieceParts, Table, TableError, TableInfo, TableParts, Terms,
};

const DEGREE: usize = 3;

/// Coefficient `k` of patch `p`, quantity `q`: multiples of 1/8192 (and so of the
/// file's quantum, which leaves them alone), small beyond the constant term.
fn coef(p: usize, k: usize, q: usize) -> f64 {
    let h = (p * 131 + k * 31 + q * 7) % 97;
    if k == 0 {
        -1.0 - q as f64 + h as f64 / 1024.0
    } else {
        (h as f64 - 48.0) / 8192.0
    }
}

fn terms(piece: usize) -> Terms {
    let active = PIECES[piece].1;
    Terms::new(
        DEGREE,
        std::array::from_fn(|k| if active[k] { DEGREE } else { 0 }),
    )
}

fn bounds() -> RectBounds {
    ParameterBox::paper_table_1().bounds().unwrap()
}

/// The main piece splits a at its midpoint, then the upper half along c; the limit
/// pieces are one patch each.
fn parts() -> TableParts {
    let rect = bounds().axes();
    let piece = |k: usize| {
        let nt = terms(k).len();
        let (tree, split, patches) = if k == 0 {
            let a_mid = 0.5 * (rect[0].min + rect[0].max);
            let c_mid = 0.5 * (rect[2].min + rect[2].max);
            (
                vec![[0, 1], [LEAF, 0], [2, 3], [LEAF, 1], [LEAF, 2]],
                vec![a_mid, 0.0, c_mid, 0.0, 0.0],
                3,
            )
        } else {
            (vec![[LEAF, 0]], vec![0.0], 1)
        };
        PieceParts {
            cells: [1, 1, 1],
            roots: vec![0],
            tree,
            split,
            cheb: (0..patches * nt)
                .map(|i| std::array::from_fn(|q| coef(100 * k + i / nt, i % nt, q)))
                .collect(),
        }
    };
    TableParts {
        bounds: bounds(),
        b_map: BMap {
            b_min: rect[1].min,
            knee: 0.0,
        },
        degree: DEGREE,
        main: piece(0),
        elastic: piece(1),
        central: piece(2),
        central_elastic: piece(3),
        info: TableInfo {
            generator: "hand-made".into(),
            spec: "test".into(),
            box_names: vec!["x".into()],
            box_ranges: vec![[1.0, 2.0]],
            tolerance: 1e-3,
            estimated_error: [1e-4; 4],
        },
    }
}

fn table() -> Table {
    Table::from_parts(parts()).unwrap()
}

/// Σ c T_i(t_a) T_j(t_b) T_k(t_c) with T_n(t) = cos(n arccos t).
fn chebyshev_sum(piece: usize, patch: usize, t: [f64; 3]) -> [f64; NQ] {
    let terms = terms(piece);
    let cheb = |n: usize, x: f64| (n as f64 * x.clamp(-1.0, 1.0).acos()).cos();
    let mut out = [0.0; NQ];
    for (k, p) in terms.powers.iter().enumerate() {
        let w = cheb(p[0], t[0]) * cheb(p[1], t[1]) * cheb(p[2], t[2]);
        for (q, o) in out.iter_mut().enumerate() {
            *o += w * coef(100 * piece + patch, k, q);
        }
    }
    out
}

fn local(x: f64, lo: f64, hi: f64) -> f64 {
    (2.0 * x - lo - hi) / (hi - lo)
}

#[test]
fn lookups_evaluate_the_patch_polynomial_of_their_leaf() {
    let t = table();
    let r = bounds().axes();
    let (a_mid, c_mid) = (0.5 * (r[0].min + r[0].max), 0.5 * (r[2].min + r[2].max));
    for (a, b, c) in [
        (0.3, 2.0, -3.0),
        (4.0, 7.5, 1.0),
        (4.4, 0.5, -9.0),
        (1.0, 9.0, 2.0),
    ] {
        let x = RectCoords { a, b, c };
        let got = t.logs_at(&x).unwrap();
        let tb = local(b, r[1].min, r[1].max);
        let want = if a < a_mid {
            chebyshev_sum(
                0,
                0,
                [local(a, r[0].min, a_mid), tb, local(c, r[2].min, r[2].max)],
            )
        } else if c < c_mid {
            chebyshev_sum(
                0,
                1,
                [local(a, a_mid, r[0].max), tb, local(c, r[2].min, c_mid)],
            )
        } else {
            chebyshev_sum(
                0,
                2,
                [local(a, a_mid, r[0].max), tb, local(c, c_mid, r[2].max)],
            )
        };
        for q in 0..NQ {
            assert!(
                (got[q] - want[q]).abs() < 1e-13,
                "{x:?} q{q}: {got:?} vs {want:?}"
            );
        }
    }
    assert_eq!(t.pieces()[0].patch_count(), 3);
}

/// The reference value of the hand-made main piece at (a, b, c): its three patches.
fn main_piece_sum(x: &RectCoords) -> [f64; NQ] {
    let r = bounds().axes();
    let (a_mid, c_mid) = (0.5 * (r[0].min + r[0].max), 0.5 * (r[2].min + r[2].max));
    let tb = local(x.b, r[1].min, r[1].max);
    if x.a < a_mid {
        let t = [
            local(x.a, r[0].min, a_mid),
            tb,
            local(x.c, r[2].min, r[2].max),
        ];
        chebyshev_sum(0, 0, t)
    } else if x.c < c_mid {
        let t = [local(x.a, a_mid, r[0].max), tb, local(x.c, r[2].min, c_mid)];
        chebyshev_sum(0, 1, t)
    } else {
        let t = [local(x.a, a_mid, r[0].max), tb, local(x.c, c_mid, r[2].max)];
        chebyshev_sum(0, 2, t)
    }
}

#[test]
fn pair_tables_evaluate_the_patch_polynomials_on_the_pair_s_plane() {
    use emdstar_contact::{ForceLaw, Impact, LinearDashpot, PairLaw, PairProperties, Sphere};
    let t = table();
    let r = bounds().axes();
    let mut compared = 0;
    for (k, gamma) in [(5e4, 0.05), (1e3, 0.3), (2e5, 2.0)] {
        let s = Sphere::from_density(0.05, 1140.0).unwrap();
        let pair = PairProperties::spheres(&s, &s);
        let law = ForceLaw::Linear(LinearDashpot::new(k, gamma).unwrap());
        let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
        let own = t.pair_table(&law, &pair).unwrap();
        let map = emdstar_table::PairMap::new(&law, &pair).unwrap();
        for v in [0.002, 0.03, 0.4, 3.0, 20.0] {
            for e in [0.05, 0.3, 0.7, 0.95] {
                let impact = Impact::from_speed_eccentricity(v, e).unwrap();
                let (x, _) = map.coords(t.bounds(), &impact).unwrap();
                let inside = x.a >= r[0].min && x.a <= r[0].max && x.c >= r[2].min;
                if !(inside && x.c <= r[2].max && x.b >= r[1].min && x.b <= r[1].max) {
                    continue;
                }
                assert!(own.patch_count() > 0);
                let got = emdstar_table::mor_to_logs(&own.lookup(&impact).unwrap().mor);
                let want = main_piece_sum(&x);
                for q in 0..NQ {
                    assert!(
                        (got[q] - want[q]).abs() < 1e-8,
                        "{x:?} q{q}: {got:?} {want:?}"
                    );
                }
                compared += 1;
            }
        }
    }
    assert!(
        compared >= 10,
        "only {compared} impacts fell into the main piece"
    );
}

#[test]
fn a_tree_too_deep_to_restrict_leaves_pairs_to_the_full_table() {
    use emdstar_contact::{ForceLaw, Impact, LinearDashpot, PairLaw, PairProperties, Sphere};
    // A chain of splits along a, 20 000 deep: each node's lower child a patch.
    let mut p = parts();
    let r = bounds().axes();
    let depth = 20_000;
    let (mut tree, mut split) = (Vec::new(), Vec::new());
    for j in 0..depth {
        // Node 2j's children: 2j + 1 (its patch) and 2j + 2 (the next split).
        let n = tree.len() as i64;
        tree.extend([[0, n + 1], [LEAF, j as i64]]);
        let s = r[0].min + (r[0].max - r[0].min) * (j + 1) as f64 / (depth + 1) as f64;
        split.extend([s, 0.0]);
    }
    tree.push([LEAF, depth as i64]);
    split.push(0.0);
    let nt = terms(0).len();
    p.main = PieceParts {
        cells: [1, 1, 1],
        roots: vec![0],
        tree,
        split,
        cheb: (0..(depth + 1) * nt)
            .map(|i| std::array::from_fn(|q| coef(i / nt, i % nt, q)))
            .collect(),
    };
    let t = Table::from_parts(p).unwrap();
    let s = Sphere::from_density(0.05, 1140.0).unwrap();
    let pair = PairProperties::spheres(&s, &s);
    let law = ForceLaw::Linear(LinearDashpot::new(5e4, 0.05).unwrap());
    let law = PairLaw::same_material(&law, pair.r_eff).unwrap();
    let own = t.pair_table(&law, &pair).unwrap();
    assert_eq!(own.patch_count(), 0);
    let impact = Impact::from_speed_eccentricity(0.4, 0.3).unwrap();
    let full = t.lookup(&law, &pair, &impact);
    assert_eq!(format!("{:?}", own.lookup(&impact)), format!("{full:?}"));
}

#[test]
fn the_limits_are_exact_and_the_extensions_interpolate() {
    let t = table();
    let r = bounds().axes();
    let b = 3.0;
    let tb = local(b, r[1].min, r[1].max);
    // c_φ = 0 and c_dis = 0 at once: the central-elastic line, with ε_φ = 0 and ε_r = 1
    // exactly (the factors s and u of the stored forms vanish).
    let m = t
        .lookup_rect(&RectCoords {
            a: f64::NEG_INFINITY,
            b,
            c: f64::NEG_INFINITY,
        })
        .unwrap();
    assert_eq!((m.eps_phi, m.eps_r), (0.0, 1.0));
    let line = chebyshev_sum(3, 0, [0.0, tb, 0.0]);
    assert!((m.eps_t.ln() - line[3]).abs() < 1e-13);
    assert!(((-m.eps_rdot).ln() - line[1]).abs() < 1e-13);
    // Below the box in c only: linear in u = e^{c − c_min} between the elastic piece
    // and the face c = c_min of the main piece, with 1−ε_r carrying the factor u.
    let (a, c) = (1.0, r[2].min - 2.0);
    let got = t.logs_at(&RectCoords { a, b, c }).unwrap();
    let u = (c - r[2].min).exp();
    let ta = local(a, r[0].min, 0.5 * (r[0].min + r[0].max));
    let lo = chebyshev_sum(1, 0, [local(a, r[0].min, r[0].max), tb, 0.0]);
    let mut hi = chebyshev_sum(0, 0, [ta, tb, -1.0]);
    hi[0] -= r[2].min;
    for q in 0..NQ {
        let mut want = lo[q] + u * (hi[q] - lo[q]);
        if q == 0 {
            want += c;
        }
        assert!((got[q] - want).abs() < 1e-12, "q{q}: {got:?}");
    }
}

#[test]
fn points_beyond_the_box_are_rejected_not_clamped() {
    let t = table();
    let [ra, rb, rc] = t.rect();
    for (x, axis) in [
        (
            RectCoords {
                a: ra.max + 1e-9,
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
                b: rb.max * 1.001,
                c: 0.0,
            },
            "b",
        ),
        (
            RectCoords {
                a: 1.0,
                b: 1.0,
                c: rc.max + 0.1,
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
    let t = table();
    let bytes = t.to_bytes();
    let back = Table::from_bytes(&bytes).unwrap();
    assert_eq!(back, t);
    assert_eq!(back.to_bytes(), bytes);
}

#[test]
fn an_independent_npz_reader_sees_the_same_arrays() {
    use ndarray::{Array1, Array2};
    use ndarray_npy::NpzReader;
    let t = table();
    let mut npz = NpzReader::new(std::io::Cursor::new(t.to_bytes())).unwrap();
    let tree: Array2<i64> = npz.by_name("main_tree").unwrap();
    assert_eq!(tree.shape(), &[5, 2]);
    assert_eq!(tree[[2, 0]], 2);
    let patches: ndarray::Array0<i64> = npz.by_name("main_patches").unwrap();
    assert_eq!(patches.into_scalar(), 3);
    // The first patch's first group: the tabulated bit, then the 6-bit width of the
    // constant term of quantity 0 and the term itself, as a zigzag multiple of the
    // quantum (a power of two: 2^-18 for the tolerance 1e-3).
    let bits: Array1<u64> = npz.by_name("main_coef_bits").unwrap();
    let word = bits[0];
    assert_eq!(word & 1, 1);
    let width = (word >> 1) & 63;
    let k = (word >> 7) & ((1 << width) - 1);
    let c0 = coef(0, 0, 0);
    assert!(c0 < 0.0);
    assert_eq!(k, (-2.0 * c0 * 2f64.powi(18)) as u64 - 1);
    let degree: ndarray::Array0<i64> = npz.by_name("degree").unwrap();
    assert_eq!(degree.into_scalar(), DEGREE as i64);
    let split: Array1<f64> = npz.by_name("main_split").unwrap();
    assert_eq!(split.len(), 5);
}

mod rejections {
    use super::{parts, table};
    use emdstar_contact::{ForceLaw, Impact, PairLaw, PairProperties, Sphere, ViscoelasticHertz};
    use emdstar_table::npz::{Array, Data, read_npz, write_npz};
    use emdstar_table::{LEAF, Table, TableError};

    fn rewrite(bytes: &[u8], edit: impl Fn(&str, &mut Array)) -> Vec<u8> {
        let mut members = read_npz(bytes).unwrap();
        for (name, a) in members.iter_mut() {
            edit(name, a);
        }
        write_npz(&members)
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
        let t = table();
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
        let bytes = table().to_bytes();
        for cut in [bytes.len() - 1, bytes.len() / 2, 100] {
            let msg = message(Table::from_bytes(&bytes[..cut]));
            assert!(
                msg.starts_with("the table file is truncated: the zip ")
                    && msg.contains(" is missing or cut short")
                    && msg.contains("emdstar table build"),
                "{cut}: {msg}"
            );
        }
        // The message is one sentence: no doubled negation of the missing record.
        let msg = message(Table::from_bytes(&bytes[..bytes.len() - 1]));
        assert!(!msg.contains("no zip"), "{msg}");
        let msg = message(Table::from_bytes(b"hello"));
        assert!(msg.starts_with("not an emdstar MoR table"), "{msg}");
    }

    #[test]
    fn checksum_mismatch() {
        let bytes = table().to_bytes();
        // Flip one bit of the first split coordinate.
        let r = super::bounds().axes();
        let first = (0.5 * (r[0].min + r[0].max)).to_le_bytes();
        let i = bytes
            .windows(8)
            .position(|w| w == first)
            .expect("the coefficient is stored");
        let mut bad = bytes.clone();
        bad[i + 3] ^= 0x10;
        let msg = message(Table::from_bytes(&bad));
        assert!(
            msg.starts_with("checksum mismatch") && msg.contains("CRC-32"),
            "{msg}"
        );
        let edited = rewrite(&bytes, |name, a| {
            if name == "main_split"
                && let Data::F64(v) = &mut a.data
            {
                v[0] += 1e-3;
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
        let bytes = table().to_bytes();
        let quantum = reseal(&rewrite(&bytes, |name, a| {
            if name == "quantum"
                && let Data::F64(v) = &mut a.data
            {
                v[0] *= 2.0;
            }
        }));
        let msg = message(Table::from_bytes(&quantum));
        assert!(msg.contains("quantum is not"), "{msg}");
        let cut = reseal(&rewrite(&bytes, |name, a| {
            if name == "main_coef_bits"
                && let Data::U64(v) = &mut a.data
            {
                v.pop();
                a.shape = vec![v.len()];
            }
        }));
        let msg = message(Table::from_bytes(&cut));
        assert!(msg.contains("main_coef_bits: "), "{msg}");
        let mut p = parts();
        p.main.cheb[11][1] = f64::NAN;
        let msg = Table::from_parts(p).unwrap_err().to_string();
        assert!(
            msg.contains("main: patch 0 holds a non-finite coefficient"),
            "{msg}"
        );
        let shape = reseal(&rewrite(&bytes, |name, a| {
            if name == "elastic_split" {
                a.shape = vec![a.len(), 1];
            }
        }));
        let msg = message(Table::from_bytes(&shape));
        assert!(
            msg.contains("elastic_split should be a float64 array"),
            "{msg}"
        );
    }

    #[test]
    fn malformed_trees() {
        type Edit = fn(&mut emdstar_table::TableParts);
        let cases: [(&str, Edit); 5] = [
            ("is not reachable", |p| p.main.tree[0] = [LEAF, 0]),
            ("has children", |p| p.main.tree[2] = [2, 1]),
            ("outside its box", |p| p.main.split[2] = 1e6),
            ("missing or taken", |p| p.main.tree[4] = [LEAF, 1]),
            ("malformed tree node", |p| p.main.tree[0] = [7, 1]),
        ];
        for (want, edit) in cases {
            let mut p = parts();
            edit(&mut p);
            let msg = Table::from_parts(p).unwrap_err().to_string();
            assert!(msg.contains(want), "{want}: {msg}");
        }
    }

    #[test]
    fn unknown_version() {
        let bytes = table().to_bytes();
        let v2 = rewrite(&bytes, |name, a| {
            if name == "format_version" {
                *a = Array::i64(vec![], vec![2]);
            }
        });
        assert_eq!(
            message(Table::from_bytes(&v2)),
            "unknown table format version 2 (this reader supports version 4); use a matching \
             emdstar release or rebuild the table"
        );
    }
}
