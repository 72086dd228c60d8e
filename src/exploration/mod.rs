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
pub mod memory;
pub mod protocol;
mod replay;
mod search;

use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

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

/// What stopped a search before it covered every path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Limit {
    /// The state budget ([`Budget::States`]).
    States,
    /// The time budget ([`Budget::Time`]).
    Time,
    /// The memory budget ([`ExploreOptions::memory`]): the process's resident set reached it.
    Memory,
}

/// One of `count` processes that split a search between them (`kairos explore --shard i/n`).
///
/// The search deals the branches off the fault-free path out by their ordinal (the module
/// documentation, "Parallel and deterministic"); shard `index` of `count` running `jobs`
/// workers is workers `index + count × w` (w < jobs) of a search with `count × jobs` workers, so
/// the shards of one search together are that search, whatever `jobs` each uses, and their
/// merge ([`merge`]) gives what one process finds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// This process's shard, `0 ≤ index < count`.
    pub index: u64,
    /// The number of shards.
    pub count: u64,
}

impl Shard {
    /// The whole search in one process.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };
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
    /// Stop, as a budget does, once the process holds this many bytes (its resident set,
    /// [`memory::resident_bytes`]).
    pub memory: u64,
    /// Which part of the search this process explores.
    pub shard: Shard,
}

impl Default for ExploreOptions {
    fn default() -> Self {
        ExploreOptions {
            faults: 1,
            depth: None,
            budget: Budget::Unbounded,
            jobs: 1,
            memory: memory::DEFAULT_BUDGET,
            shard: Shard::WHOLE,
        }
    }
}

/// An optional rule firing on a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Choice {
    /// The cycle it fired at.
    pub cycle: u64,
    /// The rule, by index into the script's rules.
    pub rule: usize,
}

/// Where a timed response with an interval landed on a path (one per rule: its first firing's
/// delay is kept for the later ones).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
pub struct Delivery {
    /// The cycle.
    pub cycle: u64,
    /// The rules whose effects were applied, in that order.
    pub order: Vec<usize>,
}

/// What a counterexample shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// What cut the search, when something did.
    pub limit: Option<Limit>,
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
    /// A shard outside its count.
    #[error("shard {0}/{1} does not exist: a shard is i/n with 0 ≤ i < n")]
    Shard(u64, u64),
}

/// Explores every path of `scenario` the options allow (of them, the part
/// [`ExploreOptions::shard`] names); `progress` is told of new states (in batches) from every
/// worker.
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
    let shard = options.shard;
    if shard.count == 0 || shard.index >= shard.count {
        return Err(ExploreError::Shard(shard.index, shard.count));
    }
    let started = Instant::now();
    let jobs = options.jobs.max(1);
    // A time budget too long for the clock to represent is no deadline at all.
    let deadline = match options.budget {
        Budget::Time(limit) => started.checked_add(limit),
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
    // The shard's workers are workers `index + count × w` of the whole search's `count × jobs`.
    let workers = (jobs as u64).saturating_mul(shard.count);
    let work = |w: usize| {
        let limits = search::Limits {
            faults: options.faults,
            depth: options.depth,
            states,
            deadline,
            memory: options.memory,
        };
        let worker = shard.index + shard.count * w as u64;
        search::Worker::new(scenario, limits, worker, workers, progress).run()
    };
    let results: Vec<Result<search::Outcome, BuildError>> = match pool {
        Some(pool) => pool.install(|| (0..jobs).into_par_iter().map(work).collect()),
        // Without a pool of its own the search still runs, on the global one.
        None => (0..jobs).into_par_iter().map(work).collect(),
    };
    let mut merged = Exploration::empty(scenario.expectations.len());
    for result in results {
        merged.add(result?.into());
    }
    merged.wall = started.elapsed();
    Ok(merged)
}

/// Joins the explorations of the shards of one search (each run with the same scenario,
/// faults, depth and budget, and [`Shard`]s `0/n` to `n−1/n`) into what one process finds: the
/// counts added, the shortest counterexample of each finding kept, the coverage the least
/// of theirs, the wall time the longest.
pub fn merge(shards: Vec<Exploration>) -> Exploration {
    let expectations = shards.first().map_or(0, |s| s.failing_paths.len());
    let mut merged = Exploration::empty(expectations);
    for shard in shards {
        let wall = merged.wall.max(shard.wall);
        merged.add(shard);
        merged.wall = wall;
    }
    merged
}

impl Exploration {
    /// Nothing explored yet, for a scenario with `expectations` expectations.
    fn empty(expectations: usize) -> Self {
        Exploration {
            states: 0,
            paths: PathCounts::default(),
            longest: 0,
            counterexamples: Vec::new(),
            failing_paths: vec![0; expectations],
            cut_at: None,
            limit: None,
            wall: Duration::ZERO,
        }
    }

    /// Adds what `other` (disjoint work of the same search) found.
    fn add(&mut self, other: Exploration) {
        self.states += other.states;
        self.paths.add(&other.paths);
        self.longest = self.longest.max(other.longest);
        for (total, count) in self.failing_paths.iter_mut().zip(&other.failing_paths) {
            *total += count;
        }
        if other
            .cut_at
            .is_some_and(|b| self.cut_at.is_none_or(|a| b < a))
        {
            self.cut_at = other.cut_at;
            self.limit = other.limit;
        }
        for candidate in other.counterexamples {
            keep_shortest(&mut self.counterexamples, candidate);
        }
        self.counterexamples.sort_by_key(|c| match &c.finding {
            Finding::Violated { expectation, .. } => *expectation,
            Finding::Error(_) => usize::MAX,
        });
        self.wall += other.wall;
    }
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
