//! The committed C header is current, and the C example compiles, links and runs.

use std::path::{Path, PathBuf};
use std::process::Command;

fn crate_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
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

#[test]
fn c_example_prints_the_mor_of_one_impact() {
    // `cargo test` builds only the rlib; build the static library with the same profile.
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
    let out = std::env::temp_dir().join(format!("emdstar_c_example_{}", std::process::id()));
    let status = Command::new("gcc")
        .arg(crate_dir().join("../../examples/c/lookup.c"))
        .arg("-I")
        .arg(crate_dir().join("include"))
        .arg(&lib)
        .args(["-lpthread", "-ldl", "-lm", "-o"])
        .arg(&out)
        .status()
        .expect("gcc runs");
    assert!(status.success(), "gcc failed");
    let run = Command::new(&out).output().unwrap();
    let _ = std::fs::remove_file(&out);
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        run.status.success(),
        "{text}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    // The example prints "eps_n = <value>" among its lines; a dissipative impact
    // must give 0 < eps_n < 1, and the out-of-box call must be refused.
    let eps_n: f64 = text
        .lines()
        .find_map(|l| l.strip_prefix("eps_n = "))
        .and_then(|v| v.trim().parse().ok())
        .unwrap_or_else(|| panic!("no eps_n line in:\n{text}"));
    assert!(eps_n > 0.0 && eps_n < 1.0, "{text}");
    assert!(text.contains("out of box: status 1"), "{text}");
}
