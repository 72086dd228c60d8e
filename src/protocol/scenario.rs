//! The rover scenario file: a grid, the rover, the constraints the environment sends and what
//! each must end with — the scenarios R1–R7 of mds-goal-networks.md §4.2 (`scenarios/rover/`),
//! checked on every interleaving by `kairos explore`. Reference for users:
//! `docs/reference/rover-scenario.md`.
//!
//! ```ron
//! RoverScenario(
//!     name: "R5: a second constraint waits for the first",   // optional; default: file name
//!     grid: 5,                       // optional (default 5): cells (x, y), 0 ≤ x, y < grid
//!     obstacles: [(2, 3)],           // optional: cells the rover cannot enter
//!     rover: (x: 0, y: 0, heading: N),  // the device's true pose; headings N NE E SE S SW W NW
//!     estimate: Known,               // optional: Known (default: the state variable starts at
//!                                    // the rover's pose) or Unknown (it starts at `uk`)
//!     constraints: [
//!         // goal: Reach(x:, y:, heading:) — each optional, a missing one is unconstrained —
//!         // or NoCstr. expect: Success or CoaNoSuccess, the endcstr every interleaving must
//!         // end it with. commands: optional, how many commands it must have taken.
//!         Constraint(name: "c1", goal: Reach(x: 2, y: 0), expect: Success, commands: 3),
//!         // arrives: Initially (default: in flight from the start), WhileProcessing("c1")
//!         // (the environment sends it at any point while the controller processes c1, which
//!         // must be declared before it), or Anytime (at any point at all).
//!         Constraint(name: "c2", goal: Reach(x: 2, y: 2), arrives: WhileProcessing("c1"),
//!                    expect: Success, commands: 3),
//!     ],
//!     ends_at: (x: 2, y: 2, heading: N),  // optional: the rover's pose at every end
//! )
//! ```
//! Every error names the file, line and column, shows the text and says what was expected.

use std::collections::BTreeSet;
use std::path::Path;

use serde::Deserialize;

use super::messages::{ConstraintId, Outcome, Reason};
use super::posandhead::{Constraint, Heading, Pose, StateValue};
use super::rover::Grid;
use crate::diagnostic::LoadErrors;
use crate::diagnostic::locate::{Locator, Step};
use crate::diagnostic::{Diagnostic, Source, SourceErrors, did_you_mean, ron_error};

/// The grid's side when the scenario does not say (§4.2).
pub const DEFAULT_GRID: i64 = 5;

/// The largest grid side accepted: far above the seed's model, small enough that a coordinate
/// never overflows.
pub const MAX_GRID: i64 = 1_000;

/// When the environment sends a constraint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arrival {
    /// In flight in the initial configuration.
    Initially,
    /// At any point while the controller processes this (earlier) constraint.
    WhileProcessing(ConstraintId),
    /// At any point.
    Anytime,
}

/// One constraint of a scenario and its expected outcome.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScenarioConstraint {
    /// Its name (unique in the scenario).
    pub name: String,
    /// The constraint.
    pub constraint: Constraint,
    /// When the environment sends it.
    pub arrives: Arrival,
    /// The `endcstr` it must end with on every interleaving.
    pub expect: Outcome,
    /// How many commands must have been issued for it at every end, if the scenario says.
    pub commands: Option<usize>,
}

/// A loaded rover scenario.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RoverScenario {
    /// Its name.
    pub name: String,
    /// The grid and its obstacles.
    pub grid: Grid,
    /// The rover's true initial pose.
    pub rover: Pose,
    /// Whether the state variable starts at the rover's pose (else at `uk`).
    pub known: bool,
    /// The constraints, in declaration order (their ids).
    pub constraints: Vec<ScenarioConstraint>,
    /// The rover's pose every terminal configuration must have, if the scenario says.
    pub ends_at: Option<Pose>,
}

impl RoverScenario {
    /// The state variable's initial value.
    pub fn initial_value(&self) -> StateValue {
        match self.known {
            true => StateValue::Known(self.rover),
            false => StateValue::Unknown,
        }
    }
}

/// Whether `text` is a rover scenario rather than a scripted one: a line of it starts with
/// `RoverScenario(` (what `kairos explore` dispatches on).
pub fn is_rover_scenario(text: &str) -> bool {
    text.lines()
        .any(|line| line.trim_start().starts_with("RoverScenario("))
}

#[derive(Deserialize)]
#[serde(rename = "RoverScenario", deny_unknown_fields)]
struct File {
    #[serde(default)]
    name: Option<String>,
    #[serde(default = "default_grid")]
    grid: i64,
    #[serde(default)]
    obstacles: Vec<(i64, i64)>,
    rover: PoseFile,
    #[serde(default)]
    estimate: Estimate,
    constraints: Vec<ConstraintFile>,
    #[serde(default)]
    ends_at: Option<PoseFile>,
}

/// The grid's side when a file does not say.
pub(crate) fn default_grid() -> i64 {
    DEFAULT_GRID
}

