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
//! have equal futures. Merging comes *before* the κ heaviest are kept (DESIGN.md §8), so the
//! enumeration must not stop merely because no single further candidate outweighs the κ-th
//! state: many light candidates that land on a state already held add up (the heating →
//! standby flow of §7.1.2, a trickle per cycle next to a heavier `failed`, is all of standby's
//! growth). While at most κ states are merged, every candidate is taken (up to a cap), so
//! TimedME is the exact update whenever κ states suffice. Past κ it stops when, besides no
//! single candidate outweighing the κ-th state, the prior mass the streams have not yet handed
//! out (`merge::Unseen`: a source's targets sum to at most its probability, the observation factor
//! being at most 1) is at most [`MASS_TOLERANCE`] of the mass merged — or when the streams are
//! exhausted, or after a cap on candidates.
//!
//! Quiet cycles repeat themselves: the same source modes under the same commands enable the
//! same transitions, and the same OCSP shapes meet the same observation. Enabled transitions are
//! cached per (modes, μ), observation factors per (modes, observation), and each OCSP shape's
//! feasible solutions with a certificate that stays valid as probabilities drift (`streams.rs`),
//! so a quiet step — even with a jittery cycle length or a clock running — makes no SAT call.
//! Such a step whose sources' shapes and observation are the last step's is *replayed*: merged
//! from the last step's solutions re-costed, where that is certified to be exactly the full
//! expansion ([`Expander::step`], `replay.rs`).
//! Within a step, the κ sources mostly differ in one component's mode, so each component's
//! next-mode distribution is computed once per distinct input and shared ([`StepMemo`]).
//!
//! What a step costs beyond its answer is kept out without changing the answer: a candidate's
//! observation factor asks no consistency question (an OPSAT solution is consistent with the
//! model and the observation by construction; `observe.rs`), the stopping test counts the
//! weights that reach the next candidate's instead of selecting the κ-th largest (the same
//! comparison), and a source's recent choices are found by hash ([`Recents`]), not by a scan.

use std::cell::OnceCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use rustc_hash::FxHashMap;

use super::merge::{Buffers, Live, merge};
use super::observe::ObservationModel;
use super::recents::{Recent, Recents, StepMemo, Untimed, timed};
use super::replay::Replay;
use super::streams::{SolutionCache, Streams};
use super::{EstimationError, WeightedState};
use crate::logic::ValueId;
use crate::opsat::{Cut, Ocsp, SearchOptions, Theory};
use crate::plant::{
    Commands, Enabled, Observation, Plant, SystemState, enabled_transitions, successor_forgetting,
};

/// Past this many entries a cache starts afresh.
pub(super) const CACHE_LIMIT: usize = 20_000;

/// Once more than κ states are merged — the belief will be truncated, an approximation by
/// design — the expansion may stop when no single further candidate outweighs the κ-th state
/// and the prior mass not yet enumerated is at most this fraction of the (observation-weighted)
/// mass merged: nothing unseen can then move a kept probability by more than that. Chosen on the
/// Mars lander, whose dozen components failing at 1e-9/s leave ~2e-9 unseen per 0.1 s cycle
/// that no state kept at κ = 10 could absorb, so that its quiet cycles examine as many
/// candidates as before the rule (docs/design/estimation.md).
pub(crate) const MASS_TOLERANCE: f64 = 1e-8;

/// One next mode of a component, with its probability and its cost (−ln p).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NextMode {
    /// The mode.
    pub(crate) mode: ValueId,
    /// Its probability in this step.
    pub(crate) probability: f64,
    /// −ln of it.
    pub(crate) cost: f64,
}

impl NextMode {
    pub(crate) fn new(mode: ValueId, probability: f64) -> NextMode {
        NextMode {
            mode,
            probability,
            cost: -probability.ln(),
        }
    }
}

