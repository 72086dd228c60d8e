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
//!
//! **Cost** (a network of `n` points and `m` constraints, `g` goals): near-linear in the goals.
//! Every constraint the scheduler adds is tried on the network itself (`Stn::try_constraint`:
//! relaxed from its edge, undone exactly if refused), so a trial costs the points it moves,
//! not a copy and a full propagation; the latest times are computed once, at the end. Step 1
//! lists the pairs that do not merge from the goals grouped by control set ([`unmergeable`]),
//! step 2 keeps its candidates ordered ([`order`]), step 3 finds coincident points from the
//! earliest times and, only on a tie, the rigid components (one pass over the graph), and sweeps
//! the points for the goals covering each interval; look-ups are maps. What remains
//! superlinear is inherent in the answer: a pair of goals that do not merge gets its own
//! constraint (two alternating sets on one SV give `g²/4` of them). Before, the scheduler
//! copied and propagated the network for every trial, sorted the candidates of every step with
//! a scan of every constraint, and ran a Bellman–Ford per pair of consecutive points: 1,000
//! Knowledge goals took 2.1 s and 194 MB, 1,000 alternating Transition goals more than five
//! minutes; now 0.03 s and 0.10 s. The scheduler before is kept as the property test's oracle
//! (`reference.rs`): the same timelines, constraints, windows or error on random missions.

mod order;
#[cfg(test)]
mod reference;
// The test support the oracle test shares with the integration tests.
#[cfg(test)]
#[path = "../../../tests/support/goal_workload.rs"]
mod goal_workload;

use super::goal::{GoalId, GoalKind};
use super::network::{ExecutableNetwork, GoalNetwork, Timeline};
use std::collections::BTreeSet;

use rustc_hash::FxHashMap;

