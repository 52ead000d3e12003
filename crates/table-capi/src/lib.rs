//! C ABI of the emdstar matrix-of-restitution table reader.
//!
//! Open a table (a file, or the embedded default of a model), look up the MoR of an
//! impact from scaled or physical parameters, close it. Functions returning a status
//! return [`EmdstarStatus::Ok`] (0) on success; on failure
//! [`emdstar_table_last_error`] gives the message (per thread). No panic crosses the
//! boundary: a panic becomes [`EmdstarStatus::Panic`].
//!
//! The header `include/emdstar_table.h` is generated from this file by cbindgen.

use emdstar_contact::{
    ForceLaw, Impact, LinearDashpot, Model, PairLaw, PairProperties, ScaledParams, Sphere,
    ViscoelasticHertz,
};
use emdstar_table::{Mor, Table, TableError};
use std::cell::RefCell;
use std::ffi::{CStr, CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// Force model of a table.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmdstarModel {
    /// Linear spring-dashpot.
    Linear = 0,
    /// Viscoelastic Hertz.
    Hertz = 1,
}

/// Outcome of a call.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EmdstarStatus {
    Ok = 0,
    /// The impact lies outside the table's box (solve it exactly instead).
    OutOfBox = 1,
    /// A near-central impact where the table has no central limit.
    NotTabulated = 2,
    /// Bad arguments (null pointer, non-finite or negative value, ...).
    InvalidInput = 3,
    /// The table is for the other model.
    WrongModel = 4,
    /// The file could not be read or is not a valid table.
    BadFile = 5,
    /// An internal error (a bug): please report it.
    Panic = 99,
}

/// The matrix of restitution of one impact, Müller & Pöschel 2013, Eqs. (16)-(21).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EmdstarMor {
    pub eps_r: f64,
    pub one_minus_eps_r: f64,
    /// Negative; the normal coefficient of restitution is -eps_rdot.
    pub eps_rdot: f64,
    /// Rotation of the inter-particle unit vector during contact, radians.
    pub eps_phi: f64,
    /// Scaled duration; the contact lasts eps_t * time_scale seconds.
    pub eps_t: f64,
    /// Time scale T in s (0 for scaled lookups).
    pub time_scale: f64,
}

/// An open table (opaque).
pub struct EmdstarTable {
    table: Table,
}

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_error(msg: &str) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = c);
}

fn status_of(e: &TableError) -> EmdstarStatus {
    match e {
        TableError::OutOfBox { .. } => EmdstarStatus::OutOfBox,
        TableError::NotTabulated(_) => EmdstarStatus::NotTabulated,
        TableError::WrongModel { .. } => EmdstarStatus::WrongModel,
        TableError::Input(_) | TableError::Fallback(_) => EmdstarStatus::InvalidInput,
        _ => EmdstarStatus::BadFile,
    }
}

/// Runs `f`, converting errors and panics into a status and the last-error message.
fn guarded(f: impl FnOnce() -> Result<(), (EmdstarStatus, String)>) -> EmdstarStatus {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(())) => EmdstarStatus::Ok,
        Ok(Err((status, msg))) => {
            set_error(&msg);
            status
        }
        Err(_) => {
            set_error("internal error (panic) in emdstar_table");
            EmdstarStatus::Panic
        }
    }
}

fn table_err(e: TableError) -> (EmdstarStatus, String) {
    (status_of(&e), e.to_string())
}

fn input_err(msg: impl ToString) -> (EmdstarStatus, String) {
    (EmdstarStatus::InvalidInput, msg.to_string())
}

fn open_with(f: impl FnOnce() -> Result<Table, (EmdstarStatus, String)>) -> *mut EmdstarTable {
    let mut out = std::ptr::null_mut();
    guarded(|| {
        out = Box::into_raw(Box::new(EmdstarTable { table: f()? }));
        Ok(())
    });
    out
}

/// Opens a table file. Returns NULL on failure (see `emdstar_table_last_error`).
///
/// # Safety
/// `path` must be NULL or a NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_open(path: *const c_char) -> *mut EmdstarTable {
    open_with(|| {
        if path.is_null() {
            return Err(input_err("path is NULL"));
        }
        // SAFETY: non-null and NUL-terminated by the caller's contract.
        let path = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| input_err("path is not UTF-8"))?;
        Table::open(path).map_err(table_err)
    })
}

