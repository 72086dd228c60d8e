//! `kairos check` on every kind of file a user writes (DESIGN.md §12: "`kairos check FILES…`
//! (parse, link and validate …)"; §13: every file error located): a scenario is checked as
//! `kairos run` loads it — with its plant, program or mission and scripts — and a file whose
//! top-level value is none of kairos's formats is refused naming the ones it accepts, not with
//! serde's "expected struct `Plant`".

#[path = "support/cli.rs"]
mod cli;

use std::path::PathBuf;

use cli::kairos;

fn scratch(name: &str, text: &str) -> String {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).expect("the scratch directory is writable");
    path.display().to_string()
}

#[test]
fn scenarios_missions_and_rover_scenarios_are_checked() {
    let (code, stdout, stderr) = kairos(&[
        "check",
        "scenarios/mars_edl/nominal.ron",
        "scenarios/thermostat/system_test_7.ron",
        "scenarios/rover/r5.ron",
        "missions/thermostat.ron",
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stdout.contains("ok: scenarios/mars_edl/nominal.ron: scenario mars_edl: nominal (program programs/mars_edl.rmpl on models/mars_lander.ron;"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok: scenarios/thermostat/system_test_7.ron: scenario")
            && stdout.contains("(mission missions/thermostat.ron on models/thermostat.ron;"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok: scenarios/rover/r5.ron: rover scenario"),
        "{stdout}"
    );
    assert!(
        stdout.contains("ok: missions/thermostat.ron: mission"),
        "{stdout}"
    );
}

#[test]
fn a_bad_scenario_is_located_in_its_own_file() {
    let path = scratch(
        "check_bad_scenario.ron",
        "Scenario(\n    name: \"x\",\n    plant: \"../models/nope.ron\",\n    program: \"p.rmpl\",\n    cycle: 1.0,\n    end: 10.0,\n)\n",
    );
    let (code, _, stderr) = kairos(&["check", &path]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("check_bad_scenario.ron:3:"), "{stderr}");
}

#[test]
fn an_unknown_top_level_value_names_the_accepted_formats() {
    let path = scratch("check_unknown.ron", "// a comment first\nFoo(a: 1)\n");
    let (code, _, stderr) = kairos(&["check", &path]);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("its top-level value is `Foo(…)`; expected one of `Plant(…)`, `Ocsp(…)`, `Mission(…)`, `Scenario(…)` or `RoverScenario(…)`"),
        "{stderr}"
    );
}
