//! State timelines and adapter histories (MDS, seed 000 §1.1; DESIGN.md §10).
//!
//! In the Mission Data System a *state variable* holds the knowledge of one physical state over
//! time, and hardware adapters keep the histories of the commands they sent and the measurements
//! they received — the estimator's evidence. Here every component's mode is a state variable
//! whose timeline is the sequence of most-likely values, each over the interval it held, with
//! its probability; commands and observation changes are kept as histories. All three are
//! bounded: the oldest entries are dropped past [`Retention`], so a run of any length uses
//! bounded memory.
//!
//! The executive records every state variable each cycle in one call,
//! [`Timelines::record_states`], which is [`Timelines::record_state`] for each in turn (a
//! property test checks the two give equal timelines): on the Mars EDL's quiet cruise cycle
//! (22 state variables) the 22 calls cost 1,234 instructions and the one call 825
//! (`cg.sh`: 38,258 → 37,849 a cycle).

use std::collections::VecDeque;

use crate::logic::{ValueId, VarId};

/// How much history to keep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Retention {
    /// Intervals kept per state variable.
    pub intervals: usize,
    /// Commands kept.
    pub commands: usize,
    /// Observation changes kept.
    pub observations: usize,
}

impl Default for Retention {
    /// Enough for a whole EDL (a few hundred changes) many times over.
    fn default() -> Self {
        Retention {
            intervals: 4096,
            commands: 4096,
            observations: 16384,
        }
    }
}

/// A state variable's value over an interval of time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// The most likely value.
    pub value: ValueId,
    /// When it became the most likely value.
    pub from: f64,
    /// The last cycle it was still the most likely value.
    pub until: f64,
    /// Its marginal probability at the last cycle.
    pub probability: f64,
    /// Its lowest marginal probability over the interval.
    pub min_probability: f64,
}

/// One state variable's history of most-likely values.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Timeline {
    intervals: VecDeque<Interval>,
    dropped: usize,
}

impl Timeline {
    /// Records the most likely value at `time`: extends the current interval or opens a new one.
    fn record(&mut self, time: f64, value: ValueId, probability: f64, capacity: usize) {
        match self.intervals.back_mut() {
            Some(last) if last.value == value => {
                last.until = time;
                last.probability = probability;
                last.min_probability = last.min_probability.min(probability);
            }
            _ => {
                push_bounded(
                    &mut self.intervals,
                    &mut self.dropped,
                    capacity,
                    Interval {
                        value,
                        from: time,
                        until: time,
                        probability,
                        min_probability: probability,
                    },
                );
            }
        }
    }

    /// The intervals kept, oldest first.
    pub fn intervals(&self) -> impl ExactSizeIterator<Item = &Interval> {
        self.intervals.iter()
    }

    /// How many old intervals were dropped to stay within the retention.
    pub fn dropped(&self) -> usize {
        self.dropped
    }

    /// The interval holding `time`: the last one that started at or before it, if it is still
    /// kept (a value holds until the next interval starts).
    pub fn at(&self, time: f64) -> Option<&Interval> {
        let after = self.intervals.partition_point(|i| i.from <= time);
        after.checked_sub(1).map(|i| &self.intervals[i])
    }
}

/// A command the executive issued.
#[derive(Debug, Clone, PartialEq)]
pub struct IssuedCommand {
    /// When.
    pub time: f64,
    /// The control assignments (non-idle values).
    pub assignments: Vec<(VarId, ValueId)>,
}

/// An observable whose reported value changed (or became unknown: `None`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObservationChange {
    /// When.
    pub time: f64,
    /// The observable.
    pub var: VarId,
    /// The new value; `None` when it is no longer reported.
    pub value: Option<ValueId>,
}

/// Every state variable's timeline and the adapters' histories.
#[derive(Debug, Clone, PartialEq)]
pub struct Timelines {
    retention: Retention,
    states: Vec<Timeline>,
    commands: VecDeque<IssuedCommand>,
    commands_dropped: usize,
    observations: VecDeque<ObservationChange>,
    observations_dropped: usize,
    last_observed: Vec<(VarId, Option<ValueId>)>,
}

