//! Acting under diagnostic ambiguity (beyond thesis §6.3, whose executive acts
//! on ŝ alone): when goal interpretation finds the goal unreachable from ŝ, the other plant states
//! mode estimation tracks are tried, most probable first, and the planner's next command toward
//! the goal *from the first one it can serve* is sent — so that the next estimate decides.
//!
//! The case it is for: at powered descent valve 2 does not answer `open2`; mode estimation
//! rightly prefers `valve2 = stuck-closed` (p 0.59) to "the command was not taken" (`valve2 =
//! closed`, p 0.41). From stuck-closed `engine = firing` is unreachable; from closed it is one
//! command away. A flight engineer sends `open2` once more: if the valve opens, the pressure
//! refutes stuck-closed; if it does not, a second silence leaves "not taken" at about 0.001 and
//! the goal fails, naming both explanations.
//!
//! The rules (docs/design/reconfiguration.md, "Acting under diagnostic ambiguity"):
//! - a hypothesis is a tracked plant state other than ŝ with probability ≥
//!   [`AmbiguityOptions::threshold`]; they are considered in the belief's order, so the most
//!   probable one from which the goal is reachable and the planner has a *command* wins (a wait
//!   or "already achieved" on a hypothesis adds nothing to the idle a failed goal gets);
//! - every command sent on a hypothesis counts against [`AmbiguityOptions::retries`], per
//!   configuration goal: the count starts again only when the goal (or the configuration it
//!   keeps) changes, so a goal whose retries all failed fails for good even if the belief later
//!   wavers;
//! - goal interpretation runs on a hypothesis once per goal: a hypothesis from which the goal is
//!   unreachable too, or from which the planner has no command, is remembered and not tried
//!   again, so a failed goal costs no search on the cycles after it. Nothing here runs while the
//!   goal is reachable from ŝ.

use std::fmt::Write;

use super::{Action, FailureCause, GoalFailed, GoalState, Reconfiguration};
use crate::logic::{Formula, ValueId};
use crate::opsat::Theory;
use crate::plant::{ComponentId, Plant};

/// How reconfiguration acts when the goal is unreachable from ŝ but not from another tracked
/// plant state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AmbiguityOptions {
    /// A tracked plant state is acted on only with at least this probability.
    pub threshold: f64,
    /// At most this many commands per configuration goal are sent on a plant state other than ŝ
    /// (0 acts on ŝ alone, as the thesis does).
    pub retries: u32,
}

impl Default for AmbiguityOptions {
    /// Threshold 0.05, two retries (docs/design/reconfiguration.md, "Acting under diagnostic
    /// ambiguity", says why).
    fn default() -> Self {
        AmbiguityOptions {
            threshold: 0.05,
            retries: 2,
        }
    }
}

/// A tracked plant state other than ŝ: a mode per component and its probability.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hypothesis<'a> {
    /// A mode per component, by [`ComponentId`].
    pub modes: &'a [ValueId],
    /// Its probability in the belief.
    pub probability: f64,
}

/// A hypothesis considered for a goal: a command was sent on it, or it could not serve.
#[derive(Debug, Clone, PartialEq)]
pub struct Tried {
    /// Where it differs from ŝ when it was first considered: `(component, mode)`.
    pub differences: Vec<(ComponentId, ValueId)>,
    /// Its probability when it was first considered.
    pub probability: f64,
    /// Commands sent on it.
    pub commands: u32,
    /// Why no command was sent on it, when none was.
    pub unserved: Option<Unserved>,
}

/// Why a hypothesis above the threshold was not acted on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Unserved {
    /// The goal is unreachable from it too.
    Unreachable,
    /// The planner has no command from it (it would wait, or the goal already holds there).
    NoCommand,
}

impl Tried {
    /// `valve2 = closed` (several differences joined by `and`).
    pub fn describe(&self, plant: &Plant) -> String {
        describe_differences(plant, &self.differences)
    }
}

