//! The handle: one executive, its names, its F´ binding, and the message of its last error.
//!
//! A handle is used by one thread at a time: every call that takes it reads or changes the
//! executive, and nothing in it is shared with another handle (no global state), so two
//! handles run on two threads without any coordination. Moving a handle to another thread
//! between calls is sound because everything in it is `Send` (the executive, its names, its
//! binding); the assertion at the end of this file checks that at compile time, and
//! `tests/threads.rs` steps a handle from a thread other than the one that made it.

use std::ffi::{CString, c_char};
use std::path::Path;
use std::sync::Arc;

use kairos::diagnostic::Source;
use kairos::executive::fprime::Binding;
use kairos::executive::{Executive, ExecutiveBuilder};

use crate::error::{Failure, KairosStatus, guard};
use crate::names::Names;
use crate::options::KairosOptions;
use crate::raw::{self, c_string};

/// An executive and what the C ABI keeps beside it. Opaque to C.
pub struct KairosExecutive {
    pub(crate) executive: Executive,
    pub(crate) names: Arc<Names>,
    pub(crate) binding: Option<Binding>,
    /// How many plant states a step names.
    pub(crate) estimates: usize,
    /// The last error's message (empty after a success).
    error: CString,
    /// Set when a call panicked: the executive may be half-way through a cycle.
    poisoned: bool,
}

impl KairosExecutive {
    fn new(builder: ExecutiveBuilder, options: &KairosOptions) -> Result<KairosExecutive, Failure> {
        let executive = (options.apply(builder)?)
            .build()
            .map_err(|e| Failure::new(KairosStatus::Build, format!("error: {e}")))?;
        Ok(KairosExecutive {
            names: Arc::new(Names::new(executive.plant())),
            executive,
            binding: None,
            estimates: options.estimates as usize,
            error: CString::default(),
            poisoned: false,
        })
    }
}

/// Runs `work` on the handle behind `handle`: NULL, a poisoned handle and a failure become a
/// status, the failure's message the handle's last error; a panic poisons the handle.
///
/// # Safety
/// `handle` is NULL or a live handle from `kairos_executive_*`, not used by another thread during
/// the call.
pub(crate) unsafe fn with_handle(
    handle: *mut KairosExecutive,
    work: impl FnOnce(&mut KairosExecutive) -> Result<(), Failure>,
) -> KairosStatus {
    // SAFETY: NULL or a live, exclusively used handle, by the caller's contract.
    let Some(handle) = (unsafe { handle.as_mut() }) else {
        return KairosStatus::NullArgument;
    };
    if handle.poisoned {
        handle.error = c_string("this handle panicked in an earlier call; free it");
        return KairosStatus::Poisoned;
    }
    match guard(|| work(&mut *handle)) {
        Ok(()) => {
            handle.error = CString::default();
            KairosStatus::Ok
        }
        Err(failure) => {
            handle.poisoned = failure.status == KairosStatus::Panic;
            handle.error = c_string(&failure.message);
            failure.status
        }
    }
}

/// Creates a handle from the executive `builder` makes and the options at `options` (NULL for
/// the defaults), writing it to `out` and any error's message to `error`.
///
/// # Safety
/// `options` is NULL or points to a valid `KairosOptions`; `out` is valid for a write; `error`
/// is NULL or valid for a write.
unsafe fn create(
    options: *const KairosOptions,
    out: *mut *mut KairosExecutive,
    error: *mut *mut c_char,
    builder: impl FnOnce() -> Result<ExecutiveBuilder, Failure>,
) -> KairosStatus {
    // SAFETY: `error` is NULL or valid for a write (the caller's contract).
    unsafe { raw::write(error, std::ptr::null_mut()) };
    if out.is_null() {
        return KairosStatus::NullArgument;
    }
    // SAFETY: NULL or a valid `KairosOptions` (the contract).
    let options = unsafe { options.as_ref() }.copied().unwrap_or_default();
    match guard(|| KairosExecutive::new(builder()?, &options)) {
        Ok(handle) => {
            // SAFETY: `out` is not NULL (checked above) and valid for a write.
            unsafe { out.write(Box::into_raw(Box::new(handle))) };
            KairosStatus::Ok
        }
        Err(failure) => {
            // SAFETY: as above.
            unsafe {
                out.write(std::ptr::null_mut());
                raw::write(error, c_string(&failure.message).into_raw());
            }
            failure.status
        }
    }
}

fn loaded<T>(result: Result<T, kairos::executive::LoadError>) -> Result<T, Failure> {
    result.map_err(|e| Failure::new(KairosStatus::Load, e.to_string()))
}

/// The default options: κ = 10, no deadline, no budget, 3 estimates named per step.
#[unsafe(no_mangle)]
pub extern "C" fn kairos_options_default() -> KairosOptions {
    KairosOptions::default()
}

/// Creates an executive from a plant model file and an RMPL program file (its first program is
/// the entry). On success `*out` is the handle (free it with `kairos_executive_free`); on
/// failure `*out` is NULL and, when `error` is not NULL, `*error` is the message (every problem,
/// located; free it with `kairos_string_free`). `options` may be NULL for the defaults.
///
/// # Safety
/// The paths are NUL-terminated strings; `options` is NULL or valid; `out` is valid for a write;
/// `error` is NULL or valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_load(
    plant_path: *const c_char,
    program_path: *const c_char,
    options: *const KairosOptions,
    out: *mut *mut KairosExecutive,
    error: *mut *mut c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        create(options, out, error, || {
            let plant = raw::text(plant_path, "plant_path")?;
            let program = raw::text(program_path, "program_path")?;
            loaded(Executive::load(Path::new(plant), Path::new(program)))
        })
    }
}

