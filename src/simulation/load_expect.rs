//! Loading a scenario's expectations, each problem located in the scenario file.

use super::ScenarioProgram;
use super::condition::Condition;
use super::expectation::{Expectation, ExpectationKind, Window};
use super::format::{ConditionFile, DelayFile, EventName, ExpectFile};
use super::load::{FileCtx, VarClasses, Vars, formula};
use super::script::{Delay, Script};
use crate::diagnostic::locate::Step;
use crate::diagnostic::{Diagnostic, did_you_mean};
use crate::executive::Submission;
use crate::goalnet::MissionNames;
use crate::logic::{Formula, ValueId};
use crate::plant::{ComponentId, ModeKind, Plant};
use crate::sequencer::Thca;

/// Every expectation of the scenario that is valid; errors are recorded in `ctx`.
pub(super) fn expectations(
    ctx: &mut FileCtx,
    files: &[ExpectFile],
    plant: &Plant,
    program: &ScenarioProgram,
    (script, declared): (&Script, &[String]),
    end: f64,
) -> Vec<Expectation> {
    let loader = ExpectLoader {
        plant,
        script,
        declared,
        classes: VarClasses::new(plant, script.hidden.clone()),
        goals: program
            .thca()
            .map_or_else(Vec::new, |t| program_goals(plant, t)),
        names: program.mission().map(|m| {
            let mission = m.mission();
            let mut names = mission.elaborators.names(&mission.network, &mission.safe);
            // What the tactics of a typed goal a rule submits will name.
            let submitted = script
                .rules()
                .iter()
                .filter_map(|r| r.effect.submit.as_ref());
            for goal in submitted.flat_map(|s| &s.goals) {
                if let Some(t) = goal.goal_type {
                    mission
                        .elaborators
                        .add_elaborated(&goal.name, t, &mut names);
                }
            }
            names
        }),
        end,
    };
    let mut expectations: Vec<Expectation> = files
        .iter()
        .enumerate()
        .filter_map(|(i, file)| {
            let at = [Step::Field("expect"), Step::Index(i)];
            loader.expectation(ctx, &at, file)
        })
        .collect();
    expectations.extend(invariants(&expectations));
    expectations
}

/// The events every scenario fails on unless one of its expectations names them (DESIGN.md
/// §9): a command against an active goal, and chatter.
pub(super) const INVARIANT_EVENTS: [EventName; 2] =
    [EventName::GoalContradicted, EventName::Chatter];

/// `NeverReported` for each of [`INVARIANT_EVENTS`] that no expectation of the scenario names
/// (a scenario that expects one says so, `Reported(event: Chatter, ...)`, and is judged by that).
fn invariants(expectations: &[Expectation]) -> Vec<Expectation> {
    INVARIANT_EVENTS
        .iter()
        .filter(|&&event| !expectations.iter().any(|e| names_event(&e.kind, event)))
        .map(|&event| Expectation {
            label: format!("never reported {event:?} (checked in every scenario)"),
            kind: ExpectationKind::NeverReported {
                event,
                saying: None,
                window: Window::ALWAYS,
            },
        })
        .collect()
}

/// True when the expectation is about events of this kind.
fn names_event(kind: &ExpectationKind, name: EventName) -> bool {
    match kind {
        ExpectationKind::Reported { event, .. } | ExpectationKind::NeverReported { event, .. } => {
            *event == name
        }
        ExpectationKind::AnyOf { members } => members.iter().any(|m| names_event(m, name)),
        _ => false,
    }
}

/// The goals the program's locations assert, displayed as the executive reports them.
fn program_goals(plant: &Plant, program: &Thca) -> Vec<String> {
    let mut goals: Vec<String> = program
        .locations()
        .iter()
        .filter_map(|l| l.goal())
        .map(|g| {
            program
                .formula(g.formula)
                .display(plant.table())
                .to_string()
        })
        .collect();
    goals.dedup();
    goals
}

