//! The per-cycle mission executive (MDS's ElaborationManager, XGoalChecker and Executive
//! together; mds-goal-networks.md §2.3, §2.5–2.9; DESIGN.md §15.2–15.3): a [`GoalController`]
//! owns the running [`Execution`] and the elaboration tree, and each cycle
//! 1. monitors the running network (the XGoalChecker): failures, and goals that hold again;
//! 2. answers the failures (§2.5 step 4, §2.6): each failed goal's type gives its response —
//!    `Ignore`, `Safing`, `FailUp` to the parent (a root goes to safing), `ReElaborate` the goal
//!    with its next tactic, cyclically, within its budget (§2.7); a re-elaboration that finds no
//!    tactic (or whose goal's interval is over) is a failure of that goal with no response
//!    left: it fails up. Re-elaborations are done once per goal per cycle; if any failure leads
//!    to safing, safing wins and the safe network is promoted once;
//!
//!    A goal's interval is *over* when its end point has fired or is due this cycle (its
//!    latest time has come, [`Execution::ends_this_cycle`]): a tactic would have no time to
//!    act in. A re-elaboration asked for such a goal because a goal *below* it failed — the goal
//!    itself holds — ends the chain there (`IntervalEnds`): there is nothing left to repair,
//!    and the goal is judged on its own at its end, like any other. Failing up instead would
//!    climb to the root and safe a mission whose goal is met at the very cycle it ends (the
//!    thermostat's switch 1 sticking open six seconds before StayWarm's end: its heater goal
//!    fails in the cycle TP_E is due, while the temperature is still warm). A goal that failed
//!    itself at its end still fails up: it was not met, and its parent may have time left;
//! 3. fires points and dispatches (the Executive), on whatever network now runs; the failures
//!    firing finds — a Transition goal whose end was forced unreached, the goals a contradicted
//!    firing bounds — are answered in the same cycle, and the network then running fires again
//!    (a few rounds; what is left is answered first thing the next cycle).
//!
//! **One path answers every failure, exactly once** (DESIGN.md §15.2): monitoring's, firing's,
//! and a delegated goal's controller's all go through [`GoalController::step`]'s answer, and each `GoalFailed` gets one
//! `ResponseTaken`: its chain, or — in a mission that declares no goal types, or once safing has
//! been invoked — that no response is taken and why. A goal that fails again after recovering
//! is answered again (a re-elaboration within its type's budget).
//!
//! Every promotion follows §2.3: the proposal is a copy of the running network
//! ([`Proposal`]) without the retired elaboration's goals, unfired points *and* the temporal
//! constraints its tactic wrote, edited (elaborated), scheduled from the current estimate (each
//! SV must be able to move from where it is into the proposed XGoals, step c) with its new points
//! anchored at or after now (step b) — a point whose window the proposal puts before now is
//! refused — and only then replaces the running one; a failed promotion leaves the running
//! network as it was and says why.
//!
//! **Safe networks are scheduled best effort** (§2.8): a safe goal that cannot be scheduled
//! from the state safing finds (a valve stuck where it cannot be closed) is dropped and reported
//! with its reason, and the rest of the safe network is promoted.
//!
//! The controller has the shape of [`Execution`] (`step`, `configuration_goal`) so an
//! executive runs either; the mission's initial network is elaborated and promoted when the
//! controller is made, and those events come with the first `step`.

use super::achievable::judge_delegated;
use super::elaborate::{Context, ElaborationState, Rejection, elaborate};
use super::events::{Explanation, MissionEvent, ResponseStep};
use super::execution::{EstimateView, Execution, FailureReason, GoalEvent, TIME_EPSILON};
use super::goal::GoalId;
use super::mission::Mission;
use super::network::{ExecutableNetwork, GoalNetwork};
use super::proposal::{Proposal, append_safe, copy};
use super::schedule::{ScheduleError, schedule};
use super::tactic::Response;
use super::time_point::TimePointId;
use crate::logic::Formula;
use crate::plant::ComponentId;
use crate::protocol::posandhead::StateValue;
use crate::reconfiguration::Reconfiguration;

