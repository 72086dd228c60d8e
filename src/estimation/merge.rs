//! The merge of the sources' solution streams, best first by trajectory probability (the
//! expansion's core; see `expand`'s module documentation for why it yields the κ most likely
//! next states): where solutions come from ([`Serve`]: the live streams or a replay), the
//! prior mass not yet handed out ([`Unseen`]) that bounds what is still to come, and the
//! merged next states with summed weights ([`Merged`]).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::hash::{Hash, Hasher};

use rustc_hash::{FxHashMap, FxHasher};

use super::expand::{Choices, Expansion, Limits, MASS_TOLERANCE, SourceChoices};
use super::observe::ObservationModel;
use super::streams::Streams;
use super::{EstimationError, WeightedState};
use crate::logic::ValueId;
use crate::opsat::{Cost, Cut, Theory};
use crate::plant::{Observation, Plant, SystemState};

/// Where the merge gets each source's solutions, cheapest first, and their observation factors:
/// the streams of a full expansion ([`Live`]), or the replay of the last one
/// ([`super::replay::Replaying`]), which answers only what it can certify.
pub(crate) trait Serve {
    /// What stops a merge: [`EstimationError`] for the streams,
    /// [`super::replay::Uncertified`] for a replay.
    type Error;

    /// The cost of solution `i` of source `k` (fetched in order: `i` is at most one past the
    /// last one asked for); `None` when there is none.
    fn cost(&mut self, k: usize, i: usize, theory: &mut Theory)
    -> Result<Option<f64>, Self::Error>;

    /// What the merge needs of a candidate it examines.
    type Candidate;

    /// Solution `i` of source `k`, whose cost was asked for.
    fn candidate(&self, k: usize, i: usize) -> Self::Candidate;

    /// See [`Streams::possible_mass`].
    fn possible_mass(&mut self, k: usize, theory: &mut Theory) -> Result<f64, Self::Error>;

    /// P_O(o | modes) for the expansion's observation and the candidate's next modes.
    fn factor(
        &mut self,
        observe: &mut ObservationModel,
        theory: &mut Theory,
        candidate: &Self::Candidate,
    ) -> Result<f64, Self::Error>;

    /// Adds the candidate's successor (as `successor` builds it) to `merged` with `weight`.
    fn merge(
        &mut self,
        merged: &mut Merged,
        candidate: Self::Candidate,
        weight: f64,
        successor: &impl Fn(usize, &[ValueId]) -> SystemState,
    );
}

/// The streams of a full expansion, with what they are asked about.
pub(super) struct Live<'s, 'o, 'a> {
    pub(super) streams: &'s mut Streams<'o>,
    pub(super) plant: &'a Plant,
    pub(super) sources: &'a [SourceChoices],
    pub(super) observation: &'a Observation,
}

impl Serve for Live<'_, '_, '_> {
    type Error = EstimationError;

    fn cost(
        &mut self,
        k: usize,
        i: usize,
        theory: &mut Theory,
    ) -> Result<Option<f64>, Self::Error> {
        Ok(self
            .streams
            .cost(k, i, self.plant, self.sources, self.observation, theory))
    }

    /// (source, solution index): the modes are read from the streams where they are kept.
    type Candidate = (usize, usize);

    fn candidate(&self, k: usize, i: usize) -> (usize, usize) {
        (k, i)
    }

    fn possible_mass(&mut self, k: usize, theory: &mut Theory) -> Result<f64, Self::Error> {
        Ok(self.streams.possible_mass(k, self.plant, theory))
    }

    fn factor(
        &mut self,
        observe: &mut ObservationModel,
        theory: &mut Theory,
        &(k, i): &(usize, usize),
    ) -> Result<f64, Self::Error> {
        let modes = self.streams.modes(k, i);
        Ok(observe.factor_of_solution(self.plant, theory, modes, self.observation)?)
    }

    fn merge(
        &mut self,
        merged: &mut Merged,
        (k, i): (usize, usize),
        weight: f64,
        successor: &impl Fn(usize, &[ValueId]) -> SystemState,
    ) {
        merged.add(successor(k, self.streams.modes(k, i)), weight);
    }
}

