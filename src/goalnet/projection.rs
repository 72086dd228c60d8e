//! The nominal projection of a scheduled network to a time `T` (`kairos schedule --at T`): what
//! an operator reads before uplinking a network — which points will have fired by `T`, the
//! windows left to the others, and the XGoal each state variable is under at `T`.
//!
//! The projection is temporal only: every point fires **as early as the network lets it** (its
//! earliest time, once the points constrained to precede it have fired), grounding it and
//! re-propagating as the executive does (mds-goal-networks.md §2.4; AG §1.2.7 d). It does not
//! wait for a Maintain XGoal's set to hold — that depends on the plant, which only a run knows —
//! so a real run fires each point at or after its projected time, never before.
//!
//! Grounding a point at its earliest time cannot contradict a propagated network (any value in
//! one point's window extends to a solution of a consistent STN), so a projection of a network
//! that scheduled never fails for temporal reasons; the error is kept for a caller who hands it
//! an unpropagated network.

use super::network::ExecutableNetwork;
use super::stn::{GroundError, Window};
use super::time_point::TimePointId;
use super::xgoal::XGoal;
use crate::plant::ComponentId;

/// A scheduled network projected to a time.
#[derive(Debug, Clone)]
pub struct Projection {
    /// The time projected to, seconds.
    pub at: f64,
    /// The network with every point fired by `at` grounded (its windows are those left at `at`).
    pub executable: ExecutableNetwork,
    /// Per point, when it fired in the projection (the origin at 0).
    pub fired: Vec<Option<f64>>,
}

impl Projection {
    /// The XGoal a state variable is under at `at`: the one whose start has fired and whose
    /// end has not.
    pub fn active(&self, sv: ComponentId) -> Option<&XGoal> {
        let timeline = self.executable.timeline(sv)?;
        timeline
            .xgoals
            .iter()
            .find(|x| self.fired[x.start.index()].is_some() && self.fired[x.end.index()].is_none())
    }

    /// A point's window at `at` (a fired point's is its firing time).
    pub fn window(&self, point: TimePointId) -> Option<Window> {
        self.executable.network.stn().window(point)
    }
}

/// Projects `executable` to `at` (see the module documentation). `at` below 0 projects to the
/// origin only.
pub fn project(executable: &ExecutableNetwork, at: f64) -> Result<Projection, GroundError> {
    let mut projected = executable.clone();
    let stn = projected.network.stn_mut();
    stn.propagate().map_err(GroundError::Inconsistent)?;
    let predecessors = stn.predecessors();
    let mut fired = vec![None; stn.point_count()];
    fired[TimePointId::ORIGIN.index()] = Some(0.0);
    while let Some((point, time)) = next_to_fire(stn, &fired, &predecessors, at) {
        stn.ground(point, time)?;
        fired[point.index()] = Some(time);
    }
    Ok(Projection {
        at,
        executable: projected,
        fired,
    })
}

/// The unfired point with the smallest earliest time at or before `at`, preferring one whose
/// predecessors have all fired (ties at equal times: a predecessor first).
fn next_to_fire(
    stn: &super::Stn,
    fired: &[Option<f64>],
    predecessors: &[Vec<TimePointId>],
    at: f64,
) -> Option<(TimePointId, f64)> {
    let mut best: Option<(bool, f64, TimePointId)> = None;
    for (i, _) in fired.iter().enumerate().filter(|(_, f)| f.is_none()) {
        let point = TimePointId(i as u32);
        let Some(window) = stn.window(point) else {
            continue;
        };
        if window.lb > at {
            continue;
        }
        let blocked = predecessors[i].iter().any(|p| fired[p.index()].is_none());
        let candidate = (blocked, window.lb, point);
        let better = best.is_none_or(|(b, lb, _)| (blocked, window.lb) < (b, lb));
        if better {
            best = Some(candidate);
        }
    }
    best.map(|(_, lb, point)| (point, lb))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Span;
    use crate::goalnet::{GoalNetwork, Provenance, TemporalConstraint};

    /// origin → a ∈ [10, 20], a → b ∈ [5, 30], origin → c ∈ [100, 200].
    fn network() -> ExecutableNetwork {
        let mut network = GoalNetwork::new();
        let a = network.add_point("a", Span::default());
        let b = network.add_point("b", Span::default());
        let c = network.add_point("c", Span::default());
        let written = || Provenance::Submitted;
        for (from, to, min, max) in [
            (TimePointId::ORIGIN, a, 10.0, 20.0),
            (a, b, 5.0, 30.0),
            (TimePointId::ORIGIN, c, 100.0, 200.0),
        ] {
            network
                .add_constraint(TemporalConstraint::new(from, to, min, max, written()))
                .expect("valid bounds");
        }
        network.propagate().expect("consistent");
        ExecutableNetwork {
            network,
            timelines: Vec::new(),
        }
    }

    #[test]
    fn points_fire_as_early_as_allowed_up_to_the_projected_time() {
        // mds-goal-networks.md §2.4: a point fires once its lower bound has passed.
        let projection = project(&network(), 15.0).expect("projects");
        let fired: Vec<Option<f64>> = projection.fired.clone();
        assert_eq!(fired, vec![Some(0.0), Some(10.0), Some(15.0), None]);
        let b = projection.window(TimePointId(2)).expect("propagated");
        assert_eq!((b.lb, b.ub), (15.0, 15.0), "b grounded at a + 5");
        let c = projection.window(TimePointId(3)).expect("propagated");
        assert_eq!((c.lb, c.ub), (100.0, 200.0), "c untouched");
    }

    #[test]
    fn windows_after_the_projected_time_follow_the_grounded_points() {
        // Grounding re-propagates (AG §1.2.7 d): b's window is a's firing time + [5, 30].
        let projection = project(&network(), 12.0).expect("projects");
        assert_eq!(projection.fired[1], Some(10.0));
        assert_eq!(projection.fired[2], None);
        let b = projection.window(TimePointId(2)).expect("propagated");
        assert_eq!((b.lb, b.ub), (15.0, 40.0));
    }

    #[test]
    fn before_the_origin_nothing_fires() {
        let projection = project(&network(), -1.0).expect("projects");
        assert_eq!(projection.fired, vec![Some(0.0), None, None, None]);
    }
}
