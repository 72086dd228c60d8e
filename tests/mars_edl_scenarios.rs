//! The Mars EDL scenarios (thesis §7.2): every scenario under
//! `scenarios/mars_edl/` runs through `kairos run` and exits 0 (all its expectations hold), and
//! the mission log shows the moments each one is about. scenarios/mars_edl/README.md maps the
//! validation requirements of §7.2.1 to the scenarios and their expectations.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/scenario_run.rs"]
mod scenario_run;

use std::path::Path;

use cli::kairos;
use scenario_run::{assert_every_file_is_tested, assert_in_order, run_passing};

const DIR: &str = "scenarios/mars_edl";

/// The scenarios this file runs, one test each.
const SCENARIOS: [&str; 15] = [
    "nominal.ron",
    "descent_mission.ron",
    "descent_flameout.ron",
    "descent_valve2_stuck_closed.ron",
    "descent_mpl_spike.ron",
    "engine_stuck_heating.ron",
    "engine_power_loss.ron",
    "pde_resettable.ron",
    "lander_pyro_misfire.ron",
    "mars_polar_lander.ron",
    "valve2_ignores_open.ron",
    "valve2_stuck_closed.ron",
    "valve2_rejected.ron",
    "valve2_accepted_stuck.ron",
    "explore_faults.ron",
];
/// The other files there: the scripts the scenarios include, the requirement mapping, and the
/// campaign scenario, whose runs `kairos campaign` judges one by one (docs/campaigns.md; at
/// ≈ 17,200 cycles a run it is measured in BENCHMARKS.md, not run here).
const NOT_SCENARIOS: [&str; 5] = [
    "plant.ron",
    "descent.ron",
    "acknowledgements.ron",
    "README.md",
    "campaign.ron",
];

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
        "tests/mars_edl_scenarios.rs",
    );
}

/// §7.2.2, the whole EDL at the 0.1 s cycle: nominal validation requirements 1-7 of §7.2.1.
#[test]
fn nominal_edl_follows_the_section_7_2_2_timeline() {
    let log = run("nominal.ron");
    assert_in_order(
        &log,
        &[
            "cycle 0.1 s until 17200 s",
            "command PDE.cmd = engine-standby (engine: off -> heating)",
            "[ 43.100 s 0:00:43.100]",
            "believed engine: heating -> standby",
            "clock t1 started",
            "[ 16243.200 s 4:30:43.200]",
            "command nav.cmd = inertial (nav: earth-relative -> inertial)",
            "command att.cmd = to-entry",
            "[ 16495.500 s 4:34:55.500]",
            "command lander.cmd = fire-primary (lander: connected -> separated)",
            "believed entry: not-initiated -> initiated",
            "command chute.cmd = fire",
            "command heatshield.cmd = fire",
            "command legs.cmd = fire",
            "command radar_altim.cmd = on",
            "command backshield.cmd = fire",
            "command PDE.cmd = on (PDE: off -> on)",
            "command PDE.cmd = open1 (valve1: closed -> open)",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "command PDE.cmd = engine-fire (engine: standby -> firing)",
            "goal achieved engine = firing",
            // The gravity turn during the landing slew (Figure B-4's concurrent threads).
            "command att.cmd = to-landing",
            "command prop.cmd = gravity-turn",
            "believed att: slew-to-landing -> landing-orient",
            "command radar_altim.cmd = off",
            "command prop.cmd = const-vel-descent",
            "goal asserted engine = off",
            "command PDE.cmd = engine-off (engine: standby -> off)",
            "goal achieved landing = success",
            "completed the program has completed",
        ],
    );
    assert!(!log.contains("DIAGNOSIS"), "{log}");
    // The 300 s hold of the entry attitude is one achievement, not one per cycle.
    assert_eq!(log.matches("achieved att = entry-orient").count(), 1);
}

/// §7.2.5: the engine stuck in heating past the 60 s bound of its timed transition is diagnosed
/// failed (fault validation requirement 2 of §7.2.1).
#[test]
fn an_engine_stuck_heating_is_diagnosed_when_the_60_s_window_closes() {
    let log = run("engine_stuck_heating.ron");
    assert_in_order(
        &log,
        &[
            "rule `heater sticks` takes effect: heater = stuck (FAULT)",
            "believed engine: off -> heating",
            "[ 60.200 s 0:01:00.200]",
            "DIAGNOSIS engine = failed",
            "GOAL FAILED engine = standby",
        ],
    );
}