/// The merge's working storage (kept by the [`Expander`](super::expand::Expander) so that a step allocates none of it
/// afresh).
#[derive(Default)]
pub(super) struct Buffers {
    unseen: Unseen,
    /// The successors merged so far (emptied by [`Merged::heaviest`]).
    pub(super) merged: Merged,
    frontier: Frontier,
    /// Per source, −ln of its probability.
    source_cost: Vec<f64>,
}

/// The merge of the sources' solutions best first (see the module documentation): the
/// candidates' successors with their weights, into `buffers.merged`; returns how many
/// candidates were examined.
pub(super) fn merge<S: Serve>(
    observe: &mut ObservationModel,
    buffers: &mut Buffers,
    theory: &mut Theory,
    sources: &[SourceChoices],
    limits: Limits,
    serve: &mut S,
    successor: &impl Fn(usize, &[ValueId]) -> SystemState,
) -> Result<u64, S::Error> {
    let Buffers {
        unseen,
        merged,
        frontier,
        source_cost,
    } = buffers;
    source_cost.clear();
    source_cost.extend(sources.iter().map(|s| -s.probability.ln()));
    unseen.reset(sources.len());
    frontier.reset(sources.len());
    merged.clear();
    for (k, source) in sources.iter().enumerate() {
        let first = if source.probability > 0.0 {
            serve.cost(k, 0, theory)?
        } else {
            None
        };
        match first {
            Some(cost) => frontier.push(order(source_cost[k] + cost), k, 0),
            None => unseen.exhausted(k),
        }
    }
    let mut best = None;
    let mut candidates = 0u64;
    let mut stopped = false;
    while let Some((cost_bits, k, i)) = frontier.pop() {
        let cost = f64::from_bits(cost_bits);
        let best = *best.get_or_insert(cost);
        candidates += 1;
        unseen.served(k, cost);
        let candidate = serve.candidate(k, i);
        match serve.cost(k, i + 1, theory)? {
            Some(next) => frontier.push(order(source_cost[k] + next), k, i + 1),
            None => unseen.exhausted(k),
        }
        let factor = serve.factor(observe, theory, &candidate)?;
        let weight = (best - cost).exp() * factor;
        if weight > 0.0 {
            merged.best_factor = merged.best_factor.max(factor);
            serve.merge(merged, candidate, weight, successor);
        }
        if candidates as usize >= limits.max_candidates {
            stopped = true;
            break;
        }
        // Past κ states, with no single candidate able to displace the κ-th, only the
        // unseen mass keeps the expansion going: tighten the bounds of the sources holding
        // most of it, one at a time, only as far as it lets the expansion stop. (The next
        // candidate's weight, an `exp`, is computed only past κ states, where it is read.)
        if merged.states.len() > limits.kappa
            && merged.kth_at_least(limits.kappa, next_weight(frontier, best))
        {
            let limit = MASS_TOLERANCE * merged.total * (-best).exp();
            unseen.bound(sources);
            if unseen.tighten_below(limit, sources, |k| serve.possible_mass(k, theory))? {
                stopped = true;
                break;
            }
        }
    }
    // What the streams did not hand out, for the truncation report (`Expansion::unseen`):
    // nothing when they ran dry, else the bound (computed already when the unseen mass
    // stopped the expansion).
    merged.scale = best.map_or(1.0, |b: f64| (-b).exp());
    merged.unseen = if stopped {
        unseen.bound(sources);
        unseen.mass() / merged.scale
    } else {
        0.0
    };
    Ok(candidates)
}

/// The prior weight, relative to the best candidate's (of cost `best`), of the next candidate
/// `frontier` holds (0 when none is left): no later candidate weighs more before its factor.
fn next_weight(frontier: &Frontier, best: f64) -> f64 {
    frontier
        .peek()
        .map_or(0.0, |bits| (best - f64::from_bits(bits)).exp())
}

/// The merge's frontier: each source's next candidate, as (cost bits, source, solution index),
/// served least first. A source has at most one entry at a time (its next solution is asked for
/// only once its last was taken), so the sources index the entries and no two tie entirely:
/// the least entry is unique and every representation serves the same sequence.
///
/// Up to [`SCAN_SOURCES`] sources the entries sit in a slot per source and the least is found by
/// a scan (the lowest source on equal costs, which is the order of the tuples); past it, in a
/// binary heap. A quiet step of the Mars lander merges from κ = 10 sources, where the heap's
/// sift-down was 5 % of the whole run's time (`perf`); the 8κ re-runs of Livingstone 2's breakers
/// merge from 80, where a scan per candidate would cost more than the heap.
#[derive(Default)]
struct Frontier {
    /// Per source, the (cost bits, solution index) of its next candidate (scanned mode).
    slots: Vec<Option<(u64, usize)>>,
    /// The entries (heap mode).
    heap: BinaryHeap<Reverse<(u64, usize, usize)>>,
    /// Whether the slots are in use rather than the heap.
    scan: bool,
}

