//! The recent steps TimedME can estimate again, wider, when truncation may have cost it the
//! truth (beyond the thesis, after Livingstone 2's history window).
//!
//! Truncating to κ states can drop the state the plant is really in, or enough weight to put the
//! wrong plant state first. TimedME keeps the belief it was given `window`–`2 · window` steps
//! ago and every step's commands and observation since; it re-runs that window tracking
//! [`WIDEN`] × κ states and keeps the κ heaviest states of the run
//! - when an observation arrives that no successor of the tracked states explains (before
//!   DESIGN.md §8's fault jumps, which would explain it by a fault instead of the state that
//!   was dropped): a dropped state within the window and among the wider run's states is found
//!   again with its true weight relative to the others;
//! - when ŝ is in doubt because of truncation: the two heaviest plant states of the step differ
//!   by less than a few times the weight truncated away within the window;
//! - when an observation surprised and a state dropped within the window may now outweigh a
//!   kept one: the re-run then starts at the latest belief recorded at or before the step
//!   that dropped it — that step's start, kept for the purpose (steps that dropped next to
//!   nothing keep none), an earlier step's, or a segment's start — or re-runs the step being
//!   updated alone when that step, or the one before it without a checkpoint, dropped it
//!   ([`History::replay_from`]).
//!
//! The triggers, which of them the user chose ([`Rerun`](super::Rerun)), and why the re-run
//! starts where it does are in `timed_me.rs` ("When the window is re-run"); what each step
//! truncated ([`Truncated`]) is recorded here.
//!
//! The wide belief a re-run ends with is kept behind the belief returned from it: when the next
//! update starts from that belief and needs a re-run too, the wide one is stepped once — the
//! same run carried one step further — instead of running the window again, so a stretch of
//! doubt costs one 8κ step per step.
//!
//! The window is kept only while the caller goes on from the belief TimedME returned last (an
//! update from any other belief starts it afresh), and is dropped when the fault jumps were
//! needed: a history that could not explain a step cannot explain the steps after it.
//!
//! Recording is on every step's path, quiet ones included, so it copies nothing it can share:
//! the belief an update returns carries a serial number (a belief cannot be changed once made,
//! so the number names its value), and a step's commands and observation are shared with the
//! previous step's when equal.

use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use super::Belief;
use crate::plant::{Commands, Observation};

/// How many times κ the re-run tracks.
pub(super) const WIDEN: usize = 8;

/// One step's inputs, as an update is given them.
#[derive(Clone, Copy)]
pub(super) struct Step<'a> {
    pub(super) commands: &'a Commands,
    pub(super) observation: &'a Observation,
    /// t(i+1).
    pub(super) time: f64,
}

/// One step's inputs, kept.
#[derive(Clone)]
pub(super) struct Input {
    commands: Arc<Commands>,
    observation: Arc<Observation>,
    time: f64,
    /// What the step's truncation dropped.
    truncated: Truncated,
    /// The belief the step started from, kept when the step dropped a state heavy enough that
    /// a re-run may start here ([`CHECKPOINT`]).
    start: Option<Belief>,
}

/// A segment reserves room for at most this many steps up front (a user's window may be long;
/// the room grows as steps come).
const CAPACITY: usize = 64;

/// A step that drops a state of more than this share of its merged weight keeps the belief it
/// started from, so that a re-run for that state can start there rather than at the window's
/// start. Quiet steps of a plant whose faults are rare drop far less and copy nothing.
const CHECKPOINT: f64 = 1e-6;

/// What one step's truncation dropped, as the re-run's triggers need it (`timed_me.rs`, "When
/// the window is re-run").
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Truncated {
    /// The fraction of the merged weight truncated away.
    pub(super) lost: f64,
    /// The weight of the heaviest state dropped, as a share of the weight merged.
    pub(super) dropped: f64,
    /// How much the step's observation may have lifted a state missing from its sources,
    /// relative to the states merged (at least 1): the best observation factor of a candidate
    /// over the weight merged, from sources whose weights sum to 1.
    pub(super) lift: f64,
}

