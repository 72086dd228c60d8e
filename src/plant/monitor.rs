//! Monitors: numeric telemetry turned into the qualitative observations estimation reads
//! (DESIGN.md §6, §8; Livingstone 2's monitors, cFS's Limit Checker watchpoints).
//!
//! A plant model may declare an observable **numeric** with a [`Monitor`]: a unit, a valid
//! range, the qualitative values it maps readings to (low to high) and the thresholds between
//! them, each with a hysteresis; a persistence; a staleness. A [`MonitorState`] runs one monitor
//! sample by sample, in three stages:
//!
//! 1. **Range.** A reading outside the valid range (or not a number) is refused: it is an odd
//!    observation, reported and otherwise ignored — it neither counts as a sample nor refreshes
//!    the value.
//! 2. **Classification with hysteresis.** Threshold `k` (between values `k` and `k + 1`) at `at`
//!    with hysteresis `h` is crossed upward by a reading of `at + h` or more and downward by a
//!    reading below `at − h`, counted from the monitor's current *output*: inside the band
//!    `[at − h, at + h)` a reading is classified on the side of the output. With `h = 0` this
//!    is plain thresholding (value `k` for readings in `[at_{k−1}, at_k)`), which is also how
//!    readings are classified while there is no output. The bands of neighbouring thresholds
//!    may not overlap, so a reading's class is well defined however far it jumps. Counting from
//!    the output rather than from the last reading's class keeps an outlier from moving the
//!    reference: the readings after it, inside the band, still read as the output.
//! 3. **Persistence.** The output changes to a class only when the last `n` readings were all
//!    classified so: a change of the classification that lasts reaches the output exactly
//!    `n − 1` readings later, and one that lasts fewer than `n` readings never does (a
//!    glitch). (Exactly, for readings outside the hysteresis bands: inside one, the output's
//!    side decides, so a reading there during the wait reads as the output and restarts it.)
//!    The first value is adopted the same way, so the output is absent for the first `n − 1`
//!    readings.
//!
//! **Staleness.** With `stale: T`, the output is held from sample to sample while the last
//! sample is at most `T` seconds old; past that it becomes absent (the observation is unknown,
//! as an unreported one) and the monitor reports it stale once; the persistence count starts
//! again. Without `stale`, a cycle without a sample has no observation of it, as for any
//! observable (DESIGN.md §3), and the monitor keeps its state for the next sample.
//!
//! A cycle may bring several readings of one observable (a sensor sampled faster than the
//! executive cycles): they are samples in the order given, and the cycle's observation is the
//! output after the last. With several times `persistence` readings a cycle, a value that
//! holds through a cycle is confirmed in that cycle — no delay for the model's timing to allow
//! for — while a stray reading is still a glitch (the model-driven plant reports twice the
//! persistence, for campaigns).
//!
//! A **symbolic** report of a monitored observable (a sensor's `invalid` flag, a scripted
//! qualitative value) bypasses the monitor: it is the observation as it is, and becomes the
//! monitor's output, so that later readings change it only through the persistence rule.
//!
//! Monitors run before estimation, at the executive's observation boundary: estimation sees the
//! qualitative values only, so its cost does not change. A monitor costs a comparison per
//! threshold and a few words of state per sample.

use crate::logic::{ValueId, VarId};

/// Two times closer than this are the same instant.
const TIME_EPSILON: f64 = 1e-9;

/// A threshold between two neighbouring qualitative values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Threshold {
    /// Where the upper value starts.
    pub at: f64,
    /// How far past `at` a reading must be to cross it (0 or more): up at `at + hysteresis`,
    /// down below `at − hysteresis`.
    pub hysteresis: f64,
}

/// How the model-driven plant draws a reading for a qualitative value (DESIGN.md §17's
/// campaigns test monitors against realistic noise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reading {
    /// A normal law around a nominal value.
    Gaussian {
        /// The nominal value.
        mean: f64,
        /// Its standard deviation.
        sd: f64,
    },
    /// Uniform on an interval.
    Uniform {
        /// The lower end.
        lower: f64,
        /// The upper end.
        upper: f64,
    },
}

/// A numeric observable's monitor, as the plant model declares it.
#[derive(Debug, Clone, PartialEq)]
pub struct Monitor {
    /// The observable it reads (an attribute variable).
    pub observable: VarId,
    /// The unit of its readings (`V`, `°C`), for people.
    pub unit: String,
    /// The valid range, both ends included.
    pub range: (f64, f64),
    /// The qualitative values readings map to, from low to high (values of the observable).
    pub values: Vec<ValueId>,
    /// The thresholds between consecutive values, increasing; one fewer than the values.
    pub thresholds: Vec<Threshold>,
    /// How many consecutive samples of one class change the output (1 or more).
    pub persistence: u32,
    /// How old the last sample may be before the output is absent, seconds.
    pub stale: Option<f64>,
    /// What the model-driven plant reports for each value it draws: a reading from this law
    /// (values without one are reported as themselves).
    pub readings: Vec<(ValueId, Reading)>,
}

