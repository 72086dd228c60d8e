//! The expectations a scenario states: what must happen (or never happen) in its run, each
//! within its time window (DESIGN.md §11). [`super::expect`] checks them cycle by cycle.
//!
//! *Eventual* expectations (`Estimated`, `Commanded`, `Diagnosed`, `Achieved`, `GoalFailed`,
//! `Completed`, `Reported`, `Fired`, `Failed`, `Recovered`, and `EstimatedAt`, `XGoalActive` at
//! their time) are met at the first cycle that shows them inside their window and fail if the
//! run ends without one; *never* expectations (`NeverEstimated`, `NeverCommanded`,
//! `NeverReported`, `NeverFired`, `NeverFailed`, `NeverXGoalActive`) fail at the first cycle
//! inside their window that shows what they exclude and hold otherwise, and so does the
//! invariant `Always(that: …)` at the first cycle its condition ([`Condition`]) does not hold.
//!
//! `Reported` and `NeverReported` may say what the event must say (`saying: "…"`): a part of
//! its text as the mission log prints it — the goals a refusal names, a forced point's
//! lateness, the response taken, the tactic chosen and why another was rejected.

use super::condition::Condition;
use super::format::EventName;
use super::script::{Delay, TIME_EPSILON};
use crate::logic::{Formula, ValueId};
use crate::plant::ComponentId;

/// A closed time window `[from, to]` in seconds; open ends are infinite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Window {
    /// Not before this time.
    pub from: f64,
    /// Not after this time.
    pub to: f64,
}

impl Window {
    /// The whole run.
    pub const ALWAYS: Window = Window {
        from: f64::NEG_INFINITY,
        to: f64::INFINITY,
    };

    /// True when `time` is inside the window.
    pub fn contains(&self, time: f64) -> bool {
        time >= self.from - TIME_EPSILON && time <= self.to + TIME_EPSILON
    }

    /// True when `time` is past the window's end.
    pub fn is_past(&self, time: f64) -> bool {
        time > self.to + TIME_EPSILON
    }
}

/// One expectation of a scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct Expectation {
    /// How the mission log names it: `engine = firing estimated by 300 s`.
    pub label: String,
    /// What is checked.
    pub kind: ExpectationKind,
}

