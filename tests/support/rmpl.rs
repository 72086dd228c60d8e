//! Helpers for the RMPL and sequencer tests and benchmarks: loading the shipped programs, a
//! variable table for the Mars entry plant, scripted estimates, and reading markings and events
//! back in terms of the program's lines.
#![allow(dead_code)] // each includer uses a different part

use kairos::diagnostic::Source;
use kairos::logic::VarId;
use kairos::logic::VarTable;
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::{AssignmentOracle, Event, Sequencer, StateEstimate, Thca};

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

/// The state variables the Mars entry and EDL programs mention, with the modes the thesis gives
/// them (Figure 3-3, Appendix C, DESIGN.md §6.3): a test fixture for linking against a plant, not
/// the plant model.
pub fn mars_lander_plant() -> VarTable {
    const TRIGGER: &[&str] = &["not-triggered", "triggered"];
    let mut table = VarTable::new();
    for (name, values) in [
        (
            "engine",
            &["off", "heating", "standby", "firing", "failed"][..],
        ),
        ("nav", &["earth-relative", "inertial", "unknown"][..]),
        (
            "att",
            &[
                "cruise-orient",
                "slew-to-entry",
                "entry-orient",
                "vel-vector-orient",
                "landing-orient",
                "failed",
            ][..],
        ),
        (
            "lander",
            &["connected", "separated", "unsuccessful-attempt", "failed"][..],
        ),
        ("entry", &["not-initiated", "initiated"][..]),
        ("landing", &["in-progress", "success"][..]),
        ("Mach_trigger", TRIGGER),
        ("alt_vel_trigger", TRIGGER),
        ("alt_40m_trigger", TRIGGER),
        ("alt_12m_trigger", TRIGGER),
        ("touchdown_sensor", TRIGGER),
        ("chute", &["stowed", "deployed"][..]),
        ("heatshield", &["attached", "jettison"][..]),
        ("backshield", &["attached", "jettisoned"][..]),
        ("legs", &["stowed", "deployed"][..]),
        ("radar_altim", &["off", "on", "failed"][..]),
        ("prop", &["idle", "gravity-turn", "const-vel-descent"][..]),
    ] {
        table
            .add_variable(name, values.iter().copied())
            .expect("valid names");
    }
    table
}

/// The lander's state before the EDL sequence (§5.4 "Initial State", extended to every variable).
pub const MARS_LANDER_INITIAL: &[(&str, &str)] = &[
    ("engine", "off"),
    ("nav", "earth-relative"),
    ("att", "cruise-orient"),
    ("lander", "connected"),
    ("entry", "not-initiated"),
    ("landing", "in-progress"),
    ("Mach_trigger", "not-triggered"),
    ("alt_vel_trigger", "not-triggered"),
    ("alt_40m_trigger", "not-triggered"),
    ("alt_12m_trigger", "not-triggered"),
    ("touchdown_sensor", "not-triggered"),
    ("chute", "stowed"),
    ("heatshield", "attached"),
    ("backshield", "attached"),
    ("legs", "stowed"),
    ("radar_altim", "off"),
    ("prop", "idle"),
];

/// The state variables of the spacecraft deployment program (Figure 5-1) with plausible modes
/// (the flags are "indirect observation" states, §5.1.2): a test fixture.
pub fn spacecraft_plant() -> VarTable {
    const FLAG: &[&str] = &["clear", "set"];
    const IMU: &[&str] = &["off", "warmed", "on", "failed"];
    const ARRAY: &[&str] = &["stowed", "deployed", "failed"];
    let mut table = VarTable::new();
    for (name, values) in [
        ("shuttle", &["attached", "separated"][..]),
        ("IMU_1", IMU),
        ("IMU_2", IMU),
        ("RCS", &["off", "warmed"][..]),
        ("LGA_deploy_flag", FLAG),
        ("SA_deploy_flag", FLAG),
        ("SSR_A", &["off", "on", "failed"][..]),
        ("SSR_B", &["off", "on", "failed"][..]),
        ("downlink", &["off", "beacon", "nominal"][..]),
        ("LGA", &["stowed", "deployed"][..]),
        ("SA_1", ARRAY),
        ("SA_2", ARRAY),
        ("ACS", &["inactive", "active"][..]),
        (
            "power_switch",
            &["ius-supplied", "engage-onboard-batts"][..],
        ),
        ("IUS", &["attached", "separated"][..]),
        (
            "spacecraft_deployment",
            &["in-progress", "success", "failure"][..],
        ),
    ] {
        table
            .add_variable(name, values.iter().copied())
            .expect("valid names");
    }
    table
}

