//! `kairos solve` on the shipped example OCSPs and on bad input (its acceptance: "prints
//! correct answers (snapshot tests)"; "exits 2 with a located error on bad input").

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

#[test]
fn full_adder_diagnosis_is_the_single_fault_x1() {
    let (code, stdout, _) = kairos(&["solve", "models/ocsp/full_adder.ron", "-k", "5"]);
    assert_eq!(code, 0);
    let first = stdout.lines().next().unwrap_or_default();
    assert!(
        first.contains("X1 = broken, X2 = ok, A1 = ok, A2 = ok, O1 = ok"),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

#[test]
fn propulsion_goal_state_is_figure_6_16s() {
    let (code, stdout, _) = kairos(&["solve", "models/ocsp/propulsion_goal.ron", "-k", "3"]);
    assert_eq!(code, 0);
    assert!(
        stdout.starts_with(
            "  1. cost 5.000000  PDE = off, valve1 = open, valve2 = open, engine = firing"
        ),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

#[test]
fn driver_valve_estimate_prefers_a_stuck_valve() {
    let (code, stdout, _) = kairos(&["solve", "models/ocsp/driver_valve_estimate.ron", "-k", "4"]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(stdout);
}

#[test]
fn json_output_lists_ranked_assignments() {
    let (code, stdout, _) = kairos(&["solve", "models/ocsp/full_adder.ron", "-k", "2", "--json"]);
    assert_eq!(code, 0);
    let value: serde_json::Value = serde_json::from_str(&stdout).expect("valid JSON");
    assert_eq!(value["solutions"][0]["rank"], 1);
    assert_eq!(value["solutions"][0]["assignment"]["X1"], "broken");
    assert_eq!(value["solutions"].as_array().map(Vec::len), Some(2));
    assert_eq!(value["complete"], true);
}

#[test]
fn bad_input_exits_2_with_a_located_error() {
    for file in [
        "tests/bad_input/ocsp_unknown_value.ron",
        "tests/bad_input/ocsp_syntax.ron",
    ] {
        let (code, stdout, stderr) = kairos(&["solve", file]);
        assert_eq!(code, 2, "{file}: {stdout}");
        insta::assert_snapshot!(file.replace(['/', '.'], "_"), stderr);
    }
    let (code, _, stderr) = kairos(&["solve", "no/such/file.ron"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("cannot read no/such/file.ron"), "{stderr}");
}
