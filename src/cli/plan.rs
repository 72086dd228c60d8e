//! `kairos plan --plant MODEL [--state "engine = off, ..."] --goal "engine = firing" [--json]`:
//! goal interpretation from the state, then the command sequence the reactive planner produces
//! when every command succeeds nominally. `kairos plan --policies MODEL`: the causal
//! graph and every component's concurrent policy, for review like Table 6.2.
//!
//! `--state` lists `component = mode` (commas or `and` between them); components it leaves out
//! are in their most likely initial mode. `--goal` is any formula of the constraint language
//! (commas read as `and`). Errors in either are located in the argument's text.

use std::path::{Path, PathBuf};

use kairos::diagnostic::{Diagnostic, Source, SourceErrors};
use kairos::logic::{Atom, Formula, ValueId, resolve, syntax};
use kairos::plant::Plant;
use kairos::reconfiguration::{Action, GoalState, NominalRun, PlanOutcome, Reconfiguration};
use serde_json::{Map, Value, json};

use super::Failure;
use super::load_plant;

/// The arguments of `kairos plan`.
#[derive(clap::Args)]
pub struct PlanArgs {
    /// The plant model (RON).
    #[arg(long, value_name = "MODEL", required_unless_present = "policies")]
    pub plant: Option<PathBuf>,
    /// The current state: `component = mode`, separated by commas; components left out are in
    /// their most likely initial mode.
    #[arg(long, requires = "plant")]
    pub state: Option<String>,
    /// The configuration goal, a formula over the plant's variables (commas read as `and`).
    #[arg(long, required_unless_present = "policies", requires = "plant")]
    pub goal: Option<String>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Print the causal graph and every component's concurrent policy instead of planning.
    #[arg(long, value_name = "MODEL", conflicts_with_all = ["plant", "state", "goal", "json"])]
    pub policies: Option<PathBuf>,
    /// Give up after this many cycles.
    #[arg(long, default_value_t = 100)]
    pub max_steps: usize,
}

/// Runs `kairos plan`.
pub fn run(args: &PlanArgs) -> Result<(), Failure> {
    if let Some(model) = &args.policies {
        let (_, reconfiguration) = compile(model)?;
        print!("{}", reconfiguration.describe_policies());
        return Ok(());
    }
    let (Some(model), Some(goal_text)) = (&args.plant, &args.goal) else {
        return Err(Failure::bad_input(
            "error: give --plant and --goal, or --policies",
        ));
    };
    let (plant, reconfiguration) = compile(model)?;
    let state = parse_state(&plant, args.state.as_deref())?;
    let goal = parse_goal(&plant, goal_text)?;
    let mut theory = plant
        .theory()
        .map_err(|e| Failure::bad_input(format!("error: {e}")))?;
    let goal_state = match reconfiguration.interpret(&mut theory, &state, &goal) {
        Ok(goal_state) => goal_state,
        Err(failed) => {
            let report = Report::new(&plant, &state, goal_text);
            report.goal_failed(&failed.reason, args.json);
            return Err(Failure::failed(format!("goal failed: {}", failed.reason)));
        }
    };
    let run = reconfiguration
        .simulate_nominal(&mut theory, &state, &goal_state, args.max_steps)
        .map_err(|e| Failure::bad_input(format!("error: {e}")))?;
    let report = Report::new(&plant, &state, goal_text);
    report.plan(&goal_state, &run, args.json);
    match &run.outcome {
        PlanOutcome::Achieved => Ok(()),
        other => Err(Failure::failed(format!(
            "the plan did not reach the goal state: {}",
            outcome_text(&plant, other)
        ))),
    }
}

/// Above this many (mode, target) pairs in all policies `kairos plan` says so before compiling.
const LARGE_POLICY_ENTRIES: usize = 1_000_000;

fn compile(model: &Path) -> Result<(Plant, Reconfiguration), Failure> {
    let plant = load_plant(model)?;
    // A policy has an entry per (mode, target) pair of a component: 5,000 modes took 900 MB.
    let policy_entries: usize = plant
        .components()
        .iter()
        .map(|c| c.modes().len().pow(2))
        .sum();
    super::announce_large_plant(
        model,
        &plant,
        &format!(
            "policy compilation ({policy_entries} (mode, target) pairs, a SAT question over the \
             plant per transition)"
        ),
        policy_entries > LARGE_POLICY_ENTRIES,
    );
    let reconfiguration = Reconfiguration::compile(&plant)
        .map_err(|e| Failure::bad_input(format!("error: {}: {e}", model.display())))?;
    Ok((plant, reconfiguration))
}