/// [`kairos_executive_load`] from texts in memory; each name is what error locations show.
///
/// # Safety
/// As [`kairos_executive_load`], every string NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_load_text(
    plant_name: *const c_char,
    plant_text: *const c_char,
    program_name: *const c_char,
    program_text: *const c_char,
    options: *const KairosOptions,
    out: *mut *mut KairosExecutive,
    error: *mut *mut c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        create(options, out, error, || {
            let plant = raw::source(plant_name, plant_text, "plant")?;
            let program = raw::source(program_name, program_text, "program")?;
            loaded(Executive::load_source(plant, program))
        })
    }
}

/// Creates an executive running a mission (a goal network) from its file; the plant model it
/// names is read relative to the mission's directory. Outputs as [`kairos_executive_load`].
///
/// # Safety
/// As [`kairos_executive_load`].
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_load_mission(
    mission_path: *const c_char,
    options: *const KairosOptions,
    out: *mut *mut KairosExecutive,
    error: *mut *mut c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        create(options, out, error, || {
            let mission = raw::text(mission_path, "mission_path")?;
            loaded(Executive::load_mission(Path::new(mission)))
        })
    }
}

/// [`kairos_executive_load_mission`] from the mission's text in memory; the plant model it names
/// is read relative to `directory`.
///
/// # Safety
/// As [`kairos_executive_load`], every string NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_load_mission_text(
    mission_name: *const c_char,
    mission_text: *const c_char,
    directory: *const c_char,
    options: *const KairosOptions,
    out: *mut *mut KairosExecutive,
    error: *mut *mut c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        create(options, out, error, || {
            let mission = raw::source(mission_name, mission_text, "mission")?;
            let directory = raw::text(directory, "directory")?;
            loaded(Executive::load_mission_source(
                &mission,
                Path::new(directory),
            ))
        })
    }
}

/// Frees a handle (NULL is ignored). Steps it returned stay valid until freed themselves.
///
/// # Safety
/// `handle` is NULL or a live handle, not used again after this call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_free(handle: *mut KairosExecutive) {
    // SAFETY: NULL or a live handle made by `Box::into_raw` in `create`, given up by the caller.
    unsafe { raw::free(handle) }
}

/// The message of the handle's last failed call ("" after a success), owned by the handle:
/// valid until the next call on it. NULL for a NULL handle.
///
/// # Safety
/// `handle` is NULL or a live handle, not used by another thread during the call.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_last_error(
    handle: *const KairosExecutive,
) -> *const c_char {
    // SAFETY: NULL or a live handle, by the caller's contract.
    match unsafe { handle.as_ref() } {
        Some(handle) => handle.error.as_ptr(),
        None => std::ptr::null(),
    }
}

/// Submits goals to the running mission: `network` is a `Network(points: [...], constraints:
/// [...], goals: [...])` written as in a mission file (its goals may name the mission's points).
/// It is made at the last cycle's time (0 before the first): its new points fire no earlier.
/// `KAIROS_STATUS_LOAD` when it does not read or resolve (the message locates every problem),
/// `KAIROS_STATUS_SUBMIT` when the mission refuses it (the running network is unchanged) or the
/// executive runs an RMPL program.
///
/// # Safety
/// `handle` is NULL or a live handle used by no other thread during the call; `network` is a
/// NUL-terminated string.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_submit(
    handle: *mut KairosExecutive,
    network: *const c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        with_handle(handle, |handle| {
            let text = raw::text(network, "network")?;
            let Some(mission) = handle.executive.control().mission() else {
                return Err(Failure::new(
                    KairosStatus::Submit,
                    "the executive runs an RMPL program: goals are submitted to a mission",
                ));
            };
            let submission = kairos::goalnet::mission::parse_submission(
                &Source::new("submission", text),
                mission,
            )
            .map_err(|e| Failure::new(KairosStatus::Load, e.to_string()))?;
            let now = handle.executive.last_time().unwrap_or(0.0);
            (handle.executive.submit(&submission, now)).map_err(|e| {
                Failure::new(
                    KairosStatus::Submit,
                    format!("the submission was refused: {e}"),
                )
            })
        })
    }
}

/// Frees a string kairos returned as owned (an `error` out-parameter). NULL is ignored.
///
/// # Safety
/// `string` is NULL or a string from kairos not freed before.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_string_free(string: *mut c_char) {
    if !string.is_null() {
        // SAFETY: made by `CString::into_raw` in this crate, given up by the caller.
        drop(unsafe { CString::from_raw(string) });
    }
}

const fn assert_send<T: Send>() {}
const fn assert_sync<T: Sync>() {}

// A step is a value of its own (names by `Arc`, strings it owns): it may be read from any thread.
const _: () = {
    assert_send::<crate::step::KairosStep>();
    assert_sync::<crate::step::KairosStep>();
};

// A handle may move between threads between calls (one call at a time): it is `Send`.
const _: () = assert_send::<KairosExecutive>();
