//! A global allocator for emdstar's programs (the command and the Python module): the
//! system allocator, asking Linux for transparent huge pages under large arrays.
//!
//! In a large run (N ≈ 10⁶) every event reads a few particle records, cells and queue
//! entries at random over a few hundred MB. With 4 KiB pages nearly each of those reads
//! also misses the TLB and walks the page table; with 2 MiB pages the same arrays need
//! a few hundred TLB entries instead of some 10⁵. Most Linux systems give huge pages
//! only to memory that asks for them (`/sys/kernel/mm/transparent_hugepage/enabled`
//! reads `madvise`), so every allocation of at least [`LARGE`] bytes is aligned to
//! 2 MiB and advised `MADV_HUGEPAGE`. Smaller allocations, and every allocation on
//! other systems, go to the system allocator unchanged. Where memory sits changes no
//! result; `EMDSTAR_HUGE_PAGES=off` leaves the advice out (for timing one against the
//! other). `docs/performance.md` has the figures.
//!
//! ```no_run
//! #[global_allocator]
//! static ALLOCATOR: emdstar_hugepages::HugePages = emdstar_hugepages::HugePages;
//!
//! fn main() {
//!     emdstar_hugepages::configure_from_env();
//!     let records = vec![0u8; 1 << 27]; // 128 MiB, on huge pages where Linux has them
//!     # drop(records);
//! }
//! ```

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicBool, Ordering};

/// The size of a huge page on x86-64 and most aarch64 Linux systems.
const HUGE_PAGE: usize = 2 << 20;

/// Allocations from this size are aligned to [`HUGE_PAGE`] and advised: two huge
/// pages, so that the alignment wastes at most a third of the block's address space
/// (and no memory: untouched pages are never backed).
pub const LARGE: usize = 2 * HUGE_PAGE;

static ADVISE: AtomicBool = AtomicBool::new(true);

/// Reads `EMDSTAR_HUGE_PAGES` (`off`, `0`, `no` or `false` leave the advice out); call once,
/// first thing in `main`.
pub fn configure_from_env() {
    if let Some(v) = std::env::var_os("EMDSTAR_HUGE_PAGES") {
        let off = matches!(v.to_str(), Some("off" | "0" | "no" | "false"));
        ADVISE.store(!off, Ordering::Relaxed);
    }
}

/// The system allocator, with huge pages advised under large blocks (module docs).
pub struct HugePages;

impl HugePages {
    /// The layout a block of this layout is given: on Linux, large blocks are aligned
    /// to a huge page. A function of the size only, so that `dealloc` sees what `alloc`
    /// used.
    fn actual(layout: Layout) -> Layout {
        if cfg!(target_os = "linux") && layout.size() >= LARGE && layout.align() < HUGE_PAGE {
            // SAFETY: HUGE_PAGE is a power of two, and a size this large rounded up to
            // it stays far below isize::MAX (the caller's layout was valid).
            unsafe { Layout::from_size_align_unchecked(layout.size(), HUGE_PAGE) }
        } else {
            layout
        }
    }

    /// Asks for huge pages under a fresh large block (a hint: failure is harmless).
    fn advise(ptr: *mut u8, size: usize) {
        #[cfg(target_os = "linux")]
        if !ptr.is_null() && size >= LARGE && ADVISE.load(Ordering::Relaxed) {
            // SAFETY: ptr is the start of a live block of `size` bytes, aligned to a
            // huge page and so to a page; madvise only changes how it is backed.
            unsafe {
                libc::madvise(ptr.cast(), size, libc::MADV_HUGEPAGE);
            }
        }
        #[cfg(not(target_os = "linux"))]
        let _ = (ptr, size);
    }
}

