//! A goal network run as the executive's control program (DESIGN.md §15.3; mds-goal-networks.md
//! §2.4–2.5, §2.9).
//!
//! Every call into the goal network is in this file, through a [`GoalController`]
//! (elaboration with tactics, the failure responses, promotion, safing). The controller is made
//! at the first cycle — it elaborates and schedules from ŝ, which only then exists — or at a
//! submission before it; until then the network scheduled at load stands for it.
//!
//! Per cycle, after estimation: the estimate view (ŝ and each component's mode marginals, summed
//! over the belief's plant states) goes to `GoalController::step` (monitoring, the failure
//! responses, then firing to a fixpoint and dispatch), its events become the executive's, and
//! the conjunction of the active XGoals' control sets on *controllable* state variables becomes
//! the configuration goal. A state variable is controllable when mode reconfiguration can move
//! it at all (its concurrent policy has a step): a sensor's health is monitored, never
//! commanded.
//!
//! A goal on a state variable that is not a component is delegated to the controller the
//! mission declares for it (`delegation.rs`): its protocol runs before the goal controller's
//! step (the device's reports, `newval`, the next command or `endcstr`) and after it (the
//! constraints of the delegated goals whose start fired are sent).

use super::delegation::Delegations;
use super::events::EventKind;
use crate::estimation::PlantEstimate;
use crate::goalnet::{
    EstimateView, ExecutableNetwork, FailureReason, GoalController, GoalEvent, GoalId, GoalNetwork,
    Mission, MissionEvent, ScheduleError, TemporalConstraint, TimePointId, Waiting, Window, XGoal,
    display, judge_delegated, schedule,
};
use crate::goalnet::{Submission, SubmitError};
use crate::logic::{Formula, ValueId};
use crate::plant::{ComponentId, Plant};
use crate::reconfiguration::Reconfiguration;

/// A loaded mission with its goal network scheduled: what [`Executive::builder`] runs as a
/// mission (it converts into a [`ControlProgram`](super::ControlProgram)).
///
/// [`Executive::builder`]: super::Executive::builder
#[derive(Debug, Clone)]
pub struct ScheduledMission {
    mission: Mission,
    executable: ExecutableNetwork,
}

impl ScheduledMission {
    /// Schedules the mission's network from the plant's most likely initial modes (the state the
    /// executive starts from) with the plant's compiled reconfiguration.
    pub fn schedule(
        mission: Mission,
        reconfiguration: &Reconfiguration,
    ) -> Result<ScheduledMission, ScheduleError> {
        let current = mission.plant.most_likely_initial();
        let executable = schedule(&mission.network, reconfiguration, &current)?;
        // Nothing has fired: every delegated goal is judged from its SV's declared value.
        let initial: Vec<_> = (mission.controllers.iter())
            .map(|c| c.initial_value())
            .collect();
        judge_delegated(&executable.network, &mission.controllers, &initial, |_| {
            false
        })?;
        Ok(ScheduledMission {
            mission,
            executable,
        })
    }

    /// The mission as loaded.
    pub fn mission(&self) -> &Mission {
        &self.mission
    }

    /// The scheduled network.
    pub fn executable(&self) -> &ExecutableNetwork {
        &self.executable
    }
}

/// A mission being executed, one cycle at a time.
#[derive(Debug, Clone)]
pub(super) struct MissionControl {
    mission: Mission,
    /// The network scheduled at load: what [`MissionControl::executable`] shows until the
    /// controller is made.
    scheduled: ExecutableNetwork,
    /// Made at the first cycle, or at a submission before it (it elaborates from ŝ).
    controller: Option<GoalController>,
    /// Events of promotions between cycles (submissions), reported with the next cycle.
    pending: Vec<MissionEvent>,
    /// Every point's window as the network gives it before this cycle's firings (an event
    /// shows the window the point fired in, not the `[t, t]` grounding makes of it); refreshed
    /// only after a cycle in which a point fired or a network was promoted.
    windows: Vec<Option<Window>>,
    /// Per goal, its state variable, kept when a promotion retires the goal (a retired goal
    /// has none in the network), so that a failure reported in the cycle a promotion retires
    /// its goal still names its SV's mode. Refreshed with the windows.
    svs: Vec<Option<ComponentId>>,
    /// Per goal, the controller it is delegated to, kept like `svs` when a promotion retires
    /// it.
    delegated: Vec<Option<usize>>,
    /// The protocols of the mission's controllers, for its delegated goals.
    delegations: Delegations,
    /// Per component, the marginal of each of its modes (reused from cycle to cycle).
    beliefs: Vec<Vec<f64>>,
    /// Per state variable, the XGoal the events reported so far leave active: its end point and
    /// goals (kept in step with the truth after a promotion, [`MissionControl::reconcile`]).
    shown: Vec<(ComponentId, String, Vec<String>)>,
    /// Whether a cycle has been stepped: the first reports the XGoals active from the origin.
    started: bool,
    /// Whether completion has been reported.
    completed: bool,
}

