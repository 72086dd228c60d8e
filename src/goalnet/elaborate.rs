//! Elaboration with tactic backtracking (mds-goal-networks.md §2.1; AG §1.2.5, §3.9; GP §3.6).
//!
//! A goal with a type is elaborated by one of its type's tactics: the tactic's points and goals
//! are added under names qualified by the parent's (`stay-warm.TP_A`, `stay-warm.heater1`), its
//! temporal constraints are written between them and the parent's points (each remembers the
//! elaboration it belongs to, [`Provenance::Elaborated`], so that a re-elaboration removes it
//! with the elaboration), its child goals get the parent as parent.
//!
//! **Names are readable and stable**: the n-th elaboration of a goal (n ≥ 2: a
//! re-elaboration) qualifies its items by the goal's name and n — `stay-warm#2.TP_A`,
//! `stay-warm#2.heater1`, and below it `stay-warm#2.heater1.TP_H` — so a name says which
//! elaboration made it and does not depend on what else was named before (the seeds write
//! TP_A′; primes would grow with every re-elaboration). A name already taken all the same (a
//! submission's) gets a prime. Children
//! with a type are elaborated in turn, depth first (parent before children, children in the
//! tactic's order). The whole network is then scheduled ([`schedule()`]: consistent,
//! mergeable, achievable from the current estimate). On failure the search backtracks
//! chronologically: the most recently chosen goal with an untried tactic takes its next one,
//! its later choices forgotten; every rejected choice is recorded with its reason. A goal whose
//! type has a single tactic is no choice and is passed over silently. The search stops after
//! [`ELABORATION_BUDGET`] schedulings.
//!
//! **Conditional elaboration** (AG §3.9; §2.1 step 5): a tactic applied while its parent runs
//! (re-elaboration) may find the parent's start already fired. A tactic constraint between a
//! fired parent point and a new point is then dropped — the new points are anchored at or after
//! now instead (promotion step b) — and a child goal ending at a fired point is not added (its
//! interval is over: StayWarm's GetWarm once TP_S has fired, §3.2).

use std::collections::BTreeMap;

use super::constraint_set::ConstraintSet;
use super::display;
use super::events::MissionEvent;
use super::goal::{Goal, GoalId, GoalKind};
use super::network::{ExecutableNetwork, GoalNetwork};
use super::schedule::{ScheduleError, schedule};
use super::tactic::{ChildConstraint, Elaborators, PointRef, TypeId};
use super::temporal_constraint::{Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use crate::logic::ValueId;
use crate::reconfiguration::Reconfiguration;

/// Schedulings one elaboration may try before it gives up (§2.1 step 3, "a node budget").
pub const ELABORATION_BUDGET: usize = 64;

/// What one goal's elaboration added, so that re-elaboration can take it back (§2.7 step 3).
#[derive(Debug, Clone, PartialEq)]
pub struct Elaboration {
    /// The tactic in use (its index in the type's list).
    pub tactic: usize,
    /// The child goals it added.
    pub goals: Vec<GoalId>,
    /// The points it added.
    pub points: Vec<TimePointId>,
}

/// The elaboration tree of a network: per goal its type and whether it is retired; per
/// elaborated goal, its elaboration.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ElaborationState {
    /// Per goal (by id), its type.
    pub types: Vec<Option<TypeId>>,
    /// Per goal (by id), whether a re-elaboration or safing took it out of the network.
    pub retired: Vec<bool>,
    /// The elaborated goals and what their tactic added.
    pub elaborations: BTreeMap<GoalId, Elaboration>,
    /// Per goal elaborated at least once, how often (its items' names count them).
    pub count: BTreeMap<GoalId, u32>,
}

impl ElaborationState {
    /// Every goal an elaboration of `goal` added, recursively (not `goal` itself), and the
    /// points they added.
    pub fn subtree(&self, goal: GoalId) -> (Vec<GoalId>, Vec<TimePointId>) {
        let (mut goals, mut points) = (Vec::new(), Vec::new());
        let mut stack = vec![goal];
        while let Some(g) = stack.pop() {
            if let Some(e) = self.elaborations.get(&g) {
                goals.extend(&e.goals);
                points.extend(&e.points);
                stack.extend(&e.goals);
            }
        }
        (goals, points)
    }
}

/// The fixed inputs of an elaboration.
pub struct Context<'a> {
    /// The mission's goal types.
    pub elaborators: &'a Elaborators,
    /// Mode reconfiguration: scheduling's achievability.
    pub reconfiguration: &'a Reconfiguration,
    /// ŝ, a mode per component.
    pub current: &'a [ValueId],
    /// The time of the promotion: new points are anchored at or after it.
    pub now: f64,
    /// Points from `anchor_from` on are new (promotion step b).
    pub anchor_from: usize,
    /// Whether a point of the base network has fired.
    pub fired: &'a dyn Fn(TimePointId) -> bool,
}

