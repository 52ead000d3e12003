//! The committed C header is current, and the C, C++ and Fortran examples compile,
//! link and run (each skipped, with a note, where its compiler is missing); under
//! valgrind the C example leaks nothing.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn examples() -> PathBuf {
    crate_dir().join("../../examples")
}

#[test]
fn committed_header_matches_cbindgen() {
    let dir = crate_dir();
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).unwrap();
    let mut fresh = Vec::new();
    cbindgen::Builder::new()
        .with_crate(&dir)
        .with_config(config)
        .generate()
        .expect("cbindgen runs")
        .write(&mut fresh);
    let path = dir.join("include/emdstar_table.h");
    if std::env::var_os("EMDSTAR_BLESS").is_some() {
        std::fs::write(&path, &fresh).unwrap();
    }
    let committed = std::fs::read(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "{} is stale; regenerate it with EMDSTAR_BLESS=1 cargo test -p emdstar-table-capi",
        path.display()
    );
}

/// target/<profile>, where cargo puts libemdstar_table_c.a.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    exe.parent().and_then(Path::parent).unwrap().to_path_buf()
}

/// The static library, built once with the test profile (`cargo test` builds only the
/// rlib).
fn static_lib() -> PathBuf {
    static LIB: OnceLock<PathBuf> = OnceLock::new();
    LIB.get_or_init(|| {
        let target_dir = profile_dir().parent().unwrap().to_path_buf();
        let status = Command::new(env!("CARGO"))
            .args([
                "build",
                "--profile",
                "test",
                "--lib",
                "-p",
                "emdstar-table-capi",
            ])
            .env("CARGO_TARGET_DIR", &target_dir)
            .status()
            .expect("cargo runs");
        assert!(status.success(), "building the static library failed");
        let lib = profile_dir().join("libemdstar_table_c.a");
        assert!(lib.exists(), "{} was not built", lib.display());
        lib
    })
    .clone()
}

/// Whether `tool` runs; if not, says so on stderr (the test then passes as skipped).
fn have(tool: &str, what: &str) -> bool {
    let ok = Command::new(tool)
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success());
    if !ok {
        eprintln!("SKIPPED: {what}: `{tool}` is not installed");
    }
    ok
}

/// Compiles `sources` with `compiler` against the library and returns the program.
fn compile(compiler: &str, name: &str, sources: &[PathBuf], flags: &[&str]) -> PathBuf {
    let out = std::env::temp_dir().join(format!("emdstar_{name}_{}", std::process::id()));
    let mut cmd = Command::new(compiler);
    cmd.args(flags).args(sources);
    cmd.arg("-I").arg(crate_dir().join("include"));
    // gfortran writes its .mod file into the working directory.
    cmd.current_dir(std::env::temp_dir());
    let o = cmd
        .arg(static_lib())
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&out)
        .output()
        .expect("the compiler runs");
    assert!(
        o.status.success(),
        "{compiler} failed:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}

fn run(program: &Path) -> (Output, String) {
    let o = Command::new(program).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    (o, text)
}

fn value(text: &str, key: &str) -> f64 {
    text.lines()
        .find_map(|l| l.trim().strip_prefix(key))
        .and_then(|v| v.split_whitespace().next()?.parse().ok())
        .unwrap_or_else(|| panic!("no `{key}` line in:\n{text}"))
}

#[test]
fn c_example_looks_up_falls_back_and_collides() {
    if !have("gcc", "C example") {
        return;
    }
    let exe = compile("gcc", "c", &[examples().join("c/lookup.c")], &[]);
    let (_, text) = run(&exe);
    let _ = std::fs::remove_file(&exe);
    // A dissipative impact gives 0 < eps_n < 1, and the table agrees with the exact
    // solver of the same impact to its accuracy.
    let eps_n = value(&text, "eps_n = ");
    let exact = value(&text, "exact eps_n = ");
    assert!(eps_n > 0.0 && eps_n < 1.0, "{text}");
    assert!((eps_n - exact).abs() <= 2e-6 * exact, "{text}");
    // The out-of-box impact is refused, then solved exactly and counted once.
    assert!(text.contains("out of box: status 1"), "{text}");
    assert!(
        text.contains("with fallback: status 0, source 1, fallbacks 1"),
        "{text}"
    );
    // The collision conserves momentum (equal masses: v1x + v2x = 0 before and after).
    assert!(value(&text, "momentum x after = ").abs() < 1e-12, "{text}");
    assert!(
        text.contains("bad file: NULL (cannot read the table file"),
        "{text}"
    );
}

#[test]
fn cpp_example_through_the_raii_header() {
    if !have("g++", "C++ example") {
        return;
    }
    let exe = compile(
        "g++",
        "cpp",
        &[examples().join("cpp/lookup.cpp")],
        &["-std=c++17", "-I", examples().join("cpp").to_str().unwrap()],
    );
    let (_, text) = run(&exe);
    let _ = std::fs::remove_file(&exe);
    let eps_n = value(&text, "eps_n = ");
    assert!(eps_n > 0.0 && eps_n < 1.0, "{text}");
    assert!(text.contains("out of box: status 1"), "{text}");
    assert!(
        text.contains("with fallback: source 1, fallbacks 1"),
        "{text}"
    );
    // The ball leaves the floor upwards, slower than it came, its tangential velocity
    // unchanged (frictionless wall).
    let vz = value(&text, "bounce: v_z = ");
    assert!(vz > 0.0 && vz < 1.0, "{text}");
    assert!(text.contains("v_x = 0.2 m/s"), "{text}");
}

#[test]
fn fortran_example_through_iso_c_binding() {
    if !have("gfortran", "Fortran example") {
        return;
    }
    let exe = compile(
        "gfortran",
        "fortran",
        &[
            examples().join("fortran/emdstar_table.f90"),
            examples().join("fortran/lookup.f90"),
        ],
        &[],
    );
    let (_, text) = run(&exe);
    let _ = std::fs::remove_file(&exe);
    let eps_n = value(&text, "eps_n = ");
    assert!(eps_n > 0.0 && eps_n < 1.0, "{text}");
    assert!(text.contains("out of box: status 1"), "{text}");
    assert!(
        text.contains("with fallback: status 0, source 1, fallbacks 1"),
        "{text}"
    );
    assert!(text.contains("bad file is null: T"), "{text}");
}

#[test]
fn the_c_example_leaks_nothing_under_valgrind() {
    if !(have("gcc", "valgrind check") && have("valgrind", "valgrind check")) {
        return;
    }
    let exe = compile(
        "gcc",
        "c_valgrind",
        &[examples().join("c/lookup.c")],
        &["-g"],
    );
    // Open, lookups, the failure paths (out of box, bad file) and close: no definite or
    // indirect leak and no invalid access. (The parsed default table, shared for the
    // life of the process, is still reachable by design.)
    let o = Command::new("valgrind")
        .args([
            "--leak-check=full",
            "--errors-for-leak-kinds=definite,indirect",
            "--error-exitcode=7",
            "-q",
        ])
        .arg(&exe)
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&exe);
    assert!(
        o.status.success(),
        "valgrind found errors:\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
}
