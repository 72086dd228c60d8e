//! Decomposition into independent sub-problems and the best-first merge of their solutions.
//!
//! Decision variables that share no constraint (directly or through other variables) form
//! independent sub-problems: a full assignment is feasible exactly when its restriction to each
//! sub-problem is. With additive costs the best global solutions are sums of per-sub-problem
//! solutions, so each sub-problem is searched on its own ([`ComponentSearch`]) and their sorted
//! streams are merged lazily: a global solution is a tuple of stream indices; the frontier starts
//! at all zeros, and a popped tuple's successors increment one position at or after its last
//! non-zero one, which generates each tuple exactly once and never before a cheaper one.
//!
//! A successor's cost needs the next solution of one stream, which may take a search. So a
//! successor enters the frontier *pending*, at its parent's cost — a lower bound, since streams
//! are sorted — and its solution is fetched only when it reaches the front; then it re-enters at
//! its true cost. Asking for the best solution of many independent sub-problems therefore
//! searches each sub-problem once, not twice.

use std::cmp::Reverse;
use std::collections::HashMap;

use petgraph::unionfind::UnionFind;
use priority_queue::PriorityQueue;

use super::ocsp::{Cut, Meter, Ocsp, SearchOptions, SearchStats, Solution};
use super::search::{ComponentSearch, Cost, FxBuildHasher, PartialSolution, Priority};
use super::shared::ConflictStore;
use super::theory::{Consistency, Literal, Theory};

struct Stream {
    search: ComponentSearch,
    found: Vec<PartialSolution>,
    done: bool,
}

impl Stream {
    /// Pulls solutions until the `index`-th is known; says whether it exists.
    fn ensure(
        &mut self,
        index: usize,
        ocsp: &Ocsp,
        theory: &mut Theory,
        options: &SearchOptions,
        mut shared: Option<&mut ConflictStore>,
        meter: &mut Meter,
    ) -> Result<bool, Cut> {
        while self.found.len() <= index && !self.done {
            let shared = shared.as_deref_mut();
            match self
                .search
                .next(ocsp, theory, options.use_conflicts, shared, meter)?
            {
                Some(solution) => self.found.push(solution),
                None => self.done = true,
            }
        }
        Ok(self.found.len() > index)
    }
}

/// A lazy, best-first enumeration of an OCSP's solutions; see [`Ocsp::enumerate`].
pub struct Enumeration<'a> {
    ocsp: &'a Ocsp,
    options: SearchOptions,
    meter: Meter,
    streams: Vec<Stream>,
    frontier: PriorityQueue<Entry, Priority, FxBuildHasher>,
    created: u64,
    state: State,
}

/// A frontier entry: a tuple of stream indices whose solutions are all known (`Ready`), or one
/// whose last-incremented stream has not produced that solution yet (`Pending`, at a lower bound).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Entry {
    Ready(Vec<u32>),
    Pending {
        tuple: Vec<u32>,
        /// The stream whose solution at `tuple[stream]` is still to be fetched.
        stream: usize,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    NotStarted,
    Running,
    Exhausted,
}

impl<'a> Enumeration<'a> {
    pub(crate) fn new(ocsp: &'a Ocsp, theory: &Theory, options: SearchOptions) -> Self {
        let streams: Vec<Stream> = partition(ocsp, theory, options.decompose)
            .into_iter()
            .map(|members| Stream {
                search: ComponentSearch::new(ocsp, members),
                found: Vec::new(),
                done: false,
            })
            .collect();
        let mut meter = Meter::new(options.budget);
        meter.stats.components = streams.len() as u64;
        Enumeration {
            ocsp,
            options,
            meter,
            streams,
            frontier: PriorityQueue::with_default_hasher(),
            created: 0,
            state: State::NotStarted,
        }
    }

    /// Work done so far.
    pub fn stats(&self) -> SearchStats {
        self.meter.stats
    }

    /// Gives the enumeration a fresh budget (after a [`Cut`]), keeping what it has learned.
    pub fn renew_budget(&mut self) {
        let stats = self.meter.stats;
        self.meter = Meter::new(self.options.budget);
        self.meter.stats = stats;
    }

    /// The next solution, cheapest first; `Ok(None)` when there are no more; `Err(cut)` when the
    /// budget ran out (call [`Enumeration::renew_budget`] to go on).
    pub fn next(&mut self, theory: &mut Theory) -> Result<Option<Solution>, Cut> {
        self.advance(theory, None)
    }

    /// [`Enumeration::next`], reading and extending `shared` with conflicts when it is a store
    /// for this OCSP's assumptions (and conflicts are on); otherwise it is left alone. The same
    /// solutions come out in the same order either way (`shared.rs`, "Why sharing is exact").
    pub fn next_sharing(
        &mut self,
        theory: &mut Theory,
        shared: &mut ConflictStore,
    ) -> Result<Option<Solution>, Cut> {
        let applies = self.options.use_conflicts && shared.assumptions() == self.ocsp.assumptions();
        self.advance(theory, applies.then_some(shared))
    }

