//! Binding the executive to an F´ (F Prime) deployment: its JSON dictionary (what `fpp-to-dict`
//! writes) names telemetry channels and commands by id and opcode; a binding file maps channels
//! to the plant's observables and the plant's control values to commands with arguments. An
//! embedder — the C ABI of `kairos-ffi`, an F´ component's rate-group handler — then hands the
//! executive telemetry as `(channel id, value)` ([`Binding::observe`]) and sends its commands as
//! `(opcode, arguments)` ([`Binding::command`]).
//!
//! The binding sits at the executive's boundary, beside [`NamedValue`](super::NamedValue): it
//! translates names and nothing else, so a cycle driven through it decides exactly what the same
//! cycle driven by name decides.
//!
//! A numeric channel binds only to an observable the plant model declares a *monitor* for:
//! turning a number into an observable's value is the monitor's job (thresholds, hysteresis,
//! persistence, staleness), and [`Binding::observe`] hands the number to it as a reading. A
//! binding that maps a numeric channel to an unmonitored observable is refused, located.

pub mod binding;
pub mod dictionary;
mod suggest;

pub use binding::{Binding, BoundChannel, BoundCommand, FprimeArg, TelemetryError, TelemetryValue};
pub use dictionary::{Channel, Command, Dictionary, FprimeType};
pub use suggest::suggest;
