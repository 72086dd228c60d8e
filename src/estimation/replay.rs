//! Replaying a quiet step: the last step's streams, re-costed, instead
//! of streams rebuilt from the solution cache — only when that is certified to give exactly the
//! full expansion's answer.
//!
//! # What a full expansion does with the solution cache
//!
//! For each source k, `Streams::take` looks up the OCSP *shape* of k's choices (allowed next
//! modes and the observation) and lists the shape's known solutions that the certificate
//! covers: C_k = { known s : cost(s) ≤ L_k }, where L_k = ∞ for a complete shape and otherwise
//! `bound − drift(certificate's choices, k's choices)`, the drift running over the modes the
//! observation allows (deciding one not decided yet is a SAT call). C_k is served in the order
//! of a list sorted dearest first, stably over the known solutions' order, served from its back
//! (`streams::Waiting`: a heap with that order); only when it runs out does
//! a live OPSAT enumeration start (and then the stream's later costs are OPSAT's sums, its tie
//! order OPSAT's, and the cache learns solutions and a new certificate). The merge asks the
//! streams for costs in order, for next modes, for observation factors (cached per (modes,
//! observation); computing one asks the theory) and, past κ states, for each source's possible
//! mass (from the shape's cached mask of possible modes; computing it asks the theory).
//!
//! # The record, and what the replay assumes
//!
//! After a full expansion of [`Expander::step`](super::expand::Expander::step) that ran no live
//! enumeration into a budget cut, [`Replay::record`] keeps the observation and, per shape met
//! (one per slot of the cache), its slot, the choices c_ref of a source of that shape and R, the
//! known solutions the merge asked its sources' streams for (not what they fetched ahead),
//! widened at the first replay by every known solution within [`TIE_GAP`] of R's dearest under
//! c_ref (R may be any set of known solutions: the argument below holds for each; widening keeps
//! a plateau of equally likely solutions from being split between R and the others, where no
//! margin could tell them apart). Any other expansion forgets the record, so while a record
//! lives the cache has not changed: no live enumeration has run since (a replay runs none), the
//! shapes map, the known solutions, their certificates and completeness are as the recorded
//! expansion left them.
//!
//! The next step is replayed only if (checked by [`Replay::prepare`], all of it or nothing):
//! 1. the observation is the same and each source has the *same shape* as a recorded one (same
//!    next modes per component, in the same order; the belief's order may have changed): the
//!    full step would look up the very slot recorded (the cache is not about to start afresh
//!    either); below, R_k is that shape's R and c_ref its recorded choices;
//! 2. every L_k can be computed from modes already decided possible or not (the full step would
//!    make no SAT call in `take`); the replay computes it with the same function and inputs, so
//!    the same number;
//! 3. the costs of R_k under the new choices are computed by the function the certified list
//!    uses (`cost_at`, the same sums in the same order), so they are the very numbers the full
//!    step serves, and sorted with the same comparator over the same (index) order, so ties fall
//!    the same way;
//! 4. every solution the merge asks of source k — the i-th cheapest of R_k, r_i — satisfies
//!    r_i ≤ L_k (it is in C_k) and r_i < O_k, where O_k bounds from below the new cost of every
//!    known solution outside R_k: at recording their cheapest cost under c_ref was G_k, and a
//!    solution's cost moves by at most D_k = Σ_components max |c_new − c_ref| over the next
//!    modes those solutions take, so O_k = G_k − D_k less a rounding margin of
//!    [`ROUNDING`]·(1 + G_k + D_k) (a cost is a sum of a few dozen non-negative terms: its
//!    rounding error is under 1e-14 relative; the margin is far wider). Then the first i + 1
//!    solutions of C_k in serving order are exactly the first i + 1 of R_k (every other member
//!    of C_k is strictly dearer than r_i, so no tie order can interleave it), served without a
//!    live run;
//! 5. a stream asked past R_k answers "none" only if the shape is complete and R_k is all of
//!    its known solutions (exactly when the full stream ends there); otherwise the replay stops;
//! 6. a factor is served only as the observation model answers without the theory — 1 with
//!    nothing observed, else from its cache (remembered per known solution for the record's
//!    life: that cache only grows or starts afresh in a full step, which replaces the record;
//!    `observe.rs`) — a possible mass only from the shape's cached mask, with the function
//!    the full step uses;
//! 7. a candidate's successor (source state s, next modes m) is the one `Expander::step` builds,
//!    `successor(s, m, t).forget_idle_clocks(plant)` (built in one pass,
//!    `plant::successor_forgetting`), or a copy of one built in an earlier step
//!    of the record's life from a source state equal to s (modes and clock starts bit for bit)
//!    with the same known solution m, kept only if every component that changed mode had its
//!    clock forgotten. That successor depends on s and m alone: a component that kept its mode
//!    keeps s's clock start (forgotten or not by its mode alone), one that changed mode would
//!    restart its clock at t but has it forgotten, by its new mode alone, whatever t. So the
//!    copy equals what the full step builds, bit for bit, and it is merged under the same hash
//!    (`expand::state_hash` of an equal state) by the same `Merged` code. "Equal to s" is
//!    checked by comparing the states, or by the source's choices having a version already
//!    seen with the state compared: `Expander::choices` hands a version of choices out only
//!    for states equal (modes and clock starts bit for bit) to the one it was made for
//!    (`recents.rs`, `Recents`), and a version is never handed out for other choices
//!    (`expand.rs`, `Choices`), so it names that state.
//!
//! Under 1–7 the merge — the same function in both cases (`expand::merge`) — sees the same
//! costs, modes, factors and masses in the same order as in the full step, so it examines the
//! same candidates, builds the same successors, sums the same weights in the same order and
//! stops at the same point: the answer is bit for bit the full step's. And the full step would
//! have left the cache as it was (no live run renews a certificate or adds a solution; the only
//! writes would be to pure caches, which hold the same answers either way), so later steps are
//! unaffected. When a condition fails the replay stops, having changed nothing but its own
//! scratch, and the step is expanded in full (and recorded afresh).
//!
//! # Shared successors
//!
//! A successor kept under condition 7 is stored as the state it was merged into: when the merge
//! already held an equal state (modes and clock starts bit for bit: `SystemState`'s equality,
//! which `Merged::find` asks), the kept copy takes that state's allocations, and a kept copy
//! found again but merged into an equal state held in other allocations is made to share them
//! too. The value is the same, so conditions 1–7 and the answer are untouched; what changes is
//! that the states a quiet step compares (a candidate found again among the merged states, a
//! source against its kept successors and its recent choices, the plant states grouped by
//! modes) are the same allocations from step to step, and equality is a pointer comparison
//! where it compared a vector of modes and one of clock starts. On the Mars lander's quiet
//! cycle, where several sources reach the same next state, it took 42.4 k → 41.2 k
//! instructions and 4 % off the nominal EDL's CPU time.
//!
//! The record's bound on the other solutions is computed once per record (it costs a pass over
//! the shape's known solutions, what `take` does every step), at the first replay. A source's
//! preparation (its shape, L, O, its R ordered and, once asked, its possible mass) is a
//! function of its choices while the record lives, so it is kept per source for the last few
//! versions of choices (a quiet source keeps its very choices from step to step, `recents.rs`
//! `Recents`) and a source whose choices have one of those versions (a version names one
//! content for good, `expand.rs` `Choices`) is not prepared again. Only the record's reference
//! choices c_ref are held (their content is read); the rest is keyed by version and holds no
//! `Arc`, so a source whose one running clock moved has its choices written in place rather
//! than copied (`expand.rs`, `Choices`), which took 5 % off the nominal Mars EDL's CPU time.

