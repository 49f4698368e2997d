//! How the hosts' allocator (mimalloc) gives freed memory back to the
//! operating system. The one unsafe call outside `gfx`: an FFI call that
//! stores one of mimalloc's options. The Blender extension makes the same
//! call at import (`blender_addon/native/src/lib.rs`).
//!
//! By default mimalloc purges freed memory by decommitting it (Linux:
//! `MADV_DONTNEED`): the next allocation that reuses it faults every page
//! in again, and the kernel zeroes each one. A union or a GC commit frees
//! and reallocates hundreds of megabytes of temporaries, so this is paid
//! in the middle of the work users wait for. Measured with
//! `gc_union_parts` on the 30-part shelf (its script, a warm-up and three
//! unions, one CPU; 2026-12-01): 376,120 page faults by default, and the
//! kernel's page clearing was 12% of the union's samples in `perf`.
//!
//! [`tune_mimalloc`] makes purges reset the memory instead (Linux and
//! macOS: `MADV_FREE`; Windows: `MEM_RESET`): the pages stay mapped, and
//! reusing them costs nothing unless the operating system took them back
//! under memory pressure, which it still may. The same run faults 16,421
//! pages. Never purging (`purge_delay` -1) faults about as little but
//! keeps the peak of every union resident whatever the machine needs, so
//! it is not used. Results do not change: the allocator decides where
//! memory comes from, not what is computed in it.
//!
//! The benches' examples (`core/examples`) are run with the same option
//! from the environment (`MIMALLOC_PURGE_DECOMMITS=0`, set by
//! `scripts/bench/run_all.py`): mimalloc reads it at process load.

/// mimalloc's `mi_option_purge_decommits`: index 5 of `mi_option_e` in
/// both of its versions (v2 and v3, `include/mimalloc.h`); the Rust
/// binding has no constant for it.
pub const PURGE_DECOMMITS: libmimalloc_sys::mi_option_t = 5;

/// Sets mimalloc to reset, not decommit, the memory it purges (see the
/// module doc). Called first thing in `main`; it takes effect from the
/// next purge. A binary with another global allocator is not affected.
pub fn tune_mimalloc() {
    // SAFETY: mi_option_set stores the option's value in mimalloc's option
    // table (a plain store of a valid index); it may be called at any time
    // from any thread.
    unsafe { libmimalloc_sys::mi_option_set(PURGE_DECOMMITS, 0) }
}

/// mimalloc's current value of `option`.
pub fn mimalloc_option(option: libmimalloc_sys::mi_option_t) -> std::ffi::c_long {
    // SAFETY: mi_option_get checks the index (0 outside the table) and
    // reads the option table.
    unsafe { libmimalloc_sys::mi_option_get(option) }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The index names the option: before the call it holds
    /// `purge_decommits`' documented default (1) and its neighbours
    /// theirs (`arena_eager_commit` 2, `allow_large_os_pages` 0); after,
    /// 0. (Unless the environment sets MIMALLOC_* options, which the
    /// tests do not.)
    #[test]
    fn the_option_set_is_purge_decommits() {
        let get = mimalloc_option;
        assert_eq!([get(PURGE_DECOMMITS - 1), get(PURGE_DECOMMITS + 1)], [2, 0]);
        assert_eq!(get(PURGE_DECOMMITS), 1);
        tune_mimalloc();
        assert_eq!(get(PURGE_DECOMMITS), 0);
    }
}
