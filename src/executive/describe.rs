//! The wording of the executive's events (DESIGN.md §10): one [`EventKind`] as a (tag, text)
//! pair — `("REPAIR", "PDE.cmd = reset (PDE: resettable -> on) for engine = standby
//! (programs/mars_edl.rmpl:20:3)")`. The mission log prints it, the trace stores its text next
//! to the event's kind, and `Display` prints it without names.
//!
//! The wording lives beside the events, not in the log that prints them, so that every surface
//! that shows an event — the mission log, the trace, an embedder's own log — words it the same
//! way without importing the report layer.

use std::fmt::{self, Write};

use crate::diagnostic::{Source, Span};
use crate::estimation::Fallback;
use crate::plant::{ComponentId, Plant};

use super::{Event, EventKind, Executive, Served};

/// One event as a (tag, text) pair: `("command", "PDE.cmd = on: PDE: off -> on")`. The log
/// prints it; the trace stores the text next to the event's kind.
pub fn describe_event(
    plant: &Plant,
    program: &Source,
    event: &EventKind,
) -> (&'static str, String) {
    describe(
        &Sources {
            plant,
            program: Some(program),
        },
        event,
    )
}

/// What the wording of an event needs from outside it: names for its component ids and places
/// for its source spans. The log has the plant and the program ([`describe_event`]); an event
/// printed on its own (`Display`) has neither and writes the ids and byte ranges.
trait Names {
    /// The component's name.
    fn component(&self, component: ComponentId) -> String;
    /// Where a span is written: `file:line:col`.
    fn at(&self, span: &Span) -> String;
    /// The text a span covers, when the program is known.
    fn text(&self, span: &Span) -> Option<String>;
}

/// The names of a run: the plant's, and the program's or mission's text when it is known (an
/// executive built from a linked program without its text writes byte ranges for places).
struct Sources<'a> {
    plant: &'a Plant,
    program: Option<&'a Source>,
}

impl Names for Sources<'_> {
    fn component(&self, component: ComponentId) -> String {
        self.plant.component(component).name().to_string()
    }

    fn at(&self, span: &Span) -> String {
        match self.program {
            Some(program) => {
                let (line, col) = program.line_col(span.start);
                format!("{}:{line}:{col}", program.name)
            }
            None => Bare.at(span),
        }
    }

    fn text(&self, span: &Span) -> Option<String> {
        let text = self.program?.text.get(span.clone())?;
        Some(text.trim().to_string())
    }
}

/// An event worded with the names of its executive's plant and program, as the mission log
/// words it: `[12.000 s] #12 REPAIR PDE.cmd = reset (PDE: resettable -> on) for engine =
/// standby (programs/mars_edl.rmpl:20:3)`. Made by [`Event::named`].
pub struct NamedEvent<'a> {
    event: &'a Event,
    names: Sources<'a>,
}

impl fmt::Display for NamedEvent<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (tag, text) = describe(&self.names, &self.event.kind);
        write!(
            f,
            "[{:.3} s] #{} {tag} {text}",
            self.event.time, self.event.cycle
        )
    }
}

impl Event {
    /// This event worded with `executive`'s names: components by name, and source places as
    /// `file:line:col` when the executive has its program's text ([`Executive::load`],
    /// [`Executive::load_mission`] or [`ExecutiveBuilder::source`](super::ExecutiveBuilder::source)
    /// keep it); byte ranges otherwise.
    pub fn named<'a>(&'a self, executive: &'a Executive) -> NamedEvent<'a> {
        NamedEvent {
            event: self,
            names: Sources {
                plant: executive.plant(),
                program: executive.source(),
            },
        }
    }
}

/// ` for engine = standby (programs/mars_edl.rmpl:20:3)`: the goals a command serves, joined
/// by ` and ` (nothing when it serves none).
fn served(names: &dyn Names, serves: &[Served]) -> String {
    let goals: Vec<String> = serves
        .iter()
        .map(|served| match served {
            Served::Program { goal, span } => format!("{goal} ({})", names.at(span)),
            Served::Mission { goal } => format!("goal {goal}"),
            Served::Intended { goal } => goal.clone(),
        })
        .collect();
    if goals.is_empty() {
        String::new()
    } else {
        format!(" for {}", goals.join(" and "))
    }
}

/// No names: `component 3`, `bytes 120..135` (an event printed without its plant and program).
struct Bare;

impl Names for Bare {
    fn component(&self, component: ComponentId) -> String {
        format!("component {}", component.0)
    }

    fn at(&self, span: &Span) -> String {
        format!("bytes {}..{}", span.start, span.end)
    }

    fn text(&self, _: &Span) -> Option<String> {
        None
    }
}

/// One event as a (tag, text) pair without its plant and program: component ids and byte
/// ranges stand for names and lines. `Event`'s `Display` prints this.
pub(crate) fn describe_bare(event: &EventKind) -> (&'static str, String) {
    describe(&Bare, event)
}

