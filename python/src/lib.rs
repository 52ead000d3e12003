//! The compiled core of the `emdstar` Python package: flat float64 arrays in, flat
//! arrays out. Broadcasting, keyword checks and result dictionaries live in the Python
//! layer (`emdstar/__init__.py`).

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, Mor, PairLaw, PairProperties, ScaledParams, Sphere,
    Vec3, ViscoelasticHertz, scale,
};
use emdstar_mor::rule::{Body, resolve};
use emdstar_table::{PairMap, PairTable, Table, TableError};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::Arc;

use emdstar_table::SharedTable as TableRef;

mod run;

// Huge pages under large arrays (the engines' particle records at N ≈ 10⁶); see the crate.
#[global_allocator]
static ALLOCATOR: emdstar_hugepages::HugePages = emdstar_hugepages::HugePages;

fn table_error(e: TableError) -> PyErr {
    match e {
        TableError::Io(_) => PyOSError::new_err(e.to_string()),
        TableError::OutOfBox { .. }
        | TableError::NotTabulated(_)
        | TableError::Input(_)
        | TableError::WrongModel { .. } => PyValueError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

fn model_of(name: &str) -> PyResult<Model> {
    name.parse::<Model>().map_err(value_error)
}

/// A matrix-of-restitution table (immutable; safe to share between threads).
#[pyclass(frozen, name = "Table", module = "emdstar._core")]
struct PyTable {
    table: TableRef,
}

#[pymethods]
impl PyTable {
    /// The default table of "linear" or "hertz", embedded in the package (parsed once).
    #[staticmethod]
    fn default(model: &str) -> PyResult<Self> {
        let t = emdstar_table::default_table(model_of(model)?).map_err(table_error)?;
        Ok(Self {
            table: TableRef::Static(t),
        })
    }

    /// A table file (`emdstar table build SPEC` writes them).
    #[staticmethod]
    fn load(path: std::path::PathBuf) -> PyResult<Self> {
        let t = Table::open(&path).map_err(table_error)?;
        Ok(Self {
            table: TableRef::Owned(Arc::new(t)),
        })
    }

    #[getter]
    fn model(&self) -> &'static str {
        self.table.model().name()
    }

    #[getter]
    fn tolerance(&self) -> f64 {
        self.table.info().tolerance
    }

    #[getter]
    fn estimated_error(&self) -> [f64; 4] {
        self.table.info().estimated_error
    }

    #[getter]
    fn rect(&self) -> [[f64; 2]; 3] {
        self.table.rect().map(|r| [r.min, r.max])
    }

    /// The physical box: {name: (min, max)} in SI units.
    #[getter]
    fn parameter_box<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let info = self.table.info();
        for (n, r) in info.box_names.iter().zip(&info.box_ranges) {
            d.set_item(n, (r[0], r[1]))?;
        }
        Ok(d)
    }

    /// MoR arrays (1−ε_r, ε_r, ε_ṙ, ε_φ, ε_t, T, source) of impacts given as
    /// equal-length arrays: the law's two or three parameters, and the geometry
    /// (radius, density, radius2, density2, speed, eccentricity).
    fn lookup<'py>(
        &self,
        py: Python<'py>,
        law: Vec<PyReadonlyArray1<'py, f64>>,
        geometry: Vec<PyReadonlyArray1<'py, f64>>,
        exact_fallback: bool,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let inputs = Inputs::new(&law, &geometry)?;
        let model = self.table.model();
        let mut out = Outputs::new(inputs.n);
        for i in 0..inputs.n {
            let (law, pair, impact) = inputs.case(model, i)?;
            let map = PairMap::new(&law, &pair).map_err(table_error)?;
            let hit = self.table.lookup_pair(&map, &impact);
            out.push_lookup(i, hit, exact_fallback, model, &map, &impact)?;
        }
        Ok(out.into_arrays(py))
    }

    /// This table restricted to one pair (`law`: the law's parameters; `geometry`:
    /// radius, density, radius2, density2, scalars; radius2 = 0: a flat wall).
    fn pair(&self, law: Vec<f64>, geometry: [f64; 4]) -> PyResult<PyPairTable> {
        let (law, pair) = law_and_pair(self.table.model(), &law, geometry)?;
        Ok(PyPairTable {
            own: PairTable::new(self.table.clone(), &law, &pair).map_err(table_error)?,
        })
    }
}