struct ExpectLoader<'a> {
    plant: &'a Plant,
    script: &'a Script,
    /// Every rule the scenario and its includes declare, those with errors of their own (and
    /// so not in `script`) included.
    declared: &'a [String],
    classes: VarClasses,
    goals: Vec<String>,
    /// The names the mission's points and goals can have (`None` for an RMPL program).
    names: Option<MissionNames>,
    end: f64,
}

/// The path to a field of the expectation at `at`.
fn field<'a>(at: &[Step<'a>], name: &'a str) -> Vec<Step<'a>> {
    let mut path = at.to_vec();
    path.push(Step::Field(name));
    path
}

impl ExpectLoader<'_> {
    fn expectation(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        file: &ExpectFile,
    ) -> Option<Expectation> {
        use ExpectFile as F;
        use ExpectationKind as K;
        let (kind, label) = match file {
            F::Estimated { state, after, by } => (
                K::Estimated {
                    state: self.formula(ctx, at, "state", state, Vars::Modes)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("estimated {state}{}", eventual(*after, *by)),
            ),
            F::EstimatedAt { state, time } => (
                K::EstimatedAt {
                    state: self.formula(ctx, at, "state", state, Vars::Modes)?,
                    time: self.time(ctx, at, "time", *time)?,
                },
                format!("estimated {state} at {time} s"),
            ),
            F::NeverEstimated { state, from, to } => (
                K::NeverEstimated {
                    state: self.formula(ctx, at, "state", state, Vars::Modes)?,
                    window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                },
                format!("never estimated {state}{}", during(*from, *to)),
            ),
            F::Commanded { command, after, by } => (
                K::Commanded {
                    command: self.formula(ctx, at, "command", command, Vars::Controls)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("commanded {command}{}", eventual(*after, *by)),
            ),
            F::CommandsInOrder {
                commands,
                after,
                by,
            } => {
                let formulas: Vec<Option<Formula>> = commands
                    .iter()
                    .enumerate()
                    .map(|(k, text)| {
                        let mut path = field(at, "commands");
                        path.push(Step::Index(k));
                        formula(
                            ctx,
                            &path,
                            text,
                            &self.script.world,
                            Vars::Controls,
                            &self.classes,
                        )
                    })
                    .collect();
                (
                    K::CommandsInOrder {
                        commands: formulas.into_iter().collect::<Option<Vec<_>>>()?,
                        window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                    },
                    format!(
                        "commands in order: {}{}",
                        commands.join("; "),
                        eventual(*after, *by)
                    ),
                )
            }
            F::NeverCommanded { command, from, to } => (
                K::NeverCommanded {
                    command: self.formula(ctx, at, "command", command, Vars::Controls)?,
                    window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                },
                format!("never commanded {command}{}", during(*from, *to)),
            ),
            F::Diagnosed {
                fault,
                after,
                by,
                within,
                of,
            } => {
                let (component, mode) = self.fault(ctx, at, fault)?;
                let within = self.tolerance(ctx, at, *within, of.as_deref())?;
                let label = match (within, of) {
                    (Some((delay, _)), Some(rule)) => {
                        format!("diagnosed {fault} within {} of rule `{rule}`", show(delay))
                    }
                    _ => format!("diagnosed {fault}{}", eventual(*after, *by)),
                };
                (
                    K::Diagnosed {
                        component,
                        mode,
                        window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                        within,
                    },
                    label,
                )
            }
            F::Achieved { goal, after, by } => (
                K::Achieved {
                    goal: self.goal(ctx, at, goal)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("achieved {goal}{}", eventual(*after, *by)),
            ),
            F::GoalFailed { goal, after, by } => {
                let displayed = match goal {
                    Some(goal) => Some(self.goal(ctx, at, goal)?),
                    None => None,
                };
                let what = goal
                    .as_deref()
                    .map_or("a goal".to_string(), |g| format!("goal {g}"));
                (
                    K::GoalFailed {
                        goal: displayed,
                        window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                    },
                    format!("{what} failed{}", eventual(*after, *by)),
                )
            }
            F::Completed { after, by } => (
                K::Completed {
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("program completed{}", eventual(*after, *by)),
            ),
            F::Reported {
                event,
                saying,
                after,
                by,
            } => (
                K::Reported {
                    event: *event,
                    saying: self.saying(ctx, at, saying.as_deref())?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!(
                    "reported {event:?}{}{}",
                    quoted(saying.as_deref()),
                    eventual(*after, *by)
                ),
            ),
            F::AnyOf(members) => {
                let (members, labels) = self.members(ctx, at, members)?;
                (
                    K::AnyOf { members },
                    format!("any of: {}", labels.join("; ")),
                )
            }
            F::NeverReported {
                event,
                saying,
                from,
                to,
            } => (
                K::NeverReported {
                    event: *event,
                    saying: self.saying(ctx, at, saying.as_deref())?,
                    window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                },
                format!(
                    "never reported {event:?}{}{}",
                    quoted(saying.as_deref()),
                    during(*from, *to)
                ),
            ),
            F::Recovered { goal, after, by } => (
                K::Recovered {
                    goal: self.network_goal(ctx, at, goal)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("mission goal {goal} recovered{}", eventual(*after, *by)),
            ),
            F::NeverXGoalActive { sv, goal, from, to } => {
                self.names(ctx, at)?;
                let component = self.component(ctx, at, sv)?;
                let checked = match goal {
                    Some(goal) => Some(self.network_goal(ctx, at, goal)?),
                    None => None,
                };
                let with = goal
                    .as_deref()
                    .map_or_else(String::new, |g| format!(" with {g}"));
                (
                    K::NeverXGoalActive {
                        sv: component,
                        goal: checked,
                        window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                    },
                    format!("no XGoal{with} active on {sv}{}", during(*from, *to)),
                )
            }
            F::Always { that, from, to } => {
                let mut slots = 0;
                let condition = self.condition(ctx, &field(at, "that"), that, &mut slots)?;
                (
                    K::Always {
                        condition,
                        window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                    },
                    format!("always {}{}", describe(that), during(*from, *to)),
                )
            }
            F::Fired { point, after, by } => (
                K::Fired {
                    point: self.point(ctx, at, point)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("time point {point} fired{}", eventual(*after, *by)),
            ),
            F::NeverFired { point, from, to } => (
                K::NeverFired {
                    point: self.point(ctx, at, point)?,
                    window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                },
                format!("time point {point} never fired{}", during(*from, *to)),
            ),
            F::Failed { goal, after, by } => (
                K::Failed {
                    goal: self.network_goal(ctx, at, goal)?,
                    window: self.window(ctx, at, ("after", *after), ("by", *by))?,
                },
                format!("mission goal {goal} failed{}", eventual(*after, *by)),
            ),
            F::NeverFailed { goal, from, to } => {
                self.names(ctx, at)?;
                let checked = match goal {
                    Some(goal) => Some(self.network_goal(ctx, at, goal)?),
                    None => None,
                };
                let what = goal.as_deref().map_or_else(
                    || "no mission goal failed".to_string(),
                    |g| format!("mission goal {g} never failed"),
                );
                (
                    K::NeverFailed {
                        goal: checked,
                        window: self.window(ctx, at, ("from", *from), ("to", *to))?,
                    },
                    format!("{what}{}", during(*from, *to)),
                )
            }
            F::XGoalActive { sv, goal, time } => {
                self.names(ctx, at)?;
                let component = self.component(ctx, at, sv)?;
                let checked = match goal {
                    Some(goal) => Some(self.network_goal(ctx, at, goal)?),
                    None => None,
                };
                let with = goal
                    .as_deref()
                    .map_or_else(String::new, |g| format!(" with {g}"));
                (
                    K::XGoalActive {
                        sv: component,
                        goal: checked,
                        time: self.time(ctx, at, "time", *time)?,
                    },
                    format!("an XGoal{with} active on {sv} at {time} s"),
                )
            }
        };
        Some(Expectation { label, kind })
    }

    /// `AnyOf([...])`'s members: eventual expectations that cannot fail before the end
    /// (`Estimated`, `Commanded`, `Diagnosed`, `Achieved`, `GoalFailed`, `Completed`,
    /// `Reported`), and their labels.
    fn members(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        files: &[ExpectFile],
    ) -> Option<(Vec<ExpectationKind>, Vec<String>)> {
        let (mut members, mut labels) = (Vec::new(), Vec::new());
        let before = ctx.errors.len();
        for (k, file) in files.iter().enumerate() {
            let mut path = at.to_vec();
            path.extend([Step::Index(0), Step::Index(k)]);
            let Some(member) = self.expectation(ctx, &path, file) else {
                continue;
            };
            let eventual = member.kind.is_eventual()
                && !matches!(
                    member.kind,
                    ExpectationKind::EstimatedAt { .. }
                        | ExpectationKind::CommandsInOrder { .. }
                        | ExpectationKind::AnyOf { .. }
                );
            if !eventual {
                ctx.error(
                    &path,
                    format!("`{}` cannot be one of `AnyOf`", member.label),
                    "an expectation that some cycle shows: Estimated, Commanded, Diagnosed, Achieved, GoalFailed, Completed or Reported",
                );
                continue;
            }
            members.push(member.kind);
            labels.push(member.label);
        }
        if files.is_empty() {
            ctx.error(
                at,
                "`AnyOf` of nothing never holds",
                "at least one expectation in the list",
            );
        }
        (ctx.errors.len() == before).then_some((members, labels))
    }

    fn formula(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        name: &str,
        text: &str,
        vars: Vars,
    ) -> Option<Formula> {
        formula(
            ctx,
            &field(at, name),
            text,
            &self.script.world,
            vars,
            &self.classes,
        )
    }

    fn time(&self, ctx: &mut FileCtx, at: &[Step<'_>], name: &str, time: f64) -> Option<f64> {
        if !(time.is_finite() && time >= 0.0) {
            ctx.error(
                &field(at, name),
                format!("{time} is not a time"),
                "seconds, 0 or more",
            );
            return None;
        }
        if time > self.end {
            ctx.error(
                &field(at, name),
                format!("{time} s is after the run ends at {} s", self.end),
                "a time within the run",
            );
            return None;
        }
        Some(time)
    }

    fn window(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        (from_name, from): (&str, Option<f64>),
        (to_name, to): (&str, Option<f64>),
    ) -> Option<Window> {
        let from = match from {
            Some(t) => self.time(ctx, at, from_name, t)?,
            None => f64::NEG_INFINITY,
        };
        let to = match to {
            Some(t) => self.time(ctx, at, to_name, t)?,
            None => f64::INFINITY,
        };
        if from > to {
            ctx.error(
                &field(at, to_name),
                format!("`{to_name}` ({to} s) is before `{from_name}` ({from} s)"),
                "a window whose end is not before its start",
            );
            return None;
        }
        Some(Window { from, to })
    }

    /// `component = fault-mode`.
    fn fault(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        text: &str,
    ) -> Option<(ComponentId, ValueId)> {
        let formula = self.formula(ctx, at, "fault", text, Vars::Modes)?;
        let assignment = formula
            .as_assignments()
            .filter(|a| a.len() == 1)
            .and_then(|a| a.first().copied());
        let span = ctx.span(&field(at, "fault"));
        let Some((var, value)) = assignment else {
            ctx.push(
                Diagnostic::new(format!("`{text}` is not one component's mode"), span)
                    .expected("`component = fault-mode`, such as `PDE = resettable`"),
            );
            return None;
        };
        let component = self.plant.component_of(var)?;
        let mode = self.plant.component(component).mode(value);
        if mode.kind != ModeKind::Fault {
            let faults: Vec<&str> = self
                .plant
                .component(component)
                .modes()
                .iter()
                .filter(|m| m.kind == ModeKind::Fault)
                .map(|m| m.name.as_str())
                .collect();
            ctx.push(
                Diagnostic::new(format!("`{}` is a nominal mode", mode.name), span)
                    .expected(format!(
                        "a fault mode of `{}`",
                        self.plant.component(component).name()
                    ))
                    .note(format!("its fault modes: {}", faults.join(", "))),
            );
            return None;
        }
        Some((component, value))
    }

    /// `within` and `of` go together; `of` names a rule.
    fn tolerance(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        within: Option<DelayFile>,
        of: Option<&str>,
    ) -> Option<Option<(Delay, usize)>> {
        match (within, of) {
            (None, None) => Some(None),
            (Some(_), None) => {
                ctx.error(
                    &field(at, "within"),
                    "`within` needs `of`, the rule that injects the fault",
                    "`of: \"rule name\"` next to `within`",
                );
                None
            }
            (None, Some(_)) => {
                ctx.error(
                    &field(at, "of"),
                    "`of` needs `within`, how soon after the rule fires",
                    "`within: Cycles(n)` or `within: Seconds(s)` next to `of`",
                );
                None
            }
            (Some(within), Some(rule)) => {
                let Some(index) = self.script.rule_named(rule) else {
                    if self.declared.iter().any(|name| name == rule) {
                        return None; // the rule's own error is reported
                    }
                    let names: Vec<&str> = self.declared.iter().map(String::as_str).collect();
                    let mut diagnostic = Diagnostic::new(
                        format!("no rule named `{rule}`"),
                        ctx.span(&field(at, "of")),
                    )
                    .expected("the name of a rule of the scenario or its includes")
                    .note(format!("rules: {}", names.join(", ")));
                    if let Some(close) = did_you_mean(rule, names.iter().copied()) {
                        diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
                    }
                    ctx.push(diagnostic);
                    return None;
                };
                let delay = match within {
                    DelayFile::Cycles(n) if n >= 0 => Delay::Cycles(n.unsigned_abs()),
                    DelayFile::Seconds(s) if s.is_finite() && s >= 0.0 => Delay::Seconds(s),
                    _ => {
                        ctx.error(
                            &field(at, "within"),
                            "not a tolerance",
                            "0 or more cycles or seconds",
                        );
                        return None;
                    }
                };
                Some(Some((delay, index)))
            }
        }
    }

    /// `saying`: a non-empty part of an event's text.
    fn saying(
        &self,
        ctx: &mut FileCtx,
        at: &[Step<'_>],
        saying: Option<&str>,
    ) -> Option<Option<String>> {
        match saying {
            Some("") => {
                ctx.error(
                    &field(at, "saying"),
                    "an empty `saying` says nothing",
                    "a part of the event's text as the log prints it",
                );
                None
            }
            other => Some(other.map(str::to_string)),
        }
    }

    /// A condition of `Always` at `path`; each `Once` takes the next of `slots`.
    fn condition(
        &self,
        ctx: &mut FileCtx,
        path: &[Step<'_>],
        file: &ConditionFile,
        slots: &mut usize,
    ) -> Option<Condition> {
        use ConditionFile as C;
        let inner = |k: usize| [path, &[Step::Index(k)]].concat();
        let formula = |ctx: &mut FileCtx, text: &str, vars| {
            formula(
                ctx,
                &inner(0),
                text,
                &self.script.world,
                vars,
                &self.classes,
            )
        };
        let condition = match file {
            C::Plant(text) => Condition::Plant(formula(ctx, text, Vars::Held)?),
            C::Estimated(text) => Condition::Estimated(formula(ctx, text, Vars::Modes)?),
            C::Reported(event) => Condition::Reported(*event),
            C::Active(goal) => {
                let names = self.names(ctx, path)?;
                let submitted = (self.submissions()).flat_map(|s| s.goals.iter().map(|g| &g.name));
                if !(names.has_goal(goal) || submitted.clone().any(|g| g == goal)) {
                    let all = names.goals.iter().chain(submitted).map(String::as_str);
                    self.known(ctx, &inner(0), goal, all, "goal")?;
                }
                Condition::Active(goal.clone())
            }
            C::Not(c) => Condition::Not(Box::new(self.condition(ctx, &inner(0), c, slots)?)),
            C::All(cs) | C::Any(cs) => {
                let before = ctx.errors.len();
                let members: Vec<Condition> = (cs.iter().enumerate())
                    .filter_map(|(k, c)| {
                        let at = [path, &[Step::Index(0), Step::Index(k)]].concat();
                        self.condition(ctx, &at, c, slots)
                    })
                    .collect();
                if ctx.errors.len() != before {
                    return None;
                }
                match file {
                    C::All(_) => Condition::All(members),
                    _ => Condition::Any(members),
                }
            }
            C::Implies(a, b) => {
                let a = self.condition(ctx, &inner(0), a, slots);
                let b = self.condition(ctx, &inner(1), b, slots);
                Condition::Implies(Box::new(a?), Box::new(b?))
            }
            C::Once(c) => {
                let condition = Box::new(self.condition(ctx, &inner(0), c, slots)?);
                *slots += 1;
                Condition::Once {
                    condition,
                    slot: *slots - 1,
                }
            }
        };
        Some(condition)
    }

    /// A goal the program asserts, displayed as the executive reports it.
    fn goal(&self, ctx: &mut FileCtx, at: &[Step<'_>], text: &str) -> Option<String> {
        let formula = self.formula(ctx, at, "goal", text, Vars::Plant)?;
        let displayed = formula.display(self.plant.table()).to_string();
        if self.goals.contains(&displayed) {
            return Some(displayed);
        }
        ctx.push(
            Diagnostic::new(
                format!("the program asserts no goal `{displayed}`"),
                ctx.span(&field(at, "goal")),
            )
            .expected("a goal written in the program")
            .note(format!("its goals: {}", self.goals.join("; "))),
        );
        None
    }
}

/// The mission's names, for `Fired`, `NeverFired`, `Failed`, `NeverFailed`, `XGoalActive`.
impl ExpectLoader<'_> {
    /// The mission's names; an error at the expectation when the scenario runs RMPL.
    fn names(&self, ctx: &mut FileCtx, at: &[Step<'_>]) -> Option<&MissionNames> {
        if self.names.is_none() {
            ctx.error(
                at,
                "this expectation is about a goal network, and the scenario runs an RMPL program",
                "a scenario with `mission: \"...\"` for time points, goals and XGoals",
            );
        }
        self.names.as_ref()
    }

    /// A time point of the mission (or one its elaborations or safing can add, or a rule's
    /// submission), by name.
    fn point(&self, ctx: &mut FileCtx, at: &[Step<'_>], name: &str) -> Option<String> {
        let names = self.names(ctx, at)?;
        let submitted = self.submissions().flat_map(|s| s.points.iter());
        if names.has_point(name) || submitted.clone().any(|p| p == name) {
            return Some(name.to_string());
        }
        let all = names.points.iter().chain(submitted).map(String::as_str);
        self.known(ctx, &field(at, "point"), name, all, "time point")
    }

    /// A goal of the mission (or one its elaborations or safing can add, or a rule's
    /// submission), by name.
    fn network_goal(&self, ctx: &mut FileCtx, at: &[Step<'_>], name: &str) -> Option<String> {
        let names = self.names(ctx, at)?;
        let submitted = self
            .submissions()
            .flat_map(|s| s.goals.iter().map(|g| &g.name));
        if names.has_goal(name) || submitted.clone().any(|g| g == name) {
            return Some(name.to_string());
        }
        let all = names.goals.iter().chain(submitted).map(String::as_str);
        self.known(ctx, &field(at, "goal"), name, all, "goal")
    }

    /// What the script's rules submit.
    fn submissions(&self) -> impl Iterator<Item = &Submission> + Clone {
        self.script
            .rules()
            .iter()
            .filter_map(|r| r.effect.submit.as_ref())
    }

    /// A component (a state variable), by name.
    fn component(&self, ctx: &mut FileCtx, at: &[Step<'_>], name: &str) -> Option<ComponentId> {
        let names = self.plant.components().iter().map(|c| c.name());
        self.known(ctx, &field(at, "sv"), name, names, "state variable")?;
        self.plant.component_named(name)
    }

    /// `name` when it is among `names`; otherwise a located error listing them.
    fn known<'n>(
        &self,
        ctx: &mut FileCtx,
        path: &[Step],
        name: &str,
        names: impl Iterator<Item = &'n str> + Clone,
        what: &str,
    ) -> Option<String> {
        if names.clone().any(|n| n == name) {
            return Some(name.to_string());
        }
        let listed: Vec<&str> = names.collect();
        let mut diagnostic = Diagnostic::new(format!("no {what} named `{name}`"), ctx.span(path))
            .expected(format!("the name of a {what} of the mission"))
            .note(format!("{what}s: {}", listed.join(", ")));
        if let Some(close) = did_you_mean(name, listed.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        ctx.push(diagnostic);
        None
    }
}

fn eventual(after: Option<f64>, by: Option<f64>) -> String {
    match (after, by) {
        (None, None) => String::new(),
        (Some(a), None) => format!(" after {a} s"),
        (None, Some(b)) => format!(" by {b} s"),
        (Some(a), Some(b)) if a == b => format!(" at {a} s"),
        (Some(a), Some(b)) => format!(" between {a} s and {b} s"),
    }
}

fn during(from: Option<f64>, to: Option<f64>) -> String {
    match (from, to) {
        (None, None) => String::new(),
        (Some(a), None) => format!(" from {a} s"),
        (None, Some(b)) => format!(" until {b} s"),
        (Some(a), Some(b)) => format!(" from {a} s to {b} s"),
    }
}

/// ` saying "…"`, or nothing.
fn quoted(saying: Option<&str>) -> String {
    saying.map_or_else(String::new, |s| format!(" saying \"{s}\""))
}

/// A condition in words, for the label of `Always`: `(if stay-warm active then the plant has
/// temp != cold)`.
fn describe(condition: &ConditionFile) -> String {
    use ConditionFile as C;
    let list = |cs: &[ConditionFile], joint: &str| {
        let parts: Vec<String> = cs.iter().map(describe).collect();
        format!("({})", parts.join(joint))
    };
    let squeezed = |text: &str| text.split_whitespace().collect::<Vec<_>>().join(" ");
    match condition {
        C::Plant(text) => format!("the plant has {}", squeezed(text)),
        C::Estimated(text) => format!("ŝ has {}", squeezed(text)),
        C::Reported(event) => format!("{event:?} reported"),
        C::Active(goal) => format!("{goal} active"),
        C::Not(c) => format!("not {}", describe(c)),
        C::All(cs) => list(cs, " and "),
        C::Any(cs) => list(cs, " or "),
        C::Implies(a, b) => format!("(if {} then {})", describe(a), describe(b)),
        C::Once(c) => format!("once {}", describe(c)),
    }
}

fn show(delay: Delay) -> String {
    match delay {
        Delay::Cycles(1) => "1 cycle".to_string(),
        Delay::Cycles(n) => format!("{n} cycles"),
        Delay::Seconds(s) => format!("{s} s"),
    }
}