// SAFETY: every block comes from `System` with the layout `actual` gives, and goes back
// to it with the same layout; `advise` does not change the block's contents.
unsafe impl GlobalAlloc for HugePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let actual = Self::actual(layout);
        // SAFETY: the caller's layout has a non-zero size, and so has `actual`.
        let ptr = unsafe { System.alloc(actual) };
        Self::advise(ptr, actual.size());
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if layout.size() < LARGE {
            // SAFETY: as for `alloc`.
            return unsafe { System.alloc_zeroed(layout) };
        }
        // Advised before the zeroing first touches the pages, so that they are huge.
        // SAFETY: as for `alloc`; the block is `layout.size()` bytes long.
        unsafe {
            let ptr = self.alloc(layout);
            if !ptr.is_null() {
                std::ptr::write_bytes(ptr, 0, layout.size());
            }
            ptr
        }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `alloc` with this layout, hence from System with
        // `actual(layout)`.
        unsafe { System.dealloc(ptr, Self::actual(layout)) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if layout.size() < LARGE && new_size < LARGE {
            // SAFETY: small before and after: System's own block, as the caller gave it.
            return unsafe { System.realloc(ptr, layout, new_size) };
        }
        // SAFETY: the caller guarantees that new_size with layout's alignment is a valid
        // layout; the old block holds layout.size() bytes and is freed after the copy.
        unsafe {
            let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
            let new = self.alloc(new_layout);
            if !new.is_null() {
                std::ptr::copy_nonoverlapping(ptr, new, layout.size().min(new_size));
                self.dealloc(ptr, layout);
            }
            new
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn large_blocks_are_aligned_to_a_huge_page_and_keep_their_contents() {
        let a = HugePages;
        let small = Layout::from_size_align(1000, 8).unwrap();
        let large = Layout::from_size_align(LARGE + 12_345, 8).unwrap();
        unsafe {
            let p = a.alloc_zeroed(large);
            assert!(!p.is_null());
            #[cfg(target_os = "linux")]
            assert_eq!(p as usize % HUGE_PAGE, 0);
            assert!((0..large.size()).step_by(4093).all(|i| *p.add(i) == 0));
            for i in 0..1000 {
                *p.add(i) = i as u8;
            }
            // Shrinking below the threshold copies into a small block, and back.
            let q = a.realloc(p, large, 1000);
            assert!((0..1000).all(|i| *q.add(i) == i as u8));
            let r = a.realloc(q, small, 3 * LARGE);
            #[cfg(target_os = "linux")]
            assert_eq!(r as usize % HUGE_PAGE, 0);
            assert!((0..1000).all(|i| *r.add(i) == i as u8));
            a.dealloc(r, Layout::from_size_align(3 * LARGE, 8).unwrap());
        }
    }

    /// The kernel marks an advised mapping `hg` in its VmFlags (proc(5)), whether or
    /// not it has huge pages to give at the moment.
    #[cfg(target_os = "linux")]
    #[test]
    fn large_blocks_are_advised_and_small_ones_are_not() {
        if !std::path::Path::new("/sys/kernel/mm/transparent_hugepage/enabled").exists() {
            eprintln!("skipped: this kernel has no transparent huge pages");
            return;
        }
        let advised = |p: *mut u8| -> bool {
            let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
            let mut inside = false;
            for line in smaps.lines() {
                let range = line.split_whitespace().next().unwrap_or("");
                if let Some((lo, hi)) = range.split_once('-') {
                    if let (Ok(lo), Ok(hi)) =
                        (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16))
                    {
                        inside = (lo..hi).contains(&(p as usize));
                        continue;
                    }
                }
                if inside && line.starts_with("VmFlags:") {
                    return line.split_whitespace().any(|f| f == "hg");
                }
            }
            panic!("no mapping holds {p:?}");
        };
        let a = HugePages;
        let large = Layout::from_size_align(3 * LARGE, 64).unwrap();
        let small = Layout::from_size_align(64 << 10, 64).unwrap();
        unsafe {
            let (p, q) = (a.alloc(large), a.alloc(small));
            assert!(advised(p), "a large block is not advised MADV_HUGEPAGE");
            assert!(!advised(q), "a small block was advised");
            a.dealloc(p, large);
            a.dealloc(q, small);
        }
    }
}