/// The most sources [`Frontier`] scans rather than keeps in a heap.
const SCAN_SOURCES: usize = 16;

impl Frontier {
    /// Empties it for a merge of `sources` sources.
    fn reset(&mut self, sources: usize) {
        self.scan = sources <= SCAN_SOURCES;
        self.heap.clear();
        self.slots.clear();
        if self.scan {
            self.slots.resize(sources, None);
        }
    }

    /// Source `k`'s next candidate, solution `i` of cost bits `bits` (`k` has none waiting).
    fn push(&mut self, bits: u64, k: usize, i: usize) {
        if self.scan {
            self.slots[k] = Some((bits, i));
        } else {
            self.heap.push(Reverse((bits, k, i)));
        }
    }

    /// The source holding the least entry, in scanned mode.
    fn least(&self) -> Option<usize> {
        let mut least: Option<(u64, usize)> = None;
        for (k, slot) in self.slots.iter().enumerate() {
            if let Some((bits, _)) = *slot
                && least.is_none_or(|(best, _)| bits < best)
            {
                least = Some((bits, k));
            }
        }
        least.map(|(_, k)| k)
    }

    /// Takes the least entry.
    fn pop(&mut self) -> Option<(u64, usize, usize)> {
        if !self.scan {
            return self.heap.pop().map(|Reverse(entry)| entry);
        }
        let k = self.least()?;
        self.slots[k].take().map(|(bits, i)| (bits, k, i))
    }

    /// The cost bits of the least entry.
    fn peek(&self) -> Option<u64> {
        if !self.scan {
            return self.heap.peek().map(|Reverse((bits, _, _))| *bits);
        }
        self.least()
            .and_then(|k| self.slots[k])
            .map(|(bits, _)| bits)
    }
}

/// A non-negative cost as an integer with the same order (IEEE-754 bit patterns of non-negative
/// doubles order like the numbers).
fn order(cost: f64) -> u64 {
    cost.max(0.0).to_bits()
}

/// The prior probability the sources' streams have not handed out yet, per source: a source's
/// targets are a subset of its next-mode combinations, whose probabilities sum to
/// p(source) · Π_components Σ p(next mode) (p(source) but for the fallback's extra jumps), so
/// that sum less what was served bounds every target still to come, feasible or not. Once
/// [tightened](Unseen::tighten_heaviest), the sums run over the next modes the observation does not
/// refute on their own, which leaves out the mass of refuted faults that no stream will ever
/// hand out. An exhausted stream has nothing left.
///
/// The product Π Σ p is remembered per version of choices ([`Combinations`]): a quiet step's
/// sources keep their very choices from step to step (`recents.rs`, `Recents`), and the
/// product, a pass over every component's next modes, was 6 % of the Mars lander's quiet cycle.
///
/// Past κ states the merge asks after every candidate whether the unseen mass is small enough
/// to stop; the answers are computed as before, in the same order (every bound, then the sum),
/// but what cannot have changed since the last candidate is not recomputed: the bounds once all
/// are known ([`Unseen::bounded`]), and the search for a source to tighten once none is left
/// ([`Unseen::untightened`]). On Livingstone 2's breakers, where the 8κ re-run merges from 80
/// sources, the merge's own instructions (these passes and the count of heavy states,
/// [`AtLeast`]) were a fifth of the 15-breaker log's; the two changes took a tenth off it.
#[derive(Default)]
struct Unseen {
    /// Per source of the current expansion (the vector is reused from one to the next).
    bounds: Vec<Bound>,
    combinations: Combinations,
    /// Every source's bound is known.
    bounded: bool,
    /// How many sources are not tightened and not exhausted: the only ones
    /// [`Unseen::tighten_heaviest`] may pick.
    untightened: usize,
}