/// A table restricted to the impacts of one pair (`emdstar_table::PairTable`):
/// immutable, safe to share between threads.
#[pyclass(frozen, name = "PairTable", module = "emdstar._core")]
struct PyPairTable {
    own: PairTable<TableRef>,
}

#[pymethods]
impl PyPairTable {
    /// MoR arrays of the pair's impacts (equal-length speed and eccentricity arrays),
    /// in the columns of `Table.lookup`.
    fn lookup<'py>(
        &self,
        py: Python<'py>,
        speed: PyReadonlyArray1<'py, f64>,
        eccentricity: PyReadonlyArray1<'py, f64>,
        exact_fallback: bool,
    ) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
        let (v, e) = (speed.as_slice()?, eccentricity.as_slice()?);
        if v.len() != e.len() {
            return Err(PyValueError::new_err("the input arrays differ in length"));
        }
        let model = self.own.table().model();
        let mut out = Outputs::new(v.len());
        for (i, (&v, &e)) in v.iter().zip(e).enumerate() {
            let impact = Impact::from_speed_eccentricity(v, e).map_err(value_error)?;
            let hit = self.own.lookup(&impact);
            out.push_lookup(i, hit, exact_fallback, model, self.own.map(), &impact)?;
        }
        Ok(out.into_arrays(py))
    }

    /// Number of two-dimensional patches of the restriction (0: every lookup goes
    /// through the full table).
    #[getter]
    fn patches(&self) -> usize {
        self.own.patch_count()
    }

    /// Bytes the restriction holds.
    #[getter]
    fn nbytes(&self) -> usize {
        self.own.bytes()
    }
}

/// A law of `model` from its parameters and the pair of spheres (radius, density,
/// radius2, density2; radius2 = 0: a flat wall).
fn law_and_pair(
    model: Model,
    law: &[f64],
    [r1, rho1, r2, rho2]: [f64; 4],
) -> PyResult<(PairLaw, PairProperties)> {
    let law = match (model, law.len()) {
        (Model::Linear, 2) => {
            ForceLaw::Linear(LinearDashpot::new(law[0], law[1]).map_err(value_error)?)
        }
        (Model::Hertz, 3) => {
            ForceLaw::Hertz(ViscoelasticHertz::new(law[0], law[1], law[2]).map_err(value_error)?)
        }
        _ => return Err(PyValueError::new_err("wrong number of law parameters")),
    };
    let a = Sphere::from_density(r1, rho1).map_err(value_error)?;
    let pair = if r2 == 0.0 {
        PairProperties::sphere_wall(&a)
    } else {
        PairProperties::spheres(&a, &Sphere::from_density(r2, rho2).map_err(value_error)?)
    };
    let law = PairLaw::same_material(&law, pair.r_eff).map_err(value_error)?;
    Ok((law, pair))
}

/// Equal-length input columns.
struct Inputs<'a> {
    n: usize,
    law: Vec<&'a [f64]>,
    cols: [&'a [f64]; 6],
}

