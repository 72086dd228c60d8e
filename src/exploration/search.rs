//! One worker's depth-first walk (the module documentation of `exploration` has the design).

use std::collections::hash_map::DefaultHasher;
use std::hash::Hasher;
use std::time::Instant;

use rustc_hash::FxHashMap;

use super::{Choice, Counterexample, Delivery, Exploration, Finding, Landing, Limit, PathCounts};
use super::{keep_shortest, landing, memory};
use crate::executive::adapters::{ControlAdapter, MonitorAdapter};
use crate::executive::{BuildError, Executive, NamedValue, Retention, Step};
use crate::simulation::{
    Checker, Names, RunOptions, Scenario, ScriptedPlant, Verdict, build_executive, report_refusals,
    submit_due,
};

/// Two times closer than this are the same instant (as in the scripted plant).
const TIME_EPSILON: f64 = 1e-6;

/// New states are reported to the progress callback in batches of this many.
const PROGRESS_BATCH: u64 = 1024;

/// What bounds a worker's walk.
pub(super) struct Limits {
    pub(super) faults: usize,
    pub(super) depth: Option<u64>,
    pub(super) states: Option<u64>,
    pub(super) deadline: Option<Instant>,
    /// Bytes the process may hold ([`memory::resident_bytes`]).
    pub(super) memory: u64,
}

/// What a worker found.
pub(super) struct Outcome {
    pub(super) states: u64,
    pub(super) paths: PathCounts,
    pub(super) longest: u64,
    pub(super) found: Vec<Counterexample>,
    pub(super) failing_paths: Vec<u64>,
    pub(super) cut_at: Option<u64>,
    pub(super) limit: Option<Limit>,
}

impl From<Outcome> for Exploration {
    fn from(outcome: Outcome) -> Self {
        Exploration {
            states: outcome.states,
            paths: outcome.paths,
            longest: outcome.longest,
            // One per finding already ([`Worker::record`] keeps the shortest).
            counterexamples: outcome.found,
            failing_paths: outcome.failing_paths,
            cut_at: outcome.cut_at,
            limit: outcome.limit,
            wall: std::time::Duration::ZERO,
        }
    }
}

/// A state of the search: the executive, the plant and the checker, with the path's choices.
#[derive(Clone)]
struct Node<'s> {
    executive: Executive,
    plant: ScriptedPlant<'s>,
    checker: Checker<'s>,
    choices: Vec<Choice>,
    /// Timed responses landed later than their lower bound.
    landings: Vec<Landing>,
    /// Simultaneous effects applied out of their fired order.
    deliveries: Vec<Delivery>,
    /// The next cycle to run.
    cycle: u64,
}

/// Whether a path goes on after a cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Next {
    Continue,
    Stop,
}

/// One worker: the fault-free path (every worker walks it) and the branches off it it owns.
pub(super) struct Worker<'s, 'p> {
    scenario: &'s Scenario,
    limits: Limits,
    /// This worker's number among `workers` (of every shard).
    worker: u64,
    workers: u64,
    progress: &'p (dyn Fn(u64) + Sync),
    /// Fingerprint → fewest optional rules fired on a path that reached the state.
    visited: FxHashMap<u64, usize>,
    states: u64,
    unreported: u64,
    paths: PathCounts,
    longest: u64,
    found: Vec<Counterexample>,
    /// Per expectation, the paths followed to their end on which it fails.
    failing_paths: Vec<u64>,
    /// Branches met along the fault-free path so far (they are dealt out by this number).
    ordinal: u64,
    /// The fault-free path's current cycle: paths whose first firing is earlier are covered.
    spine_cycle: u64,
    cut_at: Option<u64>,
    limit: Option<Limit>,
    /// New states since the resident set was last read.
    unchecked: u64,
    /// The memory budget was reached.
    out_of_memory: bool,
}