/// The kinds of [`Expectation`] (the format is documented in [`crate::simulation`]).
#[derive(Debug, Clone, PartialEq)]
pub enum ExpectationKind {
    /// ŝ satisfies the formula (over mode variables) at some cycle in the window.
    Estimated {
        /// The formula.
        state: Formula,
        /// When.
        window: Window,
    },
    /// ŝ satisfies the formula at the first cycle at or after `time`.
    EstimatedAt {
        /// The formula.
        state: Formula,
        /// The time.
        time: f64,
    },
    /// ŝ satisfies the formula at no cycle in the window.
    NeverEstimated {
        /// The formula.
        state: Formula,
        /// When.
        window: Window,
    },
    /// Some cycle's command μ (idle values elsewhere) satisfies the formula over controls.
    Commanded {
        /// The formula.
        command: Formula,
        /// When.
        window: Window,
    },
    /// The commands issued in the window (cycles whose μ is not all idle), in order, satisfy
    /// these formulas one by one, and there are no more.
    CommandsInOrder {
        /// One formula per command.
        commands: Vec<Formula>,
        /// When.
        window: Window,
    },
    /// No cycle's command in the window satisfies the formula.
    NeverCommanded {
        /// The formula.
        command: Formula,
        /// When.
        window: Window,
    },
    /// The executive reports the diagnosis `component = mode` (the fault mode becomes most
    /// likely) in the window and, with `within`, within that delay of the rule's first firing.
    Diagnosed {
        /// The component.
        component: ComponentId,
        /// Its fault mode.
        mode: ValueId,
        /// When.
        window: Window,
        /// At most this long after this rule (index into the script's rules) first fired.
        within: Option<(Delay, usize)>,
    },
    /// A program location asserting exactly this goal (as the program writes it, shown in the
    /// model's names) reports it achieved in the window.
    Achieved {
        /// The goal, displayed.
        goal: String,
        /// When.
        window: Window,
    },
    /// Goal interpretation fails in the window, for a configuration goal containing this goal if
    /// one is given.
    GoalFailed {
        /// A conjunct of the failed goal, displayed.
        goal: Option<String>,
        /// When.
        window: Window,
    },
    /// The program completes in the window.
    Completed {
        /// When.
        window: Window,
    },
    /// An event of this kind is reported in the window (saying this, if given).
    Reported {
        /// The kind.
        event: EventName,
        /// A part of its text as the log prints it.
        saying: Option<String>,
        /// When.
        window: Window,
    },
    /// One of these (eventual expectations that cannot fail before the end) is shown: a
    /// property with alternatives, such as "lands, or reports the failure".
    AnyOf {
        /// The alternatives.
        members: Vec<ExpectationKind>,
    },
    /// No event of this kind (saying this, if given) is reported in the window.
    NeverReported {
        /// The kind.
        event: EventName,
        /// A part of its text as the log prints it.
        saying: Option<String>,
        /// When.
        window: Window,
    },
    /// The mission's time point fires (on time or forced) in the window.
    Fired {
        /// The point's name.
        point: String,
        /// When.
        window: Window,
    },
    /// The mission's time point does not fire in the window.
    NeverFired {
        /// The point's name.
        point: String,
        /// When.
        window: Window,
    },
    /// The mission's goal (a constituent goal, by name) is reported failed in the window.
    Failed {
        /// The goal's name.
        goal: String,
        /// When.
        window: Window,
    },
    /// No goal of the mission (or not this one) is reported failed in the window.
    NeverFailed {
        /// The goal's name; any goal when `None`.
        goal: Option<String>,
        /// When.
        window: Window,
    },
    /// At the first cycle at or after `time`, an XGoal is active on the state variable (with
    /// this constituent goal, if one is given).
    XGoalActive {
        /// The state variable.
        sv: ComponentId,
        /// A constituent goal's name.
        goal: Option<String>,
        /// The time.
        time: f64,
    },
    /// The mission's goal (by name), having failed, is reported holding again in the window.
    Recovered {
        /// The goal's name.
        goal: String,
        /// When.
        window: Window,
    },
    /// At no cycle in the window is an XGoal active on the state variable (merging this goal,
    /// if one is given).
    NeverXGoalActive {
        /// The state variable.
        sv: ComponentId,
        /// A constituent goal's name.
        goal: Option<String>,
        /// When.
        window: Window,
    },
    /// The condition holds at every cycle in the window (an invariant `kairos explore` checks
    /// on every path).
    Always {
        /// The condition.
        condition: Condition,
        /// When.
        window: Window,
    },
}

/// The pattern of the windowed kinds (checked only while a cycle's time is in their window),
/// binding the window to `$window`: one list for [`ExpectationKind::window`] and the tests'
/// `windows_mut`, which needs it by `&mut`.
macro_rules! windowed {
    ($window:ident) => {
        ExpectationKind::Estimated {
            window: $window,
            ..
        } | ExpectationKind::NeverEstimated {
            window: $window,
            ..
        } | ExpectationKind::Commanded {
            window: $window,
            ..
        } | ExpectationKind::NeverCommanded {
            window: $window,
            ..
        } | ExpectationKind::Diagnosed {
            window: $window,
            ..
        } | ExpectationKind::Achieved {
            window: $window,
            ..
        } | ExpectationKind::GoalFailed {
            window: $window,
            ..
        } | ExpectationKind::Completed { window: $window }
            | ExpectationKind::Reported {
                window: $window,
                ..
            }
            | ExpectationKind::NeverReported {
                window: $window,
                ..
            }
            | ExpectationKind::Fired {
                window: $window,
                ..
            }
            | ExpectationKind::NeverFired {
                window: $window,
                ..
            }
            | ExpectationKind::Failed {
                window: $window,
                ..
            }
            | ExpectationKind::NeverFailed {
                window: $window,
                ..
            }
            | ExpectationKind::Recovered {
                window: $window,
                ..
            }
            | ExpectationKind::NeverXGoalActive {
                window: $window,
                ..
            }
    };
}

