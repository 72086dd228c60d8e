//! The κ most likely next system states from a set of source states, by OPSAT (Figure 6-11,
//! steps 3–6, as DESIGN.md §8 frames it).
//!
//! Per source state, the enabled transitions (guards entailed by that state's modes and μ) give
//! each component a distribution over its next mode. The OCSP of that source decides every
//! component's next mode at cost −ln p, subject to the plant's theory and the observation: its
//! solutions, cheapest first, are the next plant states consistent with o(i+1), most probable
//! first. The sources' streams are merged best first by `p(source) · p(transition)` — the
//! trajectory probability f(τ) of Figure 6-11.
//!
//! Each candidate becomes a system state (clocks restarted where the mode changed, forgotten where
//! they cannot matter), is weighed by the observation factor (1 / 1/m, Figure 6-10; the thesis's
//! TimedME drops it), and is merged with equal states by summing — exact, since equal states
//! have equal futures. Enumeration stops once κ states are held and the κ-th best already
//! outweighs anything a further candidate could bring (the factor is at most 1), or after a cap
//! on candidates.
//!
//! Quiet cycles repeat themselves: the same source modes under the same commands enable the
//! same transitions, and the same OCSP meets the same observation. Both are cached across calls —
//! enabled transitions per (modes, μ), OCSP solution prefixes per (choices, observation),
//! observation factors per (modes, observation) — so a quiescent step makes no SAT call.

use std::cell::OnceCell;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::rc::Rc;

use super::observe::ObservationModel;
use super::{EstimationError, WeightedState};
use crate::logic::ValueId;
use crate::opsat::{Cut, Enumeration, Ocsp, SearchOptions, Theory};
use crate::plant::{
    Commands, Observation, Plant, SystemState, component_distributions, enabled_transitions,
    target_ocsp,
};

/// Past this many entries a cache starts afresh.
const CACHE_LIMIT: usize = 20_000;

/// One source of candidates: a probability and, per component, the next modes with their
/// probabilities.
pub(crate) struct SourceChoices {
    /// The source state's probability (1 for the initial distribution's pseudo-source).
    pub(crate) probability: f64,
    /// Per component, next modes and probabilities.
    pub(crate) choices: Vec<Vec<(ValueId, f64)>>,
}

/// What an expansion found.
pub(crate) struct Expansion {
    /// Next system states with unnormalised posterior weights, heaviest first.
    pub(crate) states: Vec<WeightedState>,
    /// Candidates examined.
    pub(crate) candidates: u64,
    /// Set when an OPSAT budget ran out.
    pub(crate) cut: Option<Cut>,
}

/// The solutions of one OCSP found so far, cheapest first.
#[derive(Default)]
struct CachedStream {
    solutions: Vec<(Vec<ValueId>, f64)>,
    exhausted: bool,
}

/// How many candidates and which OPSAT options an expansion may use.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits {
    /// States to keep.
    pub(crate) kappa: usize,
    /// Candidates to examine at most.
    pub(crate) max_candidates: usize,
    /// OPSAT's options (budget) per source stream.
    pub(crate) search: SearchOptions,
}

/// The expansion machinery and its caches (one per estimator, per plant).
#[derive(Default)]
pub(crate) struct Expander {
    enabled: HashMap<Vec<u32>, Rc<Vec<Vec<usize>>>>,
    solutions: HashMap<Vec<u64>, CachedStream>,
    pub(crate) observe: ObservationModel,
    scratch: Vec<u32>,
}

impl Expander {
    /// Each component's distribution over its next mode from `state` (Figure 6-10's "identify
    /// enabled transitions", with the enabled set cached per modes and μ).
    pub(crate) fn choices(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        state: &SystemState,
        commands: &Commands,
        from: f64,
        to: f64,
    ) -> Result<Vec<Vec<(ValueId, f64)>>, EstimationError> {
        self.scratch.clear();
        self.scratch.extend(state.modes.iter().map(|m| m.0));
        self.scratch
            .extend(commands.values().iter().map(|(_, v)| v.0));
        let enabled = match self.enabled.get(self.scratch.as_slice()) {
            Some(enabled) => Rc::clone(enabled),
            None => {
                let enabled = Rc::new(enabled_transitions(plant, theory, &state.modes, commands)?);
                if self.enabled.len() >= CACHE_LIMIT {
                    self.enabled.clear();
                }
                self.enabled
                    .insert(self.scratch.clone(), Rc::clone(&enabled));
                enabled
            }
        };
        Ok(component_distributions(plant, state, &enabled, from, to))
    }