impl Timelines {
    /// Empty timelines for `states` state variables and these observables.
    pub fn new(states: usize, observables: &[VarId], retention: Retention) -> Self {
        Timelines {
            retention,
            states: vec![Timeline::default(); states],
            commands: VecDeque::new(),
            commands_dropped: 0,
            observations: VecDeque::new(),
            observations_dropped: 0,
            last_observed: observables.iter().map(|&v| (v, None)).collect(),
        }
    }

    /// Records the most likely value of state variable `index` at `time`.
    pub fn record_state(&mut self, index: usize, time: f64, value: ValueId, probability: f64) {
        let capacity = self.retention.intervals;
        if let Some(timeline) = self.states.get_mut(index) {
            timeline.record(time, value, probability, capacity);
        }
    }

    /// Records the most likely value of every state variable at `time`: `modes[c]` with
    /// probability `marginals[c]` (0 where there is none), as [`Timelines::record_state`] for
    /// each `c` in turn — in one call a cycle rather than one per state variable.
    pub fn record_states(&mut self, time: f64, modes: &[ValueId], marginals: &[f64]) {
        let capacity = self.retention.intervals;
        for (c, (timeline, &mode)) in self.states.iter_mut().zip(modes).enumerate() {
            let probability = marginals.get(c).copied().unwrap_or(0.0);
            timeline.record(time, mode, probability, capacity);
        }
    }

    /// Records an issued command (idle cycles are not recorded).
    pub fn record_command(&mut self, time: f64, assignments: Vec<(VarId, ValueId)>) {
        if assignments.is_empty() {
            return;
        }
        let capacity = self.retention.commands;
        let command = IssuedCommand { time, assignments };
        push_bounded(
            &mut self.commands,
            &mut self.commands_dropped,
            capacity,
            command,
        );
    }

    /// Records the observation of a cycle, keeping only the changes.
    pub fn record_observation(&mut self, time: f64, observed: &[(VarId, ValueId)]) {
        let capacity = self.retention.observations;
        for (var, last) in &mut self.last_observed {
            let now = observed.iter().find(|(x, _)| x == var).map(|&(_, v)| v);
            if now != *last {
                *last = now;
                let change = ObservationChange {
                    time,
                    var: *var,
                    value: now,
                };
                push_bounded(
                    &mut self.observations,
                    &mut self.observations_dropped,
                    capacity,
                    change,
                );
            }
        }
    }

    /// The timeline of state variable `index` (a component, by
    /// [`ComponentId`](crate::plant::ComponentId) index).
    pub fn state(&self, index: usize) -> Option<&Timeline> {
        self.states.get(index)
    }

    /// Every state variable's timeline, by component index.
    pub fn states(&self) -> &[Timeline] {
        &self.states
    }

    /// The commands kept, oldest first.
    pub fn commands(&self) -> impl ExactSizeIterator<Item = &IssuedCommand> {
        self.commands.iter()
    }

    /// Commands issued in `[from, to]`.
    pub fn commands_between(&self, from: f64, to: f64) -> impl Iterator<Item = &IssuedCommand> {
        self.commands
            .iter()
            .filter(move |c| c.time >= from && c.time <= to)
    }

    /// The observation changes kept, oldest first.
    pub fn observations(&self) -> impl ExactSizeIterator<Item = &ObservationChange> {
        self.observations.iter()
    }

    /// The value an observable was last reported with at or before `time`, if still kept.
    pub fn observed_at(&self, var: VarId, time: f64) -> Option<ValueId> {
        self.observations
            .iter()
            .rev()
            .find(|c| c.var == var && c.time <= time)
            .and_then(|c| c.value)
    }

    /// Entries dropped to stay within the retention: (intervals, commands, observations).
    pub fn dropped(&self) -> (usize, usize, usize) {
        let intervals = self.states.iter().map(Timeline::dropped).sum();
        (intervals, self.commands_dropped, self.observations_dropped)
    }
}

