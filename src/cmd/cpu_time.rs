//! CPU time for the benchmarks: on a shared machine it excludes the time a benchmark
//! waited for a core. From `clock_gettime` on Linux (scheduler statistics in /proc
//! read zero on kernels built without them); `None` elsewhere.

#[cfg(target_os = "linux")]
fn clock_seconds(clock: i32) -> Option<f64> {
    #[repr(C)]
    struct Timespec {
        sec: i64,
        nsec: i64,
    }
    unsafe extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    let mut ts = Timespec { sec: 0, nsec: 0 };
    // SAFETY: clock_gettime writes one timespec through a valid pointer.
    let ok = unsafe { clock_gettime(clock, &mut ts) };
    (ok == 0).then_some(ts.sec as f64 + ts.nsec as f64 * 1e-9)
}

#[cfg(not(target_os = "linux"))]
fn clock_seconds(_clock: i32) -> Option<f64> {
    None
}

/// CPU seconds of this process, all threads.
pub fn process_seconds() -> Option<f64> {
    const CLOCK_PROCESS_CPUTIME_ID: i32 = 2;
    clock_seconds(CLOCK_PROCESS_CPUTIME_ID)
}

/// CPU seconds of the calling thread.
pub fn thread_seconds() -> Option<f64> {
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    clock_seconds(CLOCK_THREAD_CPUTIME_ID)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    #[cfg(target_os = "linux")]
    fn cpu_clocks_advance_while_working() {
        let (p0, t0) = (process_seconds().unwrap(), thread_seconds().unwrap());
        let mut x = 1.0_f64;
        while thread_seconds().unwrap() - t0 < 0.02 {
            x = std::hint::black_box(x.sqrt() + 1.0);
        }
        assert!(process_seconds().unwrap() - p0 >= 0.02, "{x}");
    }
}