    /// The most likely next system states (see the module documentation). `successor(k, modes)`
    /// builds the system state reached from source `k` with these next modes.
    pub(crate) fn expand(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        sources: &[SourceChoices],
        observation: &Observation,
        limits: Limits,
        successor: impl Fn(usize, Vec<ValueId>) -> SystemState,
    ) -> Result<Expansion, EstimationError> {
        if self.solutions.len() >= CACHE_LIMIT {
            self.solutions.clear();
        }
        let mut streams = Streams::take(&mut self.solutions, sources, observation, limits.search);
        let ocsps: Vec<OnceCell<Ocsp>> = streams.keys.iter().map(|_| OnceCell::new()).collect();
        let mut live: Vec<Option<Enumeration>> = streams.keys.iter().map(|_| None).collect();
        let mut fetch = |streams: &mut Streams, k: usize, i: usize, theory: &mut Theory| {
            streams.cost(k, i, &ocsps, &mut live, plant, sources, observation, theory)
        };
        let source_cost: Vec<f64> = sources.iter().map(|s| -s.probability.ln()).collect();
        let mut frontier = BinaryHeap::new();
        for (k, source) in sources.iter().enumerate() {
            if source.probability > 0.0 {
                if let Some(cost) = fetch(&mut streams, k, 0, theory) {
                    frontier.push(Reverse((order(source_cost[k] + cost), k, 0usize)));
                }
            }
        }
        let mut merged = Merged::default();
        let mut best = None;
        let mut candidates = 0u64;
        while let Some(Reverse((cost_bits, k, i))) = frontier.pop() {
            let cost = f64::from_bits(cost_bits);
            let best = *best.get_or_insert(cost);
            candidates += 1;
            let modes = streams.modes(k, i);
            if let Some(next) = fetch(&mut streams, k, i + 1, theory) {
                frontier.push(Reverse((order(source_cost[k] + next), k, i + 1)));
            }
            let factor = self.observe.factor(plant, theory, &modes, observation)?;
            let weight = (best - cost).exp() * factor;
            if weight > 0.0 {
                merged.add(successor(k, modes), weight);
            }
            if candidates as usize >= limits.max_candidates {
                break;
            }
            let next_weight = frontier.peek().map_or(0.0, |Reverse((bits, _, _))| {
                (best - f64::from_bits(*bits)).exp()
            });
            if merged.kth_weight(limits.kappa) >= next_weight {
                break;
            }
        }
        let cut = streams.cut;
        streams.put_back(&mut self.solutions);
        Ok(Expansion {
            states: merged.heaviest(limits.kappa),
            candidates,
            cut,
        })
    }
}

/// A non-negative cost as an integer with the same order (IEEE-754 bit patterns of non-negative
/// doubles order like the numbers).
fn order(cost: f64) -> u64 {
    cost.max(0.0).to_bits()
}

/// The identity of a source's OCSP: its choices (values and probability bits) and the
/// observation.
fn ocsp_key(choices: &[Vec<(ValueId, f64)>], observation: &Observation) -> Vec<u64> {
    let mut key = Vec::with_capacity(choices.len() * 5 + observation.values().len() + 1);
    for distribution in choices {
        key.push(distribution.len() as u64);
        for &(value, p) in distribution {
            key.extend([u64::from(value.0), p.to_bits()]);
        }
    }
    key.push(u64::MAX);
    for &(x, v) in observation.values() {
        key.push((u64::from(x.0) << 32) | u64::from(v.0));
    }
    key
}

/// The solution streams of one expansion: one per distinct OCSP (sources with equal choices
/// share one), each a cached prefix extended by a live OPSAT enumeration when it is not long
/// enough. The cached streams are taken out of the cache for the expansion and put back after.
struct Streams {
    keys: Vec<Vec<u64>>,
    streams: Vec<CachedStream>,
    /// Per source, its stream.
    of_source: Vec<usize>,
    /// Per stream, a source it belongs to (whose choices build the OCSP).
    first_source: Vec<usize>,
    options: SearchOptions,
    cut: Option<Cut>,
}

