//! A goal network run as the executive's control program (DESIGN.md §15.3; mds-goal-networks.md
//! §2.4–2.5, §2.9).
//!
//! Every call into [`goalnet::Execution`](crate::goalnet::Execution) is in this file: issue 14's
//! controller (elaboration, failure responses, safing) has the same per-cycle shape — `step(now,
//! view, reconfiguration) -> events`, then `configuration_goal(..)` — and replaces it here.
//!
//! Per cycle, after estimation: the estimate view (ŝ and each component's mode marginals, summed
//! over the belief's plant states) goes to `Execution::step` (monitoring, then firing to a
//! fixpoint and dispatch), its events become the executive's, and the conjunction of the active
//! XGoals' control sets on *controllable* state variables becomes the configuration goal. A
//! state variable is controllable when mode reconfiguration can move it at all (its concurrent
//! policy has a step): a sensor's health is monitored, never commanded.

use super::events::EventKind;
use super::submit::{Submission, SubmitError};
use crate::estimation::PlantEstimate;
use crate::goalnet::{
    EstimateView, ExecutableNetwork, Execution, FailureReason, GoalEvent, GoalNetwork, Mission,
    Provenance, ScheduleError, TemporalConstraint, TimePointId, Window, XGoal, display, schedule,
};
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
    /// The unscheduled network: the mission's with every accepted submission added (what a new
    /// submission is scheduled with).
    network: GoalNetwork,
    execution: Execution,
    /// Every point's window as the network gives it before this cycle's firings (an event
    /// shows the window the point fired in, not the `[t, t]` grounding makes of it); refreshed
    /// only after a cycle in which a point fired.
    windows: Vec<Option<Window>>,
    /// Per component, the marginal of each of its modes (reused from cycle to cycle).
    beliefs: Vec<Vec<f64>>,
    /// Cycles stepped so far: the first reports the XGoals active from the origin.
    cycles: u64,
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
        let execution = Execution::new(executable, mission.knowledge_threshold);
        let mut control = MissionControl {
            network: mission.network.clone(),
            mission,
            execution,
            windows: Vec::new(),
            beliefs,
            cycles: 0,
            completed: false,
        };
        control.refresh_windows();
        control
    }

    /// Feeds what decides the mission's future to `state`: the execution's state, the size of
    /// the network submissions have grown, and whether the first cycle and completion have
    /// been reported.
    pub(super) fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        self.execution.fingerprint(state);
        self.network.points().len().hash(state);
        self.network.goals().len().hash(state);
        (self.cycles == 0).hash(state);
        self.completed.hash(state);
    }

    /// The mission as loaded.
    pub(super) fn mission(&self) -> &Mission {
        &self.mission
    }

    /// The scheduled network as it is being executed (windows shrink as points fire).
    pub(super) fn executable(&self) -> &ExecutableNetwork {
        self.execution.executable()
    }

    /// Every point has fired.
    pub(super) fn is_complete(&self) -> bool {
        self.execution.is_complete()
    }

    /// Monitoring, firing and dispatch at `now` from ŝ (`modes`) and the belief's plant states;
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
        let events = self.execution.step(now, view, reconfiguration);
        let fired = events.iter().any(|e| {
            matches!(
                e,
                GoalEvent::TimePointFired { .. } | GoalEvent::TimePointForced { .. }
            )
        });
        let mut kinds = Vec::new();
        if self.cycles == 0 {
            // The origin fired at 0 when execution started, dispatching its XGoals.
            kinds.extend(self.dispatched_from_origin());
        }
        kinds.extend(
            events
                .into_iter()
                .filter_map(|event| self.describe(event, modes)),
        );
        if fired {
            self.refresh_windows();
        }
        if self.execution.is_complete() && !self.completed {
            self.completed = true;
            kinds.push(EventKind::ProgramCompleted);
        }
        self.cycles += 1;
        let controllable = |sv: ComponentId| !reconfiguration.policy(sv).steps().is_empty();
        let goal = self
            .execution
            .configuration_goal(reconfiguration, controllable);
        (kinds, goal)
    }

    /// Adds `submission` to the network and reschedules it from ŝ (`modes`) with every fired
    /// point held at its firing time and every new point no earlier than `now` (a point cannot
    /// be submitted into the past); execution resumes on the new schedule (fired points stay
    /// fired, failed goals failed). Refused, with the network unchanged, when a name does not
    /// resolve or the result cannot be scheduled.
    pub(super) fn submit(
        &mut self,
        submission: &Submission,
        now: f64,
        modes: &[ValueId],
        reconfiguration: &Reconfiguration,
    ) -> Result<(), SubmitError> {
        let plant = &self.mission.plant;
        for goal in &submission.goals {
            let fits = plant
                .components()
                .get(goal.sv.index())
                .is_some_and(|c| c.modes().len() == goal.constraint.domain());
            if !fits {
                return Err(SubmitError::Domain(goal.name.clone()));
            }
        }
        let mut network = self.network.clone();
        let existing = network.points().len();
        submission.add_to(&mut network)?;
        let mut grounded = network.clone();
        let fired = self.execution.fired_times();
        for i in 0..network.points().len() {
            let point = TimePointId(i as u32);
            let (min, max, provenance) = match fired.get(i).copied().flatten() {
                Some(t) => (t, t, Provenance::Fired),
                None if i >= existing => (now, f64::INFINITY, Provenance::Submitted),
                None => continue,
            };
            let at = TemporalConstraint::new(TimePointId::ORIGIN, point, min, max, provenance);
            // Points and bounds are valid: the network accepts it.
            let _ = grounded.add_constraint(at);
        }
        let executable =
            schedule(&grounded, reconfiguration, modes).map_err(|error| SubmitError::Refused {
                explanation: display::explain(&error, &grounded, plant),
                error,
            })?;
        self.execution = Execution::resume(executable, &self.execution, Vec::new());
        self.network = network;
        self.refresh_windows();
        Ok(())
    }

    /// Sums the plant states' probabilities into each component's mode marginals.
    fn marginals(&mut self, estimates: &[PlantEstimate]) {
        self.beliefs.iter_mut().for_each(|b| b.fill(0.0));
        for estimate in estimates {
            for (belief, mode) in self.beliefs.iter_mut().zip(&estimate.modes) {
                if let Some(p) = belief.get_mut(mode.index()) {
                    *p += estimate.probability;
                }
            }
        }
    }

    /// The dispatch events of the XGoals active from the origin.
    fn dispatched_from_origin(&self) -> Vec<EventKind> {
        let executable = self.execution.executable();
        executable
            .timelines
            .iter()
            .filter_map(|t| self.execution.active(t.sv))
            .filter(|x| x.start == TimePointId::ORIGIN)
            .map(|x| self.dispatched(x))
            .collect()
    }

    /// The event of an XGoal's dispatch.
    fn dispatched(&self, xgoal: &XGoal) -> EventKind {
        let network = &self.execution.executable().network;
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
        let network = &self.execution.executable().network;
        self.windows = (0..network.points().len())
            .map(|i| network.stn().window(TimePointId(i as u32)))
            .collect();
    }

    /// The executive's event for a network event (`None` only for an XGoal the network does
    /// not hold, which the execution never dispatches).
    fn describe(&self, event: GoalEvent, modes: &[ValueId]) -> Option<EventKind> {
        let plant = &self.mission.plant;
        let executable = self.execution.executable();
        let network = &executable.network;
        let name = |p: TimePointId| network.point(p).name.clone();
        let window = |p: TimePointId| {
            self.windows
                .get(p.index())
                .copied()
                .flatten()
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
            GoalEvent::GoalFailed { goal, reason } => {
                let goal = network.goal(goal);
                let sv = goal.sv.unwrap_or(ComponentId(0));
                let mode = modes.get(sv.index()).copied().unwrap_or(ValueId(0));
                EventKind::MissionGoalFailed {
                    goal: goal.name.clone(),
                    reason: failure_text(&reason, self.mission.knowledge_threshold),
                    mode: mode_name(plant, sv, mode),
                    probability: self.beliefs[sv.index()]
                        .get(mode.index())
                        .copied()
                        .unwrap_or(0.0),
                }
            }
            GoalEvent::TemporalInconsistency {
                point,
                inconsistency,
            } => {
                let text =
                    display::explain(&ScheduleError::Inconsistent(inconsistency), network, plant);
                EventKind::TemporalInconsistency {
                    point: name(point),
                    cycle: text.lines().skip(1).map(|l| l.trim().to_string()).collect(),
                }
            }
        };
        Some(kind)
    }
}

/// A failure's reason in words; the mode ŝ is in is shown beside it.
fn failure_text(reason: &FailureReason, threshold: f64) -> String {
    match reason {
        FailureReason::Excursion(_) => "ŝ left the maintained set".to_string(),
        FailureReason::Unreachable(_) => "its set can no longer be reached".to_string(),
        FailureReason::EndForced(_) => "its end point was forced before the set was reached".into(),
        FailureReason::NotKnown => format!("not known (P below {threshold} or a least belief)"),
    }
}

fn mode_name(plant: &Plant, sv: ComponentId, mode: ValueId) -> String {
    let component = plant.component(sv);
    format!("{} = {}", component.name(), component.mode(mode).name)
}