/// A successful elaboration: the scheduled network and its elaboration tree.
pub struct Elaborated {
    /// The scheduled network.
    pub executable: ExecutableNetwork,
    /// Its elaboration tree.
    pub state: ElaborationState,
}

/// Why no elaboration of a proposal fits.
#[derive(Debug, Clone, PartialEq)]
pub struct Rejection {
    /// In words: the scheduler's explanation, or which goal ran out of tactics.
    pub reason: String,
    /// The scheduler's error of the last attempt (`None` when no attempt was scheduled: a
    /// tactic that could not be applied, or the budget): what a refused submission reports.
    pub error: Option<ScheduleError>,
    /// The goals that error names as conflicting with the goal it could not place
    /// ([`display::conflicts`]), by name.
    pub conflicts: Vec<String>,
}

/// The choice the search made for one goal.
struct Visit {
    name: String,
    tactics: usize,
    tactic: usize,
}

/// Elaborates `roots` (each with the tactic to try first) on `base` and schedules the result;
/// pushes a `TacticRejected` per rejected choice and a `TacticChosen` per goal elaborated, or
/// says why nothing fits.
pub fn elaborate(
    context: &Context,
    base: &GoalNetwork,
    base_state: &ElaborationState,
    roots: &[(GoalId, usize)],
    events: &mut Vec<MissionEvent>,
) -> Result<Elaborated, Rejection> {
    // choices[i]: the offset from its first tactic of the i-th goal visited.
    let mut choices: Vec<usize> = Vec::new();
    for _ in 0..ELABORATION_BUDGET {
        let mut error = None;
        let mut conflicts = Vec::new();
        let mut network = base.clone();
        let mut state = base_state.clone();
        let mut visits = Vec::new();
        let built = build(
            context,
            &mut network,
            &mut state,
            roots,
            &mut choices,
            &mut visits,
        );
        let outcome = built.and_then(|()| {
            anchor(&mut network, context);
            schedule(&network, context.reconfiguration, context.current).map_err(|e| {
                let reason = display::explain(&e, &network, context.reconfiguration.plant());
                conflicts = display::conflicts(&e, &network);
                error = Some(e);
                reason
            })
        });
        match outcome {
            Ok(executable) => {
                events.extend(visits.into_iter().map(|v| MissionEvent::TacticChosen {
                    goal: v.name,
                    tactic: v.tactic + 1,
                }));
                return Ok(Elaborated { executable, state });
            }
            Err(reason) => {
                backtrack(&mut choices, visits, reason, events).map_err(|reason| Rejection {
                    reason,
                    error: error.take(),
                    conflicts: std::mem::take(&mut conflicts),
                })?
            }
        }
    }
    Err(Rejection {
        reason: format!(
            "elaboration failed: its budget of {ELABORATION_BUDGET} schedulings is spent"
        ),
        error: None,
        conflicts: Vec::new(),
    })
}

/// Steps the most recent choice with an untried tactic (chronological backtracking); `Err`
/// when none is left.
fn backtrack(
    choices: &mut Vec<usize>,
    mut visits: Vec<Visit>,
    mut reason: String,
    events: &mut Vec<MissionEvent>,
) -> Result<(), String> {
    while let Some(last) = visits.pop() {
        let i = visits.len();
        choices.truncate(i + 1);
        if last.tactics > 1 {
            events.push(MissionEvent::TacticRejected {
                goal: last.name.clone(),
                tactic: last.tactic + 1,
                reason: reason.clone(),
            });
        }
        if choices[i] + 1 < last.tactics {
            choices[i] += 1;
            return Ok(());
        }
        choices.pop();
        if last.tactics > 1 {
            reason = format!("every tactic of `{}` was rejected", last.name);
        }
    }
    Err(reason)
}

/// Applies the chosen tactics depth first, extending `choices` with the first tactic of each
/// goal visited for the first time.
fn build(
    context: &Context,
    network: &mut GoalNetwork,
    state: &mut ElaborationState,
    roots: &[(GoalId, usize)],
    choices: &mut Vec<usize>,
    visits: &mut Vec<Visit>,
) -> Result<(), String> {
    let mut stack: Vec<(GoalId, usize)> = roots.iter().rev().copied().collect();
    while let Some((goal, first)) = stack.pop() {
        let Some(goal_type) = state.types[goal.index()] else {
            continue;
        };
        let tactics = context.elaborators.get(goal_type).tactics.len();
        if tactics == 0 {
            continue;
        }
        let i = visits.len();
        if choices.len() <= i {
            choices.push(0);
        }
        let tactic = (first + choices[i]) % tactics;
        visits.push(Visit {
            name: network.goal(goal).name.clone(),
            tactics,
            tactic,
        });
        let children = apply(context, network, state, goal, goal_type, tactic)?;
        stack.extend(children.into_iter().rev().map(|c| (c, 0)));
    }
    Ok(())
}