/// Commas are conjunctions in `--state` and `--goal`; `&` has the same length, so every span
/// still points into the text as given.
fn commas_as_and(text: &str) -> String {
    text.replace(',', "&")
}

fn located(name: &str, text: &str, diagnostics: Vec<Diagnostic>) -> Failure {
    Failure::bad_input(SourceErrors::new(Source::new(name, text), diagnostics))
}

/// The goal formula, resolved against the plant.
fn parse_goal(plant: &Plant, text: &str) -> Result<Formula, Failure> {
    let expr = syntax::parse(&commas_as_and(text)).map_err(|d| located("--goal", text, vec![d]))?;
    let goal = resolve(&expr, plant.table()).map_err(|ds| located("--goal", text, ds))?;
    if goal.has_external_atoms() {
        let diagnostic =
            Diagnostic::new("a goal to plan for has no clocks or confidences", expr.span)
                .expected("a formula over the plant's modes and attributes");
        return Err(located("--goal", text, vec![diagnostic]));
    }
    Ok(goal)
}

/// The state: each component's mode, from `component = mode` items or the initial mode.
fn parse_state(plant: &Plant, text: Option<&str>) -> Result<Vec<ValueId>, Failure> {
    let mut modes: Vec<Option<ValueId>> = vec![None; plant.components().len()];
    if let Some(text) = text {
        let expr =
            syntax::parse(&commas_as_and(text)).map_err(|d| located("--state", text, vec![d]))?;
        let items = match expr.kind {
            syntax::ExprKind::And(parts) => parts,
            _ => vec![expr],
        };
        let mut errors = Vec::new();
        for item in &items {
            let expected = "`component = mode`";
            match resolve(item, plant.table()) {
                Err(ds) => errors.extend(ds),
                Ok(Formula::Atom(Atom::Is(x, v))) => match plant.component_of(x) {
                    Some(c) if modes[c.index()].is_some() => errors.push(
                        Diagnostic::new(
                            format!("`{}` is given a second mode", plant.component(c).name()),
                            item.span.clone(),
                        )
                        .expected("one mode per component"),
                    ),
                    Some(c) => modes[c.index()] = Some(v),
                    None => errors.push(
                        Diagnostic::new(
                            format!(
                                "`{}` is an attribute: a state gives components' modes",
                                plant.table().variable(x).name()
                            ),
                            item.span.clone(),
                        )
                        .expected(expected),
                    ),
                },
                Ok(_) => errors.push(
                    Diagnostic::new("a state lists components' modes", item.span.clone())
                        .expected(expected),
                ),
            }
        }
        if !errors.is_empty() {
            return Err(located("--state", text, errors));
        }
    }
    Ok(plant
        .components()
        .iter()
        .zip(modes)
        .map(|(component, mode)| mode.unwrap_or_else(|| most_likely_initial(component.initial())))
        .collect())
}

fn most_likely_initial(initial: &[f64]) -> ValueId {
    let best = initial
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1).then(b.0.cmp(&a.0)))
        .map_or(0, |(i, _)| i);
    ValueId(best as u32)
}

fn outcome_text(plant: &Plant, outcome: &PlanOutcome) -> String {
    match outcome {
        PlanOutcome::Oscillating { components } => {
            let names: Vec<&str> = components
                .iter()
                .map(|&c| plant.component(c).name())
                .collect();
            format!(
                "the plan goes round: {} come back to a state already visited",
                names.join(", ")
            )
        }
        PlanOutcome::Achieved => "goal state reached".to_string(),
        PlanOutcome::Failed(failure) => format!("no action: {}", failure.reason),
        PlanOutcome::Stalled { reason } => format!("stalled: {reason}"),
        PlanOutcome::StepLimit => "step limit reached".to_string(),
    }
}

/// "warning: the plant leaves this goal state by itself: ..." for each transition that leaves
/// it with every control idle (DESIGN.md §9), located in the model by component and
/// transition.
fn leaving_lines(plant: &Plant, goal_state: &GoalState) -> Vec<String> {
    goal_state
        .leaving()
        .iter()
        .map(|&(c, t)| {
            let component = plant.component(c);
            let transition = &component.transitions()[t];
            format!(
                "warning: no state entailing the goal is one the plant rests in; this one it \
                 leaves by itself: component `{}`, transition {} -> {} (guard `{}`, {})",
                component.name(),
                component.mode(goal_state.mode(c)).name,
                component.mode(transition.target).name,
                transition.guard.display(plant.table()),
                transition.law
            )
        })
        .collect()
}

/// Prints what `kairos plan` found, as text or JSON.
struct Report<'a> {
    plant: &'a Plant,
    state: &'a [ValueId],
    goal: &'a str,
}

