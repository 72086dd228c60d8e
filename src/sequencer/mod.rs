//! The control sequencer: timed hierarchical constraint automata and their execution (thesis
//! §5.2–§5.4; DESIGN.md §5.2–§5.3).
//!
//! - [`thca`]: the automaton — locations (primitive or composite) with goals, clock
//!   initialisations, maintenance constraints and multi-target transitions; every location maps
//!   back to its RMPL source span.
//! - [`Sequencer`]: the marking, the clocks and `Step_THCA` (Figure 5-3), split into the two halves
//!   of an executive cycle ([`Sequencer::begin_cycle`], [`Sequencer::end_cycle`]).
//! - [`Entailment`]: the questions the sequencer asks the deductive controller, with an oracle on
//!   an explicit assignment and one on an OPSAT [`Theory`](crate::opsat::Theory).
//! - [`dot`]: Graphviz drawings of an automaton and a marking.

pub mod dot;
mod evaluate;
mod oracle;
#[cfg(test)]
mod reference;
mod step;
pub mod thca;

pub use oracle::{
    AssignmentOracle, Entailment, StateEstimate, TheoryOracle, entailed_in_every_case,
};
pub use step::{
    ConfigurationGoal, CycleEnd, CycleStart, Event, GoalConjunct, GoalSource, Sequencer,
    SequencerError, Step,
};
pub use thca::{
    ClockInit, Condition, Construct, FormulaId, Goal, Location, LocationId, LocationKind, Origin,
    Sense, Thca, ThcaBuilder, ThcaError, Transition,
};
