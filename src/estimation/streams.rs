//! Per-source solution streams for TimedME: each source state's next plant states, cheapest
//! first, from OPSAT — and from what earlier cycles already learned, whenever that is provably
//! the same answer.
//!
//! A source's OCSP has a *shape* — which next modes each component may take, and the
//! observation — and costs (−ln p). The feasible solutions depend on the shape only; their order
//! depends on the costs, which move every cycle a clock runs or the cycle length jitters (rates
//! depend on it). So the cache keeps, per shape, the feasible solutions found so far and a
//! **certificate**: "every feasible solution not listed costs at least `bound` under the costs
//! `c₀`". Under new costs `c₁`, with `Δ = Σ_components max_value |c₁ − c₀|`, an unlisted solution
//! costs at least `bound − Δ`; listed solutions cheaper than that are served in `c₁` order
//! without any search. Past that point a live OPSAT enumeration with `c₁` takes over (skipping
//! what was served), runs a [`MARGIN`] further so that the next cycles stay certified, and
//! renews the certificate. A shape whose enumeration ran out is complete: any costs are served
//! from the list.
//!
//! The maximum in `Δ` runs over the modes a feasible solution can take only: a mode that the
//! theory and the observation refute on its own (`entry = initiated` while no drag is sensed,
//! `engine = standby` while it still reads cold) is in no feasible solution, so its cost — the
//! one that moves fastest inside a timed window, being the timed transition's — cannot lower an
//! unlisted solution's. Which modes are refuted is decided once per observation, by one SAT
//! call per mode, and only for modes whose cost moved ([`Possible`]).

use std::cell::OnceCell;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

use rustc_hash::FxHashMap;

use std::sync::Arc;

use super::expand::{Choices, Limits, SourceChoices};
use crate::logic::ValueId;
use crate::opsat::{ConflictStore, Cut, Enumeration, Literal, Ocsp, SearchOptions, Theory};
use crate::plant::{Observation, Plant, target_ocsp};

/// Past this many shapes the cache starts afresh.
const CACHE_LIMIT: usize = 20_000;

/// A live enumeration goes on past the first solution more than this much dearer (in nats) than
/// the one asked for, to the next dearer one: the merge always looks one solution ahead, so the
/// certificate's bound must lie strictly beyond that look-ahead for the next cycles' slightly
/// different costs to stay certified…
const MARGIN: f64 = 1.0;

/// …but fetches at most this many solutions beyond the one asked for. Enough to get past a
/// plateau of equally likely solutions (the Mars lander's dozen components failing at the same
/// 1e-9/s rate): a bound still on the plateau certifies none of it once costs move at all, and
/// the source whose look-ahead reaches it would be enumerated afresh every cycle.
const PREFETCH: usize = 32;

/// A shape that has collected this many solutions without being complete starts afresh, so
/// that certifying stays cheap.
const KNOWN_LIMIT: usize = 256;

/// What is known about the feasible solutions of one OCSP shape.
#[derive(Default)]
pub(super) struct Known {
    /// Feasible next plant states, distinct.
    pub(super) solutions: Vec<Vec<ValueId>>,
    /// Per solution, each component's position among its next modes, which the shape fixes
    /// (`u32::MAX` if absent, which a solution of the shape's OCSP never is): the solution's
    /// cost under any costs of the shape is then a sum of lookups ([`cost_at`]).
    pub(super) positions: Vec<Vec<u32>>,
    /// Every feasible solution not in `solutions` costs at least `bound` under these choices'
    /// costs.
    pub(super) certificate: Option<(Arc<Choices>, f64)>,
    /// `solutions` holds every feasible solution.
    pub(super) complete: bool,
    /// Per next mode of the shape (components in order, each one's next modes in order), whether
    /// the observation leaves it possible on its own (see [`Possible`]); decided once per shape.
    pub(super) possible: Option<Vec<bool>>,
}

/// Cached knowledge, per OCSP shape, across calls.
#[derive(Default)]
pub(crate) struct SolutionCache {
    /// Shape key → slot in `known`: a step looks each shape up once and puts its knowledge
    /// back by slot, without hashing the key again.
    shapes: FxHashMap<Vec<u64>, usize>,
    known: Vec<Known>,
    /// Scratch for building a shape key.
    key: Vec<u64>,
    possible: Possible,
    /// Conflicts learned under the last expansion's observation, kept while it stays the same
    /// (every source's OCSP assumes the observation and nothing else; `opsat::ConflictStore`).
    conflicts: ConflictStore,
}

