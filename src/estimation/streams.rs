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
//!
//! # Allocations
//!
//! An expansion's streams reuse the previous expansion's (`SolutionCache::spare`, each
//! stream's list of served solutions kept with its capacity), and the live enumerations, a few
//! per expansion, are a short list rather than a slot per source: both were allocations of a
//! few kilobytes per 8κ expansion, each large enough to make the allocator consolidate its
//! free lists. Nothing served changes; 7.347 G → 7.301 G instructions on Livingstone 2's
//! 15-breaker log at κ = 10; with the propagation change before it (`opsat::propagate`, "Cost
//! per literal") CPU 0.96 of before (`farm-bench --vs`, 10 pairs, median; both measured with a
//! memory of consistent search checks since rejected, `docs/design/opsat.md`). The three
//! changes together (this, "Cost per literal" and the lazy list below): 9.048 G → 8.056 G
//! instructions at κ = 10, 4.392 G → 3.954 G at κ = 5; CPU 0.82 / 0.82 of before at 15
//! breakers (7 pairs), 0.96 / 0.98 at 255 (3 pairs, load 4–5).
//!
//! # Known solutions, found by fingerprint
//!
//! A live enumeration's solution is looked up among its shape's known ones (up to
//! [`KNOWN_LIMIT`]) before it is learned. Compared vector by vector, each comparison ran to
//! the first component where two solutions differ — on Livingstone 2's 255-breaker tree
//! hundreds of components, for solutions differing in one fault — and the scan was 3 % of the
//! replay. Each known solution keeps a fingerprint (an `FxHasher` hash, the same on every run);
//! the scan compares fingerprints and compares the solutions in full only where those are
//! equal. Equal solutions have equal fingerprints, so the first equal solution is found, as
//! before, and nothing served changes. Measured: CPU time at 255 breakers, κ = 10, 0.96 of
//! before (`farm-bench --vs`, 5 pairs, median, load ≈ 5); on the 15-breaker log (23 components,
//! short vectors) 0.1 % more instructions (κ = 5 3.734 G → 3.737 G).
//!
//! # The certified list, lazily
//!
//! A stream serves the certified known solutions of its shape cheapest first, costing them under
//! its own choices only as far as serving needs ([`certified`]): beliefs and SAT calls are
//! byte-identical to costing every known solution.

use std::cell::OnceCell;
use std::collections::BinaryHeap;
use std::hash::{Hash, Hasher};

use rustc_hash::FxHashMap;

use std::sync::Arc;

mod certified;

use super::expand::{Choices, Limits, SourceChoices};
use crate::logic::ValueId;
use crate::opsat::{ConflictStore, Cut, Enumeration, Literal, Ocsp, SearchOptions, Theory};
use crate::plant::{Observation, Plant, target_ocsp};
use certified::{Certified, Reference, Waiting, same_costs};

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
    /// The known solutions ordered by their costs under reference choices, which a stream walks
    /// to serve its certified ones without costing them all ("The certified list, lazily").
    reference: Reference,
    /// Per solution, its [`fingerprint`] ("Known solutions, found by fingerprint").
    fingerprints: Vec<u64>,
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
    /// The last expansion's streams, whose allocations the next one reuses ("Allocations").
    spare: Vec<Stream>,
}

/// Which modes can appear in a feasible solution under one observation: `component = mode`
/// consistent with the theory and the observation (a necessary condition), decided lazily and
/// remembered until the observation changes. Measured and rejected: keeping the answers of the
/// last four observations (Livingstone 2's logs alternate between nothing observed and a
/// reading) — exact, and 5–10 % fewer SAT questions, but the ones saved were answered by
/// propagation: 0.4 % fewer instructions on the 15-breaker log, 0.2 % in the 1,023-breaker
/// tree's first cycle, for SAT counts that differ from every earlier run's.
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

    /// Whether component `c` may be in `mode` as far as decided already: true when undecided.
    fn decided(&self, c: usize, mode: ValueId) -> bool {
        self.decided.get(&(c, mode)).copied().unwrap_or(true)
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
    /// Certified known solutions not yet served ([`Waiting`] says in which order).
    certified: Certified,
    /// The live enumeration's last cost, when one ran.
    live_bound: Option<f64>,
    done: bool,
    /// How many solutions the merge asked for (the rest of `served` was fetched ahead).
    asked: usize,
}

