//! The memory limit of a step (`--max-memory`, `$TOPOCCD_MAX_MEMORY`).

use std::path::Path;

use anyhow::{bail, Result};
use topoccd::io::{available_memory, MemoryEstimate};

/// The environment variable that sets the default of `--max-memory`.
pub const MAX_MEMORY_ENV: &str = "TOPOCCD_MAX_MEMORY";

/// How much memory a step may need, and where that limit comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MemoryLimit {
    /// No check.
    Off,
    /// At most this many bytes.
    Bytes(u64, LimitSource),
}

/// Where a memory limit comes from, for the error message.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LimitSource {
    /// `--max-memory`.
    Flag,
    /// `$TOPOCCD_MAX_MEMORY`.
    Env,
    /// `MemAvailable` of `/proc/meminfo`.
    Available,
}

pub fn parse_memory_limit(s: &str) -> Result<MemoryLimit, String> {
    parse_size(s).map(|limit| {
        limit.map_or(MemoryLimit::Off, |b| {
            MemoryLimit::Bytes(b, LimitSource::Flag)
        })
    })
}

/// `off` (or `none`) as `None`; else bytes, or a number with a suffix K, M, G or T (powers of
/// 1024, optionally followed by `B` or `iB`).
fn parse_size(s: &str) -> Result<Option<u64>, String> {
    let text = s.trim();
    if text.eq_ignore_ascii_case("off") || text.eq_ignore_ascii_case("none") {
        return Ok(None);
    }
    let upper = text.to_ascii_uppercase();
    let number = upper.trim_end_matches("IB").trim_end_matches('B');
    let (digits, shift) = match number.chars().last() {
        Some('K') => (&number[..number.len() - 1], 10),
        Some('M') => (&number[..number.len() - 1], 20),
        Some('G') => (&number[..number.len() - 1], 30),
        Some('T') => (&number[..number.len() - 1], 40),
        _ => (number, 0),
    };
    let bad = || format!("{s:?} is not a size (bytes, or a number with K, M, G or T; or 'off')");
    let value: f64 = digits.trim().parse().map_err(|_| bad())?;
    let bytes = value * (1u64 << shift) as f64;
    if !(bytes.is_finite() && bytes >= 0.0 && bytes < u64::MAX as f64) {
        return Err(bad());
    }
    Ok(Some(bytes as u64))
}

impl MemoryLimit {
    /// The default limit: `$TOPOCCD_MAX_MEMORY` if set, else the available memory, else none.
    pub fn from_env() -> Result<Self> {
        if let Some(value) = std::env::var_os(MAX_MEMORY_ENV) {
            let text = value.to_string_lossy();
            let limit = parse_size(&text).map_err(|e| anyhow::anyhow!("{MAX_MEMORY_ENV}: {e}"))?;
            return Ok(limit.map_or(MemoryLimit::Off, |b| {
                MemoryLimit::Bytes(b, LimitSource::Env)
            }));
        }
        Ok(available_memory().map_or(MemoryLimit::Off, |b| {
            MemoryLimit::Bytes(b, LimitSource::Available)
        }))
    }

    /// Refuses a step of this size if its estimate exceeds the limit.
    pub fn check(&self, vertices: usize, triangles: usize, t0: &Path, t1: &Path) -> Result<()> {
        let MemoryLimit::Bytes(limit, source) = *self else {
            return Ok(());
        };
        let estimate = MemoryEstimate::of_step(vertices, triangles);
        if let Err(e) = estimate.check(limit) {
            let whence = match source {
                LimitSource::Flag => "set by --max-memory".to_string(),
                LimitSource::Env => format!("set by {MAX_MEMORY_ENV}"),
                LimitSource::Available => "available (MemAvailable in /proc/meminfo)".to_string(),
            };
            bail!(
                "step from {} to {}: {e}, {whence}; refused before reading or building it. \
                 Use --max-memory SIZE (or {MAX_MEMORY_ENV}) to raise the limit, or 'off' to skip \
                 the check",
                t0.display(),
                t1.display(),
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_with_binary_suffixes() {
        assert_eq!(parse_size("123"), Ok(Some(123)));
        assert_eq!(parse_size("4K"), Ok(Some(4096)));
        assert_eq!(parse_size("1.5GiB"), Ok(Some(3 << 29)));
        assert_eq!(parse_size("512mb"), Ok(Some(512 << 20)));
        assert_eq!(parse_size(" 2T "), Ok(Some(2 << 40)));
        assert_eq!(parse_size("off"), Ok(None));
        assert_eq!(parse_size("None"), Ok(None));
        for bad in ["", "G", "-1G", "lots", "1e30T", "NaN", "inf"] {
            assert!(parse_size(bad).is_err(), "{bad}");
        }
    }
}
