//! TimedME (thesis Figure 6-11; DESIGN.md §8): the κ most likely next system states, on OPSAT.
//!
//! 1. (Figure 6-11 steps 1–2) For each of the κ current system states, clocks advance to t(i+1).
//! 2. (step 3) Its enabled transitions — guards entailed by its modes, the model and μ(i) —
//!    give each component a distribution over its next mode (§6.2.2's probabilities, timed ones
//!    in the conditional form); the targets must be consistent with o(i+1) and the model. That is
//!    one OCSP per source state over the plant's theory.
//! 3. (step 4) OPSAT enumerates each source's targets best first; the streams are merged by
//!    trajectory probability, weighed by the observation factor and merged exactly where system
//!    states coincide (see `expand.rs`).
//! 4. (step 5) Clocks restart for components that changed mode; clocks that cannot matter are
//!    forgotten.
//! 5. (step 6) The κ heaviest states, renormalised, are the new belief.
//!
//! If no target of any tracked state is consistent with o(i+1), the estimator reports an
//! [`EstimationEvent::InconsistentObservation`] and falls back (DESIGN.md §8): first it lets
//! components jump into their unconstrained fault modes, which explain anything of theirs; if
//! even that fails, it keeps the previous belief, clocks running on.
//!
//! # When the window is re-run
//!
//! The history window (`history.rs`) re-runs the recent steps tracking 8κ states, and keeps
//! the κ heaviest it ends with, on three occasions:
//! - the observation contradicts every successor of the tracked states (before DESIGN.md §8's
//!   fault jumps): from the window's start;
//! - ŝ is in doubt: the two heaviest plant states differ by less than [`AMBIGUITY`] times the
//!   weight truncated within the window (docs/design/estimation.md has the factor measured):
//!   from the window's start;
//! - the observation surprised, and a state dropped within the window may now outweigh a
//!   state kept. Each step keeps the κ heaviest states it merged — the most probable as far as
//!   the states tracked can tell — and an observation can make a dropped one the better
//!   explanation. Livingstone 2's reference diagnosis drops unknown on two breakers when led8
//!   is seen off (third in line there, behind trips and blown breakers); once led8 is seen on
//!   again, refuting the trips, those unknowns weigh 0.021 each against 0.0009 for the states
//!   kept in their place (other breakers tripping in the last step). Each step records the
//!   heaviest state it dropped, as a share of its merged weight, and its *lift*: the best
//!   observation factor of a candidate over the weight merged, from sources whose weights sum
//!   to 1 — how much more than the merged states a state missing from the sources may have
//!   kept of its weight, had it explained the observation best. Quiet steps lift by 1 (every
//!   candidate explains them alike), as does an observable every mode leaves open (all scaled
//!   by the same 1/m); an observation refuting most of the belief lifts by much. The heaviest
//!   dropped state, lifted step by step through the window, is compared with the lightest state
//!   kept, on a step whose observation left at most half the weight ([`SURPRISE`]) and with a
//!   margin of [`DISPLACE`] (equal fault rates make a dropped state tie a kept one, and ties
//!   must not re-run), and only when it weighs more than [`MIN_LOSS`] (the Mars lander keeps
//!   states of 1e-10 that any dropped state outweighs; re-running for those cost its nominal
//!   EDL 18 % of its run time, ten re-runs for changes in the last digits; two remain, at
//!   landing observations that lift by 1e7). The re-run starts no earlier than it must: at
//!   the latest belief recorded at or before the step that dropped it — that step's own
//!   start, which a step keeps when it drops more than a millionth of its weight (a quiet
//!   step of a plant whose faults are rare copies nothing), an earlier step's, or a
//!   segment's start (the window's two halves each keep the belief their first step started
//!   from). A re-run starting later could not find the state again. The propulsion model's
//!   PDE failing during a minute of heating is such a light drop, step by step, that the
//!   cold engine at the window's close lifts to 0.88: found again from the window's start.
//!   When the step before the one being updated dropped it and no belief was kept at that
//!   step's start (no checkpoint: the state weighed less than a millionth; not a segment's
//!   first step), the step being updated is re-run alone, from the belief it starts from, at
//!   8κ. The state itself is not found again (the belief it came from is not kept), but its
//!   like one step later is: the transitions that made it are open to the sources of the
//!   step being updated too, which are the previous step's survivors. (The step being
//!   updated never displaces a kept state with one it dropped itself: it keeps its heaviest.) Before that rule, the
//!   EDL's two landing re-runs went back to the window's start (31 and 29 steps at 8κ, the
//!   busy maximum 13.3 ms against 0.96 ms without them); the segment's start alone still
//!   took 15 and 13 steps (11 ms: the first 8κ steps over new OCSP shapes and the surprising
//!   step cost most of it). Re-running one step takes 1.4 ms, the busy maximum 2.1 ms, and
//!   the beliefs differ from the long re-runs' by at most 1.1e-9 (ŝ the same on every
//!   cycle). On random plants no cell of top-1 agreement or mean total-variation distance
//!   moved (both generators, κ = 3, 5, 10, 20, both re-run policies).
//!
//! # Which occasions re-run: the user's choice
//!
//! [`TimedMeOptions::rerun`] chooses between accuracy and cost. [`Rerun::Doubt`], the default,
//! re-runs on all three occasions. [`Rerun::Surprise`] leaves out doubt: on a plant observed
//! in part, where truncation keeps the leading states close, doubt fires on most steps, so a
//! step at κ costs what a step at 8κ costs. Every attempt to make doubt fire less by default
//! lost accuracy; the choice is the user's. Measured (300 random plants a generator, exact
//! belief within 80 states; `tests/estimation_accuracy.rs`), top-1 agreement with the exact
//! update and mean total-variation distance, doubt → surprise: broad plants κ = 10
//! 99.21 → 98.56 % (0.0169 → 0.0232), κ = 5 97.62 → 95.19 %; partially observed fault-to-fault
//! plants κ = 10 98.92 → 97.87 % (0.0247 → 0.0366), κ = 5 98.55 → 93.31 %; without the window
//! at all, 97.00 % and 96.78 % at κ = 10. Cost, Livingstone 2's 15-breaker log (1,600 steps,
//! whole process, callgrind): κ = 10 8.87 G instructions on doubt, 6.70 G on surprise, 1.10 G
//! without the window; κ = 5 4.22 G, 2.60 G, 0.45 G.
//!
//! The third changes answers on purpose, toward the exact update: states are still
//! kept by weight, the re-run's weights are the truer ones. Measured against the exact update
//! on random plants (`tests/estimation_accuracy.rs`, both generators, κ = 3, 5, 10, 20; figures in
//! BENCHMARKS.md), top-1 agreement and mean total-variation distance are nowhere worse than
//! without it. In the propulsion model an engine still cold when its heating window closes is
//! now explained as the exact update explains it (the PDE failed during the minute, 0.88; the
//! engine failed, 0.11) where κ = 10 had truncated the PDE's failure away.
//!
//! # How far from exact
//!
//! Every update reports how much truncation cost, so that a user sees how far the κ-best belief
//! may be from the exact update's (Figure 6-10, `exact.rs`, run from the same start):
//! - per step, [`UpdateStats::discarded`]: the fraction of the weight merged that truncation to
//!   the κ heaviest states dropped — exact, for the states the search found. What the search
//!   never enumerated (it stops early by design, `expand.rs`) is not in it: only a bound on it
//!   is known (the sources' prior mass their streams have not handed out, `expand.rs`'s
//!   `Unseen`; the observation factor is at most 1, so prior mass bounds posterior weight), and
//!   that bound is loose exactly where an observation refutes most of the prior, since it
//!   counts refuted targets too. It goes into the cumulative bound instead:
//! - cumulatively, [`Belief::distance_bound`]: an upper bound on the total-variation distance
//!   from the exact belief. Write the exact update's unnormalised posterior as ν + δ, where ν is
//!   the weight of TimedME's states along TimedME's own lineage and δ ≥ 0 everything else, and
//!   let r = |δ| / |ν|. One step maps ν to the states merged (mass M, of which K kept) and the
//!   ones never enumerated (at most U); it maps δ to at most |δ|, as transition probabilities
//!   sum to at most 1 and observation factors are at most 1. With |ν| = 1 (beliefs are
//!   normalised): r' ≤ (M − K + U + r) / K. The distance between ν / |ν| and
//!   (ν + δ) / |ν + δ| is at most |δ| / |ν + δ| = r / (1 + r). It holds whatever rule picks the
//!   kept states and whatever the history's re-runs do (a re-run carries r through its own
//!   steps from its window's start); it is lost (1) when a budget cut a search (targets were
//!   skipped unseen) or an observation forced a fallback after something was discarded (a
//!   discarded state might have explained it). When no initial state explains the first
//!   observation, the initial belief falls back to the prior's κ heaviest states, and starts
//!   from the bound of that truncation (the exact update keeps the whole prior).
//!
//! The bound only grows (K ≤ 1), and it is conservative: it assumes every discarded and every
//! unenumerated state survived every observation since, so an observation that refutes most of
//! the kept mass (K small) multiplies it — also when what was not enumerated was refuted too.
//! A user reads it as "TimedME may be this far from exact"; the per-step `discarded` says
//! where truncation bit. Tests check it against the exact update on random plants
//! (`tests/estimation_fidelity.rs`).