/// Per component, the next modes a source state may take (shared between the sources of a
/// step whose component has the same distribution), with a *version* that names the content.
///
/// # Versions
///
/// Every `Choices` value gets a version when it is made (built, collected or cloned) and a new
/// one whenever it is opened for writing ([`Choices::set`], iterating it mutably), from one
/// counter for the whole process that only counts up. So two `Choices` with the same version are
/// one value, never written since: a version names one content for good, whether or not
/// anything still holds it. The caches that remember what is computed from choices (the
/// product of `merge::Unseen`, the replay's preparations and the choices it has seen with a
/// source state) are keyed by the version, hold no `Arc`, and a quiet source's choices can be
/// updated in place.
///
/// That is what the Mars lander's quiet cycles need: a source's running clock moves its
/// distribution in one component (the nominal EDL writes a source's choices 120 k times in
/// 171,577 cycles). Keyed by the `Arc`'s address, the caches had to hold the `Arc` (lest the
/// address be reused), so a changed source copied all of its 22 next-mode lists into a new
/// allocation (22 atomic increments, 22 decrements and two frees once the last cache let go;
/// with what new allocations cost the caches, ≈ 15 % of the EDL's time samples). Keyed by
/// version, [`Recent`]'s `Arc` is unique once the caches that need the content (a recorded
/// replay's reference choices, the solution cache's certificates) have let go of it or it was
/// copied once away from them, and `Arc::make_mut` writes the one changed list in place: the
/// nominal EDL's CPU time went down 5 % (0.646 → 0.606 s, median of 7 pairs). Every write in
/// the EDL found the `Arc` unique but 163, each the first after a full expansion.
#[derive(Debug)]
pub(crate) struct Choices {
    version: u64,
    next: Vec<Arc<[NextMode]>>,
}

/// The last version handed out ([`Choices`]).
static VERSIONS: AtomicU64 = AtomicU64::new(0);

/// A version no `Choices` had before.
fn fresh_version() -> u64 {
    VERSIONS.fetch_add(1, Ordering::Relaxed) + 1
}

impl Choices {
    /// Choices of these next modes per component, with a new version.
    pub(crate) fn new(next: Vec<Arc<[NextMode]>>) -> Choices {
        Choices {
            version: fresh_version(),
            next,
        }
    }

    /// The version naming this content ([`Choices`]).
    pub(crate) fn version(&self) -> u64 {
        self.version
    }

    /// Replaces component `c`'s next modes (a new version).
    pub(crate) fn set(&mut self, c: usize, next: Arc<[NextMode]>) {
        self.version = fresh_version();
        self.next[c] = next;
    }
}

impl Clone for Choices {
    /// The same next modes under a new version: the copy is about to be written (as by
    /// `Arc::make_mut`), and a version names one value.
    fn clone(&self) -> Choices {
        Choices::new(self.next.clone())
    }
}

impl std::ops::Deref for Choices {
    type Target = [Arc<[NextMode]>];

    fn deref(&self) -> &[Arc<[NextMode]>] {
        &self.next
    }
}

impl FromIterator<Arc<[NextMode]>> for Choices {
    fn from_iter<I: IntoIterator<Item = Arc<[NextMode]>>>(iter: I) -> Choices {
        Choices::new(iter.into_iter().collect())
    }
}

impl<'a> IntoIterator for &'a Choices {
    type Item = &'a Arc<[NextMode]>;
    type IntoIter = std::slice::Iter<'a, Arc<[NextMode]>>;

    fn into_iter(self) -> Self::IntoIter {
        self.next.iter()
    }
}

impl<'a> IntoIterator for &'a mut Choices {
    type Item = &'a mut Arc<[NextMode]>;
    type IntoIter = std::slice::IterMut<'a, Arc<[NextMode]>>;

    /// Opens the choices for writing: a new version.
    fn into_iter(self) -> Self::IntoIter {
        self.version = fresh_version();
        self.next.iter_mut()
    }
}

/// Next modes from a (mode, probability) distribution.
pub(super) fn next_modes(distribution: Vec<(ValueId, f64)>) -> Arc<[NextMode]> {
    distribution
        .into_iter()
        .map(|(m, p)| NextMode::new(m, p))
        .collect()
}

/// Choices from per-component (mode, probability) distributions.
pub(crate) fn choices_from(distributions: Vec<Vec<(ValueId, f64)>>) -> Choices {
    distributions.into_iter().map(next_modes).collect()
}

