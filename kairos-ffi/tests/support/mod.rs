//! The driver/valve loop of `examples/c/embed.c`, through the C ABI, for the tests that run it
//! (`threads.rs`, `bounded.rs`).

use std::ffi::{CStr, CString};
use std::path::Path;

use kairos_ffi::*;

fn path(relative: &str) -> CString {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    CString::new(root.join(relative).display().to_string()).expect("no NUL in a path")
}

/// A handle as a C program hands it to another thread: a pointer, moved between calls.
pub struct Handle(pub *mut KairosExecutive);

// SAFETY: the contract of every `kairos_*` call is that one thread at a time uses a handle;
// the handle itself is `Send` (checked at compile time in `src/handle.rs`). These tests move it
// between calls and never call on it from two threads at once.
unsafe impl Send for Handle {}

impl Handle {
    /// The driver/valve plant running `programs/valve_open.rmpl`, with `options` (NULL for
    /// the defaults); the status and the error's message when it is refused.
    pub fn load(options: *const KairosOptions) -> Result<Handle, (KairosStatus, String)> {
        let mut handle = std::ptr::null_mut();
        let mut error = std::ptr::null_mut();
        // SAFETY: valid strings; `options` is NULL or valid (the caller's); `error` is written.
        let status = unsafe {
            kairos_executive_load(
                path("models/driver_valve.ron").as_ptr(),
                path("programs/valve_open.rmpl").as_ptr(),
                options,
                &mut handle,
                &mut error,
            )
        };
        if status == KairosStatus::Ok {
            return Ok(Handle(handle));
        }
        // SAFETY: a failed creating call sets `error` to an owned string, freed here.
        let message = unsafe {
            let message = CStr::from_ptr(error).to_string_lossy().into_owned();
            kairos_string_free(error);
            message
        };
        Err((status, message))
    }

    /// [`Handle::load`] with the default options.
    pub fn driver_valve() -> Handle {
        Handle::load(std::ptr::null()).expect("the shipped plant and program load")
    }
}

impl Drop for Handle {
    fn drop(&mut self) {
        // SAFETY: a live handle, not used after this.
        unsafe { kairos_executive_free(self.0) };
    }
}

/// The driver and valve of `examples/c/embed.c`: the driver relays commands once on, the valve
/// passes the flow when open.
#[derive(Default)]
pub struct Device {
    /// The driver is on.
    pub driver_on: bool,
    /// The valve is open.
    pub valve_open: bool,
}

/// One cycle of the loop: the device's sensors in, the commands out (applied to the device and
/// returned as `variable = value`), and the step's summary.
pub fn cycle(
    handle: &mut Handle,
    device: &mut Device,
    now: f64,
) -> (Vec<String>, KairosStepSummary) {
    let flow_out = CString::from(if device.valve_open {
        c"nominal"
    } else {
        c"zero"
    });
    let observed = [
        KairosObservation {
            variable: c"valve.flow_in".as_ptr(),
            kind: KAIROS_VALUE_SYMBOL,
            symbol: c"nominal".as_ptr(),
            number: 0.0,
        },
        KairosObservation {
            variable: c"valve.flow_out".as_ptr(),
            kind: KAIROS_VALUE_SYMBOL,
            symbol: flow_out.as_ptr(),
            number: 0.0,
        },
    ];
    let mut step = std::ptr::null_mut();
    // SAFETY: a live handle used by this thread alone during the call; two valid observations.
    let status = unsafe { kairos_step(handle.0, now, observed.as_ptr(), 2, &mut step) };
    assert_eq!(status, KairosStatus::Ok);
    // SAFETY: a live step, freed below and not used after.
    let summary = unsafe { kairos_step_summary(step) };
    let commands = (0..summary.command_count)
        .map(|i| {
            // SAFETY: a live step; the strings are valid until it is freed.
            let (variable, value) = unsafe {
                let command = kairos_step_command(step, i);
                (
                    CStr::from_ptr(command.variable),
                    CStr::from_ptr(command.value),
                )
            };
            let value = value.to_str().expect("UTF-8");
            match value {
                "on" => device.driver_on = true,
                "off" => device.driver_on = false,
                "open" if device.driver_on => device.valve_open = true,
                "close" if device.driver_on => device.valve_open = false,
                _ => {}
            }
            format!("{} = {value}", variable.to_str().expect("UTF-8"))
        })
        .collect();
    // SAFETY: a live step, not used after.
    unsafe { kairos_step_free(step) };
    (commands, summary)
}