use std::sync::Arc;

use super::expand::{
    Expander, Expansion, Limits, NextMode, SourceChoices, choices_from, successor_from,
};
use super::history::{History, Input, Replay, Start, Step, Truncated, WIDEN};
use super::{
    Belief, EstimationError, EstimationEvent, Fallback, ModeEstimator, Update, UpdateStats,
    WeightedState, check_step,
};
use crate::logic::ValueId;
use crate::opsat::{Budget, SearchOptions, Theory};
use crate::plant::{Commands, Observation, Plant, SystemState};

/// The prior of an unexplained jump into an unconstrained fault mode, per component, in the
/// fallback. Only its smallness matters: explanations with fewer jumps come first.
const JUMP: f64 = 1e-9;

/// The default history window, in steps (see [`TimedMeOptions::history`]).
pub const DEFAULT_HISTORY: usize = 16;

/// The longest history window a user may ask for, in steps: a step may re-run up to twice the
/// window at 8κ, and the window keeps every step's inputs, so a mistyped 10⁹ is refused where
/// it is read (scenario files, the command line) rather than run.
pub const MAX_HISTORY: usize = 10_000;

/// ŝ is in doubt when the two heaviest plant states' weights differ by less than this many
/// times the weight truncated away within the history window (`history.rs`: at 1, the lost
/// weight alone could have reversed them; more allows for what observations since made of it;
/// docs/design/estimation.md has 1, 4 and 16 measured)…
const AMBIGUITY: f64 = 16.0;