impl Truncated {
    /// A step that dropped nothing and lifted nothing.
    pub(super) const NONE: Truncated = Truncated {
        lost: 0.0,
        dropped: 0.0,
        lift: 1.0,
    };
}

/// The heaviest state dropped within the window, carried forward to a step
/// ([`History::heaviest_dropped`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Dropped {
    /// Its weight, as a share of the step's merged weight.
    pub(super) weight: f64,
    /// The step that dropped it (counting the window's steps from 0).
    pub(super) origin: usize,
    /// How many steps were carried.
    steps: usize,
}

impl Dropped {
    /// Carried through a step that truncated `step`: lifted by its observation, or replaced by
    /// what it dropped if that weighs more.
    pub(super) fn then(self, step: Truncated) -> Dropped {
        let lifted = self.weight * step.lift;
        let (weight, origin) = if step.dropped > lifted {
            (step.dropped, self.steps)
        } else {
            (lifted, self.origin)
        };
        Dropped {
            weight,
            origin,
            steps: self.steps + 1,
        }
    }
}

impl Input {
    /// The inputs as a step is given them.
    pub(super) fn step(&self) -> Step<'_> {
        Step {
            commands: &self.commands,
            observation: &self.observation,
            time: self.time,
        }
    }
}

/// Where a re-run of the window starts ([`History::replay_from`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Start {
    /// At the window's start: an observation no tracked state explains, or doubt.
    Window,
    /// For a state dropped at this recorded step (counting the window's steps from 0), which a
    /// surprise may have made heavier than a kept one.
    Dropped(usize),
}

/// What a re-run runs ([`History::replay_from`]).
pub(super) enum Replay<'a> {
    /// From this recorded belief, these recorded steps, then the step being updated.
    Recorded(&'a Belief, Vec<&'a Input>),
    /// The step being updated alone, from the belief it starts from.
    Current,
}

/// A belief TimedME was given, and the inputs of the steps from it on.
#[derive(Clone)]
pub(super) struct Segment {
    pub(super) start: Belief,
    pub(super) steps: Vec<Input>,
}

/// The last `window`–`2 · window` steps (two segments of at most `window` steps each).
#[derive(Clone, Default)]
pub(super) struct History {
    segments: VecDeque<Segment>,
    /// The serial number of the belief the last update returned: the next update must start
    /// from it.
    last: Option<u64>,
    /// The wide belief the last re-run ended with, and the serial number of the belief returned
    /// from it: an update from that belief steps the wide one instead of re-running the window
    /// (the same run, carried one step further).
    wide: Option<(u64, Belief)>,
}

/// The next serial number for a returned belief, over every TimedME of the process (so that a
/// belief one estimator returned never continues another's history).
static ISSUED: AtomicU64 = AtomicU64::new(0);

/// Gives `belief` a fresh serial number, and returns it.
fn issue(belief: &mut Belief) -> u64 {
    let serial = ISSUED.fetch_add(1, Ordering::Relaxed);
    belief.issued = Some(serial);
    serial
}

impl History {
    /// Whether an update from `belief` continues this history.
    pub(super) fn continues_from(&self, belief: &Belief) -> bool {
        belief.issued.is_some() && belief.issued == self.last
    }

    /// The wide belief the re-run that returned `belief` ended with, if one did.
    pub(super) fn wide_behind(&self, belief: &Belief) -> Option<&Belief> {
        let (serial, wide) = self.wide.as_ref()?;
        (belief.issued == Some(*serial)).then_some(wide)
    }

    /// Remembers the wide belief a re-run ended with, behind `returned` (recorded already).
    pub(super) fn keep_wide(&mut self, wide: Belief, returned: &Belief) {
        self.wide = returned.issued.map(|serial| (serial, wide));
    }