/// One source of candidates: a probability and, per component, its next modes.
pub(crate) struct SourceChoices {
    /// The source state's probability (1 for the initial distribution's pseudo-source).
    pub(crate) probability: f64,
    /// Per component, next modes (shared: quiet sources reuse them from cycle to cycle).
    pub(crate) choices: Arc<Choices>,
}

/// What an expansion found.
pub(crate) struct Expansion {
    /// Next system states with unnormalised posterior weights, heaviest first.
    pub(crate) states: Vec<WeightedState>,
    /// The weight of every state merged, `states` and those truncated away.
    pub(crate) merged: f64,
    /// Candidates examined.
    pub(crate) candidates: u64,
    /// Set when an OPSAT budget ran out.
    pub(crate) cut: Option<Cut>,
    /// Replayed from the last step ([`Expander::step`]) rather than expanded in full.
    pub(crate) replayed: bool,
    /// An upper bound on the weight the streams had not handed out when the expansion stopped
    /// (the prior mass of targets not enumerated, the observation factor being at most 1), in
    /// the units of `merged`: 0 when every stream was exhausted.
    pub(crate) unseen: f64,
    /// The probability one unit of `merged` stands for: weights are relative to the best
    /// candidate's trajectory probability, which is this.
    pub(crate) scale: f64,
    /// The weight of the heaviest state merged but not kept (0 when every one was kept).
    pub(crate) dropped: f64,
    /// The largest observation factor P_O(o | modes) of a candidate merged (0 when none was):
    /// how well the best explanation found explains the observation.
    pub(crate) best_factor: f64,
}

impl Expansion {
    /// The bound [`super::Belief::distance_bound`] rests on, after this step with `kept` the
    /// states kept, from a belief whose bound was `before`: the weight the exact update holds
    /// outside the kept states, over the weight of the kept states (see `timed_me.rs`,
    /// "How far from exact"). Infinite when a budget cut the search (targets were skipped
    /// unseen) or nothing was kept.
    pub(crate) fn outside(&self, kept: &[WeightedState], before: f64) -> f64 {
        let kept: f64 = kept.iter().map(|w| w.probability).sum();
        if self.cut.is_some() || kept <= 0.0 || self.scale <= 0.0 {
            return f64::INFINITY;
        }
        ((self.merged + self.unseen - kept).max(0.0) + before / self.scale) / kept
    }

    /// The fraction of the merged weight truncated away (0 when nothing was merged).
    pub(crate) fn lost(&self) -> f64 {
        let kept: f64 = self.states.iter().map(|w| w.probability).sum();
        if self.merged > 0.0 {
            (1.0 - kept / self.merged).max(0.0)
        } else {
            0.0
        }
    }
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
    /// Whether the sources' searches share their conflicts ([`crate::opsat::ConflictStore`]).
    pub(crate) share_conflicts: bool,
}

/// The expansion machinery and its caches (one per estimator, per plant).
#[derive(Default)]
pub(crate) struct Expander {
    enabled: FxHashMap<Vec<u32>, Arc<Vec<Enabled>>>,
    memo: StepMemo,
    /// The sources of the last step and of this one, with their choices ([`Recents`]).
    recent: Recents,
    solutions: SolutionCache,
    pub(crate) observe: ObservationModel,
    scratch: Vec<u32>,
    /// The merge's working storage, reused from one expansion to the next.
    buffers: Buffers,
    /// The last step, recorded for the next one to replay ([`Expander::step`]).
    replay: Option<Replay>,
}

