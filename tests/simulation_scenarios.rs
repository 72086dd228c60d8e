//! Every scenario under `scenarios/` run through `kairos run` (issue 6 items 7 and 8; DESIGN.md
//! §11, §12): exit codes, the key lines of the mission log, and the trace.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

/// The scenarios shipped, each self-checking: `kairos run` exits 0 when its expectations hold.
const SCENARIOS: &[&str] = &[
    "scenarios/driver_valve/nominal.ron",
    "scenarios/driver_valve/valve_stuck.ron",
    "scenarios/driver_valve/odd_observations.ron",
    "scenarios/engine_camera/nominal.ron",
    "scenarios/engine_camera/flameout.ron",
    "scenarios/propulsion/nominal.ron",
    "scenarios/propulsion/pde_resettable.ron",
    "scenarios/mars_edl/pde_resettable.ron",
    "scenarios/mars_edl/engine_stuck_heating.ron",
    "scenarios/mars_edl/engine_power_loss.ron",
];

/// The whole Mars EDL scenarios: ≈ 171,600 cycles each, run by their own tests.
const EDL_SCENARIOS: &[&str] = &[
    "scenarios/mars_edl/nominal.ron",
    "scenarios/mars_edl/pyro_misfire.ron",
    "scenarios/mars_edl/mars_polar_lander.ron",
];

/// Runs a scenario; asserts it passes and returns its log.
fn passes(scenario: &str) -> String {
    let (code, stdout, stderr) = kairos(&["run", scenario]);
    assert_eq!(code, 0, "{scenario}:\n{stdout}\n{stderr}");
    assert!(stdout.contains("\nPASS: "), "{stdout}");
    stdout
}

#[test]
fn every_scenario_directory_file_is_listed_and_passes() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut found: Vec<String> = std::fs::read_dir(format!("{root}/scenarios"))
        .expect("scenarios/ exists")
        .flat_map(|dir| std::fs::read_dir(dir.expect("an entry").path()).expect("a directory"))
        .map(|f| f.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .filter(|p| p.file_name().is_some_and(|n| n != "plant.ron"))
        .map(|p| {
            p.strip_prefix(root)
                .expect("under the root")
                .display()
                .to_string()
        })
        .collect();
    found.sort();
    let mut listed: Vec<String> = SCENARIOS
        .iter()
        .chain(EDL_SCENARIOS)
        .map(|s| s.to_string())
        .collect();
    listed.sort();
    assert_eq!(found, listed, "every scenario is run by these tests");
    for scenario in SCENARIOS {
        let (code, stdout, stderr) = kairos(&["run", "--quiet", scenario]);
        assert_eq!(code, 0, "{scenario}:\n{stdout}\n{stderr}");
        assert!(!stdout.contains("[ "), "--quiet prints no cycles: {stdout}");
    }
}

/// Thesis §6.3.3: PDE on, engine standby, wait for heating, both valves, fire; the PDE is
/// switched off once the goal is achieved.
#[test]
fn propulsion_reaches_firing_with_the_section_6_3_3_sequence() {
    let log = passes("scenarios/propulsion/nominal.ron");
    let commands: Vec<&str> = log
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("command      "))
        .collect();
    assert_eq!(
        commands,
        [
            "PDE.cmd = on (PDE: off -> on)",
            "PDE.cmd = engine-standby (engine: off -> heating)",
            "PDE.cmd = open1 (valve1: closed -> open)",
            "PDE.cmd = open2 (valve2: closed -> open)",
            "PDE.cmd = engine-fire (engine: standby -> firing)",
            "PDE.cmd = off (PDE: on -> off)",
        ],
        "{log}"
    );
    assert!(
        log.contains("believed     engine: standby -> firing"),
        "{log}"
    );
    // Idle cycles are not logged: 46 cycles run, a handful of blocks printed.
    assert!(
        log.lines().filter(|l| l.starts_with('[')).count() < 12,
        "{log}"
    );
}

