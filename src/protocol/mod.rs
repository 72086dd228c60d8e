//! The MDS controller protocol of seed 001 (the Maude model of MDS; mds-goal-networks.md §4)
//! (its explicit-state check, DESIGN.md §16, is [`crate::exploration::protocol`]).
//!
//! A state variable's controller receives a constraint; if the state variable's value satisfies
//! it, it answers `endcstr` (success); otherwise it plans a fixed course of action `coa(v, c)`
//! and issues it command by command, each answered — through actuator, device, sensor,
//! estimator and state variable — by `newval`; when the list runs out with the constraint
//! unsatisfied it answers `endcstr` with the reason `coanosuccess`. One constraint at a time;
//! the others wait, first come first served.
//!
//! - [`posandhead`]: the rover's state variable — values, constraints, `satisfy`, `coa`;
//! - [`rover`]: the device on its grid;
//! - [`messages`]: the protocol's messages;
//! - [`controller`]: the [`Controller`] trait and the seed's [`CoaController`];
//! - [`components`]: actuator, sensor and estimator (sort conversions) and the state variable;
//! - [`delegation`]: the protocol run one cycle at a time by the executive, for a mission goal
//!   delegated to a course-of-action controller;
//! - [`scenario`]: the rover scenario file (R1–R7, `scenarios/rover/`), which
//!   [`crate::exploration::protocol`] explores on every interleaving of the messages.

pub mod components;
pub mod controller;
pub mod delegation;
pub mod messages;
pub mod posandhead;
pub mod rover;
pub mod scenario;

pub use controller::{CoaController, Controller};
pub use delegation::{CoaDeclaration, Delegation, Delivered};
pub use scenario::{RoverScenario, is_rover_scenario};
