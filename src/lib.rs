//! kairos — a timed model-based executive.
//!
//! A *timed model-based program* states how a system's hidden states should evolve over time
//! (an RMPL control program) and how its hardware behaves and fails (timed, probabilistic
//! constraint automata). The executive estimates the hidden state from commands and observations
//! and chooses commands that reach the program's goals; both are optimal constraint problems
//! solved by OPSAT, a conflict-directed A*. See `ARCHITECTURE.md` for the map of the modules.
#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod campaign;
pub mod diagnostic;
pub mod dot;
pub mod estimation;
pub mod executive;
pub mod exploration;
pub mod goalnet;
pub mod logic;
pub mod opsat;
pub mod plant;
pub mod protocol;
pub mod reconfiguration;
pub mod report;
pub mod rmpl;
pub mod sequencer;
pub mod simulation;

/// The property tests' seeded configuration, shared with the integration tests.
#[cfg(test)]
#[path = "../tests/support/seeded.rs"]
mod seeded;