/// A command toward the goal computed from a hypothesis rather than from ŝ.
#[derive(Debug, Clone, PartialEq)]
pub struct Retry {
    /// The goal state goal interpretation chose from the hypothesis.
    pub goal_state: GoalState,
    /// The planner's action from the hypothesis: always an [`Action::Command`].
    pub action: Action,
    /// Where the hypothesis differs from ŝ: `(component, mode)`.
    pub differences: Vec<(ComponentId, ValueId)>,
    /// The hypothesis's probability now.
    pub probability: f64,
    /// Which retry of the goal this is, from 1.
    pub attempt: u32,
}

impl Retry {
    /// `valve2 = closed`: what the retry assumes.
    pub fn describe_hypothesis(&self, plant: &Plant) -> String {
        describe_differences(plant, &self.differences)
    }
}

/// The hypotheses tried for one configuration goal and the retries spent on it. The caller (the
/// executive) owns one and hands it every failed goal interpretation; it starts afresh by itself
/// when the goal changes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Ambiguity {
    /// The goal and kept configuration the record is for.
    key: Option<(Formula, Vec<ValueId>)>,
    /// Hypotheses considered, in the order first considered: acted on, or (with `unserved`)
    /// not, and then not considered again.
    tried: Vec<(Vec<ValueId>, Tried)>,
    retries: u32,
}

