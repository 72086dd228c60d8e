//! Merging and scheduling (mds-goal-networks.md §2.2; AG §1.2.6, GP §3.4, §3.6): from a goal
//! network to an [`ExecutableNetwork`], or the reason there is none.
//!
//! For each state variable, upstream first (the causal graph of mode reconfiguration is the
//! state-effects graph: affecting before affected, §2.2 step 1):
//! 1. goals whose constraints do not merge are serialised, `end(g1) ≤ start(g2)` or else the
//!    reverse; if neither is consistent, [`ScheduleError::Unmergeable`] (step 2d);
//! 2. its points get a total order consistent with the STN: depth first, candidates by
//!    increasing earliest time then creation order, each step adding `[0, +∞)` between
//!    consecutive points and re-propagating (step 2b; fixed per timeline, GP §3.6);
//! 3. each interval between consecutive points (not forced to zero length) is an XGoal, the
//!    merge of the goals covering it (step 2c);
//! 4. the XGoals are projected serially from the state given (the estimate, or the plant's most
//!    likely initial modes) and validated (step 3): a Transition XGoal projects onto the
//!    admitted modes reachable (reconfiguration's reachability, §9: a stuck or irreversible
//!    mode is not left) from the previous projection; a Maintain XGoal must already hold on the
//!    previous projection (no transition is allowed inside it) — or, on a set the plant enters
//!    by itself (transitions whose guards name no command: a trigger, a drifting temperature),
//!    it is a condition its start point waits for and projects onto those modes; XGoals without a control part
//!    (knowledge, unconstrained) leave the projection alone — knowledge is never commanded,
//!    only monitored (DESIGN.md §15.3). A Transition XGoal with an empty projection is
//!    [`ScheduleError::Unachievable`] (its set cannot be reached); a Maintain XGoal whose set the
//!    previous XGoal does not leave the SV in is [`ScheduleError::TransitionUnachievable`] (the
//!    seed's negative test: a maintain goal without its transition goal, §3.3). In a network
//!    being promoted over a running one, XGoals whose end point has fired are history and are
//!    not projected: the projection starts from ŝ on the XGoals still to come, which is
//!    promotion step c (§2.3: each SV can move from where it is into the proposed XGoals).

use super::goal::{GoalId, GoalKind};
use super::network::{ExecutableNetwork, GoalNetwork, Timeline};
use super::stn::{Inconsistency, Stn};
use super::temporal_constraint::{Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use super::xgoal::XGoal;
use crate::logic::{ValueId, VarId};
use crate::plant::{ComponentId, ModeKind, Plant, Transition};
use crate::reconfiguration::Reconfiguration;

/// Orderings of one timeline tried before giving up (a depth-first search with backtracking).
const ORDER_BUDGET: usize = 10_000;

/// Why a network cannot be scheduled, with the evidence for the message (§2.2 step 4).
#[derive(Debug, Clone, PartialEq)]
pub enum ScheduleError {
    /// The STN has no solution (before or after the scheduler's constraints).
    Inconsistent(Inconsistency),
    /// Two goals on one SV cannot hold together and cannot be serialised either way.
    Unmergeable {
        /// The state variable.
        sv: ComponentId,
        /// The two goals.
        goals: [GoalId; 2],
    },
    /// An XGoal cannot be reached from the state the SV is in.
    Unachievable {
        /// The XGoal.
        xgoal: Box<XGoal>,
        /// The modes the SV is projected to be in when the XGoal starts.
        from: Vec<ValueId>,
    },
    /// The SV cannot move from one XGoal's projection into the next XGoal.
    TransitionUnachievable {
        /// The earlier XGoal.
        previous: Box<XGoal>,
        /// Its projection.
        from: Vec<ValueId>,
        /// The XGoal that cannot be entered.
        next: Box<XGoal>,
    },
    /// Constraints that force a goal's end before its start (the cycle they form with
    /// `start ≤ end`, the constraints of the network as given).
    Reversed {
        /// The goal.
        goal: GoalId,
        /// The network's constraints in the cycle.
        cycle: Vec<super::ConstraintId>,
    },
    /// A goal whose start and end the constraints force to one instant: it would hold over no
    /// time and vanish from its timeline.
    EmptyInterval {
        /// The goal.
        goal: GoalId,
    },
    /// A goal delegated to the controller of a state variable that is not a component cannot
    /// be achieved by it from the SV's value ([`judge_delegated`](super::judge_delegated)).
    DelegatedUnachievable {
        /// The goal.
        goal: GoalId,
        /// The controlled state variable.
        sv: String,
        /// Its value.
        value: String,
    },
}

/// The error without the network's names (ids stand for them, as an event's `Display`):
/// [`display::explain`](super::display::explain) words it with goal, point and component names
/// and the evidence.
impl std::fmt::Display for ScheduleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ScheduleError::Inconsistent(inconsistency) => write!(f, "{inconsistency}"),
            ScheduleError::Unmergeable { sv, goals } => write!(
                f,
                "goals {} and {} on component {} can neither hold together nor be serialised",
                goals[0].0, goals[1].0, sv.0
            ),
            ScheduleError::Unachievable { xgoal, .. } => write!(
                f,
                "an XGoal on component {} cannot be reached from the state it is projected to be in",
                xgoal.sv.0
            ),
            ScheduleError::TransitionUnachievable { next, .. } => write!(
                f,
                "component {} cannot move from one XGoal into the next",
                next.sv.0
            ),
            ScheduleError::Reversed { goal, .. } => write!(
                f,
                "the constraints force goal {}'s end before its start",
                goal.0
            ),
            ScheduleError::EmptyInterval { goal } => write!(
                f,
                "goal {} holds over no time: its start and end are forced to one instant",
                goal.0
            ),
            ScheduleError::DelegatedUnachievable { goal, sv, value } => write!(
                f,
                "goal {} cannot be achieved by the controller of {sv} from {sv} = {value}",
                goal.0
            ),
        }
    }
}