impl<'s, 'p> Worker<'s, 'p> {
    pub(super) fn new(
        scenario: &'s Scenario,
        limits: Limits,
        worker: u64,
        workers: u64,
        progress: &'p (dyn Fn(u64) + Sync),
    ) -> Self {
        Worker {
            scenario,
            limits,
            worker,
            workers,
            progress,
            visited: FxHashMap::default(),
            states: 0,
            unreported: 0,
            paths: PathCounts::default(),
            longest: 0,
            found: Vec::new(),
            failing_paths: vec![0; scenario.expectations.len()],
            ordinal: 0,
            spine_cycle: 0,
            cut_at: None,
            limit: None,
            unchecked: 0,
            out_of_memory: false,
        }
    }

    /// Walks every path this worker owns.
    pub(super) fn run(mut self) -> Result<Outcome, BuildError> {
        let scenario = self.scenario;
        // The timelines are history no decision reads: a short one keeps the clones small.
        let retention = Retention {
            intervals: 1,
            commands: 1,
            observations: 1,
        };
        let options = RunOptions {
            retention: Some(retention),
            ..RunOptions::default()
        };
        let mut plant = ScriptedPlant::new(&scenario.script);
        plant.leave_open();
        let root = Node {
            executive: build_executive(scenario, options)?,
            plant,
            checker: Checker::new(
                &scenario.expectations,
                Names {
                    plant: &scenario.plant,
                    world: &scenario.script.world,
                    controls: &scenario.script.controls,
                },
            ),
            choices: Vec::new(),
            landings: Vec::new(),
            deliveries: Vec::new(),
            cycle: 0,
        };
        self.walk(root, true);
        (self.progress)(self.unreported);
        Ok(Outcome {
            states: self.states,
            paths: self.paths,
            longest: self.longest,
            found: self.found,
            failing_paths: self.failing_paths,
            cut_at: self.cut_at,
            limit: self.limit,
        })
    }

    /// Follows `node`'s path to its end, branching into every alternative at every cycle (on
    /// the fault-free path, into the alternatives this worker owns): which optional rules fire,
    /// in which order contending effects due are applied (the fired order is the node's own),
    /// and where timed responses fired in the cycle land ([`Worker::land`]).
    fn walk(&mut self, mut node: Node<'s>, spine: bool) {
        loop {
            if spine {
                self.spine_cycle = node.cycle;
            }
            if self.cut_if_out_of_budget() {
                return;
            }
            let orders = (node.plant).delivery_orders(node.cycle, self.time(node.cycle));
            let (candidates, left) = self.alternatives(&node);
            for (k, order) in orders.iter().enumerate() {
                // The fired order without an optional rule is the node's own path.
                let none = (k > 0).then(Vec::new);
                for forced in none.into_iter().chain(Subsets::new(&candidates, left)) {
                    // Many alternatives may end in their first cycle (a rule whose condition
                    // does not hold): the budget is checked before each, not only on paths.
                    if self.cut_if_out_of_budget() {
                        return;
                    }
                    if !self.owns(spine) {
                        continue;
                    }
                    let mut child = node.clone();
                    if k > 0 {
                        child.plant.force_order(order);
                        let cycle = node.cycle;
                        let order = order.clone();
                        child.deliveries.push(Delivery { cycle, order });
                    }
                    self.branch(child, &forced);
                    if self.cut_at.is_some() {
                        return;
                    }
                }
            }
            if self.advance(&mut node, &[], spine) == Next::Stop {
                return;
            }
            self.land(&mut node, spine);
            if self.cut_at.is_some() {
                return;
            }
        }
    }

    /// Runs a branch's first cycle with the `forced` optional rules and walks on from it.
    fn branch(&mut self, mut child: Node<'s>, forced: &[usize]) {
        if self.advance(&mut child, forced, false) == Next::Continue {
            self.land(&mut child, false);
            if self.cut_at.is_none() {
                self.walk(child, false);
            }
        }
    }

    /// True when this worker explores the next alternative: every one off a branch, and those
    /// off the fault-free path whose ordinal is its own modulo the workers.
    fn owns(&mut self, spine: bool) -> bool {
        !spine || {
            let ordinal = self.ordinal;
            self.ordinal += 1;
            ordinal % self.workers == self.worker
        }
    }

