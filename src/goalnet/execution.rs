//! Executing and monitoring a scheduled network, one cycle at a time (mds-goal-networks.md
//! §2.4–2.5, §2.9; AG §1.2.7, GP §3.7–3.8; DESIGN.md §15.3).
//!
//! Each cycle, given the estimate ŝ (a mode per component) and the belief over each component's
//! modes:
//! 1. **monitoring** (the XGoalChecker): every active XGoal is checked against ŝ and the
//!    belief — a Maintain XGoal fails when ŝ leaves its set, a Transition XGoal when its set can
//!    no longer be reached from ŝ (reconfiguration's reachability), any XGoal when its knowledge
//!    part is not met (P of the most likely value below the threshold, or a least belief not
//!    reached). A failed XGoal is narrowed to the constituent goals that fail on their own; each
//!    is reported once and stays failed (the responses are [`GoalController`]'s);
//! 2. **firing** (the Executive), repeated to a fixpoint: an unfired point fires when its
//!    earliest time has passed, every point constrained to precede it (a constraint into it with
//!    a minimum ≥ 0) has fired, and it is *ready*: every Maintain XGoal starting at it holds for
//!    ŝ and every Transition XGoal ending at it has reached its set — or anyway at the first
//!    cycle at or after its latest time (`TimePointForced`; a Transition XGoal ending there
//!    unreached fails). Firing grounds the point and re-propagates incrementally, and
//!    dispatches the XGoals that start there.
//!
//! A goal **delegated** to a controller (a state variable that is not a
//! component) is on no timeline: its controller judges it. [`Execution::end_delegated`] says that
//! the controller ended its constraint; until then the goal's end point is not ready (it is
//! forced at its latest time, and the goal fails); a failure the controller reports is reported
//! by the next monitoring, like any other, so the failure responses apply to it.
//!
//! The **configuration goal** is the conjunction of the active Maintain and Transition XGoals'
//! control sets on controllable state variables; knowledge goals never become commands.

use super::constraint_set::ConstraintSet;
#[cfg(doc)]
use super::controller::GoalController;
use super::goal::{GoalId, GoalKind};
use super::network::ExecutableNetwork;
use super::stn::{GroundError, Inconsistency};
use super::time_point::TimePointId;
use super::xgoal::XGoal;
use crate::logic::{Formula, ValueId};
use crate::plant::ComponentId;
use crate::reconfiguration::Reconfiguration;

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
}

