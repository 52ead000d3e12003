//! LAMMPS as a peer: runs `tools/lammps/hertz_gas.in` (a dilute elastic Hertz gas,
//! Y = 1 GPa, ν = 0.4, A = 0, on a simple cubic lattice) with `lmp` on one core and
//! reads its loop time. Used by `emdstar bench md --lammps` and `emdstar validate
//! --lammps`.

use anyhow::{Context, Result, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The input script, built in so that `validate --lammps` runs from any directory.
pub const HERTZ_GAS_SCRIPT: &str = include_str!("../../tools/lammps/hertz_gas.in");

/// The gas and the run: side³ spheres `spacing` apart, Maxwell velocities of
/// root-mean-square speed `rms_speed`, `warmup` untimed steps and then `steps` timed.
#[derive(Debug, Clone)]
pub struct LammpsGas {
    pub side: usize,
    pub spacing: f64,
    pub radius: f64,
    pub density: f64,
    pub rms_speed: f64,
    pub dt: f64,
    pub skin: f64,
    pub warmup: u64,
    pub steps: u64,
}

/// What the timed run cost.
#[derive(Debug, Clone, Copy)]
pub struct LammpsTiming {
    pub particles: usize,
    pub steps: f64,
    pub wall_s: f64,
    pub cpu_s: f64,
}

impl LammpsTiming {
    /// Wall seconds per simulated second.
    pub fn cost(&self, dt: f64) -> f64 {
        self.wall_s / (self.steps * dt)
    }
}

/// Writes the built-in script to a temporary file (removed when dropped).
pub struct ScriptFile(PathBuf);

impl ScriptFile {
    pub fn new() -> Result<Self> {
        let path =
            std::env::temp_dir().join(format!("emdstar_hertz_gas_{}.in", std::process::id()));
        std::fs::write(&path, HERTZ_GAS_SCRIPT)
            .with_context(|| format!("cannot write {}", path.display()))?;
        Ok(Self(path))
    }

    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for ScriptFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Fails early, with a hint, if `lmp` cannot be started (`lmp -h` must succeed).
pub fn probe(lmp: &str) -> Result<()> {
    let status = Command::new(lmp)
        .arg("-h")
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status();
    match status {
        Ok(s) if s.success() => Ok(()),
        Ok(s) => bail!("'{lmp} -h' failed ({s}): is {lmp} a LAMMPS binary?"),
        Err(e) => bail!(
            "cannot start {lmp} ({e}): install LAMMPS (on Debian: apt-get install lammps) \
             or name its binary, e.g. --lammps /opt/lammps/bin/lmp"
        ),
    }
}

/// Runs `script` with the binary `lmp` on one core for `gas`.
pub fn run(lmp: &str, script: &Path, gas: &LammpsGas) -> Result<LammpsTiming> {
    let n = gas.side.pow(3);
    let mass = 4.0 / 3.0 * std::f64::consts::PI * gas.radius.powi(3) * gas.density;
    // velocity create T: (3/2) k_B T = ½ m ⟨v²⟩ with k_B in SI units.
    let temp = mass * gas.rms_speed * gas.rms_speed / (3.0 * 1.380_649e-23);
    let vars = [
        ("side", gas.side.to_string()),
        ("spacing", format!("{:e}", gas.spacing)),
        ("diameter", format!("{:e}", 2.0 * gas.radius)),
        ("density", format!("{:e}", gas.density)),
        ("temp", format!("{temp:e}")),
        ("dt", format!("{:e}", gas.dt)),
        ("skin", format!("{:e}", gas.skin)),
        ("warmup", gas.warmup.max(1).to_string()),
        ("steps", gas.steps.max(1).to_string()),
    ];
    let out_file = std::env::temp_dir().join(format!("emdstar_lammps_{}.txt", std::process::id()));
    let mut cmd = Command::new(lmp);
    cmd.env("OMP_NUM_THREADS", "1")
        .arg("-in")
        .arg(script)
        .args(["-log", "none"]);
    for (name, value) in &vars {
        cmd.arg("-var").arg(name).arg(value);
    }
    cmd.arg("-screen").arg(&out_file);
    let status = cmd.status().with_context(|| {
        format!("running {lmp} (is LAMMPS installed? On Debian: apt-get install lammps)")
    })?;
    let text = std::fs::read_to_string(&out_file).unwrap_or_default();
    let _ = std::fs::remove_file(&out_file);
    if !status.success() {
        bail!(
            "{lmp} failed ({status}): {}",
            text.lines().rev().take(5).collect::<Vec<_>>().join(" | ")
        );
    }
    parse_loop(&text, n)
}

/// Reads the last "Loop time of X on P procs for S steps with N atoms" (the timed run)
/// and the "% CPU use" line after it.
fn parse_loop(text: &str, particles: usize) -> Result<LammpsTiming> {
    let line = text
        .lines()
        .rev()
        .find(|l| l.starts_with("Loop time of"))
        .context("no 'Loop time' line in the LAMMPS output")?;
    let words: Vec<&str> = line.split_whitespace().collect();
    let number = |k: usize| -> Result<f64> {
        words
            .get(k)
            .and_then(|w| w.parse().ok())
            .with_context(|| format!("cannot read the LAMMPS line '{line}'"))
    };
    let (wall_s, steps) = (number(3)?, number(8)?);
    let cpu_share: f64 = text
        .lines()
        .rev()
        .find(|l| l.contains("% CPU use"))
        .and_then(|l| l.split('%').next()?.trim().parse().ok())
        .context("no '% CPU use' line in the LAMMPS output")?;
    Ok(LammpsTiming {
        particles,
        steps,
        wall_s,
        cpu_s: wall_s * cpu_share / 100.0,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_the_timed_loop_of_a_lammps_screen() {
        let text = "Loop time of 0.5 on 1 procs for 100 steps with 8 atoms\n\
                    90.0% CPU use with 1 MPI tasks x 1 OpenMP threads\n\
                    Loop time of 2.5 on 1 procs for 1000 steps with 8 atoms\n\
                    99.5% CPU use with 1 MPI tasks x 1 OpenMP threads\n";
        let t = parse_loop(text, 8).unwrap();
        assert_eq!((t.wall_s, t.steps), (2.5, 1000.0));
        assert!((t.cpu_s - 2.4875).abs() < 1e-12);
        assert!((t.cost(1e-3) - 2.5).abs() < 1e-12);
        assert!(parse_loop("ERROR: Unknown command", 8).is_err());
    }
}