    /// Chooses where the timed responses fired in `node`'s last cycle land: `node` takes each
    /// one's interval's lower bound (what a run does), and every later landing cycle is a
    /// branch walked from here.
    fn land(&mut self, node: &mut Node<'s>, spine: bool) {
        let scenario = self.scenario;
        while let Some(open) = node.plant.open_landing() {
            let cycles = landing::cycles(scenario, open, node.cycle);
            for &lands in cycles.iter().skip(1) {
                if !self.owns(spine) {
                    continue;
                }
                let mut child = node.clone();
                child
                    .plant
                    .land(open.rule, landing::delay(scenario, open, lands));
                let fired = landing::cycle_of(scenario, open.fired);
                let rule = open.rule;
                child.landings.push(Landing { rule, fired, lands });
                self.land(&mut child, false);
                if self.cut_at.is_none() {
                    self.walk(child, false);
                }
                if self.cut_at.is_some() {
                    return;
                }
            }
            node.plant
                .land(open.rule, landing::lower_bound(scenario, open));
        }
    }

    /// True, with the cut recorded, when a limit is reached.
    fn cut_if_out_of_budget(&mut self) -> bool {
        match self.out_of_budget() {
            Some(limit) => {
                self.cut_at = Some(self.spine_cycle);
                self.limit = Some(limit);
                true
            }
            None => false,
        }
    }

    /// The limit the search has reached, if any.
    fn out_of_budget(&self) -> Option<Limit> {
        let states = self
            .limits
            .states
            .is_some_and(|limit| self.visited.len() as u64 >= limit);
        if states {
            Some(Limit::States)
        } else if self.limits.deadline.is_some_and(|d| Instant::now() >= d) {
            Some(Limit::Time)
        } else if self.out_of_memory {
            Some(Limit::Memory)
        } else {
            None
        }
    }

    /// Reads the resident set once every [`memory::CHECK_EVERY`] new states.
    fn check_memory(&mut self) {
        self.unchecked += 1;
        if self.unchecked >= memory::CHECK_EVERY {
            self.unchecked = 0;
            self.out_of_memory |=
                memory::resident_bytes().is_some_and(|bytes| bytes >= self.limits.memory);
        }
    }

    /// The optional rules that may fire at `node`'s next cycle, and how many of them may fire
    /// together (the faults left): the alternatives to none are every non-empty set of at most
    /// that many ([`Subsets`]).
    fn alternatives(&self, node: &Node<'s>) -> (Vec<usize>, usize) {
        let left = self.limits.faults.saturating_sub(node.choices.len());
        if left == 0 {
            return (Vec::new(), 0);
        }
        let time = self.time(node.cycle);
        let script = &self.scenario.script;
        let candidates: Vec<usize> = (script.rules().iter().enumerate())
            .filter(|(i, rule)| {
                rule.trigger.may_fire_at(node.cycle, time)
                    && node.plant.times_fired(*i) == 0
                    && !script.pinned().iter().any(|(p, _)| p == i)
            })
            .map(|(i, _)| i)
            .collect();
        (candidates, left)
    }

    fn time(&self, cycle: u64) -> f64 {
        cycle as f64 * self.scenario.cycle
    }

    /// Runs `node`'s next cycle with the `forced` optional rules, checks the expectations and
    /// whether the path ends, merges, or goes on. `spine`: a cycle of the fault-free path,
    /// which only worker 0 counts (every worker walks it).
    fn advance(&mut self, node: &mut Node<'s>, forced: &[usize], spine: bool) -> Next {
        let cycle = node.cycle;
        let time = self.time(cycle);
        let step = match run_cycle(node, forced, time) {
            Ok(step) => step,
            Err(message) => {
                self.paths.errors += u64::from(self.counts(spine));
                let finding = Finding::Error(message);
                self.record(finding, cycle, node);
                return Next::Stop;
            }
        };
        let took = forced.iter().filter(|&&rule| {
            node.plant
                .first_fired(rule)
                .is_some_and(|(c, _)| c == cycle)
        });
        if took.clone().count() < forced.len() {
            // A rule whose condition did not hold: the path is another one's (firing fewer).
            return Next::Stop;
        }
        node.choices
            .extend(took.map(|&rule| Choice { cycle, rule }).collect::<Vec<_>>());
        node.cycle += 1;
        self.longest = self.longest.max(node.cycle);
        let failed: Vec<(usize, String)> = (node.checker.failed())
            .map(|(i, reason)| (i, reason.to_string()))
            .collect();
        for (expectation, reason) in failed {
            let finding = self.violated(expectation, reason);
            self.record(finding, cycle, node);
        }
        if !self.first_visit(node, spine) {
            self.paths.merged += 1;
            return Next::Stop;
        }
        self.path_end(node, &step, time, spine)
    }

