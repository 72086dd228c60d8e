//! Execution and monitoring of a scheduled network (mds-goal-networks.md §2.4–2.5;
//! DESIGN.md §15.3), driven by scripted estimates of the thermostat for system test 4's network
//! (`missions/thermostat_stay_warm.ron`): when each point fires, the configuration goal, a
//! maintain failure narrowed to its constituent, a forced point failing a transition goal; and
//! a point ending a transition that nothing follows (`tests/missions/close_switch1.ron`), forced
//! at its last cycle inside its window, contradicted when no cycle falls in it, stalled when it
//! has no latest time and waits for a goal that failed; a goal that recovers and fails again
//! (DESIGN.md §15.2).

use std::path::Path;

use kairos::diagnostic::Source;
use kairos::goalnet::{
    EstimateView, Execution, FailureReason, GoalEvent, Waiting, mission, schedule,
};
use kairos::logic::{Formula, ValueId};
use kairos::plant::Plant;
use kairos::reconfiguration::Reconfiguration;

struct Harness {
    mission: mission::Mission,
    reconfiguration: Reconfiguration,
    execution: Execution,
    events: Vec<(f64, GoalEvent)>,
}

/// The thermostat's state at a time, as a script: `(component, mode)` pairs over the default
/// (cold, open, open, healthy); every belief certain.
fn estimate(plant: &Plant, modes: &[(&str, &str)]) -> (Vec<ValueId>, Vec<Vec<f64>>) {
    let mut values = vec![ValueId(0); plant.components().len()];
    for (component, mode) in modes {
        let c = plant.component_named(component).expect("a component");
        values[c.index()] = plant.component(c).mode_named(mode).expect("a mode");
    }
    let beliefs = plant
        .components()
        .iter()
        .zip(&values)
        .map(|(c, v)| {
            (0..c.modes().len())
                .map(|i| if i == v.index() { 1.0 } else { 0.0 })
                .collect()
        })
        .collect();
    (values, beliefs)
}

impl Harness {
    fn new() -> Self {
        Self::of("missions/thermostat_stay_warm.ron")
    }

    fn of(path: &str) -> Self {
        std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
        Self::with(mission::load(Path::new(path)).expect("loads"))
    }

    /// `close_switch1.ron` with its two constraints replaced by these.
    fn closing_switch1(constraints: &str) -> Self {
        std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
        let text = std::fs::read_to_string("tests/missions/close_switch1.ron").expect("reads");
        let written = r#"Constraint(from: "origin", to: "TP_H", min: 10.0, max: 10.0),
            Constraint(from: "TP_H", to: "TP_A", min: 0.0, max: 5.0),"#;
        assert!(text.contains(written));
        let source = Source::new("close_switch1.ron", text.replace(written, constraints));
        Self::with(mission::load_source(&source, Path::new("tests/missions")).expect("loads"))
    }

    fn with(mission: mission::Mission) -> Self {
        let reconfiguration = Reconfiguration::compile(&mission.plant).expect("compiles");
        let current = vec![ValueId(0); mission.plant.components().len()];
        let executable = schedule(&mission.network, &reconfiguration, &current).expect("schedules");
        let execution = Execution::new(executable, mission.knowledge_threshold);
        Harness {
            mission,
            reconfiguration,
            execution,
            events: Vec::new(),
        }
    }

    /// Runs 1 s cycles from `from` to `to` with the modes `script(t)` gives.
    fn run(
        &mut self,
        from: u32,
        to: u32,
        script: impl Fn(f64) -> Vec<(&'static str, &'static str)>,
    ) {
        for t in from..=to {
            let now = f64::from(t);
            let (modes, beliefs) = estimate(&self.mission.plant, &script(now));
            let view = EstimateView {
                modes: &modes,
                beliefs: &beliefs,
            };
            for event in self.execution.step(now, view, &self.reconfiguration) {
                self.events.push((now, event));
            }
        }
    }

    fn fired(&self, name: &str) -> Option<f64> {
        let point = self
            .execution
            .executable()
            .network
            .point_named(name)
            .expect("a point");
        self.execution.fired_at(point)
    }