/// §7.2.5: an unanticipated fault, power lost while heating, falls to the unconstrained failed
/// mode (fault validation requirement 1 of §7.2.1).
#[test]
fn an_engine_losing_power_while_heating_falls_to_its_unconstrained_mode() {
    let log = run("engine_power_loss.ron");
    assert_in_order(
        &log,
        &[
            "[ 20.000 s 0:00:20.000]",
            "rule `engine loses power` takes effect: engine.power = zero (FAULT)",
            "believed engine: heating -> failed",
            "DIAGNOSIS engine = failed",
        ],
    );
}

/// §7.2.4-§7.2.5: a resettable PDE is reset and the EDL continues (fault validation
/// requirement 3 of §7.2.1). Every command names the goal it serves: the
/// PDE's `on` and `reset` serve the engine's standby goal, which needs the PDE on; the PDE's
/// `off` afterwards serves no asserted goal but the intended configuration.
#[test]
fn a_resettable_pde_is_reset_and_the_edl_continues() {
    let log = run("pde_resettable.ron");
    assert_in_order(
        &log,
        &[
            "command PDE.cmd = on (PDE: off -> on) for engine = standby (programs/mars_edl.rmpl:20:3)",
            // The PDE off, stepped by `on`, would be on: its status fault is the evidence.
            "DIAGNOSIS PDE = resettable (p 1.00); evidence: PDE.status = fault",
            "REPAIR PDE.cmd = reset (PDE: resettable -> on) for engine = standby (programs/mars_edl.rmpl:20:3)",
            "command PDE.cmd = engine-standby (engine: off -> heating) for engine = standby (programs/mars_edl.rmpl:20:3)",
            "goal achieved engine = standby",
            "clock t1 started",
            "command PDE.cmd = off (PDE: on -> off) for PDE = off, bringing back a helper moved for engine = standby",
        ],
    );
    // The status is the only evidence: the PDE's other observations fit it being on.
    assert!(
        (log.lines())
            .any(|l| l.ends_with("PDE = resettable (p 1.00); evidence: PDE.status = fault")),
        "{log}"
    );
}

/// §7.2.5 and §3.3: the primary separation pyro misfires; the backup separates the lander and
/// the EDL lands (fault validation requirements 1 and 4 of §7.2.1).
#[test]
fn a_primary_pyro_misfire_is_diagnosed_and_the_backup_separates_the_lander() {
    let log = run("lander_pyro_misfire.ron");
    assert_in_order(
        &log,
        &[
            "command lander.cmd = fire-primary",
            "believed lander: connected -> unsuccessful-attempt",
            "DIAGNOSIS lander = unsuccessful-attempt",
            "REPAIR lander.cmd = fire-backup (lander: unsuccessful-attempt -> separated)",
            "believed lander: unsuccessful-attempt -> separated",
            "goal achieved lander = separated",
            "goal achieved landing = success",
            "completed the program has completed",
        ],
    );
}

/// Beyond the thesis's executive, which acts on ŝ alone: valve 2 ignores the
/// first `open2`. Mode estimation prefers stuck-closed (its hazard accumulated over the mission)
/// to "the command was not taken"; the diagnosis names the next candidates, the executive sends
/// `open2` again on the closed hypothesis, the valve opens, the engine fires and the EDL lands.
#[test]
fn a_valve_that_ignores_the_first_open_command_is_commanded_again_and_the_edl_lands() {
    let log = run("valve2_ignores_open.ron");
    assert_in_order(
        &log,
        &[
            "goal asserted engine = firing",
            "command PDE.cmd = open1 (valve1: closed -> open)",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "[ 17109.000 s 4:45:09.000]",
            "believed valve2: closed -> stuck-closed (p 0.59)",
            "DIAGNOSIS valve2 = stuck-closed (p 0.59); evidence: valve2.outlet = low; next: valve2 = closed (p 0.35), valve2 = open (p 0.06)",
            "RETRY PDE.cmd = open2 for engine = firing: the goal is reachable if valve2 = closed (p 0.35); retry 1 of 2",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "[ 17110.000 s 4:45:10.000]",
            "believed valve2: stuck-closed -> open (p 1.00)",
            "command PDE.cmd = engine-fire (engine: standby -> firing)",
            "goal achieved engine = firing",
            "goal achieved landing = success",
            "completed the program has completed",
        ],
    );
    assert_eq!(log.matches("RETRY").count(), 1, "{log}");
    assert!(!log.contains("GOAL FAILED"), "{log}");
}

