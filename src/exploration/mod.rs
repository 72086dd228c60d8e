//! Formal exploration (`kairos explore`; DESIGN.md §16, thesis §8.1's "model checking of timed
//! model-based programs"): an explicit-state search over every path the nondeterminism a
//! scenario declares open allows, with every expectation of the scenario checked on every path.
//!
//! # What is open
//! A scripted scenario is one path. Its rules with an `Optional(from:, to:, every:)` trigger
//! (the scenario format, [`crate::simulation`]) are the open part: each may fire once at any
//! cycle of its window whose number is a multiple of `every`, or never, with at most
//! [`ExploreOptions::faults`] of them per path. Everything else — the executive, the rest of the
//! script — is deterministic, so the paths are exactly the choices of which optional rules fire
//! and when, where in its interval each timed response lands, and in which order simultaneous
//! deliveries are applied.
//!
//! # Timed responses and delivery orders
//! A rule with `after: Between(from, to)` lands its effect at any cycle whose time is in
//! [fired + from, fired + to] (the cycles in it, or the first after `from` when none is; one
//! cycle past the scenario's end stands for every later one). The delay is chosen at the rule's
//! first firing on a path and kept for its later ones (`simulation::script::open` says why);
//! the path that takes the lower bound — what `kairos run` does — goes on, every later landing
//! is a branch. When effects due in one cycle contend (write a common name differently), the
//! search branches over one order per distinct outcome; otherwise it does not branch. Neither
//! counts as a fault ([`ExploreOptions::faults`] bounds optional rules only). A counterexample
//! pins its landings in `choose` (the delay) and its orders in `deliver`, so it replays.
//!
//! # The search
//! A depth-first walk (memory: one saved state per fault on the current path, rather than a
//! breadth-first frontier of thousands of executives). A *state* is the executive's whole state
//! (cloned: [`Executive`] is `Clone`, its SAT solver rebuilt from its clauses), the scripted
//! plant's and the expectation checker's; states are deduplicated by a 64-bit fingerprint of
//! the three ([`Executive::fingerprint`]: the belief rounded to
//! [`crate::executive::PROBABILITY_RESOLUTION`], marking, clocks, intended configuration, last
//! command, what was reported; the plant's values, pending effects and fired rules; each
//! expectation's progress). The cycle number is part of the state, so two paths meeting in one
//! state have the same length: the pruned one is no shorter. A state met again with no more
//! faults left to spend is not explored again.
//!
//! Every expectation is checked on every path: a never-expectation (or a broken sequence)
//! fails at the cycle that shows it; an eventual one at the path's end (the scenario's end, or
//! once the run has settled and no optional rule can fire any more). For each violated
//! expectation the search keeps the *shortest* counterexample: fewest cycles to the violation,
//! then fewest optional rules fired, then earliest firings. A cycle the executive refuses
//! (an error) is a counterexample too ([`Finding::Error`]).
//!
//! # Parallel and deterministic
//! The executive holds a SAT solver that cannot move between threads, so workers share no
//! states: each of `jobs` rayon workers walks the fault-free path itself and explores the
//! branches off it whose ordinal is its own modulo `jobs`. Results are merged in a fixed order,
//! so a search gives the same answer for any number of workers and on any run (a time budget
//! aside, which cuts where the clock says). A state budget is split evenly among the workers.
//!
//! # The controller protocol
//! [`protocol`] is the same kind of search over the MDS controller protocol (seed 001): every
//! interleaving of its messages for a rover scenario, the properties of mds-goal-networks.md §4.2
//! checked on each.
//!
//! [`Executive`]: crate::executive::Executive
//! [`Executive::fingerprint`]: crate::executive::Executive::fingerprint

pub mod deep;
mod landing;
pub mod protocol;
mod replay;
mod search;

use std::time::{Duration, Instant};

use rayon::prelude::*;

pub use replay::{replay_scenario, replay_text};

use crate::executive::BuildError;
use crate::simulation::Scenario;

/// How far a search may go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Budget {
    /// No bound but the scenario's own (its end, its windows, the fault bound).
    Unbounded,
    /// At most this many states (split evenly among the workers).
    States(u64),
    /// At most this much wall time.
    Time(Duration),
}

