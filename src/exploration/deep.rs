//! Static checks of a program against a plant model (`kairos check --deep`; thesis §8.1:
//! "potential negative interactions between concurrently-asserted goals").
//!
//! - **Goal conflicts.** The markings the THCA can reach are enumerated with every goal and
//!   guard left open (an over-approximation of Figure 5-3: any marked primitive may complete,
//!   taking any one of its transitions — or none, unless one is unguarded; a composite may
//!   complete once nothing inside is marked, and one with a maintenance constraint may be
//!   preempted at any time). Two goal locations marked together are asserted in the same cycle;
//!   when the plant model makes their goals jointly inconsistent, the sequencer would report a
//!   goal conflict at run time — found here before flight.
//! - **Unreachable modes.** A component mode that no chain of transitions leads to from the
//!   modes with an initial probability (guards ignored): dead model text, or a missing
//!   transition.
//! - **Goals the plant leaves by itself** (DESIGN.md §9). Each goal the program asserts is
//!   interpreted from the plant's most likely initial state; when no state entailing it is one
//!   the plant rests in, the goal state goal interpretation falls back on is left by a
//!   transition that needs no command (`GoalState::leaving`): at run time the planner would
//!   restore it and the plant leave it by turns. The finding names the goal and the transition.

use std::collections::{HashSet, VecDeque};

use crate::diagnostic::locate::{Locator, Step};
use crate::diagnostic::{Diagnostic, Source, Span};
use crate::logic::{Formula, ValueId};
use crate::opsat::TheoryError;
use crate::plant::{ComponentId, Plant};
use crate::reconfiguration::Reconfiguration;
use crate::sequencer::{LocationId, LocationKind, Thca};

/// Two goals the program can assert in one cycle that the model makes inconsistent.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalConflict {
    /// The goals' locations, in creation order.
    pub locations: (LocationId, LocationId),
    /// Where each goal is written in the program.
    pub spans: (Span, Span),
    /// The goals, displayed.
    pub goals: (String, String),
}

/// What the deep check found.
#[derive(Debug, Clone, PartialEq)]
pub struct DeepFindings {
    /// Jointly inconsistent goals that can be asserted together.
    pub conflicts: Vec<GoalConflict>,
    /// Modes no transition reaches, per component.
    pub unreachable: Vec<(ComponentId, ValueId)>,
    /// Distinct markings enumerated.
    pub markings: usize,
    /// False when the enumeration stopped at the limit (conflicts may be missing).
    pub complete: bool,
    /// Pairs of concurrently asserted goals whose consistency was not decided: a clock or
    /// confidence atom in a goal is decided at run time only.
    pub undecided: usize,
    /// Goals whose every goal state the plant leaves by itself, from the initial state.
    pub restless: Vec<RestlessGoal>,
}

/// A goal no state the plant rests in entails (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct RestlessGoal {
    /// Where the goal is written in the program.
    pub span: Span,
    /// The goal, displayed.
    pub goal: String,
    /// The transitions that leave the goal state by themselves: component, index into its
    /// transitions.
    pub leaving: Vec<(ComponentId, usize)>,
}

/// Runs both checks; at most `limit` markings are enumerated.
pub fn deep_check(thca: &Thca, plant: &Plant, limit: usize) -> Result<DeepFindings, TheoryError> {
    let (pairs, markings, complete) = concurrent_goals(thca, limit);
    let mut theory = plant.theory()?;
    let mut conflicts = Vec::new();
    let mut undecided = 0;
    for (a, b) in pairs {
        let (Some(first), Some(second)) = (thca.location(a).goal(), thca.location(b).goal()) else {
            continue;
        };
        let both = Formula::all([
            thca.formula(first.formula).clone(),
            thca.formula(second.formula).clone(),
        ]);
        let Ok(literal) = theory.define(&both) else {
            undecided += 1;
            continue;
        };
        let spans = (first.span.clone(), second.span.clone());
        // One goal written once may compile to several locations (`always`): one finding.
        let known = conflicts.iter().any(|c: &GoalConflict| c.spans == spans);
        if !known && !theory.consistent(&[literal]).is_consistent() {
            let show = |g: &crate::sequencer::Goal| {
                thca.formula(g.formula).display(plant.table()).to_string()
            };
            conflicts.push(GoalConflict {
                locations: (a, b),
                spans,
                goals: (show(first), show(second)),
            });
        }
    }
    Ok(DeepFindings {
        conflicts,
        unreachable: unreachable_modes(plant),
        markings,
        complete,
        undecided,
        restless: restless_goals(thca, plant, &mut theory)?,
    })
}

