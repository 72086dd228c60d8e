//! The bounded-time mode (docs/embedding.md, "Timing"; `src/options.rs`): mode estimation stops
//! half the cycle deadline after the cycle starts, with the best belief found, and the step
//! says so.

mod support;

use kairos_ffi::*;
use support::{Device, Handle, cycle};

fn bounded(deadline_s: f64) -> KairosOptions {
    KairosOptions {
        cycle_deadline_s: deadline_s,
        bounded: 1,
        ..kairos_options_default()
    }
}

/// Runs the driver/valve loop for `cycles` cycles of 0.1 s: the commands sent and each step's
/// flags.
fn run(mut handle: Handle, cycles: u32) -> (Vec<String>, Vec<u32>) {
    let mut device = Device::default();
    let (mut sent, mut flags) = (Vec::new(), Vec::new());
    for n in 0..cycles {
        let (commands, summary) = cycle(&mut handle, &mut device, f64::from(n) * 0.1);
        sent.extend(commands);
        flags.push(summary.flags);
    }
    (sent, flags)
}

#[test]
fn the_bounded_mode_needs_a_deadline() {
    let Err((status, message)) = Handle::load(&bounded(0.0)) else {
        panic!("a bounded mode without a deadline was accepted");
    };
    assert_eq!(status, KairosStatus::InvalidArgument);
    assert!(message.contains("cycle deadline"), "{message}");
}

/// A deadline the cycles never come near changes nothing: the same commands as without one, no
/// search cut, no overrun.
#[test]
fn a_generous_deadline_changes_nothing() {
    let unbounded = run(Handle::driver_valve(), 8);
    let (sent, flags) = run(Handle::load(&bounded(10.0)).expect("loads"), 8);
    assert_eq!(sent, unbounded.0);
    assert_eq!(sent.len(), 3, "on, open, off: {sent:?}");
    assert!(
        flags
            .iter()
            .all(|f| f & (KAIROS_STEP_SEARCH_CUT | KAIROS_STEP_DEADLINE_OVERRUN) == 0),
        "{flags:?}"
    );
}

/// A deadline that has passed before estimation starts (1 ns: half of it is left for
/// estimation) stops every search before its first node: the call still returns, and says so —
/// the search cut in the first cycle, the overrun in every one. No plant state was found, so
/// the executive believes none and commands nothing: it never acts on a guess. (It stays so:
/// an executive whose belief is empty has no state to estimate from; docs/embedding.md,
/// "Timing", tells a deadline to be sized from `kairos bench`.)
#[test]
fn a_passed_deadline_cuts_the_search_and_says_so() {
    let (sent, flags) = run(Handle::load(&bounded(1e-9)).expect("loads"), 8);
    assert!(sent.is_empty(), "{sent:?}");
    assert_ne!(flags[0] & KAIROS_STEP_SEARCH_CUT, 0, "{flags:?}");
    assert!(
        flags.iter().all(|f| f & KAIROS_STEP_DEADLINE_OVERRUN != 0),
        "{flags:?}"
    );
}