/// …and that weight is more than this; a dropped state displaces a kept one only if it weighs
/// more than this too (a lighter one cannot matter to the belief's reader, and a plant whose
/// faults are rare keeps states of 1e-10 that any dropped one may outweigh).
const MIN_LOSS: f64 = 1e-3;

/// An observation surprises when it lifts a missing state by at least this much: it left at
/// most half the weight the best explanation found would keep (module documentation, "When
/// the window is re-run")…
const SURPRISE: f64 = 2.0;

/// …and then a dropped state displaces a kept one when it may outweigh it this many times.
const DISPLACE: f64 = 2.0;

/// Which occasions re-run the history window (module documentation, "When the window is
/// re-run"): the user's choice between cost and accuracy. Both re-run when an observation
/// contradicts every tracked state and when a surprising observation may make a dropped state
/// outweigh a kept one; they differ on doubt.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Deserialize)]
pub enum Rerun {
    /// Also when ŝ is in doubt: the two heaviest plant states differ by less than a few times
    /// the weight truncated within the window. The default, and the more accurate: on a plant
    /// observed in part, where truncation keeps the leading states close, it fires on most
    /// steps, so a step costs about what a step at 8κ costs. Measured at κ = 10: top-1
    /// agreement with the exact update 99.21 % on broad random plants and 98.92 % on partially
    /// observed fault-to-fault ones (97.00 % and 96.78 % without the window); Livingstone 2's
    /// 15-breaker log 8.87 G instructions (module documentation, "Which occasions re-run").
    #[default]
    Doubt,
    /// Only on contradiction and surprise: doubt alone does not re-run, so a step costs κ's
    /// price unless an observation surprised. Measured at κ = 10: 98.56 % and 97.87 % top-1
    /// agreement on the same plants, the breaker log 6.70 G instructions (1.10 G without the
    /// window).
    Surprise,
}

