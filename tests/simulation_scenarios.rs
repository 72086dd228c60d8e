//! Every scenario under `scenarios/` run through `kairos run` (DESIGN.md
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
    "scenarios/engine_camera/confidence.ron",
    "scenarios/propulsion/nominal.ron",
    "scenarios/propulsion/pde_resettable.ron",
    "scenarios/propulsion/campaign.ron",
    "scenarios/power/nominal.ron",
    "scenarios/power/regulator_a_fails.ron",
    "scenarios/power/both_regulators_fail.ron",
    "scenarios/power/switch_stuck_open.ron",
    "scenarios/power/mission_regulator_a_fails.ron",
    "scenarios/power/campaign.ron",
    "scenarios/power/explore.ron",
];

/// The directories whose scenarios have their own suites: the Mars EDL's
/// (`tests/mars_edl_scenarios.rs`), the spacecraft deployment's
/// (`tests/spacecraft_deployment.rs`), the thermostat's (`tests/thermostat_model.rs`) and the
/// rover's, which `kairos explore` checks rather than `kairos run` (`tests/rover_protocol.rs`).
const SUITE_DIRS: [&str; 4] = [
    "scenarios/mars_edl",
    "scenarios/rover",
    "scenarios/spacecraft_deployment",
    "scenarios/thermostat",
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
        .filter(|p| {
            !SUITE_DIRS
                .iter()
                .any(|d| p.starts_with(format!("{root}/{d}")))
        })
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
    let mut listed: Vec<String> = SCENARIOS.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed, "every scenario is run by these tests");
    for scenario in SCENARIOS {
        let (code, stdout, stderr) = kairos(&["run", "--quiet", scenario]);
        assert_eq!(code, 0, "{scenario}:\n{stdout}\n{stderr}");
        assert!(!stdout.contains("[ "), "--quiet prints no cycles: {stdout}");
    }
}

/// Thesis §6.3.3: PDE on, engine standby, wait for heating, both valves, fire; the PDE is
/// switched off once the goal is achieved. Each command names the goal it serves (the mission
/// log says why): every step toward firing serves `engine = firing`; the PDE's `off` brings back
/// the helper moved for it (DESIGN.md §9: no command "for the intended configuration" alone).
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
            "PDE.cmd = on (PDE: off -> on) for engine = firing (programs/propulsion_fire.rmpl:4:13)",
            "PDE.cmd = engine-standby (engine: off -> heating) for engine = firing (programs/propulsion_fire.rmpl:4:13)",
            "PDE.cmd = open1 (valve1: closed -> open) for engine = firing (programs/propulsion_fire.rmpl:4:13)",
            "PDE.cmd = open2 (valve2: closed -> open) for engine = firing (programs/propulsion_fire.rmpl:4:13)",
            "PDE.cmd = engine-fire (engine: standby -> firing) for engine = firing (programs/propulsion_fire.rmpl:4:13)",
            "PDE.cmd = off (PDE: on -> off) for PDE = off, bringing back a helper moved for engine = firing",
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
/// engine still fires; the trace shows the diagnosis event with its next candidate and its
/// evidence.
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
    // The diagnosis names the next candidate, in its text and structured.
    let event = diagnosis["events"]
        .as_array()
        .and_then(|es| es.iter().find(|e| e["kind"] == "Diagnosis"))
        .expect("the diagnosis event");
    let text = event["text"].as_str().expect("a text");
    assert!(
        text.starts_with(
            "PDE = resettable (p 0.97); evidence: engine.power = zero; next: PDE = on (p 0.03)"
        ),
        "{text}"
    );
    // And its evidence — the latched PDE cut the engine's power, which the
    // PDE on (ŝ of the cycle before) cannot explain.
    assert_eq!(event["evidence"][0], "engine.power = zero");
    assert_eq!(event["next"][0]["mode"], "on");
    let p = event["next"][0]["p"].as_f64().expect("a probability");
    assert!((0.025..0.035).contains(&p), "{p}");
    let last_estimate = lines
        .iter()
        .rev()
        .find_map(|l| l.get("estimate"))
        .expect("an estimate");
    assert_eq!(last_estimate["engine"], "firing");
}