impl Expander {
    /// Each component's next modes from `state` in the step `from`–`to` (Figure 6-10's
    /// "identify enabled transitions" and §6.2.2's probabilities). The enabled transitions are
    /// cached per (modes, μ); each component's distribution is shared by the sources, in this
    /// step and (without a clock reading) later ones, that give it the same inputs
    /// ([`StepMemo`]).
    pub(crate) fn choices(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        state: &SystemState,
        commands: &Commands,
        from: f64,
        to: f64,
    ) -> Result<Arc<Choices>, EstimationError> {
        self.memo.start(plant, from, to);
        self.recent.start(from, to);
        let step = to - from;
        let now = self.recent.steps;
        let hash = match self.recent.find(state, commands, step) {
            Ok(at) => {
                let source = &mut self.recent.pool[at];
                source.advance(plant, &mut self.memo.timed, state, from, step);
                source.used = now;
                return Ok(Arc::clone(&source.choices));
            }
            Err(hash) => hash,
        };
        let enabled = self.enabled(plant, theory, state, commands)?;
        let key = (Arc::as_ptr(&enabled) as usize, step.to_bits());
        let StepMemo {
            timed: timed_memos,
            untimed,
            clockless,
            ..
        } = &mut self.memo;
        let untimed = untimed.entry(key).or_insert_with(|| Untimed {
            _enabled: Arc::clone(&enabled),
            next: vec![None; plant.components().len()],
            whole: None,
        });
        let forgotten = state.clock_starts.iter().all(Option::is_none);
        let choices = match (forgotten, &untimed.whole) {
            (true, Some(whole)) => Arc::clone(whole),
            _ => {
                let choices: Arc<Choices> = Arc::new(
                    plant
                        .component_ids()
                        .zip(state.modes.iter())
                        .zip(timed_memos)
                        .zip(&mut untimed.next)
                        .enumerate()
                        .map(|(c, ((((id, component), &mode), memos), untimed))| {
                            match state.clock(id, from) {
                                None => Arc::clone(untimed.get_or_insert_with(|| {
                                    clockless.get(component, c, mode, &enabled[c], step)
                                })),
                                Some(reading) => {
                                    timed(memos, component, c, mode, &enabled, reading, step)
                                }
                            }
                        })
                        .collect(),
                );
                if forgotten {
                    untimed.whole = Some(Arc::clone(&choices));
                }
                choices
            }
        };
        let entry = Recent::new(
            plant,
            hash,
            state,
            commands,
            (step, from),
            now,
            enabled,
            &choices,
        );
        self.recent.push(entry);
        Ok(choices)
    }

    /// The enabled transitions from `state` under μ, cached per (modes, μ).
    fn enabled(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        state: &SystemState,
        commands: &Commands,
    ) -> Result<Arc<Vec<Enabled>>, EstimationError> {
        self.scratch.clear();
        self.scratch.extend(state.modes.iter().map(|m| m.0));
        self.scratch
            .extend(commands.values().iter().map(|(_, v)| v.0));
        // Delivered commands change the distributions: a separator, then them (nothing
        // without acknowledgements, so the key is the same then).
        if !commands.delivered().is_empty() {
            self.scratch.push(u32::MAX);
            self.scratch
                .extend(commands.delivered().iter().map(|v| v.0));
        }
        if let Some(enabled) = self.enabled.get(self.scratch.as_slice()) {
            return Ok(Arc::clone(enabled));
        }
        let enabled = Arc::new(enabled_transitions(plant, theory, &state.modes, commands)?);
        if self.enabled.len() >= CACHE_LIMIT {
            self.enabled.clear();
        }
        self.enabled
            .insert(self.scratch.clone(), Arc::clone(&enabled));
        Ok(enabled)
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
        successor: impl Fn(usize, &[ValueId]) -> SystemState,
    ) -> Result<Expansion, EstimationError> {
        self.expand_in_full(
            plant,
            theory,
            sources,
            observation,
            limits,
            successor,
            false,
        )
    }