    /// Where a re-run for `start` begins, and the recorded steps from there, oldest first;
    /// `None` when there is nothing to re-run from (an empty window, for [`Start::Window`]).
    ///
    /// From [`Start::Window`], the window's start and every step. For a state dropped at
    /// recorded step `origin` ([`Start::Dropped`]), the latest belief recorded at or before
    /// that step — a step's checkpoint, or a segment's start (the belief its first step
    /// started from) — so that no step before it is re-run: a re-run that starts later cannot
    /// find the state again. Except when the state was dropped by the step being updated, or
    /// by the one before it with no belief kept at its start: then [`Replay::Current`], the
    /// step being updated alone, from the belief it starts from (`timed_me.rs`, "When the
    /// window is re-run", says why).
    pub(super) fn replay_from(&self, start: Start) -> Option<Replay<'_>> {
        let latest = match start {
            Start::Window => 0,
            Start::Dropped(origin) => {
                if origin + 1 >= self.steps().count() && self.belief_before(origin).is_none() {
                    return Some(Replay::Current);
                }
                self.latest_at_or_before(origin)
            }
        };
        let belief = self.belief_before(latest)?;
        Some(Replay::Recorded(
            belief,
            self.steps().skip(latest).collect(),
        ))
    }

    /// The latest recorded step at or before `origin` whose start belief is recorded (0, the
    /// window's start, when no later one is).
    fn latest_at_or_before(&self, origin: usize) -> usize {
        (0..=origin)
            .rev()
            .find(|&i| self.belief_before(i).is_some())
            .unwrap_or(0)
    }

    /// The belief recorded step `i` started from, where it is kept: its checkpoint, or its
    /// segment's start when it is the segment's first step.
    fn belief_before(&self, i: usize) -> Option<&Belief> {
        let mut offset = 0;
        for segment in &self.segments {
            if i < offset + segment.steps.len() {
                let input = &segment.steps[i - offset];
                return input
                    .start
                    .as_ref()
                    .or((i == offset).then_some(&segment.start));
            }
            offset += segment.steps.len();
        }
        None
    }

    /// Every recorded step, oldest first.
    fn steps(&self) -> impl Iterator<Item = &Input> {
        self.segments.iter().flat_map(|s| s.steps.iter())
    }

    /// Records an update from `from` with these inputs that returned `to`, keeping `window`
    /// to `2 · window` steps; an update from a belief that is not the last one returned starts
    /// afresh.
    pub(super) fn record(
        &mut self,
        window: usize,
        from: &Belief,
        step: &Step,
        truncated: Truncated,
        to: &mut Belief,
    ) {
        if window == 0 {
            return;
        }
        if !self.continues_from(from) {
            self.segments.clear();
        }
        if self.segments.back().is_none_or(|s| s.steps.len() >= window) {
            if self.segments.len() == 2 {
                self.segments.pop_front();
            }
            self.segments.push_back(Segment {
                start: from.clone(),
                steps: Vec::with_capacity(window.min(CAPACITY)),
            });
        }
        let previous = self.segments.iter().rev().find_map(|s| s.steps.last());
        let input = Input {
            commands: shared(previous.map(|p| &p.commands), step.commands),
            observation: shared(previous.map(|p| &p.observation), step.observation),
            time: step.time,
            truncated,
            start: (truncated.dropped > CHECKPOINT).then(|| from.clone()),
        };
        if let Some(segment) = self.segments.back_mut() {
            segment.steps.push(input);
        }
        self.last = Some(issue(to));
    }

    /// The heaviest state the window's steps dropped, carried forward to the last step
    /// recorded.
    pub(super) fn heaviest_dropped(&self) -> Dropped {
        self.steps().fold(Dropped::default(), |dropped, input| {
            dropped.then(input.truncated)
        })
    }

    /// The fraction of the window's start belief's weight truncated away on the way since.
    pub(super) fn lost(&self) -> f64 {
        1.0 - self
            .steps()
            .map(|i| 1.0 - i.truncated.lost)
            .product::<f64>()
    }

    /// Forgets every step and starts afresh from `belief`, the one just returned (an initial
    /// belief, or one the fault jumps gave).
    pub(super) fn restart(&mut self, belief: &mut Belief) {
        self.segments.clear();
        self.wide = None;
        self.last = Some(issue(belief));
    }
}

