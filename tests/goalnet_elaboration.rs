//! The thermostat, complete, at the goal-network level (DESIGN.md §15.5;
//! seed 000 App. A, Table 7; mds-goal-networks.md §3.3): `missions/thermostat.ron` run by a
//! [`GoalController`] on scripted estimates (no executive), reproducing the seed's verdicts of
//! system tests 4–9 — which tactics elaboration chooses and rejects, which goals fail, the
//! failure responses with their explanation chains, promotions and safing — in order.
//!
//! The seed submits StayWarm at 10 s: the harness makes the controller (elaborates and promotes
//! the mission's network) at 10 s, so the tactics' points are anchored at or after 10 s.

use std::path::Path;

use kairos::goalnet::{EstimateView, GoalController, GoalEvent, MissionEvent, Response, mission};
use kairos::logic::ValueId;
use kairos::plant::Plant;
use kairos::reconfiguration::Reconfiguration;

/// A scripted estimate: `(component, mode, probability)`; the rest of the probability is on the
/// component's first mode; components not named are in their first mode (cold, open, open,
/// healthy) with certainty.
type Script = fn(f64) -> Vec<(&'static str, &'static str, f64)>;

fn estimate(plant: &Plant, modes: &[(&str, &str, f64)]) -> (Vec<ValueId>, Vec<Vec<f64>>) {
    let mut values = vec![ValueId(0); plant.components().len()];
    let mut beliefs: Vec<Vec<f64>> = plant
        .components()
        .iter()
        .map(|c| {
            let mut b = vec![0.0; c.modes().len()];
            b[0] = 1.0;
            b
        })
        .collect();
    for (component, mode, p) in modes {
        let c = plant.component_named(component).expect("a component");
        let v = plant.component(c).mode_named(mode).expect("a mode");
        values[c.index()] = v;
        let b = &mut beliefs[c.index()];
        b.iter_mut().for_each(|x| *x = 0.0);
        b[0] += 1.0 - p;
        b[v.index()] += p;
    }
    (values, beliefs)
}

struct Run {
    plant: Plant,
    reconfiguration: Reconfiguration,
    controller: GoalController,
    events: Vec<(f64, MissionEvent)>,
    /// Whether the configuration goal held for ŝ on each switch, per cycle after safing.
    goals_after_safing: Vec<String>,
}

impl Run {
    /// Runs the thermostat: makes the controller at 10 s and runs 1 s cycles to `to`.
    fn new(to: u32, script: Script) -> Self {
        Self::of("missions/thermostat.ron", 10, to, script)
    }

    /// Runs `path`: makes the controller at `from` and runs 1 s cycles from `from` to `to`.
    fn of(path: &str, from: u32, to: u32, script: Script) -> Self {
        std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
        let mission = mission::load(Path::new(path)).expect("loads");
        let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
        let (modes, beliefs) = estimate(&mission.plant, &script(f64::from(from)));
        let view = EstimateView {
            modes: &modes,
            beliefs: &beliefs,
        };
        let controller = GoalController::new(&mission, &reconfiguration, f64::from(from), view);
        let mut run = Run {
            plant: mission.plant.clone(),
            reconfiguration,
            controller,
            events: Vec::new(),
            goals_after_safing: Vec::new(),
        };
        for t in from..=to {
            run.cycle(f64::from(t), script);
        }
        run
    }

    fn cycle(&mut self, now: f64, script: Script) {
        let (modes, beliefs) = estimate(&self.plant, &script(now));
        let view = EstimateView {
            modes: &modes,
            beliefs: &beliefs,
        };
        for event in self.controller.step(now, view, &self.reconfiguration) {
            self.events.push((now, event));
        }
        if self.controller.is_safed() {
            let goal = self
                .controller
                .configuration_goal(&self.reconfiguration, |_| true);
            self.goals_after_safing
                .push(goal.display(self.plant.table()).to_string());
        }
    }

    fn fired(&self, name: &str) -> Option<f64> {
        let point = self
            .controller
            .network()
            .point_named(name)
            .expect("a point");
        self.controller.execution().fired_at(point)
    }