impl Rerun {
    /// Every policy.
    pub const ALL: [Rerun; 2] = [Rerun::Doubt, Rerun::Surprise];

    /// Its name on the command line (`doubt`, `surprise`).
    pub fn name(self) -> &'static str {
        match self {
            Rerun::Doubt => "doubt",
            Rerun::Surprise => "surprise",
        }
    }

    /// The policy named `name` ([`Rerun::name`]).
    pub fn named(name: &str) -> Option<Rerun> {
        Self::ALL.into_iter().find(|r| r.name() == name)
    }
}

/// How TimedME searches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TimedMeOptions {
    /// κ: how many system states to track.
    pub kappa: usize,
    /// How many candidate trajectories to examine per tracked state at most (the enumeration
    /// usually stops well before: see `expand.rs`). More makes the observation factor's
    /// reordering more faithful at some cost.
    pub candidates_per_state: usize,
    /// OPSAT's budget per source state's enumeration; on exhaustion the belief holds the best
    /// found so far and the update reports [`EstimationEvent::SearchCut`].
    pub budget: Budget,
    /// Replay a quiet step: when the sources' OCSPs have the same shapes and the observation is
    /// the same as in the last update, serve the last update's solutions re-costed instead of
    /// rebuilding the streams from the solution cache — only where that is certified to give
    /// the same belief bit for bit, else the step is expanded in full (`replay.rs`). On by
    /// default; off, every step is expanded in full (the tests compare the two).
    pub replay: bool,
    /// How many recent steps TimedME keeps to estimate again, tracking 8κ states, when an
    /// observation contradicts every tracked state or truncation could have decided ŝ
    /// (`history.rs`): the window holds this many to twice as many steps, so a step costs at
    /// worst 2 · `history` + 1 steps at 8κ; 0 turns it off (and bounds a step by one at κ).
    /// [`DEFAULT_HISTORY`] by default.
    pub history: usize,
    /// Which occasions re-run the window ([`Rerun`]); [`Rerun::Doubt`] by default.
    pub rerun: Rerun,
    /// Share the conflicts OPSAT learns between the sources' searches of a step, and between
    /// steps with the same observation (`opsat::ConflictStore`): each source's OCSP assumes the
    /// same observation, so a conflict one source paid a SAT call for prunes the others'
    /// searches for free. On by default; off, each search learns its own (the tests compare the
    /// two: the beliefs are the same bit for bit).
    pub share_conflicts: bool,
}

impl TimedMeOptions {
    /// κ states, 4 candidates per state (2, 4 and 8 agree equally with the exact update on
    /// random plants; docs/design/estimation.md), no budget.
    pub fn kappa(kappa: usize) -> Self {
        TimedMeOptions {
            kappa: kappa.max(1),
            candidates_per_state: 4,
            budget: Budget::default(),
            replay: true,
            history: DEFAULT_HISTORY,
            rerun: Rerun::Doubt,
            share_conflicts: true,
        }
    }

    fn limits(&self) -> Limits {
        Limits {
            kappa: self.kappa,
            max_candidates: self
                .kappa
                .saturating_mul(self.candidates_per_state)
                .saturating_add(16),
            search: SearchOptions {
                budget: self.budget,
                ..SearchOptions::default()
            },
            share_conflicts: self.share_conflicts,
        }
    }
}

/// TimedME with its caches (valid for one plant and its theory).
pub struct TimedMe {
    options: TimedMeOptions,
    expander: Expander,
    history: History,
}

/// A clone starts with empty caches: every cache of the `Expander` is certified to hold a pure
/// function of its key (see its documentation), so a fresh one finds the same states with the
/// same probabilities as a warm one — and an explored state's copy need not carry megabytes of
/// memo it may never read. The history is copied: it decides answers. Not bit for bit in every
/// step, though: where a warm estimator serves a solution's cost from the solution cache (a sum
/// over the components in order) a cold one serves the live search's (a sum over independent
/// sub-problems), which can differ in the last bit (a 4e-8 probability in its 16th digit on the
/// EDL's 600 s grid); quiet steps agree bit for bit (`tests/estimation_exactness.rs`).
impl Clone for TimedMe {
    fn clone(&self) -> Self {
        TimedMe {
            history: self.history.clone(),
            ..TimedMe::new(self.options)
        }
    }
}

