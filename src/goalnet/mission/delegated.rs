//! Controllers of state variables that are not plant components, and the goals delegated to
//! them (mds-goal-networks.md §1.7: each SV has at most one controller, which
//! achieves its control goals). Reference for users: `docs/reference/mission.md`.
//!
//! ```ron
//! controllers: [
//!     // The rover's position and heading, controlled by seed 001's course-of-action
//!     // controller (`protocol`): `sv` is the name goals give it (not a component's name).
//!     CourseOfAction(
//!         sv: "pose",
//!         // The device it commands: the grid (size optional, default 5), its obstacles —
//!         // which the controller does not know of — and the rover's true initial pose.
//!         device: Grid(size: 5, obstacles: [(2, 0)], rover: (x: 0, y: 0, heading: E)),
//!         estimate: Known,   // optional: Known (default) or Unknown (the SV starts at `uk`)
//!     ),
//! ],
//! ```
//! A goal on `pose` is delegated: a Transition goal whose constraint is a conjunction of
//! `x = 3`, `y = 2`, `heading = N` (each at most once; a missing one is unconstrained), e.g.
//! `Goal(name: "to-the-rock", sv: "pose", kind: Transition, constraint: "x = 3 and y = 2",
//! start: "TP_S", end: "TP_E")`.

use serde::Deserialize;

use super::{GoalFile, Item, Loader};
use crate::diagnostic::Diagnostic;
use crate::diagnostic::locate::Step;
use crate::goalnet::goal::{Delegate, GoalKind};
use crate::logic;
use crate::plant::Plant;
use crate::protocol::CoaDeclaration;
use crate::protocol::posandhead::{Constraint, Heading};
use crate::protocol::scenario::{Checker, Estimate, PoseFile, default_grid};

/// A controller as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum ControllerFile {
    /// Seed 001's course-of-action controller of the rover's position and heading.
    CourseOfAction {
        sv: String,
        device: DeviceFile,
        #[serde(default)]
        estimate: Estimate,
    },
}

/// The device a course-of-action controller commands.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) enum DeviceFile {
    /// The rover on its grid (mds-goal-networks.md §4.2).
    Grid {
        #[serde(default = "default_grid")]
        size: i64,
        #[serde(default)]
        obstacles: Vec<(i64, i64)>,
        rover: PoseFile,
    },
}

/// What a delegated goal's constraint may say, for errors.
const POSE_CONSTRAINT: &str =
    "`x = column`, `y = row`, `heading = N|NE|E|SE|S|SW|W|NW`, joined by `and`";

impl Loader<'_> {
    /// The mission's controllers, each checked: a fresh name that is not a component's, a
    /// device on its grid.
    pub(super) fn controllers(
        &mut self,
        plant: &Plant,
        files: &[ControllerFile],
    ) -> Vec<CoaDeclaration> {
        let mut declared: Vec<CoaDeclaration> = Vec::new();
        for (i, file) in files.iter().enumerate() {
            let ControllerFile::CourseOfAction {
                sv,
                device,
                estimate,
            } = file;
            let at = |field| {
                [
                    Step::Field("controllers"),
                    Step::Index(i),
                    Step::Field(field),
                ]
            };
            if !logic::is_value_name(sv) {
                let message = format!("`{sv}` is not a valid state variable name");
                self.error(
                    &at("sv"),
                    message,
                    "an identifier (letters, digits, `_`, `-`)",
                );
            } else if plant.component_named(sv).is_some() {
                let message = format!("`{sv}` is a component of the plant");
                let expected = "a state variable that is not a component (a component's goals go to mode reconfiguration)";
                self.error(&at("sv"), message, expected);
            } else if declared.iter().any(|d| d.sv == *sv) {
                let message = format!("state variable `{sv}` has a controller already");
                self.error(&at("sv"), message, "one controller per state variable");
            }
            let DeviceFile::Grid {
                size,
                obstacles,
                rover,
            } = device;
            let device_at = |field| [at("device").as_slice(), &[Step::Field(field)]].concat();
            let mut checker = Checker::new(&self.source.text);
            checker.grid(
                &device_at("size"),
                *size,
                &device_at("obstacles"),
                obstacles,
            );
            let rover = checker.pose(&device_at("rover"), *rover);
            let grid = checker.grid.clone();
            self.errors.append(&mut checker.errors);
            declared.push(CoaDeclaration {
                sv: sv.clone(),
                grid,
                rover,
                known: *estimate == Estimate::Known,
            });
        }
        declared
    }

    /// What a goal on a controlled state variable delegates to controller `controller`: its
    /// constraint, checked (a Transition goal, a pose constraint on the grid).
    pub(super) fn delegate(
        &mut self,
        item: &Item,
        spec: &GoalFile,
        controller: usize,
    ) -> Option<Delegate> {
        let sv = self.controllers[controller].sv.clone();
        if spec.kind.kind() != GoalKind::Transition {
            let message = format!(
                "a {} goal on `{sv}`: its course-of-action controller reaches a pose, it does not hold one",
                spec.kind.kind().name()
            );
            let expected = "kind: Transition (the course-of-action controller reaches a pose)";
            self.error(&item.path("kind"), message, expected);
            return None;
        }
        let Some(text) = spec.constraint.as_deref() else {
            let message = format!("a goal on `{sv}` needs a constraint");
            self.error(&item.path("kind"), message, POSE_CONSTRAINT);
            return None;
        };
        let offset = self.locate.at(&item.path("constraint")).start;
        let size = self.controllers[controller].grid.size;
        match pose_constraint(text, offset, size) {
            Ok(constraint) => Some(Delegate {
                controller,
                constraint,
            }),
            Err(diagnostic) => {
                self.errors.push(diagnostic);
                None
            }
        }
    }
}

