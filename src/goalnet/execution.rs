//! Executing and monitoring a scheduled network, one cycle at a time (mds-goal-networks.md
//! §2.4–2.5, §2.9; AG §1.2.7, GP §3.7–3.8; DESIGN.md §15.2–15.3).
//!
//! Each cycle, given the estimate ŝ (a mode per component) and the belief over each component's
//! modes:
//! 1. **monitoring** (the XGoalChecker): every active XGoal is checked against ŝ and the
//!    belief — a Maintain XGoal fails when ŝ leaves its set, a Transition XGoal when its set can
//!    no longer be reached from ŝ (reconfiguration's reachability), any XGoal when its knowledge
//!    part is not met (P of the most likely value below the threshold, or a least belief not
//!    reached). A failed XGoal is narrowed to the constituent goals that fail on their own. A
//!    goal is reported failed when it starts failing, and **recovered** when it holds again
//!    while its XGoal is active (`GoalRecovered`): it is then monitored as before, and fails —
//!    and is reported, and answered — again if it fails again. A goal whose interval is over
//!    (a Transition failed at its forced end) or whose failure came from outside monitoring (its
//!    controller, a contradicted firing) does not recover. The responses are
//!    [`GoalController`]'s;
//! 2. **firing** (the Executive), repeated to a fixpoint: an unfired point fires when its
//!    earliest time has passed, every point constrained to precede it (a constraint into it with
//!    a minimum ≥ 0) has fired, and it is *ready*: every Maintain XGoal starting at it holds for
//!    ŝ and every Transition XGoal ending at it has reached its set — or anyway at its latest
//!    cycle: the first cycle at or after its latest time, or the last before it when the next
//!    cycle (one period on, the period being the time since the previous cycle) would be past
//!    it (`TimePointForced`; a Transition XGoal ending there unreached fails). Forcing at the
//!    last cycle *inside* the window keeps the firing consistent with the network when cycles
//!    do not line up with the bounds (mds-goal-networks.md §5 C7 keeps it so when they do).
//!    Firing grounds the point and re-propagates incrementally, and dispatches the XGoals that
//!    start there.
//! 3. A firing the network contradicts — a point whose window holds no cycle's time fires at the
//!    first cycle after it — is history: it stays, the constraints of the negative cycle that
//!    are not firings are withdrawn ([`Stn::withdraw`](super::Stn::withdraw)) so that the rest
//!    of the network keeps its windows and fires on, and every goal the point bounds fails
//!    (DESIGN.md §15.2: "a firing that contradicts the network is a failure of the goals it
//!    bounds"), answered like any other failure.
//! 4. A network that has stopped firing with points left says why, once per change
//!    ([`GoalEvent::NetworkStalled`]): a point past its latest time that an unfired point holds
//!    back, a point with no window, or a point with no latest time that waits for a goal that
//!    has failed.
//!
//! A goal **delegated** to a controller (a state variable that is not a
//! component) is on no timeline: its controller judges it. [`Execution::end_delegated`] says that
//! the controller ended its constraint; until then the goal's end point is not ready (it is
//! forced at its latest time, and the goal fails); a failure the controller reports is reported
//! by the next monitoring, like any other, so the failure responses apply to it.
//!
//! Goal interpretation finding the configuration goal unreachable does not fail a goal by
//! itself: without alternatives among redundant components its verdict can be wrong while the
//! plant progresses (the thermostat's switch 1 stuck open, switch 2 warming the device), and
//! failing — re-elaborating — on it broke runs that were going right. A tactic that cannot
//! progress fails at its end point's forcing, with its response.
//!
//! The **configuration goal** is the conjunction of the active Maintain and Transition XGoals'
//! control sets on controllable state variables — the running network's only: a promotion
//! replaces the timelines, so a retired goal is on none; knowledge goals never become commands.

use super::constraint_set::ConstraintSet;
#[cfg(doc)]
use super::controller::GoalController;
use super::goal::{GoalId, GoalKind};
use super::network::ExecutableNetwork;
use super::stn::{GroundError, Inconsistency};
use super::temporal_constraint::{Provenance, TemporalConstraint};
use super::time_point::TimePointId;
use super::xgoal::XGoal;
use crate::logic::{Formula, ValueId};
use crate::plant::ComponentId;
use crate::reconfiguration::Reconfiguration;