impl TimedMe {
    /// A TimedME tracking `options.kappa` states.
    pub fn new(options: TimedMeOptions) -> Self {
        TimedMe {
            options,
            expander: Expander::default(),
            history: History::default(),
        }
    }

    /// Its options.
    pub fn options(&self) -> TimedMeOptions {
        self.options
    }

    /// Sets OPSAT's budget for the updates that follow (the executive gives each cycle's
    /// searches their deadline: [`Budget::until`]).
    pub fn set_budget(&mut self, budget: Budget) {
        self.options.budget = budget;
    }
}

impl ModeEstimator for TimedMe {
    fn initial(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        time: f64,
        observation: &Observation,
    ) -> Result<Update, EstimationError> {
        let mut update = initial_belief(
            &mut self.expander,
            plant,
            theory,
            time,
            observation,
            self.options.limits(),
        )?;
        if self.options.history > 0 {
            self.history.restart(&mut update.belief);
        }
        Ok(update)
    }

    fn update(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        belief: &Belief,
        commands: &Commands,
        observation: &Observation,
        time: f64,
    ) -> Result<Update, EstimationError> {
        check_step(plant, belief, commands, observation, time)?;
        // The step as the acknowledgements say it happened (`plant::acknowledgement`); the
        // history keeps it so, for a re-run to see the same step.
        let commands = &*commands.acknowledged(plant, observation);
        let sat_before = theory.stats().sat_calls;
        let limits = self.options.limits();
        let step = Step {
            commands,
            observation,
            time,
        };
        let (mut sources, expansion) = expand_from(
            &mut self.expander,
            plant,
            theory,
            belief,
            &step,
            limits,
            self.options.replay,
        )?;
        let truncated = truncated_by(&expansion);
        let rerun = if self.options.history > 0
            && !expansion.states.is_empty()
            && self.history.continues_from(belief)
        {
            let window = 1.0 - (1.0 - self.history.lost()) * (1.0 - truncated.lost);
            if self.options.rerun == Rerun::Doubt && in_doubt(&expansion, window) {
                Some(Start::Window)
            } else {
                displaced(&expansion, truncated, &self.history)
            }
        } else {
            None
        };
        let mut outcome = Outcome::new(expansion, belief.outside());
        let mut wide = None;
        if let Some(start) = rerun
            && let Some(rerun) = self.reestimate(plant, theory, belief, &step, start)?
        {
            wide = Some(outcome.rerun(rerun));
        }
        let mut jumped = false;
        if outcome.is_empty() {
            if let Some(rerun) = self.reestimate(plant, theory, belief, &step, Start::Window)? {
                let steps = rerun.steps;
                wide = Some(outcome.rerun(rerun));
                outcome
                    .events
                    .push(EstimationEvent::InconsistentObservation {
                        fallback: Fallback::Reestimated { steps },
                    });
            } else {
                with_fault_jumps(plant, &mut sources);
                let expansion = self.expander.expand(
                    plant,
                    theory,
                    &sources,
                    observation,
                    limits,
                    successor_from(plant, belief.states(), time),
                )?;
                outcome.fall_back(expansion, belief.states(), fallen_from(belief));
                jumped = true;
            }
        }
        let truncated = outcome.truncated;
        let mut update = outcome.into_update(plant, time, theory.stats().sat_calls - sat_before);
        if jumped && self.options.history > 0 {
            self.history.restart(&mut update.belief);
        } else {
            self.history.record(
                self.options.history,
                belief,
                &step,
                truncated,
                &mut update.belief,
            );
            if let Some(wide) = wide {
                self.history.keep_wide(wide, &update.belief);
            }
        }
        Ok(update)
    }
}