use std::sync::Arc;

use super::WeightedState;
use super::expand::{Choices, SourceChoices};
use super::merge::{Merged, Serve, state_hash};
use super::observe::ObservationModel;
use super::streams::{Known, SolutionCache, cost_at, drift, possible_mass_under};
use crate::logic::ValueId;
use crate::opsat::Theory;
use crate::plant::{Observation, SystemState};

/// The rounding margin of condition 4 (module documentation), relative to the costs compared.
const ROUNDING: f64 = 1e-9;

/// Known solutions this close (in nats, at recording) to the dearest one served join R, so that
/// R and the others are apart by more than the costs drift in a few steps.
const TIE_GAP: f64 = 1.0;

/// The replay could not certify that its answer is the full expansion's.
#[derive(Debug)]
pub(crate) struct Uncertified;

/// The last fully expanded step, as the next one may replay it.
pub(crate) struct Replay {
    observation: Observation,
    /// The recorded shapes, one per slot.
    shapes: Vec<Shape>,
    /// This step, per source: what it is served from.
    sources: Vec<Variants>,
    /// The cache's answers about possible modes, as the drift asks them.
    decided: Decided,
}

/// The solution cache's answers to "is component c possibly in this mode under the observation"
/// ([`SolutionCache::decided`]), by component and mode, as first asked while the record lives.
/// Exact: the cache does not change while a record lives (module documentation), so neither
/// do its answers, undecided ones included; a table read is what this saves over a hash lookup
/// per component and source in every step's drift.
#[derive(Default)]
struct Decided(Vec<Vec<Option<Option<bool>>>>);