    fn goal_failures(&self) -> Vec<(f64, String, FailureReason)> {
        self.events
            .iter()
            .filter_map(|(t, e)| match e {
                GoalEvent::GoalFailed { goal, reason } => Some((
                    *t,
                    self.execution.executable().network.goal(*goal).name.clone(),
                    reason.clone(),
                )),
                _ => None,
            })
            .collect()
    }

    fn recoveries(&self) -> Vec<(f64, String)> {
        self.events
            .iter()
            .filter_map(|(t, e)| match e {
                GoalEvent::GoalRecovered { goal } => Some((
                    *t,
                    self.execution.executable().network.goal(*goal).name.clone(),
                )),
                _ => None,
            })
            .collect()
    }

    fn forced(&self) -> usize {
        self.events
            .iter()
            .filter(|(_, e)| matches!(e, GoalEvent::TimePointForced { .. }))
            .count()
    }
}

/// The nominal thermostat under tactic 1, as the model and script play it
/// (scenarios/thermostat/README.md, test 4): switch 1 closed from 11 s, warming from 12 s,
/// warm-low from 76 s, warm from 148 s.
fn nominal(t: f64) -> Vec<(&'static str, &'static str)> {
    let mut modes = Vec::new();
    if t >= 11.0 {
        modes.push(("switch1", "closed"));
    }
    let temperature = match t {
        t if t >= 148.0 => "warm",
        t if t >= 76.0 => "warm-low",
        t if t >= 12.0 => "warming",
        _ => "cold",
    };
    modes.push(("temperature", temperature));
    modes
}

/// System test 4's verdicts on the network (mds-goal-networks.md §3.3): TP_H at 10, TP_A once
/// switch 1 is closed (11), TP_S once warm (76, inside [71, 161]), TP_E 300 s later (376);
/// nothing forced, no failure.
#[test]
fn stay_warm_fires_each_point_when_ready() {
    let mut h = Harness::new();
    h.run(0, 400, nominal);
    assert_eq!(h.fired("TP_H"), Some(10.0));
    assert_eq!(h.fired("TP_A"), Some(11.0));
    assert_eq!(h.fired("TP_S"), Some(76.0));
    assert_eq!(h.fired("TP_E"), Some(376.0));
    assert_eq!(h.fired("TP_bgE"), None);
    assert_eq!(h.forced(), 0);
    assert_eq!(h.goal_failures(), []);
}

/// The configuration goal is the active control XGoals on controllable SVs (§15.3): at 10 s,
/// switch 1 closed and switch 2 open; knowledge never becomes a goal.
#[test]
fn the_configuration_goal_is_the_active_control_constraints() {
    let mut h = Harness::new();
    h.run(0, 9, nominal);
    let plant = h.mission.plant.clone();
    let switches =
        move |c: kairos::plant::ComponentId| plant.component(c).name().starts_with("switch");
    assert_eq!(
        h.execution
            .configuration_goal(&h.reconfiguration, &switches),
        Formula::True
    );
    h.run(10, 10, nominal);
    let goal = h
        .execution
        .configuration_goal(&h.reconfiguration, &switches);
    let shown = goal.display(h.mission.plant.table()).to_string();
    assert!(
        shown.contains("switch1 = closed") && shown.contains("switch2 = open"),
        "{shown}"
    );
    assert!(!shown.contains("temperature"), "{shown}");
}

/// A maintain failure (switch 1 sticks open at 187 s, as ME diagnoses it in the model's
/// `switch1_sticks_open` scenario): the heater goal fails, narrowed from its XGoal, once; the
/// temperature goal does not fail while the device is still warm.
#[test]
fn a_maintain_excursion_fails_the_constituent_goal_once() {
    let mut h = Harness::new();
    h.run(0, 200, |t| {
        let mut modes = nominal(t);
        if t >= 187.0 {
            modes.retain(|(c, _)| *c != "switch1");
            modes.push(("switch1", "stuck-open"));
        }
        modes
    });
    let stuck = h
        .mission
        .plant
        .component(h.mission.plant.component_named("switch1").unwrap())
        .mode_named("stuck-open")
        .unwrap();
    assert_eq!(
        h.goal_failures(),
        [(
            187.0,
            "heater1".to_string(),
            FailureReason::Excursion(stuck)
        )]
    );
}