impl TimedMe {
    /// The history's re-run (see `history.rs`): from the belief `start` names
    /// ([`History::replay_from`]) through the window's steps from there and then `step`,
    /// tracking [`WIDEN`] × κ states — or only `step`, from the wide belief the last re-run
    /// ended with when it returned `belief`, or from `belief` itself when `step` dropped the
    /// state the re-run is for. The κ heaviest states it ends with, how many steps it ran and
    /// the wide belief it ended with; `None` when the window is empty, is not this belief's,
    /// or cannot explain a step.
    fn reestimate(
        &mut self,
        plant: &Plant,
        theory: &mut Theory,
        belief: &Belief,
        step: &Step,
        start: Start,
    ) -> Result<Option<Reestimation>, EstimationError> {
        if !self.history.continues_from(belief) {
            return Ok(None);
        }
        let (mut current, steps): (Belief, Vec<Step>) = match self.history.wide_behind(belief) {
            Some(wide) => (wide.clone(), Vec::new()),
            None => match self.history.replay_from(start) {
                Some(Replay::Recorded(start, steps)) => {
                    (start.clone(), steps.into_iter().map(Input::step).collect())
                }
                Some(Replay::Current) => (belief.clone(), Vec::new()),
                None => return Ok(None),
            },
        };
        let wide = TimedMeOptions {
            kappa: self.options.kappa.saturating_mul(WIDEN),
            ..self.options
        }
        .limits();
        let mut last = None;
        for input in steps.iter().chain(std::iter::once(step)) {
            let before = current.outside();
            let (_, expansion) = expand_from(
                &mut self.expander,
                plant,
                theory,
                &current,
                input,
                wide,
                false,
            )?;
            // Only the last step's κ heaviest are the answer.
            let kept = std::ptr::eq(input, step).then(|| {
                let kappa = self.options.kappa.min(expansion.states.len());
                let dropped =
                    (expansion.states.get(kappa)).map_or(expansion.dropped, |w| w.probability);
                (expansion.states[..kappa].to_vec(), dropped)
            });
            let outside = expansion.outside(&expansion.states, before);
            let Some(mut next) = Belief::made_for(plant, input.time, expansion.states) else {
                return Ok(None);
            };
            next.set_outside(outside);
            current = next;
            last = kept.map(|(states, dropped)| {
                let expansion = Expansion {
                    states,
                    dropped,
                    ..expansion
                };
                (expansion, before)
            });
        }
        Ok(last.map(|(expansion, before)| Reestimation {
            expansion,
            before,
            steps: steps.len() + 1,
            wide: current,
        }))
    }
}

/// What a re-run of the history gave.
struct Reestimation {
    /// The κ heaviest states it ended with.
    expansion: Expansion,
    /// The bound of the wide belief its last step started from ([`Belief::outside`]).
    before: f64,
    /// How many steps it ran.
    steps: usize,
    /// Every state it ended with (at most 8κ), normalised.
    wide: Belief,
}

/// What `expansion`'s truncation dropped, for the history.
fn truncated_by(expansion: &Expansion) -> Truncated {
    let lost = expansion.lost();
    let mass = expansion.merged * expansion.scale;
    if expansion.merged <= 0.0 || mass <= 0.0 || !mass.is_finite() {
        return Truncated {
            lost,
            ..Truncated::NONE
        };
    }
    Truncated {
        lost,
        dropped: expansion.dropped / expansion.merged,
        lift: (expansion.best_factor / mass).max(1.0),
    }
}

/// Whether ŝ is in doubt because of truncation: the two heaviest plant states differ by less
/// than [`AMBIGUITY`] times `window`, the weight truncated within the window, this step
/// included, and that weight is more than [`MIN_LOSS`].
fn in_doubt(expansion: &Expansion, window: f64) -> bool {
    let kept: f64 = expansion.states.iter().map(|w| w.probability).sum();
    window > MIN_LOSS && margin(&expansion.states) < AMBIGUITY * window * kept
}

/// The step a re-run starts at, when this step's observation surprised ([`SURPRISE`]) and the
/// heaviest state dropped within the window (`history`'s and this step's, carried to this step)
/// weighs more than [`MIN_LOSS`] and may now outweigh the lightest state kept [`DISPLACE`]
/// times (module documentation, "When the window is re-run"); the window is folded only on a
/// surprise, off the quiet steps' path.
fn displaced(expansion: &Expansion, step: Truncated, history: &History) -> Option<Start> {
    if step.lift < SURPRISE {
        return None;
    }
    let lightest = expansion.states.last()?.probability / expansion.merged;
    let dropped = history.heaviest_dropped().then(step);
    (dropped.weight > MIN_LOSS && dropped.weight > DISPLACE * lightest)
        .then_some(Start::Dropped(dropped.origin))
}

