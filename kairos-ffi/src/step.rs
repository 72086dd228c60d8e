//! One cycle through the C ABI: observations in by name, a [`KairosStep`] out — the commands,
//! the events worded with names, the most likely state and the most likely plant states — which
//! the caller reads with the `kairos_step_*` accessors and frees with `kairos_step_free`.
//!
//! Bad data about the plant is what the executive reports as events and goes on (an unknown
//! name, a value outside the observable's domain: DESIGN.md §10, §13); what C got wrong about
//! the call itself is an error code and the cycle does not run, leaving the executive as it was:
//! a NULL where a string is needed, a string that is not UTF-8, a kind tag that is none of
//! `KAIROS_VALUE_*`, a number for an observable the model declares no monitor for, a time that
//! does not increase.
//!
//! A number for an observable with a monitor is a reading and goes to the executive as the Rust
//! API's does: the monitor turns it into the observable's value (thresholds, hysteresis,
//! persistence), and a reading that is not finite or is outside the monitor's valid range is an
//! `ObservationRejected` event, not an error. A number for a name the model does not know goes
//! to the executive too, which reports it as an event like an unknown symbolic observation.

use std::ffi::c_char;
use std::sync::Arc;

use kairos::executive::{EventKind, NamedValue, Step, StepError};
use kairos::logic::{ValueId, VarId};
use kairos::plant::Plant;

use crate::error::{Failure, KairosStatus};
use crate::events::{KairosEvent, KairosEventKind, StoredEvent};
use crate::fprime::{KairosFprimeCommand, StoredCommand};
use crate::handle::{KairosExecutive, with_handle};
use crate::names::{KairosNamedValue, Names};
use crate::raw::{self, c_string};

/// An observation's value is a symbol: `symbol` holds it.
pub const KAIROS_VALUE_SYMBOL: u32 = 0;
/// An observation's value is a number: `number` holds it, a reading for the observable's monitor
/// (refused with `KAIROS_STATUS_NO_MONITOR` when the model declares no monitor for it).
pub const KAIROS_VALUE_NUMBER: u32 = 1;

/// The program has completed.
pub const KAIROS_STEP_COMPLETED: u32 = 1;
/// The program has completed and nothing is left to command: a loop may stop.
pub const KAIROS_STEP_SETTLED: u32 = 1 << 1;
/// A budget cut mode estimation short: the belief is the best found in the time allowed.
pub const KAIROS_STEP_SEARCH_CUT: u32 = 1 << 2;
/// The cycle took longer than its deadline (`elapsed_s` says how long).
pub const KAIROS_STEP_DEADLINE_OVERRUN: u32 = 1 << 3;
/// Some observations were rejected (events say which and why).
pub const KAIROS_STEP_OBSERVATIONS_REJECTED: u32 = 1 << 4;

/// One observation: `variable = symbol` (kind `KAIROS_VALUE_SYMBOL`) or `variable = number`
/// (kind `KAIROS_VALUE_NUMBER`).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KairosObservation {
    /// The observable's name (`valve.flow_out`).
    pub variable: *const c_char,
    /// `KAIROS_VALUE_SYMBOL` or `KAIROS_VALUE_NUMBER`.
    pub kind: u32,
    /// The value's name, for a symbol (NULL otherwise).
    pub symbol: *const c_char,
    /// The value, for a number.
    pub number: f64,
}

/// What a step is, in numbers: read it first, then the items by index.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct KairosStepSummary {
    /// The cycle's number, from 0.
    pub cycle: u64,
    /// Its time, seconds.
    pub time: f64,
    /// The wall time it took, seconds.
    pub elapsed_s: f64,
    /// `KAIROS_STEP_*` flags.
    pub flags: u32,
    /// How many commands to send (`kairos_step_command`); 0 is idle.
    pub command_count: usize,
    /// How many events (`kairos_step_event`).
    pub event_count: usize,
    /// How many components the plant has (`kairos_step_mode`, `kairos_step_estimate_mode`).
    pub component_count: usize,
    /// How many plant states are named (`kairos_step_estimate_*`), most likely first.
    pub estimate_count: usize,
    /// How many F´ commands to send (`kairos_step_fprime_command`), with a binding.
    pub fprime_command_count: usize,
}

/// What one cycle produced; opaque to C. It owns everything its accessors return, and stays
/// valid (also after its handle is freed) until `kairos_step_free`.
pub struct KairosStep {
    names: Arc<Names>,
    summary: KairosStepSummary,
    commands: Vec<(VarId, ValueId)>,
    modes: Vec<ValueId>,
    estimates: Vec<(f64, Vec<ValueId>)>,
    events: Vec<StoredEvent>,
    pub(crate) fprime: Vec<StoredCommand>,
}