    /// The mission-level story, one line per event: tactics chosen for the goals with a choice
    /// (StayWarm, GetWarm) and every rejection, failures, responses (their explanation),
    /// promotions, safing, and the firing of StayWarm's points.
    fn story(&self) -> Vec<String> {
        let network = self.controller.network();
        let with_choice =
            |goal: &str| ["stay-warm", "hold"].contains(&goal) || goal.ends_with("get-warm");
        self.events
            .iter()
            .filter_map(|(t, e)| {
                let line = match e {
                    MissionEvent::TacticChosen { goal, tactic } if with_choice(goal) => {
                        format!("chosen {goal} {tactic}")
                    }
                    MissionEvent::TacticRejected { goal, tactic, .. } => {
                        format!("rejected {goal} {tactic}")
                    }
                    MissionEvent::ResponseTaken { explanation, .. } => {
                        format!("response {explanation}")
                    }
                    MissionEvent::Promoted { .. } => "promoted".to_string(),
                    MissionEvent::PromotionFailed { .. } => "promotion failed".to_string(),
                    MissionEvent::Safing { .. } => "safing".to_string(),
                    MissionEvent::Goal(GoalEvent::GoalFailed { goal, .. }) => {
                        format!("failed {}", network.goal(*goal).name)
                    }
                    MissionEvent::Goal(
                        GoalEvent::TimePointFired { point }
                        | GoalEvent::TimePointForced { point, .. },
                    ) => {
                        let name = &network.point(*point).name;
                        let shown = ["TP_S", "TP_E", "TP_bgE"].contains(&name.as_str())
                            || (name.starts_with("stay-warm") && name.ends_with(".TP_A"));
                        if !shown {
                            return None;
                        }
                        format!("fired {name}")
                    }
                    _ => return None,
                };
                Some(format!("{t} {line}"))
            })
            .collect()
    }

    fn rejection_reasons(&self) -> Vec<String> {
        self.events
            .iter()
            .filter_map(|(_, e)| match e {
                MissionEvent::TacticRejected { reason, .. } => Some(reason.clone()),
                _ => None,
            })
            .collect()
    }
}

/// The temperature of the nominal runs: warming once a heater is on at 11 s, warm-low from
/// 76 s, warm from 148 s (scenarios/thermostat/README.md, test 4).
fn temperature(t: f64) -> (&'static str, &'static str, f64) {
    let band = match t {
        t if t >= 148.0 => "warm",
        t if t >= 76.0 => "warm-low",
        t if t >= 12.0 => "warming",
        _ => "cold",
    };
    ("temperature", band, 1.0)
}

/// Test 4, nominal: switch 1 closed from 11 s.
fn nominal(t: f64) -> Vec<(&'static str, &'static str, f64)> {
    let mut modes = vec![temperature(t)];
    if t >= 11.0 {
        modes.push(("switch1", "closed", 1.0));
    }
    modes
}

/// The points of StayWarm's elaboration under tactic 1 and its own: TP_A once switch 1 is
/// closed (11 s), TP_S once warm (76 s), TP_E 300 s later.
const NOMINAL_START: [&str; 5] = [
    "10 chosen stay-warm 1",
    "10 chosen stay-warm.get-warm 1",
    "10 promoted",
    "11 fired stay-warm.TP_A",
    "76 fired TP_S",
];

/// System test 4 (seed: "maintain the WARM temperature state"): tactic 1 for StayWarm and
/// GetWarm, the points on time, no failure, no safing.
#[test]
fn test_4_tactic_1_runs() {
    let run = Run::new(400, nominal);
    let mut expected = NOMINAL_START.to_vec();
    expected.push("376 fired TP_E");
    assert_eq!(run.story(), expected);
    assert_eq!(run.fired("TP_E"), Some(376.0));
}

/// System test 5 (switch 1 stuck open from the start): tactic 1 is rejected at scheduling —
/// switch 1 cannot be closed — and tactic 2 runs. The seed says "verify that tactic 1 schedules
/// and runs"; mds-goal-networks.md §5 C1 reads that as a copy error (tests 7 and 8 fix tactic 1
/// as heater 1 on, which a switch stuck open cannot give): tactic 2 is asserted.
#[test]
fn test_5_switch_1_stuck_open_from_the_start_selects_tactic_2() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = vec![temperature(t), ("switch1", "stuck-open", 1.0)];
        if t >= 11.0 {
            modes.push(("switch2", "closed", 1.0));
        }
        modes
    }
    let run = Run::new(400, script);
    assert_eq!(
        run.story(),
        [
            // Chronological backtracking: GetWarm's tactics first, then StayWarm's.
            "10 rejected stay-warm.get-warm 1",
            "10 rejected stay-warm.get-warm 2",
            "10 rejected stay-warm 1",
            "10 rejected stay-warm.get-warm 1",
            "10 chosen stay-warm 2",
            "10 chosen stay-warm.get-warm 2",
            "10 promoted",
            "11 fired stay-warm.TP_A",
            "76 fired TP_S",
            "376 fired TP_E",
        ]
    );
    let reasons = run.rejection_reasons();
    assert!(reasons[0].contains("switch1"), "{reasons:?}");
    assert!(
        reasons[2].contains("every tactic of `stay-warm.get-warm`"),
        "{reasons:?}"
    );
}

