//! `kairos check` and `kairos compile` (items 3 and 6): exit 0 on good programs, exit 2
//! with every located error on bad ones.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

#[test]
fn check_accepts_the_shipped_programs() {
    let (code, stdout, stderr) = kairos(&[
        "check",
        "programs/mars_entry.rmpl",
        "programs/mars_edl.rmpl",
        "programs/spacecraft_deployment.rmpl",
    ]);
    assert_eq!(code, 0, "{stderr}");
    insta::assert_snapshot!(stdout);
}

#[test]
fn check_reports_every_error_of_every_file() {
    let (code, stdout, stderr) = kairos(&[
        "check",
        "programs/mars_entry.rmpl",
        "tests/bad_input/rmpl_two_broken_programs.rmpl",
        "tests/bad_input/rmpl_unknown_program.rmpl",
        "README.md",
    ]);
    assert_eq!(code, 2);
    assert!(
        stdout.starts_with("ok: programs/mars_entry.rmpl"),
        "{stdout}"
    );
    insta::assert_snapshot!(stderr);
}

#[test]
fn compile_prints_the_automaton_or_its_drawing() {
    let (code, stdout, _) = kairos(&[
        "compile",
        "programs/mars_edl.rmpl",
        "--entry",
        "EntrySequence",
    ]);
    assert_eq!(code, 0);
    assert!(
        stdout.starts_with("THCA EntrySequence (programs/mars_edl.rmpl): 12 locations"),
        "{stdout}"
    );
    let (code, stdout, _) = kairos(&["compile", "programs/spacecraft_deployment.rmpl", "--dot"]);
    assert_eq!(code, 0);
    assert!(
        stdout.starts_with("digraph \"SpacecraftDeployment\" {"),
        "{stdout}"
    );
    assert!(
        stdout.contains("subgraph \"cluster_L2\""),
        "composites are clusters"
    );
    assert!(
        stdout.contains("label=\"⊨ shuttle = separated\""),
        "guards label edges"
    );
}

#[test]
fn compile_refuses_an_unknown_entry_or_a_parameterised_one() {
    let (code, _, stderr) = kairos(&["compile", "programs/mars_edl.rmpl", "--entry", "Landing"]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("no program `Landing` in this file"),
        "{stderr}"
    );
    let (code, _, stderr) = kairos(&[
        "compile",
        "tests/bad_input/rmpl_argument_count.rmpl",
        "--entry",
        "Deploy",
    ]);
    assert_eq!(code, 2);
    assert!(
        stderr.contains("the entry program `Deploy` takes parameters"),
        "{stderr}"
    );
}

#[test]
fn check_validates_models_and_ocsps_and_links_programs_against_the_models_given() {
    let (code, stdout, _) = kairos(&[
        "check",
        "models/propulsion.ron",
        "models/ocsp/full_adder.ron",
    ]);
    assert_eq!(code, 0, "{stdout}");
    assert!(
        stdout.contains("ok: models/propulsion.ron: plant propulsion"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok: models/ocsp/full_adder.ron: OCSP"),
        "{stdout}"
    );
    // The Mars entry program names state the propulsion model does not have.
    let (code, _, stderr) = kairos(&["check", "models/propulsion.ron", "programs/mars_entry.rmpl"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("unknown variable `nav`"), "{stderr}");
    assert!(stderr.contains("programs/mars_entry.rmpl:14:5"), "{stderr}");
}
