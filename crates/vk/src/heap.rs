//! The C heap of a program that draws through a CPU Vulkan driver.
//!
//! lavapipe (llvmpipe) runs inside the program and takes each draw's vertex and binning
//! buffers from the C heap. glibc's `malloc` gives the free top of its heap back to the system
//! whenever it exceeds `M_TRIM_THRESHOLD` (128 KiB unless set), so a frame loop whose draws
//! free and allocate those buffers again gets fresh pages every frame, which the kernel zeroes
//! on first touch. On helmet40 at uniform depth 2 (640×480, 300 frames) that is 3.1–3.4 s in the
//! kernel and a median of 36–38 fps, against 0.1–0.2 s and 55–59 fps with the heap kept
//! (docs/performance.md, "The rendered frame under lavapipe: heap and uploads").
//!
//! Process-wide, so the program decides: the renderer itself never calls it.

/// Keeps freed C heap memory in the process instead of returning it to the system after
/// every large free (glibc on Linux; a no-op elsewhere), and serves blocks up to 32 MiB from
/// the heap rather than from fresh mappings. Memory stays reusable by later allocations; the
/// process keeps its peak C heap until it exits. Call it once, at the start of a program that
/// renders many frames.
pub fn keep_freed_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        // 32 MiB: the largest threshold glibc accepts on 64-bit targets (half its heap size).
        const MMAP_THRESHOLD: libc::c_int = 32 << 20;
        // SAFETY: `mallopt` only sets glibc's allocator parameters (taking its own locks); it
        // has no memory-safety preconditions. A value it refuses leaves the default (it then
        // returns 0), which is no worse than not calling it.
        unsafe {
            libc::mallopt(libc::M_TRIM_THRESHOLD, libc::c_int::MAX);
            libc::mallopt(libc::M_MMAP_THRESHOLD, MMAP_THRESHOLD);
        }
    }
}
