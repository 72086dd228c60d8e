//! What the command line may ask for (DESIGN.md §13: no panic, no abort, no exhausted machine
//! on any input): each finding of a black-box campaign of options, run through `kairos` as a
//! user would — a duration too long for the clock, threads by the hundred thousand, runs or a
//! search that would exhaust memory, κ silently ignored, a projection before the start, shards
//! of different campaigns merged, an unwritable output reported as a failed run.

#[path = "support/cli.rs"]
mod cli;

use std::path::PathBuf;

use cli::kairos;

const FLAMEOUT: &str = "tests/scenarios/explore_flameout.ron";
const NOISY: &str = "tests/scenarios/campaign_noisy.ron";

/// A fresh directory in this test binary's scratch space.
fn scratch_dir(name: &str) -> String {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("limits-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir.display().to_string()
}

fn refused(args: &[&str], says: &str) {
    let (code, stdout, stderr) = kairos(args);
    assert_eq!(code, 2, "{args:?}: {stdout}{stderr}");
    assert!(stderr.contains(says), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
}

/// `--budget 1e20s` panicked converting to a `Duration`; a budget the clock cannot hold, zero
/// or not a number is refused by name.
#[test]
fn budgets_are_durations_the_clock_can_hold() {
    refused(
        &["explore", FLAMEOUT, "--budget", "1e20s"],
        "more than a duration can hold",
    );
    refused(&["explore", FLAMEOUT, "--budget", "0s"], "--budget");
    refused(&["explore", FLAMEOUT, "--budget", "NaNs"], "--budget");
    refused(&["explore", FLAMEOUT, "--depth", "0"], "--depth");
}

/// `--jobs 100000` started 100,000 threads; more than the machine runs at once is refused,
/// saying how many it does.
#[test]
fn threads_are_at_most_the_machines() {
    refused(
        &["explore", FLAMEOUT, "--jobs", "100000"],
        "this machine runs at most",
    );
    refused(
        &["campaign", NOISY, "--runs", "2", "--jobs", "100000"],
        "this machine runs at most",
    );
}

/// `campaign --runs 1000000000` aborted allocating gigabytes; a shard whose records cannot fit
/// the memory budget is refused before it starts, with the shard count that fits. A budget
/// larger than the machine is refused too.
#[test]
fn campaigns_that_cannot_fit_are_refused_before_they_start() {
    refused(
        &["campaign", NOISY, "--runs", "1000000000"],
        "split the campaign into at least 477 shards",
    );
    refused(&["campaign", NOISY, "--runs", "0"], "--runs");
    refused(
        &["campaign", NOISY, "--runs", "2", "--memory", "1000T"],
        "more than this machine's",
    );
    refused(
        &["explore", FLAMEOUT, "--memory", "1000T"],
        "more than this machine's",
    );
    refused(
        &["explore", FLAMEOUT, "--memory", "12X"],
        "not a number of bytes",
    );
}

/// A search stopped by its memory budget says so and what it covered; here the budget is
/// below what the process already holds, so the search stops at its first check.
#[test]
fn a_search_stops_at_its_memory_budget() {
    let (code, stdout, stderr) = kairos(&[
        "explore",
        FLAMEOUT,
        "--faults",
        "2",
        "--memory",
        "1M",
        "--quiet",
        "--no-replay",
    ]);
    assert!(code <= 1, "{stderr}");
    assert!(
        stdout.contains("covered: partly — the memory budget (1.0 MiB) ran out"),
        "{stdout}"
    );
}

/// Thirty optional rules with thirty faults a path: the sets of rules that may fire together
/// number 2³⁰ and were all made before the first was tried (1.6 GB, then an abort); they are
/// made one at a time now, and the time budget ends the search.
#[test]
fn thirty_optional_rules_are_tried_within_the_budget() {
    let rules: String = (0..30)
        .map(|i| {
            format!(
                "Rule(name: \"fault {i}\", on: Optional(from: 40.0, to: 70.0, every: 10), \
                 when: \"engine.thrust = nominal\", set: {{ \"engine.thrust\": \"zero\" }}),\n"
            )
        })
        .collect();
    // Written outside the source tree, with the shipped files it names made absolute.
    let root = format!("{}/", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(FLAMEOUT)
        .expect("the flame-out scenario")
        .replace("../../", &root);
    let start = text.find("rules: [").expect("rules");
    let end = text.find("expect:").expect("expect");
    let scenario = format!(
        "{}rules: [\n{rules}],\n    {}",
        &text[..start],
        &text[end..]
    );
    let dir = scratch_dir("thirty");
    std::fs::create_dir_all(&dir).expect("writable");
    let path = PathBuf::from(dir).join("thirty_rules.ron");
    std::fs::write(&path, scenario).expect("writable");
    let file = path.display().to_string();
    let (code, stdout, stderr) = kairos(&[
        "explore",
        &file,
        "--faults",
        "30",
        "--budget",
        "3s",
        "--quiet",
        "--no-replay",
    ]);
    assert!(code <= 1, "{stdout}{stderr}");
    assert!(
        stdout.contains("covered: partly — the time budget ran out"),
        "{stdout}"
    );
}

/// `bench SCENARIO --kappa 3` ran at the scenario's κ and said nothing; it runs at each κ
/// given now, and κ = 0 (which tracked one state without a word) is refused.
#[test]
fn bench_runs_a_scenario_at_each_kappa_given() {
    let (code, stdout, stderr) = kairos(&[
        "bench",
        "scenarios/propulsion/nominal.ron",
        "--kappa",
        "3,7",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("κ = 3"), "{stdout}");
    assert!(stdout.contains("κ = 7"), "{stdout}");
    refused(
        &["bench", "scenarios/propulsion/nominal.ron", "--kappa", "0"],
        "at least 1",
    );
    refused(
        &[
            "estimate",
            "--plant",
            "models/driver_valve.ron",
            "--log",
            "x",
            "--kappa",
            "0",
        ],
        "at least 1",
    );
}

/// `schedule --at` before the mission's start is refused like a time that is not a number.
#[test]
fn a_projection_is_at_or_after_the_start() {
    refused(
        &["schedule", "missions/thermostat_stay_warm.ron", "--at=-5"],
        "at or after the mission's start",
    );
}

/// `campaign merge` joined shards run with different seeds without a word; it refuses shards
/// of different campaigns, naming the option that differs, and missing or repeated shards.
#[test]
fn merges_refuse_shards_of_different_runs() {
    let shard = |name: &str, seed: &str, i: &str| {
        let dir = scratch_dir(name);
        let (code, _, stderr) = kairos(&[
            "campaign", NOISY, "--runs", "4", "--seed", seed, "--shard", i, "--out", &dir,
            "--jobs", "1",
        ]);
        assert!(code <= 1, "{stderr}");
        dir
    };
    let a = shard("seed1-0", "1", "0/2");
    let b = shard("seed2-1", "2", "1/2");
    let c = shard("seed1-1", "1", "1/2");
    refused(
        &["campaign", "merge", &a, &b],
        "their --seed differ (1 and 2)",
    );
    refused(&["campaign", "merge", &a], "shard 1/2 missing");
    refused(&["campaign", "merge", &a, &a], "shard 0/2 is given twice");
    let (code, stdout, stderr) = kairos(&["campaign", "merge", &a, &c]);
    assert!(code <= 1, "{stderr}");
    assert!(
        stdout.contains("merged from 2 shards (seed 1, 4 runs)"),
        "{stdout}"
    );

    let search = scratch_dir("search-0");
    let (code, _, stderr) = kairos(&[
        "explore", FLAMEOUT, "--shard", "0/2", "--out", &search, "--quiet",
    ]);
    assert!(code <= 1, "{stderr}");
    refused(
        &["campaign", "merge", &a, &search],
        "not of `kairos campaign`",
    );
    refused(&["explore", "merge", &search], "shard 1/2 missing");
}

/// An output that cannot be written is exit 2 (bad input or environment), not exit 1 (a run
/// that failed).
#[test]
fn an_unwritable_output_exits_2() {
    let blocker = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("limits-a-file");
    std::fs::write(&blocker, "not a directory").expect("writable");
    let inside = blocker.join("out").display().to_string();
    refused(
        &["campaign", NOISY, "--runs", "1", "--out", &inside],
        "cannot create",
    );
    refused(
        &[
            "run",
            "scenarios/propulsion/nominal.ron",
            "--timeline",
            &inside,
        ],
        "cannot write",
    );
    refused(
        &["explore", FLAMEOUT, "--shard", "0/2", "--out", &inside],
        "cannot create",
    );
}