impl Ambiguity {
    /// With the goal unreachable from `current` (ŝ), the command to send on the most probable
    /// hypothesis that can serve it, or `None` when none can or the retries are spent.
    /// `hypotheses` are the tracked plant states, most probable first (ŝ among them is skipped);
    /// `keep` is the configuration goal interpretation keeps (as for ŝ). Runs goal
    /// interpretation at most once per hypothesis and goal.
    pub fn retry<'a>(
        &mut self,
        (reconfiguration, theory): (&Reconfiguration, &mut Theory),
        goal: &Formula,
        (current, keep): (&[ValueId], &[ValueId]),
        hypotheses: impl IntoIterator<Item = Hypothesis<'a>>,
        options: &AmbiguityOptions,
    ) -> Option<Retry> {
        self.start(goal, keep);
        if self.retries >= options.retries {
            return None;
        }
        for hypothesis in hypotheses {
            if hypothesis.probability < options.threshold {
                break;
            }
            let modes = hypothesis.modes;
            let unserved = |(m, t): &(Vec<ValueId>, Tried)| m == modes && t.unserved.is_some();
            if modes == current || self.tried.iter().any(unserved) {
                continue;
            }
            let served = reconfiguration
                .interpret_keeping(theory, modes, goal, keep)
                .map(|goal_state| {
                    let action = reconfiguration.next_action(modes, &goal_state);
                    (goal_state, action)
                });
            let why = match served {
                Ok((goal_state, action @ Action::Command(_))) => {
                    return Some(self.record(current, hypothesis, goal_state, action));
                }
                Ok(_) => Unserved::NoCommand,
                Err(_) => Unserved::Unreachable,
            };
            self.tried.push((
                modes.to_vec(),
                Tried {
                    differences: differences(current, modes),
                    probability: hypothesis.probability,
                    commands: 0,
                    unserved: Some(why),
                },
            ));
        }
        None
    }

    /// True when another plant state might serve a goal that failed from ŝ for this reason: the
    /// goal was unreachable or not entailed there. A goal that contradicts itself or the model,
    /// or that cannot be interpreted, fails from every state.
    pub fn may_help(failed: &GoalFailed) -> bool {
        matches!(
            failed.cause,
            FailureCause::Unreachable { .. } | FailureCause::NotEntailed
        )
    }

    /// The hypotheses considered for the current goal, in the order first considered.
    pub fn tried(&self) -> impl Iterator<Item = &Tried> {
        self.tried.iter().map(|(_, tried)| tried)
    }

    /// Commands sent on hypotheses for the current goal.
    pub fn retries(&self) -> u32 {
        self.retries
    }

    /// Goal interpretation's failure from ŝ with the hypotheses considered for the goal:
    /// `...: valve2 is stuck-closed); also tried valve2 = closed (p 0.41, 1 retry); unreachable
    /// also if valve2 = open and tank2 = empty (p 0.09)`. The failure's own reason when none was
    /// considered. Probabilities are those of the first consideration, so the text stays the
    /// same from cycle to cycle (the executive reports a failure once).
    pub fn explain(&self, plant: &Plant, failed: &GoalFailed) -> String {
        let mut reason = failed.reason.clone();
        self.list(plant, &mut reason, "also tried", None);
        let unreachable = Some(Unserved::Unreachable);
        self.list(plant, &mut reason, "unreachable also if", unreachable);
        let no_command = Some(Unserved::NoCommand);
        self.list(plant, &mut reason, "nothing to command if", no_command);
        reason
    }

    /// Appends `; LEAD h1 (p ..), h2 (p ..)` for the hypotheses with this `unserved`.
    fn list(&self, plant: &Plant, out: &mut String, lead: &str, unserved: Option<Unserved>) {
        let group = self.tried().filter(|t| t.unserved == unserved);
        for (k, tried) in group.enumerate() {
            let lead = if k == 0 {
                format!("; {lead} ")
            } else {
                ", ".into()
            };
            let retries = match tried.commands {
                0 => String::new(),
                1 => ", 1 retry".to_string(),
                n => format!(", {n} retries"),
            };
            let what = tried.describe(plant);
            let _ = write!(out, "{lead}{what} (p {:.2}{retries})", tried.probability);
        }
    }

    /// Starts a fresh record when the goal or the kept configuration changed.
    fn start(&mut self, goal: &Formula, keep: &[ValueId]) {
        let same = self
            .key
            .as_ref()
            .is_some_and(|(g, k)| g == goal && k.as_slice() == keep);
        if !same {
            *self = Ambiguity {
                key: Some((goal.clone(), keep.to_vec())),
                ..Ambiguity::default()
            };
        }
    }

    fn record(
        &mut self,
        current: &[ValueId],
        hypothesis: Hypothesis<'_>,
        goal_state: GoalState,
        action: Action,
    ) -> Retry {
        let differences = differences(current, hypothesis.modes);
        self.retries += 1;
        match self.tried.iter_mut().find(|(m, _)| m == hypothesis.modes) {
            Some((_, tried)) => tried.commands += 1,
            None => self.tried.push((
                hypothesis.modes.to_vec(),
                Tried {
                    differences: differences.clone(),
                    probability: hypothesis.probability,
                    commands: 1,
                    unserved: None,
                },
            )),
        }
        Retry {
            goal_state,
            action,
            differences,
            probability: hypothesis.probability,
            attempt: self.retries,
        }
    }
}

/// The components whose mode in `hypothesis` differs from `current`, with the hypothesis's mode.
fn differences(current: &[ValueId], hypothesis: &[ValueId]) -> Vec<(ComponentId, ValueId)> {
    current
        .iter()
        .zip(hypothesis)
        .enumerate()
        .filter(|(_, (a, b))| a != b)
        .map(|(c, (_, &mode))| (ComponentId(c as u32), mode))
        .collect()
}

fn describe_differences(plant: &Plant, differences: &[(ComponentId, ValueId)]) -> String {
    differences
        .iter()
        .map(|&(c, mode)| {
            let component = plant.component(c);
            format!("{} = {}", component.name(), component.mode(mode).name)
        })
        .collect::<Vec<_>>()
        .join(" and ")
}

#[cfg(test)]
mod tests {
    use super::super::testing::{SWITCH_GADGET, load, mode, state};
    use super::super::{Action, Reconfiguration};
    use super::{Ambiguity, AmbiguityOptions, Hypothesis, Retry};
    use crate::logic::Formula;
    use crate::plant::Plant;