impl std::error::Error for ScheduleError {}

/// Schedules `network` for a plant whose components are in `current` (a mode per component).
pub fn schedule(
    network: &GoalNetwork,
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
) -> Result<ExecutableNetwork, ScheduleError> {
    let given = network.stn().constraints().len();
    let mut network = network.clone();
    network.propagate().map_err(ScheduleError::Inconsistent)?;
    require_intervals(&mut network)?;
    network
        .propagate()
        .map_err(|inconsistency| reversed(&network, given, inconsistency))?;
    let plant = reconfiguration.plant();
    let fired = fired_points(&network);
    let mut timelines = Vec::new();
    for &sv in reconfiguration.upstream_first() {
        let goals: Vec<GoalId> = network.goals_on(sv).map(|(id, _)| id).collect();
        if goals.is_empty() {
            continue;
        }
        serialise(&mut network, sv, &goals)?;
        let points = order(&mut network, &goals)?;
        let domain = plant.component(sv).modes().len();
        let xgoals = xgoals(&network, sv, domain, &goals, &points, &fired)?;
        let timeline = Timeline { sv, points, xgoals };
        project(reconfiguration, &timeline, current[sv.index()], &fired)?;
        timelines.push(timeline);
    }
    Ok(ExecutableNetwork { network, timelines })
}

/// Adds `start(g) ≤ end(g)` for every goal on a state variable: a goal holds over its
/// interval, so constraints that would let its end come first are an inconsistency (its
/// explanation names them) rather than an order in which the goal covers nothing and is
/// silently left out. A goal whose start and end are one point holds over no time.
fn require_intervals(network: &mut GoalNetwork) -> Result<(), ScheduleError> {
    let intervals: Vec<(GoalId, TimePointId, TimePointId)> = (network.goals().iter().enumerate())
        .filter(|(_, g)| !g.is_macro())
        .map(|(i, g)| (GoalId(i as u32), g.start, g.end))
        .collect();
    for (goal, start, end) in intervals {
        if start == end {
            return Err(ScheduleError::EmptyInterval { goal });
        }
        let constraint = TemporalConstraint::before(start, end, Provenance::GoalInterval);
        // The points exist and the bounds are [0, +∞): the constraint is well formed.
        let _ = network.add_constraint(constraint);
    }
    Ok(())
}

/// The goal whose `start ≤ end` closes the negative cycle `inconsistency` of `network` (whose
/// first `given` constraints are the network's as given), with those of the cycle.
fn reversed(network: &GoalNetwork, given: usize, inconsistency: Inconsistency) -> ScheduleError {
    let constraints = network.stn().constraints();
    let interval = (inconsistency.cycle.iter())
        .map(|id| &constraints[id.index()])
        .find(|c| c.provenance == Provenance::GoalInterval);
    let goal = interval.and_then(|c| {
        (network
            .goals()
            .iter()
            .position(|g| !g.is_macro() && g.start == c.from && g.end == c.to))
        .map(|i| GoalId(i as u32))
    });
    match goal {
        Some(goal) => ScheduleError::Reversed {
            goal,
            cycle: (inconsistency.cycle.into_iter())
                .filter(|id| id.index() < given)
                .collect(),
        },
        None => ScheduleError::Inconsistent(inconsistency),
    }
}