/// How often one cycle answers the failures firing finds and fires again (a response promotes
/// a network whose points may be due at once); what the last round finds is answered first
/// thing the next cycle.
const ROUNDS: usize = 4;

/// A mission being run, one cycle at a time.
#[derive(Debug, Clone)]
pub struct GoalController {
    mission: Mission,
    execution: Execution,
    state: ElaborationState,
    /// Per goal, how often it was re-elaborated.
    reelaborations: Vec<u32>,
    safed: bool,
    /// Events of the construction, reported by the first step.
    pending: Vec<MissionEvent>,
    /// Failures found by the last round of a cycle, answered first thing the next.
    unanswered: Vec<(GoalId, FailureReason)>,
    /// Per controller of the mission, its state variable's value as last observed: what its
    /// delegated goals are judged from at a promotion.
    delegated: Vec<StateValue>,
}

/// Where a failure's chain of responses ends.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Outcome {
    Ignored,
    ReElaborate(GoalId),
    Done,
    Safing,
}

impl GoalController {
    /// Elaborates and promotes the mission's network at `now` from the estimate (or, if no
    /// elaboration fits, starts safed).
    pub fn new(
        mission: &Mission,
        reconfiguration: &Reconfiguration,
        now: f64,
        estimate: EstimateView,
    ) -> Self {
        let mut network = mission.network.clone();
        // The mission loaded consistent; the unelaborated network only stands for the old
        // network if safing must replace it at once.
        let _ = network.propagate();
        let unelaborated = ExecutableNetwork {
            network,
            timelines: Vec::new(),
        };
        let goals = mission.network.goals().len();
        let mut types = mission.elaborators.of_goal.clone();
        types.resize(goals, None);
        let mut controller = GoalController {
            mission: mission.clone(),
            execution: Execution::new(unelaborated, mission.knowledge_threshold),
            state: ElaborationState {
                types,
                retired: vec![false; goals],
                ..ElaborationState::default()
            },
            reelaborations: vec![0; goals],
            safed: false,
            pending: Vec::new(),
            unanswered: Vec::new(),
            delegated: (mission.controllers.iter())
                .map(|c| c.initial_value())
                .collect(),
        };
        let mut proposal = controller.proposal(&[], &[], &[], "the mission's network".into());
        proposal.roots = (0..goals as u32).map(|g| (GoalId(g), 0)).collect();
        let mut events = Vec::new();
        if let Err(rejection) =
            controller.try_promote(proposal, now, estimate, reconfiguration, &mut events)
        {
            let reason = rejection.reason;
            let cause = format!("the mission's network cannot be elaborated: {reason}");
            controller.safe(now, estimate, reconfiguration, cause, &mut events);
        }
        controller.pending = events;
        controller
    }

    /// The running execution.
    pub fn execution(&self) -> &Execution {
        &self.execution
    }

    /// The running network (ids stay valid across promotions).
    pub fn network(&self) -> &GoalNetwork {
        &self.execution.executable().network
    }

    /// The elaboration tree of the running network.
    pub fn elaboration(&self) -> &ElaborationState {
        &self.state
    }

    /// Whether safing has been invoked.
    pub fn is_safed(&self) -> bool {
        self.safed
    }

