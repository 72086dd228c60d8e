//! `kairos bench` (DESIGN.md §12, §14): per-phase cycle times, quiet and busy
//! cycles apart, for a scenario and for estimation over a replay log. Only the shape of the
//! report is checked — counts, ordering of the statistics — never a time.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;
use serde_json::Value;

/// Checks one quiet/busy part of a section: its phases' statistics are ordered.
fn check_kind(kind: &Value, phases: &[&str]) -> u64 {
    let count = kind["count"].as_u64().expect("a count");
    for phase in phases {
        let stats = &kind["phases"][phase];
        if count == 0 {
            assert!(stats.is_null(), "no samples, no statistics: {kind}");
            continue;
        }
        let get = |name: &str| stats[name].as_u64().expect("a statistic");
        assert!(get("min_ns") <= get("median_ns"), "{stats}");
        assert!(get("median_ns") <= get("p99_ns"), "{stats}");
        assert!(get("p99_ns") <= get("max_ns"), "{stats}");
    }
    count
}

#[test]
fn a_scenario_is_measured_per_phase_with_every_cycle_quiet_or_busy() {
    let (code, stdout, stderr) = kairos(&["bench", "--json", "scenarios/propulsion/nominal.ron"]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).expect("one JSON object");
    let subject = report["subject"].as_str().expect("a subject");
    let cycles: u64 = subject
        .rsplit('(')
        .next()
        .and_then(|s| s.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("the cycle count in the subject");
    let section = &report["sections"][0];
    let phases = [
        "estimation",
        "sequencer",
        "reconfiguration",
        "submission",
        "cycle",
    ];
    let quiet = check_kind(&section["quiet"], &phases);
    let busy = check_kind(&section["busy"], &phases);
    assert_eq!(quiet + busy, cycles);
    // The nominal propulsion run commands seven times and then holds: both kinds occur.
    assert!(quiet > 0 && busy >= 7, "quiet {quiet}, busy {busy}");
}

#[test]
fn a_replay_log_is_measured_once_per_kappa() {
    let (code, stdout, stderr) = kairos(&[
        "bench",
        "--plant",
        "models/mars_lander.ron",
        "--log",
        "tests/logs/mars_lander_first_minutes.jsonl",
        "--kappa",
        "1,10",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.contains("estimation, TimedME κ = 1\n"), "{stdout}");
    assert!(stdout.contains("estimation, TimedME κ = 10\n"), "{stdout}");
    for line in stdout
        .lines()
        .filter(|l| l.trim_start().starts_with("quiet"))
    {
        assert!(line.contains("estimation"), "estimation alone: {line}");
    }
}

#[test]
fn bench_needs_a_scenario_or_a_plant_and_a_log() {
    let (code, _, stderr) = kairos(&["bench", "--plant", "models/mars_lander.ron"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, stderr) = kairos(&["bench", "no/such/scenario.ron"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("no/such/scenario.ron"), "{stderr}");
}

/// Goals submitted to a running mission are the next cycle's work (rescheduling the network):
/// their time is that cycle's `submission` phase and part of its whole-cycle time, which a
/// deadline is held to. 150 submissions took 25 s while `bench` showed a 5 ms worst cycle.
#[test]
fn submissions_are_counted_in_the_cycle_that_follows_them() {
    let (code, stdout, stderr) = kairos(&[
        "bench",
        "--json",
        "scenarios/thermostat/stay_warm_submitted.ron",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let report: Value = serde_json::from_str(&stdout).expect("one JSON object");
    let busy = &report["sections"][0]["busy"]["phases"];
    let max = |phase: &str| busy[phase]["max_ns"].as_u64().expect("a maximum");
    assert!(max("submission") > 0, "{busy}");
    assert!(max("cycle") >= max("submission"), "{busy}");
}