impl Decided {
    fn get(&mut self, cache: &SolutionCache, c: usize, mode: ValueId) -> Option<bool> {
        if self.0.len() <= c {
            self.0.resize_with(c + 1, Vec::new);
        }
        let modes = &mut self.0[c];
        if modes.len() <= mode.index() {
            modes.resize(mode.index() + 1, None);
        }
        *modes[mode.index()].get_or_insert_with(|| cache.decided(c, mode))
    }
}

/// One OCSP shape of the recorded step.
struct Shape {
    /// Its slot in the solution cache.
    slot: usize,
    /// The choices of a source of this shape at recording (c_ref).
    choices: Arc<Choices>,
    /// R: the known solutions its sources' streams served or fetched ahead, by index,
    /// ascending (widened once by [`Others::of`]).
    served: Vec<usize>,
    /// G and the modes of the solutions outside R, once computed.
    others: Option<Others>,
    /// Per known solution, its observation factor under the recorded observation once looked
    /// up (NaN until then): a factor is a pure function of the modes and the observation.
    factors: Vec<f64>,
}

/// How many preparations a source keeps: one per step length that recurs (a cycle's length
/// jitters in its last bits, so a few lengths alternate, each with its own choices).
const VARIANTS: usize = 4;

/// One source's recent preparations, the current one first to be looked at.
#[derive(Default)]
struct Variants {
    prepared: Vec<Prepared>,
    /// The successors built from this source (condition 7 of the module documentation).
    successors: Successors,
    /// The one this step is served from.
    current: usize,
    /// The one to replace next when all [`VARIANTS`] are taken.
    next: usize,
}

/// The successors built from one source state, by known solution, with their hashes: kept only
/// where no clock restarted (condition 7 of the module documentation).
#[derive(Default)]
struct Successors {
    /// The source state and the shape (its index in [`Replay::shapes`]) they were built from.
    from: Option<(SystemState, usize)>,
    /// Versions of choices handed out for that state (at most [`VARIANTS`]).
    seen: Vec<u64>,
    /// Per known solution of the shape.
    built: Vec<Option<(SystemState, u64)>>,
}

impl Successors {
    /// Keeps what was built if it was built from `source` of shape `shape`, else starts afresh
    /// for a shape of `solutions` known solutions. `choices` are `source`'s: `Expander::choices`
    /// hands a version of choices out again only for a state equal to the one it was made for
    /// (`recents.rs`, `Recents`), so a version already seen with the state built from spares
    /// comparing the states.
    fn keep_for(
        &mut self,
        source: &SystemState,
        choices: &Choices,
        shape: usize,
        solutions: usize,
    ) {
        let Some((state, at)) = &self.from else {
            return self.start(source, choices, shape, solutions);
        };
        if *at != shape {
            return self.start(source, choices, shape, solutions);
        }
        if self.seen.contains(&choices.version()) {
            return;
        }
        if state != source {
            return self.start(source, choices, shape, solutions);
        }
        if self.seen.len() >= VARIANTS {
            self.seen.remove(0);
        }
        self.seen.push(choices.version());
    }