    /// Feeds what decides the controller's future to `state` (exploration's deduplication):
    /// the execution's state, the elaboration tree (each goal's type, whether it is retired,
    /// the tactic in use per elaborated goal, how often each was elaborated — the names of the
    /// next elaboration), the re-elaborations spent, whether it is safed, the failures left to
    /// answer and whether construction events are still to be reported. The network follows
    /// from these and the mission.
    pub fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        self.execution.fingerprint(state);
        self.state.types.hash(state);
        self.state.retired.hash(state);
        for (goal, elaboration) in &self.state.elaborations {
            (goal, elaboration.tactic).hash(state);
        }
        self.state.count.hash(state);
        self.reelaborations.hash(state);
        self.safed.hash(state);
        for (goal, _) in &self.unanswered {
            goal.hash(state);
        }
        self.pending.is_empty().hash(state);
    }

    /// One cycle at `now`: monitoring, the answers to its failures, then firing, the answers to
    /// firing's failures and firing again (§2.9 steps 3–5).
    pub fn step(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
    ) -> Vec<MissionEvent> {
        let mut events = std::mem::take(&mut self.pending);
        let checked = self.execution.check(estimate, reconfiguration);
        let mut failures = std::mem::take(&mut self.unanswered);
        failures.extend(failures_in(&checked));
        events.extend(checked.into_iter().map(MissionEvent::Goal));
        for _ in 0..ROUNDS {
            if !failures.is_empty() {
                self.answer(now, estimate, reconfiguration, &failures, &mut events);
            }
            let fired = self.execution.advance(now, estimate);
            failures = failures_in(&fired);
            events.extend(fired.into_iter().map(MissionEvent::Goal));
            if failures.is_empty() {
                break;
            }
        }
        self.unanswered = failures;
        events
    }

    /// The values of the controlled state variables (one per controller of the mission, in its
    /// order), which the next promotions judge delegated goals from.
    pub fn observe_delegated(&mut self, values: Vec<StateValue>) {
        self.delegated = values;
    }

    /// The controller of a delegated goal ended its constraint (see
    /// [`Execution::end_delegated`]): a failure is reported, and answered, by the next
    /// [`GoalController::step`].
    pub fn end_delegated(&mut self, goal: GoalId, failure: Option<FailureReason>) {
        self.execution.end_delegated(goal, failure);
    }

    /// The configuration goal of the running network (see [`Execution::configuration_goal`]).
    pub fn configuration_goal(
        &self,
        reconfiguration: &Reconfiguration,
        controllable: impl Fn(ComponentId) -> bool,
    ) -> Formula {
        self.execution
            .configuration_goal(reconfiguration, controllable)
    }

    /// A proposal: a copy of the running network to edit and [`GoalController::promote`].
    pub fn propose(&self) -> Proposal {
        self.proposal(&[], &[], &[], "a proposal".into())
    }

    /// Promotes an edited proposal at `now` (§2.3 steps a–j): its typed new goals are
    /// elaborated, it is scheduled and checked, and it replaces the running network — or
    /// `PromotionFailed` says why and nothing changes.
    pub fn promote(
        &mut self,
        proposal: Proposal,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
    ) -> Vec<MissionEvent> {
        let mut events = Vec::new();
        // The reason is in the `PromotionFailed` event.
        let _ = self.try_promote(proposal, now, estimate, reconfiguration, &mut events);
        events
    }

    /// Promotes the safe network now, from any state (§2.8).
    pub fn invoke_safing(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        cause: String,
    ) -> Vec<MissionEvent> {
        let mut events = Vec::new();
        self.safe(now, estimate, reconfiguration, cause, &mut events);
        events
    }

    /// A copy of the running network without the `retire` goals, the unfired of `points`, and
    /// the temporal constraints the elaborations of `retire` and `unelaborate` wrote.
    fn proposal(
        &self,
        retire: &[GoalId],
        unelaborate: &[GoalId],
        points: &[TimePointId],
        cause: String,
    ) -> Proposal {
        let mut state = self.state.clone();
        for g in retire {
            state.retired[g.index()] = true;
            state.elaborations.remove(g);
        }
        let mut unelaborated = state.retired.clone();
        for g in unelaborate {
            unelaborated[g.index()] = true;
            state.elaborations.remove(g);
        }
        let network = self.network();
        let mut retired_points: Vec<bool> = (0..network.points().len() as u32)
            .map(|p| self.execution.is_retired(TimePointId(p)))
            .collect();
        for p in points {
            if self.execution.fired_at(*p).is_none() {
                retired_points[p.index()] = true;
            }
        }
        Proposal {
            network: copy(network, &state.retired, &unelaborated, &retired_points),
            state,
            retired_points,
            roots: Vec::new(),
            anchor_from: network.points().len(),
            cause,
        }
    }

    /// [`GoalController::promote`], saying whether the proposal was promoted: `Err` carries
    /// why not (with the scheduler's error, for a caller that reports it typed, as a refused
    /// submission does). The events are pushed to `events` either way.
    pub fn try_promote(
        &mut self,
        proposal: Proposal,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        events: &mut Vec<MissionEvent>,
    ) -> Result<(), Rejection> {
        let fired = |p: TimePointId| self.execution.fired_at(p).is_some();
        let context = Context {
            elaborators: &self.mission.elaborators,
            reconfiguration,
            current: estimate.modes,
            now,
            anchor_from: proposal.anchor_from,
            fired: &fired,
        };
        let elaborated = elaborate(
            &context,
            &proposal.network,
            &proposal.state,
            &proposal.roots,
            events,
        );
        let elaborated = elaborated.and_then(|elaborated| {
            let network = &elaborated.executable.network;
            let controllers = &self.mission.controllers;
            let judged = judge_delegated(network, controllers, &self.delegated, fired);
            let past = self.past_points(network, &proposal.retired_points, now);
            match judged.and(past) {
                Ok(()) => Ok(elaborated),
                Err(error) => Err(Rejection {
                    reason: super::display::explain(&error, network, &self.mission.plant),
                    conflicts: super::display::conflicts(&error, network),
                    error: Some(error),
                }),
            }
        });
        match elaborated {
            Ok(elaborated) => {
                let retired = proposal.retired_points;
                self.execution = Execution::resume(elaborated.executable, &self.execution, retired);
                self.state = elaborated.state;
                self.reelaborations.resize(self.state.types.len(), 0);
                events.push(MissionEvent::Promoted {
                    cause: proposal.cause,
                });
                Ok(())
            }
            Err(rejection) => {
                events.push(MissionEvent::PromotionFailed {
                    reason: rejection.reason.clone(),
                });
                Err(rejection)
            }
        }
    }

    /// The unfired points of a proposed network whose window lies before `now` (DESIGN.md
    /// §15.2, promotion step b): a new point, or one whose latest time the proposal moved
    /// before now. A point of the running network already overdue (it is forced this cycle)
    /// is not the proposal's doing.
    fn past_points(
        &self,
        network: &GoalNetwork,
        retired: &[bool],
        now: f64,
    ) -> Result<(), ScheduleError> {
        let running = self.network().stn();
        let past: Vec<TimePointId> = (0..network.points().len() as u32)
            .map(TimePointId)
            .filter(|&p| !retired.get(p.index()).copied().unwrap_or(false))
            .filter(|&p| self.execution.fired_at(p).is_none())
            .filter(|&p| {
                let Some(window) = network.stn().window(p) else {
                    return false;
                };
                let before = running.window(p).map(|w| w.ub);
                window.ub < now - TIME_EPSILON
                    && before.is_none_or(|ub| window.ub < ub - TIME_EPSILON)
            })
            .collect();
        if past.is_empty() {
            Ok(())
        } else {
            Err(ScheduleError::InThePast { points: past, now })
        }
    }

    /// Answers the failures of one round (DESIGN.md §15.2: one path, each failure exactly
    /// once): after safing, and in a mission that declares no responses, each gets a
    /// `ResponseTaken` saying no response is taken; otherwise its chain of responses.
    fn answer(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        failures: &[(GoalId, FailureReason)],
        events: &mut Vec<MissionEvent>,
    ) {
        let none = if self.safed {
            Some(ResponseStep::SafeNetworkRuns)
        } else if !self.responds() {
            Some(ResponseStep::NoResponses)
        } else {
            None
        };
        match none {
            Some(step) => {
                for (goal, reason) in failures {
                    let mut explanation = self.explain(*goal, reason, estimate);
                    explanation.steps.push(step.clone());
                    events.push(MissionEvent::ResponseTaken {
                        goal: *goal,
                        response: None,
                        explanation,
                    });
                }
            }
            None => self.respond(now, estimate, reconfiguration, failures, events),
        }
    }

    /// Responds to a round's failures, all gathered first (§2.5 step 4).
    fn respond(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        failures: &[(GoalId, FailureReason)],
        events: &mut Vec<MissionEvent>,
    ) {
        let mut chains: Vec<(GoalId, Explanation, Outcome)> = failures
            .iter()
            .map(|(goal, reason)| {
                let mut explanation = self.explain(*goal, reason, estimate);
                let outcome = self.climb(*goal, &mut explanation.steps);
                (*goal, explanation, outcome)
            })
            .collect();
        let mut work = Vec::new();
        // Safing wins: no re-elaboration when a failure already leads there.
        if !chains.iter().any(|c| c.2 == Outcome::Safing) {
            // Ancestors first: re-elaborating a goal replaces its whole subtree, so a goal
            // inside it is not re-elaborated again (it would resurrect what was removed).
            let mut order: Vec<usize> = (0..chains.len()).collect();
            order.sort_by_key(|&i| match chains[i].2 {
                Outcome::ReElaborate(target) => self.depth(target),
                _ => 0,
            });
            let mut done: Vec<(GoalId, Vec<ResponseStep>, Outcome)> = Vec::new();
            for i in order {
                let (_, explanation, outcome) = &mut chains[i];
                while let Outcome::ReElaborate(target) = *outcome {
                    let shared = done.iter().find(|d| d.0 == target);
                    let replaced_by = done.iter().find(|d| self.is_inside(target, d.0));
                    let (steps, next) = match (shared, replaced_by) {
                        (Some((_, steps, next)), _) => (steps.clone(), *next),
                        (None, Some((by, _, _))) => {
                            let by = self.network().goal(*by).name.clone();
                            (vec![ResponseStep::Replaced { by }], Outcome::Done)
                        }
                        (None, None) => {
                            let result =
                                self.reelaborate(target, now, estimate, reconfiguration, &mut work);
                            done.push((target, result.0.clone(), result.1));
                            result
                        }
                    };
                    explanation.steps.extend(steps);
                    *outcome = next;
                }
            }
        }
        let safing = chains.iter().find(|c| c.2 == Outcome::Safing);
        let cause = safing.map(|c| c.1.to_string());
        if cause.is_some() {
            for (_, explanation, outcome) in &mut chains {
                if matches!(outcome, Outcome::ReElaborate(_)) {
                    explanation.steps.push(ResponseStep::Superseded);
                }
            }
        }
        for (goal, explanation, _) in chains {
            events.push(MissionEvent::ResponseTaken {
                goal,
                response: Some(self.response(goal)),
                explanation,
            });
        }
        events.extend(work);
        if let Some(cause) = cause {
            self.safe(now, estimate, reconfiguration, cause, events);
        }
    }

    /// Whether failures get responses: a mission that declares no goal types declares no
    /// responses either, and its failed goals are answered "no response" while the network
    /// runs on (as a network ran before goal types existed). With types, a goal without one
    /// fails up.
    fn responds(&self) -> bool {
        !self.mission.elaborators.types.is_empty()
    }

    /// The failed goal, the mode ŝ has its SV in and that mode's probability; for a delegated
    /// goal, its state variable and the value its controller reported (its estimator is a sort
    /// conversion: certain, p 1).
    fn explain(&self, goal: GoalId, reason: &FailureReason, estimate: EstimateView) -> Explanation {
        let g = self.network().goal(goal);
        let plant = &self.mission.plant;
        let delegated = g
            .delegate
            .map(|d| &self.mission.controllers[d.controller].sv);
        let (sv, mode, probability) = match (g.sv, delegated) {
            (_, Some(name)) => {
                let value = match reason {
                    FailureReason::Delegated { value: Some(v), .. } => v.clone(),
                    _ => "not reported".to_string(),
                };
                (name.clone(), value, 1.0)
            }
            (Some(sv), None) => {
                let mode = estimate.modes[sv.index()];
                let component = plant.component(sv);
                (
                    component.name().to_string(),
                    component.modes()[mode.index()].name.clone(),
                    estimate.beliefs[sv.index()][mode.index()],
                )
            }
            (None, None) => (String::new(), String::new(), 0.0),
        };
        Explanation {
            goal: g.name.clone(),
            sv,
            mode,
            probability,
            steps: Vec::new(),
        }
    }

    /// How many ancestors `goal` has in the elaboration tree.
    fn depth(&self, goal: GoalId) -> usize {
        std::iter::successors(self.network().goal(goal).parent, |g| {
            self.network().goal(*g).parent
        })
        .count()
    }

    /// Whether `goal` lies strictly inside `ancestor`'s subtree.
    fn is_inside(&self, goal: GoalId, ancestor: GoalId) -> bool {
        std::iter::successors(self.network().goal(goal).parent, |g| {
            self.network().goal(*g).parent
        })
        .any(|g| g == ancestor)
    }

    /// A goal's response as its type declares it (`FailUp` for a goal with no type).
    fn response(&self, goal: GoalId) -> Response {
        self.state.types[goal.index()].map_or(Response::FailUp, |t| {
            self.mission.elaborators.get(t).response
        })
    }

    /// Follows the responses from a failed `goal` up to one that acts (§2.6).
    fn climb(&self, mut goal: GoalId, steps: &mut Vec<ResponseStep>) -> Outcome {
        loop {
            match self.response(goal) {
                Response::Ignore => {
                    steps.push(ResponseStep::Ignored);
                    return Outcome::Ignored;
                }
                Response::Safing => {
                    steps.push(ResponseStep::Safing);
                    return Outcome::Safing;
                }
                Response::ReElaborate => return Outcome::ReElaborate(goal),
                Response::FailUp => match self.network().goal(goal).parent {
                    Some(parent) => {
                        steps.push(ResponseStep::FailUp);
                        goal = parent;
                    }
                    None => return self.root(goal, steps),
                },
            }
        }
    }

    fn root(&self, goal: GoalId, steps: &mut Vec<ResponseStep>) -> Outcome {
        let name = self.network().goal(goal).name.clone();
        steps.push(ResponseStep::Root { goal: name });
        steps.push(ResponseStep::Safing);
        Outcome::Safing
    }

    /// Re-elaborates `goal` with its next tactic (§2.7); if none fits, it fails up.
    fn reelaborate(
        &mut self,
        goal: GoalId,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        events: &mut Vec<MissionEvent>,
    ) -> (Vec<ResponseStep>, Outcome) {
        let name = self.network().goal(goal).name.clone();
        let goal_type = self.state.types[goal.index()].map(|t| self.mission.elaborators.get(t));
        let (tactics, budget) = goal_type.map_or((0, 0), |t| (t.tactics.len(), t.budget));
        let in_use = self.state.elaborations.get(&goal).map_or(0, |e| e.tactic);
        let end = self.network().goal(goal).end;
        let ends = self.execution.ends_this_cycle(end, now);
        if ends && !self.execution.has_failed(goal) {
            // Only a goal below it failed, and no time is left to repair it in.
            let point = self.network().point(end).name.clone();
            return (
                vec![ResponseStep::IntervalEnds { goal: name, point }],
                Outcome::Done,
            );
        }
        let attempt = if tactics == 0 {
            Err("its type has no tactic".to_string())
        } else if ends {
            let end = &self.network().point(end).name;
            Err(format!(
                "its interval is over (its end point {end} has fired or is due now)"
            ))
        } else if self.reelaborations[goal.index()] >= budget {
            Err(format!("its re-elaboration budget of {budget} is spent"))
        } else {
            let (goals, points) = self.state.subtree(goal);
            let cause = format!("re-elaboration of {name}");
            let mut proposal = self.proposal(&goals, &[goal], &points, cause);
            proposal.roots = vec![(goal, (in_use + 1) % tactics)];
            self.try_promote(proposal, now, estimate, reconfiguration, events)
                .map_err(|rejection| rejection.reason)
        };
        let mut steps = Vec::new();
        match attempt {
            Ok(()) => {
                self.reelaborations[goal.index()] += 1;
                let tactic = self.state.elaborations.get(&goal).map_or(0, |e| e.tactic) + 1;
                steps.push(ResponseStep::ReElaborated { goal: name, tactic });
                steps.push(ResponseStep::Promoted);
                (steps, Outcome::Done)
            }
            Err(reason) => {
                steps.push(ResponseStep::NoTacticLeft { goal: name, reason });
                let outcome = match self.network().goal(goal).parent {
                    Some(parent) => {
                        steps.push(ResponseStep::FailUp);
                        self.climb(parent, &mut steps)
                    }
                    None => self.root(goal, &mut steps),
                };
                (steps, outcome)
            }
        }
    }

    /// Promotes the safe network (§2.8): every goal of the running network is retired and
    /// every unfired point with it; the safe network is appended from a promotion point fired
    /// now and scheduled best effort (DESIGN.md §15.2): a safe goal that cannot be scheduled
    /// from this state is dropped, reported with the scheduler's reason, and the rest is
    /// scheduled again. If what is left still cannot be (the safe network's times contradict
    /// each other from here), the default one (every SV unconstrained) is used and the cause
    /// says why.
    fn safe(
        &mut self,
        now: f64,
        estimate: EstimateView,
        reconfiguration: &Reconfiguration,
        mut cause: String,
        events: &mut Vec<MissionEvent>,
    ) {
        let goals: Vec<GoalId> = (0..self.state.types.len() as u32).map(GoalId).collect();
        let points: Vec<TimePointId> = (0..self.network().points().len() as u32)
            .map(TimePointId)
            .collect();
        let proposal = self.proposal(&goals, &[], &points, String::new());
        let (mut network, mut state) = (proposal.network, proposal.state);
        let base = (network.clone(), state.clone());
        let first = network.goals().len();
        append_safe(&mut network, &mut state, &self.mission.safe, now);
        let mut dropped = Vec::new();
        let executable = loop {
            let error = match schedule(&network, reconfiguration, estimate.modes) {
                Ok(executable) => break Ok(executable),
                Err(error) => error,
            };
            let culprits: Vec<GoalId> = culprits(&error)
                .into_iter()
                .filter(|g| g.index() >= first && network.goal(*g).sv.is_some())
                .collect();
            let why = super::display::explain(&error, &network, &self.mission.plant);
            if culprits.is_empty() {
                break Err(why);
            }
            for goal in culprits {
                let name = network.goal(goal).name.clone();
                network.retire_goal(goal);
                state.retired[goal.index()] = true;
                dropped.push(MissionEvent::SafeGoalDropped {
                    goal: name,
                    reason: why.clone(),
                });
            }
        };
        let executable = match executable {
            Ok(executable) => executable,
            Err(why) => {
                let instead = "every state variable is left unconstrained instead";
                cause = format!("{cause} (the safe network cannot be scheduled: {why}; {instead})");
                dropped.clear();
                (network, state) = base;
                append_safe(&mut network, &mut state, &GoalNetwork::new(), now);
                // Grounded points and no goals: consistent, nothing to schedule.
                let _ = network.propagate();
                ExecutableNetwork {
                    network,
                    timelines: Vec::new(),
                }
            }
        };
        self.execution = Execution::resume(executable, &self.execution, proposal.retired_points);
        self.reelaborations.resize(state.types.len(), 0);
        self.state = state;
        self.safed = true;
        events.push(MissionEvent::Safing { cause });
        events.extend(dropped);
    }
}

