//! The mission log of `kairos run` (DESIGN.md §12: "output a person reads first: what the
//! executive believed, decided and did, with times"). One block per cycle in which something
//! notable happened — an event of the executive (§10) or a rule of the scripted plant — and
//! nothing for idle cycles; a summary and the expectations' verdicts at the end.
//!
//! Times are written twice, in seconds (as scenarios, missions and programs write them) and in
//! mission elapsed time `h:mm:ss.sss` (as a flight engineer reads a long run). The cycle header
//! gives each a fixed width — 10 characters for the seconds, 13 for the clock — which is the same
//! range, 999,999.999 s being 277:46:39.999, so the headers of any run shorter than eleven days
//! stay aligned.
//!
//! ```text
//! [    12.000 s   0:00:12.000] #12
//!   plant     rule `PDE latches up` takes effect: pde = latched  (FAULT)
//!   believed  PDE: on -> resettable (p 0.91)
//!   DIAGNOSIS PDE = resettable (p 0.91); evidence: PDE.status = fault; next: PDE = on (p 0.09)
//!   REPAIR    PDE.cmd = reset (PDE: resettable -> on) for engine = standby (programs/mars_edl.rmpl:20:3)
//! ```

use std::fmt::Write;

use crate::diagnostic::{Source, Span};
use crate::estimation::Fallback;
use crate::executive::{Event, EventKind, Served};
use crate::plant::{ComponentId, Plant};
use crate::report::timeline::hours_minutes_seconds;
use crate::sequencer::LocationId;
use crate::simulation::{CycleRecord, Outcome, PlantEventKind, RunOutcome, Scenario, StopReason};

/// One event as a (tag, text) pair: `("command", "PDE.cmd = on: PDE: off -> on")`. The log
/// prints it; the trace stores the text next to the event's kind.
pub fn describe_event(
    plant: &Plant,
    program: &Source,
    event: &EventKind,
) -> (&'static str, String) {
    describe(&Sources { plant, program }, event)
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

/// The names of a scenario run: the plant's and the program's.
struct Sources<'a> {
    plant: &'a Plant,
    program: &'a Source,
}

