//! One focused test per RMPL combinator for its timing (thesis §5.1.3: what starts "in the
//! current instant" and what "in the next instant"), run through the compiler and the sequencer's
//! `Step_THCA` (Figure 5-3). Each test scripts the estimate ME reports at the end of every cycle and
//! reads back the configuration goal asserted in each cycle.

#[path = "support/rmpl.rs"]
mod rmpl_support;

use kairos::logic::VarTable;
use kairos::opsat::Theory;
use kairos::sequencer::{AssignmentOracle, Event, Sequencer, StateEstimate, TheoryOracle};
use rmpl_support::{Figure, compile_text, updated};

/// The variables the test programs use.
fn plant() -> VarTable {
    let mut table = VarTable::new();
    for (name, values) in [
        ("x", &["off", "on"][..]),
        ("y", &["off", "on"][..]),
        ("z", &["waiting", "done"][..]),
        ("c", &["no", "yes"][..]),
        ("stop", &["no", "yes"][..]),
        ("ok", &["no", "yes"][..]),
    ] {
        table.add_variable(name, values.iter().copied()).unwrap();
    }
    table
}

/// A program under test, one cycle per second.
struct Run {
    figure: Figure,
    sequencer: Sequencer,
    oracle: AssignmentOracle,
    estimate: StateEstimate,
    time: f64,
    events: Vec<String>,
}

impl Run {
    fn new(program: &str) -> Self {
        let thca = compile_text("test.rmpl", program, Some(&plant()));
        Run {
            oracle: AssignmentOracle::new(thca.table()),
            sequencer: Sequencer::new(thca.clone()),
            figure: Figure::new(thca),
            estimate: StateEstimate::new(),
            time: 0.0,
            events: Vec::new(),
        }
    }

    /// Runs one cycle whose new estimate ŝ(i+1) is the previous one with `changes`; returns the
    /// configuration goal g(i).
    fn cycle(&mut self, changes: &[(&str, &str)]) -> String {
        let table = self.figure.thca.table().clone();
        let next = updated(&table, &self.estimate, changes);
        let step = self
            .sequencer
            .step(self.time, &self.estimate, &next, &mut self.oracle)
            .unwrap();
        let described = step
            .start
            .events
            .iter()
            .chain(&step.end.events)
            .filter_map(|e| self.figure.describe(e));
        self.events
            .extend(described.map(|e| format!("t={}: {e}", self.time)));
        self.estimate = next;
        self.time += 1.0;
        step.start.goal.formula.display(&table).to_string()
    }

    /// The goals of successive cycles, each with its estimate changes.
    fn goals(&mut self, script: &[&[(&str, &str)]]) -> Vec<String> {
        script.iter().map(|changes| self.cycle(changes)).collect()
    }

    fn done(&self) -> bool {
        self.sequencer.is_complete()
    }
}

const NONE: &[(&str, &str)] = &[];

#[test]
fn a_goal_is_asserted_until_achieved() {
    // §5.1.3 "g": asserted in the instant its location is marked, for as long as it is not
    // entailed (Figure 5-3 step 7, closed-loop execution).
    let mut run = Run::new("P() :: { x = on }");
    let goals = run.goals(&[NONE, NONE, &[("x", "on")]]);
    assert_eq!(goals, ["x = on", "x = on", "x = on"]);
    assert!(run.done());
}

#[test]
fn sequence_starts_b_the_instant_after_a_finishes() {
    // §5.1.3 "A; B"; DESIGN.md §5.2.
    let mut run = Run::new("P() :: { x = on; y = on }");
    let goals = run.goals(&[NONE, &[("x", "on")], &[("y", "on")]]);
    assert_eq!(goals, ["x = on", "x = on", "y = on"]);
    assert!(run.done());
}

#[test]
fn parallel_starts_both_in_the_current_instant() {
    // §5.1.3 "A, B": "starting in the current instant"; completion waits for both.
    let mut run = Run::new("P() :: { {x = on, y = on}; z = done }");
    let goals = run.goals(&[&[("x", "on")], NONE, &[("y", "on")], NONE]);
    assert_eq!(goals, ["x = on and y = on", "y = on", "y = on", "z = done"]);
}

#[test]
fn if_starts_its_body_in_the_next_instant_or_the_thread_dies() {
    // §5.1.3 "if c thennext A": A starts in the next instant if ŝ entails c.
    let mut run = Run::new("P() :: { if (c = yes) thennext (x = on) }");
    assert_eq!(run.goals(&[&[("c", "yes")], NONE]), ["true", "x = on"]);

    let mut run = Run::new("P() :: { if (c = yes) thennext (x = on) }");
    assert_eq!(run.goals(&[&[("c", "no")]]), ["true"]);
    assert!(run.done(), "not entailed: the thread dies");

    // DESIGN.md §5.2: `A; B` after an `if` that died still starts B.
    let mut run = Run::new("P() :: { if (c = yes) thennext (x = on); y = on }");
    assert_eq!(run.goals(&[NONE, NONE]), ["true", "y = on"]);
}