/// Robustness (DESIGN.md §13): unknown names and values, a missing observable and a contradictory
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

/// The fault scenarios show their diagnosis within the tolerance they state, with its evidence.
#[test]
fn fault_scenarios_diagnose_their_fault() {
    let log = passes("scenarios/driver_valve/valve_stuck.ron");
    assert!(log.contains("DIAGNOSIS    valve = stuck-closed"), "{log}");
    // The valve open (ŝ stepped by `open`) passes its inflow (§6.1.3,
    // `flow_out = flow_in`); nominal in and zero out each fit it alone, not together.
    assert!(
        log.contains("evidence: valve.flow_in = nominal & valve.flow_out = zero;"),
        "{log}"
    );
    assert!(log.contains("GOAL FAILED  valve = open"), "{log}");
    let log = passes("scenarios/engine_camera/flameout.ron");
    assert!(log.contains("DIAGNOSIS    engine = failed"), "{log}");
}

/// Thesis §4.4 and §7.1.2: a confidence guard reads the estimator's belief, not
/// ŝ. With no temperature readings, standby becomes the most likely mode half-way through the
/// Uniform(30, 60) s heating window, but P(engine = standby) >= 0.95 only near its end; the
/// camera is switched on then.
#[test]
fn a_confidence_guard_waits_for_the_belief_not_the_most_likely_mode() {
    let log = passes("scenarios/engine_camera/confidence.ron");
    let believed = log
        .find("believed     engine: heating -> standby (p 0.50)")
        .expect("ŝ reaches standby at even odds");
    let camera = log
        .find("command      camera.cmd = on")
        .expect("the camera is switched on");
    assert!(believed < camera, "{log}");
    assert!(log.contains("[    46.000 s   0:00:46.000]"), "{log}");
    assert!(log.contains("[    60.000 s   0:01:00.000]"), "{log}");
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
        stdout.contains("FAIL: 2 of 5 expectations do not hold"),
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

/// Runs `scenario` with `--trace` (and `extra` options); the trace's lines as JSON.
fn trace_of(scenario: &str, name: &str, extra: &[&str]) -> Vec<serde_json::Value> {
    let path = std::env::temp_dir().join(format!("kairos-{name}-{}.jsonl", std::process::id()));
    let path_arg = path.display().to_string();
    let mut args = vec!["run", "--quiet", scenario, "--trace", &path_arg];
    args.extend(extra);
    let (code, _, stderr) = kairos(&args);
    assert_eq!(code, 0, "{stderr}");
    let text = std::fs::read_to_string(&path).expect("the trace is written");
    let _ = std::fs::remove_file(&path);
    text.lines()
        .map(|l| serde_json::from_str(l).expect("each line is JSON"))
        .collect()
}

/// Two traced beliefs: the same states in the same order, probabilities within the trace's
/// resolution (1e-3).
fn same_belief(a: Option<&serde_json::Value>, b: Option<&serde_json::Value>) -> bool {
    let (Some(a), Some(b)) = (a.and_then(|a| a.as_array()), b.and_then(|b| b.as_array())) else {
        return false;
    };
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            let (p, q) = (x["p"].as_f64(), y["p"].as_f64());
            x["modes"] == y["modes"] && p.zip(q).is_some_and(|(p, q)| (p - q).abs() < 1e-3)
        })
}