fn push_bounded<T>(queue: &mut VecDeque<T>, dropped: &mut usize, capacity: usize, item: T) {
    if capacity == 0 {
        *dropped += 1;
        return;
    }
    if queue.len() == capacity {
        queue.pop_front();
        *dropped += 1;
    }
    queue.push_back(item);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_timeline_holds_intervals_queryable_by_time() {
        let mut timeline = Timeline::default();
        for (t, v, p) in [(0.0, 0, 0.9), (1.0, 0, 0.8), (2.0, 1, 0.7), (3.0, 1, 0.95)] {
            timeline.record(t, ValueId(v), p, 10);
        }
        let intervals: Vec<_> = timeline.intervals().collect();
        assert_eq!(intervals.len(), 2);
        assert_eq!((intervals[0].from, intervals[0].until), (0.0, 1.0));
        assert_eq!(intervals[0].min_probability, 0.8);
        assert_eq!(intervals[1].probability, 0.95);
        assert_eq!(timeline.at(1.5).map(|i| i.value), Some(ValueId(0)));
        assert_eq!(timeline.at(2.0).map(|i| i.value), Some(ValueId(1)));
        assert_eq!(timeline.at(-1.0), None);
    }

    #[test]
    fn retention_bounds_memory_by_dropping_the_oldest() {
        let retention = Retention {
            intervals: 3,
            commands: 2,
            observations: 2,
        };
        let mut timelines = Timelines::new(1, &[VarId(7)], retention);
        for i in 0..10 {
            let t = f64::from(i);
            timelines.record_state(0, t, ValueId((i % 2) as u32), 1.0);
            timelines.record_command(t, vec![(VarId(1), ValueId(1))]);
            timelines.record_observation(t, &[(VarId(7), ValueId((i % 2) as u32))]);
        }
        assert_eq!(timelines.state(0).map(|t| t.intervals().len()), Some(3));
        assert_eq!(timelines.commands().len(), 2);
        assert_eq!(timelines.observations().len(), 2);
        assert_eq!(timelines.dropped(), (7, 8, 8));
        assert_eq!(timelines.observed_at(VarId(7), 9.0), Some(ValueId(1)));
    }

    proptest::proptest! {
        #![proptest_config(crate::seeded::config(256))]

        /// `Timelines::record_states` is `record_state` for each state variable in turn: any
        /// number of state variables, cycles whose ŝ and marginals are shorter or longer than
        /// that (a missing marginal records 0), values that repeat (intervals extended) or
        /// change, and a small retention (intervals dropped) give equal timelines.
        #[test]
        fn recording_all_states_is_recording_each(
            states in 0usize..6,
            intervals in 1usize..5,
            cycles in proptest::collection::vec(
                (
                    proptest::collection::vec(0u32..3, 0..8),
                    proptest::collection::vec(0.0f64..1.0, 0..8),
                ),
                0..24,
            ),
        ) {
            let retention = Retention { intervals, ..Retention::default() };
            let mut each = Timelines::new(states, &[], retention);
            let mut all = each.clone();
            for (k, (modes, marginals)) in cycles.iter().enumerate() {
                let time = k as f64 * 0.1;
                let modes: Vec<ValueId> = modes.iter().map(|&v| ValueId(v)).collect();
                for (c, &mode) in modes.iter().enumerate() {
                    let probability = marginals.get(c).copied().unwrap_or(0.0);
                    each.record_state(c, time, mode, probability);
                }
                all.record_states(time, &modes, marginals);
            }
            proptest::prop_assert_eq!(all, each);
        }
    }

    #[test]
    fn only_observation_changes_are_kept() {
        let mut timelines = Timelines::new(0, &[VarId(1), VarId(2)], Retention::default());
        timelines.record_observation(0.0, &[(VarId(1), ValueId(0))]);
        timelines.record_observation(1.0, &[(VarId(1), ValueId(0))]);
        timelines.record_observation(2.0, &[(VarId(1), ValueId(1)), (VarId(2), ValueId(0))]);
        timelines.record_observation(3.0, &[(VarId(2), ValueId(0))]);
        let changes: Vec<_> = timelines
            .observations()
            .map(|c| (c.time, c.var.0))
            .collect();
        assert_eq!(changes, vec![(0.0, 1), (2.0, 1), (2.0, 2), (3.0, 1)]);
        assert_eq!(timelines.observed_at(VarId(1), 3.5), None);
    }
}
