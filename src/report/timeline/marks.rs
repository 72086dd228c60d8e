//! The marks above the swimlanes, made from the run's events: what the program asserted and
//! achieved, what the executive commanded, and what it diagnosed.
//!
//! Five rows: **program** (goals asserted — a bar runs to the cycle the goal was achieved —
//! goal failures and conflicts, preemptions, completion), **network** (a mission's time points
//! as they fire, each with the window it had then drawn as a whisker; a point forced at its
//! latest time in the fault colour — the row is drawn only for a mission), **commands** (commands issued, repairs
//! distinguished; waits for a timed transition as small rings) and **faults** (diagnoses,
//! inconsistent observations, planning failures), with the faults the simulation injected on a
//! row of their own between the last two. Mode changes are not marked: the lanes show
//! them, and an XGoal is a bar on its state variable's lane (`xgoals`), not a mark. Failed
//! mission goals and temporal inconsistencies go to the faults row. Clock starts are not marked. Observation problems, deadline overruns and search cuts
//! are counted, not drawn (the mission log lists them).

use std::collections::HashMap;

use crate::diagnostic::Span;
use crate::estimation::Fallback;
use crate::executive::{Event, EventKind, Timelines};
use crate::plant::{ComponentId, Plant};
use crate::sequencer::{LocationId, Thca};

use super::InjectedFault;
use super::labels::{file_name, shorten};
use super::scale::Clock;

/// Longest label, in characters (the tooltip has the whole text).
const MAX_LABEL: usize = 44;
/// Longest goal or condition quoted inside a label.
const MAX_QUOTE: usize = 34;

/// A row of marks above the lanes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Row {
    /// The program: goals, preemptions, completion.
    Program,
    /// A mission's goal network: its time points as they fire.
    Network,
    /// Commands issued.
    Commands,
    /// Faults the simulation injected (scripted rules marked `fault: true`): what happened to
    /// the plant, beside what the executive concluded about it.
    Injected,
    /// Diagnoses and other trouble.
    Faults,
}

impl Row {
    /// Every row, top to bottom.
    pub const ALL: [Row; 5] = [
        Row::Program,
        Row::Network,
        Row::Commands,
        Row::Injected,
        Row::Faults,
    ];

    /// The row's name, shown at its left.
    pub fn name(self) -> &'static str {
        match self {
            Row::Program => "program",
            Row::Network => "network",
            Row::Commands => "commands",
            Row::Injected => "injected",
            Row::Faults => "faults",
        }
    }
}

/// A mark's symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Symbol {
    /// ▼ a goal asserted.
    Down,
    /// ✓ a goal achieved.
    Check,
    /// ✕ a failure.
    Cross,
    /// ■ the program completed.
    Square,
    /// ◇ a construct preempted.
    Hollow,
    /// ▲ a command.
    Up,
    /// ○ a wait.
    Ring,
    /// ◆ a diagnosis.
    Diamond,
    /// ✶ a fault injected by the simulation.
    Star,
    /// ● a time point fired.
    Dot,
}

/// One mark.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Mark {
    /// When.
    pub time: f64,
    /// For a goal: when it was achieved (its bar ends there).
    pub until: Option<f64>,
    /// For a time point: its window `[earliest, latest]` when it fired (a whisker; open sides
    /// run to the edge of the drawn window).
    pub window: Option<(f64, f64)>,
    /// Its row.
    pub row: Row,
    /// Its CSS class (after `event`): `goal`, `command repair`, `diagnosis`, ...
    pub class: &'static str,
    /// Its symbol.
    pub symbol: Symbol,
    /// Its colour.
    pub colour: &'static str,
    /// The label shown beside it, if any.
    pub label: Option<String>,
    /// The full text, shown on hover.
    pub tooltip: String,
    /// Draw a faint guide line down through the lanes.
    pub guide: bool,
}

/// Colours of the marks.
pub(super) mod colour {
    /// Goals.
    pub const GOAL: &str = "#1f77b4";
    /// Achievements, completion.
    pub const DONE: &str = "#2ca02c";
    /// Faults and failures.
    pub const FAULT: &str = "#d62728";
    /// Commands.
    pub const COMMAND: &str = "#333333";
    /// Repairs.
    pub const REPAIR: &str = "#e6550d";
    /// Preemptions.
    pub const PREEMPTED: &str = "#756bb1";
    /// Waits.
    pub const WAIT: &str = "#969696";
    /// Faults injected by the simulation.
    pub const INJECTED: &str = "#8c2d04";
    /// Time points fired on time.
    pub const POINT: &str = "#17becf";
}

