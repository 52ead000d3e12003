//! End-to-end tests of the `emdstar` command line.

mod edmd;
mod mor;
mod validate;

use std::process::{Command, Output};

/// Runs the built `emdstar` binary with `args`.
pub fn emdstar(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_emdstar"))
        .args(args)
        .output()
        .expect("the emdstar binary runs")
}

/// Runs `emdstar`, expects success and parses its standard output as JSON.
pub fn emdstar_json(args: &[&str]) -> serde_json::Value {
    let out = emdstar(args);
    assert!(
        out.status.success(),
        "emdstar {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON on stdout")
}

/// Runs `emdstar`, expects a clean failure (no panic) and returns its error message.
pub fn emdstar_error(args: &[&str]) -> String {
    let out = emdstar(args);
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