/// Thesis §6.3, §7.2.4: a resettable PDE injected mid-sequence is diagnosed and reset, and the
/// engine still fires; the trace shows the diagnosis event.
#[test]
fn propulsion_repairs_a_resettable_pde_and_the_trace_shows_the_diagnosis() {
    let trace = std::env::temp_dir().join(format!("kairos-trace-{}.jsonl", std::process::id()));
    let trace_arg = trace.display().to_string();
    let (code, log, stderr) = kairos(&[
        "run",
        "scenarios/propulsion/pde_resettable.ron",
        "--trace",
        &trace_arg,
    ]);
    assert_eq!(code, 0, "{log}\n{stderr}");
    assert!(log.contains("DIAGNOSIS    PDE = resettable"), "{log}");
    assert!(log.contains("REPAIR       PDE.cmd = reset"), "{log}");
    assert!(
        log.contains("(FAULT)"),
        "the injected fault is highlighted: {log}"
    );
    assert!(log.contains("achieved engine = firing"), "{log}");

    let text = std::fs::read_to_string(&trace).expect("the trace is written");
    let _ = std::fs::remove_file(&trace);
    let lines: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("each line is JSON"))
        .collect();
    let cycles = log
        .lines()
        .find_map(|l| l.strip_prefix("run ended at "))
        .and_then(|l| l.split(" after ").nth(1))
        .and_then(|l| l.split(' ').next())
        .and_then(|n| n.parse::<usize>().ok())
        .expect("the summary gives the cycles");
    assert_eq!(lines.len(), cycles, "one line per cycle");
    let diagnosis = lines
        .iter()
        .find(|l| {
            l["events"]
                .as_array()
                .is_some_and(|es| es.iter().any(|e| e["kind"] == "Diagnosis"))
        })
        .expect("a cycle with the diagnosis");
    assert_eq!(diagnosis["estimate"]["PDE"], "resettable");
    assert_eq!(diagnosis["command"][0], "PDE.cmd = reset");
    assert_eq!(
        lines.last().expect("cycles")["estimate"]["engine"],
        "firing"
    );
}

/// Issue 6 acceptance: unknown names and values, a missing observable and a contradictory
/// observation are events, and the run continues to completion.
#[test]
fn odd_observations_are_events_and_the_run_completes() {
    let log = passes("scenarios/driver_valve/odd_observations.ron");
    for line in [
        "rejected     valve.flow_in = \"gushing\": not a value of valve.flow_in",
        "rejected     valve.temperature = \"hot\": no such variable in the plant model",
        "missing      not reported: valve.flow_out",
        "INCONSISTENT no tracked state explains the observation",
        "completed    the program has completed",
    ] {
        assert!(log.contains(line), "missing `{line}` in:\n{log}");
    }
}

/// The fault scenarios show their diagnosis within the tolerance they state.
#[test]
fn fault_scenarios_diagnose_their_fault() {
    let log = passes("scenarios/driver_valve/valve_stuck.ron");
    assert!(log.contains("DIAGNOSIS    valve = stuck-closed"), "{log}");
    assert!(log.contains("GOAL FAILED  valve = open"), "{log}");
    let log = passes("scenarios/engine_camera/flameout.ron");
    assert!(log.contains("DIAGNOSIS    engine = failed"), "{log}");
    // Thesis §7.2.1's fault requirements on the first minutes of the EDL.
    let log = passes("scenarios/mars_edl/pde_resettable.ron");
    assert!(log.contains("REPAIR       PDE.cmd = reset"), "{log}");
    let log = passes("scenarios/mars_edl/engine_stuck_heating.ron");
    assert!(
        log.contains("[    60.200 s]"),
        "diagnosed past 60 s of heating: {log}"
    );
    assert!(log.contains("DIAGNOSIS    engine = failed"), "{log}");
    let log = passes("scenarios/mars_edl/engine_power_loss.ron");
    assert!(log.contains("DIAGNOSIS    engine = failed"), "{log}");
}