/// Something that happened to the network this cycle.
#[derive(Debug, Clone, PartialEq)]
pub enum GoalEvent {
    /// A point fired on time.
    TimePointFired {
        /// The point.
        point: TimePointId,
    },
    /// A point fired at its latest time without its XGoals ready.
    TimePointForced {
        /// The point.
        point: TimePointId,
        /// How late past its latest time, seconds.
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
    /// Grounding a (forced) point contradicted the network.
    TemporalInconsistency {
        /// The point.
        point: TimePointId,
        /// The negative cycle.
        inconsistency: Inconsistency,
    },
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
    /// Goals that failed (they stay failed).
    failed: Vec<bool>,
    /// Per point, the points that must fire before it.
    predecessors: Vec<Vec<TimePointId>>,
    /// Points of an earlier network that a promotion retired: they never fire.
    retired: Vec<bool>,
    /// Per goal, whether the controller of a delegated goal has ended its constraint.
    ended: Vec<bool>,
    /// Failures of delegated goals their controllers reported, for the next monitoring.
    reported: Vec<(GoalId, FailureReason)>,
}

impl Execution {
    /// Feeds what decides the execution's future to `state` (exploration's deduplication): the
    /// firing times, the active XGoal per timeline, the failed goals and the retired points. The
    /// windows and predecessors follow from the network and the firing times.
    pub fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        for time in &self.fired {
            time.map(f64::to_bits).hash(state);
        }
        self.active.hash(state);
        self.failed.hash(state);
        self.retired.hash(state);
        self.ended.hash(state);
        for (goal, _) in &self.reported {
            goal.hash(state);
        }
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
            vec![false; goals],
            vec![false; n],
        );
        execution.ended = vec![false; goals];
        execution
    }

    /// Continues `previous` on `executable`, a promoted network that extends its network (the
    /// same ids for the same points and goals, new ones after; mds-goal-networks.md §2.3 steps
    /// d–i): fired points stay fired at their times, failed goals stay failed, the points
    /// `retired` marks (of the old network, no longer wanted) never fire, and each timeline's
    /// active XGoal is the one whose start has fired and whose end has not.
    pub fn resume(executable: ExecutableNetwork, previous: &Execution, retired: Vec<bool>) -> Self {
        let network = &executable.network;
        let mut fired = previous.fired.clone();
        fired.resize(network.points().len(), None);
        let mut failed = previous.failed.clone();
        failed.resize(network.goals().len(), false);
        let mut ended = previous.ended.clone();
        ended.resize(network.goals().len(), false);
        let mut execution =
            Self::with_history(executable, previous.threshold, fired, failed, retired);
        execution.ended = ended;
        execution.reported = previous.reported.clone();
        execution
    }

    fn with_history(
        executable: ExecutableNetwork,
        threshold: f64,
        fired: Vec<Option<f64>>,
        failed: Vec<bool>,
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
            failed,
            predecessors,
            retired,
            ended: Vec::new(),
            reported: Vec::new(),
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

    /// Whether each goal has failed, by goal id.
    pub fn failed_goals(&self) -> &[bool] {
        &self.failed
    }

    /// The network being executed (windows shrink as points fire).
    pub fn executable(&self) -> &ExecutableNetwork {
        &self.executable
    }

    /// When a point fired, if it has.
    pub fn fired_at(&self, point: TimePointId) -> Option<f64> {
        self.fired.get(point.index()).copied().flatten()
    }

    /// Whether a goal has failed.
    pub fn has_failed(&self, goal: GoalId) -> bool {
        self.failed.get(goal.index()).copied().unwrap_or(false)
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

    /// The second half of a cycle (§2.9 step 5, the Executive): firing to a fixpoint.
    pub fn advance(&mut self, now: f64, estimate: EstimateView) -> Vec<GoalEvent> {
        let mut events = Vec::new();
        while self.fire_one(now, estimate, &mut events) {}
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

    /// Checks every active XGoal; narrows failures to constituents (§2.5).
    fn monitor(
        &mut self,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        events: &mut Vec<GoalEvent>,
    ) {
        let mut failures = Vec::new();
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
            if judge(xgoal.kind, &xgoal.constraint).is_none() {
                continue;
            }
            for &id in &xgoal.constituents {
                let goal = self.executable.network.goal(id);
                if let Some(reason) = judge(goal.kind, &goal.constraint) {
                    failures.push((id, reason));
                }
            }
        }
        for (goal, reason) in failures {
            self.fail(goal, reason, events);
        }
    }

    fn fail(&mut self, goal: GoalId, reason: FailureReason, events: &mut Vec<GoalEvent>) {
        if !std::mem::replace(&mut self.failed[goal.index()], true) {
            events.push(GoalEvent::GoalFailed { goal, reason });
        }
    }

    /// Fires the first point that should fire now; false when none does.
    fn fire_one(&mut self, now: f64, estimate: EstimateView, events: &mut Vec<GoalEvent>) -> bool {
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
            if now < window.lb || !predecessors_fired {
                continue;
            }
            let ready = self.ready(point, estimate);
            if !ready && now < window.ub {
                continue;
            }
            // Forced only when not ready: a ready point at its latest time is on time.
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
    /// unreached — only at its latest time; without it an on-time end would let an unreached
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
        delegated_ended
            && self.executable.timelines.iter().all(|t| {
                t.xgoals.iter().all(|x| {
                    let entering = x.start == point && x.kind == GoalKind::Maintain;
                    let completing = x.end == point && x.kind == GoalKind::Transition;
                    !(entering || completing) || holds(x)
                })
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
            events.push(GoalEvent::TemporalInconsistency {
                point,
                inconsistency,
            });
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
}
