//! The thermostat's goal-network missions run by the executive through `kairos run` (DESIGN.md
//! §15.3, §15.5; mds-goal-networks.md §3.3): system test 1
//! (knowledge over KnowAll), system test 4 (StayWarm, tactic 1) and a maintain failure (switch 1
//! sticks open during the hold) on missions with no goal types; and the seed's system tests 4–9
//! on `missions/thermostat.ron`, the mission with the seed's goal types, run by the executive's
//! goal controller (elaboration, failure responses, promotion, safing). Each scenario's
//! expectations pass, and its mission log shows the goal-network events in order. The trace
//! carries them too.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/scenario_run.rs"]
mod scenario_run;

use cli::kairos;
use scenario_run::{assert_every_file_is_tested, assert_in_order, run_passing};

const DIR: &str = "scenarios/thermostat";

/// The mission scenarios of the directory, one test each below.
const MISSIONS: [&str; 21] = [
    "backup_heater_after_a_stuck_switch.ron",
    "campaign.ron",
    "explore_a_stuck_switch.ron",
    "know_all.ron",
    "refusal_names_every_conflict.ron",
    "sensor_dropouts.ron",
    "stay_warm_mission.ron",
    "stay_warm_submitted.ron",
    "stay_warm_submitted_at_10s.ron",
    "submitted_into_the_past.ron",
    "switch1_sticks_open_as_stay_warm_ends.ron",
    "switch1_sticks_open_mission.ron",
    "switch1_stuck_open_mission.ron",
    "switch1_stuck_open_promoted_tactic_2.ron",
    "warm_up_deadline_missed.ron",
    "system_test_4.ron",
    "system_test_5.ron",
    "system_test_6.ron",
    "system_test_7.ron",
    "system_test_8.ron",
    "system_test_9.ron",
];

fn run_mission(name: &str) -> String {
    run_passing(&format!("{DIR}/{name}"))
}

/// Every file of the directory is a mission scenario tested here, or one of the RMPL scenarios
/// `tests/thermostat_model.rs` runs, or the script and README they share.
#[test]
fn every_mission_scenario_of_the_directory_is_run() {
    assert_every_file_is_tested(
        DIR,
        &MISSIONS,
        &[
            "README.md",
            "plant.ron",
            "physics.ron",
            "stay_warm.ron",
            "telemetry.ron",
            "switch1_sticks_open.ron",
            "switch2_sticks_closed.ron",
            "sensor_fails.ron",
            "switch1_stuck_open_from_start.ron",
            "switch1_sticks_open_tactic_2.ron",
            "switch2_sticks_closed_tactic_2.ron",
            "switch1_stuck_open_warms_with_switch2.ron",
        ],
        "tests/thermostat_missions.rs",
    );
}