impl MissionControl {
    pub(super) fn new(scheduled: ScheduledMission) -> Self {
        let ScheduledMission {
            mission,
            executable,
        } = scheduled;
        let beliefs = mission
            .plant
            .components()
            .iter()
            .map(|c| vec![0.0; c.modes().len()])
            .collect();
        let delegations = Delegations::new(&mission);
        let mut control = MissionControl {
            mission,
            scheduled: executable,
            controller: None,
            pending: Vec::new(),
            windows: Vec::new(),
            svs: Vec::new(),
            delegated: Vec::new(),
            delegations,
            beliefs,
            shown: Vec::new(),
            started: false,
            completed: false,
        };
        control.refresh_windows();
        control
    }

    /// Feeds what decides the mission's future to `state`: the controller's state (execution,
    /// elaboration tree, safed) once it is made, the submission events still to report, and
    /// whether the first cycle and completion have been reported.
    pub(super) fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        self.controller.is_some().hash(state);
        if let Some(controller) = &self.controller {
            controller.fingerprint(state);
        }
        self.pending.len().hash(state);
        self.shown.hash(state);
        self.delegations.hash(state);
        self.started.hash(state);
        self.completed.hash(state);
    }

    /// The mission as loaded.
    pub(super) fn mission(&self) -> &Mission {
        &self.mission
    }

    /// The network as it is being executed (windows shrink as points fire; a promotion
    /// replaces it), or as scheduled at load before the first cycle.
    pub(super) fn executable(&self) -> &ExecutableNetwork {
        self.controller
            .as_ref()
            .map_or(&self.scheduled, |c| c.execution().executable())
    }

    /// Every point (not retired by a promotion) has fired.
    pub(super) fn is_complete(&self) -> bool {
        self.controller
            .as_ref()
            .is_some_and(|c| c.execution().is_complete())
    }

    /// The delegated goals' protocols (their devices' reports and their controllers' answers),
    /// then monitoring, the failure responses, firing and dispatch at `now` from ŝ (`modes`)
    /// and the belief's plant states, then the constraints of the delegated goals that started;
    /// returns the events and the configuration goal.
    pub(super) fn step(
        &mut self,
        now: f64,
        modes: &[ValueId],
        estimates: &[PlantEstimate],
        reconfiguration: &Reconfiguration,
    ) -> (Vec<EventKind>, Formula) {
        self.marginals(estimates);
        let view = EstimateView {
            modes,
            beliefs: &self.beliefs,
        };
        let controller = self
            .controller
            .get_or_insert_with(|| GoalController::new(&self.mission, reconfiguration, now, view));
        let delivered = self.delegations.cycle(&self.mission, controller);
        controller.observe_delegated(self.delegations.values());
        let mut stepped = controller.step(now, view, reconfiguration);
        let sent = self.delegations.dispatch(&self.mission, controller);
        if !self.started {
            // The mission's network starting is shown by the dispatches of cycle 0, not as a
            // promotion (its tactic choices are reported): the first promotion the controller
            // reports is its construction's.
            if let Some(i) = stepped
                .iter()
                .position(|e| matches!(e, MissionEvent::Promoted { .. }))
            {
                stepped.remove(i);
            }
        }
        let mut events = std::mem::take(&mut self.pending);
        events.extend(stepped);
        let refresh = events.iter().any(changes_windows);
        let promoted = (events.iter()).any(|e| {
            matches!(
                e,
                MissionEvent::Promoted { .. } | MissionEvent::Safing { .. }
            )
        });
        let mut kinds = delivered;
        let mut described = self.describe_cycle(events, modes);
        self.reconcile(&mut described, promoted);
        kinds.extend(described);
        kinds.extend(sent);
        if refresh {
            self.refresh_windows();
        }
        if self.is_complete() && !self.completed {
            self.completed = true;
            kinds.push(EventKind::ProgramCompleted);
        }
        self.started = true;
        let controllable = |sv: ComponentId| !reconfiguration.policy(sv).steps().is_empty();
        let goal = self.controller.as_ref().map_or(Formula::True, |c| {
            c.configuration_goal(reconfiguration, controllable)
        });
        (kinds, goal)
    }

    /// Adds `submission` to a proposal — a copy of the running network — and promotes it
    /// (mds-goal-networks.md §2.3 steps a–j): every fired point stays at its firing time,
    /// every new point is anchored no earlier than `now` (a point cannot be submitted into the
    /// past), and the proposal is scheduled from ŝ (`modes`). Refused, with the running network
    /// unchanged, when a name does not resolve or the proposal cannot be scheduled. Before the
    /// first cycle the controller is made here, at `now`, from ŝ.
    pub(super) fn submit(
        &mut self,
        submission: &Submission,
        now: f64,
        modes: &[ValueId],
        reconfiguration: &Reconfiguration,
    ) -> Result<(), SubmitError> {
        let plant = &self.mission.plant;
        for goal in &submission.goals {
            let fits = goal.sv.is_none_or(|sv| {
                (plant.components().get(sv.index()))
                    .is_some_and(|c| c.modes().len() == goal.constraint.domain())
            });
            if !fits {
                return Err(SubmitError::Domain(goal.name.clone()));
            }
        }
        let view = EstimateView {
            modes,
            beliefs: &self.beliefs,
        };
        // A refused submission changes nothing: a controller made for it is kept only if the
        // submission is promoted.
        let existing = self.controller.take();
        let made = existing.is_none();
        let mut controller = existing
            .unwrap_or_else(|| GoalController::new(&self.mission, reconfiguration, now, view));
        let promoted = promote(&mut controller, submission, now, view, reconfiguration);
        if promoted.is_ok() || !made {
            self.controller = Some(controller);
        }
        let events = promoted?;
        self.pending.extend(events);
        self.refresh_windows();
        Ok(())
    }

    /// The executive's events for a cycle's mission events. In the first cycle the XGoals the
    /// origin dispatched (it fired at 0 when execution started) are reported after the
    /// elaboration that made them, before the cycle's network events.
    fn describe_cycle(&self, events: Vec<MissionEvent>, modes: &[ValueId]) -> Vec<EventKind> {
        let mut kinds = Vec::new();
        let mut origin = !self.started;
        for event in events {
            if origin && matches!(event, MissionEvent::Goal(_)) {
                kinds.extend(self.dispatched_from_origin());
                origin = false;
            }
            kinds.extend(self.describe(event, modes));
        }
        if origin {
            kinds.extend(self.dispatched_from_origin());
        }
        kinds
    }

    /// Keeps [`MissionControl::shown`] in step with the cycle's events and, after a promotion
    /// (which changes the timelines without firing anything), with the truth: an SV whose active
    /// XGoal is not the one the events left there gets its dispatch, an SV left with none an
    /// `XGoalWithdrawn` — so the log, the trace and expectations never see a retired XGoal as
    /// active.
    fn reconcile(&mut self, kinds: &mut Vec<EventKind>, promoted: bool) {
        for kind in kinds.iter() {
            match kind {
                EventKind::XGoalDispatched {
                    sv,
                    interval: (_, end),
                    goals,
                    ..
                } => {
                    self.shown.retain(|(s, _, _)| s != sv);
                    self.shown.push((*sv, end.clone(), goals.clone()));
                }
                EventKind::TimePointFired { point, .. }
                | EventKind::TimePointForced { point, .. } => {
                    self.shown.retain(|(_, end, _)| end != point);
                }
                _ => {}
            }
        }
        let Some(controller) = self.controller.as_ref().filter(|_| promoted) else {
            return;
        };
        let execution = controller.execution();
        let network = &execution.executable().network;
        let truth: Vec<&XGoal> = (execution.executable().timelines.iter())
            .filter_map(|t| execution.active(t.sv))
            .collect();
        let mut corrections = Vec::new();
        for xgoal in &truth {
            let end = &network.point(xgoal.end).name;
            let goals: Vec<String> = (xgoal.constituents.iter())
                .map(|g| network.goal(*g).name.clone())
                .collect();
            let same = |(sv, e, g): &&(ComponentId, String, Vec<String>)| {
                *sv == xgoal.sv && e == end && *g == goals
            };
            if !self.shown.iter().any(|s| same(&s)) {
                corrections.push(self.dispatched(xgoal));
            }
        }
        for (sv, _, goals) in &self.shown {
            if !truth.iter().any(|x| x.sv == *sv) {
                corrections.push(EventKind::XGoalWithdrawn {
                    sv: *sv,
                    goals: goals.clone(),
                });
            }
        }
        if !corrections.is_empty() {
            self.shown = (truth.iter())
                .map(|x| {
                    let goals = (x.constituents.iter())
                        .map(|g| network.goal(*g).name.clone())
                        .collect();
                    (x.sv, network.point(x.end).name.clone(), goals)
                })
                .collect();
            kinds.extend(corrections);
        }
    }

    /// Sums the plant states' probabilities into each component's mode marginals.
    fn marginals(&mut self, estimates: &[PlantEstimate]) {
        self.beliefs.iter_mut().for_each(|b| b.fill(0.0));
        for estimate in estimates {
            for (belief, mode) in self.beliefs.iter_mut().zip(estimate.modes.iter()) {
                if let Some(p) = belief.get_mut(mode.index()) {
                    *p += estimate.probability;
                }
            }
        }
    }

    /// The dispatch events of the XGoals active from the origin.
    fn dispatched_from_origin(&self) -> Vec<EventKind> {
        let Some(controller) = &self.controller else {
            return Vec::new();
        };
        let execution = controller.execution();
        execution
            .executable()
            .timelines
            .iter()
            .filter_map(|t| execution.active(t.sv))
            .filter(|x| x.start == TimePointId::ORIGIN)
            .map(|x| self.dispatched(x))
            .collect()
    }

    /// The names of the goals merged into the XGoal active on `sv`: what a command moving
    /// `sv` toward its goal serves (empty when no XGoal is active on it).
    pub(super) fn serving(&self, sv: ComponentId) -> Vec<String> {
        let Some(controller) = &self.controller else {
            return Vec::new();
        };
        let network = &self.executable().network;
        controller
            .execution()
            .active(sv)
            .map(|xgoal| {
                (xgoal.constituents.iter())
                    .map(|g| network.goal(*g).name.clone())
                    .collect()
            })
            .unwrap_or_default()
    }

    /// The event of an XGoal's dispatch.
    fn dispatched(&self, xgoal: &XGoal) -> EventKind {
        let network = &self.executable().network;
        EventKind::XGoalDispatched {
            sv: xgoal.sv,
            constraint: display::constraint_text(&self.mission.plant, xgoal.sv, &xgoal.constraint),
            kind: xgoal.kind.name(),
            interval: (
                network.point(xgoal.start).name.clone(),
                network.point(xgoal.end).name.clone(),
            ),
            goals: xgoal
                .constituents
                .iter()
                .map(|g| network.goal(*g).name.clone())
                .collect(),
        }
    }

    fn refresh_windows(&mut self) {
        let network = &self.executable().network;
        let windows = (0..network.points().len())
            .map(|i| network.stn().window(TimePointId(i as u32)))
            .collect();
        let svs: Vec<Option<ComponentId>> = network.goals().iter().map(|g| g.sv).collect();
        let delegated: Vec<Option<usize>> = (network.goals().iter())
            .map(|g| g.delegate.map(|d| d.controller))
            .collect();
        self.windows = windows;
        self.delegated.resize(delegated.len(), None);
        for (kept, controller) in self.delegated.iter_mut().zip(delegated) {
            *kept = controller.or(*kept);
        }
        self.svs.resize(svs.len(), None);
        for (kept, sv) in self.svs.iter_mut().zip(svs) {
            *kept = sv.or(*kept);
        }
    }

    /// The executive's event for a mission event (`None` only for an XGoal the network does
    /// not hold, which the execution never dispatches). Texts are one line each: the log and
    /// the trace print them as they are.
    fn describe(&self, event: MissionEvent, modes: &[ValueId]) -> Option<EventKind> {
        let kind = match event {
            MissionEvent::Goal(event) => return self.describe_goal_event(event, modes),
            MissionEvent::TacticChosen { goal, tactic } => EventKind::TacticChosen { goal, tactic },
            MissionEvent::TacticRejected {
                goal,
                tactic,
                reason,
            } => EventKind::TacticRejected {
                goal,
                tactic,
                reason: one_line(&reason),
            },
            MissionEvent::ResponseTaken {
                response,
                explanation,
                ..
            } => EventKind::ResponseTaken {
                goal: explanation.goal.clone(),
                response: response.map_or("none", |r| r.name()),
                explanation: one_line(&explanation.to_string()),
            },
            MissionEvent::Promoted { cause } => EventKind::Promoted { cause },
            MissionEvent::PromotionFailed { reason } => EventKind::PromotionFailed {
                reason: one_line(&reason),
            },
            MissionEvent::Safing { cause } => EventKind::Safing {
                cause: one_line(&cause),
            },
            MissionEvent::SafeGoalDropped { goal, reason } => EventKind::SafeGoalDropped {
                goal,
                reason: one_line(&reason),
            },
        };
        Some(kind)
    }

    /// The executive's event for an event of the running network's execution.
    fn describe_goal_event(&self, event: GoalEvent, modes: &[ValueId]) -> Option<EventKind> {
        let executable = self.executable();
        let network = &executable.network;
        let name = |p: TimePointId| network.point(p).name.clone();
        // A point promoted and fired in the same cycle has no earlier window than its own.
        let window = |p: TimePointId| {
            self.windows
                .get(p.index())
                .copied()
                .unwrap_or_else(|| network.stn().window(p))
                .map_or((f64::NEG_INFINITY, f64::INFINITY), |w| (w.lb, w.ub))
        };
        let kind = match event {
            GoalEvent::TimePointFired { point } => EventKind::TimePointFired {
                point: name(point),
                window: window(point),
            },
            GoalEvent::TimePointForced { point, late_by } => EventKind::TimePointForced {
                point: name(point),
                window: window(point),
                late_by,
            },
            GoalEvent::XGoalDispatched { sv, index } => {
                self.dispatched(executable.timeline(sv)?.xgoals.get(index)?)
            }
            GoalEvent::GoalFailed { goal: id, reason } => {
                let (mode, probability) = self.goal_mode(id, modes);
                EventKind::MissionGoalFailed {
                    goal: network.goal(id).name.clone(),
                    reason: failure_text(&reason, self.mission.knowledge_threshold, network),
                    mode,
                    probability,
                }
            }
            GoalEvent::GoalRecovered { goal: id } => {
                let (mode, probability) = self.goal_mode(id, modes);
                EventKind::GoalRecovered {
                    goal: network.goal(id).name.clone(),
                    mode,
                    probability,
                }
            }
            GoalEvent::NetworkStalled { stalled } => EventKind::NetworkStalled {
                points: (stalled.iter())
                    .map(|(point, waiting)| self.stall_text(*point, waiting, window(*point)))
                    .collect(),
            },
            GoalEvent::TemporalInconsistency { point, cycle } => {
                let cycle: Vec<&TemporalConstraint> = cycle.iter().collect();
                let text = display::constraint_lines(&cycle, network);
                EventKind::TemporalInconsistency {
                    point: name(point),
                    cycle: text.lines().skip(1).map(|l| l.trim().to_string()).collect(),
                }
            }
        };
        Some(kind)
    }
}

