//! How much memory a search or a campaign holds, and how much the machine has: the memory
//! budget of `kairos explore` and `kairos campaign` rests on these two readings.
//!
//! A search's memory is mostly clones of the executive (its SAT solver, its belief, its
//! timelines) whose sizes depend on the model, so no count of states predicts it; the process's
//! resident set does, and on Linux the kernel keeps it in `/proc/self/statm` (its second field,
//! in pages). Reading that file costs a few microseconds, so the searches read it once every
//! [`CHECK_EVERY`] new states. Where it cannot be read (another operating system), the searches
//! fall back on their state budget and time budget alone, and say so nowhere: the bound is a
//! guard against exhausting the machine, not a measurement.

use std::fs;

/// A search reads its resident set once every this many new states.
pub const CHECK_EVERY: u64 = 256;

/// The default memory budget of a search or a campaign: 4 GiB, a sixth of the 24 GiB machine
/// the project is built on, so that two campaigns and a build fit beside each other.
pub const DEFAULT_BUDGET: u64 = 4 << 30;

/// The size of a memory page as `/proc/self/statm` counts them. Linux on x86-64 and on most
/// aarch64 kernels uses 4 KiB pages; a kernel with larger pages makes the reading smaller than
/// the truth, never larger, by that factor at most.
const PAGE: u64 = 4096;

/// The process's resident set in bytes, where the operating system tells it.
pub fn resident_bytes() -> Option<u64> {
    let statm = fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    pages.checked_mul(PAGE)
}

/// The machine's physical memory in bytes, where the operating system tells it
/// (`MemTotal` of `/proc/meminfo`, in KiB).
pub fn total_bytes() -> Option<u64> {
    let meminfo = fs::read_to_string("/proc/meminfo").ok()?;
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    kib.checked_mul(1024)
}

/// Parses a number of bytes: digits, optionally followed by `K`, `M`, `G` or `T` (binary
/// multiples: 1 K = 1024 bytes), such as `4G` or `512M`.
pub fn parse_bytes(text: &str) -> Result<u64, String> {
    let bad = || {
        format!(
            "`{text}` is not a number of bytes such as `4G`, `512M` or `1000000` (K, M, G, T are powers of 1024)"
        )
    };
    let trimmed = text.trim();
    let (digits, shift) = match trimmed.char_indices().last() {
        Some((at, unit)) if unit.is_ascii_alphabetic() => {
            let shift = match unit.to_ascii_uppercase() {
                'K' => 10,
                'M' => 20,
                'G' => 30,
                'T' => 40,
                _ => return Err(bad()),
            };
            (&trimmed[..at], shift)
        }
        _ => (trimmed, 0),
    };
    let number: u64 = digits.parse().map_err(|_| bad())?;
    let bytes = number.checked_mul(1u64 << shift).ok_or_else(bad)?;
    if bytes == 0 {
        return Err(bad());
    }
    Ok(bytes)
}

/// Checks a memory budget against the machine before anything starts: a budget larger than
/// the machine's memory bounds nothing.
pub fn check_budget(budget: u64) -> Result<(), String> {
    match total_bytes() {
        Some(total) if budget > total => Err(format!(
            "a memory budget of {} is more than this machine's {}",
            format_bytes(budget),
            format_bytes(total)
        )),
        _ => Ok(()),
    }
}

/// `bytes` in the largest binary unit that keeps a number of at least 1, one decimal.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["bytes", "KiB", "MiB", "GiB", "TiB"];
    let mut value = bytes as f64;
    let mut unit = 0;
    while value >= 1024.0 && unit + 1 < UNITS.len() {
        value /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} bytes")
    } else {
        format!("{value:.1} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn byte_counts_parse_with_binary_units() {
        assert_eq!(parse_bytes("1000"), Ok(1000));
        assert_eq!(parse_bytes("4G"), Ok(4 << 30));
        assert_eq!(parse_bytes("512m"), Ok(512 << 20));
        assert_eq!(parse_bytes("2T"), Ok(2 << 40));
        for bad in ["", "0", "G", "4X", "-1", "1.5G", "99999999999T"] {
            assert!(parse_bytes(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn byte_counts_print_in_their_unit() {
        assert_eq!(format_bytes(512), "512 bytes");
        assert_eq!(format_bytes(4 << 30), "4.0 GiB");
        assert_eq!(format_bytes(1536), "1.5 KiB");
    }

    /// On Linux, where the project is built and tested, both readings exist and are
    /// plausible: a running test holds at least a page and less than the machine.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_readings_exist_on_linux() {
        let resident = resident_bytes().expect("statm");
        let total = total_bytes().expect("meminfo");
        assert!(
            resident >= PAGE && resident < total,
            "{resident} of {total}"
        );
        assert!(check_budget(total + 1).is_err());
        assert!(check_budget(PAGE).is_ok());
    }
}