impl KairosStep {
    fn new(handle: &KairosExecutive, step: &Step) -> Result<KairosStep, Failure> {
        let mut flags = 0;
        for event in &step.events {
            flags |= match event.kind {
                EventKind::SearchCut(_) => KAIROS_STEP_SEARCH_CUT,
                EventKind::DeadlineOverrun { .. } => KAIROS_STEP_DEADLINE_OVERRUN,
                EventKind::ObservationRejected { .. } => KAIROS_STEP_OBSERVATIONS_REJECTED,
                _ => 0,
            };
        }
        if step.completed {
            flags |= KAIROS_STEP_COMPLETED;
        }
        if step.is_settled() {
            flags |= KAIROS_STEP_SETTLED;
        }
        let events: Vec<StoredEvent> = (step.events.iter())
            .map(|event| StoredEvent {
                kind: KairosEventKind::of(&event.kind),
                line: c_string(&event.named(&handle.executive).to_string()),
            })
            .collect();
        let estimates: Vec<(f64, Vec<ValueId>)> = (step.estimates.iter().take(handle.estimates))
            .map(|e| (e.probability, e.modes.to_vec()))
            .collect();
        let fprime = match &handle.binding {
            Some(binding) => {
                StoredCommand::all(binding, &step.commands_named(handle.executive.plant()))?
            }
            None => Vec::new(),
        };
        Ok(KairosStep {
            summary: KairosStepSummary {
                cycle: step.cycle,
                time: step.time,
                elapsed_s: step.times.total.as_secs_f64(),
                flags,
                command_count: step.command.len(),
                event_count: events.len(),
                component_count: handle.names.components(),
                estimate_count: estimates.len(),
                fprime_command_count: fprime.len(),
            },
            names: Arc::clone(&handle.names),
            commands: step.command.clone(),
            modes: step.most_likely.to_vec(),
            estimates,
            events,
            fprime,
        })
    }
}

/// Runs one cycle of `handle` at `now` with the observations `observe` reads for it (from what
/// C passed), writing the step to `*out`: the entry points' common part. `*out` is NULL unless
/// the cycle ran; a failure reading the observations is the call's status and the cycle does not
/// run.
///
/// # Safety
/// `handle` is NULL or a live handle used by no other thread during the call; `out` is NULL or
/// valid for a write.
pub(crate) unsafe fn step_with(
    handle: *mut KairosExecutive,
    now: f64,
    out: *mut *mut KairosStep,
    observe: impl FnOnce(&KairosExecutive) -> Result<Vec<NamedValue>, Failure>,
) -> KairosStatus {
    if out.is_null() {
        return KairosStatus::NullArgument;
    }
    // SAFETY: `out` is not NULL and valid for a write (the contract).
    unsafe { out.write(std::ptr::null_mut()) };
    let work = |handle: &mut KairosExecutive| {
        let observed = observe(handle)?;
        let step = handle.executive.step(now, &observed).map_err(|e| match e {
            StepError::TimeNotAfter { .. } => Failure::new(KairosStatus::Time, e.to_string()),
            e => Failure::new(KairosStatus::Step, e.to_string()),
        })?;
        let step = KairosStep::new(handle, &step)?;
        // SAFETY: `out` is not NULL (checked above) and valid for a write (the contract).
        unsafe { out.write(Box::into_raw(Box::new(step))) };
        Ok(())
    };
    // SAFETY: `handle`'s contract is the caller's.
    unsafe { with_handle(handle, work) }
}

/// The observations as the executive takes them.
///
/// # Safety
/// Each observation's strings are NULL or NUL-terminated strings valid for the call.
unsafe fn named(
    plant: &Plant,
    observations: &[KairosObservation],
) -> Result<Vec<NamedValue>, Failure> {
    let mut named = Vec::with_capacity(observations.len());
    for (i, observation) in observations.iter().enumerate() {
        // SAFETY: the caller's contract.
        let variable =
            unsafe { raw::text(observation.variable, &format!("observation {i}'s variable"))? };
        match observation.kind {
            KAIROS_VALUE_SYMBOL => {
                // SAFETY: the caller's contract.
                let symbol =
                    unsafe { raw::text(observation.symbol, &format!("observation {i}'s symbol"))? };
                named.push(NamedValue::new(variable, symbol));
            }
            KAIROS_VALUE_NUMBER => {
                let unmonitored = plant.table().variable_id(variable).is_some_and(|var| {
                    plant.observables().contains(&var) && plant.monitor_of(var).is_none()
                });
                if unmonitored {
                    return Err(Failure::new(
                        KairosStatus::NoMonitor,
                        format!(
                            "observation {i} gives `{variable}` the number {}: the model declares no \
                             monitor for this observable (report its symbolic value)",
                            observation.number
                        ),
                    ));
                }
                named.push(NamedValue::new(variable, observation.number));
            }
            kind => {
                return Err(Failure::new(
                    KairosStatus::InvalidArgument,
                    format!(
                        "observation {i}'s kind is {kind}: KAIROS_VALUE_SYMBOL (0) or KAIROS_VALUE_NUMBER (1) is expected"
                    ),
                ));
            }
        }
    }
    Ok(named)
}