impl ExpectationKind {
    /// The earliest time at which a cycle can move this expectation or change anything the
    /// checker keeps for it: before it, checking it returns `Progress::Open` and touches
    /// nothing, so the checker does not ask (`Checker::observe` in [`super::expect`]).
    ///
    /// Exact: a windowed kind's check is `Open` and effect-free outside its window, and a cycle
    /// at `t` is outside it when `t < from − ε` — `Window::contains`'s first clause, the same
    /// subtraction — and `EstimatedAt` and `XGoalActive` return `Open` at once while
    /// `t < time − ε`. `AnyOf` waits for its first member; `Always` updates its condition's
    /// `Once` flags at every cycle, in its window or not, and `CommandsInOrder` is checked on
    /// its own path: both are asked from the start.
    pub(super) fn opens_at(&self) -> f64 {
        use ExpectationKind as K;
        if let Some(window) = self.window() {
            return window.from - TIME_EPSILON;
        }
        match self {
            K::EstimatedAt { time, .. } | K::XGoalActive { time, .. } => time - TIME_EPSILON,
            K::AnyOf { members } => (members.iter())
                .map(ExpectationKind::opens_at)
                .fold(f64::INFINITY, f64::min),
            // Asked from the start: the safe answer for any kind not named above.
            _ => f64::NEG_INFINITY,
        }
    }

    /// The window of a windowed kind (one checked only while a cycle's time is in it);
    /// `None` for `EstimatedAt`, `XGoalActive`, `AnyOf`, `Always` and `CommandsInOrder`.
    fn window(&self) -> Option<&Window> {
        use ExpectationKind as K;
        match self {
            windowed!(window) => Some(window),
            K::EstimatedAt { .. }
            | K::XGoalActive { .. }
            | K::AnyOf { .. }
            | K::Always { .. }
            | K::CommandsInOrder { .. } => None,
        }
    }

    /// The latest time at which a cycle can move this expectation or change anything the
    /// checker keeps for it: after it, checking it returns `Progress::Open` and touches
    /// nothing, so the checker stops asking (`Checker::observe` in [`super::expect`]).
    ///
    /// Exact: a cycle's time is after every earlier cycle's, and a windowed kind's check is
    /// `Open` and effect-free at a time outside its window — `t > to + ε` is
    /// `Window::contains`'s second clause failing, the same addition (every arm of
    /// `Checker::check_kind` asks `window.contains(t)` before it fails, meets or notes a
    /// late diagnosis). An `AnyOf` closes with its last member. `EstimatedAt` and
    /// `XGoalActive` are decided at their time, `Always` updates its `Once` flags at every
    /// cycle and `CommandsInOrder` is checked on its own path: they never close.
    pub(super) fn closes_at(&self) -> f64 {
        use ExpectationKind as K;
        if let Some(window) = self.window() {
            return window.to + TIME_EPSILON;
        }
        match self {
            K::AnyOf { members } => (members.iter())
                .map(ExpectationKind::closes_at)
                .fold(f64::NEG_INFINITY, f64::max),
            // Never closes: the safe answer for any kind not named above.
            _ => f64::INFINITY,
        }
    }

    /// The windows of this kind and of its `AnyOf` members, to move them in tests.
    #[cfg(test)]
    pub(crate) fn windows_mut(&mut self) -> Vec<&mut Window> {
        use ExpectationKind as K;
        match self {
            windowed!(window) | K::CommandsInOrder { window, .. } | K::Always { window, .. } => {
                vec![window]
            }
            K::AnyOf { members } => members.iter_mut().flat_map(K::windows_mut).collect(),
            K::EstimatedAt { .. } | K::XGoalActive { .. } => Vec::new(),
        }
    }

    /// True for the kinds that must be shown by some cycle (the run goes on while one is open).
    pub fn is_eventual(&self) -> bool {
        !matches!(
            self,
            ExpectationKind::NeverEstimated { .. }
                | ExpectationKind::NeverCommanded { .. }
                | ExpectationKind::NeverReported { .. }
                | ExpectationKind::NeverFired { .. }
                | ExpectationKind::NeverFailed { .. }
                | ExpectationKind::NeverXGoalActive { .. }
                | ExpectationKind::Always { .. }
        )
    }
}

/// How an expectation came out.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// It holds; for an eventual expectation, the time of the cycle that showed it.
    Met {
        /// When it was shown (`None` for a never-expectation that held throughout).
        at: Option<f64>,
    },
    /// It does not hold.
    Failed {
        /// Why, with times and the estimate where that helps.
        reason: String,
    },
}

/// An expectation with its outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct Verdict {
    /// The expectation's label.
    pub label: String,
    /// The outcome.
    pub outcome: Outcome,
}

impl Verdict {
    /// True when the expectation holds.
    pub fn holds(&self) -> bool {
        matches!(self.outcome, Outcome::Met { .. })
    }
}