    /// Whether this worker counts what happens on the path: every worker walks the fault-free
    /// path, worker 0 counts it.
    fn counts(&self, spine: bool) -> bool {
        !spine || self.worker == 0
    }

    /// True when `node`'s state is new, or was reached before only with more faults spent.
    fn first_visit(&mut self, node: &Node<'s>, spine: bool) -> bool {
        let mut hasher = DefaultHasher::new();
        node.executive.fingerprint(&mut hasher);
        node.plant.fingerprint(&mut hasher);
        node.checker.fingerprint(&mut hasher);
        let key = hasher.finish();
        let spent = node.choices.len();
        if self
            .visited
            .get(&key)
            .is_some_and(|&before| before <= spent)
        {
            return false;
        }
        self.visited.insert(key, spent);
        self.check_memory();
        if self.counts(spine) {
            self.states += 1;
            self.unreported += 1;
            if self.unreported >= PROGRESS_BATCH {
                (self.progress)(self.unreported);
                self.unreported = 0;
            }
        }
        true
    }

    /// Whether the path ends after the cycle at `time`, judging its eventual expectations if so.
    fn path_end(&mut self, node: &Node<'s>, step: &Step, time: f64, spine: bool) -> Next {
        let counted = u64::from(self.counts(spine));
        let end = self.scenario.end;
        let last = self.time(node.cycle) > end + TIME_EPSILON || time >= end - TIME_EPSILON;
        if last {
            self.paths.ended += counted;
            self.finish(node, counted);
            return Next::Stop;
        }
        if self.limits.depth.is_some_and(|depth| node.cycle >= depth) {
            self.paths.truncated += counted;
            return Next::Stop;
        }
        let settled = step.is_settled()
            && node.plant.is_quiet(end)
            && !node.checker.awaits_something()
            && !self.may_branch_later(node);
        if settled {
            self.paths.settled += counted;
            self.finish(node, counted);
            return Next::Stop;
        }
        Next::Continue
    }

    /// True while an optional rule could still fire on this path.
    fn may_branch_later(&self, node: &Node<'s>) -> bool {
        if node.choices.len() >= self.limits.faults {
            return false;
        }
        let now = self.time(node.cycle);
        let script = &self.scenario.script;
        script
            .rules()
            .iter()
            .enumerate()
            .any(|(i, rule)| match rule.trigger {
                crate::simulation::Trigger::Optional { to, .. } => {
                    node.plant.times_fired(i) == 0 && to >= now - TIME_EPSILON
                }
                _ => false,
            })
    }

    /// Judges the path's expectations at its end (`counted`: 1 if this worker counts the path).
    fn finish(&mut self, node: &Node<'s>, counted: u64) {
        let last = node.cycle.saturating_sub(1);
        let verdicts: Vec<Verdict> = node.checker.finish(&node.plant);
        for (expectation, verdict) in verdicts.into_iter().enumerate() {
            if let crate::simulation::Outcome::Failed { reason } = verdict.outcome {
                self.failing_paths[expectation] += counted;
                let finding = self.violated(expectation, reason);
                self.record(finding, last, node);
            }
        }
    }

    fn violated(&self, expectation: usize, reason: String) -> Finding {
        Finding::Violated {
            expectation,
            label: self.scenario.expectations[expectation].label.clone(),
            reason,
        }
    }

    fn record(&mut self, finding: Finding, cycle: u64, node: &Node<'s>) {
        let candidate = Counterexample {
            finding,
            cycle,
            choices: node.choices.clone(),
            landings: node.landings.clone(),
            deliveries: node.deliveries.clone(),
        };
        keep_shortest(&mut self.found, candidate);
    }
}