    fn start(&mut self, source: &SystemState, choices: &Choices, shape: usize, solutions: usize) {
        self.from = Some((source.clone(), shape));
        self.seen.clear();
        self.seen.push(choices.version());
        self.built.clear();
        self.built.resize(solutions, None);
    }
}

impl Variants {
    /// The preparation this step is served from.
    fn current(&self) -> &Prepared {
        &self.prepared[self.current]
    }

    /// Selects the preparation made from `choices` if there is one (true), else an entry to
    /// prepare, emptied (false).
    fn select(&mut self, choices: &Choices) -> bool {
        let version = Some(choices.version());
        let made = self.prepared.iter().position(|p| p.choices == version);
        if let Some(at) = made {
            self.current = at;
            return true;
        }
        // The shape found last is where the search for the new one starts.
        let shape = self.prepared.get(self.current).map_or(0, |p| p.shape);
        if self.prepared.len() < VARIANTS {
            self.current = self.prepared.len();
            self.prepared.push(Prepared::default());
        } else {
            self.current = self.next;
            self.next = (self.next + 1) % VARIANTS;
        }
        let prepared = &mut self.prepared[self.current];
        prepared.choices = None;
        prepared.shape = shape;
        false
    }
}

/// One source of this step, prepared.
struct Prepared {
    /// The version of the choices it was prepared from: everything below is a function of
    /// them while the record lives, so a source whose choices have this version is prepared
    /// already.
    choices: Option<u64>,
    /// Index of its shape in [`Replay::shapes`].
    shape: usize,
    /// R's solutions with their costs under this step's choices, dearest first (served from
    /// the back).
    order: Vec<(usize, f64)>,
    /// L, the certified list's limit.
    certified: f64,
    /// O, below which no known solution outside R costs.
    others_bound: f64,
    /// The source's possible mass under its shape's mask (see [`Serve::possible_mass`]), once
    /// asked: a function of the choices and of the mask, which the cache keeps while the
    /// record lives.
    possible: Option<f64>,
}

/// The known solutions of a shape outside R.
struct Others {
    /// G: the cheapest of them under c_ref (∞ if none).
    cheapest: f64,
    /// Per component, per position among its next modes: whether one of them takes it.
    used: Vec<Vec<bool>>,
}

impl Others {
    /// Widens `served` by every known solution within [`TIE_GAP`] of its dearest under
    /// `choices` (so that a plateau of equally likely solutions is not split between R and
    /// the others, where no rounding margin could separate them), then bounds the rest.
    fn of(known: &Known, served: &mut Vec<usize>, choices: &Choices) -> Others {
        let costs: Vec<Option<f64>> = known
            .positions
            .iter()
            .map(|positions| cost_at(choices, positions))
            .collect();
        let dearest = served
            .iter()
            .filter_map(|&i| costs[i])
            .fold(f64::NEG_INFINITY, f64::max);
        let mut used: Vec<Vec<bool>> = choices.iter().map(|next| vec![false; next.len()]).collect();
        let mut cheapest = f64::INFINITY;
        let mut near = Vec::new();
        for (index, (positions, cost)) in known.positions.iter().zip(&costs).enumerate() {
            let cost = cost.unwrap_or(f64::INFINITY);
            if served.binary_search(&index).is_ok() {
                continue;
            }
            if cost <= dearest + TIE_GAP {
                near.push(index);
                continue;
            }
            for (flags, &at) in used.iter_mut().zip(positions) {
                if let Some(flag) = flags.get_mut(at as usize) {
                    *flag = true;
                }
            }
            cheapest = cheapest.min(cost);
        }
        // Added after the pass: `served` stays sorted (and so a set) while it is searched.
        served.extend(near);
        served.sort_unstable();
        Others { cheapest, used }
    }

