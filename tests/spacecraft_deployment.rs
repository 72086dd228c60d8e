//! The spacecraft deployment of thesis §5.1.2 end to end: `programs/
//! spacecraft_deployment.rmpl` (Figure 5-1) links against `models/spacecraft_deployment.ron`
//! (`kairos check`), and every scenario under `scenarios/spacecraft_deployment/` runs through
//! `kairos run` and exits 0 (all its expectations hold), with the mission log showing the steps
//! of the narrative each one is about. scenarios/spacecraft_deployment/README.md maps the
//! narrative's steps to the scenarios and their expectations.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/scenario_run.rs"]
mod scenario_run;
mod support;

use cli::kairos;
use kairos::logic::{Formula, ValueId};
use kairos::opsat::Literal;
use kairos::plant::ModeKind;
use scenario_run::{assert_every_file_is_tested, assert_in_order, run_passing};
use support::plants::model;

const DIR: &str = "scenarios/spacecraft_deployment";
const PROGRAM: &str = "programs/spacecraft_deployment.rmpl";
const MODEL: &str = "models/spacecraft_deployment.ron";

/// The scenarios this file runs, one test each.
const SCENARIOS: [&str; 8] = [
    "nominal.ron",
    "arrays_first.ron",
    "flags_reversed.ron",
    "flags_at_once.ron",
    "imu_1_fails.ron",
    "solar_array_fails.ron",
    "solar_array_recovers.ron",
    "both_ssrs_fail.ron",
];
/// The other files there: the shared plant script and the narrative mapping.
const NOT_SCENARIOS: [&str; 2] = ["plant.ron", "README.md"];

/// Runs a scenario of this directory and returns its mission log, failing with the log if it
/// does not pass.
fn run(name: &str) -> String {
    run_passing(&format!("{DIR}/{name}"))
}

#[test]
fn every_scenario_file_is_run() {
    assert_every_file_is_tested(
        DIR,
        &SCENARIOS,
        &NOT_SCENARIOS,
        "tests/spacecraft_deployment.rs",
    );
}

/// The deployment model's acceptance: it has every state variable Figure 5-1 names, and the program
/// links against it with no error (DESIGN.md §12, `kairos check MODEL PROGRAM`).
#[test]
fn kairos_check_links_the_program_against_the_model() {
    let (code, stdout, stderr) = kairos(&["check", MODEL, PROGRAM]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(stderr.is_empty(), "{stderr}");
    assert!(
        stdout.contains("plant spacecraft_deployment (16 components"),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!(
            "program SpacecraftDeployment (65 locations, 50 variables, 1 clock, linked against {MODEL})"
        )),
        "{stdout}"
    );
}

/// One component per state variable Figure 5-1 names, in the order the program
/// first names them (lines 3-55).
#[test]
fn the_components_are_the_programs_state_variables() {
    let plant = model("spacecraft_deployment");
    let names: Vec<&str> = plant.components().iter().map(|c| c.name()).collect();
    assert_eq!(
        names,
        [
            "shuttle",
            "IMU_1",
            "IMU_2",
            "RCS",
            "LGA_deploy_flag",
            "SA_deploy_flag",
            "SSR_A",
            "SSR_B",
            "downlink",
            "LGA",
            "SA_1",
            "SA_2",
            "ACS",
            "power_switch",
            "IUS",
            "spacecraft_deployment",
        ]
    );
    // The faults the issue names: IMU failure, solar-array deployment failure, SSR failures.
    for (component, fault) in [
        ("IMU_1", "failed"),
        ("IMU_2", "failed"),
        ("SA_1", "failed"),
        ("SA_2", "failed"),
        ("SSR_A", "failed"),
        ("SSR_B", "failed"),
    ] {
        let c = plant.component(plant.component_named(component).expect(component));
        let mode = c.mode_named(fault).expect(fault);
        assert_eq!(c.modes()[mode.index()].kind, ModeKind::Fault, "{component}");
    }
}