/// A search's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExploreOptions {
    /// At most this many optional rules fire on a path.
    pub faults: usize,
    /// Paths are cut after this many cycles (their eventual expectations are then not judged).
    pub depth: Option<u64>,
    /// When to stop.
    pub budget: Budget,
    /// Workers (at least 1).
    pub jobs: usize,
}

impl Default for ExploreOptions {
    fn default() -> Self {
        ExploreOptions {
            faults: 1,
            depth: None,
            budget: Budget::Unbounded,
            jobs: 1,
        }
    }
}

/// An optional rule firing on a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Choice {
    /// The cycle it fired at.
    pub cycle: u64,
    /// The rule, by index into the script's rules.
    pub rule: usize,
}

/// Where a timed response with an interval landed on a path (one per rule: its first firing's
/// delay is kept for the later ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Landing {
    /// The rule, by index into the script's rules.
    pub rule: usize,
    /// The cycle it first fired at.
    pub fired: u64,
    /// The cycle its effect landed at.
    pub lands: u64,
}

/// The order simultaneous effects were applied in at a cycle, where it differed from the
/// order their rules fired.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Delivery {
    /// The cycle.
    pub cycle: u64,
    /// The rules whose effects were applied, in that order.
    pub order: Vec<usize>,
}

/// What a counterexample shows.
#[derive(Debug, Clone, PartialEq)]
pub enum Finding {
    /// This expectation (by index) does not hold on the path.
    Violated {
        /// Its index in the scenario's expectations.
        expectation: usize,
        /// Its label.
        label: String,
        /// Why it fails, as the checker words it.
        reason: String,
    },
    /// The executive or the plant refused a cycle of the path.
    Error(String),
}

/// A path on which something fails, the shortest found.
#[derive(Debug, Clone, PartialEq)]
pub struct Counterexample {
    /// What fails.
    pub finding: Finding,
    /// The cycle at which it shows (for an eventual expectation, the path's last).
    pub cycle: u64,
    /// The optional rules that fired, in order.
    pub choices: Vec<Choice>,
    /// The timed responses that landed later than their interval's lower bound.
    pub landings: Vec<Landing>,
    /// The cycles whose simultaneous effects were applied out of their fired order.
    pub deliveries: Vec<Delivery>,
}

impl Counterexample {
    /// The ordering that makes one counterexample shorter than another: cycles, then the
    /// number of firings, then the firings themselves, then the other choices.
    fn key(&self) -> (u64, usize, &[Choice], usize, &[Landing], &[Delivery]) {
        (
            self.cycle,
            self.choices.len(),
            &self.choices,
            self.landings.len() + self.deliveries.len(),
            &self.landings,
            &self.deliveries,
        )
    }
}

/// How paths ended.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PathCounts {
    /// Reached the scenario's end time.
    pub ended: u64,
    /// Settled earlier: nothing more could happen.
    pub settled: u64,
    /// Cut at the depth bound.
    pub truncated: u64,
    /// Met a state another path had reached: explored once.
    pub merged: u64,
    /// Stopped by an error.
    pub errors: u64,
}

impl PathCounts {
    /// Paths followed to an end of their own (not merged into another).
    pub fn complete(&self) -> u64 {
        self.ended + self.settled + self.truncated + self.errors
    }

    fn add(&mut self, other: &PathCounts) {
        self.ended += other.ended;
        self.settled += other.settled;
        self.truncated += other.truncated;
        self.merged += other.merged;
        self.errors += other.errors;
    }
}

/// What a search found and covered.
#[derive(Debug, Clone, PartialEq)]
pub struct Exploration {
    /// Distinct states visited (the fault-free path's counted once).
    pub states: u64,
    /// How the paths ended.
    pub paths: PathCounts,
    /// The longest path, in cycles.
    pub longest: u64,
    /// The shortest counterexample of each violated expectation (in the scenario's order),
    /// then the first error, if any.
    pub counterexamples: Vec<Counterexample>,
    /// Per expectation, how many of the paths followed to their own end violate it (a path
    /// merged into another is counted with that one).
    pub failing_paths: Vec<u64>,
    /// `None` when the search covered every path; otherwise the earliest cycle from which it
    /// did not: every path whose first choice (an optional rule firing, a landing later than
    /// its lower bound, an order other than the fired one) falls before it was covered.
    pub cut_at: Option<u64>,
    /// Wall time.
    pub wall: Duration,
}