/// Π_components Σ p(next mode) of choices already met, by their version. Exact: a version
/// names one content for good (`expand.rs`, `Choices`: every value made or written gets a
/// version never handed out before), and the product is a function of the choices alone,
/// computed by the same code in the same order, so a remembered one is the very number a
/// recomputation gives. Nothing is held but the number: the choices' `Arc` stays free to be
/// written in place.
#[derive(Default)]
struct Combinations(FxHashMap<u64, f64>);

/// Past this many entries [`Combinations`] starts afresh: a quiet step meets κ choices, new
/// ones where a source changed (on the Mars lander, every source every step: a clock runs).
const COMBINATIONS_LIMIT: usize = 256;

impl Combinations {
    /// Π_components Σ p(next mode) of `choices`.
    fn of(&mut self, choices: &Choices) -> f64 {
        let key = choices.version();
        if let Some(product) = self.0.get(&key) {
            return *product;
        }
        let product: f64 = choices
            .iter()
            .map(|next| next.iter().map(|n| n.probability).sum::<f64>())
            .product();
        if self.0.len() >= COMBINATIONS_LIMIT {
            self.0.clear();
        }
        self.0.insert(key, product);
        product
    }
}

/// One source's unseen mass.
#[derive(Clone, Copy, Default)]
struct Bound {
    /// The bound on its targets' total probability: `None` until needed, 0 once exhausted.
    mass: Option<f64>,
    /// The probability of the targets served.
    served: f64,
    /// Whether the bound was tightened (or the stream ran dry, which leaves nothing to tighten).
    tightened: bool,
}

impl Unseen {
    /// Starts an expansion of `sources` sources.
    fn reset(&mut self, sources: usize) {
        self.bounds.clear();
        self.bounds.resize(sources, Bound::default());
        self.bounded = false;
        self.untightened = sources;
    }

    /// Computes the bounds not known yet (only expansions that get past κ states need them).
    fn bound(&mut self, sources: &[SourceChoices]) {
        if self.bounded {
            return;
        }
        for (bound, source) in self.bounds.iter_mut().zip(sources) {
            bound
                .mass
                .get_or_insert_with(|| source.probability * self.combinations.of(&source.choices));
        }
        self.bounded = true;
    }

    /// Tightens the heaviest sources' bounds one at a time while the unseen mass is above
    /// `limit`; whether it is at most `limit` in the end (the merge may stop).
    fn tighten_below<E>(
        &mut self,
        limit: f64,
        sources: &[SourceChoices],
        mut possible: impl FnMut(usize) -> Result<f64, E>,
    ) -> Result<bool, E> {
        loop {
            if self.mass() <= limit {
                return Ok(true);
            }
            if !self.tighten_heaviest(sources, &mut possible)? {
                return Ok(false);
            }
        }
    }

    /// Replaces the bound of the source with the most unseen mass not yet tightened by
    /// `p(source) · possible(source)` (see [`Streams::possible_mass`]); false when no source
    /// is left to tighten.
    fn tighten_heaviest<E>(
        &mut self,
        sources: &[SourceChoices],
        possible: impl FnOnce(usize) -> Result<f64, E>,
    ) -> Result<bool, E> {
        if self.untightened == 0 {
            return Ok(false);
        }
        let heaviest = (0..self.bounds.len())
            .filter(|&k| !self.bounds[k].tightened && self.left(k) > 0.0)
            .max_by(|&a, &b| self.left(a).total_cmp(&self.left(b)));
        let Some(k) = heaviest else {
            return Ok(false);
        };
        let tightened = sources[k].probability * possible(k)?;
        self.untightened -= 1;
        let bound = &mut self.bounds[k];
        bound.tightened = true;
        bound.mass = Some(bound.mass.map_or(tightened, |mass| mass.min(tightened)));
        Ok(true)
    }

    /// What source `k` may still hand out (rounding can leave it slightly below 0; a bound not
    /// computed yet counts as nothing, [`Unseen::bound`] comes first).
    fn left(&self, k: usize) -> f64 {
        let bound = &self.bounds[k];
        (bound.mass.unwrap_or(0.0) - bound.served).max(0.0)
    }

    /// Source `k` handed out a target of trajectory cost `cost` (−ln of its prior probability).
    fn served(&mut self, k: usize, cost: f64) {
        self.bounds[k].served += (-cost).exp();
    }