/// Serialises every pair of goals on `sv` whose constraints do not merge (§2.2 step 2d).
fn serialise(
    network: &mut GoalNetwork,
    sv: ComponentId,
    goals: &[GoalId],
) -> Result<(), ScheduleError> {
    for (i, &a) in goals.iter().enumerate() {
        for &b in &goals[i + 1..] {
            let (ga, gb) = (network.goal(a), network.goal(b));
            if !ga.constraint.merge(&gb.constraint).is_empty() {
                continue;
            }
            let first = (
                ga.end,
                gb.start,
                format!("end({}) ≤ start({})", ga.name, gb.name),
            );
            let second = (
                gb.end,
                ga.start,
                format!("end({}) ≤ start({})", gb.name, ga.name),
            );
            let serialised = [first, second]
                .into_iter()
                .find_map(|(end, start, reason)| {
                    let mut trial = network.stn().clone();
                    let constraint =
                        TemporalConstraint::before(end, start, Provenance::Scheduled { reason });
                    trial.add_constraint(constraint).ok()?;
                    trial.propagate().ok()?;
                    Some(trial)
                });
            match serialised {
                Some(stn) => *network.stn_mut() = stn,
                None => return Err(ScheduleError::Unmergeable { sv, goals: [a, b] }),
            }
        }
    }
    Ok(())
}

/// A total order of the goals' points consistent with the STN, added to it (§2.2 step 2b).
fn order(network: &mut GoalNetwork, goals: &[GoalId]) -> Result<Vec<TimePointId>, ScheduleError> {
    let mut points: Vec<TimePointId> = goals
        .iter()
        .flat_map(|g| [network.goal(*g).start, network.goal(*g).end])
        .collect();
    points.sort_unstable();
    points.dedup();
    let mut search = OrderSearch {
        budget: ORDER_BUDGET,
        last_failure: None,
    };
    match search.place(network.stn().clone(), Vec::new(), points) {
        Some((stn, order)) => {
            *network.stn_mut() = stn;
            Ok(order)
        }
        None => Err(ScheduleError::Inconsistent(
            search
                .last_failure
                .unwrap_or(Inconsistency { cycle: Vec::new() }),
        )),
    }
}

/// The depth-first search for a timeline's order.
struct OrderSearch {
    budget: usize,
    last_failure: Option<Inconsistency>,
}

impl OrderSearch {
    fn place(
        &mut self,
        stn: Stn,
        placed: Vec<TimePointId>,
        remaining: Vec<TimePointId>,
    ) -> Option<(Stn, Vec<TimePointId>)> {
        if remaining.is_empty() {
            return Some((stn, placed));
        }
        let mut candidates = remaining.clone();
        let earliest = |p: &TimePointId| stn.window(*p).map_or(0.0, |w| w.lb);
        // A point that a written constraint puts at or after another remaining point goes after
        // it among equals: placing it first would force the two to coincide and each would wait
        // for the other to fire (a tactic's point created before its children's, as Heater's
        // TP_H → TP_A ∈ [0, 5]).
        let follows = |p: &TimePointId| {
            stn.constraints()
                .iter()
                .any(|c| c.to == *p && c.from != *p && c.min >= 0.0 && remaining.contains(&c.from))
        };
        candidates.sort_by(|a, b| {
            earliest(a)
                .total_cmp(&earliest(b))
                .then(follows(a).cmp(&follows(b)))
                .then(a.cmp(b))
        });
        for candidate in candidates {
            if self.budget == 0 {
                return None;
            }
            self.budget -= 1;
            let mut trial = stn.clone();
            if let Some(&last) = placed.last() {
                let reason = "the state variable's timeline is ordered".to_string();
                let constraint =
                    TemporalConstraint::before(last, candidate, Provenance::Scheduled { reason });
                if trial.add_constraint(constraint).is_err() {
                    continue;
                }
                if let Err(inconsistency) = trial.propagate() {
                    self.last_failure = Some(inconsistency);
                    continue;
                }
            }
            let mut next_placed = placed.clone();
            next_placed.push(candidate);
            let rest = remaining
                .iter()
                .copied()
                .filter(|p| *p != candidate)
                .collect();
            if let Some(found) = self.place(trial, next_placed, rest) {
                return Some(found);
            }
        }
        None
    }
}