impl Exploration {
    /// True when every path was covered and nothing failed.
    pub fn holds(&self) -> bool {
        self.cut_at.is_none() && self.counterexamples.is_empty()
    }
}

/// Why a search could not start.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExploreError {
    /// The executive could not be built.
    #[error("the executive cannot be built: {0}")]
    Build(#[from] BuildError),
    /// Only scripted plants are explored.
    #[error(
        "a model-driven plant (`simulator: Model(...)`) draws its own faults; `kairos explore` explores a script's `Optional` rules"
    )]
    ModelDriven,
    /// A scenario whose `choose` or `deliver` pins its choices is one path (a replay).
    #[error(
        "the scenario pins its choices with `choose` or `deliver` (a replay is one path): explore the scenario without them"
    )]
    Pinned,
}

/// Explores every path of `scenario` the options allow; `progress` is told of new states (in
/// batches) from every worker.
pub fn explore(
    scenario: &Scenario,
    options: &ExploreOptions,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Exploration, ExploreError> {
    if scenario.model.is_some() {
        return Err(ExploreError::ModelDriven);
    }
    if !scenario.script.pinned().is_empty() || !scenario.script.deliveries().is_empty() {
        return Err(ExploreError::Pinned);
    }
    let started = Instant::now();
    let jobs = options.jobs.max(1);
    let deadline = match options.budget {
        Budget::Time(limit) => Some(started + limit),
        _ => None,
    };
    let states = match options.budget {
        Budget::States(n) => Some(n.div_ceil(jobs as u64)),
        _ => None,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .ok();
    let work = |worker: usize| {
        let limits = search::Limits {
            faults: options.faults,
            depth: options.depth,
            states,
            deadline,
        };
        search::Worker::new(scenario, limits, worker, jobs, progress).run()
    };
    let results: Vec<Result<search::Outcome, BuildError>> = match pool {
        Some(pool) => pool.install(|| (0..jobs).into_par_iter().map(work).collect()),
        // Without a pool of its own the search still runs, on the global one.
        None => (0..jobs).into_par_iter().map(work).collect(),
    };
    let mut merged = Exploration {
        states: 0,
        paths: PathCounts::default(),
        longest: 0,
        counterexamples: Vec::new(),
        failing_paths: vec![0; scenario.expectations.len()],
        cut_at: None,
        wall: Duration::ZERO,
    };
    let mut found: Vec<Counterexample> = Vec::new();
    for result in results {
        let outcome = result?;
        merged.states += outcome.states;
        merged.paths.add(&outcome.paths);
        merged.longest = merged.longest.max(outcome.longest);
        for (total, count) in merged.failing_paths.iter_mut().zip(&outcome.failing_paths) {
            *total += count;
        }
        merged.cut_at = match (merged.cut_at, outcome.cut_at) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        for candidate in outcome.found {
            keep_shortest(&mut found, candidate);
        }
    }
    found.sort_by_key(|c| match &c.finding {
        Finding::Violated { expectation, .. } => *expectation,
        Finding::Error(_) => usize::MAX,
    });
    merged.counterexamples = found;
    merged.wall = started.elapsed();
    Ok(merged)
}

/// Keeps `candidate` if it is the first counterexample of its finding or shorter than the one
/// kept.
fn keep_shortest(found: &mut Vec<Counterexample>, candidate: Counterexample) {
    let same = |c: &Counterexample| match (&c.finding, &candidate.finding) {
        (Finding::Violated { expectation: a, .. }, Finding::Violated { expectation: b, .. }) => {
            a == b
        }
        (Finding::Error(_), Finding::Error(_)) => true,
        _ => false,
    };
    match found.iter_mut().find(|c| same(c)) {
        Some(kept) if candidate.key() < kept.key() => *kept = candidate,
        Some(_) => {}
        None => found.push(candidate),
    }
}