/// System test 6 (switch 1 stuck closed from the start): tactic 1 runs, and switch 1 needs no
/// command — the configuration goal holds for switch 1 as it is (CLOSED admits stuck-closed).
#[test]
fn test_6_switch_1_stuck_closed_runs_tactic_1_without_commanding_it() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        // Heater 1 is on from power-on: warm-low after 66 s.
        let band = if t >= 66.0 { "warm-low" } else { "warming" };
        vec![("temperature", band, 1.0), ("switch1", "stuck-closed", 1.0)]
    }
    let run = Run::new(400, script);
    assert_eq!(
        run.story(),
        [
            "10 chosen stay-warm 1",
            "10 chosen stay-warm.get-warm 1",
            "10 promoted",
            "10 fired stay-warm.TP_A",
            // TP_A → TP_S ≥ 60 s: not before 70 s, warm already.
            "70 fired TP_S",
            "370 fired TP_E",
        ]
    );
}

/// The configuration goal of test 6 at 10 s holds for the switches as they are (switch 1 stuck
/// closed admitted by CLOSED, switch 2 open): mode reconfiguration has nothing to command.
#[test]
fn test_6_configuration_goal_needs_no_switch_1_command() {
    std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
    let mission = mission::load(Path::new("missions/thermostat.ron")).expect("loads");
    let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
    let (modes, beliefs) = estimate(&mission.plant, &[("switch1", "stuck-closed", 1.0)]);
    let view = EstimateView {
        modes: &modes,
        beliefs: &beliefs,
    };
    let mut controller = GoalController::new(&mission, &reconfiguration, 10.0, view);
    controller.step(10.0, view, &reconfiguration);
    let plant = &mission.plant;
    let switches = |c: kairos::plant::ComponentId| plant.component(c).name().starts_with("switch");
    let goal = controller.configuration_goal(&reconfiguration, switches);
    let holds = goal.eval(&|atom| match atom {
        kairos::logic::Atom::Is(x, v) => {
            let c = mission
                .plant
                .components()
                .iter()
                .position(|c| c.mode_var() == *x)?;
            Some(modes[c] == *v)
        }
        _ => None,
    });
    assert_eq!(holds, Some(true), "{}", goal.display(mission.plant.table()));
}

/// System test 7 (switch 1 sticks open during the maintain interval, diagnosed at 188 s with
/// p 0.97): the Heater goal fails up, StayWarm is re-elaborated with tactic 2 and promoted in
/// the same cycle, StayWarm itself never fails, its end point fires on time.
#[test]
fn test_7_switch_1_sticks_open_reelaborates_with_tactic_2() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = vec![temperature(t)];
        match t {
            t if t >= 188.0 => modes.push(("switch1", "stuck-open", 0.97)),
            t if t >= 11.0 => modes.push(("switch1", "closed", 1.0)),
            _ => {}
        }
        if t >= 189.0 {
            modes.push(("switch2", "closed", 1.0));
        }
        modes
    }
    let run = Run::new(400, script);
    let mut expected = NOMINAL_START.to_vec();
    expected.extend([
        "188 failed stay-warm.heater1",
        "188 response stay-warm.heater1 failed: switch1 = stuck-open (p 0.97) → fail up → \
         stay-warm re-elaborated with tactic 2 → promoted",
        "188 chosen stay-warm 2",
        "188 promoted",
        "189 fired stay-warm#2.TP_A",
        "376 fired TP_E",
    ]);
    assert_eq!(run.story(), expected);
    let response = run.events.iter().find_map(|(_, e)| match e {
        MissionEvent::ResponseTaken { response, .. } => Some(*response),
        _ => None,
    });
    assert_eq!(response, Some(Some(Response::FailUp)));
    // Conditional elaboration: TP_S has fired, so tactic 2 adds no GetWarm and its TP_A is
    // anchored after the failure, not 60 s before TP_S. The second elaboration's items are
    // named by it: `stay-warm#2.…`.
    let network = run.controller.network();
    assert_eq!(network.goal_named("stay-warm#2.get-warm"), None);
    assert!(network.goal_named("stay-warm#2.heater2").is_some());
    assert_eq!(run.fired("stay-warm#2.TP_A"), Some(189.0));
}

