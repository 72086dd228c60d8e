//! One configuration for every property test, so CI is deterministic (DESIGN.md §13).
//!
//! By default a property test runs a fixed number of cases from a fixed seed: the same cases on
//! every run and every machine. Two environment variables open it up for exploration before a
//! submission:
//!
//! - `KAIROS_CASES=N` runs N cases instead of the test's default;
//! - `KAIROS_PROPTEST_SEED=random` draws a fresh seed per test (proptest prints the failing
//!   case and writes it to the test's `.proptest-regressions` file, replayed first from then
//!   on); `KAIROS_PROPTEST_SEED=N` replays seed N.
//!
//! `KAIROS_CASES=25600 KAIROS_PROPTEST_SEED=random cargo test --release --test NAME` is the
//! exploration run (docs/design/testing.md).
#![allow(dead_code)] // each includer uses a different part

use proptest::test_runner::{Config, RngSeed, TestRunner};

/// The seed every property test starts from unless `KAIROS_PROPTEST_SEED` says otherwise.
pub const DEFAULT_SEED: u64 = 0x6b61_6972_6f73; // "kairos"

/// The number of cases: `KAIROS_CASES` if set to a number, else `default`.
pub fn cases(default: u32) -> u32 {
    std::env::var("KAIROS_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

/// The seed: fixed by default, random or another fixed one from `KAIROS_PROPTEST_SEED`.
pub fn seed() -> RngSeed {
    match std::env::var("KAIROS_PROPTEST_SEED") {
        Ok(value) if value.eq_ignore_ascii_case("random") => RngSeed::Random,
        Ok(value) => RngSeed::Fixed(value.trim().parse().unwrap_or_else(|_| {
            panic!("KAIROS_PROPTEST_SEED must be `random` or a number, not {value:?}")
        })),
        Err(_) => RngSeed::Fixed(DEFAULT_SEED),
    }
}

/// The proptest configuration of a property test with `default_cases` cases.
pub fn config(default_cases: u32) -> Config {
    Config {
        cases: cases(default_cases),
        rng_seed: seed(),
        ..Config::default()
    }
}

/// A test runner for hand-driven loops over generated cases (tests that tally a rate over many
/// cases rather than stopping at the first failure), seeded like [`config`].
pub fn runner() -> TestRunner {
    TestRunner::new(config(1))
}