impl<'a> Report<'a> {
    fn new(plant: &'a Plant, state: &'a [ValueId], goal: &'a str) -> Self {
        Report { plant, state, goal }
    }

    fn modes_json(&self, modes: &[ValueId]) -> Value {
        let map: Map<String, Value> = self
            .plant
            .components()
            .iter()
            .zip(modes)
            .map(|(c, &m)| (c.name().to_string(), json!(c.mode(m).name)))
            .collect();
        Value::Object(map)
    }

    fn describe(&self, modes: &[ValueId]) -> String {
        kairos::plant::describe_modes(self.plant, modes)
    }

    fn goal_failed(&self, reason: &str, as_json: bool) {
        if as_json {
            let out = json!({
                "plant": self.plant.name(),
                "state": self.modes_json(self.state),
                "goal": self.goal,
                "goal_failed": reason,
            });
            println!("{}", serde_json::to_string_pretty(&out).unwrap_or_default());
        } else {
            // The reason itself goes to standard error, with the exit code.
            println!("state:       {}", self.describe(self.state));
            println!("goal:        {}", self.goal);
        }
    }

    fn plan(&self, goal_state: &GoalState, run: &NominalRun, as_json: bool) {
        if as_json {
            self.plan_json(goal_state, run);
            return;
        }
        println!("state:       {}", self.describe(self.state));
        println!("goal:        {}", self.goal);
        println!(
            "goal state:  {} (reward {})",
            goal_state.describe(self.plant),
            goal_state.reward()
        );
        for line in leaving_lines(self.plant, goal_state) {
            println!("{line}");
        }
        println!("plan, one action per cycle, every command succeeding nominally:");
        let width = run
            .steps
            .iter()
            .map(|s| s.action.summary(self.plant).len())
            .max()
            .unwrap_or(0);
        for (i, step) in run.steps.iter().enumerate() {
            println!(
                "  {:>2}. {:<width$}  {}",
                i + 1,
                step.action.summary(self.plant),
                self.moves_text(step)
            );
        }
        println!(
            "{} after {} cycles",
            outcome_text(self.plant, &run.outcome),
            run.steps.len()
        );
    }

    fn moves_text(&self, step: &kairos::reconfiguration::PlanStep) -> String {
        step.moves
            .iter()
            .map(|m| {
                let component = self.plant.component(m.component);
                format!(
                    "{}: {} -> {}",
                    component.name(),
                    component.mode(m.from).name,
                    component.mode(m.to).name
                )
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    fn plan_json(&self, goal_state: &GoalState, run: &NominalRun) {
        let table = self.plant.table();
        let name = |c: kairos::plant::ComponentId| self.plant.component(c).name();
        let mode =
            |c: kairos::plant::ComponentId, m: ValueId| &self.plant.component(c).mode(m).name;
        let steps: Vec<Value> = run
            .steps
            .iter()
            .enumerate()
            .map(|(i, step)| {
                let mut entry = json!({ "cycle": i + 1 });
                match &step.action {
                    Action::Command(command) => {
                        let controls: Map<String, Value> = command
                            .assignments
                            .iter()
                            .map(|&(x, v)| {
                                let variable = table.variable(x);
                                (variable.name().to_string(), json!(variable.value_name(v)))
                            })
                            .collect();
                        entry["action"] = json!("command");
                        entry["controls"] = Value::Object(controls);
                        entry["repair"] = json!(command.repair);
                    }
                    Action::Idle(wait) => {
                        entry["action"] = json!("wait");
                        entry["law"] = json!(wait.law.to_string());
                    }
                    Action::Achieved | Action::Failure(_) => {}
                }
                if let Some((c, from, to)) = step.action.intended() {
                    entry["for"] = json!({"component": name(c), "from": mode(c, from), "to": mode(c, to)});
                }
                entry["moves"] = step
                    .moves
                    .iter()
                    .map(|m| json!({"component": name(m.component), "from": mode(m.component, m.from), "to": mode(m.component, m.to)}))
                    .collect();
                entry
            })
            .collect();
        let out = json!({
            "plant": self.plant.name(),
            "state": self.modes_json(self.state),
            "goal": self.goal,
            "goal_state": {
                "modes": self.modes_json(goal_state.modes()),
                "reward": goal_state.reward(),
            },
            "steps": steps,
            "outcome": outcome_text(self.plant, &run.outcome),
            "achieved": run.outcome == PlanOutcome::Achieved,
        });
        println!("{}", serde_json::to_string_pretty(&out).unwrap_or_default());
    }
}