/// By default the trace says only what changed — a quiet cycle is a short
/// line — and carrying each field forward from the last line that had it gives back the full
/// trace (`--trace-full`), field for field (the belief within the trace's 1e-3 resolution).
#[test]
fn the_trace_holds_changes_only_and_they_add_up_to_the_full_trace() {
    let scenario = "scenarios/propulsion/pde_resettable.ron";
    let changes = trace_of(scenario, "changes", &[]);
    let full = trace_of(scenario, "full", &["--trace-full"]);
    assert_eq!(changes.len(), full.len());
    let carried = ["observation", "estimate", "belief", "distance_bound"];
    let per_cycle = ["command", "events", "plant"];
    let mut known = serde_json::Map::new();
    let mut quiet = 0;
    for (short, long) in changes.iter().zip(&full) {
        for field in carried {
            if let Some(value) = short.get(field) {
                known.insert(field.to_string(), value.clone());
            }
            let (said, truth) = (known.get(field), long.get(field));
            if field == "belief" {
                assert!(same_belief(said, truth), "{said:?} for {truth:?}");
            } else if field == "distance_bound" {
                let (p, q) = (
                    said.and_then(|s| s.as_f64()),
                    truth.and_then(|t| t.as_f64()),
                );
                assert!(
                    p.zip(q).is_some_and(|(p, q)| (p - q).abs() < 1e-2),
                    "{said:?} for {truth:?}"
                );
            } else {
                assert_eq!(said, truth, "{field} at {short}");
            }
        }
        for field in per_cycle {
            let said = short.get(field).cloned().unwrap_or(serde_json::json!([]));
            assert_eq!(Some(&said), long.get(field), "{field} at {short}");
        }
        assert_eq!(short["cycle"], long["cycle"]);
        if carried
            .iter()
            .chain(&per_cycle)
            .all(|f| short.get(f).is_none())
        {
            quiet += 1;
            assert!(short.to_string().len() <= 200, "a quiet line: {short}");
        }
    }
    assert!(
        2 * quiet > changes.len(),
        "most cycles of the run are quiet: {quiet} of {}",
        changes.len()
    );
}

/// `kairos run --timeline FILE.svg` draws the run — one lane per state variable
/// of the model — also when an expectation fails (exit 1), which is the run worth looking at; a
/// path that cannot be written is bad input, reported before the run.
#[test]
fn timeline_draws_the_run_even_when_it_fails() {
    let svg = std::env::temp_dir().join(format!("kairos-timeline-{}.svg", std::process::id()));
    let svg_arg = svg.display().to_string();
    let (code, stdout, stderr) = kairos(&[
        "run",
        "--quiet",
        "tests/scenarios/failing_expectation.ron",
        "--timeline",
        &svg_arg,
    ]);
    assert_eq!(code, 1, "{stdout}\n{stderr}");
    let text = std::fs::read_to_string(&svg).expect("the timeline is written");
    let _ = std::fs::remove_file(&svg);
    let document = roxmltree::Document::parse(&text).expect("the timeline is well-formed SVG");
    let lanes: Vec<&str> = document
        .descendants()
        .filter(|n| n.has_tag_name("g") && n.attribute("class") == Some("lane"))
        .filter_map(|n| n.attribute("data-component"))
        .collect();
    assert_eq!(
        lanes,
        ["PDE", "tank1", "tank2", "valve1", "valve2", "engine"],
        "one lane per component of models/propulsion.ron"
    );

    let (code, stdout, stderr) = kairos(&[
        "run",
        "scenarios/propulsion/nominal.ron",
        "--timeline",
        "no/such/dir/run.svg",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stdout.is_empty(), "nothing runs: {stdout}");
    assert!(
        stderr.contains("cannot write no/such/dir/run.svg"),
        "{stderr}"
    );
}

/// DESIGN.md §9 (redundancy): with both regulators failed, the payload's goal fails and the
/// reason names each alternative way of powering the bus and why it fails.
#[test]
fn power_goal_failure_names_both_regulators() {
    let log = passes("scenarios/power/both_regulators_fail.ron");
    assert!(
        log.contains("reg_a = on (reg_a is failed) or reg_b = on (reg_b is failed)"),
        "{log}"
    );
}
