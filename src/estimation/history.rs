//! The recent steps TimedME can estimate again, wider, when an observation contradicts every
//! tracked state (issue 16 item 3; beyond the thesis, after Livingstone 2's history window).
//!
//! Truncating to κ states can drop the state the plant is really in; TimedME learns it when an
//! observation arrives that no successor of the tracked states explains. DESIGN.md §8's first
//! fallback then lets components jump into unconstrained fault modes — an explanation, but
//! usually not the one that was dropped. Before that, TimedME re-runs the last steps of its own
//! history (the belief it was given `window`–`2 · window` steps ago, then the same commands and
//! observations) tracking [`WIDEN`] × κ states, and takes the κ heaviest states of that run
//! when it explains the new observation. A dropped state within the window and among the wider
//! run's states is found again with its true weight relative to the others; one dropped longer
//! ago, or explained by nothing the model allows, still ends in the fault jumps.
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
use std::rc::Rc;
use std::sync::atomic::{AtomicU64, Ordering};

use super::Belief;
use crate::plant::{Commands, Observation};

/// How many times κ the re-run tracks.
pub(super) const WIDEN: usize = 4;

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
    commands: Rc<Commands>,
    observation: Rc<Observation>,
    time: f64,
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

    /// The oldest segment's start and every recorded step since, oldest first; `None` when
    /// nothing is recorded.
    pub(super) fn replay(&self) -> Option<(&Belief, impl Iterator<Item = &Input>)> {
        let first = self.segments.front()?;
        Some((
            &first.start,
            self.segments.iter().flat_map(|s| s.steps.iter()),
        ))
    }

    /// Records an update from `from` with these inputs that returned `to`, keeping `window`
    /// to `2 · window` steps; an update from a belief that is not the last one returned starts
    /// afresh.
    pub(super) fn record(&mut self, window: usize, from: &Belief, step: &Step, to: &mut Belief) {
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
                steps: Vec::with_capacity(window),
            });
        }
        let previous = self.segments.iter().rev().find_map(|s| s.steps.last());
        let input = Input {
            commands: shared(previous.map(|p| &p.commands), step.commands),
            observation: shared(previous.map(|p| &p.observation), step.observation),
            time: step.time,
        };
        if let Some(segment) = self.segments.back_mut() {
            segment.steps.push(input);
        }
        self.last = Some(issue(to));
    }

    /// Forgets every step and starts afresh from `belief`, the one just returned (an initial
    /// belief, or one the fault jumps gave).
    pub(super) fn restart(&mut self, belief: &mut Belief) {
        self.segments.clear();
        self.last = Some(issue(belief));
    }
}

/// `value`, sharing `previous` when it is equal.
fn shared<T: Clone + PartialEq>(previous: Option<&Rc<T>>, value: &T) -> Rc<T> {
    match previous {
        Some(previous) if **previous == *value => Rc::clone(previous),
        _ => Rc::new(value.clone()),
    }
}