    /// `name = mode` for a component's mode variable.
    fn is(plant: &Plant, name: &str, mode_name: &str) -> Formula {
        let component = plant.component_named(name).expect("component");
        let var = plant.component(component).mode_var();
        Formula::is(var, mode(plant, name, mode_name))
    }

    /// `gadget = b`: reachable only with the switch on, so not from a stuck switch.
    fn gadget_b(plant: &Plant) -> Formula {
        is(plant, "gadget", "b")
    }

    struct Fixture {
        plant: Plant,
        reconfiguration: Reconfiguration,
        theory: crate::opsat::Theory,
    }

    impl Fixture {
        /// The modes `switch = names[0]`, `gadget = names[1]`.
        fn state(&self, names: [&str; 2]) -> Vec<crate::logic::ValueId> {
            state(&self.plant, &names)
        }

        /// What `ambiguity` does for `goal`, unreachable from ŝ = the switch stuck with the
        /// gadget at `a`, when the belief also holds `hypothesis` at probability `p`.
        fn retry_with(
            &mut self,
            ambiguity: &mut Ambiguity,
            goal: &Formula,
            (hypothesis, p): ([&str; 2], f64),
            options: &AmbiguityOptions,
        ) -> Option<Retry> {
            let stuck = self.state(["stuck", "a"]);
            let modes = self.state(hypothesis);
            let belief = [Hypothesis {
                modes: &modes,
                probability: p,
            }];
            ambiguity.retry(
                (&self.reconfiguration, &mut self.theory),
                goal,
                (&stuck, &stuck),
                belief,
                options,
            )
        }
    }

    fn fixture() -> Fixture {
        let plant = load(SWITCH_GADGET);
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let theory = plant.theory().expect("theory");
        Fixture {
            plant,
            reconfiguration,
            theory,
        }
    }