/// Which modes can appear in a feasible solution under one observation: `component = mode`
/// consistent with the theory and the observation (a necessary condition), decided lazily and
/// remembered until the observation changes.
#[derive(Default)]
struct Possible {
    observation: Observation,
    /// (component, mode) → consistent.
    decided: FxHashMap<(usize, ValueId), bool>,
    assumptions: Vec<Literal>,
}

impl SolutionCache {
    /// What is known about the shape in `slot` (a slot [`Streams::served`] named, while no
    /// expansion has run since).
    pub(super) fn known(&self, slot: usize) -> Option<&Known> {
        self.known.get(slot)
    }

    /// Whether the next expansion will start the cache afresh (it holds [`CACHE_LIMIT`] shapes).
    pub(super) fn is_full(&self) -> bool {
        self.shapes.len() >= CACHE_LIMIT
    }

    /// Whether component `c` may be in `mode` under the last expansion's observation, if that is
    /// decided already (`None`: deciding it takes a SAT call).
    pub(super) fn decided(&self, c: usize, mode: ValueId) -> Option<bool> {
        self.possible.decided.get(&(c, mode)).copied()
    }
}

impl Possible {
    /// Forgets what was decided under another observation.
    fn observe(&mut self, observation: &Observation) {
        if self.observation != *observation {
            self.observation = observation.clone();
            self.decided.clear();
        }
    }

    /// Whether component `c` may be in `mode` in a solution consistent with the observation.
    fn allows(&mut self, plant: &Plant, theory: &mut Theory, c: usize, mode: ValueId) -> bool {
        if let Some(&possible) = self.decided.get(&(c, mode)) {
            return possible;
        }
        self.assumptions.clear();
        self.assumptions
            .push(Literal::Is(plant.components()[c].mode_var(), mode));
        self.assumptions.extend(self.observation.literals());
        let possible = theory.is_consistent(&self.assumptions);
        self.decided.insert((c, mode), possible);
        possible
    }
}

/// One source's stream during an expansion.
struct Stream {
    /// Index into [`Streams::known`].
    shape: usize,
    choices: Arc<Choices>,
    /// Solutions handed out (or fetched ahead), cheapest first under `costs`, by index into
    /// the shape's solutions (which only grow during an expansion, and are distinct, so an
    /// index names one solution).
    served: Vec<(usize, f64)>,
    /// Certified known solutions not yet served, by index into the shape's solutions
    /// ([`Waiting`] says in which order).
    certified: BinaryHeap<Waiting>,
    /// The live enumeration's last cost, when one ran.
    live_bound: Option<f64>,
    done: bool,
    /// How many solutions the merge asked for (the rest of `served` was fetched ahead).
    asked: usize,
}

/// The streams of one expansion; the cache's knowledge is taken out for it and put back after.
pub(crate) struct Streams<'o> {
    /// Per shape of this expansion, its slot in the cache.
    slots: Vec<usize>,
    known: Vec<Known>,
    streams: Vec<Stream>,
    ocsps: &'o [OnceCell<Ocsp>],
    live: Vec<Option<Enumeration<'o>>>,
    options: SearchOptions,
    /// Set when an OPSAT budget ran out.
    pub(crate) cut: Option<Cut>,
    /// The cache's [`Possible`], taken out for the expansion.
    possible: Possible,
    /// The cache's conflicts, taken out for the expansion when the searches share them.
    conflicts: Option<ConflictStore>,
}

/// The shape of a source's OCSP, into `key`: the allowed values per component and the
/// observation.
fn shape_key(choices: &Choices, observation: &Observation, key: &mut Vec<u64>) {
    key.clear();
    for next in choices {
        key.push(next.len() as u64);
        key.extend(next.iter().map(|n| u64::from(n.mode.0)));
    }
    key.push(u64::MAX);
    for &(x, v) in observation.values() {
        key.push((u64::from(x.0) << 32) | u64::from(v.0));
    }
}