impl Stream {
    /// Becomes `fresh`, keeping the allocation of the list served (which `fresh` has empty).
    fn reuse(&mut self, fresh: Stream) {
        let mut served = std::mem::take(&mut self.served);
        served.clear();
        *self = Stream { served, ..fresh };
    }
}

/// The streams of one expansion; the cache's knowledge is taken out for it and put back after.
pub(crate) struct Streams<'o> {
    /// Per shape of this expansion, its slot in the cache.
    slots: Vec<usize>,
    known: Vec<Known>,
    streams: Vec<Stream>,
    ocsps: &'o [OnceCell<Ocsp>],
    /// The live enumerations, by source: a few per expansion, so a short list rather than a
    /// slot per source ("Allocations").
    live: Vec<(usize, Enumeration<'o>)>,
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

/// A solution's hash, the same on every run (`FxHasher` has no random state): two equal
/// solutions have equal fingerprints.
fn fingerprint(modes: &[ValueId]) -> u64 {
    let mut hasher = rustc_hash::FxHasher::default();
    modes.hash(&mut hasher);
    hasher.finish()
}

impl Known {
    /// The index of `modes` among the known solutions, learning it (with its `positions`
    /// under `choices`) if it is new: the first solution equal to it, as a scan of the list
    /// finds it, but compared in full only where the fingerprints are equal.
    fn index_of(&mut self, modes: Vec<ValueId>, choices: &Choices) -> usize {
        let print = fingerprint(&modes);
        let found = self
            .fingerprints
            .iter()
            .zip(&self.solutions)
            .position(|(&p, s)| p == print && *s == modes);
        found.unwrap_or_else(|| {
            self.positions.push(positions_of(choices, &modes));
            self.solutions.push(modes);
            self.fingerprints.push(print);
            self.solutions.len() - 1
        })
    }

    /// The known solutions servable under `choices`' costs before any unknown one, to be
    /// served in [`Waiting`]'s order (see [`Certified::pop`]). The certificate's drift runs
    /// over the modes a feasible solution may take, deciding those not decided yet ([`drift`],
    /// [`Possible`]); the drift from the reference choices asks only what is decided already
    /// (a mode not decided counts as possible, which only widens the bound), so it asks the
    /// theory nothing.
    fn certified(
        &self,
        choices: &Choices,
        possible: &mut Possible,
        plant: &Plant,
        theory: &mut Theory,
    ) -> Certified {
        let limit = if self.complete {
            f64::INFINITY
        } else {
            match &self.certificate {
                Some((old, bound)) => {
                    bound
                        - drift(old, choices, |c, mode| {
                            possible.allows(plant, theory, c, mode)
                        })
                }
                None => return Certified::none(),
            }
        };
        let Some(reference) = &self.reference.choices else {
            return Certified::none();
        };
        let same = same_costs(reference, choices);
        let drift = if same {
            0.0
        } else {
            drift(reference, choices, |c, mode| possible.decided(c, mode))
        };
        Certified {
            limit,
            drift,
            same,
            next: 0,
            waiting: BinaryHeap::new(),
        }
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
            streams: std::mem::take(&mut cache.spare),
            ocsps,
            live: Vec::new(),
            options: limits.search,
            cut: None,
            possible: Possible::default(),
            conflicts,
        };
        for (k, source) in sources.iter().enumerate() {
            shape_key(&source.choices, observation, &mut cache.key);
            let slot = match cache.shapes.get(cache.key.as_slice()) {
                Some(&slot) => slot,
                None => {
                    cache.shapes.insert(cache.key.clone(), cache.known.len());
                    cache.known.push(Known::default());
                    cache.known.len() - 1
                }
            };
            let possible = &mut cache.possible;
            let shape = match streams.slots.iter().position(|&s| s == slot) {
                Some(shape) => shape,
                None => {
                    let mut known = std::mem::take(&mut cache.known[slot]);
                    let choices = &source.choices;
                    known
                        .reference
                        .refresh(&known.positions, choices, |reference| {
                            drift(reference, choices, |c, mode| possible.decided(c, mode))
                        });
                    streams.known.push(known);
                    streams.slots.push(slot);
                    streams.slots.len() - 1
                }
            };
            let known = &streams.known[shape];
            let certified = known.certified(&source.choices, possible, plant, theory);
            let stream = Stream {
                shape,
                certified,
                done: known.complete,
                choices: Arc::clone(&source.choices),
                served: Vec::new(),
                live_bound: None,
                asked: 0,
            };
            match streams.streams.get_mut(k) {
                Some(spare) => spare.reuse(stream),
                None => streams.streams.push(stream),
            }
        }
        streams.streams.truncate(sources.len());
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
        cache.spare = self.streams;
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
    /// Borrowed: the known solutions only grow while the streams live (the cache starts afresh
    /// in [`Streams::take`] and [`Streams::put_back`] alone), so a served index stays valid.
    pub(crate) fn modes(&self, k: usize, i: usize) -> &[ValueId] {
        let stream = &self.streams[k];
        stream.served.get(i).map_or(&[], |&(index, _)| {
            &self.known[stream.shape].solutions[index]
        })
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
            let known = &self.known[stream.shape];
            let next =
                (stream.certified).pop(&known.reference.order, &known.positions, &stream.choices);
            if let Some(Waiting { index, cost }) = next {
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
        let at = match self.live.iter().position(|(source, _)| *source == k) {
            Some(at) => at,
            None => {
                let ocsp = ocsps[k]
                    .get_or_init(|| target_ocsp(plant, costs(&sources[k].choices), observation));
                self.live.push((k, ocsp.enumerate(theory, options)));
                self.live.len() - 1
            }
        };
        let enumeration = &mut self.live[at].1;
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
                    let index = known.index_of(modes, &stream.choices);
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

#[cfg(test)]
mod tests {
    use super::super::expand::NextMode;
    use super::certified::floor;
    use super::*;
    use crate::seeded;
    use proptest::prelude::*;

    /// A shape's choices: per component, its next modes' costs.
    fn choices_of(costs: &[Vec<f64>]) -> Choices {
        costs
            .iter()
            .map(|next| {
                next.iter()
                    .enumerate()
                    .map(|(m, &cost)| NextMode {
                        mode: ValueId(m as u32),
                        probability: (-cost).exp(),
                        cost,
                    })
                    .collect()
            })
            .collect()
    }

    proptest! {
        #![proptest_config(seeded::config(256))]

        /// "Known solutions, found by fingerprint": `Known::index_of` gives the index a scan of
        /// the list for the first equal solution gives (the oracle, kept alongside), learns
        /// exactly the solutions that scan does not find, with their positions, and keeps the
        /// fingerprints in step with the solutions.
        #[test]
        fn a_known_solution_is_found_by_fingerprint_as_by_a_scan(
            found in prop::collection::vec(prop::collection::vec(0u32..3, 4), 1..60),
        ) {
            let choices = choices_of(&vec![vec![0.0, 1.0, 2.0]; 4]);
            let mut known = Known::default();
            let mut oracle: Vec<Vec<ValueId>> = Vec::new();
            for modes in found {
                let modes: Vec<ValueId> = modes.into_iter().map(ValueId).collect();
                let expected = oracle.iter().position(|s| *s == modes).unwrap_or_else(|| {
                    oracle.push(modes.clone());
                    oracle.len() - 1
                });
                prop_assert_eq!(known.index_of(modes.clone(), &choices), expected);
                prop_assert_eq!(&known.solutions, &oracle);
                prop_assert_eq!(known.fingerprints.len(), oracle.len());
                prop_assert_eq!(&known.positions[expected], &positions_of(&choices, &modes));
            }
        }
    }

    /// A cost drawn from a few values (ties) or anywhere in [0, 12).
    fn a_cost() -> impl Strategy<Value = f64> {
        prop_oneof![
            prop::sample::select(vec![0.0, 0.5, 1.0, 2.5, 7.0]),
            0.0..12.0f64,
        ]
    }

    /// Per component (1–4 of them) 1–4 next modes: reference costs, the stream's costs (equal,
    /// slightly moved or moved anywhere), and whether the mode is possible (an impossible one's
    /// cost may move without bound: no known solution takes it).
    fn a_shape() -> impl Strategy<Value = Vec<Vec<(f64, f64, bool)>>> {
        let mode = (a_cost(), 0usize..3, -0.3..0.3f64, a_cost(), 0usize..6).prop_map(
            |(reference, how, nudge, anywhere, possible)| {
                let moved = match how {
                    0 => reference,
                    1 => (reference + nudge).max(0.0),
                    _ => anywhere,
                };
                (reference, moved, possible != 0)
            },
        );
        prop::collection::vec(prop::collection::vec(mode, 1..5), 1..5)
    }

    proptest! {
        #![proptest_config(seeded::config(512))]

        /// The lazily costed certified list serves exactly what costing every known solution
        /// and serving them from a heap does, in the same order, ties included ("The certified
        /// list, lazily"): random shapes, reference orders built in two runs (solutions learned
        /// later merged in), drifts over possible modes only, any limit.
        #[test]
        fn the_lazy_certified_list_serves_as_the_whole_heap(
            shape in a_shape(),
            picks in prop::collection::vec(prop::collection::vec(0u32..4, 4), 0..40),
            learned_first in 0usize..40,
            limit in prop_oneof![Just(f64::INFINITY), 0.0..30.0f64],
            absent in 0usize..50,
            identical in any::<bool>(),
        ) {
            let reference: Vec<Vec<f64>> =
                shape.iter().map(|c| c.iter().map(|m| m.0).collect()).collect();
            let moved: Vec<Vec<f64>> =
                shape.iter().map(|c| c.iter().map(|m| m.1).collect()).collect();
            let moved = if identical { reference.clone() } else { moved };
            let (reference, moved) = (Arc::new(choices_of(&reference)), choices_of(&moved));
            // Known solutions take possible modes only (one position may be absent).
            let positions: Vec<Vec<u32>> = picks
                .iter()
                .enumerate()
                .filter_map(|(s, pick)| {
                    shape
                        .iter()
                        .zip(pick)
                        .map(|(next, &p)| {
                            let allowed: Vec<u32> = (0..next.len() as u32)
                                .filter(|&m| next[m as usize].2)
                                .collect();
                            (!allowed.is_empty()).then(|| allowed[p as usize % allowed.len()])
                        })
                        .enumerate()
                        .map(|(c, p)| if s == absent && c == 0 { Some(u32::MAX) } else { p })
                        .collect()
                })
                .collect();
            let possible = |c: usize, mode: ValueId| shape[c][mode.index()].2;
            let mut order = Reference::default();
            let first = learned_first.min(positions.len());
            order.refresh(&positions[..first], &reference, |_| 0.0);
            order.refresh(&positions, &reference, |_| 0.0);
            prop_assert_eq!(order.covered, positions.len());
            let same = same_costs(&reference, &moved);
            prop_assert!(same || !identical);
            let mut lazy = Certified {
                limit,
                drift: drift(&reference, &moved, possible),
                same,
                next: 0,
                waiting: BinaryHeap::new(),
            };
            let mut whole: BinaryHeap<Waiting> = positions
                .iter()
                .enumerate()
                .filter_map(|(index, at)| Some((index, cost_at(&moved, at)?)))
                .filter(|(_, cost)| *cost <= limit)
                .map(|(index, cost)| Waiting { index, cost })
                .collect();
            loop {
                let served = lazy.pop(&order.order, &positions, &moved);
                let expected = whole.pop();
                prop_assert_eq!(
                    served.map(|w| (w.index, w.cost.to_bits())),
                    expected.map(|w| (w.index, w.cost.to_bits()))
                );
                if expected.is_none() {
                    break;
                }
            }
        }
    }

    /// The lower bound from a reference cost never decreases as the reference cost grows, so
    /// bounding the next solution in the reference order bounds every later one.
    #[test]
    fn the_floor_is_monotone() {
        let costs = [
            -1.0,
            -1e-300,
            -0.0,
            0.0,
            1e-300,
            1e-9,
            0.5,
            1.0,
            7.0,
            1e12,
            f64::INFINITY,
        ];
        for drift in [0.0, 1e-12, 0.3, 5.0] {
            for pair in costs.windows(2) {
                assert!(
                    floor(pair[0], drift) <= floor(pair[1], drift),
                    "{pair:?} {drift}"
                );
            }
        }
        assert!(floor(f64::INFINITY, f64::INFINITY).is_nan());
        assert_eq!(floor(3.0, f64::INFINITY), f64::NEG_INFINITY);
    }
}