/// The marks of a run and what was left out.
#[derive(Debug, Clone, Default, PartialEq)]
pub(super) struct Marks {
    /// The marks, in time order.
    pub marks: Vec<Mark>,
    /// Events counted but not drawn: (what, how many).
    pub omitted: Vec<(&'static str, usize)>,
}

/// What the marks are made from.
pub(super) struct Sources<'a> {
    /// The plant (component names).
    pub plant: &'a Plant,
    /// The program (goal lines, preemption conditions).
    pub program: Option<&'a Thca>,
    /// Command history, for commands no event reports.
    pub timelines: &'a Timelines,
    /// The events.
    pub events: &'a [Event],
    /// The faults the simulation injected.
    pub injected: &'a [InjectedFault],
    /// How times are written.
    pub clock: Clock,
    /// The drawn time window.
    pub window: (f64, f64),
}

/// The marks of the events within the window, and of commands the history has but no event
/// reports.
pub(super) fn collect(sources: &Sources) -> Marks {
    let mut events: Vec<&Event> = sources.events.iter().collect();
    events.sort_by(|a, b| a.time.total_cmp(&b.time));
    let mut builder = Builder {
        sources,
        marks: Vec::new(),
        pending: HashMap::new(),
        goals: HashMap::new(),
        omitted: Vec::new(),
    };
    for event in events {
        if builder.inside(event.time) {
            builder.event(event);
        } else {
            builder.omit("events outside the drawn window");
        }
    }
    builder.history_commands();
    for fault in sources.injected {
        if builder.inside(fault.time) {
            builder.injected(fault);
        } else {
            builder.omit("events outside the drawn window");
        }
    }
    let Builder {
        mut marks, omitted, ..
    } = builder;
    marks.sort_by(|a, b| a.time.total_cmp(&b.time));
    Marks { marks, omitted }
}

struct Builder<'s, 'a> {
    sources: &'s Sources<'a>,
    marks: Vec<Mark>,
    /// Goal marks not yet achieved, by location.
    pending: HashMap<LocationId, usize>,
    /// The text of each location's last goal.
    goals: HashMap<LocationId, String>,
    omitted: Vec<(&'static str, usize)>,
}

impl Builder<'_, '_> {
    fn inside(&self, time: f64) -> bool {
        let (start, end) = self.sources.window;
        time >= start && time <= end
    }

    fn at(&self, time: f64) -> String {
        self.sources.clock.precise(time)
    }

    fn omit(&mut self, what: &'static str) {
        match self.omitted.iter_mut().find(|(w, _)| *w == what) {
            Some((_, count)) => *count += 1,
            None => self.omitted.push((what, 1)),
        }
    }

    fn push(&mut self, mark: Mark) -> usize {
        self.marks.push(mark);
        self.marks.len() - 1
    }

