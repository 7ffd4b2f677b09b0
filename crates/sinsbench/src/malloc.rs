//! The C allocator's policy for this process (glibc on Linux).
//!
//! By default glibc serves blocks of 128 kB and more by `mmap`, raises that threshold to the
//! size of the largest such block freed (up to 32 MB), and gives the top of a thread's heap
//! back to the system once twice that much of it is free. The Parquet writer's encoder
//! allocates and frees a page buffer of about 0.5 MB per column and row group, so each page was
//! written into fresh, zero-filled pages: 0.92 M page faults and 3.0 s of system time for one
//! 15 h dataset (5.4 s of user time). Blocks up to 32 MB from the heap and 8 MB of free heap
//! kept bring that to 7-9 k faults and 0.6-1.2 s. A 4 MB threshold, tried first, made the noise
//! identification worse (0.43 M faults, 1.9 s of system time against 0.5 s by default), its
//! blocks of 4-32 MB then coming by `mmap` each time; keeping 64 MB of free heap cost the
//! diagnosis 84 MB of peak memory for nothing, and 8 MB kept cost it 0.8 s of system time
//! (glibc's own rule keeps more there), so only the commands whose main cost is writing a
//! dataset (`simulate`, `import`) set it. No output changes (session 38).

/// Largest block served from the heap rather than by `mmap` (bytes).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const MMAP_THRESHOLD_BYTES: libc::c_int = 32 << 20;
/// Free memory kept at the top of a heap before it is given back to the system (bytes).
#[cfg(all(target_os = "linux", target_env = "gnu"))]
const TRIM_THRESHOLD_BYTES: libc::c_int = 8 << 20;

/// Set the policy above for the rest of the process (`simulate`, `import`). Elsewhere than on
/// glibc it does nothing. A refusal (a value out of glibc's range) leaves the default.
pub fn tune() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets allocator parameters (under the allocator's own lock) and takes
    // plain integers.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES);
        libc::mallopt(libc::M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES);
    }
}
