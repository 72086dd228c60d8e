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
//!   kept one: the re-run then starts at the step that dropped it, from the belief that step
//!   started from, kept for the purpose (steps that dropped next to nothing keep none).
//!
//! The triggers are in `timed_me.rs` ("When the window is re-run"); what each step truncated
//! ([`Truncated`]) is recorded here.
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

    /// The latest start a re-run can take at or before recorded step `origin` (counting from 0),
    /// and the recorded steps from there, oldest first: the step's own start where it kept one,
    /// else the window's start (`origin` 0: the window's start and every step recorded); `None`
    /// when nothing is recorded.
    pub(super) fn replay_from(
        &self,
        origin: usize,
    ) -> Option<(&Belief, impl Iterator<Item = &Input>)> {
        let first = self.segments.front()?;
        let (skip, start) = self
            .steps()
            .enumerate()
            .take(origin.saturating_add(1))
            .filter_map(|(i, input)| input.start.as_ref().map(|start| (i, start)))
            .last()
            .unwrap_or((0, &first.start));
        Some((start, self.steps().skip(skip)))
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
