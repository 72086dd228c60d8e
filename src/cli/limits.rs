//! The limits the command line puts on what it is asked for, each a named error (exit 2)
//! rather than a panic, an abort or a machine brought to its knees: threads at most what the
//! machine can run at once, a memory budget at most the machine's memory, times the clock can
//! represent, shards that exist.

use std::time::Duration;

use kairos::exploration::memory;

use super::Failure;

/// How many threads this machine runs at once (`std::thread::available_parallelism`, which
/// honours CPU affinity and cgroup quotas, so a Slurm task sees its own CPUs); 1 when unknown.
pub fn machine_threads() -> usize {
    std::thread::available_parallelism().map_or(1, usize::from)
}

/// `--jobs`: 0 means one per core; more threads than the machine runs at once only add
/// switching, and a mistyped 100000 would start that many, so it is refused.
pub fn threads(jobs: usize) -> Result<usize, Failure> {
    let most = machine_threads();
    match jobs {
        0 => Ok(most),
        n if n <= most => Ok(n),
        n => Err(Failure::bad_input(format!(
            "error: --jobs {n}: this machine runs at most {most} thread{} at once\n  expected: \
             1 to {most}, or 0 for one per core",
            if most == 1 { "" } else { "s" }
        ))),
    }
}

/// `--memory`: parses a number of bytes (`4G`, `512M`) for clap.
pub fn parse_memory(text: &str) -> Result<u64, String> {
    memory::parse_bytes(text)
}

/// Refuses a memory budget larger than the machine, before anything starts.
pub fn memory_budget(bytes: u64) -> Result<u64, Failure> {
    memory::check_budget(bytes)
        .map(|()| bytes)
        .map_err(|message| Failure::bad_input(format!("error: --memory: {message}")))
}

/// Seconds as a [`Duration`]: finite, positive and within what a `Duration` holds (about
/// 5.8 × 10¹¹ years), so that no conversion panics.
pub fn duration(seconds: f64) -> Result<Duration, String> {
    if seconds.is_nan() || seconds <= 0.0 {
        return Err(format!("{seconds} s is not a positive number of seconds"));
    }
    Duration::try_from_secs_f64(seconds)
        .map_err(|_| format!("{seconds} s is more than a duration can hold (about 1.8e19 s)"))
}

/// `--kappa`: how many states estimation tracks, at least 1 (0 tracks nothing and would
/// silently mean 1).
pub fn parse_kappa(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(k) if k >= 1 => Ok(k),
        _ => Err(format!(
            "`{text}` is not a number of states to track, at least 1"
        )),
    }
}

/// `i/n` with `0 ≤ i < n`, such as `3/100`.
pub fn parse_shard(text: &str) -> Result<(u64, u64), String> {
    let bad = || format!("`{text}` is not a shard `i/n` with 0 ≤ i < n, such as 0/4");
    let (i, n) = text.split_once('/').ok_or_else(bad)?;
    let (i, n): (u64, u64) = (
        i.trim().parse().map_err(|_| bad())?,
        n.trim().parse().map_err(|_| bad())?,
    );
    if i < n { Ok((i, n)) } else { Err(bad()) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_are_checked_before_conversion() {
        assert_eq!(duration(90.0), Ok(Duration::from_secs(90)));
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e20] {
            assert!(duration(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn shards_exist() {
        assert_eq!(parse_shard("3/4"), Ok((3, 4)));
        for bad in ["4/4", "0/0", "1", "a/b", "-1/2"] {
            assert!(parse_shard(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn threads_are_at_most_the_machines() {
        let most = machine_threads();
        assert_eq!(threads(0).ok(), Some(most));
        assert_eq!(threads(most).ok(), Some(most));
        assert!(threads(most + 1).is_err());
    }
}