/// Each component's position in `choices` of its mode in `modes` (`u32::MAX` if absent).
fn positions_of(choices: &Choices, modes: &[ValueId]) -> Vec<u32> {
    choices
        .iter()
        .zip(modes)
        .map(|(next, m)| {
            next.iter()
                .position(|n| n.mode == *m)
                .map_or(u32::MAX, |i| i as u32)
        })
        .collect()
}

/// The cost under `choices` of the solution at `positions` (see [`positions_of`]); `None` if a
/// position is absent. Summed component by component, in order, from −0.0 as `Iterator::sum`
/// does: the very number every step computes for this solution under these costs (a replayed
/// step relies on it, `replay.rs`).
pub(super) fn cost_at(choices: &Choices, positions: &[u32]) -> Option<f64> {
    let mut sum = -0.0;
    for (next, &i) in choices.iter().zip(positions) {
        sum += next.get(i as usize)?.cost;
    }
    Some(sum)
}

/// Σ p over the next modes in `choices` that `mask` (see [`Known::possible`]) allows, multiplied
/// over the components (see [`Streams::possible_mass`]).
pub(super) fn possible_mass_under(choices: &Choices, mask: &[bool]) -> f64 {
    let mut allowed = mask.iter();
    choices
        .iter()
        .map(|next| {
            next.iter()
                .filter(|_| allowed.next().copied().unwrap_or(true))
                .map(|n| n.probability)
                .sum::<f64>()
        })
        .product()
}

/// Per component, (mode, cost) pairs for OPSAT.
fn costs(choices: &Choices) -> impl Iterator<Item = impl Iterator<Item = (ValueId, f64)> + '_> {
    choices
        .iter()
        .map(|next| next.iter().map(|n| (n.mode, n.cost)))
}

/// Σ over components of the largest change of the cost of a mode that `possible(component,
/// mode)` allows (same shape, so same order): how much cheaper any feasible solution can have
/// become. `possible` is asked only about modes whose change would raise the maximum (never
/// about a component whose next modes are shared, unchanged, by both).
pub(super) fn drift(
    old: &Choices,
    new: &Choices,
    mut possible: impl FnMut(usize, ValueId) -> bool,
) -> f64 {
    old.iter()
        .zip(new)
        .enumerate()
        .map(|(c, (a, b))| {
            if Arc::ptr_eq(a, b) {
                // The same allocation: every change is 0 (or NaN for an infinite cost), which
                // the fold below would never take either.
                return 0.0;
            }
            a.iter().zip(b.iter()).fold(0.0, |largest: f64, (x, y)| {
                let change = (x.cost - y.cost).abs();
                if change > largest && possible(c, x.mode) {
                    change
                } else {
                    largest
                }
            })
        })
        .sum()
}

/// A certified known solution waiting to be served, by index into its shape's solutions, with
/// its cost. The greatest is served first: the cheapest (by [`f64::total_cmp`]) and, among equal
/// costs, the one known last — the order in which a list of them sorted dearest first, stably
/// over the known solutions' order, is served from its back (the order `replay.rs` reproduces).
/// Indices are distinct, so no two compare equal and the order is total. A heap gives it without
/// sorting the whole list: the merge takes a few solutions of a source that may know hundreds,
/// and sorting them all was most of an expansion's sorting.
#[derive(Debug, Clone, Copy)]
struct Waiting {
    index: usize,
    cost: f64,
}

impl Ord for Waiting {
    fn cmp(&self, other: &Self) -> Ordering {
        (other.cost.total_cmp(&self.cost)).then(self.index.cmp(&other.index))
    }
}