    /// O: G less how far the costs of the modes they take moved from `old` to `new`, less the
    /// rounding margin.
    fn bound(&self, old: &Choices, new: &Choices) -> f64 {
        if self.cheapest == f64::INFINITY {
            return f64::INFINITY;
        }
        let moved: f64 = old
            .iter()
            .zip(new)
            .zip(&self.used)
            .map(|((a, b), used)| {
                if Arc::ptr_eq(a, b) {
                    return 0.0;
                }
                a.iter()
                    .zip(b.iter())
                    .zip(used)
                    .filter(|(_, used)| **used)
                    .map(|((x, y), _)| (x.cost - y.cost).abs())
                    .fold(0.0, f64::max)
            })
            .sum();
        let margin = ROUNDING * (1.0 + self.cheapest.abs() + moved);
        // A NaN (an infinite cost moved) compares false below: nothing is certified.
        self.cheapest - moved - margin
    }
}

/// Whether two choices have the same shape: the same next modes per component, in order.
fn same_shape(a: &Choices, b: &Choices) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            Arc::ptr_eq(x, y)
                || (x.len() == y.len() && x.iter().zip(y.iter()).all(|(m, n)| m.mode == n.mode))
        })
}

impl Replay {
    /// The record of a full expansion of `sources` under `observation`, from what its streams
    /// `served` ((slot, indices) per source, as `Streams::served` gives them), read after the
    /// knowledge was put back into `cache`; `None` if a shape's knowledge was started afresh
    /// on the way back (the indices would name nothing).
    pub(crate) fn record(
        cache: &SolutionCache,
        sources: &[SourceChoices],
        observation: &Observation,
        served: Vec<(usize, Vec<usize>)>,
    ) -> Option<Replay> {
        let mut shapes: Vec<Shape> = Vec::new();
        for (source, (slot, served)) in sources.iter().zip(served) {
            let known = cache.known(slot)?;
            if served.iter().any(|&i| i >= known.solutions.len()) {
                return None;
            }
            match shapes.iter_mut().find(|shape| shape.slot == slot) {
                Some(shape) => {
                    shape.served.extend(served);
                    shape.served.sort_unstable();
                    shape.served.dedup();
                }
                None => shapes.push(Shape {
                    slot,
                    choices: Arc::clone(&source.choices),
                    served,
                    others: None,
                    factors: vec![f64::NAN; known.solutions.len()],
                }),
            }
        }
        Some(Replay {
            observation: observation.clone(),
            shapes,
            sources: Vec::new(),
            decided: Decided::default(),
        })
    }

    /// Checks conditions 1 and 2 of the module documentation for a step of `sources` under
    /// `observation`, and costs and orders each source's R under its new choices (condition
    /// 3) with the limits of condition 4.
    pub(crate) fn prepare(
        &mut self,
        cache: &SolutionCache,
        sources: &[SourceChoices],
        observation: &Observation,
    ) -> Result<(), Uncertified> {
        if self.observation != *observation || cache.is_full() {
            return Err(Uncertified);
        }
        self.sources.resize_with(sources.len(), Variants::default);
        for (k, (variants, source)) in self.sources.iter_mut().zip(sources).enumerate() {
            if variants.select(&source.choices) {
                continue;
            }
            let prepared = &mut variants.prepared[variants.current];
            // The shape of this source in the last step first (the belief's order seldom
            // changes), then the others from the source's own index on.
            let shape = std::iter::once(prepared.shape)
                .chain(k..self.shapes.len())
                .chain(0..k.min(self.shapes.len()))
                .find(|&j| {
                    self.shapes
                        .get(j)
                        .is_some_and(|shape| same_shape(&shape.choices, &source.choices))
                })
                .ok_or(Uncertified)?;
            let decided = &mut self.decided;
            prepared.prepare(
                cache,
                decided,
                &mut self.shapes[shape],
                shape,
                &source.choices,
            )?;
            prepared.choices = Some(source.choices.version());
        }
        Ok(())
    }

