//! Status codes, failures, and the guard every entry point runs its work in: a panic inside
//! kairos never unwinds into C (that would be undefined behaviour); it is caught and becomes
//! [`KairosStatus::Panic`] with the panic's message, and the handle it happened on refuses every
//! further call ([`KairosStatus::Poisoned`]) but `kairos_executive_free`, since its executive may
//! have been left half-way through a cycle.

use std::any::Any;
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call did. `KAIROS_STATUS_OK` is 0; every other value is an error, whose message
/// `kairos_executive_last_error` (or the `error` out-parameter of the calls that create a handle)
/// gives.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KairosStatus {
    /// Success.
    Ok = 0,
    /// A pointer that must not be NULL was NULL.
    NullArgument = 1,
    /// A string was not UTF-8.
    InvalidUtf8 = 2,
    /// An argument is out of its range: a kind tag that is no `KAIROS_VALUE_*` or
    /// `KAIROS_TLM_*`, an option that is not finite or not positive, a bool that is not 0 or 1.
    InvalidArgument = 3,
    /// A file or text did not load: a plant model, program, mission, F´ dictionary, binding or
    /// submission. The message has every problem, located (`file:line:col`).
    Load = 4,
    /// The executive could not be built from what loaded (the plant cannot be encoded).
    Build = 5,
    /// The time is not finite or not after the previous cycle's: the cycle did not run.
    Time = 6,
    /// Mode estimation or the sequencer refused the cycle's inputs: the cycle did not run.
    Step = 7,
    /// An observation is a number, and the plant model has no monitor for the observable
    /// (plant models declare no monitors yet): the cycle did not run.
    NoMonitor = 8,
    /// A telemetry id is no channel of the F´ dictionary: the cycle did not run.
    UnknownChannel = 9,
    /// A telemetry value is not of its channel's type: the cycle did not run.
    WrongType = 10,
    /// An F´ call on a handle that has no binding (`kairos_executive_bind_fprime` first).
    NotBound = 11,
    /// A submission was refused by the running mission (or the executive runs no mission); the
    /// running network is unchanged.
    Submit = 12,
    /// kairos panicked (a defect): the message says where. The handle is poisoned.
    Panic = 13,
    /// The handle panicked in an earlier call and refuses every call but its free.
    Poisoned = 14,
}

/// A failed call: its status and its message.
#[derive(Debug)]
pub(crate) struct Failure {
    pub(crate) status: KairosStatus,
    pub(crate) message: String,
}

impl Failure {
    pub(crate) fn new(status: KairosStatus, message: impl Into<String>) -> Self {
        Failure {
            status,
            message: message.into(),
        }
    }
}

/// Runs `work`, turning a panic into a [`KairosStatus::Panic`] failure.
pub(crate) fn guard<T>(work: impl FnOnce() -> Result<T, Failure>) -> Result<T, Failure> {
    // Unwind safety: after a panic the state `work` touched is never used again — a handle is
    // poisoned, everything else was local to the call.
    catch_unwind(AssertUnwindSafe(work)).unwrap_or_else(|payload| {
        Err(Failure::new(
            KairosStatus::Panic,
            format!(
                "kairos panicked (a defect; please report it): {}",
                panic_text(&*payload)
            ),
        ))
    })
}

fn panic_text(payload: &(dyn Any + Send)) -> &str {
    if let Some(text) = payload.downcast_ref::<&str>() {
        text
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text
    } else {
        "a panic without a message"
    }
}
