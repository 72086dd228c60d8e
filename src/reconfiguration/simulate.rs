//! The command sequence the reactive planner produces when every command succeeds nominally
//! (`kairos plan`): cycle after cycle, ask the planner for its action, then let the
//! plant take the nominal transitions that action enables, as mode estimation would confirm
//! them.
//!
//! In a simulated cycle every component takes at most one transition: the one the action meant
//! to cause when it is enabled, otherwise the first enabled nominal per-cycle transition (a
//! command succeeds at once); a timed or rate transition fires only when the planner waits for
//! it (the wait lasts until it has fired). Faults never strike.

use super::Reconfiguration;
use super::goal::GoalState;
use super::planner::{Action, PlanFailure};
use crate::logic::ValueId;
use crate::opsat::Theory;
use crate::plant::{ComponentId, ModeKind, StepError, TransitionLaw, enabled_transitions};

/// A transition a component took in a simulated cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Move {
    /// The component.
    pub component: ComponentId,
    /// The transition, by index into the component's transitions.
    pub transition: usize,
    /// The mode it left.
    pub from: ValueId,
    /// The mode it entered.
    pub to: ValueId,
}

/// One simulated cycle: the planner's action and what the plant did.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanStep {
    /// The action issued.
    pub action: Action,
    /// The transitions taken in response.
    pub moves: Vec<Move>,
    /// Every component's mode after the cycle.
    pub state: Vec<ValueId>,
}

/// How a simulated run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum PlanOutcome {
    /// The planner reported the goal state achieved.
    Achieved,
    /// The planner had no action.
    Failed(PlanFailure),
    /// An action changed nothing: the plant did not respond as the policy expected.
    Stalled {
        /// What was expected.
        reason: String,
    },
    /// The step limit was reached first.
    StepLimit,
    /// The run came back to a state it had already been in: these components went round
    /// (the goal state is one the plant leaves by itself, see [`GoalState::leaving`]).
    Oscillating {
        /// The components whose modes changed between the two visits.
        components: Vec<ComponentId>,
    },
}

/// A simulated run from a start state to a goal state.
#[derive(Debug, Clone, PartialEq)]
pub struct NominalRun {
    /// The cycles, in order; the last action (achieved, failed) is not among them.
    pub steps: Vec<PlanStep>,
    /// How it ended.
    pub outcome: PlanOutcome,
}

/// See [`Reconfiguration::simulate_nominal`].
pub(crate) fn simulate_nominal(
    reconfiguration: &Reconfiguration,
    theory: &mut Theory,
    start: &[ValueId],
    goal: &GoalState,
    max_steps: usize,
) -> Result<NominalRun, StepError> {
    let mut state = start.to_vec();
    let mut steps: Vec<PlanStep> = Vec::new();
    for _ in 0..max_steps {
        let action = reconfiguration.next_action(&state, goal);
        match action {
            Action::Achieved => return Ok(finish(steps, PlanOutcome::Achieved)),
            Action::Failure(failure) => return Ok(finish(steps, PlanOutcome::Failed(failure))),
            Action::Command(_) | Action::Idle(_) => {}
        }
        let moves = cycle(reconfiguration, theory, &state, &action)?;
        if moves.is_empty() {
            let plant = reconfiguration.plant();
            let reason = format!("nothing responded to `{}`", action.describe(plant));
            return Ok(finish(steps, PlanOutcome::Stalled { reason }));
        }
        for m in &moves {
            state[m.component.index()] = m.to;
        }
        steps.push(PlanStep {
            action,
            moves,
            state: state.clone(),
        });
        // A nominal run that comes back to a state goes round for ever: say who goes round.
        let earlier = std::iter::once(start)
            .chain(steps[..steps.len() - 1].iter().map(|s| s.state.as_slice()))
            .position(|seen| seen == state.as_slice());
        if let Some(first) = earlier {
            let mut components: Vec<ComponentId> = steps[first..]
                .iter()
                .flat_map(|s| s.moves.iter().map(|m| m.component))
                .collect();
            components.sort_unstable();
            components.dedup();
            return Ok(finish(steps, PlanOutcome::Oscillating { components }));
        }
    }
    Ok(finish(steps, PlanOutcome::StepLimit))
}

fn finish(steps: Vec<PlanStep>, outcome: PlanOutcome) -> NominalRun {
    NominalRun { steps, outcome }
}

/// The transitions taken in one cycle under `action` (see the module doc).
fn cycle(
    reconfiguration: &Reconfiguration,
    theory: &mut Theory,
    state: &[ValueId],
    action: &Action,
) -> Result<Vec<Move>, StepError> {
    let plant = reconfiguration.plant();
    let Ok(commands) = action.commands(plant) else {
        return Ok(Vec::new());
    };
    let enabled = enabled_transitions(plant, theory, state, &commands)?;
    let intended = match action {
        Action::Command(c) => Some((c.component, c.transition)),
        Action::Idle(w) => Some((w.component, w.transition)),
        _ => None,
    };
    let awaited = match action {
        Action::Idle(w) => Some((w.component, w.transition)),
        _ => None,
    };
    let mut moves = Vec::new();
    for ((id, component), enabled) in plant.component_ids().zip(&enabled) {
        let nominal = enabled.transitions.iter().copied().filter(|&t| {
            let transition = &component.transitions()[t];
            let immediate = matches!(transition.law, TransitionLaw::PerCycle { .. });
            component.mode(transition.target).kind == ModeKind::Nominal
                && (immediate || awaited == Some((id, t)))
        });
        let chosen: Vec<usize> = nominal.collect();
        let pick = chosen
            .iter()
            .copied()
            .find(|&t| intended == Some((id, t)))
            .or_else(|| chosen.first().copied());
        if let Some(t) = pick {
            moves.push(Move {
                component: id,
                transition: t,
                from: state[id.index()],
                to: component.transitions()[t].target,
            });
        }
    }
    Ok(moves)
}