    /// [`Expander::expand`], replaying the last step instead when that is certified to give the
    /// same answer ([`Replay`]) and `replay` allows it; a step expanded in full is recorded for
    /// the next one to replay.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn step(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        (sources, states): (&[SourceChoices], &[WeightedState]),
        (observation, time): (&Observation, f64),
        limits: Limits,
        replay: bool,
    ) -> Result<Expansion, EstimationError> {
        let successor = successor_from(plant, states, time);
        if let Some(recorded) = self.replay.as_mut().filter(|_| replay)
            && recorded
                .prepare(&self.solutions, sources, observation)
                .is_ok()
        {
            let mut serve = recorded.serve(&self.solutions, sources, states);
            let replayed = merge(
                &mut self.observe,
                &mut self.buffers,
                theory,
                sources,
                limits,
                &mut serve,
                &successor,
            );
            // Uncertified: the full expansion below gives the answer.
            if let Ok(candidates) = replayed {
                return Ok(self
                    .buffers
                    .merged
                    .expansion(limits.kappa, candidates, None, true));
            }
        }
        self.expand_in_full(
            plant,
            theory,
            sources,
            observation,
            limits,
            successor,
            replay,
        )
    }

    /// The expansion by the sources' streams; with `record`, kept for [`Expander::step`] to
    /// replay (any other expansion may change the solution cache a replay reads, so it forgets
    /// the recorded one).
    #[allow(clippy::too_many_arguments)]
    fn expand_in_full(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        sources: &[SourceChoices],
        observation: &Observation,
        limits: Limits,
        successor: impl Fn(usize, &[ValueId]) -> SystemState,
        record: bool,
    ) -> Result<Expansion, EstimationError> {
        self.replay = None;
        let ocsps: Vec<OnceCell<Ocsp>> = sources.iter().map(|_| OnceCell::new()).collect();
        let mut streams = Streams::take(
            &mut self.solutions,
            plant,
            theory,
            sources,
            observation,
            limits,
            &ocsps,
        );
        let mut live = Live {
            streams: &mut streams,
            plant,
            sources,
            observation,
        };
        let candidates = merge(
            &mut self.observe,
            &mut self.buffers,
            theory,
            sources,
            limits,
            &mut live,
            &successor,
        )?;
        let cut = streams.cut;
        let served: Vec<(usize, Vec<usize>)> = if record && cut.is_none() {
            streams.served().collect()
        } else {
            Vec::new()
        };
        streams.put_back(&mut self.solutions);
        if record && cut.is_none() {
            self.replay = Replay::record(&self.solutions, sources, observation, served);
        }
        Ok(self
            .buffers
            .merged
            .expansion(limits.kappa, candidates, cut, false))
    }
}

/// The system state source `k` of `states` reaches at `time` with next modes `modes` (Figure
/// 6-11 step 5: clocks restart where the mode changed; the clocks that cannot matter are
/// forgotten).
pub(crate) fn successor_from<'a>(
    plant: &'a Plant,
    states: &'a [WeightedState],
    time: f64,
) -> impl Fn(usize, &[ValueId]) -> SystemState + 'a {
    move |k, modes| successor_forgetting(plant, &states[k].state, modes, time)
}

#[cfg(test)]
mod tests {
    use super::super::recents::{Clockless, RECENT_STEPS, same_bits};
    use super::*;
    use crate::diagnostic::Source;
    use crate::plant;
    use crate::plant::component_distribution;
    use crate::seeded;
    use proptest::prelude::*;

    /// Choices' contents as bits, per component (mode, probability, cost).
    type Bits = Vec<Vec<(u32, u64, u64)>>;

    fn bits_of(choices: &Choices) -> Bits {
        choices
            .iter()
            .map(|next| {
                (next.iter())
                    .map(|n| (n.mode.0, n.probability.to_bits(), n.cost.to_bits()))
                    .collect()
            })
            .collect()
    }

    fn one_mode(mode: u32, probability: f64) -> Arc<[NextMode]> {
        Arc::from([NextMode::new(ValueId(mode), probability)])
    }

    /// `Choices`' versions: every value made, cloned or opened for writing has a version none
    /// had before; `Arc::make_mut` writes unique choices in place and copies shared ones,
    /// leaving the other holder's content and version as they were.
    #[test]
    fn every_written_choices_get_a_new_version() {
        let a = Choices::new(vec![one_mode(0, 1.0), one_mode(1, 0.5)]);
        let b: Choices = [one_mode(0, 1.0)].into_iter().collect();
        let copy = a.clone();
        assert!(a.version() != b.version() && copy.version() > a.version().max(b.version()));
        assert_eq!(bits_of(&copy), bits_of(&a));

        let mut unique = Arc::new(a);
        let (address, before) = (Arc::as_ptr(&unique), unique.version());
        Arc::make_mut(&mut unique).set(1, one_mode(1, 0.25));
        assert_eq!(Arc::as_ptr(&unique), address, "written in place");
        assert!(unique.version() > before);
        assert_eq!(unique[1][0].probability, 0.25);

        let held = Arc::clone(&unique);
        let (held_version, held_bits) = (held.version(), bits_of(&held));
        Arc::make_mut(&mut unique).set(0, one_mode(2, 1.0));
        assert!(!Arc::ptr_eq(&unique, &held), "a shared one is copied");
        assert_eq!((held.version(), bits_of(&held)), (held_version, held_bits));
        assert!(unique.version() > held_version);

        let mut opened = Choices::new(vec![one_mode(0, 1.0)]);
        let before = opened.version();
        for _ in &mut opened {}
        assert!(opened.version() > before);
        for _ in &opened {}
        assert_eq!(opened.version(), opened.version());
    }

