//! The rover's position-and-heading state variable (seed 001 ¶10, class `posandhead`): its
//! values, the constraints goals put on it, `satisfy`, and the course of action `coa` (¶11, with
//! the y-phase and the final heading the seed cuts off read as mds-goal-networks.md §4.2).

use std::fmt;

use serde::Deserialize;

/// The eight headings of §4.2; N is +y, E is +x.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Deserialize)]
pub enum Heading {
    /// +y.
    N,
    /// +x +y (diagonal: the rover cannot drive).
    NE,
    /// +x.
    E,
    /// +x −y (diagonal).
    SE,
    /// −y.
    S,
    /// −x −y (diagonal).
    SW,
    /// −x.
    W,
    /// −x +y (diagonal).
    NW,
}

impl Heading {
    /// The cell offset of one drive step, for the four cardinal headings only: the seed's rover
    /// cannot move along the grid when heading diagonally (¶8).
    pub fn step(self) -> Option<(i32, i32)> {
        match self {
            Heading::N => Some((0, 1)),
            Heading::E => Some((1, 0)),
            Heading::S => Some((0, -1)),
            Heading::W => Some((-1, 0)),
            Heading::NE | Heading::SE | Heading::SW | Heading::NW => None,
        }
    }
}

impl fmt::Display for Heading {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self, f)
    }
}

/// A cell and a heading: what the rover reports after every command (¶8) and, through the
/// sort conversions of ¶12, the state variable's value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Pose {
    /// Column, 0 at the west edge.
    pub x: i32,
    /// Row, 0 at the south edge.
    pub y: i32,
    /// Where the rover faces.
    pub heading: Heading,
}

impl fmt::Display for Pose {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "({}, {}, {})", self.x, self.y, self.heading)
    }
}

/// A state value (¶3): a pose, or `uk` (the subsort of unknown values) when the estimator has
/// nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum StateValue {
    /// `uk`: the value is unknown.
    Unknown,
    /// The estimated pose.
    Known(Pose),
}

impl fmt::Display for StateValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StateValue::Unknown => f.write_str("uk"),
            StateValue::Known(pose) => pose.fmt(f),
        }
    }
}

/// A constraint on the state variable (¶4): `nocstr`, always satisfied, or a pose with some
/// components left free (§4.2's `PosHead { x, y, h }`, `None` = unconstrained) — "move to a
/// location" and "face a direction" (¶10) are both of this form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Constraint {
    /// `nocstr`: satisfied by every value, `uk` included.
    NoCstr,
    /// The constrained components.
    PosHead {
        /// The column to be in, if constrained.
        x: Option<i32>,
        /// The row to be in, if constrained.
        y: Option<i32>,
        /// The heading to face, if constrained.
        heading: Option<Heading>,
    },
}

impl fmt::Display for Constraint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Constraint::PosHead { x, y, heading } = self else {
            return f.write_str("nocstr");
        };
        let parts: Vec<String> = [
            x.map(|x| format!("x={x}")),
            y.map(|y| format!("y={y}")),
            heading.map(|h| format!("heading={h}")),
        ]
        .into_iter()
        .flatten()
        .collect();
        if parts.is_empty() {
            return f.write_str("(any pose)");
        }
        write!(f, "({})", parts.join(", "))
    }
}

/// A command of the controller–actuator interface (¶9): `drive` one cell ahead, or `turn` to an
/// absolute heading (§4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Command {
    /// One cell in the heading's direction, if the device can (¶8).
    Drive,
    /// Face this heading.
    Turn(Heading),
}

impl fmt::Display for Command {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Command::Drive => f.write_str("drive"),
            Command::Turn(h) => write!(f, "turn({h})"),
        }
    }
}

/// `satisfy(v, c)` (¶6): every constrained component equals the value's; `uk` satisfies only
/// `nocstr` (§4.2).
pub fn satisfy(value: &StateValue, constraint: &Constraint) -> bool {
    let Constraint::PosHead { x, y, heading } = constraint else {
        return true;
    };
    let StateValue::Known(pose) = value else {
        return false;
    };
    x.is_none_or(|x| x == pose.x)
        && y.is_none_or(|y| y == pose.y)
        && heading.is_none_or(|h| h == pose.heading)
}

/// `coa(v, c)` (¶11, completed by §4.2): the x-phase (turn E or W if not already facing it,
/// then |Δx| drives), the y-phase (the same with N or S), then a turn to the constrained heading
/// if the rover does not face it. Empty for `uk` (nothing to plan from, §5 C12) and for
/// `nocstr`. Planned on the value alone: obstacles are not known to the controller (R3).
pub fn coa(value: &StateValue, constraint: &Constraint) -> Vec<Command> {
    let (StateValue::Known(pose), Constraint::PosHead { x, y, heading }) = (value, constraint)
    else {
        return Vec::new();
    };
    let mut commands = Vec::new();
    let mut facing = pose.heading;
    let mut phase = |from: i32, to: Option<i32>, plus: Heading, minus: Heading| {
        let Some(to) = to.filter(|&to| to != from) else {
            return;
        };
        let direction = if to > from { plus } else { minus };
        if facing != direction {
            commands.push(Command::Turn(direction));
            facing = direction;
        }
        commands.extend(std::iter::repeat_n(
            Command::Drive,
            to.abs_diff(from) as usize,
        ));
    };
    phase(pose.x, *x, Heading::E, Heading::W);
    phase(pose.y, *y, Heading::N, Heading::S);
    if let Some(goal) = heading.filter(|&h| h != facing) {
        commands.push(Command::Turn(goal));
    }
    commands
}