/// Two times closer than this are the same instant (cycle times and bounds are sums of seconds).
pub(crate) const TIME_EPSILON: f64 = 1e-6;

/// What the estimator says this cycle: ŝ and the belief over each component's modes.
#[derive(Debug, Clone, Copy)]
pub struct EstimateView<'a> {
    /// The most likely mode of each component.
    pub modes: &'a [ValueId],
    /// Per component, the probability of each of its modes.
    pub beliefs: &'a [Vec<f64>],
}

/// Why a goal failed.
#[derive(Debug, Clone, PartialEq)]
pub enum FailureReason {
    /// ŝ left a Maintain goal's set (the mode it is in).
    Excursion(ValueId),
    /// A Transition goal's set cannot be reached from ŝ any more (the mode it is in).
    Unreachable(ValueId),
    /// A Transition goal's end point was forced with the set not reached.
    EndForced(ValueId),
    /// The knowledge requirement is not met.
    NotKnown,
    /// A delegated goal's controller ended its constraint unachieved, or had not ended it when
    /// the goal's end point was forced.
    Delegated {
        /// The state variable's value as the controller last heard it, if known here.
        value: Option<String>,
        /// What the controller said (or did not say), in words.
        why: String,
    },
    /// A point bounding the goal fired where the network did not allow it (no cycle fell in
    /// its window); the constraints its firing contradicted were withdrawn.
    Contradicted {
        /// The point.
        point: TimePointId,
    },
}

impl FailureReason {
    /// Whether a goal failed for this reason is judged again by monitoring, and recovers when
    /// it holds: a failure monitoring found. A forced end, a contradicted firing and a
    /// controller's verdict are over.
    fn recovers(&self) -> bool {
        matches!(
            self,
            FailureReason::Excursion(_) | FailureReason::Unreachable(_) | FailureReason::NotKnown
        )
    }
}

/// Something that happened to the network this cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum GoalEvent {
    /// A point fired on time.
    TimePointFired {
        /// The point.
        point: TimePointId,
    },
    /// A point fired at its latest cycle without its XGoals ready.
    TimePointForced {
        /// The point.
        point: TimePointId,
        /// How late past its latest time, seconds (negative: the last cycle before it, the
        /// next one being past it).
        late_by: f64,
    },
    /// An XGoal became active on its state variable.
    XGoalDispatched {
        /// The state variable.
        sv: ComponentId,
        /// The XGoal's index in the SV's timeline.
        index: usize,
    },
    /// A goal failed (narrowed from its XGoal).
    GoalFailed {
        /// The goal.
        goal: GoalId,
        /// Why.
        reason: FailureReason,
    },
    /// A goal that had failed holds again; it is monitored as before.
    GoalRecovered {
        /// The goal.
        goal: GoalId,
    },
    /// Grounding a point contradicted the network; the constraints of the cycle that are not
    /// firings were withdrawn.
    TemporalInconsistency {
        /// The point.
        point: TimePointId,
        /// The constraints of the negative cycle, as they were (a promotion later in the cycle
        /// renumbers the network's constraints; point and goal ids stay).
        cycle: Vec<TemporalConstraint>,
    },
    /// Points are left that nothing will fire (reported when the set changes).
    NetworkStalled {
        /// Each stalled point and what it waits for.
        stalled: Vec<(TimePointId, Waiting)>,
    },
}

/// What a stalled point waits for.
#[derive(Debug, Clone, PartialEq)]
pub enum Waiting {
    /// The network has no windows (it could not be propagated).
    NoWindow,
    /// Its latest time has passed and this point, which must fire first, has not.
    Point(TimePointId),
    /// It has no latest time and waits for this goal to hold, which has failed.
    Goal(GoalId),
}