/// The thermostat campaign against the sampled model (its sensor read in °C through the
/// model's monitor), and a run of it with the story of the one that found a
/// defect (DESIGN.md §15, mds-goal-networks.md §2.5 step 4 and §2.7): switch 1 sticks open while
/// the device warms, so `stay-warm.heater1` and `stay-warm.get-warm.heater1` fail in the same
/// cycle; both fail up, to `stay-warm` and to `stay-warm.get-warm`. Re-elaborating `stay-warm`
/// replaces its whole subtree, `get-warm` included, so `get-warm` must not be re-elaborated
/// again in that cycle (it once was, from the removed elaboration, and the promoted network
/// contradicted itself: no point fired after it). Now the second chain says it was replaced,
/// tactic 2 holds the device warm and StayWarm's end fires.
#[test]
fn two_failures_under_one_re_elaboration_are_answered_once() {
    let (code, stdout, stderr) = kairos(&[
        "run",
        "scenarios/thermostat/campaign.ron",
        "--seed",
        "16498624368888480460",
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert_in_order(
        &stdout,
        &[
            "DIAGNOSIS switch1 = stuck-open (p 1.00)",
            "RESPONSE stay-warm.heater1 failed: switch1 = stuck-open (p 1.00) → fail up → \
             stay-warm re-elaborated with tactic 2 → promoted",
            "RESPONSE stay-warm.get-warm.heater1 failed: switch1 = stuck-open (p 1.00) → fail up \
             → replaced by the re-elaboration of stay-warm",
            "promoted the proposed network (re-elaboration of stay-warm)",
            "fired TP_S",
            "fired TP_E",
        ],
    );
    assert!(!stdout.contains("TEMPORAL"), "{stdout}");
    assert_eq!(stdout.matches("promoted ").count(), 1, "{stdout}");
}

/// System test 1 (seed 000 App. A, Table 7): every SV known for 1,000 s, the points fire at their
/// fixed times, zero commands, zero failures; the XGoals of [TP_k1, TP_k2] merge both knowledge
/// activities.
#[test]
fn system_test_1_knows_every_state_variable_with_no_command() {
    let log = run_mission("know_all.ron");
    assert_in_order(
        &log,
        &[
            "mission missions/thermostat_know_all.ron",
            "[ 0.000 s 0:00:00.000] #0",
            "dispatched Knowledge switch1 known over [origin, TP_k1] (know-switch1)",
            "[ 10.000 s 0:00:10.000] #10",
            "fired TP_k1 (window [10, 10])",
            "dispatched Knowledge switch1 known over [TP_k1, TP_k2] (know-switch1, know-switch1-2)",
            "[ 70.000 s 0:01:10.000] #70",
            "fired TP_k2 (window [70, 70])",
            "[ 1000.000 s 0:16:40.000] #1000",
            "fired TP_bgE (window [1000, 1000])",
            "completed the program has completed",
            "PASS: 14 expectations hold",
        ],
    );
    for absent in ["command", "GOAL FAILED", "FORCED", "DIAGNOSIS"] {
        assert!(
            !log.lines().any(|l| l.trim_start().starts_with(absent)),
            "`{absent}` in:\n{log}"
        );
    }
}

/// System test 4 (seed 000 App. A, Table 7; mds-goal-networks.md §3.3): one command closing
/// switch 1 when TP_H dispatches the switch transitions, TP_A once switch 1 is believed closed,
/// TP_S once the device is WARM (76 s, inside [71, 161]), TP_E on time (376 s), no failure.
#[test]
fn system_test_4_closes_switch_1_once_and_fires_tp_s_once_warm() {
    let log = run_mission("stay_warm_mission.ron");
    assert_in_order(
        &log,
        &[
            "[ 10.000 s 0:00:10.000] #10",
            "fired TP_H (window [10, 10])",
            "dispatched Transition switch1 ∈ {closed, stuck-closed}, known over [TP_H, TP_A] (know-switch1, close-switch1)",
            "command switch1.cmd = close (switch1: open -> closed)",
            "[ 11.000 s 0:00:11.000] #11",
            "believed switch1: open -> closed (p 1.00)",
            "fired TP_A (window [10, 15])",
            "dispatched Maintain switch1 ∈ {closed, stuck-closed}, known over [TP_A, TP_E] (know-switch1, heater1)",
            "[ 76.000 s 0:01:16.000] #76",
            "believed temperature: warming -> warm-low (p 1.00)",
            "fired TP_S (window [71, 161])",
            "dispatched Maintain temperature ∈ {warm-low, warm, warm-high}, known over [TP_S, TP_E] (know-temperature, stay-warm)",
            "[ 376.000 s 0:06:16.000] #376",
            "fired TP_E (window [376, 376])",
            "PASS: 20 expectations hold",
        ],
    );
    let commands = log
        .lines()
        .filter(|l| l.trim_start().starts_with("command"))
        .count();
    assert_eq!(commands, 1, "{log}");
}

/// Goals submitted to the running mission by a scenario rule (DESIGN.md §15.4):
/// a second StayWarm submitted at 200 s is scheduled after the first, TP_S2 fires when TP_E
/// does and TP_E2 100 s later, with its XGoals dispatched on the temperature and switch 1 and no
/// new command; a submission contradicting the running `stay-warm` at 250 s is refused with the
/// scheduler's reason, and the network runs on unchanged.
#[test]
fn a_submitted_stay_warm_runs_after_the_first_and_a_contradicting_one_is_refused() {
    let log = run_mission("stay_warm_submitted.ron");
    assert_in_order(
        &log,
        &[
            "[ 200.000 s 0:03:20.000] #200",
            "plant rule `operator asks for a second StayWarm` takes effect: submits stay-warm-2, heater1-2",
            "[ 250.000 s 0:04:10.000] #250",
            "REFUSED freeze submitted by `operator asks to freeze during the hold`: the submission cannot be scheduled: unmergeable: on temperature, goal `freeze` (temperature = cold) cannot hold together with `stay-warm`",
            "[ 376.000 s 0:06:16.000] #376",
            "fired TP_E (window [376, 376])",
            "fired TP_S2 (window [376, 396])",
            "dispatched Maintain switch1 ∈ {closed, stuck-closed}, known over [TP_S2, TP_E2] (know-switch1, heater1-2)",
            "dispatched Maintain temperature ∈ {warm-low, warm, warm-high}, known over [TP_S2, TP_E2] (know-temperature, stay-warm-2)",
            "[ 476.000 s 0:07:56.000] #476",
            "fired TP_E2 (window [476, 476])",
            "PASS: 13 expectations hold",
        ],
    );
    for absent in ["GOAL FAILED", "FORCED"] {
        assert!(
            !log.lines().any(|l| l.trim_start().starts_with(absent)),
            "`{absent}` in:\n{log}"
        );
    }
    let commands = log
        .lines()
        .filter(|l| l.trim_start().starts_with("command"))
        .count();
    assert_eq!(commands, 1, "{log}");
}

/// A maintain failure: switch 1 sticks open at 181 s; in the cycle it is
/// diagnosed (187 s) the maintain XGoal on switch 1 fails and is narrowed to `heater1`, with the
/// mode ŝ is in; `stay-warm` fails only when the device reads cold (205 s).
#[test]
fn a_switch_sticking_open_fails_heater1_then_stay_warm() {
    let log = run_mission("switch1_sticks_open_mission.ron");
    assert_in_order(
        &log,
        &[
            "[ 187.000 s 0:03:07.000] #187",
            "DIAGNOSIS switch1 = stuck-open (p 1.00)",
            "GOAL FAILED heater1: ŝ left the maintained set; ŝ has switch1 = stuck-open (p 1.00)",
            "[ 205.000 s 0:03:25.000] #205",
            "GOAL FAILED stay-warm: ŝ left the maintained set; ŝ has temperature = cold (p 1.00)",
            "[ 376.000 s 0:06:16.000] #376",
            "fired TP_E (window [376, 376])",
            "PASS: 15 expectations hold",
        ],
    );
}

/// A forced point (mds-goal-networks.md §2.4 (b)): with switch 1 stuck open from power-on the
/// device never warms, TP_S is forced at its latest time and the transition ending there unreached
/// (`get-warm`) fails; `heater1` failed earlier, at the diagnosis.
#[test]
fn a_point_never_ready_is_forced_and_its_unreached_transition_fails() {
    let log = run_mission("switch1_stuck_open_mission.ron");
    assert_in_order(
        &log,
        &[
            "[ 87.000 s 0:01:27.000] #87",
            "DIAGNOSIS switch1 = stuck-open (p 1.00)",
            "GOAL FAILED heater1: ŝ left the maintained set; ŝ has switch1 = stuck-open (p 1.00)",
            "[ 161.000 s 0:02:41.000] #161",
            "FORCED TP_S at its latest time, not ready (window [71, 161], 0.000 s late)",
            "GOAL FAILED get-warm: its end point was forced before the set was reached; ŝ has temperature = cold (p 1.00)",
            "[ 162.000 s 0:02:42.000] #162",
            "GOAL FAILED stay-warm: ŝ left the maintained set; ŝ has temperature = cold (p 1.00)",
            "PASS: 13 expectations hold",
        ],
    );
}

/// A goal that fails in the cycle its parent's interval ends (the goal controller's module doc,
/// DESIGN.md §15.2): switch 1 sticks open at 360 s, the heater goal fails at 366 s when TP_E is
/// due; StayWarm holds and has no time left for a tactic, so the failure is answered there —
/// no re-elaboration, no safing, TP_E on time.
#[test]
fn a_failure_as_the_parent_s_interval_ends_is_answered_without_safing() {
    let log = run_mission("switch1_sticks_open_as_stay_warm_ends.ron");
    assert_in_order(
        &log,
        &[
            "[ 366.000 s 0:06:06.000] #366",
            "DIAGNOSIS switch1 = stuck-open (p 1.00)",
            "GOAL FAILED stay-warm.heater1: ŝ left the maintained set; ŝ has switch1 = stuck-open (p 1.00)",
            "RESPONSE stay-warm.heater1 failed: switch1 = stuck-open (p 1.00) → fail up → stay-warm's interval ends at TP_E: nothing left to re-elaborate",
            "fired TP_E (window [366, 366])",
            "PASS: 10 expectations hold",
        ],
    );
}

/// The events of a scenario's JSON trace (`kairos run --trace`): (kind, text) pairs.
fn trace_events(name: &str, tag: &str) -> Vec<(String, String)> {
    let file = format!("kairos-mission-trace-{tag}-{}.jsonl", std::process::id());
    let trace = std::env::temp_dir().join(file);
    let trace_arg = trace.to_string_lossy().to_string();
    let scenario = format!("{DIR}/{name}");
    let (code, stdout, stderr) = kairos(&["run", &scenario, "--trace", &trace_arg]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    let text = std::fs::read_to_string(&trace).expect("the trace is written");
    let _ = std::fs::remove_file(&trace);
    text.lines()
        .map(|l| serde_json::from_str::<serde_json::Value>(l).expect("a JSON line"))
        .flat_map(|line| line["events"].as_array().cloned().unwrap_or_default())
        .map(|e| {
            let field = |k: &str| e[k].as_str().unwrap_or_default().to_string();
            (field("kind"), field("text"))
        })
        .collect()
}

/// The JSON trace carries the goal-network events with their kinds and the log's text.
#[test]
fn the_trace_carries_the_goal_network_events() {
    let events = trace_events("switch1_sticks_open_mission.ron", "maintain");
    for (kind, text) in [
        (
            "XGoalDispatched",
            "Maintain switch1 ∈ {closed, stuck-closed}, known over [TP_A, TP_E]  (know-switch1, heater1)",
        ),
        ("TimePointFired", "TP_S  (window [71, 161])"),
        (
            "MissionGoalFailed",
            "heater1: ŝ left the maintained set; ŝ has switch1 = stuck-open (p 1.00)",
        ),
    ] {
        assert!(
            events.iter().any(|(k, t)| k == kind && t == text),
            "no {kind} `{text}` in the trace: {events:?}"
        );
    }
}

/// The lines of the goal controller's story in the log, `[time] tag text` with padding
/// squeezed: tactics, responses, promotions, safing, mission goals' failures, and the firing of StayWarm's
/// points (`TP_S`, `TP_E`, `stay-warm.TP_A`, `stay-warm#2.TP_A`).
fn story(log: &str) -> Vec<String> {
    let mut time = String::new();
    let mut lines = Vec::new();
    for line in log.lines() {
        if let Some(rest) = line.strip_prefix('[') {
            // `[  66.000 s   0:01:06.000] #66`: the time in seconds.
            time = rest
                .split_whitespace()
                .take(2)
                .collect::<Vec<_>>()
                .join(" ");
            continue;
        }
        let words: Vec<&str> = line.split_whitespace().collect();
        let Some(tag) = words.first() else { continue };
        let shown = match *tag {
            "tactic" | "RESPONSE" | "promoted" | "PROMOTION" | "SAFING" => true,
            // A mission goal's failure (goal interpretation's say the configuration goal).
            "GOAL" => line.contains("; ŝ has "),
            "fired" => {
                ["TP_S", "TP_E", "TP_bgE", "safing"].contains(&words[1])
                    || (words[1].starts_with("stay-warm") && words[1].ends_with(".TP_A"))
            }
            _ => false,
        };
        if shown && !line.starts_with("  ok") {
            lines.push(format!("{time} {}", words.join(" ")));
        }
    }
    lines
}

/// The controller's story of a scenario (which must pass), with the rejection reasons and the
/// chosen tactics of goals with one tactic left out, for comparison with the seed's verdicts.
fn verdict(name: &str) -> Vec<String> {
    verdict_of(&run_mission(name))
}

/// [`verdict`] of a mission log.
fn verdict_of(log: &str) -> Vec<String> {
    let one_choice = ["know-all:", "heater1:", "heater2:"];
    story(log)
        .into_iter()
        .filter(|l| !(l.contains(" chosen") && one_choice.iter().any(|g| l.contains(g))))
        .map(|l| match l.find(" rejected: ") {
            Some(i) => l[..i + " rejected".len()].to_string(),
            None => l,
        })
        .map(|l| l.split(" (window").next().unwrap_or_default().to_string())
        .collect()
}

/// The first cycle of a nominal elaboration: StayWarm and GetWarm with tactic 1.
const NOMINAL: [&str; 2] = [
    "0.000 s tactic stay-warm: tactic 1 chosen",
    "0.000 s tactic stay-warm.get-warm: tactic 1 chosen",
];

/// System test 4 (seed 000 App. A, Table 7) through `kairos run`: tactic 1 for StayWarm and
/// GetWarm, TP_A once switch 1 is closed, TP_S once warm, TP_E on time; nothing fails.
#[test]
fn system_test_4_tactic_1_runs() {
    let mut expected = NOMINAL.to_vec();
    expected.extend([
        "1.000 s fired stay-warm.TP_A",
        "66.000 s fired TP_S",
        "366.000 s fired TP_E",
    ]);
    assert_eq!(verdict("system_test_4.ron"), expected);
}

/// System test 5, switch 1 stuck open from the start (believed so): tactic 1 is rejected at
/// scheduling — chronological backtracking through GetWarm's tactics first — and tactic 2 runs
/// (the seed's text says tactic 1: inconsistency C1, mds-goal-networks.md §5, noted in the
/// scenario).
#[test]
fn system_test_5_rejects_tactic_1_and_runs_tactic_2() {
    assert_eq!(
        verdict("system_test_5.ron"),
        [
            "0.000 s tactic stay-warm.get-warm: tactic 1 rejected",
            "0.000 s tactic stay-warm.get-warm: tactic 2 rejected",
            "0.000 s tactic stay-warm: tactic 1 rejected",
            "0.000 s tactic stay-warm.get-warm: tactic 1 rejected",
            "0.000 s tactic stay-warm: tactic 2 chosen",
            "0.000 s tactic stay-warm.get-warm: tactic 2 chosen",
            "1.000 s fired stay-warm.TP_A",
            "66.000 s fired TP_S",
            "366.000 s fired TP_E",
        ]
    );
}

/// System test 6, switch 1 stuck closed from the start (believed so): tactic 1 runs and
/// nothing is commanded — CLOSED admits stuck-closed.
#[test]
fn system_test_6_runs_tactic_1_without_a_command() {
    let log = run_mission("system_test_6.ron");
    assert!(
        !log.lines().any(|l| l.trim_start().starts_with("command")),
        "{log}"
    );
    let mut expected = NOMINAL.to_vec();
    expected.extend([
        "0.000 s fired stay-warm.TP_A",
        "66.000 s fired TP_S",
        "366.000 s fired TP_E",
    ]);
    assert_eq!(verdict("system_test_6.ron"), expected);
}

/// System test 7, switch 1 sticks open during the hold: diagnosed from the temperature, the
/// Heater goal fails up, StayWarm is re-elaborated with tactic 2 and promoted in that cycle;
/// StayWarm never fails and its end point fires on time.
#[test]
fn system_test_7_reelaborates_with_tactic_2() {
    let mut expected = NOMINAL.to_vec();
    expected.extend([
        "1.000 s fired stay-warm.TP_A",
        "66.000 s fired TP_S",
        "187.000 s GOAL FAILED stay-warm.heater1: ŝ left the maintained set; ŝ has switch1 = stuck-open (p 1.00)",
        "187.000 s RESPONSE stay-warm.heater1 failed: switch1 = stuck-open (p 1.00) → fail up → stay-warm re-elaborated with tactic 2 → promoted",
        "187.000 s tactic stay-warm: tactic 2 chosen",
        "187.000 s promoted the proposed network (re-elaboration of stay-warm)",
        "188.000 s fired stay-warm#2.TP_A",
        "366.000 s fired TP_E",
    ]);
    assert_eq!(verdict("system_test_7.ron"), expected);
}

/// System test 8, switch 2 sticks closed during the hold: the same with the roles swapped.
#[test]
fn system_test_8_reelaborates_with_tactic_2() {
    let mut expected = NOMINAL.to_vec();
    expected.extend([
        "1.000 s fired stay-warm.TP_A",
        "66.000 s fired TP_S",
        "187.000 s GOAL FAILED stay-warm.heater2: ŝ left the maintained set; ŝ has switch2 = stuck-closed (p 1.00)",
        "187.000 s RESPONSE stay-warm.heater2 failed: switch2 = stuck-closed (p 1.00) → fail up → stay-warm re-elaborated with tactic 2 → promoted",
        "187.000 s tactic stay-warm: tactic 2 chosen",
        "187.000 s promoted the proposed network (re-elaboration of stay-warm)",
        "188.000 s fired stay-warm#2.TP_A",
        "366.000 s fired TP_E",
    ]);
    assert_eq!(verdict("system_test_8.ron"), expected);
}

/// System test 9, the sensor fails: no tactic remains (both need the sensor healthy),
/// StayWarm is a root, safing once; TP_E never fires and nothing is commanded after safing.
#[test]
fn system_test_9_leaves_no_tactic_and_safes_once() {
    let log = run_mission("system_test_9.ron");
    let chain = "stay-warm.sensor failed: sensor = failed (p 1.00) → fail up → stay-warm: no \
                 tactic left (every tactic of `stay-warm` was rejected) → stay-warm is a root → \
                 safing";
    let mut expected: Vec<String> = NOMINAL.iter().map(|l| l.to_string()).collect();
    expected.extend([
        "1.000 s fired stay-warm.TP_A".to_string(),
        "66.000 s fired TP_S".to_string(),
        "181.000 s GOAL FAILED stay-warm.sensor: ŝ left the maintained set; ŝ has sensor = failed (p 1.00)".to_string(),
        format!("181.000 s RESPONSE {chain}"),
        "181.000 s tactic stay-warm: tactic 2 rejected".to_string(),
        "181.000 s tactic stay-warm: tactic 1 rejected".to_string(),
        "181.000 s PROMOTION failed: every tactic of `stay-warm` was rejected".to_string(),
        format!("181.000 s SAFING {chain}"),
        "181.000 s fired safing".to_string(),
    ]);
    assert_eq!(verdict_of(&log), expected);
    let after_safing = log.split("SAFING").nth(1).unwrap_or_default();
    assert!(
        !after_safing
            .lines()
            .any(|l| l.trim_start().starts_with("command")),
        "{log}"
    );
}

/// The mission log's lines for the goal controller's events (tactic chosen and rejected with
/// its reason, response with its explanation chain, promotion, promotion failed, safing with
/// its cause), as `kairos run` prints them: system test 7's re-elaboration and system test 9's
/// safing, snapshot-tested.
#[test]
fn the_controller_events_in_the_mission_log() {
    let lines: Vec<String> = ["system_test_7.ron", "system_test_9.ron"]
        .iter()
        .flat_map(|name| {
            let log = run_mission(name);
            let mut lines = vec![format!("# {name}")];
            lines.extend(
                story(&log)
                    .into_iter()
                    .filter(|l| !l.starts_with("0.000 s")),
            );
            lines
        })
        .collect();
    insta::assert_snapshot!(lines.join("\n"));
}

/// The JSON trace carries the goal controller's events by kind, with the log's text: system
/// test 9's rejected tactics, response chain, failed promotion and safing.
#[test]
fn the_trace_carries_the_controller_events() {
    let events = trace_events("system_test_9.ron", "safing");
    let kinds: Vec<&str> = events
        .iter()
        .map(|(k, _)| k.as_str())
        .filter(|k| {
            [
                "TacticRejected",
                "ResponseTaken",
                "Promoted",
                "PromotionFailed",
                "Safing",
            ]
            .contains(k)
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "ResponseTaken",
            "TacticRejected",
            "TacticRejected",
            "PromotionFailed",
            "Safing"
        ]
    );
    let safing = events.iter().find(|(k, _)| k == "Safing").map(|(_, t)| t);
    assert_eq!(
        safing.map(String::as_str),
        Some(
            "stay-warm.sensor failed: sensor = failed (p 1.00) → fail up → stay-warm: no tactic \
             left (every tactic of `stay-warm` was rejected) → stay-warm is a root → safing"
        )
    );
}

/// DESIGN.md §15.2, a point whose window is in the past is refused at promotion: a sensor check
/// submitted at 100 s that must start by 99.5 s is refused with the two constraints that
/// contradict each other; the running network runs on.
#[test]
fn a_submission_into_the_past_is_refused_and_the_network_runs_on() {
    let log = run_mission("submitted_into_the_past.ron");
    assert_in_order(
        &log,
        &[
            "[ 100.000 s 0:01:40.000] #100",
            "REFUSED sensor-check submitted by `operator asks for a late sensor check`: the submission cannot be scheduled: inconsistent",
            "origin → TP_X ∈ [99, 99.5] (submitted)",
            "origin → TP_X ∈ [100, +∞] (scheduler: a new point is not in the past (promotion step b))",
            "fired TP_E (window [376, 376])",
        ],
    );
    assert!(!log.contains("TEMPORAL"), "{log}");
}

/// DESIGN.md §15.2, one path answers every failure: the forced end of `warm-up` is answered by
/// its own response (safing) in the cycle it is forced, not by the hold that would have failed
/// a cycle later.
#[test]
fn a_missed_warm_up_deadline_is_answered_in_its_cycle() {
    let log = run_mission("warm_up_deadline_missed.ron");
    assert_in_order(
        &log,
        &[
            "[ 61.000 s 0:01:01.000] #61",
            "FORCED TP_W at its latest time, not ready (window [31, 61], 0.000 s late)",
            "GOAL FAILED warm-up: its end point was forced before the set was reached; ŝ has temperature = warming (p 1.00)",
            "RESPONSE warm-up failed: temperature = warming (p 1.00) → safing",
            "SAFING warm-up failed: temperature = warming (p 1.00) → safing",
            "fired safing (window [61, 61])",
        ],
    );
    assert!(!log.contains("GOAL FAILED hold"), "{log}");
}

/// DESIGN.md §15.2, a goal that holds again is reported recovered and monitored again: the
/// knowledge of the temperature fails in each of two sensor drop-outs, each failure answered,
/// and recovers after each.
#[test]
fn a_knowledge_goal_fails_in_each_drop_out_and_recovers() {
    let log = run_mission("sensor_dropouts.ron");
    let failed = "GOAL FAILED know-temperature: not known (P below 0.9 or a least belief); ŝ has temperature = warm-low (p 0.89)";
    let answered = "RESPONSE know-temperature failed: temperature = warm-low (p 0.89) → no response (the mission declares none): the network runs on";
    assert_in_order(
        &log,
        &[
            "[ 102.000 s 0:01:42.000] #102",
            failed,
            answered,
            "[ 105.000 s 0:01:45.000] #105",
            "recovered know-temperature holds again; ŝ has temperature = warm-low (p 1.00)",
            "[ 127.000 s 0:02:07.000] #127",
            failed,
            answered,
            "[ 130.000 s 0:02:10.000] #130",
            "recovered know-temperature holds again",
        ],
    );
}

/// DESIGN.md §15.2, refusals name every conflicting goal: heater 1 off over the whole hold
/// conflicts with `heater1` and with `close-switch1`, and the refusal names both.
#[test]
fn a_refusal_names_every_conflicting_goal() {
    let log = run_mission("refusal_names_every_conflict.ron");
    assert_in_order(
        &log,
        &[
            "REFUSED heater1-off submitted by `operator asks for heater 1 off`: the submission cannot be scheduled: unmergeable: on switch1, goal `heater1-off` (switch1 = open) cannot hold together with `heater1` (switch1 = closed or switch1 = stuck-closed) nor with `close-switch1` (switch1 = closed or switch1 = stuck-closed) and cannot be serialised either way",
            "fired TP_E (window [376, 376])",
        ],
    );
}

/// Typed submissions: StayWarm submitted at 10 s, as the seed's system tests do, is elaborated
/// by its type's tactics when it is promoted and runs as system test 4.
#[test]
fn a_typed_submission_is_elaborated_by_its_tactics() {
    let log = run_mission("stay_warm_submitted_at_10s.ron");
    assert_in_order(
        &log,
        &[
            "[ 10.000 s 0:00:10.000] #10",
            "tactic stay-warm: tactic 1 chosen",
            "tactic stay-warm.get-warm: tactic 1 chosen",
            "promoted the proposed network (a submission)",
            "command switch1.cmd = close (switch1: open -> closed)",
            "fired stay-warm.TP_A",
            "fired TP_S (window [71, 161])",
            "fired TP_E (window [376, 376])",
        ],
    );
}

/// DESIGN.md §15.2, a promotion replaces the retired tactic's constraints: after switch 1 is
/// found stuck open, StayWarm's backup tactic is not bound by the primary's tighter warming
/// window, and TP_S fires in tactic 2's.
#[test]
fn the_backup_tactic_is_not_bound_by_the_primary_window() {
    let log = run_mission("backup_heater_after_a_stuck_switch.ron");
    assert_in_order(
        &log,
        &[
            "[ 77.000 s 0:01:17.000] #77",
            "RESPONSE stay-warm.heater1 failed: switch1 = stuck-open (p 1.00) → fail up → stay-warm re-elaborated with tactic 2 → promoted",
            "tactic stay-warm: tactic 2 chosen",
            "command switch2.cmd = close (switch2: open -> closed)",
            "fired TP_S (window [138, 210])",
            "fired TP_E (window [443, 443])",
        ],
    );
}

/// DESIGN.md §15.2, after a promotion only the live network's XGoals form the configuration
/// goal, and the promoted tactic progresses: switch 1 stuck open from power-on, tactic 2 warms
/// the device with heater 2, nothing of tactic 1 is asked for again.
#[test]
fn the_promoted_tactic_warms_the_device() {
    let log = run_mission("switch1_stuck_open_promoted_tactic_2.ron");
    assert_in_order(
        &log,
        &[
            "[ 77.000 s 0:01:17.000] #77",
            "tactic stay-warm: tactic 2 chosen",
            "promoted the proposed network (re-elaboration of stay-warm)",
            "command switch2.cmd = close (switch2: open -> closed)",
            "fired TP_S (window [138, 210])",
        ],
    );
    assert!(!log.contains("FORCED"), "{log}");
}

/// The exploration scenario's nominal path: no fault, the device warm through the hold.
#[test]
fn the_exploration_scenario_runs_its_nominal_path() {
    run_mission("explore_a_stuck_switch.ron");
}