/// Reads `x = 3 and y = 2 and heading = N` (the text starting at byte `offset` of the file)
/// as a pose constraint on a grid of side `size`.
fn pose_constraint(text: &str, offset: usize, size: i32) -> Result<Constraint, Diagnostic> {
    let (mut x, mut y, mut heading) = (None, None, None);
    let mut at = 0;
    for part in text.split(" and ") {
        let trimmed = part.trim();
        let start = offset + at + (part.len() - part.trim_start().len());
        at += part.len() + " and ".len();
        let span = start..start + trimmed.len();
        let error = |message: String, expected: &str| {
            Diagnostic::new(message, span.clone()).expected(expected)
        };
        let not_pose = || {
            error(
                format!("`{trimmed}` is not a constraint on a pose"),
                POSE_CONSTRAINT,
            )
        };
        let (field, value) = trimmed.split_once('=').ok_or_else(not_pose)?;
        let (field, value) = (field.trim(), value.trim());
        let coordinate = || match value.parse::<i32>() {
            Ok(v) if (0..size).contains(&v) => Ok(Some(v)),
            _ => Err(error(
                format!("{field} = {value} is not on the grid"),
                &format!("a coordinate from 0 to {}", size - 1),
            )),
        };
        let twice = || {
            error(
                format!("`{field}` is constrained twice"),
                "each of x, y, heading at most once",
            )
        };
        match field {
            "x" if x.is_some() => return Err(twice()),
            "y" if y.is_some() => return Err(twice()),
            "heading" if heading.is_some() => return Err(twice()),
            "x" => x = coordinate()?,
            "y" => y = coordinate()?,
            "heading" => {
                let parsed = ron::from_str::<Heading>(value).map_err(|_| {
                    error(
                        format!("`{value}` is not a heading"),
                        "N, NE, E, SE, S, SW, W or NW",
                    )
                })?;
                heading = Some(parsed);
            }
            _ => return Err(not_pose()),
        }
    }
    Ok(Constraint::PosHead { x, y, heading })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The constraint language of a delegated goal: any of x, y, heading, joined by `and`.
    #[test]
    fn pose_constraints_read_each_component_once() {
        assert_eq!(
            pose_constraint("x = 3 and y = 2", 0, 5),
            Ok(Constraint::PosHead {
                x: Some(3),
                y: Some(2),
                heading: None
            })
        );
        assert_eq!(
            pose_constraint("heading = NW", 0, 5),
            Ok(Constraint::PosHead {
                x: None,
                y: None,
                heading: Some(Heading::NW)
            })
        );
        let off = pose_constraint("x = 1 and y = 5", 10, 5).expect_err("off the grid");
        assert_eq!(off.span, 20..25);
        assert!(pose_constraint("x = 1 and x = 2", 0, 5).is_err());
        assert!(pose_constraint("z = 1", 0, 5).is_err());
        assert!(pose_constraint("heading = up", 0, 5).is_err());
    }
}