impl Names for Sources<'_> {
    fn component(&self, component: ComponentId) -> String {
        self.plant.component(component).name().to_string()
    }

    fn at(&self, span: &Span) -> String {
        let (line, col) = self.program.line_col(span.start);
        format!("{}:{line}:{col}", self.program.name)
    }

    fn text(&self, span: &Span) -> Option<String> {
        let text = self.program.text.get(span.clone())?;
        Some(text.trim().to_string())
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
            Served::Intended { goal } => format!("{goal} (the intended configuration)"),
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
        E::Retrying {
            assignments,
            hypothesis,
            probability,
            attempt,
            budget,
            ..
        } => (
            "RETRY",
            format!(
                "{}: the goal is reachable if {hypothesis} (p {probability:.2}); retry {attempt} of {budget}",
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
        E::SubmissionRefused { by, goals, reason } => (
            "REFUSED",
            format!("{} submitted by `{by}`: {reason}", goals.join(", ")),
        ),
        E::TemporalInconsistency { point, cycle } => (
            "TEMPORAL",
            format!(
                "firing {point} contradicts the network: {}",
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
    }
}

/// Which lines of the mission log to print (`kairos run --hide-plant --only … --from … --to …`).
/// The default shows everything. Filtering changes what is printed, never what is reported:
/// the summary, the verdicts and the trace are whole.
#[derive(Debug, Clone, PartialEq)]
pub struct LogFilter {
    /// Leave out the scripted plant's rule lines.
    pub hide_plant: bool,
    /// Only lines that concern one of these components (empty: all): a mode change or a
    /// diagnosis of it, or any other line that names it (a command to it, a goal on it, a rule
    /// setting one of its attributes).
    pub only: Vec<String>,
    /// Only cycles at or after this time, seconds.
    pub from: f64,
    /// Only cycles at or before this time, seconds.
    pub to: f64,
}

impl Default for LogFilter {
    fn default() -> Self {
        LogFilter {
            hide_plant: false,
            only: Vec::new(),
            from: f64::NEG_INFINITY,
            to: f64::INFINITY,
        }
    }
}

impl LogFilter {
    fn shows_time(&self, time: f64) -> bool {
        self.from <= time && time <= self.to
    }

    /// Whether a line of text names one of the components (as a whole word: `valve1` is not
    /// named by `valve10`; `engine.power` names `engine`).
    fn names_one(&self, text: &str) -> bool {
        self.only.is_empty() || self.only.iter().any(|name| names_word(text, name))
    }
}

fn names_word(text: &str, word: &str) -> bool {
    let part_of_name = |c: char| c.is_alphanumeric() || c == '_' || c == '-';
    text.match_indices(word).any(|(at, _)| {
        let before = text[..at].chars().next_back();
        let after = text[at + word.len()..].chars().next();
        !before.is_some_and(part_of_name) && !after.is_some_and(part_of_name)
    })
}

/// `[71, 161]`: a time point's window, open sides as `−∞`/`+∞`.
fn window_text((lb, ub): (f64, f64)) -> String {
    format!(
        "[{}, {}]",
        crate::goalnet::mission::seconds(lb),
        crate::goalnet::mission::seconds(ub)
    )
}

/// Writes the mission log of one scenario run.
pub struct MissionLog<'a> {
    scenario: &'a Scenario,
    filter: LogFilter,
    /// The locations whose goal was reported achieved in the last cycle: an `always` goal is
    /// achieved again every cycle it holds, which is not news (the trace keeps every report).
    achieved: Vec<LocationId>,
}

impl<'a> MissionLog<'a> {
    /// A log for `scenario`.
    pub fn new(scenario: &'a Scenario) -> Self {
        Self::filtered(scenario, LogFilter::default())
    }

    /// A log for `scenario` printing only what `filter` lets through.
    pub fn filtered(scenario: &'a Scenario, filter: LogFilter) -> Self {
        MissionLog {
            scenario,
            filter,
            achieved: Vec::new(),
        }
    }

    /// The heading: what runs, against what, how.
    pub fn header(&self) -> String {
        let s = self.scenario;
        let mut out = format!("scenario  {}\n", s.name);
        if !s.description.is_empty() {
            let _ = writeln!(out, "          {}", s.description.trim());
        }
        let _ = writeln!(
            out,
            "{}   {}{}\nplant     {} ({})\ncycle     {} s until {} s, κ = {}{}",
            if s.program.mission().is_some() {
                "mission"
            } else {
                "program"
            },
            s.program_source.name,
            s.entry
                .as_deref()
                .map(|e| format!(" ({e})"))
                .unwrap_or_default(),
            s.plant.name(),
            s.plant_path,
            s.cycle,
            s.end,
            s.kappa,
            s.deadline
                .map(|d| format!(", deadline {:.1} ms", d.as_secs_f64() * 1e3))
                .unwrap_or_default(),
        );
        out
    }

    /// The block of one cycle, or `None` when nothing notable happened in it.
    pub fn cycle(&mut self, record: &CycleRecord<'_>) -> Option<String> {
        let s = self.scenario;
        let step = record.step;
        let mut lines = String::new();
        for (k, event) in record.plant_events.iter().enumerate() {
            // A rule that fires and takes effect at once (its `Applied` follows its `Fired`) is
            // shown once, by its effect.
            let immediate = event.kind == PlantEventKind::Fired
                && record.plant_events.get(k + 1).is_some_and(|next| {
                    next.rule == event.rule && next.kind == PlantEventKind::Applied
                });
            if immediate {
                continue;
            }
            let rule = &s.script.rules()[event.rule];
            let what = match event.kind {
                PlantEventKind::Fired => format!("rule `{}` fired", rule.name),
                PlantEventKind::Applied => format!(
                    "rule `{}` takes effect: {}",
                    rule.name,
                    rule.effect.describe(s.script.variables())
                ),
            };
            let fault = if rule.fault { "  (FAULT)" } else { "" };
            if !self.filter.hide_plant && self.filter.names_one(&what) {
                let _ = writeln!(lines, "  {:<12} {what}{fault}", "plant");
            }
        }
        let mut achieved = Vec::new();
        for event in &step.events {
            if let EventKind::GoalAchieved { location, .. } = event.kind {
                achieved.push(location);
                if self.achieved.contains(&location) {
                    continue;
                }
            }
            if self.concerns_shown_components(&event.kind) {
                let _ = writeln!(lines, "  {}", self.event_line(event));
            }
        }
        self.achieved = achieved;
        let shown = !lines.is_empty() && self.filter.shows_time(step.time);
        shown.then(|| {
            format!(
                "[{:>10.3} s {:>13}] #{}\n{lines}",
                step.time,
                hours_minutes_seconds(step.time),
                step.cycle
            )
        })
    }

    /// `--only`: a mode change or diagnosis by its component, any other event by its text.
    fn concerns_shown_components(&self, kind: &EventKind) -> bool {
        let plant = &self.scenario.plant;
        match kind {
            _ if self.filter.only.is_empty() => true,
            EventKind::ModeChanged { component, .. } | EventKind::Diagnosis { component, .. } => {
                let name = plant.component(*component).name();
                self.filter.only.iter().any(|n| n == name)
            }
            other => {
                let (_, text) = describe_event(plant, &self.scenario.program_source, other);
                self.filter.names_one(&text)
            }
        }
    }

    fn event_line(&self, event: &Event) -> String {
        let s = self.scenario;
        let (tag, text) = describe_event(&s.plant, &s.program_source, &event.kind);
        format!("{tag:<12} {text}")
    }

    /// The summary: how the run ended, its timing, and every expectation's verdict.
    pub fn summary(&self, outcome: &RunOutcome) -> String {
        let stop = match outcome.stop {
            StopReason::EndTime => "the end time",
            StopReason::Settled => "nothing more could happen",
        };
        let mut out = format!(
            "\nrun ended at {:.3} s ({}) after {} cycles ({stop}); program {}\n",
            outcome.last_time,
            hours_minutes_seconds(outcome.last_time),
            outcome.cycles,
            if outcome.completed {
                "completed"
            } else {
                "not completed"
            }
        );
        let _ = writeln!(
            out,
            "wall time {:.1} ms, slowest cycle {:.2} ms, {} deadline overrun{}",
            outcome.wall.as_secs_f64() * 1e3,
            outcome.slowest_cycle.as_secs_f64() * 1e3,
            outcome.overruns,
            if outcome.overruns == 1 { "" } else { "s" }
        );
        let _ = writeln!(out, "\nexpectations");
        for verdict in &outcome.verdicts {
            match &verdict.outcome {
                Outcome::Met { at: Some(t) } => {
                    let _ = writeln!(
                        out,
                        "  ok     {} (at {t:.3} s, {})",
                        verdict.label,
                        hours_minutes_seconds(*t)
                    );
                }
                Outcome::Met { at: None } => {
                    let _ = writeln!(out, "  ok     {}", verdict.label);
                }
                Outcome::Failed { reason } => {
                    let _ = writeln!(out, "  FAILED {}: {reason}", verdict.label);
                }
            }
        }
        let failed = outcome.verdicts.iter().filter(|v| !v.holds()).count();
        if failed == 0 {
            let _ = writeln!(out, "\nPASS: {} expectations hold", outcome.verdicts.len());
        } else {
            let _ = writeln!(
                out,
                "\nFAIL: {failed} of {} expectations do not hold",
                outcome.verdicts.len()
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::names_word;

    #[test]
    fn a_component_is_named_as_a_whole_word() {
        assert!(names_word(
            "PDE.cmd = open2: valve2: closed -> open",
            "valve2"
        ));
        assert!(names_word("rule sets engine.power = zero", "engine"));
        assert!(!names_word("valve10 = open", "valve1"));
        assert!(!names_word("alt_12m_trigger = triggered", "trigger"));
        assert!(!names_word("slew-to-landing", "landing"));
        assert!(names_word("landing = success", "landing"));
    }
}