/// Thesis §7.2.2 (issue 7 item 3): the nominal EDL at a 0.1 s cycle, from engine standby to
/// landing = success, with §6.3.3's PDE/valve sequence for the powered descent. The log stays a
/// few hundred lines over ≈ 171,600 cycles: idle cycles and `always` goals achieved again are
/// not news.
#[test]
fn the_nominal_mars_edl_lands() {
    let log = passes("scenarios/mars_edl/nominal.ron");
    for line in [
        "command      PDE.cmd = engine-standby (engine: off -> heating)",
        "command      nav.cmd = inertial (nav: earth-relative -> inertial)",
        "command      lander.cmd = fire-primary (lander: connected -> separated)",
        "command      chute.cmd = fire (chute: stowed -> deployed)",
        "command      PDE.cmd = engine-fire (engine: standby -> firing)",
        "command      landing.cmd = set-success (landing: in-progress -> success)",
        "completed    the program has completed",
    ] {
        assert!(log.contains(line), "missing `{line}` in:\n{log}");
    }
    assert!(log.lines().count() < 400, "{log}");
}

/// Thesis §3.3: the primary separation pyro misfires; the executive diagnoses the unsuccessful
/// attempt and fires the backup, then lands.
#[test]
fn the_mars_edl_recovers_from_a_pyro_misfire() {
    let log = passes("scenarios/mars_edl/pyro_misfire.ron");
    for line in [
        "DIAGNOSIS    lander = unsuccessful-attempt",
        "REPAIR       lander.cmd = fire-backup",
        "achieved landing = success",
    ] {
        assert!(log.contains(line), "missing `{line}` in:\n{log}");
    }
}

/// Thesis §1.1 (DESIGN.md §11): a touchdown-sensor spike latched at leg deployment must not shut
/// the engine down before the 12 m trigger; the program resets the flag and lands.
#[test]
fn the_mars_polar_lander_spike_does_not_stop_the_engine() {
    let log = passes("scenarios/mars_edl/mars_polar_lander.ron");
    assert!(
        log.contains("command      touchdown_sensor.cmd = reset"),
        "{log}"
    );
    let engine_off = log
        .find("PDE.cmd = engine-off")
        .expect("the engine is shut down at touchdown");
    let twelve_metres = log
        .find("rule `12 m` takes effect")
        .expect("the 12 m trigger");
    assert!(twelve_metres < engine_off, "{log}");
}

/// DESIGN.md §11: "`kairos run SCENARIO` exits non-zero when one fails" — 1, naming each.
#[test]
fn a_failing_expectation_exits_1_and_is_named() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/failing_expectation.ron"]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("  ok     program completed by 100 s"),
        "{stdout}"
    );
    assert!(
        stdout.contains("  FAILED never estimated engine = firing: at "),
        "{stdout}"
    );
    assert!(
        stdout.contains("  FAILED commanded PDE.cmd = reset: not shown by the end"),
        "{stdout}"
    );
    assert!(
        stdout.contains("FAIL: 2 of 3 expectations do not hold"),
        "{stdout}"
    );
    assert!(
        stderr.contains(
            "2 expectations failed: never estimated engine = firing; commanded PDE.cmd = reset"
        ),
        "{stderr}"
    );
}

/// DESIGN.md §12: 2 on bad input, with the located message on standard error.
#[test]
fn bad_input_exits_2() {
    let (code, stdout, stderr) = kairos(&["run", "tests/bad_scenarios/unknown_value.ron"]);
    assert_eq!(code, 2);
    assert!(stdout.is_empty(), "{stdout}");
    assert!(stderr.contains("unknown_value.ron:8:74"), "{stderr}");
    let (code, _, stderr) = kairos(&["run", "no/such/scenario.ron"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("cannot read no/such/scenario.ron"),
        "{stderr}"
    );
    let (code, _, stderr) = kairos(&[
        "run",
        "scenarios/propulsion/nominal.ron",
        "--trace",
        "no/such/dir/trace.jsonl",
    ]);
    assert_eq!(code, 2, "{stderr}");
}