/// `value`, sharing `previous` when it is equal.
fn shared<T: Clone + PartialEq>(previous: Option<&Arc<T>>, value: &T) -> Arc<T> {
    match previous {
        Some(previous) if **previous == *value => Arc::clone(previous),
        _ => Arc::new(value.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;
    use crate::estimation::{ModeEstimator, TimedMe, TimedMeOptions};
    use crate::plant::Plant;

    /// A step that dropped `dropped` of its weight.
    fn truncated(dropped: f64) -> Truncated {
        Truncated {
            lost: dropped,
            dropped,
            lift: 1.0,
        }
    }

    /// A history of two-step segments whose steps dropped `drops` in turn, and the serial
    /// number of the belief each step started from.
    fn recorded(drops: &[f64]) -> (History, Vec<Option<u64>>) {
        let plant = Plant::load(&Source::new(
            "driver_valve.ron",
            include_str!("../../models/driver_valve.ron"),
        ))
        .expect("the model loads");
        let mut theory = plant.theory().expect("theory");
        let mut belief = TimedMe::new(TimedMeOptions::kappa(1))
            .initial(&plant, &mut theory, 0.0, &Observation::none())
            .expect("initial")
            .belief;
        let mut history = History::default();
        history.restart(&mut belief);
        let (commands, observation) = (Commands::idle(&plant), Observation::none());
        let mut starts = Vec::new();
        for (i, &dropped) in drops.iter().enumerate() {
            let step = Step {
                commands: &commands,
                observation: &observation,
                time: i as f64 + 1.0,
            };
            let mut next = belief.clone();
            history.record(2, &belief, &step, truncated(dropped), &mut next);
            starts.push(belief.issued);
            belief = next;
        }
        (history, starts)
    }

    /// Where a re-run for `start` begins: the serial number of its belief and how many
    /// recorded steps it runs; `None` for the step being updated alone.
    fn begins(history: &History, start: Start) -> Option<(Option<u64>, usize)> {
        match history.replay_from(start).expect("something to re-run") {
            Replay::Recorded(belief, steps) => Some((belief.issued, steps.len())),
            Replay::Current => None,
        }
    }

    /// `timed_me.rs`, "When the window is re-run": a surprise's re-run starts at the latest
    /// belief recorded at or before the step that dropped the state (a checkpoint or a
    /// segment's start), or re-runs the step being updated alone when the step before it
    /// dropped the state without a checkpoint; doubt and contradictions start at the window's
    /// start.
    #[test]
    fn a_rerun_starts_no_earlier_than_it_must() {
        let light = CHECKPOINT / 10.0;
        let heavy = CHECKPOINT * 10.0;
        // Segments [0, 1] and [2, 3]; step 0 kept a checkpoint (and starts the window).
        let (history, starts) = recorded(&[heavy, light, light, light]);
        assert_eq!(begins(&history, Start::Window), Some((starts[0], 4)));
        assert_eq!(begins(&history, Start::Dropped(0)), Some((starts[0], 4)));
        assert_eq!(begins(&history, Start::Dropped(1)), Some((starts[0], 4)));
        assert_eq!(begins(&history, Start::Dropped(2)), Some((starts[2], 2)));
        assert_eq!(begins(&history, Start::Dropped(3)), None);
        assert_eq!(begins(&history, Start::Dropped(4)), None);
        // A checkpoint within the newer segment, and at the last step.
        let (history, starts) = recorded(&[light, light, light, heavy]);
        assert_eq!(begins(&history, Start::Dropped(1)), Some((starts[0], 4)));
        assert_eq!(begins(&history, Start::Dropped(3)), Some((starts[3], 1)));
        let (history, starts) = recorded(&[light, light, light, heavy, light]);
        // Three segments were started; the oldest is gone: [2, 3], [4].
        assert_eq!(begins(&history, Start::Window), Some((starts[2], 3)));
        assert_eq!(begins(&history, Start::Dropped(1)), Some((starts[3], 2)));
        // The last step recorded starts a segment: its start is kept.
        assert_eq!(begins(&history, Start::Dropped(2)), Some((starts[4], 1)));
    }
}