#[test]
fn unless_with_an_unknown_state_proceeds() {
    // §5.1.3 "unless c thennext A": A starts in the next instant if c is *not* entailed, and an
    // unknown state entails neither c nor its negation (§5.1.1).
    let mut run = Run::new("P() :: { unless (c = yes) thennext (x = on) }");
    assert_eq!(run.goals(&[NONE, NONE]), ["true", "x = on"]);

    let mut run = Run::new("P() :: { unless (c = yes) thennext (x = on) }");
    assert_eq!(run.goals(&[&[("c", "yes")]]), ["true"]);
    assert!(run.done(), "entailed: the thread dies");

    // The same unknown state makes `if` die: non-entailment is not entailment of the negation.
    let mut run = Run::new("P() :: { if (c = no) thennext (x = on) }");
    assert_eq!(run.goals(&[NONE]), ["true"]);
    assert!(run.done());
}

#[test]
fn if_elsenext_takes_the_else_branch_when_not_entailed() {
    // §5.1.3 derived combinator: {if c thennext A, unless c thennext B}.
    let mut run = Run::new("P() :: { if (c = yes) thennext (x = on) elsenext (y = on) }");
    assert_eq!(run.goals(&[NONE, NONE]), ["true", "y = on"]);
    let mut run = Run::new("P() :: { if (c = yes) thennext (x = on) elsenext (y = on) }");
    assert_eq!(run.goals(&[&[("c", "yes")], NONE]), ["true", "x = on"]);
}

#[test]
fn when_waits_then_starts_its_body_in_the_next_instant() {
    // §5.1.3 "when c donext A": waits until c is entailed, then starts A in the next instant.
    let mut run = Run::new("P() :: { when (c = yes) donext (x = on) }");
    let goals = run.goals(&[NONE, NONE, &[("c", "yes")], &[("c", "no")], NONE]);
    assert_eq!(goals, ["true", "true", "true", "x = on", "x = on"]);
    assert!(!run.done());
}

#[test]
fn whenever_retriggers_every_instant_its_condition_holds() {
    // §5.1.3 "whenever c donext A": for every instant in which c holds, start A in the next.
    let mut run = Run::new("P() :: { whenever (c = yes) donext (x = on) }");
    let goals = run.goals(&[
        &[("c", "yes"), ("x", "on")],
        &[("c", "no")],
        NONE,
        &[("c", "yes")],
        &[("c", "no")],
    ]);
    assert_eq!(goals, ["true", "x = on", "true", "true", "x = on"]);
    assert!(!run.done(), "whenever never finishes");
}

#[test]
fn always_starts_its_body_now_and_every_instant() {
    // §5.1.3 "always A": starts A at each instant of time, the first included (§5.4: locations
    // 9 and 10 are both marked when composite 8 is entered).
    let mut run = Run::new("P() :: { always (x = on) }");
    let goals = run.goals(&[&[("x", "on")], NONE, NONE]);
    assert_eq!(goals, ["x = on", "x = on", "x = on"]);
    assert!(!run.done());
}

#[test]
fn watching_preempts_a_running_always() {
    // §5.1.3 "do A watching c" and Figure 5-3 step 2 (reactive preemption): once ŝ(i) entails c,
    // nothing inside asserts a goal, and what follows starts in the next instant.
    let mut run = Run::new("P() :: { do always (x = on) watching (stop = yes); y = on }");
    let goals = run.goals(&[NONE, &[("stop", "yes")], NONE, &[("y", "on")]]);
    assert_eq!(goals, ["x = on", "x = on", "true", "y = on"]);
    assert!(run.done());
    assert!(
        run.events
            .iter()
            .any(|e| e == "t=2: location 2 preempted (`do always (x = on) watching (stop = yes)`)"),
        "{:#?}",
        run.events
    );
}

#[test]
fn maintaining_violation_stops_the_body() {
    // §5.1.3 "A maintaining c": if c is not entailed at any instant the thread terminates; an
    // unknown state does not entail c.
    let program = "P() :: { {always (x = on)} maintaining (ok = yes); y = on }";
    let mut run = Run::new(program);
    let table = run.figure.thca.table().clone();
    run.estimate = updated(&table, &run.estimate, &[("ok", "yes")]);
    let goals = run.goals(&[NONE, &[("ok", "no")], NONE]);
    assert_eq!(goals, ["x = on", "x = on", "true"]);
    assert!(
        run.events.iter().any(|e| e.contains("preempted")),
        "{:#?}",
        run.events
    );

    let mut run = Run::new(program);
    assert_eq!(run.goals(&[NONE, NONE]), ["true", "y = on"], "ok unknown");
}