impl Streams {
    fn take(
        cache: &mut HashMap<Vec<u64>, CachedStream>,
        sources: &[SourceChoices],
        observation: &Observation,
        options: SearchOptions,
    ) -> Streams {
        let mut streams = Streams {
            keys: Vec::new(),
            streams: Vec::new(),
            of_source: Vec::with_capacity(sources.len()),
            first_source: Vec::new(),
            options,
            cut: None,
        };
        for (k, source) in sources.iter().enumerate() {
            let key = ocsp_key(&source.choices, observation);
            let index = match streams.keys.iter().position(|other| *other == key) {
                Some(index) => index,
                None => {
                    streams.streams.push(cache.remove(&key).unwrap_or_default());
                    streams.keys.push(key);
                    streams.first_source.push(k);
                    streams.keys.len() - 1
                }
            };
            streams.of_source.push(index);
        }
        streams
    }

    fn put_back(self, cache: &mut HashMap<Vec<u64>, CachedStream>) {
        cache.extend(self.keys.into_iter().zip(self.streams));
    }

    /// The next modes of solution `i` of source `k` (which [`Streams::cost`] has fetched).
    fn modes(&self, k: usize, i: usize) -> Vec<ValueId> {
        self.streams[self.of_source[k]]
            .solutions
            .get(i)
            .map(|(modes, _)| modes.clone())
            .unwrap_or_default()
    }

    /// The cost of solution `i` of source `k`, fetching it from OPSAT if needed; `None` when
    /// there is none (or the budget ran out).
    #[allow(clippy::too_many_arguments)]
    fn cost<'o>(
        &mut self,
        k: usize,
        i: usize,
        ocsps: &'o [OnceCell<Ocsp>],
        live: &mut [Option<Enumeration<'o>>],
        plant: &Plant,
        sources: &[SourceChoices],
        observation: &Observation,
        theory: &mut Theory,
    ) -> Option<f64> {
        let s = self.of_source[k];
        loop {
            let stream = &mut self.streams[s];
            if let Some((_, cost)) = stream.solutions.get(i) {
                return Some(*cost);
            }
            if stream.exhausted || self.cut.is_some() {
                return None;
            }
            let choices = &sources[self.first_source[s]].choices;
            let enumeration = live[s].get_or_insert_with(|| {
                ocsps[s]
                    .get_or_init(|| target_ocsp(plant, choices, observation))
                    .enumerate(theory, self.options)
            });
            match enumeration.next(theory) {
                Ok(Some(solution)) => {
                    let modes: Vec<ValueId> =
                        solution.assignment.into_iter().map(|(_, v)| v).collect();
                    // A fresh enumeration re-finds what an earlier call cached: skip those.
                    if !stream.solutions.iter().any(|(m, _)| *m == modes) {
                        stream.solutions.push((modes, solution.cost));
                    }
                }
                Ok(None) => stream.exhausted = true,
                Err(cut) => self.cut = Some(cut),
            }
        }
    }
}

/// Next system states with summed weights, in order of first appearance.
#[derive(Default)]
struct Merged {
    index: HashMap<SystemState, usize>,
    states: Vec<WeightedState>,
}

impl Merged {
    fn add(&mut self, state: SystemState, weight: f64) {
        match self.index.get(&state) {
            Some(&i) => self.states[i].probability += weight,
            None => {
                self.index.insert(state.clone(), self.states.len());
                self.states.push(WeightedState {
                    state,
                    probability: weight,
                });
            }
        }
    }

    /// The `k`-th largest weight, or 0 with fewer than `k` states.
    fn kth_weight(&self, k: usize) -> f64 {
        if k == 0 || self.states.len() < k {
            return 0.0;
        }
        let mut weights: Vec<f64> = self.states.iter().map(|w| w.probability).collect();
        weights.select_nth_unstable_by(k - 1, |a, b| b.total_cmp(a));
        weights[k - 1]
    }

    /// The `k` heaviest states, heaviest first (ties in order of appearance).
    fn heaviest(mut self, k: usize) -> Vec<WeightedState> {
        self.states
            .sort_by(|a, b| b.probability.total_cmp(&a.probability));
        self.states.truncate(k);
        self.states
    }
}