impl MissionControl {
    /// The mode ŝ (`modes`) gives a goal's state variable and its probability, as a failure or
    /// a recovery names it: for a delegated goal, its controller's value (certain: the
    /// protocol's estimator is a sort conversion).
    fn goal_mode(&self, id: GoalId, modes: &[ValueId]) -> (String, f64) {
        let network = &self.executable().network;
        let goal = network.goal(id);
        let delegated = (goal.delegate.map(|d| d.controller))
            .or_else(|| self.delegated.get(id.index()).copied().flatten());
        if let Some(controller) = delegated {
            let sv = &self.mission.controllers[controller].sv;
            return (
                format!("{sv} = {}", self.delegations.value(controller)),
                1.0,
            );
        }
        let sv = goal
            .sv
            .or_else(|| self.svs.get(id.index()).copied().flatten())
            .unwrap_or(ComponentId(0));
        let mode = modes.get(sv.index()).copied().unwrap_or(ValueId(0));
        let probability = (self.beliefs.get(sv.index()))
            .and_then(|b| b.get(mode.index()))
            .copied()
            .unwrap_or(0.0);
        (mode_name(&self.mission.plant, sv, mode), probability)
    }

    /// `TP_E: its latest time 376 s has passed and TP_S, which must fire first, has not`.
    fn stall_text(&self, point: TimePointId, waiting: &Waiting, window: (f64, f64)) -> String {
        let network = &self.executable().network;
        let name = &network.point(point).name;
        match waiting {
            Waiting::NoWindow => format!("{name}: the network has no windows"),
            Waiting::Point(q) => format!(
                "{name}: its latest time {} s has passed and {}, which must fire first, has not",
                window.1,
                network.point(*q).name
            ),
            Waiting::Goal(g) => format!(
                "{name}: it has no latest time and waits for {}, which has failed",
                network.goal(*g).name
            ),
        }
    }
}

