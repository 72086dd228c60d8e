//! The F´ face of a handle: bind it to a deployment's dictionary and a binding file
//! (`kairos::executive::fprime`), then step it with telemetry as `(channel id, value)` and read
//! its commands as `(opcode, arguments)`. The binding is checked against the handle's own plant
//! when it is attached, so every command a step issues has its F´ command.

use std::ffi::{CString, c_char};
use std::path::Path;

use kairos::diagnostic::Source;
use kairos::executive::NamedValue;
use kairos::executive::fprime::{Binding, Dictionary, FprimeArg, TelemetryError, TelemetryValue};

use crate::error::{Failure, KairosStatus};
use crate::handle::{KairosExecutive, with_handle};
use crate::raw::{self, c_string};
use crate::step::{KairosStep, step_with};

/// A telemetry value of an enumeration channel: `integer` holds the constant's value.
pub const KAIROS_TLM_ENUM: u32 = 0;
/// A telemetry value of a `bool` channel: `integer` holds 0 or 1.
pub const KAIROS_TLM_BOOL: u32 = 1;
/// A telemetry value of an integer channel: `integer` holds it.
pub const KAIROS_TLM_INTEGER: u32 = 2;
/// A telemetry value of a float channel: `real` holds it.
pub const KAIROS_TLM_FLOAT: u32 = 3;

/// One telemetry value: channel `channel` (its id in the dictionary) reads the value `kind`
/// says where to find.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KairosTelemetry {
    /// The channel's id.
    pub channel: u32,
    /// `KAIROS_TLM_ENUM`, `KAIROS_TLM_BOOL`, `KAIROS_TLM_INTEGER` or `KAIROS_TLM_FLOAT`.
    pub kind: u32,
    /// The value for the enumeration, bool and integer kinds.
    pub integer: i64,
    /// The value for the float kind.
    pub real: f64,
}

/// The type of an F´ command argument.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KairosArgKind {
    /// No argument (an index out of range).
    None = 0,
    /// An integer, in `integer`.
    Int = 1,
    /// A float, in `real`.
    Float = 2,
    /// A bool, in `integer` (0 or 1).
    Bool = 3,
    /// An enumeration constant: its value in `integer`, its name in `text`.
    Enum = 4,
    /// A string, in `text`.
    String = 5,
}

/// One argument of an F´ command; `text` is owned by the step.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KairosFprimeArg {
    /// Which field holds the value.
    pub kind: KairosArgKind,
    /// Integer, bool and enumeration values.
    pub integer: i64,
    /// Float values.
    pub real: f64,
    /// Enumeration constants' names and strings; NULL otherwise.
    pub text: *const c_char,
}

/// One F´ command of a step: `name` is owned by the step; NULL (opcode 0) for an index out of
/// range. Its arguments are read with `kairos_step_fprime_arg`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KairosFprimeCommand {
    /// The opcode.
    pub opcode: u32,
    /// The command's qualified name (`Prop.prop.VALVE_OPEN`).
    pub name: *const c_char,
    /// How many arguments it has.
    pub arg_count: usize,
}

impl KairosFprimeCommand {
    pub(crate) const NONE: KairosFprimeCommand = KairosFprimeCommand {
        opcode: 0,
        name: std::ptr::null(),
        arg_count: 0,
    };
}

/// What an argument index out of range reads as.
const NO_ARG: KairosFprimeArg = KairosFprimeArg {
    kind: KairosArgKind::None,
    integer: 0,
    real: 0.0,
    text: std::ptr::null(),
};

/// An F´ command kept by a step.
pub(crate) struct StoredCommand {
    opcode: u32,
    name: CString,
    args: Vec<(KairosArgKind, i64, f64, Option<CString>)>,
}

