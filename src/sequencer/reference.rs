//! The oracle the sequencer's incremental execution is tested against: `Step_THCA` (thesis
//! Figure 5-3) written plainly — every pass over every location, every condition asked of the
//! oracle afresh, nothing kept between cycles — and a property test that random automata run
//! by both, on random estimate sequences with clocks crossing their bounds, give the same
//! goals, clock values, events and markings.

use proptest::prelude::*;

use super::oracle::{AssignmentOracle, Entailment, StateEstimate, entailed_in_every_case};
use super::step::{Event, Sequencer};
use super::thca::{
    ClockInit, Condition, Construct, Goal, LocationId, LocationKind, Origin, Sense, Thca,
    ThcaBuilder, Transition,
};
use crate::diagnostic::Source;
use crate::logic::{Atom, ClockId, Formula, VarTable, parse_formula};
use crate::seeded;

/// The marking and clock references of a plain execution.
struct Plain {
    marked: Vec<bool>,
    started: Vec<Option<f64>>,
}

/// What the first half cycle leaves for the second.
struct Half {
    clocks: Vec<Option<f64>>,
    violated: Vec<bool>,
    started: Vec<(ClockId, f64)>,
}

/// m_F, recursively.
fn mark_full(thca: &Thca, location: LocationId, marking: &mut [bool]) {
    marking[location.index()] = true;
    for &start in thca.location(location).starts() {
        mark_full(thca, start, marking);
    }
}

/// Does `condition` hold on `estimate` and ω = `clocks`?
fn holds(
    thca: &Thca,
    clocks: &[Option<f64>],
    estimate: &StateEstimate,
    oracle: &mut AssignmentOracle,
    condition: &Condition,
) -> bool {
    let entailed = entailed(thca, clocks, estimate, oracle, condition.formula);
    entailed == (condition.sense == Sense::Entailed)
}

fn entailed(
    thca: &Thca,
    clocks: &[Option<f64>],
    estimate: &StateEstimate,
    oracle: &mut AssignmentOracle,
    formula: super::thca::FormulaId,
) -> bool {
    let grounded = thca.formula(formula).ground(&mut |atom| match atom {
        Atom::Clock { clock, op, seconds } => clocks[clock.index()].map(|v| op.holds(v, seconds.0)),
        _ => None,
    });
    entailed_in_every_case(
        &grounded,
        &|atom| matches!(atom, Atom::Clock { .. }),
        &mut |f| oracle.entailed(estimate, f),
    )
}

impl Plain {
    fn new(thca: &Thca) -> Self {
        let mut marked = vec![false; thca.locations().len()];
        for &start in thca.starts() {
            mark_full(thca, start, &mut marked);
        }
        Plain {
            marked,
            started: vec![None; thca.table().clocks().len()],
        }
    }

    /// Steps 1–4: the goal's locations, ω's active clocks, the events.
    #[allow(clippy::type_complexity)]
    fn begin(
        &mut self,
        thca: &Thca,
        time: f64,
        current: &StateEstimate,
        oracle: &mut AssignmentOracle,
    ) -> (Half, Vec<LocationId>, Vec<(ClockId, f64)>, Vec<Event>) {
        let clocks: Vec<Option<f64>> = self.started.iter().map(|s| s.map(|t0| time - t0)).collect();
        let count = self.marked.len();
        let (mut violated, mut inside) = (vec![false; count], vec![false; count]);
        let mut events = Vec::new();
        for location in thca.locations() {
            let i = location.id.index();
            if location
                .parent
                .is_some_and(|p| inside[p.index()] || violated[p.index()])
            {
                inside[i] = true;
                self.marked[i] = false;
                continue;
            }
            let Some(maintenance) = location.maintenance.as_ref() else {
                continue;
            };
            if self.marked[i] && !holds(thca, &clocks, current, oracle, maintenance) {
                violated[i] = true;
                events.push(Event::maintenance_failed(location, maintenance.clone()));
            }
        }
        let mut started: Vec<(ClockId, f64)> = Vec::new();
        let marked: Vec<_> = (thca.locations().iter())
            .filter(|l| self.marked[l.id.index()])
            .collect();
        for location in &marked {
            for init in location.clock_inits() {
                let c = init.clock;
                if self.started[c.index()].is_none() && !started.iter().any(|(x, _)| *x == c) {
                    started.push((c, time));
                    events.push(Event::ClockStarted {
                        clock: c,
                        time,
                        location: location.id,
                        span: init.span.clone(),
                    });
                }
            }
        }
        let goals = (marked.iter())
            .filter(|l| !violated[l.id.index()] && l.goal().is_some())
            .map(|l| l.id)
            .collect();
        let active = (clocks.iter().enumerate())
            .filter_map(|(i, v)| v.map(|v| (ClockId(i as u32), v)))
            .collect();
        let half = Half {
            clocks,
            violated,
            started,
        };
        (half, goals, active, events)
    }