impl<'a> Inputs<'a> {
    /// `law`: the law's parameters; `geometry`: radius, density, radius2, density2,
    /// speed, eccentricity.
    fn new(
        law: &'a [PyReadonlyArray1<'a, f64>],
        geometry: &'a [PyReadonlyArray1<'a, f64>],
    ) -> PyResult<Self> {
        let slices = |a: &'a [PyReadonlyArray1<'a, f64>]| -> PyResult<Vec<&'a [f64]>> {
            a.iter()
                .map(|a| a.as_slice())
                .collect::<Result<_, _>>()
                .map_err(value_error)
        };
        let law = slices(law)?;
        let cols = slices(geometry)?;
        if cols.len() != 6 {
            return Err(PyValueError::new_err(
                "geometry needs radius, density, radius2, density2, speed, eccentricity",
            ));
        }
        let n = cols[0].len();
        if law.iter().chain(&cols).any(|c| c.len() != n) {
            return Err(PyValueError::new_err("the input arrays differ in length"));
        }
        Ok(Self {
            n,
            law,
            cols: cols.try_into().expect("six columns"),
        })
    }

    /// Law, pair and impact of case `i` (radius2 = 0: a flat wall).
    fn case(&self, model: Model, i: usize) -> PyResult<(PairLaw, PairProperties, Impact)> {
        let [r1, rho1, r2, rho2, v, e] = self.cols.map(|c| c[i]);
        // At most three law parameters, gathered without an allocation per impact.
        let mut buffer = [0.0; 3];
        let Some(law) = buffer.get_mut(..self.law.len()) else {
            return Err(PyValueError::new_err("wrong number of law parameters"));
        };
        for (p, column) in law.iter_mut().zip(&self.law) {
            *p = column[i];
        }
        let (law, pair) = law_and_pair(model, law, [r1, rho1, r2, rho2])?;
        let impact = Impact::from_speed_eccentricity(v, e).map_err(value_error)?;
        Ok((law, pair, impact))
    }
}

/// Output columns of MoR lookups.
struct Outputs {
    cols: [Vec<f64>; 7],
}

impl Outputs {
    fn new(n: usize) -> Self {
        Self {
            cols: std::array::from_fn(|_| Vec::with_capacity(n)),
        }
    }

    fn push(&mut self, m: &Mor, time: f64, source: f64) {
        for (c, x) in self.cols.iter_mut().zip([
            m.one_minus_eps_r,
            m.eps_r,
            m.eps_rdot,
            m.eps_phi,
            m.eps_t,
            time,
            source,
        ]) {
            c.push(x);
        }
    }

    /// Pushes impact `i`'s table answer, or with `exact_fallback` its exact solve where
    /// the table does not answer; other errors name the impact.
    fn push_lookup(
        &mut self,
        i: usize,
        hit: Result<emdstar_table::PhysicalLookup, TableError>,
        exact_fallback: bool,
        model: Model,
        map: &PairMap,
        impact: &Impact,
    ) -> PyResult<()> {
        match hit {
            Ok(hit) => self.push(&hit.mor, hit.time, 0.0),
            Err(TableError::OutOfBox { .. } | TableError::NotTabulated(_)) if exact_fallback => {
                let s = scale(map.law(), map.pair(), impact).map_err(value_error)?;
                let m = emdstar_mor::solve(model, &s.params)
                    .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                self.push(&m, s.time, 1.0);
            }
            Err(e) => return Err(PyValueError::new_err(format!("impact {i}: {e}"))),
        }
        Ok(())
    }