/// The difference between the two heaviest plant states' weights (`states` not empty).
fn margin(states: &[WeightedState]) -> f64 {
    let mut plants: Vec<(&[ValueId], f64)> = Vec::new();
    for w in states {
        match plants.iter_mut().find(|(m, _)| *m == &w.state.modes[..]) {
            Some((_, p)) => *p += w.probability,
            None => plants.push((&w.state.modes, w.probability)),
        }
    }
    plants.sort_by(|a, b| b.1.total_cmp(&a.1));
    let second = plants.get(1).map_or(0.0, |p| p.1);
    plants.first().map_or(0.0, |p| p.1 - second)
}

/// One TimedME step from `belief` (Figure 6-11 steps 1–6): the sources' next-mode choices and
/// the expansion, replayed from the last step where `replay` allows and that is certified.
fn expand_from(
    expander: &mut Expander,
    plant: &Plant,
    theory: &mut Theory,
    belief: &Belief,
    step: &Step,
    limits: Limits,
    replay: bool,
) -> Result<(Vec<SourceChoices>, Expansion), EstimationError> {
    let mut sources = Vec::with_capacity(belief.states().len());
    for weighted in belief.states() {
        let choices = expander.choices(
            plant,
            theory,
            &weighted.state,
            step.commands,
            belief.time(),
            step.time,
        )?;
        sources.push(SourceChoices {
            probability: weighted.probability,
            choices,
        });
    }
    let expansion = expander.step(
        plant,
        theory,
        (&sources, belief.states()),
        (step.observation, step.time),
        limits,
        replay,
    )?;
    Ok((sources, expansion))
}

/// The initial belief (shared with the exact update, which passes unbounded limits): the
/// initial distribution as one pseudo-source whose "next modes" are the initial modes, every
/// clock starting at `time`, conditioned on `observation`; falling back like an update.
pub(crate) fn initial_belief(
    expander: &mut Expander,
    plant: &Plant,
    theory: &mut Theory,
    time: f64,
    observation: &Observation,
    limits: Limits,
) -> Result<Update, EstimationError> {
    if !time.is_finite() {
        return Err(EstimationError::TimeWentBackwards {
            from: time,
            to: time,
        });
    }
    let sat_before = theory.stats().sat_calls;
    let initial = plant
        .components()
        .iter()
        .map(|c| {
            (0..c.modes().len())
                .map(|m| (ValueId(m as u32), c.initial()[m]))
                .filter(|(_, p)| *p > 0.0)
                .collect()
        })
        .collect();
    let mut sources = vec![SourceChoices {
        probability: 1.0,
        choices: Arc::new(choices_from(initial)),
    }];
    let entered =
        |_: usize, modes: &[ValueId]| SystemState::entered_at(plant, modes.to_vec(), time);
    let expansion = expander.expand(plant, theory, &sources, observation, limits, entered)?;
    let mut outcome = Outcome::new(expansion, 0.0);
    if outcome.is_empty() {
        with_fault_jumps(plant, &mut sources);
        let expansion = expander.expand(plant, theory, &sources, observation, limits, entered)?;
        // Nothing at all: the prior, unconditioned.
        let prior = expander.expand(
            plant,
            theory,
            &sources[..],
            &Observation::none(),
            limits,
            entered,
        )?;
        // The exact update, run from the same start, falls back the same way: an empty
        // expansion means no initial state at all is consistent with the observation. It
        // keeps the whole prior, TimedME the κ heaviest of its states: what the prior's
        // truncation left out is the distance between the two.
        let truncated = prior.outside(&prior.states, 0.0);
        outcome.fall_back_to(expansion, &prior.states, 0.0, truncated);
    }
    Ok(outcome.into_update(plant, time, theory.stats().sat_calls - sat_before))
}

/// Adds each component's unconstrained fault modes to its choices, with the small prior
/// [`JUMP`] (DESIGN.md §8's first fallback).
pub(crate) fn with_fault_jumps(plant: &Plant, sources: &mut [SourceChoices]) {
    for source in sources {
        let choices = Arc::make_mut(&mut source.choices);
        for (component, next) in plant.components().iter().zip(choices) {
            let jumps = (0..component.modes().len())
                .map(|m| ValueId(m as u32))
                .filter(|&m| {
                    component.modes()[m.index()].is_unconstrained_fault()
                        && !next.iter().any(|n| n.mode == m)
                })
                .map(|m| NextMode::new(m, JUMP));
            *next = next.iter().copied().chain(jumps).collect();
        }
    }
}

