//! The Maude rover (mds-goal-networks.md §4.2, seed 001 ¶6–¶13): scenarios
//! R1–R7 checked on every interleaving of the controller protocol's messages, controllers that
//! break the protocol caught with their shortest counterexamples, `kairos explore` on a rover
//! scenario, and the scenario file's located errors (DESIGN.md §13).

#[path = "support/bad_files.rs"]
#[macro_use]
mod bad_files;
#[path = "support/cli.rs"]
mod cli;

use std::path::Path;

use kairos::exploration::Budget;
use kairos::exploration::protocol::{Property, ProtocolExploration, explore};
use kairos::protocol::messages::{ConstraintId, Message, Outcome, Reason};
use kairos::protocol::posandhead::{Command, Constraint, StateValue, coa, satisfy};
use kairos::protocol::scenario::{self, RoverScenario};
use kairos::protocol::{CoaController, Controller};

fn rover(file: &str) -> RoverScenario {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(file);
    scenario::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn explore_with<C: Controller>(file: &str, make: impl Fn(StateValue) -> C) -> ProtocolExploration {
    let scenario = rover(file);
    explore(
        &scenario,
        make(scenario.initial_value()),
        Budget::Unbounded,
        u64::MAX,
    )
}

/// Explores `scenarios/rover/<r>.ron` with the seed's controller and asserts that every
/// property holds on every interleaving, with these numbers of configurations, terminal
/// configurations and interleavings.
fn holds(r: &str, states: u64, terminals: u64, paths: u128) {
    let explored = explore_with(&format!("scenarios/rover/{r}.ron"), CoaController::new);
    assert!(explored.holds(), "{r}: {:#?}", explored.counterexamples);
    assert_eq!(
        (explored.states, explored.terminals, explored.paths),
        (states, terminals, Some(paths)),
        "{r}"
    );
}

/// §4.2 R1: turn(E), drive ×3, turn(N), drive ×2, success after the 7th newval at (3, 2, N).
/// One chain of messages: the constraint, six hops per command, the endcstr — 44 steps.
#[test]
fn r1_reaches_3_2_with_seven_commands() {
    holds("r1", 45, 1, 1);
}

/// §4.2 R2: already satisfied — C-new's first branch, no command.
#[test]
fn r2_an_already_satisfied_constraint_ends_at_once() {
    holds("r2", 3, 1, 1);
}

/// §4.2 R3: the obstacle at (2, 0) blocks the second and third drives; the fixed course of
/// action runs out at (1, 0) and ends with coanosuccess (P-fail), after exactly 3 commands.
#[test]
fn r3_an_obstacle_ends_the_course_of_action_with_coanosuccess() {
    holds("r3", 21, 1, 1);
}

/// §4.2 R4: a diagonal heading makes the x-phase turn first.
#[test]
fn r4_a_diagonal_heading_turns_before_driving() {
    holds("r4", 21, 1, 1);
}

/// §4.2 R5: c2 arrives at any point of c1's processing, waits (FIFO) and then runs from (2, 0):
/// both succeed on every one of the interleavings, one constraint at a time. The two terminal
/// configurations differ only in the order the state variable received the two endcstrs (c1's
/// may be delivered after c2's). The one configuration where c1 ended before c2 was sent is
/// outside the scenario.
#[test]
fn r5_a_second_constraint_waits_for_the_first_on_every_interleaving() {
    holds("r5", 99, 2, 3798);
    let explored = explore_with("scenarios/rover/r5.ron", CoaController::new);
    assert_eq!(explored.excluded, 1);
}

/// §4.2 R6 and §5 C12: from `uk` there is no first command: coanosuccess at once.
#[test]
fn r6_an_unknown_value_fails_at_once_with_no_command() {
    holds("r6", 3, 1, 1);
}

/// §4.2 R7: nocstr is satisfied at once.
#[test]
fn r7_nocstr_succeeds_at_once() {
    holds("r7", 3, 1, 1);
}

/// Processes every constraint the moment it arrives, each with its own course of action — the
/// deliberately broken controller the explorer must catch (no `waitafter` check, no queue).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct TwoAtOnce {
    value: StateValue,
    active: Vec<(ConstraintId, Constraint, Vec<Command>)>,
}

impl Controller for TwoAtOnce {
    fn on_constraint(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        let mut plan = coa(&self.value, &constraint);
        if satisfy(&self.value, &constraint) || plan.is_empty() {
            let outcome = match satisfy(&self.value, &constraint) {
                true => Outcome::Success,
                false => Outcome::Failure(Reason::CoaNoSuccess),
            };
            return vec![Message::EndCstr { id, outcome }];
        }
        let command = plan.remove(0);
        self.active.push((id, constraint, plan));
        vec![Message::Command { id, command }]
    }