/// System test 8 (switch 2 sticks closed during the maintain interval): the same with the
/// roles swapped — heater 2's goal fails up, StayWarm takes tactic 2 (heater 2 on, which a
/// switch stuck closed gives), no safing.
#[test]
fn test_8_switch_2_sticks_closed_reelaborates_with_tactic_2() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = vec![temperature(t)];
        match t {
            t if t >= 189.0 => modes.push(("switch1", "open", 1.0)),
            t if t >= 11.0 => modes.push(("switch1", "closed", 1.0)),
            _ => {}
        }
        if t >= 188.0 {
            modes.push(("switch2", "stuck-closed", 0.97));
        }
        modes
    }
    let run = Run::new(400, script);
    let mut expected = NOMINAL_START.to_vec();
    expected.extend([
        "188 failed stay-warm.heater2",
        "188 response stay-warm.heater2 failed: switch2 = stuck-closed (p 0.97) → fail up → \
         stay-warm re-elaborated with tactic 2 → promoted",
        "188 chosen stay-warm 2",
        "188 promoted",
        "189 fired stay-warm#2.TP_A",
        "376 fired TP_E",
    ]);
    assert_eq!(run.story(), expected);
}

/// System test 9 (the sensor fails during execution): the Sensor goal fails up, StayWarm has
/// no tactic left (both need the sensor healthy, which a failed sensor cannot become), it is a
/// root: safing, once; the network's last point never fires (checked to 500 s) and nothing is
/// commanded after safing (the configuration goal is empty).
#[test]
fn test_9_sensor_failure_leaves_no_tactic_and_safes_once() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = nominal(t);
        if t >= 188.0 {
            modes.push(("sensor", "failed", 1.0));
        }
        modes
    }
    let run = Run::new(500, script);
    let story = run.story();
    let mut expected = NOMINAL_START.to_vec();
    expected.extend([
        "188 failed stay-warm.sensor",
        "188 rejected stay-warm 2",
        "188 rejected stay-warm 1",
        "188 promotion failed",
        "188 safing",
    ]);
    // The response's line carries the chain; checked apart below.
    let without_response: Vec<&String> =
        story.iter().filter(|l| !l.contains(" response ")).collect();
    assert_eq!(without_response, expected.iter().collect::<Vec<_>>());
    let response = story
        .iter()
        .find(|l| l.contains(" response "))
        .expect("a response");
    assert!(
        response.starts_with("188 response stay-warm.sensor failed: sensor = failed (p 1.00) → fail up → stay-warm: no tactic left (")
            && response.ends_with(") → stay-warm is a root → safing"),
        "{response}"
    );
    assert_eq!(run.fired("TP_E"), None);
    assert_eq!(run.fired("TP_bgE"), None);
    assert!(run.controller.is_safed());
    assert!(
        run.goals_after_safing.iter().all(|g| g == "true"),
        "{:?}",
        run.goals_after_safing
    );
    let failures_after = run.events.iter().filter(|(t, e)| {
        *t > 188.0 && matches!(e, MissionEvent::Goal(GoalEvent::GoalFailed { .. }))
    });
    assert_eq!(failures_after.count(), 0);
}

/// The other responses (mds-goal-networks.md §2.6–2.8; `tests/missions/responses.ron`):
/// `Ignore` lets the plan run; a re-elaboration within budget promotes; past its budget the
/// goal has no response left and, a root, goes to safing; the custom safe network is promoted
/// from a point fired at the safing time, and its goal drives the configuration from then on.
#[test]
fn ignore_budget_and_a_custom_safe_network() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let switch1 = match t {
            t if t >= 10.0 => "stuck-open",
            t if t >= 5.0 => "closed",
            _ => "open",
        };
        let switch2 = if (3.0..5.0).contains(&t) {
            "closed"
        } else {
            "open"
        };
        vec![("switch1", switch1, 1.0), ("switch2", switch2, 1.0)]
    }
    let run = Run::of("tests/missions/responses.ron", 0, 20, script);
    assert_eq!(
        run.story(),
        [
            "0 chosen hold 1",
            "0 promoted",
            "3 failed watch",
            "3 response watch failed: switch2 = closed (p 1.00) → ignored",
            "5 failed hold.keep",
            "5 response hold.keep failed: switch1 = closed (p 1.00) → fail up → hold re-elaborated \
             with tactic 2 → promoted",
            "5 chosen hold 2",
            "5 promoted",
            "10 failed hold#2.keep",
            "10 response hold#2.keep failed: switch1 = stuck-open (p 1.00) → fail up → hold: no \
             tactic left (its re-elaboration budget of 1 is spent) → hold is a root → safing",
            "10 safing",
        ]
    );
    assert!(run.controller.is_safed());
    assert_eq!(run.fired("TP_E"), None);
    assert_eq!(run.fired("safing"), Some(10.0));
    assert!(
        run.goals_after_safing.iter().all(|g| g == "switch2 = open"),
        "{:?}",
        run.goals_after_safing
    );
}