/// The model's conventions (its header; docs/design/shipped-models.md, the Mars lander and the
/// spacecraft deployment): nominal rewards are flat (the program asserts goals once and moves on,
/// §6.3.1 would otherwise undo them), faults are -10 (repairable) or -20 (permanent), and every
/// nominal mode determines each observable of its component, so an unconstrained fault mode pays
/// the observation factor 1/m (DESIGN.md §8) every cycle.
#[test]
fn rewards_are_flat_and_every_nominal_mode_determines_its_observables() {
    let plant = model("spacecraft_deployment");
    let mut theory = plant.theory().expect("theory");
    for component in plant.components() {
        for mode in component.modes() {
            let allowed: &[f64] = match mode.kind {
                ModeKind::Nominal => &[0.0],
                ModeKind::Fault => &[-10.0, -20.0],
            };
            assert!(
                allowed.contains(&mode.reward),
                "{}.{}",
                component.name(),
                mode.name
            );
        }
        let observables = plant
            .observables()
            .iter()
            .filter(|x| component.attributes().contains(x));
        for &x in observables {
            let nominal = component
                .modes()
                .iter()
                .enumerate()
                .filter(|(_, m)| m.kind == ModeKind::Nominal);
            for (m, mode) in nominal {
                let assumption = [Literal::Is(component.mode_var(), ValueId(m as u32))];
                let determined = plant
                    .table()
                    .variable(x)
                    .value_ids()
                    .any(|v| theory.entails(&assumption, &Formula::is(x, v)).expect("ok"));
                let name = plant.table().variable(x).name();
                assert!(
                    determined,
                    "{}.{} leaves {name} open",
                    component.name(),
                    mode.name
                );
            }
        }
    }
}

/// §5.1.2 nominal: separation (line 3), warm-ups (lines 4-8), the LGA flag and DeployLGA steps
/// 1-4 (lines 10-11, 21-28), the SA flag and DeploySolarArrays steps 1-10 (lines 12, 32-55),
/// success preempting the sequence (line 17).
#[test]
fn nominal_deployment_follows_the_narrative() {
    let log = run("nominal.ron");
    assert_in_order(
        &log,
        &[
            "cycle 1 s until 2400 s",
            "[ 60.000 s 0:01:00.000]",
            "believed shuttle: attached -> separated",
            "command IMU_1.cmd = warm-up (IMU_1: off -> warming)",
            "command IMU_2.cmd = warm-up (IMU_2: off -> warming)",
            "command RCS.cmd = warm-up (RCS: off -> warming)",
            "believed IMU_1: warming -> warmed",
            "believed RCS: warming -> warmed",
            "[ 600.000 s 0:10:00.000]",
            "believed LGA_deploy_flag: clear -> set",
            "command SSR_A.cmd = on (SSR_A: off -> on)",
            "preempted do … watching (programs/spacecraft_deployment.rmpl:28:3): (SSR_A = on) ∨ (SSR_B = on) became entailed",
            "command downlink.cmd = beacon",
            "command IMU_1.cmd = on (IMU_1: warmed -> on)",
            "command LGA.cmd = deploy (LGA: stowed -> deployed)",
            "goal achieved LGA = deployed",
            "[ 900.000 s 0:15:00.000]",
            "clock t1 started",
            "command downlink.cmd = nominal",
            "command SA_1.cmd = deploy (SA_1: stowed -> deploying)",
            "command SA_2.cmd = deploy (SA_2: stowed -> deploying)",
            "believed SA_1: deploying -> deployed",
            "believed SA_2: deploying -> deployed",
            "[ 2041.000 s 0:34:01.000]",
            "believed IUS: nulling-rates -> pre-separation",
            "command ACS.cmd = activate",
            "[ 2221.000 s 0:37:01.000]",
            "command power_switch.cmd = to-batteries",
            "believed IUS: pre-separation -> separated",
            "command spacecraft_deployment.cmd = set-success",
            "goal achieved spacecraft_deployment = success",
            "preempted do … watching (programs/spacecraft_deployment.rmpl:9:3): (spacecraft_deployment = success) ∨ (spacecraft_deployment = failure) became entailed",
            "completed the program has completed",
        ],
    );
    assert!(!log.contains("DIAGNOSIS"), "{log}");
}

/// §5.1.2: the SA flag first, line 14: DeployLGA is bypassed, DeploySolarArrays steps 2 and 4
/// turn the recorder and the IMU on.
#[test]
fn arrays_first_bypasses_the_lga() {
    let log = run("arrays_first.ron");
    assert_in_order(
        &log,
        &[
            "believed SA_deploy_flag: clear -> set",
            "clock t1 started",
            "command SSR_A.cmd = on",
            "command downlink.cmd = nominal",
            "command IMU_1.cmd = on",
            "command SA_1.cmd = deploy",
            "command ACS.cmd = activate",
            "goal achieved spacecraft_deployment = success",
            "completed the program has completed",
        ],
    );
    assert!(!log.contains("command LGA.cmd"), "{log}");
}

/// Figure 5-1 lines 10-14: an LGA flag after the SA flag cannot start DeployLGA.
#[test]
fn a_late_lga_flag_is_ignored() {
    let log = run("flags_reversed.ron");
    assert_in_order(
        &log,
        &[
            "believed SA_deploy_flag: clear -> set",
            "clock t1 started",
            "command SA_2.cmd = deploy",
            "believed LGA_deploy_flag: clear -> set",
            "command ACS.cmd = activate",
            "goal achieved spacecraft_deployment = success",
        ],
    );
    assert!(!log.contains("command LGA.cmd"), "{log}");
}

