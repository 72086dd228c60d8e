//! Decomposition into independent sub-problems and the best-first merge of their solutions.
//!
//! Decision variables that share no constraint (directly or through other variables) form
//! independent sub-problems: a full assignment is feasible exactly when its restriction to each
//! sub-problem is. With additive costs the best global solutions are sums of per-sub-problem
//! solutions, so each sub-problem is searched on its own ([`ComponentSearch`]) and their sorted
//! streams are merged lazily: a global solution is a tuple of stream indices; the frontier starts
//! at all zeros, and a popped tuple's successors increment one position at or after its last
//! non-zero one, which generates each tuple exactly once and never before a cheaper one.

use std::cmp::Reverse;
use std::collections::HashMap;

use petgraph::unionfind::UnionFind;
use priority_queue::PriorityQueue;

use super::ocsp::{Cut, Meter, Ocsp, SearchOptions, SearchStats, Solution};
use super::search::{ComponentSearch, Cost, PartialSolution, Priority};
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
        meter: &mut Meter,
    ) -> Result<bool, Cut> {
        while self.found.len() <= index && !self.done {
            match self
                .search
                .next(ocsp, theory, options.use_conflicts, meter)?
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
    frontier: PriorityQueue<Vec<u32>, Priority>,
    created: u64,
    state: State,
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
            frontier: PriorityQueue::new(),
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
        if self.state == State::NotStarted {
            self.start(theory)?;
        }
        if self.state == State::Exhausted {
            return Ok(None);
        }
        let Some((tuple, _)) = self.frontier.peek() else {
            self.state = State::Exhausted;
            return Ok(None);
        };
        let tuple = tuple.clone();
        // Fetch every successor's solutions before popping, so a cut leaves the state intact.
        let first = tuple.iter().rposition(|&i| i > 0).unwrap_or(0);
        let mut successors = Vec::new();
        for j in first..self.streams.len() {
            let next = tuple[j] as usize + 1;
            if self.streams[j].ensure(next, self.ocsp, theory, &self.options, &mut self.meter)? {
                let mut successor = tuple.clone();
                successor[j] += 1;
                successors.push(successor);
            }
        }
        self.frontier.pop();
        for successor in successors {
            self.push(successor);
        }
        Ok(Some(self.combine(&tuple)))
    }

    fn start(&mut self, theory: &mut Theory) -> Result<(), Cut> {
        self.meter.stats.consistency_checks += 1;
        if let Consistency::Conflict(_) = theory.consistent(self.ocsp.assumptions()) {
            self.state = State::Exhausted;
            return Ok(());
        }
        for j in 0..self.streams.len() {
            if !self.streams[j].ensure(0, self.ocsp, theory, &self.options, &mut self.meter)? {
                self.state = State::Exhausted;
                return Ok(());
            }
        }
        self.push(vec![0; self.streams.len()]);
        self.state = State::Running;
        Ok(())
    }

    fn push(&mut self, tuple: Vec<u32>) {
        let cost: f64 = tuple
            .iter()
            .zip(&self.streams)
            .map(|(&i, s)| s.found[i as usize].cost)
            .sum();
        self.created += 1;
        self.frontier
            .push(tuple, Reverse((Cost(cost), self.created)));
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
                assignment[d].1 = decisions[d].choices[c as usize].value;
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