/// Whether an event changes the windows an event reports (a firing grounds a point, a
/// promotion reschedules).
fn changes_windows(event: &MissionEvent) -> bool {
    matches!(
        event,
        MissionEvent::Goal(
            GoalEvent::TimePointFired { .. }
                | GoalEvent::TimePointForced { .. }
                | GoalEvent::TemporalInconsistency { .. }
        ) | MissionEvent::Promoted { .. }
            | MissionEvent::Safing { .. }
    )
}

/// Promotes a proposal with `submission` added (a copy of the running network, so that a
/// refusal leaves it as it was); the promotion's events.
fn promote(
    controller: &mut GoalController,
    submission: &Submission,
    now: f64,
    view: EstimateView,
    reconfiguration: &Reconfiguration,
) -> Result<Vec<MissionEvent>, SubmitError> {
    let mut proposal = controller.propose().because("a submission");
    submission.add_to(&mut proposal)?;
    let mut events = Vec::new();
    match controller.try_promote(proposal, now, view, reconfiguration, &mut events) {
        Ok(()) => Ok(events),
        // The reason is the scheduler's explanation of the network it was given.
        Err(rejection) => Err(match rejection.error {
            Some(error) => SubmitError::Refused {
                error,
                explanation: rejection.reason,
                conflicts: rejection.conflicts,
            },
            None => SubmitError::NotElaborated(rejection.reason),
        }),
    }
}

/// `text` on one line: its lines trimmed and joined by "; " (explanations of the scheduler
/// put their evidence on lines of their own).
fn one_line(text: &str) -> String {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    lines.join("; ")
}

/// A failure's reason in words; the mode ŝ is in is shown beside it.
fn failure_text(reason: &FailureReason, threshold: f64, network: &GoalNetwork) -> String {
    match reason {
        FailureReason::Contradicted { point } => format!(
            "{} fired where the network did not allow it (no cycle in its window)",
            network.point(*point).name
        ),
        FailureReason::Excursion(_) => "ŝ left the maintained set".to_string(),
        FailureReason::Unreachable(_) => "its set can no longer be reached".to_string(),
        FailureReason::EndForced(_) => "its end point was forced before the set was reached".into(),
        FailureReason::NotKnown => format!("not known (P below {threshold} or a least belief)"),
        FailureReason::Delegated { why, .. } => why.clone(),
    }
}

fn mode_name(plant: &Plant, sv: ComponentId, mode: ValueId) -> String {
    let component = plant.component(sv);
    format!("{} = {}", component.name(), component.mode(mode).name)
}
