//! `kairos plan` (items 4 and 5): the goal state and the nominal command sequence, the
//! policy tables for review (Table 6.2), and its exit codes — 0 when the plan reaches the goal
//! state, 1 when the goal fails, 2 with a located error for bad `--state`/`--goal` text.

#[path = "support/cli.rs"]
mod cli;

use cli::kairos;

/// Table 6.2 is the engine's table here; the PDE's shows the repairs of §6.3.
#[test]
fn propulsion_policies_print_like_table_6_2() {
    let (code, stdout, _) = kairos(&["plan", "--policies", "models/propulsion.ron"]);
    assert_eq!(code, 0);
    assert!(
        stdout.contains(
            "standby          | engine.cmd = off     | engine.cmd = off     | Idle                 | valve1 = open, valve2 = open, engine.cmd = fire"
        ),
        "{stdout}"
    );
    insta::assert_snapshot!(stdout);
}

#[test]
fn lander_policies_mark_the_irreversible_separation() {
    let (code, stdout, _) = kairos(&["plan", "--policies", "models/lander_separation.ron"]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(stdout);
}

/// §6.3.3: from all off to `engine = firing`.
#[test]
fn engine_firing_from_all_off_is_the_section_6_3_3_sequence() {
    let (code, stdout, _) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--state",
        "PDE = off, valve1 = closed, valve2 = closed, engine = off",
        "--goal",
        "engine = firing",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(stdout);
}

#[test]
fn a_resettable_pde_is_repaired_first() {
    let (code, stdout, _) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--state",
        "PDE = resettable, valve1 = open, engine = standby",
        "--goal",
        "engine = firing",
    ]);
    assert_eq!(code, 0);
    insta::assert_snapshot!(stdout);
}

#[test]
fn json_output_lists_goal_state_and_steps() {
    let (code, stdout, _) = kairos(&[
        "plan",
        "--plant",
        "models/lander_separation.ron",
        "--goal",
        "lander = separated",
        "--json",
    ]);
    assert_eq!(code, 0);
    let value: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(value["goal_state"]["modes"]["lander"], "separated");
    assert_eq!(
        value["steps"][1]["controls"]["pyro_bus.cmd"],
        "fire-primary"
    );
    assert_eq!(value["achieved"], true);
    insta::assert_snapshot!(stdout);
}

#[test]
fn a_failed_goal_exits_1_with_the_reason() {
    let (code, stdout, stderr) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--state",
        "engine = failed",
        "--goal",
        "engine = standby",
    ]);
    assert_eq!(code, 1);
    assert!(stdout.contains("engine = failed"), "{stdout}");
    assert_eq!(
        stderr.trim(),
        "goal failed: engine = standby is unreachable: engine is failed"
    );
    let (code, stdout, _) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--goal",
        "engine = standby, engine = firing",
        "--json",
    ]);
    assert_eq!(code, 1);
    let value: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    assert_eq!(
        value["goal_failed"],
        "conflicting goals: engine = standby and engine = firing cannot hold together"
    );
}

/// §13: located errors, every problem in the argument, exit 2.
#[test]
fn bad_state_and_goal_text_are_located() {
    let (code, _, stderr) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--state",
        "engine = off, engine = heating, engine.temp = low, PDE != on, valve3 = open",
        "--goal",
        "engine = firing",
    ]);
    assert_eq!(code, 2);
    insta::assert_snapshot!("bad_state", stderr);
    let (code, _, stderr) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--goal",
        "engine = fring and (",
    ]);
    assert_eq!(code, 2);
    insta::assert_snapshot!("bad_goal_syntax", stderr);
    let (code, _, stderr) = kairos(&[
        "plan",
        "--plant",
        "models/propulsion.ron",
        "--goal",
        "engine = fring, valve = open",
    ]);
    assert_eq!(code, 2);
    insta::assert_snapshot!("bad_goal_names", stderr);
}

#[test]
fn arguments_are_checked() {
    let (code, _, stderr) = kairos(&["plan", "--plant", "models/propulsion.ron"]);
    assert_eq!(code, 2, "{stderr}");
    let (code, _, _) = kairos(&[
        "plan",
        "--policies",
        "models/propulsion.ron",
        "--goal",
        "engine = firing",
    ]);
    assert_eq!(code, 2);
    let (code, _, stderr) = kairos(&["plan", "--policies", "models/missing.ron"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("cannot read"), "{stderr}");
}

/// DESIGN.md §9 (redundancy): with regulator A failed the payload is powered through B; with
/// both failed the goal fails naming each alternative and why.
#[test]
fn the_power_subsystem_plans_around_a_failed_regulator() {
    let goal = [
        "plan",
        "--plant",
        "models/power.ron",
        "--goal",
        "payload = powered",
    ];
    let (code, stdout, stderr) = kairos(&[&goal[..], &["--state", "reg_a = failed"]].concat());
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let steps: Vec<String> = stdout
        .lines()
        .filter(|l| l.starts_with("   "))
        .map(|l| l.split_whitespace().collect::<Vec<_>>().join(" "))
        .collect();
    assert_eq!(
        steps,
        [
            "1. command reg_b.cmd = on reg_b: off -> on",
            "2. command load_switch.cmd = close load_switch: open -> closed",
            "3. wait, p 1 payload: unpowered -> powered",
        ],
        "{stdout}"
    );
    let both = ["--state", "reg_a = failed, reg_b = failed"];
    let (code, _, stderr) = kairos(&[&goal[..], &both].concat());
    assert_eq!(code, 1);
    assert!(
        stderr.contains(
            "payload can reach only unpowered from unpowered (unpowered -> powered needs reg_a = \
             on (reg_a is failed) or reg_b = on (reg_b is failed))"
        ),
        "{stderr}"
    );
}

/// DESIGN.md §9: a goal the plant leaves by itself is said up front, located in the model, and
/// a plan that comes back to a state it visited stops and names who goes round (before, `plan`
/// alternated two commands to its step limit).
#[test]
fn a_goal_state_the_plant_leaves_is_reported() {
    let (code, stdout, stderr) = kairos(&[
        "plan",
        "--plant",
        "models/thermostat.ron",
        "--goal",
        "temperature = warming",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stdout.contains(
            "warning: no state entailing the goal is one the plant rests in; this one it leaves \
             by itself: component `temperature`, transition warming -> cold"
        ),
        "{stdout}"
    );
}