/// The spacecraft in the Shuttle's bay, before deployment.
pub const SPACECRAFT_INITIAL: &[(&str, &str)] = &[
    ("shuttle", "attached"),
    ("IMU_1", "off"),
    ("IMU_2", "off"),
    ("RCS", "off"),
    ("LGA_deploy_flag", "clear"),
    ("SA_deploy_flag", "clear"),
    ("SSR_A", "off"),
    ("SSR_B", "off"),
    ("downlink", "off"),
    ("LGA", "stowed"),
    ("SA_1", "stowed"),
    ("SA_2", "stowed"),
    ("ACS", "inactive"),
    ("power_switch", "ius-supplied"),
    ("IUS", "attached"),
    ("spacecraft_deployment", "in-progress"),
];

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
            Event::Preempted { location, span, .. } => {
                format!("location {location} preempted (`{}`)", self.text(span))
            }
            Event::MaintenanceViolated { location, span, .. } => format!(
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

/// A plant that achieves every goal one cycle after it is asserted, except for variables that are
/// broken, plus scripted happenings: enough to run a program end to end without a plant model.
pub struct IdealPlant {
    /// The program.
    pub figure: Figure,
    /// Its sequencer.
    pub sequencer: Sequencer,
    oracle: AssignmentOracle,
    /// ŝ(i).
    pub estimate: StateEstimate,
    /// t(i).
    pub time: f64,
    period: f64,
    broken: Vec<VarId>,
    /// What happened, in words: goal changes and sequencer events, with times.
    pub log: Vec<String>,
    last_goal: String,
}

impl IdealPlant {
    /// Runs `thca` from `initial`, one cycle every `period` seconds from time 0.
    pub fn new(thca: Thca, initial: &[(&str, &str)], period: f64) -> Self {
        let estimate = state(thca.table(), initial);
        IdealPlant {
            oracle: AssignmentOracle::new(thca.table()),
            sequencer: Sequencer::new(thca.clone()),
            figure: Figure::new(thca),
            estimate,
            time: 0.0,
            period,
            broken: Vec::new(),
            log: Vec::new(),
            last_goal: "true".to_string(),
        }
    }

    /// From now on, goals on `name` are not achieved.
    pub fn break_variable(&mut self, name: &str) {
        let table = self.figure.thca.table();
        self.broken.extend(table.variable_id(name));
    }

    /// One cycle: ŝ(i+1) is ŝ(i) with the goal g(i) achieved (but for broken variables) and then
    /// `happenings` applied.
    pub fn cycle(&mut self, happenings: &[(&str, &str)]) {
        let start = self
            .sequencer
            .begin_cycle(self.time, &self.estimate, &mut self.oracle)
            .expect("cycles alternate, time advances");
        let table = self.figure.thca.table().clone();
        let goal = start.goal.formula.display(&table).to_string();
        if goal != self.last_goal {
            self.log.push(format!("t={:.1} goal {goal}", self.time));
            self.last_goal = goal;
        }
        let mut next = self.estimate.clone();
        for (var, value) in start.goal.formula.as_assignments().unwrap_or_default() {
            if !self.broken.contains(&var) {
                next.set(var, value);
            }
        }
        let next = updated(&table, &next, happenings);
        let end = self
            .sequencer
            .end_cycle(&next, &mut self.oracle)
            .expect("a cycle is open");
        for event in start.events.iter().chain(&end.events) {
            if !matches!(event, Event::GoalAchieved { .. }) {
                let text = self.figure.describe(event).unwrap_or_default();
                self.log.push(format!("t={:.1} {text}", self.time));
            }
        }
        self.estimate = next;
        self.time += self.period;
    }

    /// Cycles until the program completes or time reaches `until`; each scripted happening is
    /// reported by ME at the end of the first cycle at or after its time.
    pub fn run_until(&mut self, until: f64, script: &[(f64, &[(&str, &str)])]) {
        let mut pending = script.iter().peekable();
        while self.time < until && !self.sequencer.is_complete() {
            let mut now: Vec<(&str, &str)> = Vec::new();
            while let Some((_, happening)) = pending.next_if(|(at, _)| *at <= self.time) {
                now.extend_from_slice(happening);
            }
            self.cycle(&now);
        }
    }

    /// Asserts that the log holds lines containing each of `expected`, in this order.
    pub fn assert_in_order(&self, expected: &[&str]) {
        let mut lines = self.log.iter();
        for wanted in expected {
            assert!(
                lines.any(|line| line.contains(wanted)),
                "{wanted:?} missing (or out of order) in the log:\n{}",
                self.log.join("\n")
            );
        }
    }
}