    fn on_newval(&mut self, value: StateValue) -> Vec<Message> {
        self.value = value;
        let mut out = Vec::new();
        self.active.retain_mut(|(id, constraint, rest)| {
            let outcome = if satisfy(&value, constraint) {
                Outcome::Success
            } else if rest.is_empty() {
                Outcome::Failure(Reason::CoaNoSuccess)
            } else {
                let command = rest.remove(0);
                out.push(Message::Command { id: *id, command });
                return true;
            };
            out.push(Message::EndCstr { id: *id, outcome });
            false
        });
        out
    }

    fn processing(&self) -> Vec<ConstraintId> {
        self.active.iter().map(|(id, _, _)| *id).collect()
    }
}

/// §4.2 P-excl, the explorer's acceptance: a controller that processes two constraints at once is
/// caught on R5, with the shortest trace — c1 starts, the environment sends c2 while c1 is
/// processed, c2 is delivered and started too (planned from where c1 has not moved the rover
/// yet).
#[test]
fn p_excl_catches_a_controller_that_processes_two_constraints_at_once() {
    let explored = explore_with("scenarios/rover/r5.ron", |value| TwoAtOnce {
        value,
        active: Vec::new(),
    });
    let excl: Vec<_> = (explored.counterexamples.iter())
        .filter(|c| c.property == Property::Excl)
        .collect();
    assert_eq!(excl.len(), 1, "{:#?}", explored.counterexamples);
    let counterexample = excl[0];
    assert_eq!(
        counterexample.reason,
        "the controller processes `c1` and `c2` at once"
    );
    assert_eq!(counterexample.trace.len(), 3, "{:#?}", counterexample.trace);
    assert!(counterexample.trace[0].contains("environment → controller: constraint `c1`"));
    assert!(counterexample.trace[1].contains("environment sends `c2`"));
    assert!(
        counterexample.trace[2].contains("constraint `c2`")
            && counterexample.trace[2].ends_with("controller → actuator: turn(E) (for `c2`)"),
        "{}",
        counterexample.trace[2]
    );
}

/// Replans from every new value, as a reactive planner would (mds-goal-networks.md §4.2 "Fit
/// with kairos"): not the seed's fixed course of action.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Replanner {
    value: StateValue,
    active: Option<(ConstraintId, Constraint)>,
}

impl Replanner {
    fn next(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        let outcome = match coa(&self.value, &constraint).first() {
            _ if satisfy(&self.value, &constraint) => Outcome::Success,
            Some(&command) => {
                self.active = Some((id, constraint));
                return vec![Message::Command { id, command }];
            }
            None => Outcome::Failure(Reason::CoaNoSuccess),
        };
        self.active = None;
        vec![Message::EndCstr { id, outcome }]
    }
}

impl Controller for Replanner {
    fn on_constraint(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        self.next(id, constraint)
    }

    fn on_newval(&mut self, value: StateValue) -> Vec<Message> {
        self.value = value;
        match self.active {
            Some((id, constraint)) => self.next(id, constraint),
            None => Vec::new(),
        }
    }

    fn processing(&self) -> Vec<ConstraintId> {
        self.active.iter().map(|(id, _)| *id).collect()
    }
}

/// §4.2 P-cmds and P-term's "no divergence": against R3's obstacle a replanning controller
/// drives forever. P-cmds stops it at its fourth drive — not a prefix of coa((0, 0, E), c) =
/// drive ×3 — so the search ends although the controller never would.
#[test]
fn p_cmds_stops_a_controller_that_would_drive_into_the_obstacle_forever() {
    let explored = explore_with("scenarios/rover/r3.ron", |value| Replanner {
        value,
        active: None,
    });
    assert!(!explored.cut);
    assert_eq!(explored.counterexamples.len(), 1);
    let counterexample = &explored.counterexamples[0];
    assert_eq!(counterexample.property, Property::Cmds);
    assert_eq!(
        counterexample.reason,
        "the commands issued for `c1`, [drive, drive, drive, drive], are not a prefix of \
         coa((0, 0, E), (x=3, y=0)) = [drive, drive, drive]"
    );
    assert_eq!((explored.stopped, explored.terminals), (1, 0));
}

/// Forgets to answer: the seed's controller with every endcstr dropped.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
struct Mute(CoaController);

impl Controller for Mute {
    fn on_constraint(&mut self, id: ConstraintId, constraint: Constraint) -> Vec<Message> {
        let out = self.0.on_constraint(id, constraint);
        out.into_iter()
            .filter(|m| !matches!(m, Message::EndCstr { .. }))
            .collect()
    }

    fn on_newval(&mut self, value: StateValue) -> Vec<Message> {
        let out = self.0.on_newval(value);
        out.into_iter()
            .filter(|m| !matches!(m, Message::EndCstr { .. }))
            .collect()
    }

    fn processing(&self) -> Vec<ConstraintId> {
        self.0.processing()
    }
}