    proptest! {
        #![proptest_config(seeded::config(64))]

        /// `Recents` and `Choices`' versions (DESIGN.md §8, the quiet step's caches): over
        /// steps with jittering lengths, on the Mars lander (22 components, clocks running in
        /// several modes), every choices `Expander::choices` hands out are, bit for bit, the
        /// distributions computed afresh from the state's enabled transitions and clocks
        /// (`plant::component_distributions`), whether found, advanced in place or made; and a
        /// version seen again names the same content for an equal state.
        #[test]
        fn choices_advanced_in_place_are_the_ones_computed_afresh(
            states in proptest::collection::vec((0usize..22, 0u32..6, 0u32..4), 1..6),
            steps in proptest::collection::vec(
                (0u32..3, proptest::collection::vec(0usize..6, 1..8)),
                1..40,
            ),
        ) {
            let text = include_str!("../../models/mars_lander.ron");
            let (plant, mut theory, idle, _) = one_mode_changed("mars_lander.ron", text);
            let initial = plant.most_likely_initial();
            let states: Vec<SystemState> = states
                .iter()
                .map(|&(c, m, start)| {
                    let mut modes = initial.clone();
                    modes[c] = ValueId(m % plant.components()[c].modes().len() as u32);
                    SystemState::entered_at(&plant, modes, -f64::from(start) * 0.7)
                })
                .collect();
            let mut expander = Expander::default();
            let mut named: FxHashMap<u64, (SystemState, Bits)> = FxHashMap::default();
            let mut from = 0.0;
            for (jitter, asked) in steps {
                let to = from + 0.1 + f64::from(jitter) * 1e-15;
                for k in asked {
                    let state = &states[k % states.len()];
                    let Ok(enabled) = enabled_transitions(&plant, &mut theory, &state.modes, &idle)
                    else {
                        continue;
                    };
                    let choices = expander.choices(&plant, &mut theory, state, &idle, from, to);
                    let choices = choices.expect("choices");
                    let computed: Choices =
                        plant::component_distributions(&plant, state, &enabled, from, to)
                            .into_iter()
                            .map(next_modes)
                            .collect();
                    prop_assert_eq!(bits_of(&choices), bits_of(&computed));
                    let entry = (state.clone(), bits_of(&choices));
                    let seen = named.entry(choices.version()).or_insert_with(|| entry.clone());
                    prop_assert!(seen.0 == entry.0 && seen.1 == entry.1, "a version names one");
                }
                from = to;
            }
        }
    }

    /// The case `Choices`' versions are for: a quiet source whose running clock changes its
    /// distribution from step to step keeps one allocation, written in place under a new
    /// version each time (the Mars lander, every component in every mode entered at 0, twelve
    /// steps of 0.125 s, a length every step gives bit for bit; the choices are dropped between
    /// steps as `TimedMe` drops its sources).
    #[test]
    fn a_running_clock_writes_its_choices_in_place() {
        let text = include_str!("../../models/mars_lander.ron");
        let (plant, mut theory, idle, variants) = one_mode_changed("mars_lander.ron", text);
        let mut expander = Expander::default();
        let (mut in_place, mut moved) = (0, 0);
        for (_, _, modes) in variants {
            let state = SystemState::entered_at(&plant, modes, 0.0);
            let mut last: Option<(usize, u64)> = None;
            for step in 0..12 {
                let from = f64::from(step) * 0.125;
                let made = expander.choices(&plant, &mut theory, &state, &idle, from, from + 0.125);
                let Ok(choices) = made else { break };
                let now = (Arc::as_ptr(&choices) as usize, choices.version());
                if let Some(before) = last
                    && before.1 != now.1
                {
                    moved += 1;
                    in_place += usize::from(before.0 == now.0);
                }
                last = Some(now);
            }
        }
        assert!(moved > 10, "distributions moved with a clock {moved} times");
        assert_eq!(in_place, moved, "every move written in place");
    }

