//! Resources checked before a run starts: the memory its particles need against what
//! the machine has free, and the sizes of its trajectory and log against the free space
//! of the disks they go to. `--force` runs anyway.

use anyhow::{Result, bail};
use emdstar_engines::run::{Estimate, MAX_CHECKPOINTS, gigabytes};
use emdstar_system::Config;
use std::path::Path;

/// Bytes one particle takes at most in any engine, with its neighbour lists, cells and
/// event records. Measured peak resident sizes of `emdstar run` on gases of 13 824,
/// 110 592 and 373 248 spheres (packing fractions 0.05 and 0.3) grew by 140 (md), 150
/// (hybrid) and 215 (emdstar) bytes per particle; this bound leaves room for denser
/// gases and for generating the gas.
pub const BYTES_PER_PARTICLE: u64 = 500;

/// Bytes any run takes besides its particles: the program, and the MoR tables the
/// event-driven engines load (about 80 MB measured).
pub const BASE_BYTES: u64 = 150 << 20;

/// Particles the config describes, before any is generated.
pub fn particle_count(config: &Config) -> u64 {
    match &config.gas {
        Some(gas) => gas.count as u64,
        None => config.particles.len() as u64,
    }
}

/// Bytes a run of `particles` particles needs, about (an upper bound).
pub fn memory_estimate(particles: u64) -> u64 {
    particles
        .saturating_mul(BYTES_PER_PARTICLE)
        .saturating_add(BASE_BYTES)
}

/// Refuses a config whose particles would not fit into the memory available now,
/// unless `force`.
pub fn check_memory(config: &Config, force: bool) -> Result<()> {
    let n = particle_count(config);
    let need = memory_estimate(n);
    let Some(available) = available_memory() else {
        return Ok(());
    };
    if need > available && !force {
        bail!(
            "{n} particles need about {} of memory, but only {} is available on this \
             machine; lower the particle count (gas.count), or give --force to try anyway",
            gigabytes(need as f64),
            gigabytes(available as f64)
        );
    }
    Ok(())
}

/// Refuses outputs that would not fit into the free space of their disks (those in one
/// directory counted together), unless `force`.
pub fn check_outputs(estimates: &[Estimate], force: bool) -> Result<()> {
    if force {
        return Ok(());
    }
    for e in estimates {
        if e.what == "checkpoint" && e.records > MAX_CHECKPOINTS {
            bail!(
                "output.restart_interval writes about {:.1e} checkpoints to {}, each synced to \
                 the disk (a millisecond or more): more than {MAX_CHECKPOINTS:.0e}, which take \
                 a day; raise restart_interval, or give --force to start anyway",
                e.records,
                e.path.display()
            );
        }
        let Some(free) = free_disk_space(&e.path) else {
            continue;
        };
        // The outputs in the same directory share its disk: the largest is named.
        let together: Vec<&Estimate> = estimates
            .iter()
            .filter(|o| o.path.parent() == e.path.parent())
            .collect();
        let total: f64 = together.iter().map(|o| o.bytes).sum();
        let largest = together
            .iter()
            .copied()
            .max_by(|a, b| a.bytes.total_cmp(&b.bytes))
            .is_some_and(|l| std::ptr::eq(l, e));
        if e.bytes > free as f64 || (total > free as f64 && largest) {
            let advice = match e.what {
                "log" => "write lines less often (output.log_interval)",
                "checkpoint" => "write the checkpoint elsewhere (--checkpoint)",
                _ => {
                    "write frames less often (output.trajectory_interval), write a .gsd file \
                     (a fifth of the size), no trajectory (--trajectory none)"
                }
            };
            let others = if total > e.bytes {
                format!(" ({} with the other outputs there)", gigabytes(total))
            } else {
                String::new()
            };
            bail!(
                "the {} {} would take about {}{others}, but its disk has {} free; {advice}, \
                 or give --force to start anyway",
                e.what,
                e.path.display(),
                gigabytes(e.bytes),
                gigabytes(free as f64)
            );
        }
    }
    Ok(())
}

/// `MemAvailable` of /proc/meminfo (Linux): memory that can be given to a new process
/// without swapping. `None` where it cannot be read.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Bytes free for an unprivileged user on the file system that holds `path` (which
/// need not exist yet: its directory is asked). `None` where it cannot be found.
fn free_disk_space(path: &Path) -> Option<u64> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    statvfs_free(dir)
}

#[cfg(unix)]
fn statvfs_free(dir: &Path) -> Option<u64> {
    use std::os::unix::ffi::OsStrExt;
    let name = std::ffi::CString::new(dir.as_os_str().as_bytes()).ok()?;
    let mut stat = std::mem::MaybeUninit::<libc::statvfs>::uninit();
    // SAFETY: `name` is a NUL-terminated path and `stat` a writable statvfs record.
    let rc = unsafe { libc::statvfs(name.as_ptr(), stat.as_mut_ptr()) };
    if rc != 0 {
        return None;
    }
    // SAFETY: statvfs succeeded, so it filled the record.
    let stat = unsafe { stat.assume_init() };
    #[allow(clippy::unnecessary_cast)] // u64 here, narrower on other platforms
    let (blocks, block_size) = (stat.f_bavail as u64, stat.f_frsize as u64);
    Some(blocks.saturating_mul(block_size))
}

#[cfg(not(unix))]
fn statvfs_free(_dir: &Path) -> Option<u64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_space_of_the_working_directory_is_found() {
        // The temporary directory's file system has some space, and less than an exabyte.
        let free = free_disk_space(&std::env::temp_dir().join("x.xyz")).unwrap();
        assert!(free > 0 && free < 1 << 60, "{free}");
        assert!(free_disk_space(Path::new("x.xyz")).is_some());
    }
}
