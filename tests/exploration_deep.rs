//! `kairos check --deep` (thesis §8.1: "potential negative interactions
//! between concurrently-asserted goals"): goals the THCA can assert in one cycle that the plant
//! model makes inconsistent, and modes no transition reaches, each located in its file.

use std::path::Path;

use kairos::diagnostic::Source;
use kairos::exploration::deep::{DeepFindings, deep_check, describe};
use kairos::plant::Plant;
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::Thca;

fn load(program: &str, model: &str) -> (Thca, Plant, Source) {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    let model = Source::read(Path::new(model)).expect("readable");
    let plant = Plant::load(&model).unwrap_or_else(|e| panic!("{e}"));
    let program = Source::read(Path::new(program)).expect("readable");
    let options = LinkOptions {
        plant: Some(plant.table()),
        ..LinkOptions::default()
    };
    let thca = rmpl::load(&program, &options).unwrap_or_else(|e| panic!("{e}"));
    (thca, plant, model)
}

fn check(program: &str, model: &str) -> (DeepFindings, String) {
    let (thca, plant, source) = load(program, model);
    let findings = deep_check(&thca, &plant, 200_000).expect("the model encodes");
    let text = describe(&findings, &thca, &plant, &source);
    (findings, text)
}

/// The planted conflict: `engine = firing` in one thread, `engine = off` after a wait in the
/// other; and the planted unreachable mode `overheated`. Both located (snapshot).
#[test]
fn a_planted_conflict_and_an_unreachable_mode_are_found() {
    let (findings, text) = check(
        "tests/deep/conflict.rmpl",
        "tests/deep/unreachable_mode.ron",
    );
    assert!(findings.complete);
    assert_eq!(findings.conflicts.len(), 1);
    assert_eq!(
        findings.conflicts[0].goals,
        ("engine = firing".to_string(), "engine = off".to_string())
    );
    assert_eq!(findings.unreachable.len(), 1);
    assert!(text.contains("tests/deep/conflict.rmpl:7:5"), "{text}");
    assert!(
        text.contains("tests/deep/unreachable_mode.ron:39:29"),
        "{text}"
    );
    insta::assert_snapshot!(text);
}

/// The shipped programs whose goals are asserted in sequence or on independent components
/// have no finding against their models.
#[test]
fn the_sequential_shipped_programs_have_no_finding() {
    for (program, model) in [
        ("programs/engine_burn.rmpl", "models/engine_camera.ron"),
        (
            "programs/engine_confidence.rmpl",
            "models/engine_camera.ron",
        ),
        ("programs/propulsion_fire.rmpl", "models/propulsion.ron"),
        ("programs/valve_open.rmpl", "models/driver_valve.ron"),
        (
            "programs/thermostat_stay_warm.rmpl",
            "models/thermostat.ron",
        ),
        (
            "programs/thermostat_stay_warm_tactics.rmpl",
            "models/thermostat.ron",
        ),
    ] {
        let (findings, text) = check(program, model);
        assert!(findings.complete, "{program}");
        assert!(text.is_empty(), "{program}:\n{text}");
    }
}

/// The spacecraft deployment's parallel threads may assert `spacecraft_deployment = failure`
/// (a solar array failed) and `= success` (the IUS separated) in the same cycle: a finding the
/// report writes up (a run where an array fails as the IUS separates would meet a goal
/// conflict).
#[test]
fn the_spacecraft_deployment_may_assert_success_and_failure_together() {
    let (findings, _) = check(
        "programs/spacecraft_deployment.rmpl",
        "models/spacecraft_deployment.ron",
    );
    assert!(findings.conflicts.iter().any(|c| {
        c.goals.0.starts_with("spacecraft_deployment = ")
            && c.goals.1.starts_with("spacecraft_deployment = ")
    }));
}