/// Safing is promotable at any time, from any state (mds-goal-networks.md §2.8), best effort
/// (DESIGN.md §15.2): invoked with switch 2 stuck closed, the custom safe network's goal (switch
/// 2 open) cannot be scheduled, so it is dropped — reported with the scheduler's reason — and
/// the rest of the safe network (its end point) runs; nothing is commanded.
#[test]
fn safing_drops_the_safe_goals_it_cannot_schedule() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let switch2 = if t >= 2.0 { "stuck-closed" } else { "open" };
        vec![("switch2", switch2, 1.0)]
    }
    let mut run = Run::of("tests/missions/responses.ron", 0, 1, script);
    let (modes, beliefs) = estimate(&run.plant, &script(2.0));
    let view = EstimateView {
        modes: &modes,
        beliefs: &beliefs,
    };
    let cause = "an operator's command".to_string();
    let events = run
        .controller
        .invoke_safing(2.0, view, &run.reconfiguration, cause);
    let [
        MissionEvent::Safing { cause },
        MissionEvent::SafeGoalDropped { goal, reason },
    ] = events.as_slice()
    else {
        panic!("{events:?}");
    };
    assert_eq!(cause, "an operator's command");
    assert_eq!(goal, "rest");
    assert!(
        reason.starts_with("unachievable: [safing, rest-end] Maintain switch2 ∈ {open}: rest")
            && reason
                .ends_with("from switch2 {stuck-closed} cannot be reached by mode reconfiguration"),
        "{reason}"
    );
    run.cycle(2.0, script);
    assert_eq!(run.goals_after_safing, ["true"]);
    assert_eq!(run.fired("safing"), Some(2.0));
    run.cycle(102.0, script);
    assert_eq!(run.fired("rest-end"), Some(102.0));
}

/// All failures of a cycle are gathered before responding (mds-goal-networks.md §2.5 step 4):
/// switch 1 sticking open and the sensor failing at once both fail up to StayWarm, which is
/// re-elaborated once for both (each tactic rejected once), and safing follows once.
#[test]
fn two_failures_reaching_one_goal_re_elaborate_it_once() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = vec![temperature(t)];
        match t {
            t if t >= 188.0 => {
                modes.extend([("switch1", "stuck-open", 1.0), ("sensor", "failed", 1.0)])
            }
            t if t >= 11.0 => modes.push(("switch1", "closed", 1.0)),
            _ => {}
        }
        modes
    }
    let run = Run::new(200, script);
    let at_188: Vec<String> = run
        .story()
        .into_iter()
        .filter(|l| l.starts_with("188 "))
        .map(|l| l.split(": ").next().unwrap_or_default().to_string())
        .collect();
    assert_eq!(
        at_188,
        [
            "188 failed stay-warm.heater1",
            "188 failed stay-warm.sensor",
            "188 response stay-warm.heater1 failed",
            "188 response stay-warm.sensor failed",
            "188 rejected stay-warm 2",
            "188 rejected stay-warm 1",
            "188 promotion failed",
            "188 safing",
        ]
    );
}

/// Safing wins (§2.5 step 4): switch 1 sticks open but is believed so with p 0.6 only, below
/// the knowledge threshold — the heater goal's failure would re-elaborate StayWarm, KnowAll's
/// knowledge goal on switch 1 fails up to a root: no tactic is tried, safing at once.
#[test]
fn safing_wins_over_re_elaboration_in_the_same_cycle() {
    fn script(t: f64) -> Vec<(&'static str, &'static str, f64)> {
        let mut modes = vec![temperature(t)];
        match t {
            t if t >= 188.0 => modes.push(("switch1", "stuck-open", 0.6)),
            t if t >= 11.0 => modes.push(("switch1", "closed", 1.0)),
            _ => {}
        }
        modes
    }
    let run = Run::new(200, script);
    let at_188: Vec<String> = run
        .story()
        .into_iter()
        .filter(|l| l.starts_with("188 "))
        .collect();
    assert_eq!(
        at_188,
        [
            "188 failed know-all.switch1",
            "188 failed stay-warm.heater1",
            "188 response know-all.switch1 failed: switch1 = stuck-open (p 0.60) → fail up → \
             know-all is a root → safing",
            "188 response stay-warm.heater1 failed: switch1 = stuck-open (p 0.60) → fail up → \
             safing (another failure of this cycle)",
            "188 safing",
        ]
    );
}
