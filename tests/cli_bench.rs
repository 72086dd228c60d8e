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

/// `kairos bench --json` of Livingstone 2's 15-breaker log at `kappa`, with `extra` options:
/// the report, parsed (the run must succeed).
fn breaker_bench(kappa: &str, extra: &[&str]) -> Value {
    let log = "tests/logs/l2_breakers_15.jsonl";
    let plant = "models/l2_breakers_15.ron";
    let base = [
        "bench", "--json", "--plant", plant, "--log", log, "--kappa", kappa,
    ];
    let (code, stdout, stderr) = kairos(&[&base[..], extra].concat());
    assert_eq!(code, 0, "{stderr}");
    serde_json::from_str(&stdout).expect("one JSON object")
}

/// Livingstone 2's breaker benchmark commands every cycle: every cycle is busy, and the mean
/// over all cycles and the satisfiability questions asked per cycle are reported.
#[test]
fn a_replay_reports_its_mean_cycle_and_questions_asked() {
    let report = breaker_bench("3", &[]);
    let section = &report["sections"][0];
    let busy = check_kind(&section["busy"], &["estimation"]);
    assert_eq!(busy, 1600, "100 cycles of 16 steps, each with a command");
    let all = &section["all"];
    assert_eq!(all["count"].as_u64(), Some(1600), "{all}");
    let mean = all["mean_ns"].as_u64().expect("a mean");
    let stats = &section["busy"]["phases"]["estimation"];
    let (min, max) = (stats["min_ns"].as_u64(), stats["max_ns"].as_u64());
    assert!(min <= Some(mean) && Some(mean) <= max, "{section}");
    assert!(all["sat_calls"].as_u64().is_some_and(|n| n > 0), "{all}");
}

/// `--rerun surprise` reaches the estimator (src/estimation/timed_me.rs, "When the window is
/// re-run"): on the breaker log, observed in part, doubt re-runs the window on most steps at
/// 8κ, so re-running on surprise alone asks fewer satisfiability questions; the sections say
/// which policy they measured. Counts, not times: the questions asked are deterministic.
#[test]
fn a_replay_is_measured_under_the_rerun_policy_given() {
    let sat_calls = |extra: &[&str]| {
        let report = breaker_bench("5", extra);
        let section = &report["sections"][0];
        let calls = section["all"]["sat_calls"].as_u64().expect("a count");
        (
            section["title"].as_str().unwrap_or_default().to_string(),
            calls,
        )
    };
    let (doubt_title, doubt) = sat_calls(&[]);
    let (surprise_title, surprise) = sat_calls(&["--rerun", "surprise"]);
    assert_eq!(doubt_title, "estimation, TimedME κ = 5");
    assert_eq!(
        surprise_title,
        "estimation, TimedME κ = 5, re-run on surprise"
    );
    assert!(surprise < doubt, "surprise {surprise}, doubt {doubt}");
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