/// Command acknowledgements (src/plant/acknowledgement.rs): the PDE rejects the first `open2`,
/// so the step is estimated as if it had not been sent — no diagnosis, no retry on a
/// hypothesis: the planner sends `open2` again from ŝ in the next cycle.
#[test]
fn a_rejected_open_command_is_sent_again_at_once_without_ambiguity() {
    let log = run("valve2_rejected.ron");
    assert_in_order(
        &log,
        &[
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "PDE.ack = rejected",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "PDE.ack = accepted",
            "command PDE.cmd = engine-fire (engine: standby -> firing)",
            "completed the program has completed",
        ],
    );
    for absent in ["RETRY", "DIAGNOSIS", "GOAL FAILED"] {
        assert!(!log.contains(absent), "{absent}: {log}");
    }
}

/// Command acknowledgements: the PDE accepts `open2` and the pressure stays low. "The command
/// was not taken" is then impossible: stuck-closed is diagnosed with only an empty tank behind
/// an open valve beside it (no `closed` candidate), nothing is retried and the goal fails.
#[test]
fn an_accepted_open_command_without_flow_is_a_stuck_valve_without_retry() {
    let log = run("valve2_accepted_stuck.ron");
    assert_in_order(
        &log,
        &[
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "PDE.ack = accepted",
            "DIAGNOSIS valve2 = stuck-closed (p 0.91); evidence: valve2.outlet = low; next: valve2 = open (p 0.09)",
            "GOAL FAILED engine = firing",
        ],
    );
    assert!(!log.contains("RETRY"), "{log}");
    assert!(!log.contains("valve2 = closed (p"), "{log}");
    let sent = "PDE.cmd = open2 (valve2: closed -> open)";
    assert_eq!(log.matches(sent).count(), 1, "{log}");
}

/// Valve 2 is really stuck closed. One retry on the closed hypothesis; its
/// silence leaves "not taken twice" below the threshold, and `engine = firing` fails, the failure
/// naming both explanations — stuck-closed (ŝ) and closed (tried) — and the one left that cannot
/// serve the goal (an empty tank behind an open valve). The engine is never fired.
#[test]
fn a_valve_stuck_closed_is_retried_once_then_the_goal_fails_naming_the_hypotheses() {
    let log = run("valve2_stuck_closed.ron");
    assert_in_order(
        &log,
        &[
            "command PDE.cmd = open2 (valve2: closed -> open) for engine = firing (programs/mars_edl.rmpl:71:7)",
            "[ 17109.000 s 4:45:09.000]",
            // The evidence: after `open2`, the valve that ŝ (closed) stepped by the command
            // would have opened reports its outlet low.
            "DIAGNOSIS valve2 = stuck-closed (p 0.59); evidence: valve2.outlet = low; next: valve2 = closed (p 0.35)",
            "RETRY PDE.cmd = open2 for engine = firing: the goal is reachable if valve2 = closed (p 0.35); retry 1 of 2",
            "command PDE.cmd = open2 (valve2: closed -> open)",
            "[ 17110.000 s 4:45:10.000]",
            "GOAL FAILED engine = firing: engine = firing is unreachable: engine can reach only off, standby from standby (standby -> firing needs valve2 = open (valve2 is stuck-closed)); also tried valve2 = closed (p 0.35, 1 retry); unreachable also if valve2 = open and tank2 = empty (p 0.09)",
        ],
    );
    assert_eq!(log.matches("RETRY").count(), 1, "{log}");
    assert_eq!(log.matches("GOAL FAILED").count(), 1, "{log}");
    assert!(!log.contains("PDE.cmd = engine-fire ("), "{log}");
}

