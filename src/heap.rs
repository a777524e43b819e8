//! The allocator policy of the programs that run studies (`report`, the solver benchmark): freed
//! memory stays with the process for the next adaptive cycle instead of going back to the
//! kernel.
//!
//! **Why.** Every cycle of a study allocates the arrays of the one before again, larger: the
//! sparsity pattern, the matrix, the cell data, the multigrid levels, some tens of MB each at
//! 0.7 M unknowns. glibc's default policy hands freed memory back to the kernel (a block above
//! its dynamic mmap threshold is unmapped when freed, the top of a heap is trimmed, and each
//! thread that allocates gets an arena of its own), so each cycle faults its arrays in again,
//! page by page. On the 2-core VM a page fault costs about 2.4 µs: Table IV.36 took 320 k faults,
//! 0.75 s of system time of its 3.4 CPU-s.
//!
//! **Policy** (glibc `mallopt`): one arena for all threads (`M_ARENA_MAX` = 1), no trimming of
//! the heap (`M_TRIM_THRESHOLD` at its maximum), and mmap only for blocks above 32 MiB
//! (`M_MMAP_THRESHOLD`, the largest value glibc accepts). IV.36 then takes 170 k page faults
//! and 0.39 s of system time; its phases went 1.79 → 1.65 s (medians of three interleaved
//! runs). The price is that the process keeps its high-water mark of heap until it ends.
//!
//! Only the time changes: no allocation returns other memory or other values. Elsewhere than
//! Linux with glibc this is a no-op.

/// Applies the policy of the module docs; call it first thing in `main`, before any thread
/// allocates. Returns whether glibc accepted every setting (`false` also where there is no
/// glibc); a setting it refuses leaves its default in place, which is slower, not wrong.
pub fn keep_freed_memory() -> bool {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        use std::ffi::c_int;
        // glibc's <malloc.h>.
        const M_TRIM_THRESHOLD: c_int = -1;
        const M_MMAP_THRESHOLD: c_int = -3;
        const M_ARENA_MAX: c_int = -8;
        extern "C" {
            fn mallopt(param: c_int, value: c_int) -> c_int;
        }
        let settings = [
            (M_ARENA_MAX, 1),
            (M_TRIM_THRESHOLD, c_int::MAX),
            (M_MMAP_THRESHOLD, 32 << 20),
        ];
        // SAFETY: mallopt only sets parameters of glibc's allocator, takes plain integers and
        // is safe to call at any time, from any thread; it returns 1 on success, 0 otherwise.
        settings
            .iter()
            .all(|&(param, value)| unsafe { mallopt(param, value) } == 1)
    }
    #[cfg(not(all(target_os = "linux", target_env = "gnu")))]
    {
        false
    }
}