/// A device that never warms: TP_S is forced at its latest time (TP_A + 150 = 161 s) and the
/// GetWarm transition goal fails there.
#[test]
fn a_forced_end_point_fails_the_unreached_transition() {
    let mut h = Harness::new();
    h.run(0, 170, |t| {
        nominal(t)
            .into_iter()
            .map(|(c, m)| {
                if c == "temperature" {
                    (c, if t >= 12.0 { "warming" } else { "cold" })
                } else {
                    (c, m)
                }
            })
            .collect()
    });
    assert_eq!(h.fired("TP_S"), Some(161.0));
    assert_eq!(h.forced(), 1);
    let failures = h.goal_failures();
    assert!(
        failures.iter().any(|(t, g, r)| *t == 161.0
            && g == "get-warm"
            && matches!(r, FailureReason::EndForced(_))),
        "{failures:?}"
    );
}

/// A point that ends a Transition goal is ready only once the transition is complete (§2.4 (a),
/// `is_ready_to_transition(incoming, …)`): TP_A waits within [10, 15] s for switch 1 and fires
/// the cycle it is believed closed, though no goal starting there asks for it.
#[test]
fn a_transition_end_waits_for_its_set() {
    let mut h = Harness::of("tests/missions/close_switch1.ron");
    h.run(0, 20, |t| {
        if t >= 13.0 {
            vec![("switch1", "closed")]
        } else {
            vec![]
        }
    });
    assert_eq!(h.fired("TP_H"), Some(10.0));
    assert_eq!(h.fired("TP_A"), Some(13.0));
    assert_eq!(h.forced(), 0);
    assert_eq!(h.goal_failures(), []);
}

/// The same transition never completed (switch 1 stays open, still reachable, so monitoring
/// does not fail it): TP_A is forced at its latest time and the goal fails there — before
/// readiness looked at incoming transitions, TP_A fired on time at 10 s and the unreached goal
/// passed unnoticed.
#[test]
fn a_transition_end_never_reached_is_forced_and_fails() {
    let mut h = Harness::of("tests/missions/close_switch1.ron");
    h.run(0, 20, |_| vec![]);
    assert_eq!(h.fired("TP_A"), Some(15.0));
    assert_eq!(h.forced(), 1);
    let failures = h.goal_failures();
    assert!(
        matches!(
            failures.as_slice(),
            [(15.0, goal, FailureReason::EndForced(_))] if goal == "close-switch1"
        ),
        "{failures:?}"
    );
}

/// A point whose latest time falls between two cycles is forced at the last cycle inside its
/// window — the next would be past it — and its grounding is consistent (DESIGN.md §15.2: no
/// point fires outside its window): TP_A ≤ TP_H + 4.5 s = 14.5 s, not ready, fires at 14 s,
/// 0.5 s before its latest time.
#[test]
fn a_point_is_forced_at_its_last_cycle_inside_its_window() {
    let mut h = Harness::closing_switch1(
        r#"Constraint(from: "origin", to: "TP_H", min: 10.0, max: 10.0),
           Constraint(from: "TP_H", to: "TP_A", min: 0.0, max: 4.5),"#,
    );
    h.run(0, 20, |_| vec![]);
    assert_eq!(h.fired("TP_A"), Some(14.0));
    let forced: Vec<f64> = (h.events.iter())
        .filter_map(|(_, e)| match e {
            GoalEvent::TimePointForced { late_by, .. } => Some(*late_by),
            _ => None,
        })
        .collect();
    assert_eq!(forced, [-0.5]);
    assert!(
        !h.events
            .iter()
            .any(|(_, e)| matches!(e, GoalEvent::TemporalInconsistency { .. }))
    );
    assert!(h.execution.executable().network.stn().is_propagated());
}