    fn event(&mut self, event: &Event) {
        let time = event.time;
        match &event.kind {
            EventKind::GoalAsserted {
                goal,
                location,
                span,
                ..
            } => self.goal_asserted(time, goal, *location, span),
            EventKind::GoalAchieved { location, span } => self.goal_achieved(time, *location, span),
            EventKind::GoalFailed { goal, reason } => self.goal_failed(time, goal, reason),
            EventKind::GoalConflict { first, second } => {
                self.goal_conflict(time, &first.span, &second.span)
            }
            EventKind::Preempted {
                span,
                condition,
                condition_span,
                ..
            } => self.preempted(time, span, condition, condition_span),
            EventKind::ProgramCompleted => self.completed(time),
            EventKind::CommandIssued {
                assignments,
                purpose,
                repair,
                ..
            } => self.command(time, &assignments.join(", "), Some(purpose), *repair),
            EventKind::Waiting { purpose } => self.waiting(time, purpose),
            EventKind::Diagnosis {
                component,
                mode,
                probability,
                ..
            } => self.diagnosis(time, *component, mode, *probability),
            // The retried command is drawn by its `CommandIssued`.
            EventKind::Retrying { .. } => self.omit("retries on a less likely diagnosis"),
            EventKind::EstimatorInconsistency { fallback } => self.inconsistency(time, *fallback),
            EventKind::PlanFailed { reason } => {
                self.trouble(time, "plan-failed", "plan failed", reason)
            }
            EventKind::GoalContradicted { goal, command, .. } => self.trouble(
                time,
                "plan-failed",
                "command withheld",
                &format!("{} would break {goal}", command.join(", ")),
            ),
            EventKind::Chatter { mode, cycles, .. } => self.trouble(
                time,
                "plan-failed",
                "chatter",
                &format!("commanded back into {mode} after {cycles} cycles"),
            ),
            EventKind::ObservationRejected { .. } => self.omit("rejected observations"),
            EventKind::Monitored { .. } => self.omit("monitor changes"),
            EventKind::Stale { .. } => self.omit("stale readings"),
            EventKind::ObservationsMissing { .. } => {
                self.omit("changes in the missing observations")
            }
            EventKind::DeadlineOverrun { .. } => self.omit("cycle deadline overruns"),
            EventKind::SearchCut(_) => self.omit("estimation search cuts"),
            EventKind::ModeChanged { .. } | EventKind::ClockStarted { .. } => {}
            EventKind::TimePointFired { point, window } => {
                self.time_point(time, point, *window, None)
            }
            EventKind::TimePointForced {
                point,
                window,
                late_by,
            } => self.time_point(time, point, *window, Some(*late_by)),
            // A bar on its state variable's lane (`xgoals`).
            EventKind::XGoalDispatched { .. } | EventKind::XGoalWithdrawn { .. } => {}
            EventKind::MissionGoalFailed {
                goal,
                reason,
                mode,
                probability,
            } => self.trouble(
                time,
                "goal-failed",
                &shorten(&format!("goal failed: {goal}"), MAX_LABEL),
                &format!("{goal} — {reason}; ŝ has {mode} (p {probability:.2})"),
            ),
            EventKind::SubmissionRefused {
                by, goals, reason, ..
            } => self.trouble(
                time,
                "submission-refused",
                "submission refused",
                &format!("{} submitted by `{by}`: {reason}", goals.join(", ")),
            ),
            EventKind::TemporalInconsistency { point, cycle } => self.trouble(
                time,
                "temporal-inconsistency",
                "temporal inconsistency",
                &format!("firing {point} contradicts {}", cycle.join("; ")),
            ),
            // Safing ends the mission's plan: drawn, with its cause in the tooltip.
            EventKind::Safing { cause } => self.trouble(time, "safing", "safing", cause),
            EventKind::NetworkStalled { points } => self.trouble(
                time,
                "network-stalled",
                "network stalled",
                &points.join("; "),
            ),
            EventKind::SafeGoalDropped { goal, reason } => self.trouble(
                time,
                "safe-goal-dropped",
                &shorten(&format!("safe goal dropped: {goal}"), MAX_LABEL),
                reason,
            ),
            // The responses' chains are in the mission log; the timeline counts them.
            EventKind::TacticChosen { .. }
            | EventKind::TacticRejected { .. }
            | EventKind::ResponseTaken { .. }
            | EventKind::GoalRecovered { .. }
            | EventKind::Promoted { .. }
            | EventKind::PromotionFailed { .. } => self.omit("goal-network responses"),
            // The protocol's messages of a delegated goal are in the mission log; its failure
            // is a `MissionGoalFailed`, drawn above.
            EventKind::ConstraintSent { .. }
            | EventKind::ControllerCommand { .. }
            | EventKind::ConstraintEnded { .. }
            | EventKind::ConstraintWithdrawn { .. } => self.omit("delegated-goal messages"),
        }
    }

    /// A time point of the mission's network fired (DESIGN.md §15.3): on time, or forced at its
    /// latest time (`late_by`) with an XGoal starting there not ready — forced is drawn in the
    /// fault colour and traced down through the lanes.
    fn time_point(&mut self, time: f64, point: &str, window: (f64, f64), late_by: Option<f64>) {
        let bounds = format!(
            "[{}, {}]",
            crate::goalnet::mission::seconds(window.0),
            crate::goalnet::mission::seconds(window.1)
        );
        let (class, colour, label, tooltip) = match late_by {
            None => (
                "time-point",
                colour::POINT,
                point.to_string(),
                format!(
                    "time point {point} fired at {}, window {bounds}",
                    self.at(time)
                ),
            ),
            Some(late) => (
                "time-point forced",
                colour::FAULT,
                format!("{point} forced"),
                format!(
                    "time point {point} forced at {}, its latest time, with an XGoal starting there not ready; window {bounds}, {late:.3} s late",
                    self.at(time)
                ),
            ),
        };
        self.push(Mark {
            time,
            until: None,
            window: Some(window),
            row: Row::Network,
            class,
            symbol: Symbol::Dot,
            colour,
            label: Some(shorten(&label, MAX_LABEL)),
            tooltip,
            guide: late_by.is_some(),
        });
    }

