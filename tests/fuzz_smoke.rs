//! The fuzz targets on the stable toolchain (DESIGN.md §13: no panic, no abort,
//! no hang on any input). `cargo fuzz` needs nightly compiler flags, so CI runs the same entry
//! functions (`fuzz/src/lib.rs`, included below) over
//!
//! - every committed corpus file (`fuzz/corpus/<target>/`: the shipped files and what the
//!   fuzzers kept) and every minimised finding (`fuzz/regressions/<target>/`), and
//! - proptest-generated inputs: the seeds edited at random for the text formats, random bytes read
//!   through the same `arbitrary` generator for the executive.
//!
//! A finding of the fuzzers becomes a file in `fuzz/regressions/<target>/` and a named test at
//! the end of this file (FUZZING.md).

#[path = "../fuzz/src/lib.rs"]
#[allow(dead_code)] // the constants only the fuzz binaries read
mod targets;

#[path = "support/seeded.rs"]
mod seeded;

use std::fs;
use std::path::PathBuf;

use proptest::prelude::*;

/// The files of `fuzz/<kind>/<target>/`, sorted (none if the directory does not exist).
fn files(kind: &str, target: &str) -> Vec<PathBuf> {
    let dir = targets::repository().join("fuzz").join(kind).join(target);
    let mut files: Vec<PathBuf> = fs::read_dir(&dir)
        .map(|entries| entries.filter_map(|e| Some(e.ok()?.path())).collect())
        .unwrap_or_default();
    files.retain(|path| path.is_file());
    files.sort();
    files
}

fn entry(target: &str) -> targets::Entry {
    targets::TARGETS
        .iter()
        .find(|(name, _)| *name == target)
        .map(|&(_, run)| run)
        .unwrap_or_else(|| panic!("no fuzz target {target}"))
}

/// Runs `target` on every corpus and regression file; returns how many there were.
fn replay_files(target: &str) -> usize {
    let run = entry(target);
    let inputs: Vec<PathBuf> = ["corpus", "regressions"]
        .iter()
        .flat_map(|kind| files(kind, target))
        .collect();
    for path in &inputs {
        let data = fs::read(path).expect("a corpus file is readable");
        eprintln!("{target}: {}", path.display());
        run(&data);
    }
    inputs.len()
}

#[test]
fn every_target_has_a_fuzz_binary() {
    for (name, _) in targets::TARGETS {
        let binary = targets::repository().join(format!("fuzz/fuzz_targets/{name}.rs"));
        assert!(binary.is_file(), "{} is missing", binary.display());
    }
}

