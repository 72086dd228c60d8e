//! Helpers for the RMPL and sequencer tests and benchmarks: loading the shipped programs, a
//! variable table for the Mars entry plant, scripted estimates, and reading markings and events
//! back in terms of the program's lines.
#![allow(dead_code)] // each includer uses a different part

use kairos::diagnostic::Source;
use kairos::logic::VarTable;
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::{Event, Sequencer, StateEstimate, Thca};

/// Loads and compiles a program file of the crate (its first program), panicking with the
/// rendered errors if it does not compile.
pub fn load_program(path: &str, plant: Option<&VarTable>) -> Thca {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"));
    compile_text(path, &text, plant)
}

/// Compiles RMPL text, panicking with the rendered errors if it does not compile.
pub fn compile_text(name: &str, text: &str, plant: Option<&VarTable>) -> Thca {
    let source = Source::new(name, text);
    let options = LinkOptions { entry: None, plant };
    rmpl::load(&source, &options).unwrap_or_else(|errors| panic!("{errors}"))
}

/// The state variables of the simplified Mars lander of the thesis's Chapter 3 (Figure 3-3,
/// Appendix C) that the entry sequence mentions, with their modes.
pub fn mars_entry_plant() -> VarTable {
    let mut table = VarTable::new();
    for (name, values) in [
        (
            "engine",
            &["off", "heating", "standby", "firing", "failed"][..],
        ),
        ("nav", &["earth-relative", "inertial", "unknown"][..]),
        (
            "att",
            &["cruise-orient", "slew-to-entry", "entry-orient", "failed"][..],
        ),
        (
            "lander",
            &["connected", "separated", "unsuccessful-attempt", "failed"][..],
        ),
        ("entry", &["not-initiated", "initiated"][..]),
    ] {
        table
            .add_variable(name, values.iter().copied())
            .expect("valid names");
    }
    table
}

/// An estimate assigning `assignments` (variable, value) by name.
pub fn state(table: &VarTable, assignments: &[(&str, &str)]) -> StateEstimate {
    let mut estimate = StateEstimate::new();
    set(table, &mut estimate, assignments);
    estimate
}

/// `previous` with `changes` applied.
pub fn updated(
    table: &VarTable,
    previous: &StateEstimate,
    changes: &[(&str, &str)],
) -> StateEstimate {
    let mut estimate = previous.clone();
    set(table, &mut estimate, changes);
    estimate
}

fn set(table: &VarTable, estimate: &mut StateEstimate, assignments: &[(&str, &str)]) {
    for (name, value) in assignments {
        let var = table
            .variable_id(name)
            .unwrap_or_else(|| panic!("no variable {name}"));
        let value = table
            .variable(var)
            .value(value)
            .unwrap_or_else(|| panic!("{value} is not a value of {name}"));
        estimate.set(var, value);
    }
}

/// A compiled program read back in the terms of the figure it was typed from: lines are counted
/// from the program's first line (the file's header comment is not part of the figure).
pub struct Figure {
    /// The automaton.
    pub thca: Thca,
    first_line: usize,
}

impl Figure {
    /// Wraps `thca`; its first location's line becomes line 1.
    pub fn new(thca: Thca) -> Self {
        let first_line = thca
            .locations()
            .first()
            .map_or(1, |l| thca.source().line_col(l.origin.span.start).0);
        Figure { thca, first_line }
    }

    /// The figure line of a byte offset.
    pub fn line(&self, offset: usize) -> usize {
        self.thca.source().line_col(offset).0 + 1 - self.first_line
    }

    /// The first line of a span's text.
    pub fn text(&self, span: &std::ops::Range<usize>) -> String {
        self.thca.source().text[span.clone()]
            .lines()
            .next()
            .unwrap_or_default()
            .trim()
            .to_string()
    }

    /// Location `number`'s figure line and the first line of its text.
    pub fn origin(&self, number: u32) -> (usize, String) {
        let location = self
            .thca
            .locations()
            .iter()
            .find(|l| l.id.number() == number)
            .unwrap_or_else(|| panic!("no location {number}"));
        let span = &location.origin.span;
        (self.line(span.start), self.text(span))
    }

    /// The marking as "number@line" entries, by number.
    pub fn marking(&self, sequencer: &Sequencer) -> String {
        let entries: Vec<String> = sequencer
            .marking()
            .map(|l| format!("{}@{}", l.id, self.line(l.origin.span.start)))
            .collect();
        entries.join(" ")
    }

    /// An event in words, with the source text it concerns.
    pub fn describe(&self, event: &Event) -> Option<String> {
        Some(match event {
            Event::ClockStarted {
                clock,
                time,
                location,
                span,
            } => format!(
                "clock {} started at {time} by location {location} (`{}`)",
                self.thca.table().clock_name(*clock),
                self.text(span)
            ),
            Event::GoalAchieved { location, span } => {
                format!(
                    "goal of location {location} achieved (`{}`)",
                    self.text(span)
                )
            }
            Event::Preempted { location, span } => {
                format!("location {location} preempted (`{}`)", self.text(span))
            }
            Event::MaintenanceViolated { location, span } => format!(
                "maintenance of location {location} violated (`{}`)",
                self.text(span)
            ),
            Event::GoalConflict { first, second } => format!(
                "goal conflict: location {} (`{}`) and location {} (`{}`)",
                first.location,
                self.text(&first.span),
                second.location,
                self.text(&second.span)
            ),
            Event::Completed => "completed".to_string(),
        })
    }
}