/// §4.2 P-term: a controller that never answers leaves the state variable waiting — a
/// deadlock, shown at its one-step trace on R2.
#[test]
fn p_term_catches_a_controller_that_never_answers() {
    let explored = explore_with("scenarios/rover/r2.ron", |v| Mute(CoaController::new(v)));
    assert_eq!(explored.counterexamples.len(), 1);
    let counterexample = &explored.counterexamples[0];
    assert_eq!(counterexample.property, Property::Term);
    assert_eq!(
        counterexample.reason,
        "deadlock: nothing can happen and no endcstr for `c1`"
    );
    assert_eq!(counterexample.trace.len(), 1);
}

/// §4.2 P-succ/P-fail: a scenario expecting the wrong outcome is refuted at the endcstr that
/// shows it (R3's obstacle, expecting success).
#[test]
fn p_succ_refutes_a_wrong_expectation_at_the_endcstr() {
    let explored = explore_with(
        "tests/scenarios/rover_blocked_expects_success.ron",
        CoaController::new,
    );
    assert_eq!(explored.counterexamples.len(), 1);
    let counterexample = &explored.counterexamples[0];
    assert_eq!(counterexample.property, Property::SuccFail);
    assert_eq!(
        counterexample.reason,
        "`c1` ends with coanosuccess, expected success"
    );
    assert_eq!(counterexample.trace.len(), 20);
}

/// A state budget stops the search cleanly and says so.
#[test]
fn a_state_budget_cuts_the_search_and_says_so() {
    let scenario = rover("scenarios/rover/r5.ron");
    let controller = CoaController::new(scenario.initial_value());
    let explored = explore(&scenario, controller, Budget::States(20), u64::MAX);
    assert!(explored.cut && !explored.holds());
    assert!(explored.states <= 21 + 2, "{}", explored.states);
}

/// `kairos explore` on a rover scenario: the summary in the style of the scripted explorer's,
/// exit 0; a violated property exits 1 with its trace; a bad file exits 2, located.
#[test]
fn kairos_explore_runs_a_rover_scenario() {
    let (code, stdout, stderr) = cli::kairos(&["explore", "scenarios/rover/r5.ron"]);
    assert_eq!(code, 0, "{stdout}{stderr}");
    assert!(stdout.contains("99 states, 152 steps; 2 terminal configurations, 3798 interleavings"));
    assert!(stdout.contains("covered: every interleaving"));
    assert!(stdout.contains("properties: 4 of 4 hold on every interleaving"));
    assert!(
        stdout.contains("P-excl: the controller never processes two constraints at once — holds")
    );
    let (code, _, stderr) = cli::kairos(&["explore", "tests/bad_rover/goal_off_grid.ron"]);
    assert_eq!(code, 2);
    assert!(stderr.contains("goal_off_grid.ron:5:53"), "{stderr}");
    let file = "tests/scenarios/rover_blocked_expects_success.ron";
    let (code, stdout, stderr) = cli::kairos(&["explore", file]);
    assert_eq!(code, 1, "{stdout}{stderr}");
    assert!(stdout.contains(
        "counterexample 1: P-succ/P-fail fails: `c1` ends with coanosuccess, expected success"
    ));
    assert!(stdout.contains(" 20. controller → state variable: endcstr `c1` coanosuccess"));
    assert!(stderr.contains("1 property violated"), "{stderr}");
    let (code, stdout, _) = cli::kairos(&["explore", "scenarios/rover/r5.ron", "--budget", "10"]);
    assert_eq!(code, 1);
    assert!(stdout.contains("covered: partly"), "{stdout}");
}

/// Each file in `tests/bad_rover/` says in its first comment what is wrong with it; its
/// snapshot shows the message as `kairos explore` prints it (DESIGN.md §13: file:line:column,
/// the offending text, what was expected).
macro_rules! bad_rover {
    ($($case:tt)+) => { bad_file!(scenario::load, "tests/bad_rover", $($case)+); };
}

bad_rover!(syntax_error, "syntax_error.ron:4:5");
bad_rover!(unknown_field, "unknown_field.ron:3:5", "obstacle");
bad_rover!(bad_heading, "bad_heading.ron:3:34");
bad_rover!(grid_zero, "grid_zero.ron:3:11", "a side from 1 to 1000");
bad_rover!(
    obstacle_off_grid,
    "obstacle_off_grid.ron:3:25",
    "(5, 1) is off the grid"
);
bad_rover!(
    rover_on_obstacle,
    "rover_on_obstacle.ron:4:12",
    "holds an obstacle"
);
bad_rover!(
    goal_off_grid,
    "goal_off_grid.ron:5:53",
    "y = 7 is off the grid"
);
bad_rover!(
    duplicate_constraint,
    "duplicate_constraint.ron:6:27",
    "already declared"
);
bad_rover!(
    while_processing_unknown,
    "while_processing_unknown.ron:6:91",
    "did you mean `drive-east`?"
);
bad_rover!(
    while_processing_later,
    "while_processing_later.ron:5:77",
    "not declared before this constraint"
);
bad_rover!(
    no_constraints,
    "no_constraints.ron:4:18",
    "nothing to explore"
);