    /// `Recents`' steady stretches (`plant::distribution_steady_at`): across the ends of the
    /// Mars lander's steady stretches — the engine's heating window opening at 30 s, the entry
    /// trigger's Gaussian 40 σ before its mean, at 15,612 s — a source advanced step by step
    /// gets, bit for bit, the distributions computed afresh at each step (every component in
    /// every mode, entered at 0, 0.1 s steps).
    #[test]
    fn a_steady_clock_keeps_the_distributions_computed_afresh() {
        let text = include_str!("../../models/mars_lander.ron");
        let (plant, mut theory, idle, variants) = one_mode_changed("mars_lander.ron", text);
        let mut checked = 0;
        for (_, _, modes) in variants {
            let state = SystemState::entered_at(&plant, modes, 0.0);
            let Ok(enabled) = enabled_transitions(&plant, &mut theory, &state.modes, &idle) else {
                continue;
            };
            let mut expander = Expander::default();
            for first in [25.0, 15_590.0] {
                for i in 0..300 {
                    let from = first + f64::from(i) * 0.1;
                    let to = from + 0.1;
                    let choices = expander.choices(&plant, &mut theory, &state, &idle, from, to);
                    let computed: Choices =
                        plant::component_distributions(&plant, &state, &enabled, from, to)
                            .into_iter()
                            .map(next_modes)
                            .collect();
                    assert_eq!(bits_of(&choices.expect("choices")), bits_of(&computed));
                    checked += 1;
                }
            }
        }
        assert!(checked > 1000, "{checked}");
    }

    /// A component, its mode, its enabled transitions and a step length as bits.
    type Inputs = (usize, ValueId, Enabled, u64);

    /// Asserts that `value` is the very allocation of a `seen` value exactly when their keys
    /// are equal, and remembers it under `key` if its key is new.
    fn shared_exactly_by_key<K: PartialEq, T: ?Sized>(
        seen: &mut Vec<(K, Arc<T>)>,
        key: K,
        value: Arc<T>,
        context: &str,
    ) {
        for (other_key, other) in seen.iter() {
            let same = *other_key == key;
            assert_eq!(Arc::ptr_eq(other, &value), same, "{context}");
        }
        if !seen.iter().any(|(other_key, _)| *other_key == key) {
            seen.push((key, value));
        }
    }

    /// Mode vectors as (the component moved, its mode, the modes).
    type Variants = Vec<(usize, u32, Vec<ValueId>)>;

    /// A model of `models/`, its theory, μ idle, and every mode vector that moves one
    /// component of the most likely initial state to one of its modes.
    fn one_mode_changed(name: &str, text: &str) -> (Plant, Theory, Commands, Variants) {
        let plant = Plant::load(&Source::new(name, text)).expect("the model loads");
        let theory = plant.theory().expect("theory");
        let idle = Commands::idle(&plant);
        let initial = plant.most_likely_initial();
        let variants = (plant.components().iter().enumerate())
            .flat_map(|(c, component)| (0..component.modes().len() as u32).map(move |m| (c, m)))
            .map(|(c, m)| {
                let mut modes = initial.clone();
                modes[c] = ValueId(m);
                (c, m, modes)
            })
            .collect();
        (plant, theory, idle, variants)
    }