    /// The merge's view of this step (after [`Replay::prepare`]).
    /// `states` are the sources' states, from which `Expander::step` builds the successors.
    pub(crate) fn serve<'a>(
        &'a mut self,
        cache: &'a SolutionCache,
        sources: &'a [SourceChoices],
        states: &'a [WeightedState],
    ) -> Replaying<'a> {
        for ((variants, weighted), source) in self.sources.iter_mut().zip(states).zip(sources) {
            let shape = variants.current().shape;
            let solutions = self.shapes[shape].factors.len();
            variants
                .successors
                .keep_for(&weighted.state, &source.choices, shape, solutions);
        }
        Replaying {
            replay: self,
            cache,
            sources,
            states,
        }
    }
}

impl Default for Prepared {
    fn default() -> Prepared {
        Prepared {
            choices: None,
            shape: 0,
            order: Vec::new(),
            certified: f64::NEG_INFINITY,
            others_bound: f64::NEG_INFINITY,
            possible: None,
        }
    }
}

impl Prepared {
    fn prepare(
        &mut self,
        cache: &SolutionCache,
        decided: &mut Decided,
        shape: &mut Shape,
        index: usize,
        choices: &Choices,
    ) -> Result<(), Uncertified> {
        self.shape = index;
        self.possible = None;
        let known = cache.known(shape.slot).ok_or(Uncertified)?;
        self.certified = if known.complete {
            f64::INFINITY
        } else {
            let (old, bound) = known.certificate.as_ref().ok_or(Uncertified)?;
            let mut undecided = false;
            let moved = drift(old, choices, |c, mode| {
                decided.get(cache, c, mode).unwrap_or_else(|| {
                    undecided = true;
                    true
                })
            });
            if undecided {
                return Err(Uncertified);
            }
            bound - moved
        };
        let others = shape
            .others
            .get_or_insert_with(|| Others::of(known, &mut shape.served, &shape.choices));
        self.others_bound = others.bound(&shape.choices, choices);
        self.order.clear();
        for &index in &shape.served {
            let cost = cost_at(choices, &known.positions[index]).ok_or(Uncertified)?;
            self.order.push((index, cost));
        }
        // The certified list's order (`streams::Waiting`): dearest first, stably, served
        // from the back.
        self.order.sort_by(|a, b| b.1.total_cmp(&a.1));
        Ok(())
    }
}

/// A prepared replay answering the merge (see [`Serve`]).
pub(crate) struct Replaying<'a> {
    replay: &'a mut Replay,
    cache: &'a SolutionCache,
    sources: &'a [SourceChoices],
    /// The source states, as the successors are built from them.
    states: &'a [WeightedState],
}

impl Replaying<'_> {
    fn known(&self, k: usize) -> Result<&Known, Uncertified> {
        let shape = &self.replay.shapes[self.replay.sources[k].current().shape];
        self.cache.known(shape.slot).ok_or(Uncertified)
    }
}