/// One cycle of `node`: the plant (with the forced rules) reports, the executive steps, the
/// command goes to the plant, the checker sees the step — as `simulation::run` does.
fn run_cycle(node: &mut Node<'_>, forced: &[usize], time: f64) -> Result<Step, String> {
    node.plant.force(forced);
    let observation = node.plant.observe(time);
    let refused = submit_due(&mut node.plant, &mut node.executive);
    let mut step = (node.executive.step(time, &observation)).map_err(|e| e.to_string())?;
    report_refusals(&mut step, refused);
    let command: Vec<NamedValue> = (step.command.iter())
        .map(|&(x, v)| NamedValue::of(node.executive.plant(), x, v))
        .collect();
    node.plant
        .send(time, &command)
        .map_err(|message| format!("the plant refused the command at {time} s: {message}"))?;
    node.plant.estimated(&step.most_likely);
    node.plant.take_events();
    node.checker.observe(&step, &node.plant);
    Ok(step)
}

/// Every non-empty subset of `items` with at most `max` elements, smallest first and, among
/// those of one size, in lexicographic order of positions. They are made one at a time: with
/// many optional rules and many faults their number, the sum of C(n, k), is far too large to
/// hold (30 rules and 30 faults: 2³⁰ sets), while a search walks them in order and a budget
/// stops it.
struct Subsets<'a> {
    items: &'a [usize],
    max: usize,
    /// The positions of the last subset given; empty before the first.
    positions: Vec<usize>,
    done: bool,
}

impl<'a> Subsets<'a> {
    fn new(items: &'a [usize], max: usize) -> Self {
        Subsets {
            items,
            max: max.min(items.len()),
            positions: Vec::new(),
            done: false,
        }
    }

    /// Moves `positions` to the next subset of its size; false after the last one.
    fn advance(&mut self) -> bool {
        let (n, k) = (self.items.len(), self.positions.len());
        let Some(i) = (0..k).rev().find(|&i| self.positions[i] < n - k + i) else {
            return false;
        };
        self.positions[i] += 1;
        for j in i + 1..k {
            self.positions[j] = self.positions[j - 1] + 1;
        }
        true
    }
}

impl Iterator for Subsets<'_> {
    type Item = Vec<usize>;

    fn next(&mut self) -> Option<Vec<usize>> {
        if self.done {
            return None;
        }
        if !self.advance() {
            let size = self.positions.len() + 1;
            if size > self.max {
                self.done = true;
                return None;
            }
            self.positions = (0..size).collect();
        }
        Some(self.positions.iter().map(|&p| self.items[p]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::Subsets;

    /// The brute-force oracle: every bit mask of the items, kept when its size is 1 to `max`,
    /// ordered by size then by the positions.
    fn oracle(items: &[usize], max: usize) -> Vec<Vec<usize>> {
        let mut all: Vec<Vec<usize>> = (1u32..1 << items.len())
            .map(|mask| {
                (0..items.len())
                    .filter(|&i| mask & (1 << i) != 0)
                    .map(|i| items[i])
                    .collect::<Vec<usize>>()
            })
            .filter(|set| set.len() <= max)
            .collect();
        all.sort_by(|a, b| a.len().cmp(&b.len()).then_with(|| a.cmp(b)));
        all
    }

    #[test]
    fn subsets_are_every_small_set_in_order() {
        for n in 0..7 {
            let items: Vec<usize> = (0..n).map(|i| 3 * i + 1).collect();
            for max in 0..n + 2 {
                let made: Vec<Vec<usize>> = Subsets::new(&items, max).collect();
                assert_eq!(made, oracle(&items, max), "n = {n}, max = {max}");
            }
        }
    }

    /// Thirty rules and thirty faults: the first sets come at once, none is held beyond the
    /// one given.
    #[test]
    fn subsets_of_many_rules_are_made_lazily() {
        let items: Vec<usize> = (0..30).collect();
        let first: Vec<Vec<usize>> = Subsets::new(&items, 30).take(31).collect();
        assert_eq!(first[29], vec![29]);
        assert_eq!(first[30], vec![0, 1]);
    }
}