#[test]
fn next_starts_its_body_in_the_next_instant() {
    // §5.1.3 "next A" = {if true thennext A}.
    let mut run = Run::new("P() :: { next (x = on) }");
    assert_eq!(run.goals(&[NONE, &[("x", "on")]]), ["true", "x = on"]);
    assert!(run.done());
}

#[test]
fn a_re_marked_clock_initialisation_does_not_reset_the_clock() {
    // Figure 5-3 step 3, clock persistence: the `always` re-marks `t = 0` every instant, yet t
    // keeps counting from its first initialisation, so the `when` fires at t >= 2.
    let mut run = Run::new("P() :: { t = 0; { always (t = 0), when (t >= 2) donext (z = done) } }");
    let goals = run.goals(&[NONE, NONE, NONE, NONE, NONE]);
    // t starts at time 0 (the first cycle marks `t = 0`) and is active from the next cycle; at
    // time 2 it reads 2 and the `when` is enabled; z's goal comes in the next instant. Were t
    // reset by each re-marking it would never reach 2.
    assert_eq!(goals, ["true", "true", "true", "z = done", "z = done"]);
    let starts: Vec<&String> = run
        .events
        .iter()
        .filter(|e| e.contains("started"))
        .collect();
    assert_eq!(
        starts,
        ["t=0: clock t started at 0 by location 2 (`t = 0`)"]
    );
}

#[test]
fn a_location_awaiting_its_goal_keeps_its_clock() {
    // Figure 5-3 step 3: "an already-active clock does not get reset to zero if the primitive
    // location gets re-marked, for example due to incomplete achievement of its goal".
    let mut run = Run::new("P() :: { x = on and t = 0; when (t >= 3) donext (z = done) }");
    let goals = run.goals(&[NONE, NONE, NONE, NONE, &[("x", "on")], NONE, NONE]);
    // x is achieved at time 4; the `when` is marked from time 5, when t = 5 >= 3 already.
    assert_eq!(
        goals,
        [
            "x = on", "x = on", "x = on", "x = on", "x = on", "true", "z = done"
        ]
    );
}

#[test]
fn contradictory_goals_from_two_threads_are_a_conflict_naming_both() {
    // DESIGN.md §5.3: goals from different threads are conjoined; contradictory ones raise a goal
    // conflict with both source spans, and neither reaches reconfiguration.
    let mut run = Run::new("P() :: { x = on, x = off, y = on }");
    assert_eq!(run.goals(&[NONE]), ["y = on"]);
    assert_eq!(
        run.events,
        ["t=0: goal conflict: location 2 (`x = on`) and location 3 (`x = off`)"]
    );
}

#[test]
fn goal_conflicts_are_judged_by_the_plant_model() {
    // The Theory-backed oracle (the executive's): the model forbids x = on with y = on.
    let program = "P() :: { x = on, y = on, z = done }";
    let table = plant();
    let thca = compile_text("test.rmpl", program, Some(&table));
    let forbid = kairos::logic::parse_formula("not (x = on and y = on)", &table).unwrap();
    let mut theory = Theory::new(table, &[forbid]).unwrap();
    let mut oracle = TheoryOracle::new(&mut theory);
    let mut sequencer = Sequencer::new(thca);
    let estimate = StateEstimate::new();
    let start = sequencer.begin_cycle(0.0, &estimate, &mut oracle).unwrap();
    assert_eq!(start.goal.conjuncts.len(), 1);
    assert!(matches!(
        &start.events[..],
        [Event::GoalConflict { first, second }] if first.location.number() == 2 && second.location.number() == 3
    ));
}

#[test]
fn the_halves_must_alternate_and_time_must_not_go_back() {
    let table = plant();
    let thca = compile_text("test.rmpl", "P() :: { x = on }", Some(&table));
    let mut oracle = AssignmentOracle::new(thca.table());
    let mut sequencer = Sequencer::new(thca);
    let estimate = StateEstimate::new();
    assert!(sequencer.end_cycle(&estimate, &mut oracle).is_err());
    sequencer.begin_cycle(5.0, &estimate, &mut oracle).unwrap();
    assert!(sequencer.begin_cycle(5.0, &estimate, &mut oracle).is_err());
    sequencer.end_cycle(&estimate, &mut oracle).unwrap();
    assert!(sequencer.begin_cycle(4.0, &estimate, &mut oracle).is_err());
    assert!(
        sequencer
            .begin_cycle(f64::NAN, &estimate, &mut oracle)
            .is_err()
    );
    assert!(sequencer.begin_cycle(6.0, &estimate, &mut oracle).is_ok());
}