fn describe(names: &dyn Names, event: &EventKind) -> (&'static str, String) {
    use EventKind as E;
    let at = |span: &Span| names.at(span);
    let component = |c: ComponentId| names.component(c);
    match event {
        E::GoalAsserted {
            goal, span, again, ..
        } => {
            let verb = if *again { "re-asserted" } else { "asserted" };
            ("goal", format!("{verb} {goal}  ({})", at(span)))
        }
        E::GoalAchieved { location, span } => (
            "goal",
            format!(
                "achieved {}  ({})",
                names
                    .text(span)
                    .unwrap_or_else(|| format!("the goal of location {location}")),
                at(span)
            ),
        ),
        E::GoalFailed { goal, reason } => ("GOAL FAILED", format!("{goal}: {reason}")),
        // The goal the retried command serves, as every command names its goal (DESIGN.md §9).
        E::Retrying {
            goal,
            assignments,
            hypothesis,
            probability,
            attempt,
            budget,
        } => (
            "RETRY",
            format!(
                "{} for {goal}: the goal is reachable if {hypothesis} (p {probability:.2}); retry \
                 {attempt} of {budget}",
                assignments.join(", ")
            ),
        ),
        E::GoalConflict { first, second } => (
            "CONFLICT",
            format!(
                "goals at {} and {} contradict",
                at(&first.span),
                at(&second.span)
            ),
        ),
        // `do … watching (file:28:3): (SSR_A = on) ∨ (SSR_B = on) became entailed`: the
        // construct, then the condition as the program writes it.
        E::Preempted {
            span,
            construct,
            condition,
            condition_span,
            entailed,
            ..
        } => {
            let condition = names
                .text(condition_span)
                .unwrap_or_else(|| condition.clone());
            let change = if *entailed {
                "became entailed"
            } else {
                "is not entailed"
            };
            (
                "preempted",
                format!("{construct} ({}): {condition} {change}", at(span)),
            )
        }
        E::ClockStarted { clock, span } => ("clock", format!("{clock} started  ({})", at(span))),
        E::ModeChanged {
            component: c,
            from,
            to,
            probability,
        } => (
            "believed",
            format!("{}: {from} -> {to} (p {probability:.2})", component(*c)),
        ),
        E::Diagnosis {
            component: c,
            mode,
            probability,
            next,
            evidence,
        } => {
            let name = component(*c);
            let mut text = format!("{name} = {mode} (p {probability:.2})");
            if !evidence.is_empty() {
                let _ = write!(text, "; evidence: {}", evidence.join(", "));
            }
            for (k, (other, p)) in next.iter().enumerate() {
                let lead = if k == 0 { "; next: " } else { ", " };
                let _ = write!(text, "{lead}{name} = {other} (p {p:.2})");
            }
            ("DIAGNOSIS", text)
        }
        E::CommandIssued {
            assignments,
            purpose,
            repair,
            serves,
        } => {
            // The planner's purpose already names the command (`command PDE.cmd = on (PDE: off
            // -> on)`); the assignments are shown only when it does not.
            let what = purpose.strip_prefix("command ").map_or_else(
                || format!("{}: {purpose}", assignments.join(", ")),
                str::to_string,
            );
            // The tag says it is a repair; the planner's " (repair)" would say it twice.
            let what = if *repair {
                what.replacen(" (repair)", "", 1)
            } else {
                what
            };
            let tag = if *repair { "REPAIR" } else { "command" };
            (tag, format!("{what}{}", served(names, serves)))
        }
        // `waiting  after Uniform(30, 60) s (engine: heating -> standby)`, not "waiting wait".
        E::Waiting { purpose } => (
            "waiting",
            purpose
                .strip_prefix("wait, ")
                .unwrap_or(purpose)
                .to_string(),
        ),
        E::PlanFailed { reason } => ("NO PLAN", reason.clone()),
        E::EstimatorInconsistency { fallback } => (
            "INCONSISTENT",
            format!(
                "no tracked state explains the observation; {}",
                match fallback {
                    Fallback::Reestimated { steps } => format!(
                        "the last {steps} steps estimated again, tracking more states, explain it"
                    ),
                    Fallback::UnconstrainedFaults =>
                        "components may jump into unconstrained faults".to_string(),
                    Fallback::PreviousBelief =>
                        "the previous belief is kept, the observation set aside".to_string(),
                }
            ),
        ),
        E::SearchCut(cut) => (
            "search cut",
            format!("estimation stopped by its {cut:?} budget"),
        ),
        E::ObservationRejected {
            variable,
            value,
            reason,
        } => ("rejected", format!("{variable} = \"{value}\": {reason}")),
        E::Monitored {
            variable,
            reading,
            unit,
            from,
            to,
        } => (
            "monitor",
            format!(
                "{variable} = {reading}{} -> {to}{}",
                unit_suffix(unit),
                from.as_ref()
                    .map_or(String::new(), |from| format!(" (was {from})"))
            ),
        ),
        E::Stale {
            variable,
            last,
            limit,
        } => (
            "STALE",
            format!("{variable}: no reading since {last:.3} s (more than {limit} s): unknown"),
        ),
        E::ObservationsMissing { variables } if variables.is_empty() => {
            ("observed", "every observable is reported again".to_string())
        }
        E::ObservationsMissing { variables } => {
            ("missing", format!("not reported: {}", variables.join(", ")))
        }
        E::DeadlineOverrun { elapsed, deadline } => (
            "OVERRUN",
            format!(
                "the cycle took {:.1} ms, over its {:.1} ms deadline",
                elapsed.as_secs_f64() * 1e3,
                deadline.as_secs_f64() * 1e3
            ),
        ),
        E::ProgramCompleted => ("completed", "the program has completed".to_string()),
        E::TimePointFired { point, window } => (
            "fired",
            format!("{point}  (window {})", window_text(*window)),
        ),
        E::TimePointForced {
            point,
            window,
            late_by,
        } => (
            "FORCED",
            format!(
                "{point} at its latest time, not ready  (window {}, {late_by:.3} s late)",
                window_text(*window)
            ),
        ),
        E::XGoalDispatched {
            sv,
            constraint,
            kind,
            interval: (start, end),
            goals,
        } => {
            // The constraint names its SV when it has a control part (`switch1 ∈ {..}`).
            let sv = component(*sv);
            let what = if constraint.starts_with(&sv) {
                constraint.clone()
            } else {
                format!("{sv} {constraint}")
            };
            let goals = if goals.is_empty() {
                "no goal".to_string()
            } else {
                goals.join(", ")
            };
            (
                "dispatched",
                format!("{kind} {what} over [{start}, {end}]  ({goals})"),
            )
        }
        E::MissionGoalFailed {
            goal,
            reason,
            mode,
            probability,
        } => (
            "GOAL FAILED",
            format!("{goal}: {reason}; ŝ has {mode} (p {probability:.2})"),
        ),
        E::ConstraintSent {
            goal,
            sv,
            constraint,
        } => (
            "delegated",
            format!("{goal}: constraint {constraint} sent to the controller of {sv}"),
        ),
        E::ControllerCommand { sv, command, goal } => {
            ("controller", format!("{sv}: {command}  (for goal {goal})"))
        }
        E::ConstraintEnded {
            goal,
            sv,
            outcome,
            value,
        } => (
            if outcome == "success" {
                "endcstr"
            } else {
                "ENDCSTR"
            },
            format!("{goal}: the controller of {sv} ended it {outcome}; {sv} = {value}"),
        ),
        E::ConstraintWithdrawn { goal, sv, value } => (
            "withdrawn",
            format!(
                "{goal}: retired while the controller of {sv} worked on it; its constraint is \
                 withdrawn, no further command; {sv} = {value}"
            ),
        ),
        E::SubmissionRefused {
            by, goals, reason, ..
        } => (
            "REFUSED",
            format!("{} submitted by `{by}`: {reason}", goals.join(", ")),
        ),
        E::TemporalInconsistency { point, cycle } => (
            "TEMPORAL",
            format!(
                "firing {point} contradicts the network: {}; the constraints not fired are \
                 withdrawn",
                cycle.join("; ")
            ),
        ),
        E::TacticChosen { goal, tactic } => ("tactic", format!("{goal}: tactic {tactic} chosen")),
        E::TacticRejected {
            goal,
            tactic,
            reason,
        } => (
            "tactic",
            format!("{goal}: tactic {tactic} rejected: {reason}"),
        ),
        E::ResponseTaken { explanation, .. } => ("RESPONSE", explanation.clone()),
        E::Promoted { cause } => ("promoted", format!("the proposed network ({cause})")),
        E::PromotionFailed { reason } => ("PROMOTION", format!("failed: {reason}")),
        E::Safing { cause } => ("SAFING", cause.clone()),
        E::GoalRecovered {
            goal,
            mode,
            probability,
        } => (
            "recovered",
            format!("{goal} holds again; ŝ has {mode} (p {probability:.2})"),
        ),
        E::NetworkStalled { points } => ("STALLED", points.join("; ")),
        E::SafeGoalDropped { goal, reason } => {
            ("SAFE DROP", format!("safe goal {goal} dropped: {reason}"))
        }
        E::XGoalWithdrawn { sv, goals } => (
            "withdrawn",
            format!(
                "{}: no XGoal active since the promotion ({} no longer asked for)",
                component(*sv),
                goals.join(", ")
            ),
        ),
        E::GoalContradicted {
            goal,
            command,
            component: c,
            mode,
        } => (
            "CONTRADICTED",
            format!(
                "withheld {}: it would move {} out of {mode}, which {goal} requires",
                command.join(", "),
                component(*c)
            ),
        ),
        E::Chatter {
            component: c,
            mode,
            cycles,
        } => (
            "CHATTER",
            format!(
                "{} commanded back into {mode}, which it was commanded out of {cycles} cycles ago",
                component(*c)
            ),
        ),
    }
}

/// `[71, 161]`: a time point's window, open sides as `−∞`/`+∞`.
fn window_text((lb, ub): (f64, f64)) -> String {
    format!(
        "[{}, {}]",
        crate::goalnet::mission::seconds(lb),
        crate::goalnet::mission::seconds(ub)
    )
}

/// A unit after a number (` V`, ` °C`), nothing for none.
fn unit_suffix(unit: &str) -> String {
    if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    }
}
