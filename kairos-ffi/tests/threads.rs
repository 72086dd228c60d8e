//! A handle is one executive, usable from any thread one call at a time (DESIGN.md §10;
//! docs/embedding.md, "Threads"): a handle created on one thread runs its whole driver/valve
//! loop with every cycle on a thread of its own, and issues exactly the commands of the same
//! loop run on one thread; two handles run their loops on two threads at once without seeing
//! each other (no global state).

use std::ffi::{CStr, CString};
use std::path::Path;

use kairos_ffi::*;

fn path(relative: &str) -> CString {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    CString::new(root.join(relative).display().to_string()).expect("no NUL in a path")
}

/// A handle as a C program hands it to another thread: a pointer, moved between calls.
struct Handle(*mut KairosExecutive);

// SAFETY: the contract of every `kairos_*` call is that one thread at a time uses a handle;
// the handle itself is `Send` (checked at compile time in `src/handle.rs`). These tests move it
// between calls and never call on it from two threads at once.
unsafe impl Send for Handle {}

impl Handle {
    fn driver_valve() -> Handle {
        let mut handle = std::ptr::null_mut();
        // SAFETY: valid strings; NULL options and error are allowed.
        let status = unsafe {
            kairos_executive_load(
                path("models/driver_valve.ron").as_ptr(),
                path("programs/valve_open.rmpl").as_ptr(),
                std::ptr::null(),
                &mut handle,
                std::ptr::null_mut(),
            )
        };
        assert_eq!(status, KairosStatus::Ok);
        Handle(handle)
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
struct Device {
    driver_on: bool,
    valve_open: bool,
}

/// One cycle of the loop: the device's sensors in, the commands out (applied to the device and
/// returned as `variable = value`), and whether the program has settled.
fn cycle(handle: &mut Handle, device: &mut Device, now: f64) -> (Vec<String>, bool) {
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
    (commands, summary.flags & KAIROS_STEP_SETTLED != 0)
}

/// Runs the loop until it settles (at most 50 cycles of 0.1 s), each cycle on a thread of its
/// own when `hop` is set; returns every command sent and whether the valve ended open.
fn run(mut handle: Handle, hop: bool) -> (Vec<String>, bool) {
    let mut device = Device::default();
    let mut sent = Vec::new();
    for n in 0..50 {
        let now = f64::from(n) * 0.1;
        let (commands, settled) = if hop {
            std::thread::scope(|s| {
                s.spawn(|| cycle(&mut handle, &mut device, now))
                    .join()
                    .expect("the cycle's thread ran")
            })
        } else {
            cycle(&mut handle, &mut device, now)
        };
        sent.extend(commands);
        if settled {
            break;
        }
    }
    (sent, device.valve_open)
}

#[test]
fn a_handle_is_stepped_from_a_new_thread_every_cycle() {
    let expected = (
        vec![
            "driver.dcmd_in = on".to_string(),
            "driver.dcmd_in = open".to_string(),
            "driver.dcmd_in = off".to_string(),
        ],
        true,
    );
    assert_eq!(run(Handle::driver_valve(), false), expected);
    assert_eq!(run(Handle::driver_valve(), true), expected);
}

#[test]
fn two_handles_run_on_two_threads_at_once() {
    let (first, second) = (Handle::driver_valve(), Handle::driver_valve());
    let (a, b) = std::thread::scope(|s| {
        let a = s.spawn(|| run(first, true));
        let b = s.spawn(|| run(second, false));
        (a.join().expect("ran"), b.join().expect("ran"))
    });
    assert_eq!(a, b);
    assert!(a.1, "the valve opened");
}