/// New points are not in the past (promotion step b, mds-goal-networks.md §5 C14).
fn anchor(network: &mut GoalNetwork, context: &Context) {
    for p in context.anchor_from..network.points().len() {
        let reason = "a new point is not in the past (promotion step b)".to_string();
        let constraint = TemporalConstraint::new(
            TimePointId::ORIGIN,
            TimePointId(p as u32),
            context.now,
            f64::INFINITY,
            Provenance::Scheduled { reason },
        );
        // The point exists and the bounds are valid: the network accepts it.
        let _ = network.add_constraint(constraint);
    }
}

/// Adds one tactic's points, constraints and child goals under `goal`; returns the children.
fn apply(
    context: &Context,
    network: &mut GoalNetwork,
    state: &mut ElaborationState,
    goal: GoalId,
    goal_type: TypeId,
    index: usize,
) -> Result<Vec<GoalId>, String> {
    let parent = network.goal(goal).clone();
    let tactic = &context.elaborators.get(goal_type).tactics[index];
    let ordinal = state.count.get(&goal).copied().unwrap_or(0) + 1;
    state.count.insert(goal, ordinal);
    let prefix = qualifier(&parent.name, ordinal);
    let locals: Vec<TimePointId> = tactic
        .points
        .iter()
        .map(|name| {
            let name = format!("{prefix}.{name}");
            let name = fresh(&name, |n| network.point_named(n).is_some());
            network.add_point(name, 0..0)
        })
        .collect();
    let resolve = |r: PointRef| match r {
        PointRef::Start => parent.start,
        PointRef::End => parent.end,
        PointRef::Local(i) => locals[i],
    };
    let is_new = |p: TimePointId| locals.contains(&p);
    let fired = |p: TimePointId| !is_new(p) && (context.fired)(p);
    for c in &tactic.constraints {
        let (from, to) = (resolve(c.from), resolve(c.to));
        if (fired(from) && is_new(to)) || (fired(to) && is_new(from)) {
            continue; // conditional elaboration: the new point is anchored after now instead
        }
        let provenance = Provenance::Elaborated {
            goal,
            span: c.span.clone(),
        };
        let constraint = TemporalConstraint::new(from, to, c.min, c.max, provenance);
        network
            .add_constraint(constraint)
            .map_err(|e| format!("tactic `{}`: {e:?}", tactic.name))?;
    }
    let mut added = Vec::new();
    for child in &tactic.goals {
        let (start, end) = (resolve(child.start), resolve(child.end));
        if fired(end) {
            continue; // its interval is over
        }
        let Some(sv) = child.sv.or(parent.sv) else {
            return Err(format!(
                "`{}` of tactic `{}` needs its parent's state variable, and `{}` is a macro goal",
                child.name, tactic.name, parent.name
            ));
        };
        let (constraint, text) = match &child.constraint {
            ChildConstraint::Given(set, text) => (set.clone(), text.clone()),
            ChildConstraint::Inherit => inherited(&parent, child.kind),
        };
        let id = network.add_goal(Goal {
            name: fresh(&format!("{prefix}.{}", child.name), |n| {
                network.goal_named(n).is_some()
            }),
            sv: Some(sv),
            kind: child.kind,
            constraint,
            delegate: None,
            text,
            start,
            end,
            parent: Some(goal),
            priority: child.priority,
            span: child.span.clone(),
        });
        state.types.push(child.goal_type);
        state.retired.push(false);
        added.push(id);
    }
    state.elaborations.insert(
        goal,
        Elaboration {
            tactic: index,
            goals: added.clone(),
            points: locals,
        },
    );
    Ok(added)
}

/// The constraint a child on its parent's state variable inherits: the parent's for a control
/// goal, "known" for a Knowledge goal, none for an Unconstrained one.
fn inherited(parent: &Goal, kind: GoalKind) -> (ConstraintSet, String) {
    let domain = parent.constraint.domain();
    match kind {
        GoalKind::Maintain | GoalKind::Transition => {
            (parent.constraint.clone(), parent.text.clone())
        }
        GoalKind::Knowledge => (
            ConstraintSet::unconstrained(domain).with_known(),
            String::new(),
        ),
        GoalKind::Unconstrained => (ConstraintSet::unconstrained(domain), String::new()),
    }
}

/// What the `ordinal`-th elaboration of goal `name` qualifies its items' names with: `name`
/// for the first, `name#2` for the second, and so on.
pub fn qualifier(name: &str, ordinal: u32) -> String {
    if ordinal <= 1 {
        name.to_string()
    } else {
        format!("{name}#{ordinal}")
    }
}

/// `name`, or `name′`, `name′′`, … — the first not taken.
pub fn fresh(name: &str, taken: impl Fn(&str) -> bool) -> String {
    let mut candidate = name.to_string();
    while taken(&candidate) {
        candidate.push('′');
    }
    candidate
}
