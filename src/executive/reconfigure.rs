//! Step 4 of the cycle (thesis §6.3, DESIGN.md §9): goal interpretation of the configuration
//! goal g(i) on the estimate ŝ, the planner's next action toward the intended configuration,
//! the command issued (checked against the active goals, `faithful`), and the retry or failure
//! when a goal stays unreached. Every action is reported with what it serves.
//!
//! The intended configuration is settled on ŝ every cycle (a reached transient goal mode
//! replaced by where the component goes by itself, a kept mode left for good by where it is),
//! but only when ŝ differs from the one it was last settled on: settling is idempotent
//! (`GoalState::settle`, with its argument and property test), and nothing else writes the
//! intended configuration without settling it on the ŝ of that cycle. On the Mars lander's
//! quiet cruise cycle (the same ŝ for thousands of cycles) that took 38.9 k → 38.3 k
//! instructions (−645) and 4 % off the nominal EDL's CPU time (median of 7 pairs, noisy).

use std::sync::Arc;

use super::control::Program;
use super::{EventKind, EventLog, Executive, Interpretation, Served};
use crate::logic::{Formula, ValueId, VarId};
use crate::plant::{Commands, ComponentId};
use crate::reconfiguration::{Action, Ambiguity, GoalFailed, GoalState, Hypothesis};
use crate::sequencer::ConfigurationGoal;

impl Executive {
    /// Step 4: goal interpretation (cached while g, ŝ and the intended configuration are
    /// unchanged) and the planner's action toward the intended configuration.
    pub(super) fn reconfigure(
        &mut self,
        goal: Option<&ConfigurationGoal>,
        log: &mut EventLog,
    ) -> (Option<GoalState>, Option<Action>) {
        let modes = self.most_likely();
        // A transient goal mode, once reached, is achieved: the plant is then meant to be where
        // it leaves it for by itself, also as the configuration a new goal keeps
        // (docs/design/reconfiguration.md, "The intended configuration").
        if let Some(intended) = &mut self.intended {
            // Settling is idempotent (`GoalState::settle`): a goal state settled on this very ŝ
            // (`intended_settled_on`) is settled already.
            let on = &mut self.intended_settled_on;
            if !on
                .as_ref()
                .is_some_and(|on| Arc::ptr_eq(on, &modes) || **on == *modes)
            {
                self.reconfiguration.settle_in_place(intended, &modes);
                *on = Some(Arc::clone(&modes));
            }
            // The crate's tests check what the skip relies on, with settling's own code.
            #[cfg(test)]
            assert_eq!(
                &self.reconfiguration.settle(intended, &modes),
                intended,
                "the intended configuration is settled on ŝ"
            );
            self.faithful.settle(&modes, intended.modes());
        }
        if log
            .events
            .iter()
            .any(|e| matches!(e.kind, EventKind::Safing { .. }))
        {
            self.faithful.forget_helpers();
        }
        let Some(goal) = goal.filter(|g| !matches!(g.formula, Formula::True)) else {
            // No goal: only helpers a plan moved are brought back (`faithful.rs`).
            self.reported.goal_failure = None;
            return self.restore_helpers(&modes);
        };
        match self.interpret(goal, &modes) {
            Ok(goal_state) => {
                self.reported.goal_failure = None;
                self.intended = Some(self.reconfiguration.settle(&goal_state, &modes));
                self.intended_settled_on = Some(Arc::clone(&modes));
            }
            Err(failed) => return self.retry_or_fail(goal, &modes, &failed, log),
        }
        let Some(intended) = &self.intended else {
            return (None, None);
        };
        let action = self.reconfiguration.next_action(&modes, intended);
        (Some(intended.clone()), Some(action))
    }

    /// The goal is unreachable from ŝ: the planner's command from another tracked plant state
    /// that can serve it, while the retry budget lasts (`reconfiguration::Ambiguity`),
    /// or the goal failure, naming the hypotheses tried. The intended configuration is
    /// left as it was: a hypothesis is acted on, not believed.
    fn retry_or_fail(
        &mut self,
        goal: &ConfigurationGoal,
        modes: &[ValueId],
        failed: &GoalFailed,
        log: &mut EventLog,
    ) -> (Option<GoalState>, Option<Action>) {
        let keep = self.keep(modes);
        let plausible = if Ambiguity::may_help(failed) {
            self.estimates.as_slice()
        } else {
            &[]
        };
        let hypotheses = plausible.iter().map(|e| Hypothesis {
            modes: &e.modes,
            probability: e.probability,
        });
        let retry = self.ambiguity.retry(
            (&self.reconfiguration, &mut self.theory),
            &goal.formula,
            (modes, &keep),
            hypotheses,
            &self.options.ambiguity,
        );
        if let Some(retry) = retry {
            let assignments = match &retry.action {
                Action::Command(command) => command.assignments.as_slice(),
                _ => &[],
            };
            let table = self.plant.table();
            log.push(EventKind::Retrying {
                goal: goal.formula.display(table).to_string(),
                assignments: (assignments.iter())
                    .map(|&(x, v)| table.assignment(x, v).to_string())
                    .collect(),
                hypothesis: retry.describe_hypothesis(&self.plant),
                probability: retry.probability,
                attempt: retry.attempt,
                budget: self.options.ambiguity.retries,
            });
            return (Some(retry.goal_state), Some(retry.action));
        }
        let reason = self.ambiguity.explain(&self.plant, failed);
        if self.reported.goal_failure.as_ref() != Some(&reason) {
            log.push(EventKind::GoalFailed {
                goal: goal.formula.display(self.plant.table()).to_string(),
                reason: reason.clone(),
            });
            self.reported.goal_failure = Some(reason);
        }
        (None, None)
    }