    /// Source `k`'s stream ran dry. Nothing is left to tighten of it (its bound is 0), so it
    /// counts as tightened.
    fn exhausted(&mut self, k: usize) {
        let bound = &mut self.bounds[k];
        bound.mass = Some(0.0);
        if !bound.tightened {
            bound.tightened = true;
            self.untightened -= 1;
        }
    }

    /// The bound on everything still to come.
    fn mass(&self) -> f64 {
        (0..self.bounds.len()).map(|k| self.left(k)).sum()
    }
}

/// The hash [`Merged`] indexes a state by.
pub(crate) fn state_hash(state: &SystemState) -> u64 {
    let mut hasher = FxHasher::default();
    state.hash(&mut hasher);
    hasher.finish()
}

/// Next system states with summed weights, in order of first appearance. Indexed by hash, so a
/// new state is stored once (hash collisions fall back to comparing states).
#[derive(Default)]
pub(crate) struct Merged {
    index: FxHashMap<u64, usize>,
    states: Vec<WeightedState>,
    /// The sum of the weights.
    total: f64,
    /// [`Expansion::unseen`] of the merge.
    unseen: f64,
    /// [`Expansion::scale`] of the merge.
    scale: f64,
    /// [`Expansion::best_factor`] of the merge.
    best_factor: f64,
    /// Which states are known to weigh at least the last weight [`Merged::kth_at_least`] was
    /// asked about.
    at_least: AtLeast,
}

/// [`Merged::kth_at_least`] counts afresh below this many states, and keeps its count from here on.
const KEEP_COUNT_FROM: usize = 64;

/// The count behind [`Merged::kth_at_least`], kept from one question to the next. The merge asks
/// about the next candidate's prior weight, which never grows (candidates come cheapest first),
/// while a state's weight never shrinks (merging only adds): a state that weighed at least one
/// asked weight weighs at least every later one, so it is counted once, for good. The others wait
/// in a max-heap by their weight when last changed (a state whose weight grows is pushed again; the
/// stale entry, lighter, is skipped when it comes out). A question pops what weighs at least its
/// weight: every state not counted has its current weight in the heap, so what stays there weighs
/// less, and the count is the exact number of states at least that heavy (or `k`, when it gets
/// there first). A question about a heavier weight than the last (which the merge never asks) is
/// answered by counting afresh, and leaves the count as it was. Nothing is kept before the first
/// question, and nothing until the merge holds [`KEEP_COUNT_FROM`] states: a quiet cycle's merges
/// hold a few dozen, which a count reads faster than a heap yields them (keeping the heap from
/// the first candidate cost the Mars lander's quiet cycle 7 %, from the first question 3 %).
#[derive(Default)]
struct AtLeast {
    /// The least weight asked about so far (`None` before any question: nothing is kept).
    asked: Option<f64>,
    /// How many states are counted.
    count: usize,
    /// Per state, whether it is counted.
    counted: Vec<bool>,
    /// The states not counted, by weight when pushed (a weight ordered totally, as OPSAT orders
    /// costs).
    waiting: BinaryHeap<(Cost, usize)>,
}

impl AtLeast {
    /// Whether the count is kept (a question was asked since the merge started).
    fn is_kept(&self) -> bool {
        self.asked.is_some()
    }

    fn clear(&mut self) {
        self.asked = None;
        self.count = 0;
        self.counted.clear();
        self.waiting.clear();
    }

    /// State `i` is new, or its weight grew to `weight`.
    fn weighs(&mut self, i: usize, weight: f64) {
        if self.asked.is_none() {
            return;
        }
        if i == self.counted.len() {
            self.counted.push(false);
        }
        if !self.counted[i] {
            self.waiting.push((Cost(weight), i));
        }
    }

    /// Whether at least `k` of the `states` states, of weights `weight_of(i)`, weigh at least
    /// `weight` (`k` ≤ `states`).
    fn at_least(
        &mut self,
        k: usize,
        weight: f64,
        states: usize,
        weight_of: impl Fn(usize) -> f64,
    ) -> bool {
        match self.asked {
            Some(asked) if weight > asked => {
                return (0..states).filter(|&i| weight_of(i) >= weight).count() >= k;
            }
            Some(_) => {}
            None => {
                self.counted.clear();
                self.counted.resize(states, false);
                self.waiting.clear();
                self.waiting
                    .extend((0..states).map(|i| (Cost(weight_of(i)), i)));
            }
        }
        self.asked = Some(weight);
        while self.count < k {
            match self.waiting.peek() {
                Some(&(Cost(w), i)) if w >= weight => {
                    self.waiting.pop();
                    if !self.counted[i] && w.total_cmp(&weight_of(i)).is_eq() {
                        self.counted[i] = true;
                        self.count += 1;
                    }
                }
                _ => break,
            }
        }
        self.count >= k
    }
}