/// The failures among `events`.
fn failures_in(events: &[GoalEvent]) -> Vec<(GoalId, FailureReason)> {
    (events.iter())
        .filter_map(|e| match e {
            GoalEvent::GoalFailed { goal, reason } => Some((*goal, reason.clone())),
            _ => None,
        })
        .collect()
}

/// The goals a scheduling error blames, that dropping them could fix: an unachievable
/// XGoal's constituents, the goals of an XGoal that cannot be entered, a goal that merges with
/// none of those it overlaps, a delegated goal its controller cannot achieve, a goal the
/// constraints force reversed or over no time. A temporal inconsistency blames no goal.
fn culprits(error: &ScheduleError) -> Vec<GoalId> {
    match error {
        ScheduleError::Unachievable { xgoal, .. } => xgoal.constituents.clone(),
        ScheduleError::TransitionUnachievable { next, .. } => next.constituents.clone(),
        ScheduleError::Unmergeable { goal, .. } => vec![*goal],
        ScheduleError::DelegatedUnachievable { goal, .. }
        | ScheduleError::Reversed { goal, .. }
        | ScheduleError::EmptyInterval { goal } => vec![*goal],
        ScheduleError::Inconsistent(_) | ScheduleError::InThePast { .. } => Vec::new(),
    }
}
