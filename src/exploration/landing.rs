//! Where a timed response with an interval may land ("timed plant responses
//! may land anywhere in a declared interval (discretised to the cycle)").

use crate::simulation::{OpenLanding, Scenario};

/// Two times closer than this are the same instant (as in the scripted plant).
const TIME_EPSILON: f64 = 1e-6;

/// The cycles an open landing may land at, earliest first: from the first the effect may show
/// at (`next`, the next cycle to run, or later), those whose time lies in [fired + from,
/// fired + to]; the first at or after fired + from when none does (the run's choice, always
/// first); and at most one past the scenario's end, which stands for every later one (the run
/// is over before any of them).
pub(super) fn cycles(scenario: &Scenario, open: OpenLanding, next: u64) -> Vec<u64> {
    let (from, to) = interval(scenario, open);
    let period = scenario.cycle;
    let earliest = ((open.fired + from - TIME_EPSILON) / period)
        .ceil()
        .max(0.0) as u64;
    let first = earliest.max(open.not_before).max(next);
    let mut cycles = vec![first];
    let mut cycle = first + 1;
    while cycle as f64 * period <= open.fired + to + TIME_EPSILON
        && (cycle - 1) as f64 * period <= scenario.end + TIME_EPSILON
    {
        cycles.push(cycle);
        cycle += 1;
    }
    cycles
}

/// The delay that lands the effect at cycle `lands`.
pub(super) fn delay(scenario: &Scenario, open: OpenLanding, lands: u64) -> f64 {
    lands as f64 * scenario.cycle - open.fired
}

/// The interval's lower bound: the delay a run takes.
pub(super) fn lower_bound(scenario: &Scenario, open: OpenLanding) -> f64 {
    interval(scenario, open).0
}

/// The cycle at this time (firings happen at cycle times).
pub(super) fn cycle_of(scenario: &Scenario, time: f64) -> u64 {
    (time / scenario.cycle).round().max(0.0) as u64
}

fn interval(scenario: &Scenario, open: OpenLanding) -> (f64, f64) {
    let rules = scenario.script.rules();
    rules[open.rule].interval.unwrap_or_default()
}