impl Merged {
    fn add(&mut self, state: SystemState, weight: f64) {
        let hash = state_hash(&state);
        self.add_hashed(state, hash, weight);
    }

    /// [`Merged::add`] of `state`, whose hash ([`state_hash`]) is `hash`; returns its index
    /// among the states merged.
    pub(crate) fn add_hashed(&mut self, state: SystemState, hash: u64, weight: f64) -> usize {
        self.total += weight;
        match self.find(hash, &state) {
            Some(i) => {
                self.grow(i, weight);
                i
            }
            None => self.push(hash, state, weight),
        }
    }

    /// [`Merged::add`] of a copy of `state`, whose hash ([`state_hash`]) is `hash`, copied only
    /// if it is new; returns its index among the states merged.
    pub(crate) fn add_known(&mut self, state: &SystemState, hash: u64, weight: f64) -> usize {
        self.total += weight;
        match self.find(hash, state) {
            Some(i) => {
                self.grow(i, weight);
                i
            }
            None => self.push(hash, state.clone(), weight),
        }
    }

    /// State `i` of the states merged (an index [`Merged::add_hashed`] or
    /// [`Merged::add_known`] returned in this merge).
    pub(crate) fn state(&self, i: usize) -> &SystemState {
        &self.states[i].state
    }

    /// Adds `weight` to state `i`.
    fn grow(&mut self, i: usize, weight: f64) {
        let state = &mut self.states[i];
        state.probability += weight;
        self.at_least.weighs(i, state.probability);
    }

    /// The index of `state` (of hash `hash`) among the states merged, if it is one.
    fn find(&self, hash: u64, state: &SystemState) -> Option<usize> {
        match self.index.get(&hash) {
            Some(&i) if self.states[i].state == *state => Some(i),
            Some(_) => self.states.iter().position(|w| w.state == *state),
            None => None,
        }
    }

    fn push(&mut self, hash: u64, state: SystemState, weight: f64) -> usize {
        let at = self.states.len();
        self.at_least.weighs(at, weight);
        self.index.entry(hash).or_insert(at);
        self.states.push(WeightedState {
            state,
            probability: weight,
        });
        at
    }

    /// Whether the `k`-th largest weight (0 with fewer than `k` states) is at least `weight`
    /// (a weight of a candidate, ≥ 0). Counted rather than selected: the `k`-th largest is at
    /// least `weight` exactly when `k` weights are — asked after every candidate, a selection
    /// was a tenth of a partially observed replay's instructions — and the count is kept from
    /// one question to the next ([`AtLeast`]), since re-counting every state after every
    /// candidate was most of what was left.
    fn kth_at_least(&mut self, k: usize, weight: f64) -> bool {
        if k == 0 || self.states.len() < k {
            return 0.0 >= weight;
        }
        let states = &self.states;
        if !self.at_least.is_kept() && states.len() < KEEP_COUNT_FROM {
            return states
                .iter()
                .filter(|w| w.probability >= weight)
                .nth(k - 1)
                .is_some();
        }
        self.at_least
            .at_least(k, weight, states.len(), |i| states[i].probability)
    }

    /// Empties it for a new merge (keeping the index's capacity).
    fn clear(&mut self) {
        self.index.clear();
        self.states.clear();
        self.total = 0.0;
        self.unseen = 0.0;
        self.scale = 1.0;
        self.best_factor = 0.0;
        self.at_least.clear();
    }

    /// The expansion that ends here: the `kappa` heaviest states and the weight of all merged.
    pub(super) fn expansion(
        &mut self,
        kappa: usize,
        candidates: u64,
        cut: Option<Cut>,
        replayed: bool,
    ) -> Expansion {
        let (states, dropped) = self.heaviest(kappa);
        Expansion {
            merged: self.total,
            states,
            candidates,
            cut,
            replayed,
            unseen: self.unseen,
            scale: self.scale,
            dropped,
            best_factor: self.best_factor,
        }
    }