use super::constraint_set::ConstraintSet;
use super::stn::Inconsistency;
#[cfg(doc)]
use super::stn::Stn;
use super::temporal_constraint::{Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use super::xgoal::XGoal;
use crate::logic::{ValueId, VarId};
use crate::plant::{ComponentId, ModeKind, Plant, Transition};
use crate::reconfiguration::Reconfiguration;

/// Why a network cannot be scheduled, with the evidence for the message (§2.2 step 4).
#[derive(Debug, Clone, PartialEq)]
pub enum ScheduleError {
    /// The STN has no solution (before or after the scheduler's constraints).
    Inconsistent(Inconsistency),
    /// A goal on one SV cannot hold together with others and cannot be serialised with them
    /// either way.
    Unmergeable {
        /// The state variable.
        sv: ComponentId,
        /// The goal (the later of the first pair found).
        goal: GoalId,
        /// Every goal it conflicts with, in network order (DESIGN.md §15.2: a refusal names
        /// every conflicting goal).
        conflicts: Vec<GoalId>,
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
    /// Points a proposal would have fire before now (DESIGN.md §15.2; promotion step b, a point
    /// whose window is in the past is refused).
    InThePast {
        /// The points, each new or with its latest time moved before now.
        points: Vec<TimePointId>,
        /// The time of the promotion.
        now: f64,
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
            ScheduleError::Unmergeable {
                sv,
                goal,
                conflicts,
            } => {
                let others: Vec<String> = conflicts.iter().map(|g| g.0.to_string()).collect();
                write!(
                    f,
                    "goal {} on component {} can neither hold together nor be serialised with \
                     goals {}",
                    goal.0,
                    sv.0,
                    others.join(", ")
                )
            }
            ScheduleError::InThePast { points, now } => {
                let points: Vec<String> = points.iter().map(|p| p.0.to_string()).collect();
                write!(
                    f,
                    "points {} would have to fire before now ({now} s)",
                    points.join(", ")
                )
            }
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
    let fired = Fired::of(&network);
    let by_sv = goals_by_sv(&network, plant.components().len());
    let mut timelines = Vec::new();
    for &sv in reconfiguration.upstream_first() {
        let goals = by_sv.get(sv.index()).map_or(&[][..], Vec::as_slice);
        if goals.is_empty() {
            continue;
        }
        serialise(&mut network, sv, goals)?;
        let points = order::order(&mut network, goals)?;
        let domain = plant.component(sv).modes().len();
        let xgoals = xgoals(&network, sv, domain, goals, &points, &fired)?;
        let timeline = Timeline { sv, points, xgoals };
        project(reconfiguration, &timeline, current[sv.index()], &fired)?;
        timelines.push(timeline);
    }
    // The trials kept the earliest times up to date; the latest times once, at the end.
    network.propagate().map_err(ScheduleError::Inconsistent)?;
    Ok(ExecutableNetwork { network, timelines })
}

/// The goals on each state variable (by component index), in network order.
fn goals_by_sv(network: &GoalNetwork, components: usize) -> Vec<Vec<GoalId>> {
    let mut by_sv = vec![Vec::new(); components];
    for (i, goal) in network.goals().iter().enumerate() {
        if let Some(goals) = goal.sv.and_then(|sv| by_sv.get_mut(sv.index())) {
            goals.push(GoalId(i as u32));
        }
    }
    by_sv
}

/// The points grounded by firing (a network being promoted over a running one), by point.
struct Fired(Vec<bool>);

impl Fired {
    fn of(network: &GoalNetwork) -> Fired {
        let mut fired = vec![false; network.points().len()];
        for c in network.stn().constraints() {
            if c.provenance == Provenance::Fired
                && let Some(slot) = fired.get_mut(c.to.index())
            {
                *slot = true;
            }
        }
        Fired(fired)
    }

    fn contains(&self, point: TimePointId) -> bool {
        self.0.get(point.index()).copied().unwrap_or(false)
    }
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

/// Serialises every pair of goals on `sv` whose constraints do not merge (§2.2 step 2d), in
/// network order: for each goal, each later goal it does not merge with, `end(a) ≤ start(b)` or
/// else the reverse, each tried on the network itself ([`Stn::try_constraint`]: relaxed from the
/// new edge, a refusal leaves it unchanged). A goal that can be serialised with a goal neither
/// way is reported with every goal it conflicts with so (as the network stands when the first
/// conflict is found: each tried and undone).
fn serialise(
    network: &mut GoalNetwork,
    sv: ComponentId,
    goals: &[GoalId],
) -> Result<(), ScheduleError> {
    for (a, b) in unmergeable(network, goals) {
        if !order_pair(network, a, b, true) {
            let conflicts = (goals.iter().copied())
                .filter(|&c| c != b && !merge(network, c, b) && !order_pair(network, c, b, false))
                .collect();
            return Err(ScheduleError::Unmergeable {
                sv,
                goal: b,
                conflicts,
            });
        }
    }
    Ok(())
}

/// Whether the constraints of goals `a` and `b` merge (hold together on one timeline).
fn merge(network: &GoalNetwork, a: GoalId, b: GoalId) -> bool {
    let (ga, gb) = (network.goal(a), network.goal(b));
    !ga.constraint.merge(&gb.constraint).is_empty()
}

/// Orders goals `a` and `b` on the network — `end(a) ≤ start(b)`, or else the reverse — kept
/// when `keep`, taken back otherwise; false when neither order fits.
fn order_pair(network: &mut GoalNetwork, a: GoalId, b: GoalId, keep: bool) -> bool {
    let (ga, gb) = (network.goal(a), network.goal(b));
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
    for (end, start, reason) in [first, second] {
        let constraint = TemporalConstraint::before(end, start, Provenance::Scheduled { reason });
        if let Ok(trial) = network.stn_mut().try_constraint(constraint) {
            if !keep {
                network.stn_mut().undo(trial);
            }
            return true;
        }
    }
    false
}

/// The pairs `(a, b)` of `goals` (a before b) whose constraints do not merge, in the order of a
/// nested loop over `goals`. Whether two goals merge depends only on their control sets (the
/// merge is empty iff the admitted sets are disjoint), so the goals are grouped by admitted set
/// and the pairs are listed from the groups: the cost is the goals times the groups plus the
/// pairs, not every pair of goals.
fn unmergeable(network: &GoalNetwork, goals: &[GoalId]) -> Vec<(GoalId, GoalId)> {
    let mut groups: Vec<(&ConstraintSet, Vec<usize>)> = Vec::new();
    let mut group_of = Vec::with_capacity(goals.len());
    for (k, &goal) in goals.iter().enumerate() {
        let set = &network.goal(goal).constraint;
        let same = |(other, _): &(&ConstraintSet, Vec<usize>)| other.admitted().eq(set.admitted());
        let group = match groups.iter().position(same) {
            Some(group) => group,
            None => {
                groups.push((set, Vec::new()));
                groups.len() - 1
            }
        };
        groups[group].1.push(k);
        group_of.push(group);
    }
    let disjoint: Vec<Vec<usize>> = (groups.iter())
        .map(|(a, _)| {
            (groups.iter().enumerate())
                .filter(|(_, (b, _))| a.merge(b).is_empty())
                .map(|(g, _)| g)
                .collect()
        })
        .collect();
    let mut pairs = Vec::new();
    for (k, &a) in goals.iter().enumerate() {
        let mut later: Vec<usize> = (disjoint[group_of[k]].iter())
            .flat_map(|&g| {
                let members = &groups[g].1;
                members[members.partition_point(|&m| m <= k)..]
                    .iter()
                    .copied()
            })
            .collect();
        later.sort_unstable();
        pairs.extend(later.into_iter().map(|m| (a, goals[m])));
    }
    pairs
}

/// The XGoals of one timeline (§2.2 step 2c): one per interval of consecutive points not forced
/// to zero length, the merge of the goals covering it. A goal that covers no interval — its
/// start and end forced to one instant — is an [`ScheduleError::EmptyInterval`], unless it is
/// history (its end has fired).
///
/// Consecutive points `a`, `b` (ordered, so `t(a) ≤ t(b)`) coincide iff `d(a, b) ≤ 0`. The
/// earliest times `e` are a solution, so `d(a, b) ≥ e(b) − e(a)`: points with different earliest
/// times do not coincide; points with equal ones coincide iff they are rigidly bound
/// ([`Stn::rigid_components`], computed once per timeline and only when needed). The goals
/// covering each interval come from a sweep over the points (a goal enters at its start and
/// leaves at its end), so the cost is the points plus the XGoals' constituents.
fn xgoals(
    network: &GoalNetwork,
    sv: ComponentId,
    domain: usize,
    goals: &[GoalId],
    points: &[TimePointId],
    fired: &Fired,
) -> Result<Vec<XGoal>, ScheduleError> {
    let stn = network.stn();
    let position: FxHashMap<TimePointId, usize> =
        points.iter().enumerate().map(|(i, &p)| (p, i)).collect();
    let at = |p: TimePointId| position.get(&p).copied().unwrap_or(0);
    let mut starting = vec![Vec::new(); points.len()];
    let mut ending = vec![Vec::new(); points.len()];
    for (k, &id) in goals.iter().enumerate() {
        let goal = network.goal(id);
        let (start, end) = (at(goal.start), at(goal.end));
        if start < end {
            starting[start].push(k);
            ending[end].push(k);
        }
    }
    let mut rigid: Option<Option<Vec<usize>>> = None;
    let mut coincide = |a: TimePointId, b: TimePointId| {
        if stn.earliest(a) != stn.earliest(b) {
            return false;
        }
        let components = rigid.get_or_insert_with(|| stn.rigid_components());
        components
            .as_ref()
            .is_some_and(|c| c[a.index()] == c[b.index()])
    };
    let mut active = BTreeSet::new();
    let mut out = Vec::new();
    let mut covered = vec![false; goals.len()];
    for (i, pair) in points.windows(2).enumerate() {
        for k in &ending[i] {
            active.remove(k);
        }
        active.extend(starting[i].iter().copied());
        let (a, b) = (pair[0], pair[1]);
        if coincide(a, b) {
            continue; // a and b coincide: no interval
        }
        let covering = active.iter().map(|&k| {
            covered[k] = true;
            (goals[k], network.goal(goals[k]))
        });
        out.push(XGoal::merge(sv, a, b, domain, covering));
    }
    if let Some(k) =
        (0..goals.len()).find(|&k| !covered[k] && !fired.contains(network.goal(goals[k]).end))
    {
        return Err(ScheduleError::EmptyInterval { goal: goals[k] });
    }
    Ok(out)
}

/// Serial projection and validation of one timeline from `current` (§2.2 step 3).
fn project(
    reconfiguration: &Reconfiguration,
    timeline: &Timeline,
    current: ValueId,
    fired: &Fired,
) -> Result<(), ScheduleError> {
    let reachability = reconfiguration.policy(timeline.sv).reachability();
    let mut projected = vec![current];
    for (i, xgoal) in timeline.xgoals.iter().enumerate() {
        // A promoted proposal keeps its history: an XGoal whose end has fired is over, and the
        // projection starts from the state the SV is in now (promotion step c, §2.3).
        if xgoal.constraint.is_control_free() || fired.contains(xgoal.end) {
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