/// A pose as written: `(x: 0, y: 0, heading: N)` (also a mission's course-of-action device).
#[derive(Deserialize, Clone, Copy)]
#[serde(deny_unknown_fields)]
pub(crate) struct PoseFile {
    x: i64,
    y: i64,
    heading: Heading,
}

/// Whether the state variable starts at the rover's pose (`Known`) or at `uk`.
#[derive(Deserialize, Default, Clone, Copy, PartialEq)]
pub(crate) enum Estimate {
    #[default]
    Known,
    Unknown,
}

#[derive(Deserialize)]
#[serde(rename = "Constraint", deny_unknown_fields)]
struct ConstraintFile {
    name: String,
    goal: Goal,
    #[serde(default)]
    arrives: ArrivalFile,
    expect: Expect,
    #[serde(default)]
    commands: Option<usize>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
enum Goal {
    Reach {
        #[serde(default)]
        x: Option<i64>,
        #[serde(default)]
        y: Option<i64>,
        #[serde(default)]
        heading: Option<Heading>,
    },
    NoCstr,
}

#[derive(Deserialize, Default)]
enum ArrivalFile {
    #[default]
    Initially,
    WhileProcessing(String),
    Anytime,
}

#[derive(Deserialize, Clone, Copy)]
enum Expect {
    Success,
    CoaNoSuccess,
}

/// Reads the rover scenario at `path`.
pub fn load(path: &Path) -> Result<RoverScenario, LoadErrors> {
    let source = Source::read(path)?;
    load_source(&source)
}

/// Reads a rover scenario from its text.
pub fn load_source(source: &Source) -> Result<RoverScenario, LoadErrors> {
    let invalid =
        |diagnostics| LoadErrors::Invalid(vec![SourceErrors::new(source.clone(), diagnostics)]);
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let file: File = options
        .from_str(&source.text)
        .map_err(|e| invalid(vec![ron_error(source, &e)]))?;
    let mut checker = Checker::new(&source.text);
    let scenario = checker.scenario(&file, source);
    match checker.errors.is_empty() {
        true => Ok(scenario),
        false => Err(invalid(checker.errors)),
    }
}

/// Validates a file read by serde, collecting located errors: a rover scenario, or the device
/// of a mission's course-of-action controller (`goalnet::mission`).
pub(crate) struct Checker {
    locate: Locator,
    /// The errors found so far.
    pub(crate) errors: Vec<Diagnostic>,
    /// The grid, once read (cells are checked against it).
    pub(crate) grid: Grid,
}

impl Checker {
    /// A checker of the file whose text is `text` (paths are from its root).
    pub(crate) fn new(text: &str) -> Self {
        Checker {
            locate: Locator::new(text),
            errors: Vec::new(),
            grid: Grid {
                size: 0,
                obstacles: BTreeSet::new(),
            },
        }
    }

    /// Reads the grid: its side (at `side_at`) and its obstacles (at `obstacles_at`), each on
    /// the grid.
    pub(crate) fn grid(
        &mut self,
        side_at: &[Step],
        side: i64,
        obstacles_at: &[Step],
        obstacles: &[(i64, i64)],
    ) {
        self.grid.size = if (1..=MAX_GRID).contains(&side) {
            side as i32
        } else {
            let message = format!("a grid of {side} cells a side");
            self.error(side_at, message, "a side from 1 to 1000");
            DEFAULT_GRID as i32
        };
        for (i, &(x, y)) in obstacles.iter().enumerate() {
            let at = [obstacles_at, &[Step::Index(i)]].concat();
            if let Some(cell) = self.cell(&at, x, y) {
                self.grid.obstacles.insert(cell);
            }
        }
    }