    fn goal_asserted(&mut self, time: f64, goal: &str, location: LocationId, span: &Span) {
        let label = match self.line(span) {
            Some(line) => format!("{} (line {line})", shorten(goal, MAX_QUOTE)),
            None => shorten(goal, MAX_QUOTE),
        };
        let tooltip = format!(
            "goal asserted at {}: {goal}{}",
            self.at(time),
            self.written_at(span)
        );
        let index = self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "goal",
            symbol: Symbol::Down,
            colour: colour::GOAL,
            label: Some(label),
            tooltip,
            guide: false,
        });
        self.pending.insert(location, index);
        self.goals.insert(location, goal.to_string());
    }

    /// Marks the achievement of a pending goal and ends its bar. A goal held by `always` or
    /// `maintaining` is achieved again every cycle without being asserted again: those repeats
    /// are counted, not drawn, or they would bury the row (and keep the axis from compressing).
    fn goal_achieved(&mut self, time: f64, location: LocationId, span: &Span) {
        let Some(index) = self.pending.remove(&location) else {
            self.omit("repeated achievements of held goals");
            return;
        };
        self.marks[index].until = Some(time);
        let goal = self
            .goals
            .get(&location)
            .cloned()
            .unwrap_or_else(|| format!("location {}", location.number()));
        let tooltip = format!(
            "goal achieved at {}: {goal}{}",
            self.at(time),
            self.written_at(span)
        );
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "goal-achieved",
            symbol: Symbol::Check,
            colour: colour::DONE,
            label: None,
            tooltip,
            guide: false,
        });
    }

    fn goal_failed(&mut self, time: f64, goal: &str, reason: &str) {
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "goal-failed",
            symbol: Symbol::Cross,
            colour: colour::FAULT,
            label: Some(format!("failed: {}", shorten(goal, MAX_QUOTE))),
            tooltip: format!("goal failed at {}: {goal} — {reason}", self.at(time)),
            guide: true,
        });
    }

    fn goal_conflict(&mut self, time: f64, first: &Span, second: &Span) {
        let lines = match (self.line(first), self.line(second)) {
            (Some(a), Some(b)) => format!(" (lines {a}, {b})"),
            _ => String::new(),
        };
        let tooltip = format!(
            "goal conflict at {}: {} contradicts {}",
            self.at(time),
            self.snippet(first).unwrap_or_default(),
            self.snippet(second).unwrap_or_default()
        );
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "goal-conflict",
            symbol: Symbol::Cross,
            colour: colour::FAULT,
            label: Some(format!("goal conflict{lines}")),
            tooltip,
            guide: true,
        });
    }

    /// `preempted: c (line N)`, `c` the condition whose entailment preempted, as the program
    /// writes it (on one line) or, without the program, as the event renders it.
    fn preempted(&mut self, time: f64, span: &Span, condition: &str, condition_span: &Span) {
        let condition = self.snippet(condition_span).map_or_else(
            || condition.to_string(),
            |text| text.split_whitespace().collect::<Vec<_>>().join(" "),
        );
        let mut label = format!("preempted: {}", shorten(&condition, MAX_QUOTE));
        if let Some(line) = self.line(span) {
            label.push_str(&format!(" (line {line})"));
        }
        let tooltip = format!("{label} at {}{}", self.at(time), self.written_at(span));
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "preempted",
            symbol: Symbol::Hollow,
            colour: colour::PREEMPTED,
            label: Some(label),
            tooltip,
            guide: false,
        });
    }

    fn completed(&mut self, time: f64) {
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Program,
            class: "completed",
            symbol: Symbol::Square,
            colour: colour::DONE,
            label: Some("program completed".to_string()),
            tooltip: format!("program completed at {}", self.at(time)),
            guide: false,
        });
    }

    fn command(&mut self, time: f64, assignments: &str, purpose: Option<&String>, repair: bool) {
        let label = if repair {
            format!("repair: {assignments}")
        } else {
            assignments.to_string()
        };
        let kind = if repair { "repair command" } else { "command" };
        let why = purpose.map(|p| format!(" — {p}")).unwrap_or_default();
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Commands,
            class: if repair { "command repair" } else { "command" },
            symbol: Symbol::Up,
            colour: if repair {
                colour::REPAIR
            } else {
                colour::COMMAND
            },
            label: Some(shorten(&label, MAX_LABEL)),
            tooltip: format!("{kind} at {}: {assignments}{why}", self.at(time)),
            guide: true,
        });
    }

    fn waiting(&mut self, time: f64, purpose: &str) {
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Commands,
            class: "waiting",
            symbol: Symbol::Ring,
            colour: colour::WAIT,
            label: None,
            tooltip: format!("waiting from {}: {purpose}", self.at(time)),
            guide: false,
        });
    }

    fn diagnosis(&mut self, time: f64, component: ComponentId, mode: &str, probability: f64) {
        let name = self
            .sources
            .plant
            .components()
            .get(component.index())
            .map_or_else(
                || format!("component {}", component.0),
                |c| c.name().to_string(),
            );
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Faults,
            class: "diagnosis",
            symbol: Symbol::Diamond,
            colour: colour::FAULT,
            label: Some(shorten(
                &format!("{name}: {mode} (p {probability:.2})"),
                MAX_LABEL,
            )),
            tooltip: format!(
                "diagnosis at {}: {name} = {mode}, probability {probability:.3}",
                self.at(time)
            ),
            guide: true,
        });
    }

    fn injected(&mut self, fault: &InjectedFault) {
        self.push(Mark {
            time: fault.time,
            until: None,
            window: None,
            row: Row::Injected,
            class: "injected",
            symbol: Symbol::Star,
            colour: colour::INJECTED,
            label: Some(shorten(&fault.name, MAX_LABEL)),
            tooltip: format!(
                "fault injected at {}: {} — {}",
                self.at(fault.time),
                fault.name,
                fault.effect
            ),
            guide: true,
        });
    }

    fn inconsistency(&mut self, time: f64, fallback: Fallback) {
        let reading = match fallback {
            Fallback::Reestimated { steps } => {
                format!("explained by the last {steps} steps estimated again, wider")
            }
            Fallback::UnconstrainedFaults => {
                "explained only by unconstrained fault modes".to_string()
            }
            Fallback::PreviousBelief => {
                "explained by nothing: the previous belief was kept".to_string()
            }
        };
        self.trouble(time, "inconsistency", "inconsistent observation", &reading);
    }

    fn trouble(&mut self, time: f64, class: &'static str, what: &str, detail: &str) {
        self.push(Mark {
            time,
            until: None,
            window: None,
            row: Row::Faults,
            class,
            symbol: Symbol::Cross,
            colour: colour::FAULT,
            label: Some(what.to_string()),
            tooltip: format!("{what} at {}: {detail}", self.at(time)),
            guide: true,
        });
    }

    /// Commands in the history that no `CommandIssued` event reports (events not collected, or
    /// partly): marked plainly, from the assignments.
    fn history_commands(&mut self) {
        let mut reported: Vec<f64> = self
            .sources
            .events
            .iter()
            .filter(|e| matches!(e.kind, EventKind::CommandIssued { .. }))
            .map(|e| e.time)
            .collect();
        reported.sort_by(f64::total_cmp);
        let table = self.sources.plant.table();
        for command in self.sources.timelines.commands() {
            let time = command.time;
            let known = reported.binary_search_by(|t| t.total_cmp(&time)).is_ok();
            if known || !self.inside(time) {
                continue;
            }
            let text: Vec<String> = command
                .assignments
                .iter()
                .map(|&(var, value)| {
                    let variable = (var.index() < table.len()).then(|| table.variable(var));
                    let name = variable.map_or("?", |v| v.name());
                    let value = variable
                        .and_then(|v| v.values().get(value.index()))
                        .map_or("?", String::as_str);
                    format!("{name} = {value}")
                })
                .collect();
            self.command(time, &text.join(", "), None, false);
        }
    }

    /// `, written at file:line:col` when the program is known.
    fn written_at(&self, span: &Span) -> String {
        match self.sources.program {
            Some(program) => {
                let source = program.source();
                let (line, col) = source.line_col(span.start);
                format!(" — {}:{line}:{col}", file_name(&source.name))
            }
            None => String::new(),
        }
    }

    fn line(&self, span: &Span) -> Option<usize> {
        self.sources
            .program
            .map(|p| p.source().line_col(span.start).0)
    }

    fn snippet(&self, span: &Span) -> Option<String> {
        let text = &self.sources.program?.source().text;
        text.get(span.clone()).map(|s| s.to_string())
    }
}