impl Serve for Replaying<'_> {
    type Error = Uncertified;

    fn cost(&mut self, k: usize, i: usize, _: &mut Theory) -> Result<Option<f64>, Uncertified> {
        let source = self.replay.sources[k].current();
        match source.order.len().checked_sub(i + 1) {
            Some(at) => {
                let cost = source.order[at].1;
                if cost <= source.certified && cost < source.others_bound {
                    Ok(Some(cost))
                } else {
                    Err(Uncertified)
                }
            }
            None => {
                let known = self.known(k)?;
                if known.complete && known.solutions.len() == source.order.len() {
                    Ok(None)
                } else {
                    Err(Uncertified)
                }
            }
        }
    }

    /// Source `k` and the index of its `i`-th solution among the shape's known ones
    /// (`usize::MAX`, which no factor is remembered for, if there is none).
    type Candidate = (usize, usize);

    fn candidate(&self, k: usize, i: usize) -> (usize, usize) {
        let source = self.replay.sources[k].current();
        let at = source.order.len().checked_sub(i + 1);
        (k, at.map_or(usize::MAX, |at| source.order[at].0))
    }

    fn possible_mass(&mut self, k: usize, _: &mut Theory) -> Result<f64, Uncertified> {
        let variants = &self.replay.sources[k];
        if let Some(possible) = variants.current().possible {
            return Ok(possible);
        }
        let mask = self.known(k)?.possible.as_ref().ok_or(Uncertified)?;
        let possible = possible_mass_under(&self.sources[k].choices, mask);
        let variants = &mut self.replay.sources[k];
        variants.prepared[variants.current].possible = Some(possible);
        Ok(possible)
    }

    fn factor(
        &mut self,
        observe: &mut ObservationModel,
        _: &mut Theory,
        &(k, index): &(usize, usize),
    ) -> Result<f64, Uncertified> {
        let shape = &mut self.replay.shapes[self.replay.sources[k].current().shape];
        let known = shape.factors.get_mut(index).ok_or(Uncertified)?;
        if known.is_nan() {
            let solutions = &self.cache.known(shape.slot).ok_or(Uncertified)?.solutions;
            let modes = solutions.get(index).ok_or(Uncertified)?;
            *known = observe
                .known_of_solution(modes, &self.replay.observation)
                .ok_or(Uncertified)?;
        }
        Ok(*known)
    }

    fn merge(
        &mut self,
        merged: &mut Merged,
        (k, index): (usize, usize),
        weight: f64,
        successor: &impl Fn(usize, &[ValueId]) -> SystemState,
    ) {
        let built = &mut self.replay.sources[k].successors.built;
        if let Some(Some((state, hash))) = built.get_mut(index) {
            let at = merged.add_known(state, *hash, weight);
            share(state, merged.state(at));
            return;
        }
        let modes = self
            .known(k)
            .ok()
            .and_then(|known| known.solutions.get(index))
            .map_or(&[][..], Vec::as_slice);
        let state = successor(k, modes);
        let hash = state_hash(&state);
        let keep = restarts_no_clock(&self.states[k].state, &state);
        let at = merged.add_hashed(state, hash, weight);
        let built = &mut self.replay.sources[k].successors.built;
        if keep && let Some(slot) = built.get_mut(index) {
            *slot = Some((merged.state(at).clone(), hash));
        }
    }
}

/// Makes `kept`, a successor kept for later steps, share the allocations of `merged`, the state
/// it was merged into (equal to it: modes and clock starts bit for bit), where it does not
/// already: the same value, so what later steps build from it is unchanged, but comparing the
/// two next time is a pointer comparison (the module documentation, "Shared successors").
#[inline]
fn share(kept: &mut SystemState, merged: &SystemState) {
    if !Arc::ptr_eq(&kept.modes, &merged.modes)
        || !Arc::ptr_eq(&kept.clock_starts, &merged.clock_starts)
    {
        *kept = merged.clone();
    }
}

/// Whether `next`, a successor of `source`, restarted no clock: every component that changed
/// mode has its clock forgotten, so that `next` does not depend on the step's end (condition 7
/// of the module documentation).
fn restarts_no_clock(source: &SystemState, next: &SystemState) -> bool {
    source
        .modes
        .iter()
        .zip(next.modes.iter())
        .zip(next.clock_starts.iter())
        .all(|((before, after), start)| before == after || start.is_none())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(modes: &[u32], starts: &[Option<f64>]) -> SystemState {
        SystemState::new(modes.iter().map(|&m| ValueId(m)).collect(), starts.to_vec())
    }

    /// "Shared successors": a kept successor takes the allocations of the equal state it was
    /// merged into, keeping its value bit for bit, and is left alone when it shares them
    /// already.
    #[test]
    fn a_kept_successor_shares_the_merged_states_allocations() {
        let merged = state(&[1, 0, 2], &[None, Some(0.25), None]);
        let mut kept = state(&[1, 0, 2], &[None, Some(0.25), None]);
        assert!(!Arc::ptr_eq(&kept.modes, &merged.modes));
        let (hash, before) = (state_hash(&kept), kept.clone());
        share(&mut kept, &merged);
        assert!(Arc::ptr_eq(&kept.modes, &merged.modes));
        assert!(Arc::ptr_eq(&kept.clock_starts, &merged.clock_starts));
        assert_eq!(kept, before);
        assert_eq!(state_hash(&kept), hash);
        let shared = kept.clone();
        share(&mut kept, &merged);
        assert!(Arc::ptr_eq(&kept.modes, &shared.modes));
    }
}