    #[test]
    fn the_goal_is_pursued_from_the_most_probable_hypothesis_that_reaches_it() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let stuck = state(&f.plant, &["stuck", "a"]);
        let off = state(&f.plant, &["off", "a"]);
        let broken = state(&f.plant, &["stuck", "broken"]);
        // From ŝ (the switch stuck) the goal is unreachable: the premise of a retry.
        assert!(
            f.reconfiguration
                .interpret(&mut f.theory, &stuck, &goal)
                .is_err()
        );
        let belief = [
            Hypothesis {
                modes: &stuck,
                probability: 0.5,
            },
            Hypothesis {
                modes: &broken,
                probability: 0.3,
            },
            Hypothesis {
                modes: &off,
                probability: 0.2,
            },
        ];
        let mut ambiguity = Ambiguity::default();
        let retry = ambiguity
            .retry(
                (&f.reconfiguration, &mut f.theory),
                &goal,
                (&stuck, &stuck),
                belief,
                &AmbiguityOptions::default(),
            )
            .expect("a retry from switch = off");
        assert_eq!(retry.describe_hypothesis(&f.plant), "switch = off");
        assert_eq!(retry.attempt, 1);
        assert_eq!(retry.probability, 0.2);
        let Action::Command(command) = &retry.action else {
            panic!("{:?}", retry.action);
        };
        assert_eq!(
            retry.action.summary(&f.plant),
            "command switch.cmd = on",
            "{command:?}"
        );
        // The switch is a helper: on to move the gadget, off again in the goal state.
        assert_eq!(retry.goal_state.modes(), state(&f.plant, &["off", "b"]));
    }

    #[test]
    fn hypotheses_below_the_threshold_are_not_acted_on() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let retry = f.retry_with(
            &mut Ambiguity::default(),
            &goal,
            (["off", "a"], 0.04),
            &AmbiguityOptions::default(),
        );
        assert_eq!(retry, None);
    }

    #[test]
    fn retries_are_bounded_per_goal_and_the_failure_names_every_hypothesis_tried() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let stuck = f.state(["stuck", "a"]);
        let options = AmbiguityOptions {
            threshold: 0.05,
            retries: 2,
        };
        let mut ambiguity = Ambiguity::default();
        let attempts: Vec<_> = [0.4, 0.3, 0.2]
            .into_iter()
            .map(|p| {
                f.retry_with(&mut ambiguity, &goal, (["off", "a"], p), &options)
                    .map(|r| r.attempt)
            })
            .collect();
        assert_eq!(attempts, [Some(1), Some(2), None]);
        let failed = f
            .reconfiguration
            .interpret(&mut f.theory, &stuck, &goal)
            .expect_err("unreachable from ŝ");
        let reason = ambiguity.explain(&f.plant, &failed);
        assert!(reason.starts_with(&failed.reason), "{reason}");
        assert!(
            reason.ends_with("; also tried switch = off (p 0.40, 2 retries)"),
            "{reason}"
        );
    }

    #[test]
    fn a_new_goal_gets_a_new_budget() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let other = Formula::And(vec![goal.clone(), is(&f.plant, "switch", "on")]);
        let options = AmbiguityOptions {
            threshold: 0.05,
            retries: 1,
        };
        let mut ambiguity = Ambiguity::default();
        let mut retry = |goal: &Formula| {
            f.retry_with(&mut ambiguity, goal, (["off", "a"], 0.4), &options)
                .map(|r| r.attempt)
        };
        assert_eq!(retry(&goal), Some(1));
        assert_eq!(retry(&goal), None);
        assert_eq!(retry(&other), Some(1));
    }

    #[test]
    fn only_an_unreachable_goal_may_be_served_from_another_state() {
        let mut f = fixture();
        let stuck = state(&f.plant, &["stuck", "a"]);
        let unreachable = f
            .reconfiguration
            .interpret(&mut f.theory, &stuck, &gadget_b(&f.plant))
            .expect_err("unreachable from ŝ");
        assert!(Ambiguity::may_help(&unreachable), "{unreachable:?}");
        let both = Formula::And(vec![
            is(&f.plant, "gadget", "a"),
            is(&f.plant, "gadget", "b"),
        ]);
        let contradictory = f
            .reconfiguration
            .interpret(&mut f.theory, &stuck, &both)
            .expect_err("contradictory");
        assert!(!Ambiguity::may_help(&contradictory), "{contradictory:?}");
    }

    #[test]
    fn no_retries_act_on_the_estimate_alone() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let options = AmbiguityOptions {
            threshold: 0.05,
            retries: 0,
        };
        let mut ambiguity = Ambiguity::default();
        let retry = f.retry_with(&mut ambiguity, &goal, (["off", "a"], 0.4), &options);
        assert_eq!(retry, None);
        assert_eq!(ambiguity.tried().count(), 0);
        assert_eq!(ambiguity.retries(), 0);
    }

    #[test]
    fn a_hypothesis_that_cannot_serve_the_goal_is_not_searched_again() {
        let mut f = fixture();
        let goal = gadget_b(&f.plant);
        let stuck = f.state(["stuck", "a"]);
        let mut ambiguity = Ambiguity::default();
        for _ in 0..2 {
            let retry = f.retry_with(
                &mut ambiguity,
                &goal,
                (["stuck", "broken"], 0.4),
                &AmbiguityOptions::default(),
            );
            assert_eq!(retry, None);
        }
        let tried: Vec<_> = ambiguity.tried().collect();
        assert_eq!(tried.len(), 1);
        assert_eq!(tried[0].unserved, Some(super::Unserved::Unreachable));
        assert_eq!(ambiguity.retries(), 0);
        let failed = f
            .reconfiguration
            .interpret(&mut f.theory, &stuck, &goal)
            .expect_err("unreachable from ŝ");
        let reason = ambiguity.explain(&f.plant, &failed);
        assert!(
            reason.ends_with("; unreachable also if gadget = broken (p 0.40)"),
            "{reason}"
        );
    }
}