    /// Steps 7–10: the events.
    fn end(
        &mut self,
        thca: &Thca,
        half: Half,
        next: &StateEstimate,
        oracle: &mut AssignmentOracle,
    ) -> Vec<Event> {
        let count = self.marked.len();
        let (mut marking, mut busy) = (vec![false; count], vec![false; count]);
        let (mut events, mut enabled) = (Vec::new(), Vec::new());
        for location in thca.locations().iter().rev() {
            let i = location.id.index();
            let mut moves = false;
            if self.marked[i] {
                let ready = match &location.kind {
                    LocationKind::Primitive { goal, .. } => {
                        let achieved = goal
                            .as_ref()
                            .is_none_or(|g| entailed(thca, &half.clocks, next, oracle, g.formula));
                        marking[i] = !achieved && !half.violated[i];
                        if let (true, false, Some(goal)) = (achieved, half.violated[i], goal) {
                            events.push(Event::GoalAchieved {
                                location: location.id,
                                span: goal.span.clone(),
                            });
                        }
                        achieved || half.violated[i]
                    }
                    LocationKind::Composite { .. } => !busy[i],
                };
                if ready {
                    for (k, transition) in location.transitions.iter().enumerate() {
                        let guard = transition.guard.as_ref();
                        if guard.is_none_or(|g| holds(thca, &half.clocks, next, oracle, g)) {
                            enabled.push((location.id, k));
                            moves = true;
                        }
                    }
                }
            }
            if let Some(parent) = location.parent {
                busy[parent.index()] |= busy[i] || marking[i] || moves;
            }
        }
        for (location, k) in enabled {
            for &target in &thca.location(location).transitions[k].targets {
                mark_full(thca, target, &mut marking);
            }
        }
        for location in thca.locations().iter().rev() {
            if let (true, Some(parent)) = (marking[location.id.index()], location.parent) {
                marking[parent.index()] = true;
            }
        }
        for (clock, time) in half.started {
            self.started[clock.index()] = Some(time);
        }
        let was_running = self.marked.contains(&true);
        self.marked = marking;
        if was_running && !self.marked.contains(&true) {
            events.push(Event::Completed);
        }
        events
    }
}

/// [`AssignmentOracle`] with revisions (the executive's oracle has them, so the sequencer
/// keeps answers across cycles) and every goal set consistent (the plain execution does not
/// resolve conflicts; that code is not incremental).
struct Revised(AssignmentOracle);

impl Entailment for Revised {
    type Estimate = (u64, StateEstimate);

    fn entailed(&mut self, estimate: &Self::Estimate, formula: &Formula) -> bool {
        self.0.entailed(&estimate.1, formula)
    }

    fn consistent(&mut self, _: &Formula) -> bool {
        true
    }

    fn revision(&self, estimate: &Self::Estimate) -> Option<u64> {
        Some(estimate.0)
    }
}

