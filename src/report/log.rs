//! The mission log of `kairos run` (DESIGN.md §12: "output a person reads first: what the
//! executive believed, decided and did, with times"). One block per cycle in which something
//! notable happened — an event of the executive (§10) or a rule of the scripted plant — and
//! nothing for idle cycles; a summary and the expectations' verdicts at the end.
//!
//! ```text
//! [  12.000 s] #12
//!   plant     rule `PDE latches up` takes effect: pde = latched  (FAULT)
//!   believed  PDE: on -> resettable (p 0.91)
//!   DIAGNOSIS PDE = resettable (p 0.91); next: PDE = on (p 0.09)
//!   REPAIR    PDE.cmd = reset (PDE: resettable -> on)
//! ```

use std::fmt::Write;

use crate::diagnostic::Source;
use crate::estimation::Fallback;
use crate::executive::{Event, EventKind};
use crate::plant::Plant;
use crate::sequencer::LocationId;
use crate::simulation::{CycleRecord, Outcome, PlantEventKind, RunOutcome, Scenario, StopReason};

/// One event as a (tag, text) pair: `("command", "PDE.cmd = on: PDE: off -> on")`. The log
/// prints it; the trace stores the text next to the event's kind.
pub fn describe_event(
    plant: &Plant,
    program: &Source,
    event: &EventKind,
) -> (&'static str, String) {
    use EventKind as E;
    let at = |span: &crate::diagnostic::Span| {
        let (line, col) = program.line_col(span.start);
        format!("{}:{line}:{col}", program.name)
    };
    let component = |c: crate::plant::ComponentId| plant.component(c).name().to_string();
    match event {
        E::GoalAsserted { goal, span, .. } => ("goal", format!("asserted {goal}  ({})", at(span))),
        E::GoalAchieved { span, .. } => (
            "goal",
            format!(
                "achieved {}  ({})",
                program.text.get(span.clone()).unwrap_or("?").trim(),
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
        E::Preempted { span, .. } => ("preempted", format!("the construct at {}", at(span))),
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
        } => {
            let name = component(*c);
            let mut text = format!("{name} = {mode} (p {probability:.2})");
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
        } => {
            // The planner's purpose already names the command (`command PDE.cmd = on (PDE: off
            // -> on)`); the assignments are shown only when it does not.
            let what = purpose.strip_prefix("command ").map_or_else(
                || format!("{}: {purpose}", assignments.join(", ")),
                str::to_string,
            );
            // The tag says it is a repair; the planner's " (repair)" would say it twice.
            if *repair {
                ("REPAIR", what.replacen(" (repair)", "", 1))
            } else {
                ("command", what)
            }
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
                    Fallback::UnconstrainedFaults =>
                        "components may jump into unconstrained faults",
                    Fallback::PreviousBelief =>
                        "the previous belief is kept, the observation set aside",
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
        shown.then(|| format!("[{:>10.3} s] #{}\n{lines}", step.time, step.cycle))
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
            "\nrun ended at {:.3} s after {} cycles ({stop}); program {}\n",
            outcome.last_time,
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
                    let _ = writeln!(out, "  ok     {} (at {t:.3} s)", verdict.label);
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