/// Runs one cycle at time `now` (seconds, finite, after the previous cycle's) with `count`
/// observations (`observations` may be NULL when `count` is 0). On success `*out` is the step
/// (free it with `kairos_step_free`); on failure `*out` is NULL, the cycle did not run, and
/// `kairos_executive_last_error` says why.
///
/// # Safety
/// `handle` is NULL or a live handle used by no other thread during the call; `observations`
/// points to `count` observations whose strings are NUL-terminated (or is NULL with `count` 0);
/// `out` is valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step(
    handle: *mut KairosExecutive,
    now: f64,
    observations: *const KairosObservation,
    count: usize,
    out: *mut *mut KairosStep,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        step_with(handle, now, out, |handle| {
            let observations = raw::slice(observations, count, "observations")?;
            named(handle.executive.plant(), observations)
        })
    }
}

/// Frees a step (NULL is ignored).
///
/// # Safety
/// `step` is NULL or a step from `kairos_step` / `kairos_fprime_step` not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_free(step: *mut KairosStep) {
    // SAFETY: NULL or made by `Box::into_raw` in `step_with`, given up by the caller.
    unsafe { raw::free(step) }
}

/// Borrows the step behind `step`.
///
/// # Safety
/// `step` is NULL or a live step.
pub(crate) unsafe fn borrow<'a>(step: *const KairosStep) -> Option<&'a KairosStep> {
    // SAFETY: NULL or a live step, by the caller's contract.
    unsafe { step.as_ref() }
}

/// The step's numbers (all zero for NULL).
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_summary(step: *const KairosStep) -> KairosStepSummary {
    // SAFETY: the caller's contract.
    unsafe { borrow(step) }
        .map(|s| s.summary)
        .unwrap_or_default()
}

/// Command `index` (`PDE.cmd = on`), to send this cycle.
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_command(
    step: *const KairosStep,
    index: usize,
) -> KairosNamedValue {
    // SAFETY: the caller's contract.
    let Some(step) = (unsafe { borrow(step) }) else {
        return KairosNamedValue::NONE;
    };
    (step.commands.get(index)).map_or(KairosNamedValue::NONE, |&a| step.names.assignment(a))
}

/// The most likely mode of component `component` (`valve = open`).
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_mode(
    step: *const KairosStep,
    component: usize,
) -> KairosNamedValue {
    // SAFETY: the caller's contract.
    let Some(step) = (unsafe { borrow(step) }) else {
        return KairosNamedValue::NONE;
    };
    (step.modes.get(component)).map_or(KairosNamedValue::NONE, |&m| step.names.mode(component, m))
}

/// The probability of the `index`-th most likely plant state (NaN out of range).
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_estimate_probability(
    step: *const KairosStep,
    index: usize,
) -> f64 {
    // SAFETY: the caller's contract.
    let estimate = unsafe { borrow(step) }.and_then(|s| s.estimates.get(index));
    estimate.map_or(f64::NAN, |e| e.0)
}

/// The mode of component `component` in the `index`-th most likely plant state.
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_estimate_mode(
    step: *const KairosStep,
    index: usize,
    component: usize,
) -> KairosNamedValue {
    // SAFETY: the caller's contract.
    let Some(step) = (unsafe { borrow(step) }) else {
        return KairosNamedValue::NONE;
    };
    let mode = step.estimates.get(index).and_then(|e| e.1.get(component));
    mode.map_or(KairosNamedValue::NONE, |&m| step.names.mode(component, m))
}

/// Event `index`: its kind and its line with names.
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_event(step: *const KairosStep, index: usize) -> KairosEvent {
    // SAFETY: the caller's contract.
    let event = unsafe { borrow(step) }.and_then(|s| s.events.get(index));
    event.map_or(StoredEvent::NONE, StoredEvent::view)
}

/// F´ command `index` of the step (with a binding): its opcode, name and arguments.
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_fprime_command(
    step: *const KairosStep,
    index: usize,
) -> KairosFprimeCommand {
    // SAFETY: the caller's contract.
    let command = unsafe { borrow(step) }.and_then(|s| s.fprime.get(index));
    command.map_or(KairosFprimeCommand::NONE, StoredCommand::view)
}