/// The goals of `thca` whose goal state from the plant's most likely initial state is one the
/// plant leaves by itself (see the module doc); goals with clock or confidence atoms are left
/// to run time, and so are goals unreachable from there (the executive reports those).
fn restless_goals(
    thca: &Thca,
    plant: &Plant,
    theory: &mut crate::opsat::Theory,
) -> Result<Vec<RestlessGoal>, TheoryError> {
    let reconfiguration = Reconfiguration::compile(plant)?;
    let initial: Vec<ValueId> = plant
        .components()
        .iter()
        .map(|c| {
            let best = (c.initial().iter().enumerate())
                .max_by(|a, b| a.1.total_cmp(b.1).then(b.0.cmp(&a.0)))
                .map_or(0, |(i, _)| i);
            ValueId(best as u32)
        })
        .collect();
    let mut found: Vec<RestlessGoal> = Vec::new();
    for location in thca.locations() {
        let Some(goal) = location.goal() else {
            continue;
        };
        let formula = thca.formula(goal.formula);
        if formula.has_external_atoms() || found.iter().any(|r| r.span == goal.span) {
            continue;
        }
        let Ok(state) = reconfiguration.interpret(theory, &initial, formula) else {
            continue;
        };
        if !state.leaving().is_empty() {
            found.push(RestlessGoal {
                span: goal.span.clone(),
                goal: formula.display(plant.table()).to_string(),
                leaving: state.leaving().to_vec(),
            });
        }
    }
    Ok(found)
}

/// The pairs of goal locations marked together in some reachable marking, sorted; the number
/// of markings enumerated and whether that was all of them.
fn concurrent_goals(thca: &Thca, limit: usize) -> (Vec<(LocationId, LocationId)>, usize, bool) {
    let mut initial = vec![false; thca.locations().len()];
    for &start in thca.starts() {
        mark(thca, start, &mut initial);
    }
    let mut seen: HashSet<Vec<bool>> = HashSet::from([initial.clone()]);
    let mut queue = VecDeque::from([initial]);
    let mut pairs: HashSet<(LocationId, LocationId)> = HashSet::new();
    while let Some(marking) = queue.pop_front() {
        let goals: Vec<LocationId> = (thca.locations().iter())
            .filter(|l| marking[l.id.index()] && l.goal().is_some())
            .map(|l| l.id)
            .collect();
        for (k, &a) in goals.iter().enumerate() {
            pairs.extend(goals[k + 1..].iter().map(|&b| (a, b)));
        }
        for next in successors(thca, &marking) {
            if seen.len() >= limit {
                let mut pairs: Vec<_> = pairs.into_iter().collect();
                pairs.sort();
                return (pairs, seen.len(), false);
            }
            if seen.insert(next.clone()) {
                queue.push_back(next);
            }
        }
    }
    let mut pairs: Vec<_> = pairs.into_iter().collect();
    pairs.sort();
    (pairs, seen.len(), true)
}

/// Marks `location` and, recursively, the start locations of the composites marked (m_F).
fn mark(thca: &Thca, location: LocationId, marking: &mut [bool]) {
    let mut pending = vec![location];
    while let Some(l) = pending.pop() {
        if !std::mem::replace(&mut marking[l.index()], true) {
            pending.extend(thca.location(l).starts());
        }
    }
}

/// Every marking one location's completion (or a composite's preemption) leads to.
fn successors(thca: &Thca, marking: &[bool]) -> Vec<Vec<bool>> {
    let mut out = Vec::new();
    for location in thca.locations() {
        let i = location.id.index();
        if !marking[i] {
            continue;
        }
        let inside = descendants(thca, location.id);
        let busy = inside.iter().any(|d| marking[d.index()]);
        let preemptible = location.maintenance.is_some() && location.is_composite();
        if busy && !preemptible {
            continue;
        }
        let mut left = marking.to_vec();
        left[i] = false;
        inside.iter().for_each(|d| left[d.index()] = false);
        let unguarded = location.transitions.iter().any(|t| t.guard.is_none());
        if !unguarded {
            out.push(with_ancestors(thca, left.clone()));
        }
        for transition in &location.transitions {
            let mut next = left.clone();
            transition
                .targets
                .iter()
                .for_each(|&t| mark(thca, t, &mut next));
            out.push(with_ancestors(thca, next));
        }
    }
    out
}