impl PartialOrd for Waiting {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Waiting {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}

impl Eq for Waiting {}

impl Known {
    /// The known solutions servable under `choices`' costs before any unknown one, to be
    /// served in [`Waiting`]'s order. `possible` says which modes a feasible solution may take
    /// (see [`drift`]).
    fn certified(
        &self,
        choices: &Choices,
        possible: impl FnMut(usize, ValueId) -> bool,
    ) -> BinaryHeap<Waiting> {
        let limit = if self.complete {
            f64::INFINITY
        } else {
            match &self.certificate {
                Some((old, bound)) => bound - drift(old, choices, possible),
                None => return BinaryHeap::new(),
            }
        };
        let waiting: Vec<Waiting> = self
            .positions
            .iter()
            .enumerate()
            .filter_map(|(index, at)| Some((index, cost_at(choices, at)?)))
            .filter(|(_, cost)| *cost <= limit)
            .map(|(index, cost)| Waiting { index, cost })
            .collect();
        BinaryHeap::from(waiting)
    }
}

impl<'o> Streams<'o> {
    /// Streams for `sources`, with the cache's knowledge of their shapes taken out of it.
    /// `ocsps` holds one lazily built OCSP per source.
    pub(crate) fn take(
        cache: &mut SolutionCache,
        plant: &Plant,
        theory: &mut Theory,
        sources: &[SourceChoices],
        observation: &Observation,
        limits: Limits,
        ocsps: &'o [OnceCell<Ocsp>],
    ) -> Streams<'o> {
        if cache.shapes.len() >= CACHE_LIMIT {
            cache.shapes.clear();
            cache.known.clear();
        }
        cache.possible.observe(observation);
        let conflicts = limits.share_conflicts.then(|| {
            let mut conflicts = std::mem::take(&mut cache.conflicts);
            // The assumptions `target_ocsp` makes: the observation's literals, in order.
            let assumptions: Vec<Literal> = observation.literals().collect();
            conflicts.assume(&assumptions);
            conflicts
        });
        let mut streams = Streams {
            slots: Vec::new(),
            known: Vec::new(),
            streams: Vec::with_capacity(sources.len()),
            ocsps,
            live: sources.iter().map(|_| None).collect(),
            options: limits.search,
            cut: None,
            possible: Possible::default(),
            conflicts,
        };
        for source in sources {
            shape_key(&source.choices, observation, &mut cache.key);
            let slot = match cache.shapes.get(cache.key.as_slice()) {
                Some(&slot) => slot,
                None => {
                    cache.shapes.insert(cache.key.clone(), cache.known.len());
                    cache.known.push(Known::default());
                    cache.known.len() - 1
                }
            };
            let shape = match streams.slots.iter().position(|&s| s == slot) {
                Some(shape) => shape,
                None => {
                    streams.known.push(std::mem::take(&mut cache.known[slot]));
                    streams.slots.push(slot);
                    streams.slots.len() - 1
                }
            };
            let known = &streams.known[shape];
            streams.streams.push(Stream {
                shape,
                certified: known.certified(&source.choices, |c, mode| {
                    cache.possible.allows(plant, theory, c, mode)
                }),
                done: known.complete,
                choices: Arc::clone(&source.choices),
                served: Vec::new(),
                live_bound: None,
                asked: 0,
            });
        }
        streams.possible = std::mem::take(&mut cache.possible);
        streams
    }

    /// Puts the knowledge back into the cache, with the certificates live enumerations earned:
    /// a certificate under this cycle's costs replaces an older one (the next cycle's costs will
    /// be compared with it), the highest bound winning among this cycle's.
    pub(crate) fn put_back(self, cache: &mut SolutionCache) {
        cache.possible = self.possible;
        if let Some(conflicts) = self.conflicts {
            cache.conflicts = conflicts;
        }
        let mut renewed: Vec<Option<(Arc<Choices>, f64)>> = vec![None; self.known.len()];
        for stream in &self.streams {
            if let Some(bound) = stream.live_bound {
                let slot = &mut renewed[stream.shape];
                if slot.as_ref().is_none_or(|(_, b)| bound > *b) {
                    *slot = Some((Arc::clone(&stream.choices), bound));
                }
            }
        }
        for ((slot, mut known), certificate) in self.slots.into_iter().zip(self.known).zip(renewed)
        {
            if certificate.is_some() {
                known.certificate = certificate;
            }
            if !known.complete && known.solutions.len() > KNOWN_LIMIT {
                known = Known::default();
            }
            cache.known[slot] = known;
        }
    }

    /// Σ p over the next modes of source `k` that a solution consistent with the observation may
    /// take, multiplied over the components: a bound on the probability of the source's feasible
    /// targets (relative to the source), tighter than 1 when the observation refutes some next
    /// modes on their own (a fault whose mode constraint contradicts a reading).
    pub(crate) fn possible_mass(&mut self, k: usize, plant: &Plant, theory: &mut Theory) -> f64 {
        let stream = &self.streams[k];
        let possible = &mut self.possible;
        let mask = self.known[stream.shape].possible.get_or_insert_with(|| {
            stream
                .choices
                .iter()
                .enumerate()
                .flat_map(|(c, next)| next.iter().map(move |n| (c, n.mode)))
                .map(|(c, mode)| possible.allows(plant, theory, c, mode))
                .collect()
        });
        possible_mass_under(&stream.choices, mask)
    }

