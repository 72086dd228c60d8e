//! A handle is one executive, usable from any thread one call at a time (DESIGN.md §10;
//! docs/embedding.md, "Threads"): a handle created on one thread runs its whole driver/valve
//! loop with every cycle on a thread of its own, and issues exactly the commands of the same
//! loop run on one thread; two handles run their loops on two threads at once without seeing
//! each other (no global state).

mod support;

use kairos_ffi::KAIROS_STEP_SETTLED;
use support::{Device, Handle, cycle};

/// Runs the loop until it settles (at most 50 cycles of 0.1 s), each cycle on a thread of its
/// own when `hop` is set; returns every command sent and whether the valve ended open.
fn run(mut handle: Handle, hop: bool) -> (Vec<String>, bool) {
    let mut device = Device::default();
    let mut sent = Vec::new();
    for n in 0..50 {
        let now = f64::from(n) * 0.1;
        let (commands, summary) = if hop {
            std::thread::scope(|s| {
                s.spawn(|| cycle(&mut handle, &mut device, now))
                    .join()
                    .expect("the cycle's thread ran")
            })
        } else {
            cycle(&mut handle, &mut device, now)
        };
        sent.extend(commands);
        if summary.flags & KAIROS_STEP_SETTLED != 0 {
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