/// §1.1 and §7.2.3: the Mars Polar Lander's latched touchdown spike is reset and the engine
/// burns until the real touchdown.
#[test]
fn a_touchdown_spike_at_leg_deployment_does_not_stop_the_engine() {
    let log = run("mars_polar_lander.ron");
    assert_in_order(
        &log,
        &[
            "rule `leg deployment spike` takes effect: touchdown_sensor.flag = set (FAULT)",
            "believed touchdown_sensor: not-triggered -> triggered",
            "goal achieved engine = firing",
            "goal asserted touchdown_sensor = not-triggered",
            "command touchdown_sensor.cmd = reset",
            "believed touchdown_sensor: triggered -> not-triggered",
            "rule `12 m` takes effect",
            "rule `touchdown` takes effect",
            "goal asserted engine = off",
            "goal achieved landing = success",
        ],
    );
}

/// The Mars Polar Lander scenario is a real check: without the program's touchdown-reset thread
/// (Figure B-4's `whenever ... donext touchdown_sensor = not-triggered`), the latched spike and
/// the 12 m trigger shut the engine down in the air, and the scenario fails (exit 1).
#[test]
fn without_the_reset_thread_the_mars_polar_lander_scenario_fails() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let program = std::fs::read_to_string(root.join("programs/mars_edl.rmpl")).expect("program");
    let reset = "        whenever ((alt_12m_trigger = not-triggered) ∧ (touchdown_sensor = triggered)) donext\n          touchdown_sensor = not-triggered,\n";
    assert!(
        program.contains(reset),
        "the reset thread is in the program"
    );
    let scenario = std::fs::read_to_string(root.join(DIR).join("mars_polar_lander.ron"))
        .expect("scenario")
        .replace(
            "../../programs/mars_edl.rmpl",
            "mars_edl_without_reset.rmpl",
        )
        .replace(
            "../../models/mars_lander.ron",
            &root.join("models/mars_lander.ron").to_string_lossy(),
        )
        .replace(
            "[\"plant.ron\", \"descent.ron\"]",
            &format!(
                "[\"{}\", \"{}\"]",
                root.join(DIR).join("plant.ron").to_string_lossy(),
                root.join(DIR).join("descent.ron").to_string_lossy()
            ),
        );
    let dir = std::env::temp_dir().join(format!("kairos-mpl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    std::fs::write(
        dir.join("mars_edl_without_reset.rmpl"),
        program.replace(reset, ""),
    )
    .expect("written");
    let path = dir.join("mpl.ron");
    std::fs::write(&path, scenario).expect("written");
    let (code, stdout, stderr) = kairos(&["run", &path.to_string_lossy(), "--quiet"]);
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, 1, "the scenario must fail:\n{stdout}\n{stderr}");
    assert!(
        stdout.contains("FAILED never commanded PDE.cmd = engine-off or PDE.cmd = engine-standby"),
        "the engine is shut down before touchdown:\n{stdout}"
    );
}

/// The EDL with optional hardware faults is, under `kairos run`, the nominal EDL — an
/// optional rule fires in a run only where `choose` pins it (its exploration is measured in
/// BENCHMARKS.md; a small one runs in tests/exploration.rs).
#[test]
fn the_explored_edl_runs_as_the_nominal_one() {
    let log = run("explore_faults.ron");
    assert!(!log.contains("(FAULT)"), "an optional rule fired:\n{log}");
    assert_in_order(&log, &["landing = success", "the program has completed"]);
}

/// The powered descent as a goal network (missions/mars_edl_descent.ron) run
/// by the goal controller: the triggers hold its points, the engine is maintained firing until
/// touchdown, then off and the landing declared; the mission completes.
#[test]
fn the_descent_mission_lands() {
    let log = run("descent_mission.ron");
    assert_in_order(
        &log,
        &[
            "mission missions/mars_edl_descent.ron",
            "fired TP_warm",
            "fired TP_att (window [16700, 16800])",
            "[ 17102.500 s 4:45:02.500]",
            "fired TP_bs (window [17000, 17300])",
            // A command names the mission goal it serves.
            "command PDE.cmd = engine-fire (engine: standby -> firing) for goal ignite",
            "fired TP_fire",
            "fired TP_12m",
            "[ 17157.000 s 4:45:57.000]",
            "fired TP_td",
            "command PDE.cmd = engine-off (engine: standby -> off) for goal engine-off",
            "command landing.cmd = set-success (landing: in-progress -> success) for goal landed",
            "fired TP_end",
            "fired TP_rest",
            "completed the program has completed",
            "PASS: 20 expectations hold",
        ],
    );
}

