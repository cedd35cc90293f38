//! Memory guards: large allocations (sparse factors, dense eigen problems, assembly triplets)
//! are estimated before they are made and refused with [`FeError::MemoryRefused`], naming the
//! estimate and the memory available, instead of a panic or an abort of the allocator.
//!
//! The memory available is, in this order: the thread's limit set by [`with_memory_limit`]
//! (tests), the environment variable [`MEMORY_LIMIT_ENV`] (bytes, or a number with the suffix
//! `K`, `M`, `G` or `T`, powers of 1024; `0` or `off` disables the guard), or `MemAvailable` of
//! `/proc/meminfo`. Without any of them (not Linux) nothing is refused.

use crate::FeError;
use std::cell::Cell;

/// Environment variable that overrides the memory available to the guards.
pub const MEMORY_LIMIT_ENV: &str = "FLEXMBS_MEMORY_LIMIT";

/// Largest dimension of the dense eigen path (`solver = "dense"`): its matrices take about
/// [`DENSE_BYTES_PER_ENTRY`] bytes per entry of an `n x n` matrix, 19 GB at this size.
pub const DENSE_MAX_DIM: usize = 20_000;

/// Bytes per entry of an `n x n` matrix that the dense eigen path holds at its peak (K and M
/// densified, the reduced matrix, its eigenvectors and the solver's workspace: six matrices).
pub const DENSE_BYTES_PER_ENTRY: u64 = 6 * 8;

thread_local! {
    static THREAD_LIMIT: Cell<Option<u64>> = const { Cell::new(None) };
}

/// Runs `f` with the memory available to the guards of this thread set to `bytes` (for tests:
/// a small limit exercises a refusal without allocating gigabytes).
pub fn with_memory_limit<R>(bytes: u64, f: impl FnOnce() -> R) -> R {
    let old = THREAD_LIMIT.with(|l| l.replace(Some(bytes)));
    let r = f();
    THREAD_LIMIT.with(|l| l.set(old));
    r
}

/// The memory available to an allocation and where that figure comes from, or `None` when the
/// guard is off or the figure unknown.
pub fn available_memory() -> Option<(u64, &'static str)> {
    if let Some(b) = THREAD_LIMIT.with(Cell::get) {
        return Some((b, "the limit set for this computation"));
    }
    if let Ok(v) = std::env::var(MEMORY_LIMIT_ENV) {
        return parse_size(&v)
            .filter(|&b| b > 0)
            .map(|b| (b, MEMORY_LIMIT_ENV));
    }
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let kib: u64 = info
        .lines()
        .find_map(|l| l.strip_prefix("MemAvailable:"))?
        .split_whitespace()
        .next()?
        .parse()
        .ok()?;
    Some((kib * 1024, "MemAvailable in /proc/meminfo"))
}

/// Parses `123`, `1.5G`, `512M`, `64k` (powers of 1024); `off` is 0.
pub fn parse_size(s: &str) -> Option<u64> {
    let s = s.trim();
    if s.eq_ignore_ascii_case("off") {
        return Some(0);
    }
    let (num, mult) = match s.char_indices().last()? {
        (i, c) if c.is_ascii_alphabetic() => {
            let p = match c.to_ascii_uppercase() {
                'K' => 1u64 << 10,
                'M' => 1 << 20,
                'G' => 1 << 30,
                'T' => 1 << 40,
                _ => return None,
            };
            (&s[..i], p)
        }
        _ => (s, 1),
    };
    let v: f64 = num.trim().parse().ok()?;
    (v.is_finite() && v >= 0.0).then_some((v * mult as f64) as u64)
}

/// Refuses an allocation of about `bytes` for `what` when it exceeds the memory available
/// ([`available_memory`]).
pub fn check_allocation(what: &str, bytes: u64) -> Result<(), FeError> {
    match available_memory() {
        Some((available, source)) if bytes > available => Err(FeError::MemoryRefused {
            what: what.to_string(),
            estimate: bytes,
            available,
            limit_source: source,
        }),
        _ => Ok(()),
    }
}

/// Blocks of at least this many bytes are mapped from the kernel and returned on free
/// ([`fix_mmap_threshold`]).
pub const MMAP_THRESHOLD: usize = 2 << 20;

/// Fixes glibc's mmap threshold at [`MMAP_THRESHOLD`] for the whole process (a program's first
/// call, e.g. in `main`; a no-op on other C libraries). glibc raises the threshold dynamically
/// to the size of each freed mapped block, up to 32 MB; in a modal analysis the Lanczos blocks
/// (`n x 8` doubles, 3.8 MB at 60 000 DOFs) then come from the heap, and the heap's fragmentation
/// keeps freed blocks resident up to the peak (the Sturm check): 15 MB of the 0.66 GB peak at
/// 60 000 DOFs. Smaller blocks (time stepping of reduced models) are not affected.
pub fn fix_mmap_threshold() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    {
        extern "C" {
            fn mallopt(param: std::ffi::c_int, value: std::ffi::c_int) -> std::ffi::c_int;
        }
        const M_MMAP_THRESHOLD: std::ffi::c_int = -3;
        // SAFETY: mallopt only changes a tuning parameter of the allocator (no pointers); the
        // value is a positive int.
        unsafe {
            mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD as std::ffi::c_int);
        }
    }
}

/// `bytes` for messages: `1.23 GB`, `456.7 MB`, `12.0 kB` (powers of 1000).
pub fn format_bytes(bytes: u64) -> String {
    let b = bytes as f64;
    if b >= 1e9 {
        format!("{:.2} GB", b / 1e9)
    } else if b >= 1e6 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.1} kB", b / 1e3)
    }
}

/// Refuses the dense eigen path for `n` unknowns above [`DENSE_MAX_DIM`] or above the memory
/// available.
pub fn check_dense_eigen(n: usize) -> Result<(), FeError> {
    let bytes = DENSE_BYTES_PER_ENTRY.saturating_mul((n as u64).saturating_mul(n as u64));
    if n > DENSE_MAX_DIM {
        return Err(FeError::Invalid(format!(
            "the dense eigen solver is limited to {DENSE_MAX_DIM} unknowns (about {}); this model \
             has {n} (it would need about {}): use the default sparse solver (Lanczos)",
            format_bytes(DENSE_BYTES_PER_ENTRY * (DENSE_MAX_DIM as u64).pow(2)),
            format_bytes(bytes)
        )));
    }
    check_allocation(&format!("dense eigen solution of {n} unknowns"), bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse() {
        assert_eq!(parse_size("123"), Some(123));
        assert_eq!(parse_size("2K"), Some(2048));
        assert_eq!(parse_size("1.5G"), Some(3 << 29));
        assert_eq!(parse_size("off"), Some(0));
        assert_eq!(parse_size("12Q"), None);
        assert_eq!(parse_size("-1M"), None);
    }

    #[test]
    fn thread_limit_refuses_with_the_numbers() {
        with_memory_limit(1000, || {
            let e = check_allocation("test matrix", 5000)
                .unwrap_err()
                .to_string();
            assert!(e.contains("test matrix") && e.contains("5.0 kB") && e.contains("1.0 kB"));
            assert!(check_allocation("small", 999).is_ok());
        });
        // a dense problem above the stated size is refused whatever the memory
        let e = check_dense_eigen(DENSE_MAX_DIM + 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("20000 unknowns"), "{e}");
    }
}