/// A window that holds no cycle's time: TP_H ∈ [10.2, 10.7] s fires at 11 s, the first cycle
/// after it. The firing stays, the constraint it contradicts is withdrawn — the network keeps
/// its windows and TP_A fires on — and the goal TP_H bounds fails (DESIGN.md §15.2: a firing
/// that contradicts the network is a failure of the goals it bounds).
#[test]
fn a_firing_the_network_contradicts_withdraws_the_constraint_and_fails_its_goals() {
    let mut h = Harness::closing_switch1(
        r#"Constraint(from: "origin", to: "TP_H", min: 10.2, max: 10.7),
           Constraint(from: "TP_H", to: "TP_A", min: 0.0, max: 5.0),"#,
    );
    h.run(0, 20, |t| {
        if t >= 13.0 {
            vec![("switch1", "closed")]
        } else {
            vec![]
        }
    });
    assert_eq!(h.fired("TP_H"), Some(11.0));
    let contradicted = h.events.iter().find_map(|(t, e)| match e {
        GoalEvent::TemporalInconsistency { cycle, .. } => Some((*t, cycle.len())),
        _ => None,
    });
    assert_eq!(
        contradicted,
        Some((11.0, 2)),
        "the written window and the firing"
    );
    let stn = h.execution.executable().network.stn();
    assert!(stn.is_propagated(), "consistent again");
    assert_eq!(h.fired("TP_A"), Some(13.0), "the rest fires on");
    let failures = h.goal_failures();
    assert!(
        matches!(
            failures.as_slice(),
            [(11.0, goal, FailureReason::Contradicted { .. })] if goal == "close-switch1"
        ),
        "{failures:?}"
    );
}

/// A point with no latest time that waits for a goal that has failed will never fire: the
/// network says so, once (DESIGN.md §15.2: a network that stops firing with time left says
/// why). Switch 1 sticks open at 12 s, so `close-switch1` can no longer be reached and fails;
/// TP_A, after TP_H with no bound, waits for it for ever.
#[test]
fn a_network_waiting_for_a_failed_goal_says_it_has_stalled() {
    let mut h = Harness::closing_switch1(
        r#"Constraint(from: "origin", to: "TP_H", min: 10.0, max: 10.0),
           Constraint(from: "TP_H", to: "TP_A", min: 0.0),"#,
    );
    h.run(0, 30, |t| {
        if t >= 12.0 {
            vec![("switch1", "stuck-open")]
        } else {
            vec![]
        }
    });
    let stalls: Vec<(f64, Vec<(String, Waiting)>)> = (h.events.iter())
        .filter_map(|(t, e)| match e {
            GoalEvent::NetworkStalled { stalled } => Some((
                *t,
                (stalled.iter())
                    .map(|(p, w)| {
                        (
                            h.execution.executable().network.point(*p).name.clone(),
                            w.clone(),
                        )
                    })
                    .collect(),
            )),
            _ => None,
        })
        .collect();
    let goal = h
        .execution
        .executable()
        .network
        .goal_named("close-switch1")
        .expect("a goal");
    assert_eq!(
        stalls,
        [(12.0, vec![("TP_A".to_string(), Waiting::Goal(goal))])]
    );
    assert_eq!(h.fired("TP_A"), None);
}

/// A goal that fails and holds again is reported recovered and monitored again: a second
/// excursion fails it again (DESIGN.md §15.2). Switch 1 is believed open from 187 s to 189 s,
/// closed again, then open from 195 s: `heater1` fails at 187, recovers at 190, fails at 195.
#[test]
fn a_goal_that_holds_again_recovers_and_fails_again() {
    let mut h = Harness::new();
    h.run(0, 200, |t| {
        let mut modes = nominal(t);
        if (187.0..190.0).contains(&t) || t >= 195.0 {
            modes.retain(|(c, _)| *c != "switch1");
            modes.push(("switch1", "open"));
        }
        modes
    });
    let failures: Vec<(f64, String)> = (h.goal_failures().into_iter())
        .map(|(t, g, _)| (t, g))
        .collect();
    assert_eq!(
        failures,
        [
            (187.0, "heater1".to_string()),
            (195.0, "heater1".to_string())
        ]
    );
    assert_eq!(h.recoveries(), [(190.0, "heater1".to_string())]);
}