/// A scheduled network being executed.
#[derive(Debug, Clone)]
pub struct Execution {
    executable: ExecutableNetwork,
    threshold: f64,
    /// Firing time of each point (the origin fires at 0).
    fired: Vec<Option<f64>>,
    /// Per timeline, the index of its active XGoal.
    active: Vec<Option<usize>>,
    /// Per goal, why it is failing (`None`: it holds, or has recovered).
    failing: Vec<Option<FailureReason>>,
    /// Per point, the points that must fire before it.
    predecessors: Vec<Vec<TimePointId>>,
    /// Points of an earlier network that a promotion retired: they never fire.
    retired: Vec<bool>,
    /// Per goal, whether the controller of a delegated goal has ended its constraint.
    ended: Vec<bool>,
    /// Failures a delegated goal's controller reported, for the next monitoring.
    reported: Vec<(GoalId, FailureReason)>,
    /// The time of the last [`Execution::advance`]: the next cycle is expected one period on.
    last_advance: Option<f64>,
    /// The stalled points last reported.
    stalled: Vec<TimePointId>,
}

impl Execution {
    /// Feeds what decides the execution's future to `state` (exploration's deduplication): the
    /// firing times, the active XGoal per timeline, the failing goals, the retired points, the
    /// reports pending, the last cycle's time (the period forcing reads) and the stall last
    /// reported. The windows and predecessors follow from the network and the firing times.
    pub fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        for time in &self.fired {
            time.map(f64::to_bits).hash(state);
        }
        self.active.hash(state);
        for failing in &self.failing {
            failing.is_some().hash(state);
        }
        self.retired.hash(state);
        self.ended.hash(state);
        for (goal, _) in &self.reported {
            goal.hash(state);
        }
        self.last_advance.map(f64::to_bits).hash(state);
        self.stalled.hash(state);
    }

    /// Starts executing `executable` with the mission's knowledge threshold; the origin has
    /// fired at time 0.
    pub fn new(executable: ExecutableNetwork, threshold: f64) -> Self {
        let n = executable.network.points().len();
        let mut fired = vec![None; n];
        fired[TimePointId::ORIGIN.index()] = Some(0.0);
        let goals = executable.network.goals().len();
        let mut execution = Self::with_history(
            executable,
            threshold,
            fired,
            vec![None; goals],
            vec![false; n],
        );
        execution.ended = vec![false; goals];
        execution
    }

    /// Continues `previous` on `executable`, a promoted network that extends its network (the
    /// same ids for the same points and goals, new ones after; mds-goal-networks.md §2.3 steps
    /// d–i): fired points stay fired at their times, failing goals stay failing, the points
    /// `retired` marks (of the old network, no longer wanted) never fire, and each timeline's
    /// active XGoal is the one whose start has fired and whose end has not.
    pub fn resume(executable: ExecutableNetwork, previous: &Execution, retired: Vec<bool>) -> Self {
        let network = &executable.network;
        let mut fired = previous.fired.clone();
        fired.resize(network.points().len(), None);
        let mut failing = previous.failing.clone();
        failing.resize(network.goals().len(), None);
        let mut ended = previous.ended.clone();
        ended.resize(network.goals().len(), false);
        let mut execution =
            Self::with_history(executable, previous.threshold, fired, failing, retired);
        execution.ended = ended;
        execution.reported = previous.reported.clone();
        execution.last_advance = previous.last_advance;
        execution.stalled = previous.stalled.clone();
        execution
    }

    fn with_history(
        executable: ExecutableNetwork,
        threshold: f64,
        fired: Vec<Option<f64>>,
        failing: Vec<Option<FailureReason>>,
        mut retired: Vec<bool>,
    ) -> Self {
        let network = &executable.network;
        let n = network.points().len();
        retired.resize(n, false);
        let predecessors = network.stn().predecessors();
        let has_fired = |p: TimePointId| fired[p.index()].is_some();
        let active = executable
            .timelines
            .iter()
            .map(|t| {
                t.xgoals
                    .iter()
                    .position(|x| has_fired(x.start) && !has_fired(x.end))
            })
            .collect();
        Execution {
            executable,
            threshold,
            fired,
            active,
            failing,
            predecessors,
            retired,
            ended: Vec::new(),
            reported: Vec::new(),
            last_advance: None,
            stalled: Vec::new(),
        }
    }

    /// The knowledge threshold it monitors with.
    pub fn threshold(&self) -> f64 {
        self.threshold
    }

    /// Whether a point was retired by a promotion (it never fires).
    pub fn is_retired(&self, point: TimePointId) -> bool {
        self.retired.get(point.index()).copied().unwrap_or(false)
    }

    /// When each point fired, by point id (`None`: not yet).
    pub fn fired_times(&self) -> &[Option<f64>] {
        &self.fired
    }

    /// The network being executed (windows shrink as points fire).
    pub fn executable(&self) -> &ExecutableNetwork {
        &self.executable
    }

    /// When a point fired, if it has.
    pub fn fired_at(&self, point: TimePointId) -> Option<f64> {
        self.fired.get(point.index()).copied().flatten()
    }

    /// Whether a goal is failing (it failed and has not recovered).
    pub fn has_failed(&self, goal: GoalId) -> bool {
        self.failing.get(goal.index()).is_some_and(Option::is_some)
    }

    /// The controller of a delegated goal ended its constraint: achieved (`None`) or not (the
    /// failure, reported by the next monitoring). Either way the goal no longer holds its end
    /// point back.
    pub fn end_delegated(&mut self, goal: GoalId, failure: Option<FailureReason>) {
        if let Some(ended) = self.ended.get_mut(goal.index()) {
            *ended = true;
            self.reported.extend(failure.map(|f| (goal, f)));
        }
    }

    /// Whether the controller of a delegated goal has ended its constraint.
    pub fn has_ended(&self, goal: GoalId) -> bool {
        self.ended.get(goal.index()).copied().unwrap_or(false)
    }

    /// Whether `point` has fired or must fire this cycle at `now`: its latest time has come, or
    /// the next cycle (one period on) would be past it — when [`Execution::advance`] forces it.
    pub fn ends_this_cycle(&self, point: TimePointId, now: f64) -> bool {
        if self.fired_at(point).is_some() {
            return true;
        }
        let Some(window) = self.executable.network.stn().window(point) else {
            return false;
        };
        at_latest(window.ub, now, self.next_cycle(now))
    }

    /// When the next cycle is expected after one at `now`: one period on (none is known before
    /// a second cycle).
    fn next_cycle(&self, now: f64) -> Option<f64> {
        self.last_advance
            .filter(|last| now > *last + TIME_EPSILON)
            .map(|last| 2.0 * now - last)
    }

    /// The active XGoal of a state variable.
    pub fn active(&self, sv: ComponentId) -> Option<&XGoal> {
        let t = self.executable.timelines.iter().position(|t| t.sv == sv)?;
        self.active[t].map(|i| &self.executable.timelines[t].xgoals[i])
    }

    /// Whether every point (not retired) has fired.
    pub fn is_complete(&self) -> bool {
        self.fired
            .iter()
            .zip(&self.retired)
            .all(|(fired, retired)| fired.is_some() || *retired)
    }

    /// One cycle at `now`: monitoring, then firing to a fixpoint (§2.9 steps 3 and 5).
    pub fn step(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
    ) -> Vec<GoalEvent> {
        let mut events = self.check(estimate, reconfiguration);
        events.extend(self.advance(now, estimate));
        events
    }

    /// The first half of a cycle (§2.9 step 3, the XGoalChecker): monitoring alone, so that
    /// failure responses can run before anything fires.
    pub fn check(
        &mut self,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
    ) -> Vec<GoalEvent> {
        let mut events = Vec::new();
        for (goal, reason) in std::mem::take(&mut self.reported) {
            self.fail(goal, reason, &mut events);
        }
        self.monitor(estimate, reconfiguration, &mut events);
        events
    }

    /// The second half of a cycle (§2.9 step 5, the Executive): firing to a fixpoint, then
    /// whether the network has stalled. Called again in a cycle (after a promotion), it fires
    /// what the promoted network makes due.
    pub fn advance(&mut self, now: f64, estimate: EstimateView) -> Vec<GoalEvent> {
        let mut events = Vec::new();
        let next = self.next_cycle(now);
        while self.fire_one(now, next, estimate, &mut events) {}
        if self
            .last_advance
            .is_none_or(|last| now > last + TIME_EPSILON)
        {
            self.last_advance = Some(now);
        }
        events.extend(self.stall(now));
        events
    }

    /// The conjunction of the active Maintain and Transition XGoals' control sets on the state
    /// variables `controllable` admits.
    pub fn configuration_goal(
        &self,
        reconfiguration: &Reconfiguration,
        controllable: impl Fn(ComponentId) -> bool,
    ) -> Formula {
        let plant = reconfiguration.plant();
        let parts = self
            .active_xgoals()
            .filter(|x| matches!(x.kind, GoalKind::Maintain | GoalKind::Transition))
            .filter(|x| !x.constraint.is_control_free() && controllable(x.sv))
            .map(|x| {
                let var = plant.component(x.sv).mode_var();
                let admitted = x.constraint.admitted().map(|v| Formula::is(var, v));
                Formula::Or(admitted.collect())
            });
        Formula::all(parts)
    }

    fn active_xgoals(&self) -> impl Iterator<Item = &XGoal> {
        self.executable
            .timelines
            .iter()
            .zip(&self.active)
            .filter_map(|(t, a)| a.map(|i| &t.xgoals[i]))
    }

    /// Checks every active XGoal; narrows failures to constituents, and notes the failed
    /// constituents that hold again (§2.5).
    fn monitor(
        &mut self,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        events: &mut Vec<GoalEvent>,
    ) {
        let mut failures = Vec::new();
        let mut recoveries = Vec::new();
        for xgoal in self.active_xgoals() {
            let (mode, belief) = (
                estimate.modes[xgoal.sv.index()],
                &estimate.beliefs[xgoal.sv.index()],
            );
            let reachable = |set: &ConstraintSet| {
                let reachability = reconfiguration.policy(xgoal.sv).reachability();
                set.admitted().any(|v| {
                    v == mode
                        || reachability.is_reversible(mode, v)
                        || reachability.is_irreversible(mode, v)
                })
            };
            let judge = |kind: GoalKind, set: &ConstraintSet| {
                if !set.knowledge_met(belief, self.threshold) {
                    Some(FailureReason::NotKnown)
                } else if kind == GoalKind::Maintain && !set.admits(mode) {
                    Some(FailureReason::Excursion(mode))
                } else if kind == GoalKind::Transition && !reachable(set) {
                    Some(FailureReason::Unreachable(mode))
                } else {
                    None
                }
            };
            let xgoal_fails = judge(xgoal.kind, &xgoal.constraint).is_some();
            for &id in &xgoal.constituents {
                let failing = self.failing[id.index()].as_ref();
                if !xgoal_fails && failing.is_none() {
                    continue; // the XGoal holds, so does every constituent
                }
                let goal = self.executable.network.goal(id);
                let verdict = judge(goal.kind, &goal.constraint);
                match (verdict, failing) {
                    (Some(reason), None) => failures.push((id, reason)),
                    (None, Some(reason)) if reason.recovers() => recoveries.push(id),
                    _ => {}
                }
            }
        }
        for goal in recoveries {
            self.failing[goal.index()] = None;
            events.push(GoalEvent::GoalRecovered { goal });
        }
        for (goal, reason) in failures {
            self.fail(goal, reason, events);
        }
    }

    /// Reports `goal` failed unless it is failing already.
    fn fail(&mut self, goal: GoalId, reason: FailureReason, events: &mut Vec<GoalEvent>) {
        let Some(failing) = self.failing.get_mut(goal.index()) else {
            return;
        };
        if failing.is_none() {
            *failing = Some(reason.clone());
            events.push(GoalEvent::GoalFailed { goal, reason });
        }
    }

    /// Fires the first point that should fire now; false when none does. `next` is when the
    /// next cycle is expected.
    fn fire_one(
        &mut self,
        now: f64,
        next: Option<f64>,
        estimate: EstimateView,
        events: &mut Vec<GoalEvent>,
    ) -> bool {
        let n = self.fired.len();
        for i in 0..n {
            let point = TimePointId(i as u32);
            if self.fired[i].is_some() || self.retired[i] {
                continue;
            }
            let Some(window) = self.executable.network.stn().window(point) else {
                continue;
            };
            let predecessors_fired = self.predecessors[i]
                .iter()
                .all(|q| self.fired[q.index()].is_some());
            if now < window.lb - TIME_EPSILON || !predecessors_fired {
                continue;
            }
            let latest = at_latest(window.ub, now, next);
            let ready = self.ready(point, estimate);
            if !ready && !latest {
                continue;
            }
            // Forced only when not ready: a ready point at its latest cycle is on time.
            let late_by = (!ready).then_some(now - window.ub);
            self.fire(point, now, late_by, estimate, events);
            return true;
        }
        false
    }

    /// `point` is ready to transition (§2.4 (a), the seeds' `is_ready_to_transition(incoming,
    /// current, outgoing)`): every Maintain XGoal starting there holds for ŝ, every Transition
    /// XGoal ending there has reached its set, and every delegated goal ending there has been
    /// ended by its controller. The incoming half is why a point that ends a transition waits
    /// within its window for the transition to complete, and is forced — failing the transition
    /// unreached — only at its latest cycle; without it an on-time end would let an unreached
    /// Transition goal pass unnoticed.
    fn ready(&self, point: TimePointId, estimate: EstimateView) -> bool {
        let holds = |x: &XGoal| {
            x.constraint.satisfied_by(
                estimate.modes[x.sv.index()],
                &estimate.beliefs[x.sv.index()],
                self.threshold,
            )
        };
        let delegated_ended = (self.executable.network.goals().iter().enumerate())
            .filter(|(_, g)| g.delegate.is_some() && g.end == point)
            .all(|(i, _)| self.ended[i]);
        delegated_ended && self.gating(point).all(holds)
    }

    /// The XGoals `point`'s readiness waits for: the Maintain XGoals starting there and the
    /// Transition XGoals ending there.
    fn gating(&self, point: TimePointId) -> impl Iterator<Item = &XGoal> {
        let timelines = self.executable.timelines.iter();
        timelines.flat_map(|t| &t.xgoals).filter(move |x| {
            (x.start == point && x.kind == GoalKind::Maintain)
                || (x.end == point && x.kind == GoalKind::Transition)
        })
    }

    fn fire(
        &mut self,
        point: TimePointId,
        now: f64,
        late_by: Option<f64>,
        estimate: EstimateView,
        events: &mut Vec<GoalEvent>,
    ) {
        self.fired[point.index()] = Some(now);
        match late_by {
            None => events.push(GoalEvent::TimePointFired { point }),
            Some(late_by) => {
                events.push(GoalEvent::TimePointForced { point, late_by });
                self.fail_unreached_transitions(point, estimate, events);
            }
        }
        if let Err(GroundError::Inconsistent(inconsistency)) =
            self.executable.network.stn_mut().ground(point, now)
        {
            self.contradicted(point, inconsistency, events);
        }
        for (t, timeline) in self.executable.timelines.iter().enumerate() {
            if let Some(index) = timeline.xgoals.iter().position(|x| x.start == point) {
                self.active[t] = Some(index);
                events.push(GoalEvent::XGoalDispatched {
                    sv: timeline.sv,
                    index,
                });
            } else if timeline.xgoals.iter().any(|x| x.end == point) {
                self.active[t] = None;
            }
        }
    }

    /// `point` fired where the network did not allow it: the firing stays (it happened), the
    /// constraints of each negative cycle that are not firings (nor a point's `[0, +∞)` from the
    /// origin) are withdrawn until the network is consistent again, and every goal the point
    /// bounds fails.
    fn contradicted(
        &mut self,
        point: TimePointId,
        inconsistency: Inconsistency,
        events: &mut Vec<GoalEvent>,
    ) {
        let stn = self.executable.network.stn_mut();
        let mut cycle = inconsistency.cycle.clone();
        // Each round withdraws at least one constraint, or stops.
        for _ in 0..stn.constraints().len() {
            let withdrawn: Vec<_> = (cycle.iter().copied())
                .filter(|&id| {
                    !matches!(
                        stn.constraint(id).provenance,
                        Provenance::Fired | Provenance::AfterOrigin
                    )
                })
                .collect();
            if withdrawn.is_empty() {
                break;
            }
            match stn.withdraw(&withdrawn) {
                Ok(()) => break,
                Err(next) => cycle = next.cycle,
            }
        }
        self.predecessors = self.executable.network.stn().predecessors();
        let stn = self.executable.network.stn();
        let cycle = (inconsistency.cycle.iter())
            .map(|id| stn.constraint(*id).clone())
            .collect();
        events.push(GoalEvent::TemporalInconsistency { point, cycle });
        let bounded: Vec<GoalId> = (self.executable.network.goals().iter().enumerate())
            .filter(|(_, g)| g.sv.is_some() || g.delegate.is_some())
            .filter(|(_, g)| g.start == point || g.end == point)
            .map(|(i, _)| GoalId(i as u32))
            .collect();
        for goal in bounded {
            self.fail(goal, FailureReason::Contradicted { point }, events);
        }
    }

    /// A forced end point fails the Transition goals ending there unreached (§2.4 (b)), and the
    /// delegated goals ending there that their controller has not ended.
    fn fail_unreached_transitions(
        &mut self,
        point: TimePointId,
        estimate: EstimateView,
        events: &mut Vec<GoalEvent>,
    ) {
        let mut failures = Vec::new();
        for (id, goal) in self.executable.network.goals().iter().enumerate() {
            if goal.delegate.is_some() && goal.end == point && !self.ended[id] {
                let why = "its end point was forced before its controller ended the constraint";
                let reason = FailureReason::Delegated {
                    value: None,
                    why: why.to_string(),
                };
                failures.push((GoalId(id as u32), reason));
            }
            let Some(sv) = goal.sv else { continue };
            let mode = estimate.modes[sv.index()];
            if goal.end == point
                && goal.kind == GoalKind::Transition
                && !goal.constraint.admits(mode)
            {
                failures.push((GoalId(id as u32), FailureReason::EndForced(mode)));
            }
        }
        for (goal, reason) in failures {
            self.fail(goal, reason, events);
        }
    }

    /// The points nothing will fire, reported when that set changes (DESIGN.md §15.2: a network
    /// that has stopped firing with time left says why).
    fn stall(&mut self, now: f64) -> Option<GoalEvent> {
        let stalled = self.stalled_points(now);
        let points: Vec<TimePointId> = stalled.iter().map(|(p, _)| *p).collect();
        if points == self.stalled {
            return None;
        }
        self.stalled = points;
        (!stalled.is_empty()).then_some(GoalEvent::NetworkStalled { stalled })
    }

    /// Every unfired point (not retired) that cannot fire any more, and what it waits for: no
    /// window; past its latest time behind an unfired point; or no latest time, enabled, and
    /// held back by a goal that is failing.
    fn stalled_points(&self, now: f64) -> Vec<(TimePointId, Waiting)> {
        let stn = self.executable.network.stn();
        // Only a failing goal holds a point back for ever: without one, no search of the
        // timelines (this runs every cycle).
        let any_failing = self.failing.iter().any(Option::is_some);
        let mut stalled = Vec::new();
        for i in 0..self.fired.len() {
            let point = TimePointId(i as u32);
            if self.fired[i].is_some() || self.retired[i] {
                continue;
            }
            let Some(window) = stn.window(point) else {
                stalled.push((point, Waiting::NoWindow));
                continue;
            };
            let unfired = (self.predecessors[i].iter())
                .find(|q| self.fired[q.index()].is_none())
                .copied();
            if now > window.ub + TIME_EPSILON {
                stalled.push((point, unfired.map_or(Waiting::NoWindow, Waiting::Point)));
            } else if any_failing
                && window.ub.is_infinite()
                && unfired.is_none()
                && now >= window.lb
            {
                let failed = self.failed_holding_back(point);
                stalled.extend(failed.map(|g| (point, Waiting::Goal(g))));
            }
        }
        stalled
    }

    /// A failing goal among those `point`'s readiness waits for (whatever ŝ is).
    fn failed_holding_back(&self, point: TimePointId) -> Option<GoalId> {
        let network = &self.executable.network;
        let gating = self.gating(point);
        let delegated = (network.goals().iter().enumerate())
            .filter(|(i, g)| g.delegate.is_some() && g.end == point && !self.ended[*i])
            .map(|(i, _)| GoalId(i as u32));
        gating
            .flat_map(|x| x.constituents.iter().copied())
            .chain(delegated)
            .find(|&g| self.has_failed(g))
    }
}

/// Whether a point whose latest time is `latest` must fire in the cycle at `now`: its latest
/// time has come, or the next cycle (at `next`, if known) would be past it.
fn at_latest(latest: f64, now: f64, next: Option<f64>) -> bool {
    now >= latest - TIME_EPSILON || next.is_some_and(|next| next > latest + TIME_EPSILON)
}