impl StoredCommand {
    /// The F´ commands of a step's commands.
    pub(crate) fn all(
        binding: &Binding,
        commands: &[NamedValue],
    ) -> Result<Vec<StoredCommand>, Failure> {
        commands
            .iter()
            .map(|command| {
                let Some(bound) = binding.command(command) else {
                    // A binding is checked against the handle's plant when attached, and binds
                    // every non-idle control value: this is a defect, said as such.
                    return Err(Failure::new(
                        KairosStatus::NotBound,
                        format!("the binding has no F´ command for `{command}` (a defect: it was checked)"),
                    ));
                };
                Ok(StoredCommand {
                    opcode: bound.opcode,
                    name: c_string(&bound.command),
                    args: bound.args.iter().map(stored_arg).collect(),
                })
            })
            .collect()
    }

    pub(crate) fn view(&self) -> KairosFprimeCommand {
        KairosFprimeCommand {
            opcode: self.opcode,
            name: self.name.as_ptr(),
            arg_count: self.args.len(),
        }
    }

    fn arg(&self, index: usize) -> KairosFprimeArg {
        match self.args.get(index) {
            Some((kind, integer, real, text)) => KairosFprimeArg {
                kind: *kind,
                integer: *integer,
                real: *real,
                text: text.as_ref().map_or(std::ptr::null(), |t| t.as_ptr()),
            },
            None => NO_ARG,
        }
    }
}

fn stored_arg(arg: &FprimeArg) -> (KairosArgKind, i64, f64, Option<CString>) {
    match arg {
        FprimeArg::Int(n) => (KairosArgKind::Int, *n, 0.0, None),
        FprimeArg::Float(x) => (KairosArgKind::Float, 0, *x, None),
        FprimeArg::Bool(b) => (KairosArgKind::Bool, i64::from(*b), 0.0, None),
        FprimeArg::Enum { constant, value } => {
            (KairosArgKind::Enum, *value, 0.0, Some(c_string(constant)))
        }
        FprimeArg::Str(s) => (KairosArgKind::String, 0, 0.0, Some(c_string(s))),
    }
}

fn attach(
    handle: &mut KairosExecutive,
    dictionary: &Source,
    binding: &Source,
) -> Result<(), Failure> {
    let load =
        |e: kairos::diagnostic::SourceErrors| Failure::new(KairosStatus::Load, e.to_string());
    let dictionary = Dictionary::load(dictionary).map_err(load)?;
    let binding = Binding::load(binding, &dictionary, handle.executive.plant()).map_err(load)?;
    handle.binding = Some(binding);
    Ok(())
}

fn read(path: &str) -> Result<Source, Failure> {
    Source::read(Path::new(path)).map_err(|e| Failure::new(KairosStatus::Load, e.to_string()))
}

/// Binds the handle to an F´ deployment: its JSON dictionary (what `fpp-to-dict` writes) and a
/// binding file (docs/embedding.md), checked against the handle's plant. `KAIROS_STATUS_LOAD`
/// with every problem located when either does not load or check; the handle keeps its earlier
/// binding then.
///
/// # Safety
/// `handle` is NULL or a live handle used by no other thread during the call; the paths are
/// NUL-terminated strings.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_bind_fprime(
    handle: *mut KairosExecutive,
    dictionary_path: *const c_char,
    binding_path: *const c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        with_handle(handle, |handle| {
            let dictionary = read(raw::text(dictionary_path, "dictionary_path")?)?;
            let binding = read(raw::text(binding_path, "binding_path")?)?;
            attach(handle, &dictionary, &binding)
        })
    }
}

/// [`kairos_executive_bind_fprime`] from texts in memory; each name is what error locations show.
///
/// # Safety
/// As [`kairos_executive_bind_fprime`], every string NUL-terminated.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_executive_bind_fprime_text(
    handle: *mut KairosExecutive,
    dictionary_name: *const c_char,
    dictionary_text: *const c_char,
    binding_name: *const c_char,
    binding_text: *const c_char,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        with_handle(handle, |handle| {
            let dictionary = raw::source(dictionary_name, dictionary_text, "dictionary")?;
            let binding = raw::source(binding_name, binding_text, "binding")?;
            attach(handle, &dictionary, &binding)
        })
    }
}