#[test]
fn corpus_constraint() {
    assert!(
        replay_files("constraint") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_rmpl() {
    assert!(
        replay_files("rmpl") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_plant() {
    assert!(
        replay_files("plant") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_scenario() {
    assert!(
        replay_files("scenario") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_ocsp() {
    assert!(
        replay_files("ocsp") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_estimation_log() {
    assert!(
        replay_files("estimation_log") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_mission() {
    assert!(
        replay_files("mission") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_schedule() {
    assert!(
        replay_files("schedule") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_mission_scenario() {
    assert!(
        replay_files("mission_scenario") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_protocol() {
    assert!(
        replay_files("protocol") > 0,
        "no seeds: run fuzz/seed-corpus.sh"
    );
}

#[test]
fn corpus_executive() {
    replay_files("executive");
}

/// Text that breaks the formats' structure: brackets, separators, operators, numbers at the
/// edges of `f64` and `Duration`, comments, non-ASCII characters.
const FRAGMENTS: &[&str] = &[
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    ",",
    ":",
    ";",
    "\"",
    "=",
    "!=",
    "=>",
    "<=",
    " and ",
    " or ",
    "not ",
    "P(",
    "||",
    "\n",
    "//",
    "/*",
    "*/",
    "0",
    "-1",
    "1e300",
    "NaN",
    "inf",
    "0.0000001",
    "é",
    "∞",
    "\u{0}",
    "Some(",
    "true",
    "s",
    "min",
    "::",
    "Wait(",
    "watching",
    "maintaining",
];

/// One edit of a seed: where (a fraction of the text's length) and what.
#[derive(Debug, Clone)]
enum Edit {
    Insert(&'static str),
    Delete(u8),
    /// Copy the following `n` characters in place: repeats structure (deeper nesting, longer
    /// lists).
    Repeat(u8),
}

fn edit() -> impl Strategy<Value = (u16, Edit)> {
    let kind = prop_oneof![
        prop::sample::select(FRAGMENTS).prop_map(Edit::Insert),
        any::<u8>().prop_map(Edit::Delete),
        any::<u8>().prop_map(Edit::Repeat),
    ];
    (any::<u16>(), kind)
}

/// The seed with the edits applied, each at a character boundary.
fn mutate(seed: &str, edits: &[(u16, Edit)]) -> String {
    let mut chars: Vec<char> = seed.chars().collect();
    for (at, edit) in edits {
        let at = usize::from(*at) * chars.len() / (usize::from(u16::MAX) + 1);
        match edit {
            Edit::Insert(text) => {
                chars.splice(at..at, text.chars());
            }
            Edit::Delete(n) => {
                let end = (at + usize::from(*n)).min(chars.len());
                chars.drain(at..end);
            }
            Edit::Repeat(n) => {
                let end = (at + usize::from(*n)).min(chars.len());
                let copy: Vec<char> = chars[at..end].to_vec();
                chars.splice(at..at, copy);
            }
        }
    }
    chars.into_iter().collect()
}

/// The target's seeds (the shipped files and formulas), as text.
fn seeds(target: &str) -> Vec<String> {
    files("corpus", target)
        .into_iter()
        .filter(|path| {
            path.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("seed-"))
        })
        .filter_map(|path| fs::read_to_string(path).ok())
        .collect()
}

/// Runs `target` on `cases` seeds edited at random (seeded: the same inputs on every run).
fn mutated_seeds(target: &'static str, cases: u32) {
    let all = seeds(target);
    assert!(
        !all.is_empty(),
        "no seeds for {target}: run fuzz/seed-corpus.sh"
    );
    let run = entry(target);
    let strategy = (
        prop::sample::select(all),
        prop::collection::vec(edit(), 1..6),
    );
    let mut runner = proptest::test_runner::TestRunner::new(seeded::config(cases));
    runner
        .run(&strategy, |(seed, edits)| {
            run(mutate(&seed, &edits).as_bytes());
            Ok(())
        })
        .unwrap_or_else(|failure| panic!("{target}: {failure}"));
}

#[test]
fn mutated_constraints() {
    mutated_seeds("constraint", 1024);
}

#[test]
fn mutated_rmpl() {
    mutated_seeds("rmpl", 256);
}

#[test]
fn mutated_plants() {
    mutated_seeds("plant", 256);
}

#[test]
fn mutated_scenarios() {
    mutated_seeds("scenario", 128);
}

#[test]
fn mutated_ocsps() {
    mutated_seeds("ocsp", 256);
}

#[test]
fn mutated_estimation_logs() {
    mutated_seeds("estimation_log", 256);
}

#[test]
fn mutated_missions() {
    mutated_seeds("mission", 128);
}

#[test]
fn mutated_schedules() {
    mutated_seeds("schedule", 128);
}

#[test]
fn mutated_mission_scenarios() {
    mutated_seeds("mission_scenario", 64);
}

#[test]
fn mutated_protocol_scenarios() {
    mutated_seeds("protocol", 256);
}

proptest! {
    #![proptest_config(seeded::config(256))]

    /// The executive target's own generator (`arbitrary`) over random bytes: the same
    /// structure-aware inputs the fuzzer builds, without its coverage feedback.
    #[test]
    fn arbitrary_executive_runs(bytes in prop::collection::vec(any::<u8>(), 0..1024)) {
        targets::executive(&bytes);
    }
}
