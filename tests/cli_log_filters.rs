//! The mission log's filters and its wording (DESIGN.md §12): `--hide-plant`,
//! `--only COMPONENT…`, `--from T`, `--to T` choose what is printed, never what is checked; a
//! repair and a wait are said once ("REPAIR PDE.cmd = reset", "waiting after …"); a goal its
//! location asserts again is "re-asserted"; a preemption names its construct and condition.

use std::process::Command;

fn kairos(args: &[&str]) -> (Option<i32>, String, String) {
    let output = Command::new(env!("CARGO_BIN_EXE_kairos"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .expect("kairos runs");
    let text = |bytes: &[u8]| String::from_utf8_lossy(bytes).into_owned();
    (
        output.status.code(),
        text(&output.stdout),
        text(&output.stderr),
    )
}

/// The cycles' blocks of a log (header and summary left out: the summary has wall times).
fn blocks(log: &str) -> String {
    log.lines()
        .skip_while(|l| !l.starts_with('['))
        .take_while(|l| !l.starts_with("run ended"))
        .collect::<Vec<_>>()
        .join("\n")
        .trim_end()
        .to_string()
}

/// The PDE latch-up scenario's first 0.5 s, only the PDE, no plant rules: the diagnosis, the
/// repair said once, the PDE's own mode changes — and none of the engine's.
#[test]
fn only_the_pde_until_half_a_second() {
    let (code, stdout, stderr) = kairos(&[
        "run",
        "scenarios/mars_edl/pde_resettable.ron",
        "--hide-plant",
        "--only",
        "PDE",
        "--to",
        "0.5",
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let log = blocks(&stdout);
    assert!(
        log.contains("REPAIR       PDE.cmd = reset (PDE: resettable -> on)"),
        "{log}"
    );
    assert!(!log.contains("(repair)"), "{log}");
    assert!(!log.contains("plant "), "{log}");
    assert!(!log.contains("engine: off -> heating (p"), "{log}");
    // The verdicts are whole whatever the filter.
    assert!(stdout.contains("PASS:"), "{stdout}");
    insta::assert_snapshot!(log);
}

/// A wait is said once: `waiting  after Uniform(30, 60) s (engine: heating -> standby)`; a
/// plant rule setting `engine.power` names the engine.
#[test]
fn a_wait_is_not_waiting_wait() {
    let (code, stdout, stderr) = kairos(&[
        "run",
        "scenarios/mars_edl/pde_resettable.ron",
        "--only",
        "engine",
        "--from",
        "0.25",
        "--to",
        "0.35",
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let log = blocks(&stdout);
    assert_eq!(
        log,
        "[     0.300 s   0:00:00.300] #3\n  plant        rule `engine powers up` takes effect: engine.power = nominal\n  believed     engine: off -> heating (p 1.00)\n  waiting      after Uniform(30, 60) s (engine: heating -> standby)"
    );
}

/// An unknown component is bad input with a suggestion; an empty time range is refused.
#[test]
fn bad_filters_are_refused_before_the_run() {
    let (code, _, stderr) = kairos(&[
        "run",
        "scenarios/mars_edl/pde_resettable.ron",
        "--only",
        "valve3",
    ]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(
        stderr.contains("--only valve3: no such component"),
        "{stderr}"
    );
    assert!(stderr.contains("did you mean `valve2`?"), "{stderr}");
    let (code, _, stderr) = kairos(&[
        "run",
        "scenarios/mars_edl/pde_resettable.ron",
        "--from",
        "10",
        "--to",
        "5",
    ]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("--from 10 is after --to 5"), "{stderr}");
}

/// A goal asserted again by the same program location — each iteration of the camera loop's
/// `always` re-enters `camera = taking-picture` (thesis §5.2: the sequencer re-marks the
/// location) — is reported `re-asserted`; the first assertion, and a location entered once
/// (`camera = idle`), say `asserted`.
#[test]
fn a_goal_asserted_again_by_its_location_is_re_asserted() {
    let (code, stdout, stderr) = kairos(&["run", "tests/scenarios/camera_pictures.ron"]);
    assert_eq!(code, Some(0), "{stderr}");
    let log = blocks(&stdout);
    let picture = "camera = taking-picture  (tests/scenarios/camera_loop.rmpl:5:43)";
    let first = format!("goal         asserted {picture}");
    let again = format!("goal         re-asserted {picture}");
    assert_eq!(log.matches(&first).count(), 1, "{log}");
    assert!(log.matches(&again).count() >= 2, "{log}");
    assert!(log.find(&first) < log.find(&again), "{log}");
    assert_eq!(log.matches("asserted camera = idle").count(), 1, "{log}");
    assert!(!log.contains("re-asserted camera = idle"), "{log}");
}

/// A preemption names the construct and the condition whose entailment preempted it (the mission
/// log says why; thesis §5.2 `do A watching c`, Figure 5-3 step 2): when IMU_1 fails, `do (IMU_1 =
/// on) watching (IMU_1 = failed)` is preempted "IMU_1 = failed became entailed", the
/// condition quoted from the program; the trace carries it rendered from the formula, with
/// `entailed`; an event printed on its own (`Display`, no program) renders it too.
#[test]
fn a_preemption_names_the_construct_and_the_condition_that_became_entailed() {
    let scenario = "scenarios/spacecraft_deployment/imu_1_fails.ron";
    let trace = std::env::temp_dir().join(format!("kairos-preempt-{}.jsonl", std::process::id()));
    let trace_arg = trace.display().to_string();
    let (code, stdout, stderr) = kairos(&[
        "run",
        scenario,
        "--hide-plant",
        "--from",
        "600",
        "--to",
        "605",
        "--trace",
        &trace_arg,
    ]);
    assert_eq!(code, Some(0), "{stderr}");
    let log = blocks(&stdout);
    let watch = "preempted    do … watching (programs/spacecraft_deployment.rmpl:33:3): \
                 IMU_1 = failed became entailed";
    assert!(log.contains(watch), "{log}");
    insta::assert_snapshot!(log);

    let text = std::fs::read_to_string(&trace).expect("the trace is written");
    let _ = std::fs::remove_file(&trace);
    let preemptions: Vec<serde_json::Value> = text
        .lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).expect("each line is JSON"))
        .flat_map(|l| l["events"].as_array().cloned().unwrap_or_default())
        .filter(|e| e["kind"] == "Preempted")
        .collect();
    let conditions: Vec<&str> = preemptions
        .iter()
        .map(|e| e["condition"].as_str().expect("a condition"))
        .collect();
    assert_eq!(
        conditions,
        [
            "SSR_A = on or SSR_B = on",
            "IMU_1 = failed",
            "spacecraft_deployment = success or spacecraft_deployment = failure",
        ]
    );
    assert!(preemptions.iter().all(|e| e["entailed"] == true));

    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(scenario);
    let loaded = kairos::simulation::load(&path).expect("the scenario loads");
    let options = kairos::simulation::RunOptions::default();
    let run = kairos::simulation::run(&loaded, options, &mut |_| {}).expect("it runs");
    let bare: Vec<String> = run
        .events
        .iter()
        .filter(|e| matches!(e.kind, kairos::executive::EventKind::Preempted { .. }))
        .map(|e| e.kind.to_string())
        .collect();
    assert!(
        bare.iter()
            .any(|e| e.starts_with("preempted do … watching (bytes ")
                && e.ends_with("): IMU_1 = failed became entailed")),
        "{bare:?}"
    );
}