/// One XGoal per interval of consecutive points not forced to zero length (§2.2 step 2c).
/// The XGoals of one timeline (§2.2 step 2c); a goal that covers no interval — its start and
/// end forced to one instant — is an [`ScheduleError::EmptyInterval`], unless it is history (its
/// end has fired).
fn xgoals(
    network: &GoalNetwork,
    sv: ComponentId,
    domain: usize,
    goals: &[GoalId],
    points: &[TimePointId],
    fired: &[TimePointId],
) -> Result<Vec<XGoal>, ScheduleError> {
    let position = |p: TimePointId| points.iter().position(|q| *q == p).unwrap_or(0);
    let mut out = Vec::new();
    let mut covered = vec![false; goals.len()];
    for (i, pair) in points.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        if network.stn().distance(a, b).is_some_and(|d| d <= 0.0) {
            continue; // a and b coincide: no interval
        }
        let covering: Vec<(GoalId, &super::goal::Goal)> = (goals.iter().enumerate())
            .filter_map(|(k, &id)| {
                let goal = network.goal(id);
                let covers = position(goal.start) <= i && position(goal.end) > i;
                covered[k] |= covers;
                covers.then_some((id, goal))
            })
            .collect();
        out.push(XGoal::merge(sv, a, b, domain, covering));
    }
    if let Some(k) =
        (0..goals.len()).find(|&k| !covered[k] && !fired.contains(&network.goal(goals[k]).end))
    {
        return Err(ScheduleError::EmptyInterval { goal: goals[k] });
    }
    Ok(out)
}

/// The points grounded by firing (a network being promoted over a running one).
fn fired_points(network: &GoalNetwork) -> Vec<TimePointId> {
    let constraints = network.stn().constraints().iter();
    constraints
        .filter(|c| c.provenance == Provenance::Fired)
        .map(|c| c.to)
        .collect()
}

/// Serial projection and validation of one timeline from `current` (§2.2 step 3).
fn project(
    reconfiguration: &Reconfiguration,
    timeline: &Timeline,
    current: ValueId,
    fired: &[TimePointId],
) -> Result<(), ScheduleError> {
    let reachability = reconfiguration.policy(timeline.sv).reachability();
    let mut projected = vec![current];
    for (i, xgoal) in timeline.xgoals.iter().enumerate() {
        // A promoted proposal keeps its history: an XGoal whose end has fired is over, and the
        // projection starts from the state the SV is in now (promotion step c, §2.3).
        if xgoal.constraint.is_control_free() || fired.contains(&xgoal.end) {
            continue;
        }
        let next: Vec<ValueId> = match xgoal.kind {
            GoalKind::Transition => xgoal
                .constraint
                .admitted()
                .filter(|&target| {
                    projected.iter().any(|&from| {
                        from == target
                            || reachability.is_reversible(from, target)
                            || reachability.is_irreversible(from, target)
                    })
                })
                .collect(),
            _ => {
                let holding: Vec<ValueId> = projected
                    .iter()
                    .copied()
                    .filter(|&v| xgoal.constraint.admits(v))
                    .collect();
                if holding.is_empty() && xgoal.kind == GoalKind::Maintain {
                    // A set the plant enters by itself is a condition the start point waits
                    // for (the firing rule: a Maintain XGoal is ready when its set holds).
                    let plant = reconfiguration.plant();
                    entered_by_itself(plant, timeline.sv, &projected)
                        .into_iter()
                        .filter(|&v| xgoal.constraint.admits(v))
                        .collect()
                } else {
                    holding
                }
            }
        };
        if next.is_empty() {
            let previous = i.checked_sub(1).map(|p| &timeline.xgoals[p]);
            return Err(match (xgoal.kind, previous) {
                (GoalKind::Maintain, Some(previous)) => ScheduleError::TransitionUnachievable {
                    previous: Box::new(previous.clone()),
                    from: projected,
                    next: Box::new(xgoal.clone()),
                },
                _ => ScheduleError::Unachievable {
                    xgoal: Box::new(xgoal.clone()),
                    from: projected,
                },
            });
        }
        projected = next;
    }
    Ok(())
}

/// The nominal modes of `sv` the plant may enter by itself from `from` (transitively): through
/// transitions whose guard names no command — a trigger that sets when the radar acquires the
/// ground, a temperature that drifts. No command brings them about, so no configuration goal
/// can; a Maintain goal on them is a condition to wait for, not a state to achieve.
fn entered_by_itself(plant: &Plant, sv: ComponentId, from: &[ValueId]) -> Vec<ValueId> {
    let component = plant.component(sv);
    let controls: Vec<VarId> = plant.controls().iter().map(|c| c.var).collect();
    let spontaneous = |t: &Transition| {
        component.mode(t.target).kind == ModeKind::Nominal
            && t.guard.variables().iter().all(|v| !controls.contains(v))
    };
    let mut reached: Vec<ValueId> = from.to_vec();
    let mut frontier: Vec<ValueId> = from.to_vec();
    while let Some(mode) = frontier.pop() {
        for &t in component.outgoing(mode) {
            let transition = &component.transitions()[t];
            if spontaneous(transition) && !reached.contains(&transition.target) {
                reached.push(transition.target);
                frontier.push(transition.target);
            }
        }
    }
    reached
}