/// Figure 5-1 lines 10-14: with both flags set at once neither guard holds; the program as
/// printed deploys nothing.
#[test]
fn flags_set_at_once_deploy_nothing() {
    let log = run("flags_at_once.ron");
    assert_in_order(
        &log,
        &[
            "believed LGA_deploy_flag: clear -> set",
            "believed SA_deploy_flag: clear -> set",
            "believed IUS: pre-separation -> separated",
            "program not completed",
        ],
    );
    assert!(!log.contains("clock t1 started"), "{log}");
}

/// DeployLGA step 3 (lines 26-28) and DESIGN.md §5.2: IMU_1 fails, the watch preempts, IMU_2
/// is turned on and the LGA still deploys.
#[test]
fn an_imu_1_failure_turns_imu_2_on_and_still_deploys_the_lga() {
    let log = run("imu_1_fails.ron");
    assert_in_order(
        &log,
        &[
            "command IMU_1.cmd = on (IMU_1: warmed -> on)",
            "rule `IMU_1 dies` takes effect: IMU_1.current = zero (FAULT)",
            "believed IMU_1: warmed -> failed",
            "DIAGNOSIS IMU_1 = failed",
            "preempted do … watching (programs/spacecraft_deployment.rmpl:33:3): IMU_1 = failed became entailed",
            "goal asserted IMU_2 = on (programs/spacecraft_deployment.rmpl:34:33)",
            "command IMU_2.cmd = on (IMU_2: warmed -> on)",
            "goal asserted LGA = deployed",
            "command LGA.cmd = deploy",
            "goal achieved LGA = deployed",
            "goal achieved spacecraft_deployment = success",
            "completed the program has completed",
        ],
    );
}

/// DeploySolarArrays steps 5-6 (lines 44-49, 17): a wing that jams again after its recovery
/// action is failed, and the sequence is flagged a failure and ends.
#[test]
fn a_failed_solar_array_flags_the_deployment_a_failure() {
    let log = run("solar_array_fails.ron");
    assert_in_order(
        &log,
        &[
            "rule `SA_2 jams` takes effect: SA_2.motor = stalled (FAULT)",
            "DIAGNOSIS SA_2 = jammed",
            "REPAIR SA_2.cmd = retry (SA_2: jammed -> deploying-backup)",
            "rule `SA_2 jams again` takes effect: SA_2.motor = stalled (FAULT)",
            "believed SA_2: deploying-backup -> failed",
            "DIAGNOSIS SA_2 = failed",
            "preempted do … watching (programs/spacecraft_deployment.rmpl:51:3): (SA_1 = failed) ∨ (SA_2 = failed) became entailed",
            "goal asserted spacecraft_deployment = failure (programs/spacecraft_deployment.rmpl:56:54)",
            "command spacecraft_deployment.cmd = set-failure",
            "goal achieved spacecraft_deployment = failure",
            "preempted do … watching (programs/spacecraft_deployment.rmpl:9:3): (spacecraft_deployment = success) ∨ (spacecraft_deployment = failure) became entailed",
            "completed the program has completed",
        ],
    );
    assert!(!log.contains("command ACS.cmd"), "{log}");
}

/// DeploySolarArrays step 5: the recovery action of the SA subsystem model (the backup winding)
/// deploys a wing that jammed once, and the deployment succeeds.
#[test]
fn a_jammed_solar_array_is_recovered_by_the_backup_winding() {
    let log = run("solar_array_recovers.ron");
    assert_in_order(
        &log,
        &[
            "DIAGNOSIS SA_2 = jammed",
            "REPAIR SA_2.cmd = retry (SA_2: jammed -> deploying-backup)",
            "believed SA_2: deploying-backup -> deployed",
            "goal achieved SA_2 = deployed",
            "command ACS.cmd = activate",
            "goal achieved spacecraft_deployment = success",
        ],
    );
    assert!(!log.contains("DIAGNOSIS SA_2 = failed"), "{log}");
}

/// DeployLGA step 1 (lines 21-24) with both recorders dead: the goal fails and the program as
/// printed stops there.
#[test]
fn with_both_ssrs_dead_the_deployment_stops_at_deploy_lga_step_1() {
    let log = run("both_ssrs_fail.ron");
    assert_in_order(
        &log,
        &[
            "goal asserted SSR_A = on",
            "goal asserted SSR_B = on",
            "command SSR_A.cmd = on",
            "command SSR_A.cmd = on",
            "DIAGNOSIS SSR_A = failed",
            "GOAL FAILED SSR_A = on and SSR_B = on: SSR_A = on is unreachable: SSR_A is failed",
            "believed SA_deploy_flag: clear -> set",
            "program not completed",
        ],
    );
    assert!(!log.contains("command downlink.cmd"), "{log}");
}