/// Conditions and goals the generated automata use: state atoms, clock bounds both ways, and
/// mixtures (clocks `t` and `u`; a cycle lasts 0.5 s, so the bounds are crossed mid-run).
const FORMULAS: &[&str] = &[
    "x = yes",
    "y = no",
    "ok = yes",
    "x = yes and y = yes",
    "t >= 2",
    "u < 3",
    "t >= 1 or y = yes",
    "not (u >= 4) and ok = yes",
    "x = no or t >= 6",
];

fn table() -> VarTable {
    let mut table = VarTable::new();
    for name in ["x", "y", "ok"] {
        table.add_variable(name, ["no", "yes"]).unwrap();
    }
    table.add_clock("t").unwrap();
    table.add_clock("u").unwrap();
    table
}

/// One generated location: composite or not, where it sits, what it says.
#[derive(Debug, Clone)]
struct Spec {
    composite: bool,
    /// Index of its composite among the earlier locations (taken modulo, skipped if none).
    parent: Option<usize>,
    start: bool,
    goal: Option<usize>,
    maintenance: Option<ConditionSpec>,
    clock: Option<u32>,
    transitions: Vec<TransitionSpec>,
}

/// A generated condition: which of [`FORMULAS`], and whether it must be entailed.
type ConditionSpec = (usize, bool);

/// A generated transition: its guard (none: **True**) and its targets (taken modulo).
type TransitionSpec = (Option<ConditionSpec>, Vec<usize>);

fn spec() -> impl Strategy<Value = Spec> {
    let condition = (0..FORMULAS.len(), any::<bool>());
    (
        prop::bool::weighted(0.35),
        prop::option::weighted(0.7, 0usize..16),
        prop::bool::weighted(0.5),
        prop::option::weighted(0.6, 0..FORMULAS.len()),
        prop::option::weighted(0.3, condition.clone()),
        prop::option::weighted(0.2, 0u32..2),
        prop::collection::vec(
            (
                prop::option::weighted(0.6, condition),
                prop::collection::vec(0usize..16, 1..3),
            ),
            0..3,
        ),
    )
        .prop_map(
            |(composite, parent, start, goal, maintenance, clock, transitions)| Spec {
                composite,
                parent,
                start,
                goal,
                maintenance,
                clock,
                transitions,
            },
        )
}

fn origin() -> Origin {
    Origin {
        construct: Construct::Assertion,
        span: 0..0,
        call_stack: Vec::new(),
    }
}

/// Builds the automaton the specs describe (always valid: parents are earlier composites,
/// starts are children of their automaton).
fn build(specs: &[Spec]) -> Thca {
    let table = table();
    let mut builder = ThcaBuilder::new("generated", table.clone(), Source::new("generated", ""));
    let formula = |builder: &mut ThcaBuilder, k: usize| {
        builder.formula(parse_formula(FORMULAS[k], &table).unwrap())
    };
    let mut ids: Vec<LocationId> = Vec::new();
    let mut composites: Vec<LocationId> = Vec::new();
    for spec in specs {
        let parent = spec
            .parent
            .filter(|_| !composites.is_empty())
            .map(|p| composites[p % composites.len()]);
        let id = if spec.composite {
            let id = builder.composite(parent, origin());
            composites.push(id);
            id
        } else {
            let goal = spec.goal.map(|k| Goal {
                formula: formula(&mut builder, k),
                span: 0..0,
            });
            let inits = (spec.clock.iter())
                .map(|&c| ClockInit {
                    clock: ClockId(c),
                    span: 0..0,
                })
                .collect();
            builder.primitive(parent, origin(), goal, inits)
        };
        if let Some((k, entailed)) = spec.maintenance {
            let sense = if entailed {
                Sense::Entailed
            } else {
                Sense::NotEntailed
            };
            let condition =
                builder.condition(parse_formula(FORMULAS[k], &table).unwrap(), sense, 0..0);
            builder.set_maintenance(id, condition);
        }
        if spec.start || ids.is_empty() {
            builder.add_start(parent, id);
        }
        ids.push(id);
    }
    for (spec, &id) in specs.iter().zip(&ids) {
        for (guard, targets) in &spec.transitions {
            let guard = guard.map(|(k, entailed)| {
                let sense = if entailed {
                    Sense::Entailed
                } else {
                    Sense::NotEntailed
                };
                builder.condition(parse_formula(FORMULAS[k], &table).unwrap(), sense, 0..0)
            });
            let targets = targets.iter().map(|&t| ids[t % ids.len()]).collect();
            builder.add_transition(id, Transition { guard, targets });
        }
    }
    builder.build().unwrap()
}

