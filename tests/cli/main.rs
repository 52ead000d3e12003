//! End-to-end tests of the `emdstar` command line.

mod edmd;
mod examples;
mod files;
mod hybrid;
mod md;
mod messages;
mod mor;
mod reliability;
mod restart;
mod restitution;
mod table;
mod validate;

use std::path::Path;
use std::process::{Command, Output};

/// Runs the built `emdstar` binary with `args` in the directory `dir`.
pub fn emdstar_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_emdstar"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("the emdstar binary runs")
}

/// Runs the built `emdstar` binary with `args` in the package root.
pub fn emdstar(args: &[&str]) -> Output {
    emdstar_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}

/// Runs `emdstar` in `dir`, expects success and returns its standard output.
pub fn stdout_in(dir: &Path, args: &[&str]) -> String {
    let out = emdstar_in(dir, args);
    assert!(
        out.status.success(),
        "emdstar {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs `emdstar`, expects success and parses its standard output as JSON.
pub fn emdstar_json(args: &[&str]) -> serde_json::Value {
    let stdout = stdout_in(Path::new(env!("CARGO_MANIFEST_DIR")), args);
    serde_json::from_str(&stdout).expect("valid JSON on stdout")
}

/// Runs `emdstar` in `dir`, expects a clean failure (no panic) and returns its error message.
pub fn error_in(dir: &Path, args: &[&str]) -> String {
    let out = emdstar_in(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "emdstar {args:?} should fail");
    assert!(
        !stderr.contains("panicked"),
        "emdstar {args:?} panicked: {stderr}"
    );
    assert!(
        !stderr.trim().is_empty(),
        "emdstar {args:?} failed silently"
    );
    stderr
}

/// Runs `emdstar` in the package root, expects a clean failure and returns its error message.
pub fn emdstar_error(args: &[&str]) -> String {
    error_in(Path::new(env!("CARGO_MANIFEST_DIR")), args)
}