    /// The configuration goal interpretation keeps where the goal allows: ŝ, except for the
    /// helpers still to be brought back to their intended modes (`faithful.rs`).
    fn keep(&self, modes: &[ValueId]) -> Vec<ValueId> {
        let intended = self.intended.as_ref().map(GoalState::modes);
        self.faithful.keep(modes, intended)
    }

    /// Goal interpretation of `goal` from ŝ, keeping the intended configuration where the goal
    /// allows; the answer is reused while its inputs do not change.
    fn interpret(
        &mut self,
        goal: &ConfigurationGoal,
        modes: &[ValueId],
    ) -> Result<GoalState, GoalFailed> {
        let keep = self.keep(modes);
        let fresh = self
            .interpretation
            .as_ref()
            .is_some_and(|i| i.goal == goal.formula && i.modes == modes && i.keep == keep);
        if !fresh {
            let result = self.reconfiguration.interpret_keeping(
                &mut self.theory,
                modes,
                &goal.formula,
                &keep,
            );
            self.interpretation = Some(Interpretation {
                goal: goal.formula.clone(),
                modes: modes.to_vec(),
                keep,
                result,
            });
        }
        match self.interpretation.as_ref().map(|i| &i.result) {
            Some(Ok(state)) => Ok(state.clone()),
            Some(Err(failed)) => Err(failed.clone()),
            None => Err(GoalFailed {
                reason: "goal interpretation did not run".to_string(),
                cause: crate::reconfiguration::FailureCause::BadInput,
            }),
        }
    }

    /// Turns the planner's action into μ(i), reports it, and remembers it for estimation.
    pub(super) fn issue(
        &mut self,
        action: Option<&Action>,
        purpose: Purpose<'_>,
        log: &mut EventLog,
    ) -> Vec<(VarId, ValueId)> {
        let assignments = match action {
            Some(Action::Command(command)) => command.assignments.clone(),
            _ => Vec::new(),
        };
        self.report_action(action, purpose, log);
        // The planner only commands controls with their own values, so this cannot fail; were
        // it to, idling is the safe reading.
        self.last_command = Commands::new(&self.plant, &assignments)
            .unwrap_or_else(|_| Commands::idle(&self.plant));
        self.timelines.record_command(log.time, assignments.clone());
        assignments
    }

    fn report_action(&mut self, action: Option<&Action>, purpose: Purpose<'_>, log: &mut EventLog) {
        let awaited = action.and_then(|a| match a {
            Action::Idle(_) => a.intended(),
            _ => None,
        });
        match action {
            Some(command @ Action::Command(c)) => {
                let table = self.plant.table();
                log.push(EventKind::CommandIssued {
                    assignments: c
                        .assignments
                        .iter()
                        .map(|&(x, v)| table.assignment(x, v).to_string())
                        .collect(),
                    purpose: command.describe(&self.plant),
                    repair: c.repair,
                    serves: self.served(c.serves, purpose),
                });
            }
            Some(wait @ Action::Idle(_)) if awaited != self.reported.awaited => {
                log.push(EventKind::Waiting {
                    purpose: wait.describe(&self.plant),
                });
            }
            Some(Action::Failure(failure))
                if self.reported.plan_failure.as_ref() != Some(&failure.reason) =>
            {
                log.push(EventKind::PlanFailed {
                    reason: failure.reason.clone(),
                });
                self.reported.plan_failure = Some(failure.reason.clone());
            }
            _ => {}
        }
        if !matches!(action, Some(Action::Failure(_))) {
            self.reported.plan_failure = None;
        }
        self.reported.awaited = awaited;
    }

    /// The goals a command moving `component` toward its goal mode serves ([`Served`]): the
    /// conjuncts of g(i) naming its mode, or the mission's goals on it, or else its mode in the
    /// intended configuration. Computed only for a cycle that issues a command.
    fn served(&self, component: ComponentId, purpose: Purpose<'_>) -> Vec<Served> {
        let var = self.plant.component(component).mode_var();
        let table = self.plant.table();
        let mut served: Vec<Served> = match &self.control.0 {
            Program::Mission(mission) => (mission.serving(component).into_iter())
                .map(|goal| Served::Mission { goal })
                .collect(),
            Program::Rmpl(_) => (purpose.goal.iter())
                .flat_map(|g| &g.conjuncts)
                .filter(|c| c.formula.variables().contains(&var))
                .map(|c| Served::Program {
                    goal: c.formula.display(table).to_string(),
                    span: c.span.clone(),
                })
                .collect(),
        };
        if served.is_empty() {
            served.extend(purpose.intended.map(|state| {
                let mode = table.assignment(var, state.mode(component)).to_string();
                let goal = match (&self.faithful.helpers[component.index()], purpose.goal) {
                    (Some(moved_for), _) => {
                        format!("{mode}, bringing back a helper moved for {moved_for}")
                    }
                    (None, Some(g)) => {
                        format!("{mode} in the goal state of {}", g.formula.display(table))
                    }
                    (None, None) => mode,
                };
                Served::Intended { goal }
            }));
        }
        served
    }
}

/// What a cycle's action is for: the configuration goal g(i) and the intended configuration
/// goal interpretation chose for it.
#[derive(Clone, Copy)]
pub(super) struct Purpose<'a> {
    pub(super) goal: Option<&'a ConfigurationGoal>,
    pub(super) intended: Option<&'a GoalState>,
}