/// An estimate of x, y, ok from three codes (0 unknown, 1 no, 2 yes).
fn estimate(codes: [u8; 3]) -> StateEstimate {
    let mut estimate = StateEstimate::new();
    for (x, code) in codes.into_iter().enumerate() {
        if code > 0 {
            estimate.set(
                crate::logic::VarId(x as u32),
                crate::logic::ValueId(u32::from(code) - 1),
            );
        }
    }
    estimate
}

proptest! {
    #![proptest_config(seeded::config(256))]

    /// DESIGN.md §5.3, thesis Figure 5-3: the sequencer's passes over the marked locations
    /// only, and its answers kept across cycles while the estimate's revision and the clock
    /// atoms' truth values hold, execute as every pass over every location with every
    /// condition asked afresh — same goals, clock values, events and markings, cycle by cycle.
    #[test]
    fn incremental_execution_is_the_plain_execution(
        specs in prop::collection::vec(spec(), 1..16),
        // Each estimate holds for a number of cycles (the quiet stretches answers are kept in).
        run in prop::collection::vec((prop::array::uniform3(0u8..3), 1usize..6), 1..10),
    ) {
        let thca = build(&specs);
        let table = thca.table().clone();
        let mut sequencer = Sequencer::new(thca.clone());
        let mut plain = Plain::new(&thca);
        let mut revised = Revised(AssignmentOracle::new(&table));
        let mut oracle = AssignmentOracle::new(&table);
        let estimates: Vec<(u64, StateEstimate)> = (run.iter().enumerate())
            .flat_map(|(revision, &(codes, cycles))| {
                std::iter::repeat_n((revision as u64, estimate(codes)), cycles)
            })
            .collect();
        for (cycle, pair) in estimates.windows(2).enumerate() {
            if sequencer.is_complete() {
                break;
            }
            let time = cycle as f64 * 0.5;
            let start = sequencer.begin_cycle(time, &pair[0], &mut revised).unwrap();
            let (half, goals, clocks, events) = plain.begin(&thca, time, &pair[0].1, &mut oracle);
            let conjuncts: Vec<LocationId> = start.goal.conjuncts.iter().map(|c| c.location).collect();
            prop_assert_eq!(conjuncts, goals, "cycle {} g(i)", cycle);
            prop_assert_eq!(start.clocks, clocks, "cycle {} ω(i)", cycle);
            prop_assert_eq!(start.events, events, "cycle {} steps 2–4", cycle);
            let end = sequencer.end_cycle(&pair[1], &mut revised).unwrap();
            let events = plain.end(&thca, half, &pair[1].1, &mut oracle);
            prop_assert_eq!(end.events, events, "cycle {} steps 7–9", cycle);
            let marked: Vec<bool> = (thca.locations().iter()).map(|l| sequencer.is_marked(l.id)).collect();
            prop_assert_eq!(&marked, &plain.marked, "cycle {} m(i+1)", cycle);
            let listed: Vec<LocationId> = sequencer.marking().map(|l| l.id).collect();
            let expected: Vec<LocationId> = (thca.locations().iter()).filter(|l| plain.marked[l.id.index()]).map(|l| l.id).collect();
            prop_assert_eq!(listed, expected, "cycle {} marking()", cycle);
        }
    }
}
