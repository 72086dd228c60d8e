//! Time points (mds-goal-networks.md §1.5; seed 000 AG §1.2.1): events that *fire* when they
//! occur. A point has no internal relation to time; its window comes from the temporal
//! constraints of the network it belongs to.

use crate::diagnostic::Span;

/// A time point's index in its network; the origin (absolute time 0) is always point 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TimePointId(pub u32);

impl TimePointId {
    /// The origin `Z`, fixed at absolute time 0 (mds-goal-networks.md §1.5, "STN semantics").
    pub const ORIGIN: TimePointId = TimePointId(0);

    /// The index as a `usize`.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A named time point of a goal network.
#[derive(Debug, Clone, PartialEq)]
pub struct TimePoint {
    /// The name the mission gives it (`"TP_S"`), shown in messages and events.
    pub name: String,
    /// Where it is declared (empty for the origin and for points the scheduler creates).
    pub span: Span,
}

impl TimePoint {
    /// A point with a name and a declaration span.
    pub fn new(name: impl Into<String>, span: Span) -> Self {
        TimePoint {
            name: name.into(),
            span,
        }
    }
}