    /// The `k` heaviest states, heaviest first (ties in order of appearance), and the weight of
    /// the heaviest of the others (0 when none is left); leaves none.
    fn heaviest(&mut self, k: usize) -> (Vec<WeightedState>, f64) {
        self.states
            .sort_by(|a, b| b.probability.total_cmp(&a.probability));
        // Drained rather than taken, so that the merge keeps its capacity for the next step.
        let kept = k.min(self.states.len());
        let mut heaviest = Vec::with_capacity(kept);
        heaviest.extend(self.states.drain(..kept));
        let dropped = self.states.first().map_or(0.0, |w| w.probability);
        self.states.clear();
        self.at_least.clear();
        (heaviest, dropped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::seeded;
    use proptest::prelude::*;

    /// One step of a merge as [`AtLeast`] sees it: a state added or grown by a weight, or a
    /// question about the `k`-th weight.
    #[derive(Debug, Clone)]
    enum Op {
        Add { state: usize, weight: f64 },
        Ask { k: usize, weight: f64 },
    }

    fn op() -> impl Strategy<Value = Op> {
        let weight = prop_oneof![(1u32..8).prop_map(|w| f64::from(w) / 8.0), 0.0..1.0f64];
        prop_oneof![
            (0usize..12, weight.clone()).prop_map(|(state, weight)| Op::Add { state, weight }),
            (1usize..6, weight).prop_map(|(k, weight)| Op::Ask { k, weight }),
        ]
    }

    proptest! {
        #![proptest_config(seeded::config(512))]

        /// DESIGN.md §8, the merge best first: `Frontier` serves the entries in the order a
        /// binary heap of (cost bits, source, solution) serves them, scanned (few sources) or
        /// heaped (many), with ties on cost among sources; `peek` names the cost `pop` takes.
        #[test]
        fn the_frontier_serves_as_a_heap_does(
            sources in 1usize..40,
            ops in proptest::collection::vec((any::<bool>(), 0usize..40, 0u64..4), 1..120),
        ) {
            let mut frontier = Frontier::default();
            frontier.reset(sources);
            let mut oracle = BinaryHeap::new();
            let mut waiting = vec![false; sources];
            let mut next = vec![0usize; sources];
            for (pop, k, bits) in ops {
                let k = k % sources;
                if pop || waiting[k] {
                    prop_assert_eq!(
                        frontier.peek(),
                        oracle.peek().map(|Reverse((bits, _, _))| *bits)
                    );
                    let served = frontier.pop();
                    prop_assert_eq!(served, oracle.pop().map(|Reverse(entry)| entry));
                    if let Some((_, k, _)) = served {
                        waiting[k] = false;
                    }
                } else {
                    frontier.push(bits, k, next[k]);
                    oracle.push(Reverse((bits, k, next[k])));
                    waiting[k] = true;
                    next[k] += 1;
                }
            }
        }

        /// DESIGN.md §8, the expansion's stopping rule (`expand.rs`): `Merged::kth_at_least`'s
        /// kept count answers as counting every state afresh does,
        /// for the merge's questions (weights that never grow) and for any others.
        #[test]
        fn the_kept_count_answers_as_a_fresh_count(
            ops in proptest::collection::vec(op(), 1..60),
            descending in any::<bool>(),
        ) {
            let mut at_least = AtLeast::default();
            let mut weights: Vec<f64> = Vec::new();
            let mut last_ask = f64::INFINITY;
            for op in ops {
                match op {
                    Op::Add { state, weight } => {
                        let i = state.min(weights.len());
                        if i == weights.len() {
                            weights.push(0.0);
                        }
                        weights[i] += weight;
                        at_least.weighs(i, weights[i]);
                    }
                    Op::Ask { k, weight } => {
                        let weight = if descending { weight.min(last_ask) } else { weight };
                        last_ask = weight;
                        if k > weights.len() {
                            continue;
                        }
                        let fresh = weights.iter().filter(|&&w| w >= weight).count() >= k;
                        let kept = at_least.at_least(k, weight, weights.len(), |i| weights[i]);
                        prop_assert_eq!(kept, fresh);
                    }
                }
            }
        }
    }
}