    /// Per source, in order, its shape's slot in the cache and the solutions the merge asked
    /// its stream for, by index into the shape's known solutions, ascending: what a replay of
    /// this expansion needs ([`super::replay`]).
    pub(crate) fn served(&self) -> impl Iterator<Item = (usize, Vec<usize>)> + '_ {
        self.streams.iter().map(|stream| {
            let asked = stream.served.iter().take(stream.asked);
            let mut served: Vec<usize> = asked.map(|&(index, _)| index).collect();
            served.sort_unstable();
            (self.slots[stream.shape], served)
        })
    }

    /// The next modes of solution `i` of source `k` (which [`Streams::cost`] has fetched).
    pub(crate) fn modes(&self, k: usize, i: usize) -> Vec<ValueId> {
        let stream = &self.streams[k];
        stream
            .served
            .get(i)
            .map(|&(index, _)| self.known[stream.shape].solutions[index].clone())
            .unwrap_or_default()
    }

    /// The cost of solution `i` of source `k`, cheapest first, fetching it if needed; `None`
    /// when there is none (or the budget ran out).
    pub(crate) fn cost(
        &mut self,
        k: usize,
        i: usize,
        plant: &Plant,
        sources: &[SourceChoices],
        observation: &Observation,
        theory: &mut Theory,
    ) -> Option<f64> {
        self.streams[k].asked = self.streams[k].asked.max(i + 1);
        loop {
            let stream = &mut self.streams[k];
            if let Some((_, cost)) = stream.served.get(i) {
                return Some(*cost);
            }
            if let Some(Waiting { index, cost }) = stream.certified.pop() {
                stream.served.push((index, cost));
                continue;
            }
            if stream.done || self.cut.is_some() {
                return None;
            }
            self.run_live(k, plant, sources, observation, theory);
        }
    }

    /// Extends source `k`'s stream from a live OPSAT enumeration: one new solution, then on up to
    /// [`MARGIN`] dearer (at most [`PREFETCH`] more), recording what it finds.
    fn run_live(
        &mut self,
        k: usize,
        plant: &Plant,
        sources: &[SourceChoices],
        observation: &Observation,
        theory: &mut Theory,
    ) {
        let options = self.options;
        let ocsps = self.ocsps;
        let enumeration = self.live[k].get_or_insert_with(|| {
            ocsps[k]
                .get_or_init(|| target_ocsp(plant, costs(&sources[k].choices), observation))
                .enumerate(theory, options)
        });
        let stream = &mut self.streams[k];
        let known = &mut self.known[stream.shape];
        let wanted = stream.served.len();
        let mut target = f64::INFINITY;
        let mut beyond = f64::INFINITY;
        loop {
            let next = match self.conflicts.as_mut() {
                Some(conflicts) => enumeration.next_sharing(theory, conflicts),
                None => enumeration.next(theory),
            };
            match next {
                Ok(Some(solution)) => {
                    let cost = solution.cost;
                    let modes: Vec<ValueId> =
                        solution.assignment.into_iter().map(|(_, v)| v).collect();
                    stream.live_bound = Some(cost);
                    let index = match known.solutions.iter().position(|s| *s == modes) {
                        Some(index) => index,
                        None => {
                            known.positions.push(positions_of(&stream.choices, &modes));
                            known.solutions.push(modes);
                            known.solutions.len() - 1
                        }
                    };
                    // A fresh enumeration re-finds what was served from the certificate.
                    if stream.served.iter().any(|&(served, _)| served == index) {
                        continue;
                    }
                    stream.served.push((index, cost));
                    if stream.served.len() == wanted + 1 {
                        target = cost + MARGIN;
                    }
                    if cost > target && beyond == f64::INFINITY {
                        beyond = cost;
                    }
                    if cost > beyond || stream.served.len() > wanted + PREFETCH {
                        break;
                    }
                }
                Ok(None) => {
                    stream.done = true;
                    known.complete = true;
                    break;
                }
                Err(cut) => {
                    self.cut = Some(cut);
                    break;
                }
            }
        }
    }
}