/// Opens the default table of `model`, embedded in the library. NULL on failure.
#[unsafe(no_mangle)]
pub extern "C" fn emdstar_table_open_default(model: EmdstarModel) -> *mut EmdstarTable {
    open_with(|| {
        let model = match model {
            EmdstarModel::Linear => Model::Linear,
            EmdstarModel::Hertz => Model::Hertz,
        };
        emdstar_table::default_table(model)
            .cloned()
            .map_err(table_err)
    })
}

/// Closes a table; NULL is ignored.
///
/// # Safety
/// `table` must be NULL or a pointer returned by an open function, not yet closed.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_close(table: *mut EmdstarTable) {
    if !table.is_null() {
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the pointer came from Box::into_raw in an open function.
            drop(unsafe { Box::from_raw(table) })
        }));
    }
}

/// The last error message of this thread (empty if none). Valid until the next call.
#[unsafe(no_mangle)]
pub extern "C" fn emdstar_table_last_error() -> *const c_char {
    LAST_ERROR.with(|e| e.borrow().as_ptr())
}

fn write_out(
    table: *const EmdstarTable,
    out: *mut EmdstarMor,
    f: impl FnOnce(&Table) -> Result<(Mor, f64), (EmdstarStatus, String)>,
) -> EmdstarStatus {
    guarded(|| {
        if table.is_null() || out.is_null() {
            return Err(input_err("table or out is NULL"));
        }
        // SAFETY: non-null pointers from the caller, valid by contract.
        let t = unsafe { &(*table).table };
        let (m, time_scale) = f(t)?;
        let res = EmdstarMor {
            eps_r: m.eps_r,
            one_minus_eps_r: m.one_minus_eps_r,
            eps_rdot: m.eps_rdot,
            eps_phi: m.eps_phi,
            eps_t: m.eps_t,
            time_scale,
        };
        // SAFETY: `out` is non-null and points to writable memory by contract.
        unsafe { out.write(res) };
        Ok(())
    })
}

/// MoR at scaled parameters l̃ > 0, c_φ ≥ 0, c_dis ≥ 0 (time_scale is set to 0).
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_scaled(
    table: *const EmdstarTable,
    l_tilde: f64,
    c_phi: f64,
    c_dis: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    write_out(table, out, |t| {
        let p = ScaledParams::new(l_tilde, c_phi, c_dis).map_err(input_err)?;
        Ok((t.lookup_scaled(&p).map_err(table_err)?, 0.0))
    })
}

fn physical(
    t: &Table,
    law: Result<ForceLaw, emdstar_contact::ContactError>,
    spheres: [f64; 4],
    speeds: [f64; 2],
) -> Result<(Mor, f64), (EmdstarStatus, String)> {
    let [r1, m1, r2, m2] = spheres;
    let pair = PairProperties::spheres(
        &Sphere::new(r1, m1).map_err(input_err)?,
        &Sphere::new(r2, m2).map_err(input_err)?,
    );
    let law = PairLaw::same_material(&law.map_err(input_err)?, pair.r_eff).map_err(input_err)?;
    let impact = Impact {
        normal_speed: speeds[0],
        tangential_speed: speeds[1],
    };
    let hit = t.lookup(&law, &pair, &impact).map_err(table_err)?;
    Ok((hit.mor, hit.time))
}

/// MoR of two linear spring-dashpot spheres of one material (k in N/m, γ in kg/s),
/// radii in m, masses in kg, normal and tangential speed at contact in m/s.
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_linear(
    table: *const EmdstarTable,
    stiffness: f64,
    damping: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
    normal_speed: f64,
    tangential_speed: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    write_out(table, out, |t| {
        let law = LinearDashpot::new(stiffness, damping).map(ForceLaw::Linear);
        physical(
            t,
            law,
            [radius1, mass1, radius2, mass2],
            [normal_speed, tangential_speed],
        )
    })
}

/// MoR of two viscoelastic Hertz spheres of one material (Young's modulus in Pa,
/// Poisson ratio, dissipative constant A in s), radii in m, masses in kg, speeds in m/s.
///
/// # Safety
/// `table` from an open function; `out` points to a writable `EmdstarMor`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn emdstar_table_lookup_hertz(
    table: *const EmdstarTable,
    young: f64,
    poisson: f64,
    dissipation: f64,
    radius1: f64,
    mass1: f64,
    radius2: f64,
    mass2: f64,
    normal_speed: f64,
    tangential_speed: f64,
    out: *mut EmdstarMor,
) -> EmdstarStatus {
    write_out(table, out, |t| {
        let law = ViscoelasticHertz::new(young, poisson, dissipation).map(ForceLaw::Hertz);
        physical(
            t,
            law,
            [radius1, mass1, radius2, mass2],
            [normal_speed, tangential_speed],
        )
    })
}
