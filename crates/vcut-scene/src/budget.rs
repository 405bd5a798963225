//! How much memory building a scene may take, and what its parts are estimated to take before
//! anything is allocated: a scene file asking for a billion-vertex teapot or a lat-long map wider
//! than memory is refused with the estimate, not discovered by allocation.
//!
//! The estimates are peak bytes while building, measured on this workspace's builders (a teapot
//! at 300 quads per patch edge: 108 B per vertex; a sphere or torus of 2M vertices: 125 B; a
//! 8192-wide sky: 44 B per texel), rounded up.

/// Peak bytes per vertex while a mesh is built (positions, normals, welding), before welding.
pub const MESH_BYTES_PER_VERTEX: u64 = 64;
/// Peak bytes per triangle while a mesh is built.
pub const MESH_BYTES_PER_TRIANGLE: u64 = 32;
/// Peak bytes per texel while a built-in map is baked.
pub const MAP_BYTES_PER_TEXEL: u64 = 48;

/// The memory a scene may use while it is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budget {
    /// Bytes.
    pub max_bytes: u64,
}

impl Budget {
    /// What the machine has available now (Linux: `MemAvailable`), or no limit where that is not
    /// known (the hard limits on each key still hold).
    pub fn available() -> Budget {
        Budget { max_bytes: available_memory().unwrap_or(u64::MAX) }
    }

    /// A budget of `max_bytes`.
    pub fn bytes(max_bytes: u64) -> Budget {
        Budget { max_bytes }
    }
}

/// The memory available to a new allocation now, from `/proc/meminfo` (`MemAvailable`), if
/// this system has it.
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// This process's resident memory now (Linux: `VmRSS`), if the system says.
pub fn resident_memory() -> Option<u64> {
    status_kib("VmRSS:")
}

/// This process's peak resident memory so far (Linux: `VmHWM`), if the system says.
pub fn peak_memory() -> Option<u64> {
    status_kib("VmHWM:")
}

/// Starts a new peak: [`peak_memory`] drops to the resident memory now (Linux: `5` written to
/// `/proc/self/clear_refs`). False where the system does not allow it; a caller then says its
/// peak covers the process's whole life.
pub fn reset_peak_memory() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// Returns the heap's freed memory to the system where the allocator keeps it (glibc:
/// `malloc_trim`), so that [`resident_memory`] and a new peak measure what is in use — before
/// measuring one job's peak after another's in the same process.
#[allow(unsafe_code)] // one of the workspace's two foreign calls (with `lower_thread_priority`)
pub fn trim_heap() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: malloc_trim only releases free pages of glibc's heap; any argument is valid.
    unsafe {
        libc::malloc_trim(0);
    }
}

/// Lowers the calling thread's scheduling priority (Linux: nice +`by`, for this thread alone):
/// background work run on it yields the cores to the threads that must answer at once (a
/// window's, and a CPU rasterizer's). Returns whether the system took it.
#[allow(unsafe_code)] // one of the workspace's two foreign calls (with `trim_heap`)
pub fn lower_thread_priority(by: i32) -> bool {
    #[cfg(target_os = "linux")]
    {
        // SAFETY: getpriority and setpriority read and set a scheduling value; `who` 0 is the
        // calling thread on Linux (its threads have their own nice value); errno is cleared
        // first since -1 is a valid priority.
        unsafe {
            *libc::__errno_location() = 0;
            let now = libc::getpriority(libc::PRIO_PROCESS, 0);
            if now == -1 && *libc::__errno_location() != 0 {
                return false;
            }
            libc::setpriority(libc::PRIO_PROCESS, 0, (now + by).clamp(-20, 19)) == 0
        }
    }
    #[cfg(not(target_os = "linux"))]
    {
        let _ = by;
        false
    }
}

fn status_kib(key: &str) -> Option<u64> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let kib: u64 = text.lines().find(|l| l.starts_with(key))?.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Peak bytes of building a mesh of `vertices` and `triangles` (before welding).
pub fn mesh_bytes(vertices: u64, triangles: u64) -> u64 {
    vertices.saturating_mul(MESH_BYTES_PER_VERTEX).saturating_add(triangles.saturating_mul(MESH_BYTES_PER_TRIANGLE))
}

/// Peak bytes of baking a map of `texels`.
pub fn map_bytes(texels: u64) -> u64 {
    texels.saturating_mul(MAP_BYTES_PER_TEXEL)
}

/// Bytes for people: "512 B", "3.4 MB", "1.21 GB" (SI units).
pub fn human(bytes: u64) -> String {
    let b = bytes as f64;
    match bytes {
        u64::MAX => "unlimited".into(),
        0..1_000 => format!("{bytes} B"),
        1_000..1_000_000 => format!("{:.1} kB", b / 1e3),
        1_000_000..1_000_000_000 => format!("{:.1} MB", b / 1e6),
        _ => format!("{:.2} GB", b / 1e9),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peak_covers_an_allocation_and_resets() {
        let Some(before) = peak_memory() else {
            eprintln!("skipped: this system reports no VmHWM");
            return;
        };
        let big = vec![1u8; 64 << 20];
        std::hint::black_box(&big);
        let peak = peak_memory().unwrap();
        assert!(peak >= before && peak >= 64 << 20, "peak {peak} after a 64 MB allocation");
        drop(big);
        if reset_peak_memory() {
            let after = peak_memory().unwrap();
            assert!(after < peak, "reset peak {after} not below {peak}");
        } else {
            eprintln!("skipped: /proc/self/clear_refs is not writable here");
        }
    }

    #[test]
    fn estimates_saturate_and_read_well() {
        assert_eq!(mesh_bytes(u64::MAX, 1), u64::MAX);
        assert_eq!(mesh_bytes(1000, 2000), 128_000);
        assert_eq!(human(999), "999 B");
        assert_eq!(human(3_400_000), "3.4 MB");
        assert_eq!(human(1_210_000_000), "1.21 GB");
        if let Some(m) = available_memory() {
            assert!(m > 0);
        }
        if let (Some(now), Some(peak)) = (resident_memory(), peak_memory()) {
            assert!(now > 0 && peak >= now, "{now} {peak}");
        }
    }
}