/// Every location inside a composite, at any depth.
fn descendants(thca: &Thca, location: LocationId) -> Vec<LocationId> {
    let mut out = Vec::new();
    let mut pending = vec![location];
    while let Some(l) = pending.pop() {
        if let LocationKind::Composite { children, .. } = &thca.location(l).kind {
            out.extend(children);
            pending.extend(children);
        }
    }
    out
}

/// Marks the composites that contain marked locations (step 9's re-marking).
fn with_ancestors(thca: &Thca, mut marking: Vec<bool>) -> Vec<bool> {
    // Children come after their parents: a backward pass reaches every ancestor.
    for location in thca.locations().iter().rev() {
        if let (true, Some(parent)) = (marking[location.id.index()], location.parent) {
            marking[parent.index()] = true;
        }
    }
    marking
}

/// Modes of each component that no chain of transitions reaches from its initial modes.
fn unreachable_modes(plant: &Plant) -> Vec<(ComponentId, ValueId)> {
    let mut out = Vec::new();
    for (c, component) in plant.components().iter().enumerate() {
        let modes = component.modes().len();
        let mut reached: Vec<bool> = (0..modes)
            .map(|m| component.initial().get(m).is_some_and(|&p| p > 0.0))
            .collect();
        let mut pending: Vec<usize> = (0..modes).filter(|&m| reached[m]).collect();
        while let Some(m) = pending.pop() {
            for &t in component.outgoing(ValueId(m as u32)) {
                let target = component.transitions()[t].target.index();
                if !std::mem::replace(&mut reached[target], true) {
                    pending.push(target);
                }
            }
        }
        let unreached = (0..modes).filter(|&m| !reached[m]);
        out.extend(unreached.map(|m| (ComponentId(c as u32), ValueId(m as u32))));
    }
    out
}

/// The findings as located messages: goal conflicts at the first goal in the program, with the
/// second named; unreachable modes at their name in the model (`model` is the model's file).
pub fn describe(findings: &DeepFindings, thca: &Thca, plant: &Plant, model: &Source) -> String {
    let program = thca.source();
    let conflicts: Vec<Diagnostic> = (findings.conflicts.iter())
        .map(|conflict| {
            let (line, column) = program.line_col(conflict.spans.1.start);
            Diagnostic::new(
                format!(
                    "goals `{}` and `{}` may be asserted in the same cycle, and the plant model makes them inconsistent",
                    conflict.goals.0, conflict.goals.1
                ),
                conflict.spans.0.clone(),
            )
            .expected("goals asserted together that the plant can hold at once")
            .note(format!(
                "the other goal: {}:{line}:{column}; on a run that marks both, the sequencer reports a goal conflict (guards and goal completion are left open here: a run may never mark both)",
                program.name
            ))
        })
        .collect();
    let locator = Locator::new(&model.text);
    let modes: Vec<Diagnostic> = (findings.unreachable.iter())
        .map(|&(c, m)| {
            let component = plant.component(c);
            let path = [
                Step::Field("components"),
                Step::Index(c.index()),
                Step::Field("modes"),
                Step::Index(m.index()),
                Step::Field("name"),
            ];
            Diagnostic::new(
                format!(
                    "mode `{}` of `{}` cannot be reached: no transition leads to it from the initial modes",
                    component.mode(m).name,
                    component.name()
                ),
                locator.at(&path),
            )
            .expected("a mode some transition enters, or one with an initial probability")
        })
        .collect();
    let restless: Vec<Diagnostic> = (findings.restless.iter())
        .map(|restless| {
            let leaving: Vec<String> = (restless.leaving.iter())
                .map(|&(c, t)| {
                    let component = plant.component(c);
                    let transition = &component.transitions()[t];
                    format!(
                        "`{}` leaves it by itself by its transition to {} (guard `{}`, {})",
                        component.name(),
                        component.mode(transition.target).name,
                        transition.guard.display(plant.table()),
                        transition.law
                    )
                })
                .collect();
            Diagnostic::new(
                format!(
                    "goal `{}` holds only in states the plant leaves by itself: {}",
                    restless.goal,
                    leaving.join("; ")
                ),
                restless.span.clone(),
            )
            .expected("a goal some state the plant rests in entails")
            .note("at run time the planner would restore it and the plant leave it by turns")
        })
        .collect();
    let mut text = String::new();
    if !conflicts.is_empty() {
        text.push_str(&program.render(&conflicts));
    }
    if !restless.is_empty() {
        text.push_str(&program.render(&restless));
    }
    if !modes.is_empty() {
        text.push_str(&model.render(&modes));
    }
    text
}