impl Monitor {
    /// The class (index into [`Monitor::values`]) of a reading `x` given the output's class:
    /// hysteresis keeps a reading inside a threshold's band on the output's side; with no
    /// output, plain thresholds.
    pub fn classify(&self, previous: Option<usize>, x: f64) -> usize {
        let Some(mut class) = previous.filter(|&c| c < self.values.len()) else {
            return self.thresholds.iter().filter(|t| x >= t.at).count();
        };
        while let Some(up) = self.thresholds.get(class) {
            if x < up.at + up.hysteresis {
                break;
            }
            class += 1;
        }
        while class > 0 {
            let down = self.thresholds[class - 1];
            if x >= down.at - down.hysteresis {
                break;
            }
            class -= 1;
        }
        class
    }

    /// True when `x` is a reading the monitor accepts: a number in the valid range.
    pub fn in_range(&self, x: f64) -> bool {
        self.range.0 <= x && x <= self.range.1
    }

    /// The law of the readings of `value`, if the model gives one.
    pub fn reading_of(&self, value: ValueId) -> Option<Reading> {
        self.readings
            .iter()
            .find(|(v, _)| *v == value)
            .map(|&(_, reading)| reading)
    }
}

/// What one sample or one cycle did to a monitor's output.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MonitorEvent {
    /// The output changed on a reading.
    Changed {
        /// The reading that made it change.
        reading: f64,
        /// The output before (`None`: absent).
        from: Option<ValueId>,
        /// The output now.
        to: ValueId,
    },
    /// A reading outside the valid range (or not a number) was refused.
    OutOfRange {
        /// The reading.
        reading: f64,
    },
    /// No sample for longer than the staleness: the output is absent.
    Stale {
        /// The time of the last sample, seconds.
        last: f64,
    },
}

/// A sample of a monitored observable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Sample {
    /// A number, for the monitor.
    Reading(f64),
    /// A qualitative value reported as it is (the monitor is bypassed).
    Value(ValueId),
}

/// One monitor's state: the run of equal classes that differ from the output (for
/// persistence), the output (the reference of hysteresis) and the last sample's time (for
/// staleness).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MonitorState {
    run: Option<(usize, u32)>,
    output: Option<ValueId>,
    last: Option<f64>,
    stale: bool,
}

impl MonitorState {
    /// A monitor that has seen nothing: no output.
    pub fn new() -> Self {
        MonitorState::default()
    }

    /// The current output (`None`: absent).
    pub fn output(&self) -> Option<ValueId> {
        self.output
    }

    /// Feeds one sample at `time`; says what it did to the output.
    pub fn sample(&mut self, monitor: &Monitor, time: f64, sample: Sample) -> Option<MonitorEvent> {
        let x = match sample {
            Sample::Value(value) => {
                self.run = None;
                self.output = Some(value);
                self.fresh(time);
                return None;
            }
            Sample::Reading(x) if !monitor.in_range(x) => {
                return Some(MonitorEvent::OutOfRange { reading: x });
            }
            Sample::Reading(x) => x,
        };
        self.fresh(time);
        let current = self
            .output
            .and_then(|o| monitor.values.iter().position(|&v| v == o));
        let class = monitor.classify(current, x);
        if current == Some(class) {
            self.run = None;
            return None;
        }
        let count = match self.run {
            Some((c, n)) if c == class => n.saturating_add(1),
            _ => 1,
        };
        self.run = Some((class, count));
        if count < monitor.persistence.max(1) {
            return None;
        }
        self.run = None;
        let to = monitor.values[class];
        let from = self.output.replace(to);
        Some(MonitorEvent::Changed {
            reading: x,
            from,
            to,
        })
    }

    /// Ends a cycle at `time`: the output to report (absent once stale, or — without a
    /// staleness — when the cycle had no sample), and the staleness event when it went stale
    /// now. `sampled` says whether the cycle had a sample.
    pub fn close(
        &mut self,
        monitor: &Monitor,
        time: f64,
        sampled: bool,
    ) -> (Option<ValueId>, Option<MonitorEvent>) {
        let Some(limit) = monitor.stale else {
            return (self.output.filter(|_| sampled), None);
        };
        match self.last {
            Some(last) if time - last > limit + TIME_EPSILON => {
                let event = (!self.stale).then_some(MonitorEvent::Stale { last });
                self.stale = true;
                self.output = None;
                self.run = None;
                (None, event)
            }
            _ => (self.output, None),
        }
    }

    /// Feeds the state to `state` (explicit-state exploration's fingerprint).
    pub fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        use std::hash::Hash;
        self.run.hash(state);
        self.output.hash(state);
        self.last.map(f64::to_bits).hash(state);
        self.stale.hash(state);
    }

    fn fresh(&mut self, time: f64) {
        self.last = Some(time);
        self.stale = false;
    }
}

