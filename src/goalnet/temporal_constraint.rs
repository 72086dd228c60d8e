//! Temporal constraints (mds-goal-networks.md §1.5; seed 000 AG §1.2.1): `(from, to, min, max)`
//! means `min ≤ t(to) − t(from) ≤ max`, with `−∞`/`+∞` allowed for an open side. Every
//! constraint remembers where it came from, so a negative cycle can be explained.

use super::time_point::TimePointId;
use crate::diagnostic::Span;

/// A constraint's index in its network.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ConstraintId(pub u32);

impl ConstraintId {
    /// The index as a `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Why a temporal constraint is in the network (DESIGN.md §15.1: the error names "where each
/// came from (file span, tactic, scheduler serialisation)").
#[derive(Debug, Clone, PartialEq)]
pub enum Provenance {
    /// Written in the mission file, at this span.
    Written(Span),
    /// Every point is at or after the origin: `Z → p ∈ [0, +∞)`, added with the point.
    AfterOrigin,
    /// The point fired at this time: `Z → p ∈ [τ, τ]` (grounding, AG §1.2.7 d).
    Fired,
    /// The scheduler ordered two points of one state variable's timeline (§2.2 step 2b), or
    /// serialised two goals whose constraints do not merge (§2.2 step 2d).
    Scheduled {
        /// What the scheduler did, for messages (`"end(heat1) ≤ start(cool1)"`).
        reason: String,
    },
    /// Given with a goal submitted to a running network.
    Submitted,
    /// A goal holds over its interval: its start no later than its end, added by the scheduler
    /// for every goal, so that constraints allowing the reverse order are an inconsistency
    /// naming them rather than a goal left out of the timeline.
    GoalInterval,
}

/// `min ≤ t(to) − t(from) ≤ max`.
#[derive(Debug, Clone, PartialEq)]
pub struct TemporalConstraint {
    /// The earlier point (when `min ≥ 0`).
    pub from: TimePointId,
    /// The later point.
    pub to: TimePointId,
    /// The least separation, seconds (`f64::NEG_INFINITY` for none).
    pub min: f64,
    /// The greatest separation, seconds (`f64::INFINITY` for none).
    pub max: f64,
    /// Where it came from.
    pub provenance: Provenance,
}

impl TemporalConstraint {
    /// A constraint with its provenance.
    pub fn new(
        from: TimePointId,
        to: TimePointId,
        min: f64,
        max: f64,
        provenance: Provenance,
    ) -> Self {
        TemporalConstraint {
            from,
            to,
            min,
            max,
            provenance,
        }
    }

    /// Order only: `from` no later than `to` (`[0, +∞)`, AG glossary).
    pub fn before(from: TimePointId, to: TimePointId, provenance: Provenance) -> Self {
        Self::new(from, to, 0.0, f64::INFINITY, provenance)
    }

    /// Whether the bounds describe a non-empty interval of reals (not NaN, `min ≤ max`,
    /// neither bound infinite towards the inside).
    pub fn bounds_are_valid(&self) -> bool {
        !self.min.is_nan()
            && !self.max.is_nan()
            && self.min <= self.max
            && self.min != f64::INFINITY
            && self.max != f64::NEG_INFINITY
    }
}
