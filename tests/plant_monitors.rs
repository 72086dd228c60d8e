//! Monitors (`src/plant/monitor.rs`; DESIGN.md §6, §8: numeric telemetry turned into the
//! qualitative observations estimation reads), against their definitions on random monitors
//! and random streams of readings:
//! - a reading inside a threshold's hysteresis band never changes the output while the output
//!   is on either side of that threshold, whatever the persistence;
//! - persistence n delays every change of the classification that lasts n readings by exactly
//!   n − 1 readings, and drops every shorter one (an independent run-length oracle; without
//!   hysteresis, so that a reading's class does not depend on the output);
//! - readings outside the valid range change nothing.

#[path = "support/seeded.rs"]
mod seeded;

use kairos::logic::{ValueId, VarId};
use kairos::plant::monitor::{Monitor, MonitorEvent, MonitorState, Sample, Threshold};
use proptest::prelude::*;

/// A monitor with `values` values whose thresholds are `gaps` apart (each gap wider than both
/// neighbouring hysteresis bands), over [0, 1000].
fn monitor(gaps: &[(f64, f64)], persistence: u32) -> Monitor {
    let mut at = 0.0;
    let mut thresholds = Vec::new();
    let mut last_band = 0.0;
    for &(gap, hysteresis) in gaps {
        at += last_band + gap + hysteresis;
        thresholds.push(Threshold { at, hysteresis });
        last_band = hysteresis;
    }
    Monitor {
        observable: VarId(0),
        unit: String::new(),
        range: (-100.0, at + 100.0),
        values: (0..=gaps.len() as u32).map(ValueId).collect(),
        thresholds,
        persistence,
        stale: None,
        readings: Vec::new(),
    }
}

fn gaps() -> impl Strategy<Value = Vec<(f64, f64)>> {
    prop::collection::vec((1.0..20.0f64, prop_oneof![Just(0.0), 0.1..5.0f64]), 1..5)
}

/// A reading somewhere in the range, often inside a band: a threshold's `at` plus an offset
/// within ±1.5 of its hysteresis.
fn readings(monitor: &Monitor, len: usize) -> impl Strategy<Value = Vec<f64>> + use<> {
    let thresholds = monitor.thresholds.clone();
    let top = monitor.range.1;
    let one = prop_oneof![
        (0.0..top),
        (0..thresholds.len(), -1.5..1.5f64).prop_map(move |(k, f)| {
            let t = thresholds[k];
            t.at + f * t.hysteresis.max(0.5)
        }),
    ];
    prop::collection::vec(one, 1..len)
}

/// The output after each reading.
fn outputs(monitor: &Monitor, readings: &[f64]) -> Vec<Option<ValueId>> {
    let mut state = MonitorState::new();
    (readings.iter().enumerate())
        .map(|(i, &x)| {
            state.sample(monitor, i as f64, Sample::Reading(x));
            state.output()
        })
        .collect()
}

proptest! {
    #![proptest_config(seeded::config(512))]

    /// A reading in threshold k's band [at − h, at + h) leaves the output as it was when it
    /// was one of the two values the threshold separates.
    #[test]
    fn a_reading_inside_a_band_never_changes_the_output(
        (monitor, stream) in (gaps(), 1..4u32).prop_flat_map(|(g, n)| {
            let m = monitor(&g, n);
            (Just(m.clone()), readings(&m, 60))
        })
    ) {
        let out = outputs(&monitor, &stream);
        for i in 1..stream.len() {
            let x = stream[i];
            let Some(before) = out[i - 1] else { continue };
            for (k, t) in monitor.thresholds.iter().enumerate() {
                let inside = t.at - t.hysteresis <= x && x < t.at + t.hysteresis;
                let beside = before.0 as usize == k || before.0 as usize == k + 1;
                if inside && beside {
                    prop_assert_eq!(out[i], Some(before), "reading {} at {}: {:?}", x, i, t);
                }
            }
        }
    }

    /// With persistence n, the output is the classification (persistence 1) with every run of
    /// at least n equal classes shown from its n-th reading on — every change exactly n − 1
    /// readings late — and shorter runs never shown.
    #[test]
    fn persistence_delays_every_change_by_n_minus_1_readings(
        (gaps, n, stream) in gaps().prop_flat_map(|g| {
            let g: Vec<(f64, f64)> = g.into_iter().map(|(gap, _)| (gap, 0.0)).collect();
            let m = monitor(&g, 1);
            (Just(g), 1..6u32, readings(&m, 80))
        })
    ) {
        let classes: Vec<ValueId> = outputs(&monitor(&gaps, 1), &stream)
            .into_iter()
            .map(|c| c.expect("persistence 1 classifies every reading"))
            .collect();
        let out = outputs(&monitor(&gaps, n), &stream);
        // The oracle: run lengths of the classification.
        let mut expected: Vec<Option<ValueId>> = Vec::new();
        let mut shown = None;
        let mut run = 0u32;
        for i in 0..classes.len() {
            run = if i > 0 && classes[i] == classes[i - 1] { run + 1 } else { 1 };
            if run >= n {
                shown = Some(classes[i]);
            }
            expected.push(shown);
        }
        prop_assert_eq!(&out, &expected);
        // Stated as the acceptance says it: every change of the output is a change of the
        // classification n − 1 readings before, held since.
        for i in 1..out.len() {
            if out[i] != out[i - 1] {
                let start = i + 1 - n as usize;
                prop_assert!(classes[start..=i].iter().all(|&c| Some(c) == out[i]));
                prop_assert!(start == 0 || Some(classes[start - 1]) != out[i]);
            }
        }
    }

    /// A reading outside the valid range is refused and changes nothing: the monitor's
    /// outputs are those of the stream without it.
    #[test]
    fn readings_out_of_range_change_nothing(
        (gaps, n, stream, odd) in gaps().prop_flat_map(|g| {
            let m = monitor(&g, 1);
            (Just(g), 1..4u32, readings(&m, 40), prop::collection::vec(any::<bool>(), 40))
        })
    ) {
        let m = monitor(&gaps, n);
        let mut with = MonitorState::new();
        let mut without = MonitorState::new();
        for (i, &x) in stream.iter().enumerate() {
            if odd[i] {
                let reading = m.range.0 - 1.0 - x.abs();
                let refused = with.sample(&m, i as f64, Sample::Reading(reading));
                prop_assert_eq!(refused, Some(MonitorEvent::OutOfRange { reading }));
            }
            with.sample(&m, i as f64, Sample::Reading(x));
            without.sample(&m, i as f64, Sample::Reading(x));
            prop_assert_eq!(with.output(), without.output());
        }
    }
}