    fn into_arrays(self, py: Python<'_>) -> Vec<Bound<'_, PyArray1<f64>>> {
        self.cols.into_iter().map(|c| c.into_pyarray(py)).collect()
    }
}

/// The dissipation (γ for "linear", A for "hertz") with which a central impact of each
/// pair (elastic law parameters; radius, density, radius2, density2) at normal speed
/// `speed` has normal restitution `restitution` (Müller & Pöschel 2013's exact
/// collision, inverted as `emdstar mor --restitution` does).
#[pyfunction]
fn dissipation_for_restitution<'py>(
    py: Python<'py>,
    model: &str,
    elastic: Vec<PyReadonlyArray1<'py, f64>>,
    geometry: Vec<PyReadonlyArray1<'py, f64>>,
    restitution: PyReadonlyArray1<'py, f64>,
    speed: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let model = model_of(model)?;
    fn cols<'a>(a: &'a [PyReadonlyArray1<'_, f64>]) -> PyResult<Vec<&'a [f64]>> {
        a.iter()
            .map(|c| c.as_slice().map_err(value_error))
            .collect()
    }
    let (elastic, geometry) = (cols(&elastic)?, cols(&geometry)?);
    let (e, v) = (restitution.as_slice()?, speed.as_slice()?);
    let n = e.len();
    if geometry.len() != 4 || elastic.iter().chain(&geometry).any(|c| c.len() != n) || v.len() != n
    {
        return Err(PyValueError::new_err("the input arrays differ in length"));
    }
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut law: Vec<f64> = elastic.iter().map(|c| c[i]).collect();
        law.push(0.0);
        let g = [
            geometry[0][i],
            geometry[1][i],
            geometry[2][i],
            geometry[3][i],
        ];
        let (_, pair) = law_and_pair(model, &law, g)?;
        let material = match model {
            Model::Linear => {
                ForceLaw::Linear(LinearDashpot::new(law[0], 0.0).map_err(value_error)?)
            }
            Model::Hertz => {
                ForceLaw::Hertz(ViscoelasticHertz::new(law[0], law[1], 0.0).map_err(value_error)?)
            }
        };
        let fitted =
            emdstar_mor::with_restitution(&material, &pair, v[i], e[i]).map_err(|err| {
                PyValueError::new_err(format!("impact {i}: restitution {}: {err}", e[i]))
            })?;
        out.push(match fitted {
            ForceLaw::Linear(l) => l.damping,
            ForceLaw::Hertz(h) => h.dissipation,
        });
    }
    Ok(out.into_pyarray(py))
}

/// Exact MoR arrays of impacts (same inputs as `Table.lookup`), one ODE solve each.
#[pyfunction]
fn exact<'py>(
    py: Python<'py>,
    model: &str,
    law: Vec<PyReadonlyArray1<'py, f64>>,
    geometry: Vec<PyReadonlyArray1<'py, f64>>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let model = model_of(model)?;
    let inputs = Inputs::new(&law, &geometry)?;
    let mut out = Outputs::new(inputs.n);
    for i in 0..inputs.n {
        let (law, pair, impact) = inputs.case(model, i)?;
        let s = scale(&law, &pair, &impact).map_err(value_error)?;
        let m = emdstar_mor::solve(model, &s.params)
            .map_err(|e| PyRuntimeError::new_err(format!("impact {i}: {e}")))?;
        out.push(&m, s.time, 1.0);
    }
    Ok(out.into_arrays(py))
}

/// Exact MoR at scaled parameters (l̃, c_φ, c_dis) arrays.
#[pyfunction]
fn exact_scaled<'py>(
    py: Python<'py>,
    model: &str,
    l_tilde: PyReadonlyArray1<'py, f64>,
    c_phi: PyReadonlyArray1<'py, f64>,
    c_dis: PyReadonlyArray1<'py, f64>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let model = model_of(model)?;
    let (l, c, d) = (
        l_tilde.as_slice().map_err(value_error)?,
        c_phi.as_slice().map_err(value_error)?,
        c_dis.as_slice().map_err(value_error)?,
    );
    if c.len() != l.len() || d.len() != l.len() {
        return Err(PyValueError::new_err("the input arrays differ in length"));
    }
    let mut out = Outputs::new(l.len());
    for i in 0..l.len() {
        let p = ScaledParams::new(l[i], c[i], d[i]).map_err(value_error)?;
        let m = emdstar_mor::solve(model, &p)
            .map_err(|e| PyRuntimeError::new_err(format!("point {i}: {e}")))?;
        out.push(&m, 0.0, 1.0);
    }
    Ok(out.into_arrays(py))
}

/// How far the centre distance of a pair given to `collide` may be from the sum of the
/// radii, relative to it (the round-off of positions computed at first touch).
const CONTACT_TOLERANCE: f64 = 1e-6;