/// The observations `telemetry` stands for through `binding`.
fn observations(
    binding: &Binding,
    telemetry: &[KairosTelemetry],
) -> Result<Vec<NamedValue>, Failure> {
    let mut named = Vec::with_capacity(telemetry.len());
    for (i, item) in telemetry.iter().enumerate() {
        let value = match item.kind {
            KAIROS_TLM_ENUM => TelemetryValue::Enum(item.integer),
            KAIROS_TLM_BOOL if item.integer == 0 || item.integer == 1 => {
                TelemetryValue::Bool(item.integer == 1)
            }
            KAIROS_TLM_BOOL => {
                return Err(Failure::new(
                    KairosStatus::InvalidArgument,
                    format!(
                        "telemetry {i} is a bool of value {}: 0 or 1 is expected",
                        item.integer
                    ),
                ));
            }
            KAIROS_TLM_INTEGER => TelemetryValue::Integer(item.integer),
            KAIROS_TLM_FLOAT => TelemetryValue::Float(item.real),
            kind => {
                return Err(Failure::new(
                    KairosStatus::InvalidArgument,
                    format!(
                        "telemetry {i}'s kind is {kind}: one of KAIROS_TLM_ENUM (0), _BOOL (1), _INTEGER (2), _FLOAT (3) is expected"
                    ),
                ));
            }
        };
        match binding.observe(item.channel, value) {
            Ok(Some(observation)) => named.push(observation),
            Ok(None) => {}
            Err(e @ TelemetryError::UnknownChannel(_)) => {
                return Err(Failure::new(
                    KairosStatus::UnknownChannel,
                    format!("telemetry {i}: {e}"),
                ));
            }
            Err(e @ TelemetryError::WrongType { .. }) => {
                return Err(Failure::new(
                    KairosStatus::WrongType,
                    format!("telemetry {i}: {e}"),
                ));
            }
        }
    }
    Ok(named)
}

/// Runs one cycle at time `now` with `count` telemetry values through the handle's F´ binding
/// (`telemetry` may be NULL when `count` is 0). Channels of the dictionary that are not bound are
/// ignored; an id that is no channel, or a value of the wrong type, is an error and the cycle
/// does not run. Outputs as `kairos_step`; the step's F´ commands are read with
/// `kairos_step_fprime_command`.
///
/// # Safety
/// `handle` is NULL or a live handle used by no other thread during the call; `telemetry` points
/// to `count` values (or is NULL with `count` 0); `out` is valid for a write.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_fprime_step(
    handle: *mut KairosExecutive,
    now: f64,
    telemetry: *const KairosTelemetry,
    count: usize,
    out: *mut *mut KairosStep,
) -> KairosStatus {
    // SAFETY: the pointers' contract is the caller's (this function's `# Safety`).
    unsafe {
        step_with(handle, now, out, |handle| {
            let telemetry = raw::slice(telemetry, count, "telemetry")?;
            let Some(binding) = &handle.binding else {
                return Err(Failure::new(
                    KairosStatus::NotBound,
                    "the handle has no F´ binding: call kairos_executive_bind_fprime first",
                ));
            };
            observations(binding, telemetry)
        })
    }
}

/// Argument `arg` of F´ command `index` of the step (kind `KAIROS_ARG_KIND_NONE` out of range).
///
/// # Safety
/// `step` is NULL or a live step.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn kairos_step_fprime_arg(
    step: *const KairosStep,
    index: usize,
    arg: usize,
) -> KairosFprimeArg {
    // SAFETY: the caller's contract.
    let command = unsafe { crate::step::borrow(step) }.and_then(|s| s.fprime.get(index));
    command.map_or(NO_ARG, |command| command.arg(arg))
}
