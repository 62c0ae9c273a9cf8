//! A global allocator for programs that hold million-move toolpaths.
//!
//! A 1,000,000-block program and its toolpath take a few hundred megabytes,
//! and on a virtual machine the first write to each fresh 4 KiB page costs a
//! few microseconds: as much as parsing or interpreting the block that fills
//! it. [`LargePages`] is the system allocator, except that it asks Linux to
//! back every allocation of [`LargePages::THRESHOLD`] bytes or more with
//! transparent huge pages (`madvise(MADV_HUGEPAGE)`), which cuts those faults
//! by a factor of 512 where the kernel's `transparent_hugepage` setting is
//! `madvise` or `always`. Elsewhere it is exactly [`System`].
//!
//! The libraries do not choose an allocator; the `kezuri` binary and the
//! benchmarks do:
//! ```
//! #[global_allocator]
//! static ALLOC: kezuri_geom::LargePages = kezuri_geom::LargePages;
//! let v: Vec<u8> = vec![1; 32 << 20];
//! assert_eq!(v[12345], 1);
//! ```

use std::alloc::{GlobalAlloc, Layout, System};

/// The system allocator with transparent huge pages for large blocks.
pub struct LargePages;

impl LargePages {
    /// Allocations at least this large (8 MiB) are advised to use huge pages.
    pub const THRESHOLD: usize = 8 << 20;
}

#[cfg(target_os = "linux")]
fn advise(ptr: *mut u8, size: usize) {
    if ptr.is_null() || size < LargePages::THRESHOLD {
        return;
    }
    const PAGE: usize = 4096;
    let start = (ptr as usize).next_multiple_of(PAGE);
    let end = (ptr as usize + size) & !(PAGE - 1);
    // SAFETY: [start, end) lies inside the block the allocator just handed
    // out; MADV_HUGEPAGE changes only how the kernel backs those pages, never
    // their contents, and a failure (an old kernel, THP off) is harmless.
    unsafe {
        libc::madvise(start as *mut libc::c_void, end - start, libc::MADV_HUGEPAGE);
    }
}

#[cfg(not(target_os = "linux"))]
fn advise(_ptr: *mut u8, _size: usize) {}

// SAFETY: every call is forwarded to `System` with the same arguments; the
// only addition is advice on pages the caller now owns.
unsafe impl GlobalAlloc for LargePages {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc(layout) };
        advise(ptr, layout.size());
        ptr
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc_zeroed(layout) };
        advise(ptr, layout.size());
        ptr
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let ptr = unsafe { System.realloc(ptr, layout, new_size) };
        advise(ptr, new_size);
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}