    /// [`StepMemo`]'s certificate for the shared clockless distributions: an entry is the very
    /// distribution `component_distribution` computes from the same inputs (bit for bit), the
    /// same inputs share one allocation, and inputs that differ in the mode, the enabled
    /// transitions or the step's length never share one (the breaker tree, whose faults have
    /// rates, every component in every mode, two step lengths).
    #[test]
    fn a_shared_clockless_distribution_is_the_one_computed_from_its_inputs() {
        let text = include_str!("../../models/breakers_15.ron");
        let (plant, mut theory, idle, variants) = one_mode_changed("breakers_15.ron", text);
        let mut clockless = Clockless::default();
        let mut seen: Vec<(Inputs, Arc<[NextMode]>)> = Vec::new();
        for (c, m, modes) in variants {
            let component = &plant.components()[c];
            let Ok(enabled) = enabled_transitions(&plant, &mut theory, &modes, &idle) else {
                continue;
            };
            for step in [0.1, 1.0] {
                let (mode, own) = (modes[c], &enabled[c]);
                let next = clockless.get(component, c, mode, own, step);
                let computed = next_modes(component_distribution(component, mode, own, None, step));
                assert!(
                    same_bits(&next, &computed),
                    "component {c} mode {m} step {step}"
                );
                let again = clockless.get(component, c, mode, own, step);
                assert!(Arc::ptr_eq(&next, &again), "the same inputs share one");
                let inputs = (c, mode, own.clone(), step.to_bits());
                shared_exactly_by_key(&mut seen, inputs, next, &format!("{c} {m} {step}"));
            }
        }
        assert!(
            seen.len() > 40,
            "the breakers in their modes: {}",
            seen.len()
        );
    }

    /// `Untimed::whole`: a state with every clock forgotten gets one `Arc<Choices>` per (modes,
    /// μ, step length) — again in a later step once its recent entry is gone, and never for
    /// other modes — holding per component the distribution `component_distributions` computes
    /// (bit for bit); a state with clock starts gets its own (Livingstone 2's 15 breakers,
    /// every breaker in every mode).
    #[test]
    fn a_state_without_clocks_shares_its_whole_choices() {
        let text = include_str!("../../models/l2_breakers_15.ron");
        let (plant, mut theory, idle, variants) = one_mode_changed("l2_breakers_15.ron", text);
        let mut expander = Expander::default();
        let initial = plant.most_likely_initial();
        let mut seen: Vec<(Vec<ValueId>, Arc<Choices>)> = Vec::new();
        for (c, m, modes) in variants {
            let state = SystemState::new(modes.clone(), vec![None; modes.len()]);
            let Ok(first) = expander.choices(&plant, &mut theory, &state, &idle, 0.0, 1.0) else {
                continue;
            };
            // Steps on until the recent entry is dropped: the whole choices remain.
            let other = SystemState::new(initial.clone(), vec![None; initial.len()]);
            for t in 1..=RECENT_STEPS + 1 {
                let t = t as f64 * 10.0;
                let made = expander.choices(&plant, &mut theory, &other, &idle, t, t + 1.0);
                made.expect("choices");
            }
            assert!(expander.recent.pool.iter().all(|r| r.state != state) || modes == initial);
            let later = expander.choices(&plant, &mut theory, &state, &idle, 500.0, 501.0);
            let later = later.expect("choices");
            assert!(Arc::ptr_eq(&first, &later), "component {c} mode {m}");
            let enabled = enabled_transitions(&plant, &mut theory, &modes, &idle);
            let enabled = enabled.expect("enabled transitions");
            let computed = plant::component_distributions(&plant, &state, &enabled, 0.0, 1.0);
            assert_eq!(first.len(), computed.len());
            for (next, computed) in first.iter().zip(computed) {
                assert!(
                    same_bits(next, &next_modes(computed)),
                    "component {c} mode {m}"
                );
            }
            shared_exactly_by_key(&mut seen, modes, first, &format!("{c} {m}"));
        }
        assert!(
            seen.len() > 40,
            "the breakers in their modes: {}",
            seen.len()
        );
        let timed = SystemState::new(initial.clone(), vec![Some(0.0); initial.len()]);
        let own = expander.choices(&plant, &mut theory, &timed, &idle, 0.0, 1.0);
        let own = own.expect("choices");
        assert!(seen.iter().all(|(_, choices)| !Arc::ptr_eq(choices, &own)));
    }
}