#[cfg(test)]
mod tests {
    use super::*;
    use Command::{Drive, Turn};
    use Heading::*;

    fn at(x: i32, y: i32, heading: Heading) -> StateValue {
        StateValue::Known(Pose { x, y, heading })
    }

    fn reach(x: Option<i32>, y: Option<i32>, heading: Option<Heading>) -> Constraint {
        Constraint::PosHead { x, y, heading }
    }

    /// §4.2 R1: x-phase (turn E, drive ×3), then y-phase (turn N, drive ×2).
    #[test]
    fn coa_does_the_x_phase_then_the_y_phase() {
        let plan = coa(&at(0, 0, N), &reach(Some(3), Some(2), None));
        assert_eq!(plan, [Turn(E), Drive, Drive, Drive, Turn(N), Drive, Drive]);
    }

    /// §4.2: no turn when already facing the phase's direction; west and south when the goal is
    /// behind; a final turn only to a constrained heading not already faced.
    #[test]
    fn coa_turns_only_when_the_heading_differs() {
        assert_eq!(
            coa(&at(0, 0, E), &reach(Some(3), Some(0), None)),
            [Drive; 3]
        );
        assert_eq!(
            coa(&at(4, 4, E), &reach(Some(2), Some(3), Some(E))),
            [Turn(W), Drive, Drive, Turn(S), Drive, Turn(E)]
        );
        assert_eq!(coa(&at(1, 1, S), &reach(None, Some(0), Some(S))), [Drive]);
        assert_eq!(coa(&at(1, 1, S), &reach(None, None, Some(NW))), [Turn(NW)]);
    }

    /// §4.2 R4: a diagonal heading is not E, so the x-phase turns first.
    #[test]
    fn coa_turns_from_a_diagonal_heading() {
        assert_eq!(
            coa(&at(0, 0, NE), &reach(Some(2), Some(0), None)),
            [Turn(E), Drive, Drive]
        );
    }

    /// §4.2 step 4 and §5 C12: nothing to plan from `uk`; nothing to do for `nocstr` or a
    /// constraint already satisfied.
    #[test]
    fn coa_is_empty_from_uk_and_for_satisfied_constraints() {
        assert!(coa(&StateValue::Unknown, &reach(Some(1), Some(1), None)).is_empty());
        assert!(coa(&at(0, 0, N), &Constraint::NoCstr).is_empty());
        assert!(coa(&at(2, 2, E), &reach(Some(2), Some(2), None)).is_empty());
    }

    /// ¶6, §4.2: `satisfy` compares the constrained components only; `uk` satisfies `nocstr`
    /// alone.
    #[test]
    fn satisfy_checks_constrained_components_and_uk_only_meets_nocstr() {
        assert!(satisfy(&at(2, 2, E), &reach(Some(2), Some(2), None)));
        assert!(!satisfy(&at(2, 2, E), &reach(Some(2), Some(2), Some(N))));
        assert!(satisfy(&at(0, 3, W), &reach(None, Some(3), None)));
        assert!(satisfy(&StateValue::Unknown, &Constraint::NoCstr));
        assert!(!satisfy(&StateValue::Unknown, &reach(None, None, None)));
    }

    /// Whatever the start and goal on the grid, `coa` leads to a value satisfying the goal when
    /// nothing blocks the way (the plan is complete, §4.2).
    #[test]
    fn coa_reaches_every_goal_on_an_empty_grid() {
        let headings = [N, NE, E, SE, S, SW, W, NW];
        for (x0, y0, x1, y1) in
            (0..25).flat_map(|a| (0..25).map(move |b| (a % 5, a / 5, b % 5, b / 5)))
        {
            for &h in &headings {
                let goal = reach(Some(x1), Some(y1), Some(headings[(x0 + y1) as usize % 8]));
                let mut pose = Pose {
                    x: x0,
                    y: y0,
                    heading: h,
                };
                for command in coa(&StateValue::Known(pose), &goal) {
                    match command {
                        Turn(to) => pose.heading = to,
                        Drive => {
                            let (dx, dy) = pose.heading.step().expect("coa drives only cardinally");
                            pose.x += dx;
                            pose.y += dy;
                        }
                    }
                }
                assert!(
                    satisfy(&StateValue::Known(pose), &goal),
                    "{goal} from ({x0}, {y0}, {h})"
                );
            }
        }
    }
}