/// The states an update settles on, and what happened on the way.
pub(crate) struct Outcome {
    states: Vec<WeightedState>,
    events: Vec<EstimationEvent>,
    candidates: u64,
    replayed: bool,
    rerun: u32,
    /// [`UpdateStats::discarded`].
    discarded: f64,
    /// The new belief's bound ([`Belief::outside`]).
    outside: f64,
    /// What the truncation that gave the states dropped (for the history).
    truncated: Truncated,
}

/// The bound a fallback from `belief` starts from: the exact update falls back the same way
/// only if nothing was ever discarded; otherwise a discarded state might have explained the
/// observation, and nothing is known.
pub(crate) fn fallen_from(belief: &Belief) -> f64 {
    if belief.outside() == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

impl Outcome {
    /// The outcome of `expansion`, from a belief whose bound was `before` ([`Belief::outside`]).
    pub(crate) fn new(expansion: Expansion, before: f64) -> Outcome {
        let mut outcome = Outcome::from_states(Vec::new(), 0);
        outcome.absorb(expansion, before);
        outcome
    }

    /// Weighted states found without OPSAT (the exact update's enumeration).
    pub(crate) fn from_states(states: Vec<WeightedState>, candidates: u64) -> Outcome {
        Outcome {
            states,
            events: Vec::new(),
            candidates,
            replayed: false,
            rerun: 0,
            discarded: 0.0,
            outside: 0.0,
            truncated: Truncated::NONE,
        }
    }

    fn absorb(&mut self, expansion: Expansion, before: f64) {
        self.truncated = truncated_by(&expansion);
        self.discarded = self.truncated.lost;
        self.outside = expansion.outside(&expansion.states, before);
        self.candidates += expansion.candidates;
        self.replayed = expansion.replayed;
        if let Some(cut) = expansion.cut {
            self.events.push(EstimationEvent::SearchCut(cut));
        }
        self.states = expansion.states;
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.states.is_empty()
    }

    /// The history's re-run gave the belief instead (`history.rs`); returns the wide belief it
    /// ended with.
    fn rerun(&mut self, rerun: Reestimation) -> Belief {
        self.absorb(rerun.expansion, rerun.before);
        self.rerun = rerun.steps as u32;
        rerun.wide
    }

    /// DESIGN.md §8's fallbacks: the fault-jump expansion, else `previous` as it was; `before`
    /// is the bound the fallback starts from ([`fallen_from`]), and the bound of `previous`
    /// when it is kept.
    pub(crate) fn fall_back(&mut self, jumps: Expansion, previous: &[WeightedState], before: f64) {
        self.fall_back_to(jumps, previous, before, before);
    }

    /// [`Outcome::fall_back`], keeping `previous` with the bound `kept` ([`Belief::outside`])
    /// when nothing explains the observation.
    fn fall_back_to(
        &mut self,
        jumps: Expansion,
        previous: &[WeightedState],
        before: f64,
        kept: f64,
    ) {
        self.absorb(jumps, before);
        let fallback = if self.states.is_empty() {
            self.states = previous.to_vec();
            self.discarded = 0.0;
            self.truncated = Truncated::NONE;
            self.outside = kept;
            Fallback::PreviousBelief
        } else {
            Fallback::UnconstrainedFaults
        };
        self.events
            .push(EstimationEvent::InconsistentObservation { fallback });
    }

    pub(crate) fn into_update(self, plant: &Plant, time: f64, sat_calls: u64) -> Update {
        let states = self.states.len() as u64;
        let mut belief = Belief::made_for(plant, time, self.states).unwrap_or_else(|| Belief {
            time,
            states: Vec::new(),
            mode_vars: plant.components().iter().map(|c| c.mode_var()).collect(),
            issued: None,
            outside: f64::INFINITY,
        });
        belief.set_outside(self.outside);
        Update {
            belief,
            events: self.events,
            stats: UpdateStats {
                candidates: self.candidates,
                sat_calls,
                states,
                replayed: self.replayed,
                rerun: self.rerun,
                discarded: self.discarded,
            },
        }
    }
}
