//! The rover device (seed 001 ¶8) on the grid of mds-goal-networks.md §4.2: `turn` sets the
//! heading (absolute); `drive` moves one cell ahead unless the heading is diagonal, the target
//! cell holds an obstacle or lies off the grid — then the rover stays put. Either way it then
//! reports its pose to its sensor.

use std::collections::BTreeSet;

use super::posandhead::{Command, Pose};

/// The grid the rover drives on: cells (x, y) with 0 ≤ x, y < `size`, some holding obstacles.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Grid {
    /// Cells per side (§4.2: 5).
    pub size: i32,
    /// Cells the rover cannot enter.
    pub obstacles: BTreeSet<(i32, i32)>,
}

impl Grid {
    /// Whether (x, y) is a cell of the grid.
    pub fn contains(&self, x: i32, y: i32) -> bool {
        (0..self.size).contains(&x) && (0..self.size).contains(&y)
    }

    /// Whether the rover may stand on (x, y): on the grid, no obstacle.
    pub fn free(&self, x: i32, y: i32) -> bool {
        self.contains(x, y) && !self.obstacles.contains(&(x, y))
    }

    /// The rover's pose after executing `command` from `pose` (¶8); what it then reports.
    pub fn execute(&self, pose: Pose, command: Command) -> Pose {
        match command {
            Command::Turn(heading) => Pose { heading, ..pose },
            Command::Drive => match pose.heading.step() {
                Some((dx, dy)) if self.free(pose.x + dx, pose.y + dy) => Pose {
                    x: pose.x + dx,
                    y: pose.y + dy,
                    ..pose
                },
                _ => pose,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::protocol::posandhead::Heading::{self, *};

    fn grid(obstacles: &[(i32, i32)]) -> Grid {
        Grid {
            size: 5,
            obstacles: obstacles.iter().copied().collect(),
        }
    }

    fn pose(x: i32, y: i32, heading: Heading) -> Pose {
        Pose { x, y, heading }
    }

    /// ¶8 and §4.2: a drive moves one cell along a cardinal heading (N is +y, E is +x).
    #[test]
    fn drive_moves_one_cell_along_a_cardinal_heading() {
        let g = grid(&[]);
        assert_eq!(g.execute(pose(2, 2, N), Command::Drive), pose(2, 3, N));
        assert_eq!(g.execute(pose(2, 2, E), Command::Drive), pose(3, 2, E));
        assert_eq!(g.execute(pose(2, 2, S), Command::Drive), pose(2, 1, S));
        assert_eq!(g.execute(pose(2, 2, W), Command::Drive), pose(1, 2, W));
    }

    /// ¶8 and §4.2: the three ways a drive is blocked — a diagonal heading, an obstacle, the
    /// grid's edge — leave the rover where it is.
    #[test]
    fn drive_is_blocked_by_diagonals_obstacles_and_the_edge() {
        let g = grid(&[(2, 0)]);
        for h in [NE, SE, SW, NW] {
            assert_eq!(g.execute(pose(2, 2, h), Command::Drive), pose(2, 2, h));
        }
        assert_eq!(g.execute(pose(1, 0, E), Command::Drive), pose(1, 0, E));
        assert_eq!(g.execute(pose(4, 3, E), Command::Drive), pose(4, 3, E));
        assert_eq!(g.execute(pose(0, 0, S), Command::Drive), pose(0, 0, S));
        assert_eq!(g.execute(pose(3, 4, N), Command::Drive), pose(3, 4, N));
    }

    /// §4.2: `turn(h)` is absolute and never moves the rover.
    #[test]
    fn turn_sets_the_heading_absolutely() {
        let g = grid(&[]);
        assert_eq!(g.execute(pose(1, 1, N), Command::Turn(SW)), pose(1, 1, SW));
        assert_eq!(g.execute(pose(1, 1, SW), Command::Turn(SW)), pose(1, 1, SW));
    }
}
