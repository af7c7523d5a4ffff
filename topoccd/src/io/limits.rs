//! How large an input may be: the memory a whole-step query will need, estimated from the
//! vertex and triangle counts before anything large is read or built, and the memory the
//! system has available. A step that would exceed it can then be refused with a clear error
//! instead of being killed by the operating system halfway through.
//!
//! The estimate was measured with `/usr/bin/time -v topoccd step` (maximum resident set size)
//! on sheets of 250k and 1M triangles, with `Method::Bvh` and 18-DOPs: about 700 bytes per
//! triangle when few features come close (the mesh read twice, the step, its edges and
//! feature boxes, the hierarchy), to which the candidate feature pairs add 8 bytes each. The
//! constants below allow for a typical cloth step's candidates (about 50 per triangle);
//! steps where far more features come close need more (a sheet folded onto itself in one
//! step: about 2.2 kB per triangle).

use std::fmt;
use thiserror::Error;

/// Memory of the program itself and of small fixed buffers, in bytes.
pub const BASE_BYTES: u64 = 16 << 20;
/// Memory per vertex, in bytes: positions at both ends as read and as kept by the step, the
/// vertex boxes and adjacency.
pub const BYTES_PER_VERTEX: u64 = 128;
/// Memory per triangle, in bytes: indices as read and kept, edges, feature boxes, the k-DOP
/// hierarchy (a leaf and about one inner node per triangle) and a typical candidate load.
pub const BYTES_PER_TRIANGLE: u64 = 1024;

/// The memory a whole-step query is expected to need, from the step's size alone.
///
/// ```
/// use topoccd::io::MemoryEstimate;
/// let estimate = MemoryEstimate::of_step(500_000, 1_000_000);
/// assert!(estimate.bytes > 1_000_000_000 && estimate.bytes < 1_200_000_000);
/// assert!(estimate.check(4 << 30).is_ok());
/// let err = estimate.check(512 << 20).unwrap_err();
/// assert_eq!(
///     err.to_string(),
///     "a step of 500000 vertices and 1000000 triangles needs about 1.03 GiB \
///      (estimated), more than the limit of 512 MiB"
/// );
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// Number of vertices of the step.
    pub vertices: usize,
    /// Number of triangles of the step.
    pub triangles: usize,
    /// Estimated peak memory, in bytes (saturated at `u64::MAX`).
    pub bytes: u64,
}

impl MemoryEstimate {
    /// The estimate for a step of `vertices` vertices and `triangles` triangles: reading both
    /// frames, building the step and running one query with [`Method::Bvh`].
    ///
    /// [`Method::Bvh`]: crate::Method::Bvh
    pub fn of_step(vertices: usize, triangles: usize) -> Self {
        let bytes = BASE_BYTES
            .saturating_add((vertices as u64).saturating_mul(BYTES_PER_VERTEX))
            .saturating_add((triangles as u64).saturating_mul(BYTES_PER_TRIANGLE));
        Self {
            vertices,
            triangles,
            bytes,
        }
    }

    /// `Ok` if the estimate fits in `limit` bytes; else why not.
    pub fn check(&self, limit: u64) -> Result<(), TooLarge> {
        if self.bytes <= limit {
            Ok(())
        } else {
            Err(TooLarge {
                vertices: self.vertices,
                triangles: self.triangles,
                needed: self.bytes,
                limit,
            })
        }
    }
}

/// A step whose estimated memory exceeds the limit.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
#[error(
    "a step of {vertices} vertices and {triangles} triangles needs about {} (estimated), \
     more than the limit of {}",
    Bytes(*needed),
    Bytes(*limit)
)]
pub struct TooLarge {
    /// Number of vertices of the step.
    pub vertices: usize,
    /// Number of triangles of the step.
    pub triangles: usize,
    /// The estimate, in bytes.
    pub needed: u64,
    /// The limit, in bytes.
    pub limit: u64,
}

/// The memory available to a new program without swapping, in bytes: `MemAvailable` of
/// `/proc/meminfo` on Linux; `None` where that cannot be read (other systems), in which case
/// a caller should skip the check rather than guess.
///
/// ```
/// if let Some(bytes) = topoccd::io::available_memory() {
///     println!("{}", topoccd::io::Bytes(bytes));
/// }
/// ```
pub fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    mem_available(&text)
}

/// The `MemAvailable:  123456 kB` line of a `/proc/meminfo` text, in bytes.
fn mem_available(meminfo: &str) -> Option<u64> {
    let line = meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?;
    let mut words = line.split_whitespace();
    let value: u64 = words.next()?.parse().ok()?;
    let unit = match words.next() {
        None => 1,
        Some("kB") => 1024,
        Some(_) => return None,
    };
    value.checked_mul(unit)
}

/// A byte count printed with a binary unit: `512 MiB`, `1.03 GiB`, `100 bytes`.
///
/// ```
/// use topoccd::io::Bytes;
/// assert_eq!(Bytes(100).to_string(), "100 bytes");
/// assert_eq!(Bytes(3 << 29).to_string(), "1.50 GiB");
/// assert_eq!(Bytes(64 << 20).to_string(), "64 MiB");
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Bytes(pub u64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        const UNITS: [&str; 6] = ["KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
        if self.0 < 1024 {
            return write!(f, "{} bytes", self.0);
        }
        let mut value = self.0 as f64 / 1024.0;
        let mut unit = 0;
        while value >= 1024.0 && unit + 1 < UNITS.len() {
            value /= 1024.0;
            unit += 1;
        }
        if value.fract() == 0.0 {
            write!(f, "{value:.0} {}", UNITS[unit])
        } else {
            write!(f, "{value:.2} {}", UNITS[unit])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mem_available_is_read_in_bytes() {
        let text = "MemTotal:       24576000 kB\nMemFree:         1000 kB\n\
                    MemAvailable:   20000000 kB\nBuffers: 1 kB\n";
        assert_eq!(mem_available(text), Some(20_000_000 * 1024));
        assert_eq!(mem_available("MemTotal: 5 kB\n"), None);
        assert_eq!(mem_available("MemAvailable: lots\n"), None);
        assert_eq!(mem_available("MemAvailable: 5 MB\n"), None);
    }

    #[test]
    fn estimates_saturate_instead_of_overflowing() {
        let huge = MemoryEstimate::of_step(usize::MAX, usize::MAX);
        assert_eq!(huge.bytes, u64::MAX);
        assert!(huge.check(u64::MAX).is_ok());
        assert!(MemoryEstimate::of_step(0, 0).check(BASE_BYTES).is_ok());
    }
}