    fn advance(
        &mut self,
        theory: &mut Theory,
        mut shared: Option<&mut ConflictStore>,
    ) -> Result<Option<Solution>, Cut> {
        if self.state == State::NotStarted {
            self.start(theory, shared.as_deref_mut())?;
        }
        if self.state == State::Exhausted {
            return Ok(None);
        }
        loop {
            let Some((entry, priority)) = self.frontier.pop() else {
                self.state = State::Exhausted;
                return Ok(None);
            };
            match entry {
                Entry::Ready(tuple) => {
                    self.push_successors(&tuple, priority);
                    return Ok(Some(self.combine(&tuple)));
                }
                Entry::Pending { tuple, stream } => {
                    let index = tuple[stream] as usize;
                    let fetched = self.streams[stream].ensure(
                        index,
                        self.ocsp,
                        theory,
                        &self.options,
                        shared.as_deref_mut(),
                        &mut self.meter,
                    );
                    match fetched {
                        Ok(true) => self.push_ready(tuple),
                        Ok(false) => {}
                        Err(cut) => {
                            // Leave the state as it was, so a renewed budget can go on.
                            self.frontier
                                .push(Entry::Pending { tuple, stream }, priority);
                            return Err(cut);
                        }
                    }
                }
            }
        }
    }

    fn start(
        &mut self,
        theory: &mut Theory,
        mut shared: Option<&mut ConflictStore>,
    ) -> Result<(), Cut> {
        self.meter.stats.consistency_checks += 1;
        if let Consistency::Conflict(_) = theory.consistent(self.ocsp.assumptions()) {
            self.state = State::Exhausted;
            return Ok(());
        }
        for j in 0..self.streams.len() {
            let shared = shared.as_deref_mut();
            let stream = &mut self.streams[j];
            if !stream.ensure(0, self.ocsp, theory, &self.options, shared, &mut self.meter)? {
                self.state = State::Exhausted;
                return Ok(());
            }
        }
        self.push_ready(vec![0; self.streams.len()]);
        self.state = State::Running;
        Ok(())
    }

    /// Pushes the successors of a popped tuple as pending entries at its own cost.
    fn push_successors(&mut self, tuple: &[u32], priority: Priority) {
        let Reverse((cost, _)) = priority;
        let first = tuple.iter().rposition(|&i| i > 0).unwrap_or(0);
        for stream in first..self.streams.len() {
            let mut successor = tuple.to_vec();
            successor[stream] += 1;
            let stream_done = self.streams[stream].done;
            if stream_done && self.streams[stream].found.len() <= successor[stream] as usize {
                continue;
            }
            self.created += 1;
            self.frontier.push(
                Entry::Pending {
                    tuple: successor,
                    stream,
                },
                Reverse((cost, self.created)),
            );
        }
    }

    /// Pushes a tuple whose solutions are all known, at its true cost.
    fn push_ready(&mut self, tuple: Vec<u32>) {
        let cost: f64 = tuple
            .iter()
            .zip(&self.streams)
            .map(|(&i, s)| s.found[i as usize].cost)
            .sum();
        self.created += 1;
        self.frontier
            .push(Entry::Ready(tuple), Reverse((Cost(cost), self.created)));
    }

    fn combine(&self, tuple: &[u32]) -> Solution {
        let decisions = self.ocsp.decisions();
        let mut assignment: Vec<_> = decisions
            .iter()
            .map(|d| (d.var, crate::logic::ValueId(0)))
            .collect();
        let mut cost = 0.0;
        for (&i, stream) in tuple.iter().zip(&self.streams) {
            let part = &stream.found[i as usize];
            cost += part.cost;
            for (&d, &c) in stream.search.members().iter().zip(&part.choices) {
                assignment[d].1 = self.ocsp.choices(d)[c as usize].value;
            }
        }
        Solution { assignment, cost }
    }
}

/// Groups the OCSP's decisions into independent sub-problems, in order of their first decision.
fn partition(ocsp: &Ocsp, theory: &Theory, decompose: bool) -> Vec<Vec<usize>> {
    let decisions = ocsp.decisions();
    if !decompose {
        return if decisions.is_empty() {
            Vec::new()
        } else {
            vec![(0..decisions.len()).collect()]
        };
    }
    let mut links = UnionFind::new(theory.table().len());
    for literal in ocsp.assumptions() {
        if let Literal::Holds(d) | Literal::Fails(d) = *literal {
            let vars = theory.definition_variables(d);
            if let Some((first, rest)) = vars.split_first() {
                for x in rest {
                    links.union(theory.component_root(*first), theory.component_root(*x));
                }
            }
        }
    }
    let mut group_of_root: HashMap<usize, usize> = HashMap::new();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (d, decision) in decisions.iter().enumerate() {
        let root = links.find(theory.component_root(decision.var));
        let group = *group_of_root.entry(root).or_insert_with(|| {
            groups.push(Vec::new());
            groups.len() - 1
        });
        groups[group].push(d);
    }
    groups
}