    fn error(&mut self, path: &[Step], message: impl Into<String>, expected: &str) {
        let span = self.locate.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    fn scenario(&mut self, file: &File, source: &Source) -> RoverScenario {
        self.grid(
            &[Step::Field("grid")],
            file.grid,
            &[Step::Field("obstacles")],
            &file.obstacles,
        );
        let rover = self.pose(&[Step::Field("rover")], file.rover);
        let ends_at = file
            .ends_at
            .map(|p| self.pose(&[Step::Field("ends_at")], p));
        if file.constraints.is_empty() {
            self.error(
                &[Step::Field("constraints")],
                "no constraints: there is nothing to explore",
                "at least one `Constraint(...)`",
            );
        }
        let constraints = (file.constraints.iter().enumerate())
            .map(|(i, c)| self.constraint(i, c, &file.constraints))
            .collect();
        let name = file.name.clone().unwrap_or_else(|| {
            Path::new(&source.name)
                .file_stem()
                .map_or_else(|| source.name.clone(), |s| s.to_string_lossy().to_string())
        });
        RoverScenario {
            name,
            grid: self.grid.clone(),
            rover,
            known: file.estimate == Estimate::Known,
            constraints,
            ends_at,
        }
    }

    /// A cell, if on the grid.
    fn cell(&mut self, at: &[Step], x: i64, y: i64) -> Option<(i32, i32)> {
        let size = i64::from(self.grid.size);
        if (0..size).contains(&x) && (0..size).contains(&y) {
            return Some((x as i32, y as i32));
        }
        let expected = format!("a cell with 0 ≤ x, y < {size}");
        self.error(at, format!("({x}, {y}) is off the grid"), &expected);
        None
    }

    /// A pose the rover can stand at.
    pub(crate) fn pose(&mut self, at: &[Step], pose: PoseFile) -> Pose {
        let (x, y) = self.cell(at, pose.x, pose.y).unwrap_or((0, 0));
        if self.grid.obstacles.contains(&(x, y)) {
            let message = format!("({x}, {y}) holds an obstacle");
            self.error(at, message, "a cell without an obstacle");
        }
        Pose {
            x,
            y,
            heading: pose.heading,
        }
    }

    fn constraint(
        &mut self,
        i: usize,
        file: &ConstraintFile,
        all: &[ConstraintFile],
    ) -> ScenarioConstraint {
        let here = [Step::Field("constraints"), Step::Index(i)];
        if all[..i].iter().any(|c| c.name == file.name) {
            let at = [here[0], here[1], Step::Field("name")];
            let message = format!("constraint `{}` is already declared", file.name);
            self.error(&at, message, "a name not used by an earlier constraint");
        }
        let constraint = match file.goal {
            Goal::NoCstr => Constraint::NoCstr,
            Goal::Reach { x, y, heading } => Constraint::PosHead {
                x: x.and_then(|x| self.coordinate(&here, "x", x)),
                y: y.and_then(|y| self.coordinate(&here, "y", y)),
                heading,
            },
        };
        let arrives = match &file.arrives {
            ArrivalFile::Initially => Arrival::Initially,
            ArrivalFile::Anytime => Arrival::Anytime,
            ArrivalFile::WhileProcessing(other) => self.earlier(&here, other, all, i),
        };
        ScenarioConstraint {
            name: file.name.clone(),
            constraint,
            arrives,
            expect: match file.expect {
                Expect::Success => Outcome::Success,
                Expect::CoaNoSuccess => Outcome::Failure(Reason::CoaNoSuccess),
            },
            commands: file.commands,
        }
    }

    /// A goal's coordinate, if on the grid.
    fn coordinate(&mut self, here: &[Step], field: &str, value: i64) -> Option<i32> {
        let size = i64::from(self.grid.size);
        if (0..size).contains(&value) {
            return Some(value as i32);
        }
        let at = [here[0], here[1], Step::Field("goal"), Step::Field(field)];
        let expected = format!("a coordinate from 0 to {}", size - 1);
        self.error(&at, format!("{field} = {value} is off the grid"), &expected);
        None
    }

    /// The constraint `WhileProcessing` names: declared before the one at `i`.
    fn earlier(&mut self, here: &[Step], other: &str, all: &[ConstraintFile], i: usize) -> Arrival {
        let at = [here[0], here[1], Step::Field("arrives"), Step::Index(0)];
        if let Some(id) = all[..i].iter().position(|c| c.name == other) {
            return Arrival::WhileProcessing(id);
        }
        let earlier: Vec<&str> = all[..i].iter().map(|c| c.name.as_str()).collect();
        let message = match all.iter().position(|c| c.name == other) {
            Some(_) => format!("`{other}` is not declared before this constraint"),
            None => format!("no constraint `{other}`"),
        };
        let mut diagnostic = Diagnostic::new(message, self.locate.at(&at))
            .expected("the name of a constraint declared before this one");
        diagnostic = match did_you_mean(other, earlier.iter().copied()) {
            Some(name) => diagnostic.note(format!("did you mean `{name}`?")),
            None if earlier.is_empty() => diagnostic.note("no constraint is declared before it"),
            None => diagnostic.note(format!("declared before it: {}", earlier.join(", "))),
        };
        self.errors.push(diagnostic);
        Arrival::Anytime
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/rover-scenario.md` lists every field and variant this loader accepts,
    /// and no other.
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        reference::add::<Heading>(&mut tracer);
        reference::add::<Estimate>(&mut tracer);
        reference::add::<Goal>(&mut tracer);
        reference::add::<ArrivalFile>(&mut tracer);
        reference::add::<Expect>(&mut tracer);
        reference::add::<File>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[
                ("RoverScenario", "rover-scenario.md", "`RoverScenario(...)`"),
                ("PoseFile", "rover-scenario.md", "Poses"),
                ("Heading", "rover-scenario.md", "Headings"),
                ("Estimate", "rover-scenario.md", "Estimate"),
                ("Constraint", "rover-scenario.md", "`Constraint(...)`"),
                ("Goal", "rover-scenario.md", "Goals"),
                ("ArrivalFile", "rover-scenario.md", "Arrivals"),
                ("Expect", "rover-scenario.md", "Outcomes"),
            ],
        );
    }
}