/// The eMD* lab-frame collision rule (Müller & Pöschel 2013, Sec. IV) applied to
/// given MoRs: positions and velocities (n×3, flattened) of both spheres at first
/// touch, their masses and contact distances, the MoR columns and time scales.
/// Returns x1, v1, x2, v2 after the collision, the rotated positions of the E^φ event,
/// the transient (centre-of-mass) velocity, and the durations.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
fn resolve_collisions<'py>(
    py: Python<'py>,
    x1: PyReadonlyArray1<'py, f64>,
    v1: PyReadonlyArray1<'py, f64>,
    x2: PyReadonlyArray1<'py, f64>,
    v2: PyReadonlyArray1<'py, f64>,
    m1: PyReadonlyArray1<'py, f64>,
    m2: PyReadonlyArray1<'py, f64>,
    contact: PyReadonlyArray1<'py, f64>,
    mor: Vec<PyReadonlyArray1<'py, f64>>,
    time_scale: PyReadonlyArray1<'py, f64>,
) -> PyResult<Vec<Bound<'py, PyArray1<f64>>>> {
    let slice =
        |a: &PyReadonlyArray1<'py, f64>| a.as_slice().map_err(value_error).map(<[f64]>::to_vec);
    let (x1, v1, x2, v2) = (slice(&x1)?, slice(&v1)?, slice(&x2)?, slice(&v2)?);
    let (m1, m2, l, t) = (
        slice(&m1)?,
        slice(&m2)?,
        slice(&contact)?,
        slice(&time_scale)?,
    );
    let mor: Vec<Vec<f64>> = mor.iter().map(slice).collect::<Result<_, _>>()?;
    let n = m1.len();
    if mor.len() != 5
        || [&x1, &v1, &x2, &v2].iter().any(|c| c.len() != 3 * n)
        || [&m2, &l, &t]
            .iter()
            .chain(mor.iter().collect::<Vec<_>>().iter())
            .any(|c| c.len() != n)
    {
        return Err(PyValueError::new_err(
            "collide needs n×3 positions and velocities and n masses, distances and MoRs",
        ));
    }
    let v3 = |c: &[f64], i: usize| Vec3::new(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
    for (i, &contact) in l.iter().enumerate() {
        let distance = (v3(&x1, i) - v3(&x2, i)).norm();
        // Written so that NaN positions or distances are refused too.
        let touching = (distance - contact).abs() <= CONTACT_TOLERANCE * contact;
        if !touching {
            return Err(PyValueError::new_err(format!(
                "pair {i} is not in contact: its centres are {distance:e} m apart, but spheres \
                 of radii summing to {:e} m touch at that distance; collide takes the two \
                 spheres at their first touch (|x1 - x2| = R1 + R2, within a relative \
                 {CONTACT_TOLERANCE:e})",
                contact
            )));
        }
    }
    let mut out: [Vec<f64>; 8] = std::array::from_fn(|_| Vec::with_capacity(3 * n));
    for i in 0..n {
        let m = Mor {
            one_minus_eps_r: mor[0][i],
            eps_r: mor[1][i],
            eps_rdot: mor[2][i],
            eps_phi: mor[3][i],
            eps_t: mor[4][i],
        };
        let bodies = [
            Body {
                position: v3(&x1, i),
                velocity: v3(&v1, i),
                mass: m1[i],
            },
            Body {
                position: v3(&x2, i),
                velocity: v3(&v2, i),
                mass: m2[i],
            },
        ];
        let o = resolve(&bodies, l[i], &m, t[i]);
        for (col, v) in out.iter_mut().zip([
            o.after[0].position,
            o.after[0].velocity,
            o.after[1].position,
            o.after[1].velocity,
            o.rotated_positions[0],
            o.rotated_positions[1],
            o.transient_velocity,
        ]) {
            col.extend(v.iter());
        }
        out[7].push(o.duration);
    }
    Ok(out.into_iter().map(|c| c.into_pyarray(py)).collect())
}

#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    emdstar_hugepages::configure_from_env();
    m.add_class::<PyTable>()?;
    m.add_class::<PyPairTable>()?;
    m.add_function(wrap_pyfunction!(exact, m)?)?;
    m.add_function(wrap_pyfunction!(dissipation_for_restitution, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(exact_scaled, m)?)?;
    m.add_function(wrap_pyfunction!(resolve_collisions, m)?)?;
    m.add_function(wrap_pyfunction!(run::run_config, m)?)?;
    Ok(())
}