/// The engine flames out mid-descent; the Maintain goal on `engine = firing`
/// fails, its response (safing: the model cannot restart a failed engine) is taken with its
/// explanation, the safe network closes the propellant valves, and nothing of the descent
/// fires after it.
#[test]
fn a_flame_out_fails_the_engine_goal_and_safes_the_descent() {
    let log = run("descent_flameout.ron");
    assert_in_order(
        &log,
        &[
            "[ 17130.000 s 4:45:30.000]",
            "rule `the engine flames out` takes effect: engine.thrust = zero (FAULT)",
            "DIAGNOSIS engine = failed (p 1.00)",
            "GOAL FAILED engine-firing: ŝ left the maintained set; ŝ has engine = failed (p 1.00)",
            "RESPONSE engine-firing failed: engine = failed (p 1.00) → safing",
            "SAFING engine-firing failed: engine = failed (p 1.00) → safing",
            "fired safing (window [17130, 17130])",
            "command PDE.cmd = close1 (valve1: open -> closed)",
            "command PDE.cmd = close2 (valve2: open -> closed)",
            "fired isolated",
            "fired safe-end",
            "completed the program has completed",
            "PASS: 19 expectations hold",
        ],
    );
    for point in ["TP_12m", "TP_td", "TP_end"] {
        assert!(
            !log.contains(&format!("fired {point} ")),
            "{point} fired:\n{log}"
        );
    }
}

/// Valve 2 stuck closed in the powered descent as a goal network (DESIGN.md §15.2): TP_fire is
/// forced, the goals ending there unreached fail — `ignite` among them — and safing is invoked
/// once for all of them (one response each). The safe network is scheduled best effort: its two goals on valve 2
/// (stuck closed, not `closed`) are dropped with their reason, valve 1 is closed.
#[test]
fn valve_2_stuck_closed_safes_the_descent_best_effort() {
    let log = run("descent_valve2_stuck_closed.ron");
    assert_in_order(
        &log,
        &[
            "DIAGNOSIS valve2 = stuck-closed",
            "[ 17107.500 s 4:45:07.500]",
            "FORCED TP_fire at its latest time, not ready",
            "GOAL FAILED ignite: its end point was forced before the set was reached",
            "RESPONSE ignite failed: engine = standby (p 1.00) → fail up → PoweredDescent is a root → safing",
            "SAFING jettison-backshell failed",
            "SAFE DROP safe goal close-valve2 dropped: unachievable:",
            "SAFE DROP safe goal valve2-closed dropped: unachievable:",
            "fired safing (window [17107.5, 17107.5])",
            "command PDE.cmd = close1 (valve1: open -> closed) for goal close-valve1",
            "fired isolated",
            "PASS: 19 expectations hold",
        ],
    );
    assert_eq!(log.matches("SAFING ").count(), 1, "{log}");
}

/// The Mars Polar Lander's spike (thesis §1.1, §7.2.3) against the powered descent as a goal
/// network: the latched touchdown flag is reset once the descent begins (`touchdown-armed`),
/// so touchdown is declared at the real one, not a cycle after the 12 m trigger.
#[test]
fn a_latched_touchdown_spike_is_reset_and_the_engine_burns_to_touchdown() {
    let log = run("descent_mpl_spike.ron");
    assert_in_order(
        &log,
        &[
            "[ 17061.000 s 4:44:21.000]",
            "believed touchdown_sensor: not-triggered -> triggered (p 1.00)",
            "fired TP_bs",
            "command touchdown_sensor.cmd = reset (touchdown_sensor: triggered -> not-triggered) for goal touchdown-armed",
            "fired TP_12m",
            "[ 17157.000 s 4:45:57.000]",
            "fired TP_td",
            "command PDE.cmd = on (PDE: off -> on) for goal engine-off",
            "PASS: 17 expectations hold",
        ],
    );
}