#[cfg(test)]
mod tests {
    //! The three stages of the module documentation on a two-threshold monitor.

    use super::*;

    fn monitor(persistence: u32, stale: Option<f64>) -> Monitor {
        Monitor {
            observable: VarId(0),
            unit: "°C".into(),
            range: (-40.0, 120.0),
            values: vec![ValueId(0), ValueId(1), ValueId(2)],
            thresholds: vec![
                Threshold {
                    at: 20.0,
                    hysteresis: 1.0,
                },
                Threshold {
                    at: 40.0,
                    hysteresis: 0.0,
                },
            ],
            persistence,
            stale,
            readings: Vec::new(),
        }
    }

    fn outputs(monitor: &Monitor, readings: &[f64]) -> Vec<Option<u32>> {
        let mut state = MonitorState::new();
        readings
            .iter()
            .enumerate()
            .map(|(i, &x)| {
                state.sample(monitor, i as f64, Sample::Reading(x));
                state.close(monitor, i as f64, true).0.map(|v| v.0)
            })
            .collect()
    }

    #[test]
    fn hysteresis_holds_inside_the_band_and_the_first_reading_is_plain() {
        let m = monitor(1, None);
        assert_eq!(
            outputs(&m, &[19.5, 20.5, 21.0, 20.0, 19.2, 18.9, 45.0, 39.0, 40.0]),
            [0, 0, 1, 1, 1, 0, 2, 1, 2].map(Some)
        );
        assert_eq!(
            outputs(&m, &[20.5]),
            [Some(1)],
            "the first reading: plain thresholds"
        );
    }

    #[test]
    fn persistence_needs_n_samples_of_one_class_and_drops_glitches() {
        let m = monitor(3, None);
        assert_eq!(
            outputs(&m, &[10.0, 10.0, 10.0, 30.0, 10.0, 30.0, 30.0, 30.0]),
            [
                None,
                None,
                Some(0),
                Some(0),
                Some(0),
                Some(0),
                Some(0),
                Some(1)
            ]
        );
    }

    #[test]
    fn out_of_range_readings_are_refused_and_change_nothing() {
        let m = monitor(2, None);
        let mut state = MonitorState::new();
        state.sample(&m, 0.0, Sample::Reading(10.0));
        assert_eq!(
            state.sample(&m, 1.0, Sample::Reading(500.0)),
            Some(MonitorEvent::OutOfRange { reading: 500.0 })
        );
        assert_eq!(
            state
                .sample(&m, 1.0, Sample::Reading(f64::NAN))
                .map(|e| matches!(e, MonitorEvent::OutOfRange { .. })),
            Some(true)
        );
        let changed = state.sample(&m, 2.0, Sample::Reading(10.0));
        assert_eq!(
            changed,
            Some(MonitorEvent::Changed {
                reading: 10.0,
                from: None,
                to: ValueId(0)
            }),
            "the refused readings neither count nor break the run"
        );
    }

    #[test]
    fn a_stale_output_is_absent_and_reported_once() {
        let m = monitor(1, Some(2.0));
        let mut state = MonitorState::new();
        state.sample(&m, 0.0, Sample::Reading(30.0));
        assert_eq!(state.close(&m, 0.0, true), (Some(ValueId(1)), None));
        assert_eq!(
            state.close(&m, 2.0, false),
            (Some(ValueId(1)), None),
            "held"
        );
        assert_eq!(
            state.close(&m, 3.0, false),
            (None, Some(MonitorEvent::Stale { last: 0.0 }))
        );
        assert_eq!(state.close(&m, 4.0, false), (None, None), "reported once");
        state.sample(&m, 5.0, Sample::Reading(30.0));
        assert_eq!(state.close(&m, 5.0, true).0, Some(ValueId(1)));
    }

    #[test]
    fn without_a_staleness_an_unsampled_cycle_has_no_observation() {
        let m = monitor(1, None);
        let mut state = MonitorState::new();
        state.sample(&m, 0.0, Sample::Reading(30.0));
        assert_eq!(state.close(&m, 1.0, false).0, None);
        assert_eq!(state.output(), Some(ValueId(1)), "the state is kept");
    }

    #[test]
    fn a_symbolic_value_bypasses_the_monitor() {
        let m = monitor(3, None);
        let mut state = MonitorState::new();
        assert_eq!(state.sample(&m, 0.0, Sample::Value(ValueId(2))), None);
        assert_eq!(state.output(), Some(ValueId(2)));
        state.sample(&m, 1.0, Sample::Reading(10.0));
        state.sample(&m, 2.0, Sample::Reading(10.0));
        assert_eq!(state.output(), Some(ValueId(2)), "two readings of three");
    }
}
