//! Executing a THCA: the control sequencer's `Step_THCA` (thesis Figure 5-3, §5.3).
//!
//! DESIGN.md §3 cuts each cycle in two around mode reconfiguration and mode estimation, so the
//! ten steps of Figure 5-3 are split the same way:
//! - [`Sequencer::begin_cycle`] at time t(i) with ŝ(i): steps 1–4 (update clocks, check the
//!   maintenance of marked composites, assert clock initialisations, form the configuration goal);
//! - steps 5 and 6 are the caller's: reconfiguration acts on the goal, estimation returns ŝ(i+1);
//! - [`Sequencer::end_cycle`] with ŝ(i+1): steps 7–10 (await incomplete goals, find enabled
//!   transitions, take them, keep the clock references).
//!
//! [`Sequencer::step`] runs both halves for callers (and tests) that already have ŝ(i+1).
//! Ids ascend from each composite to its contents, so one ascending pass propagates preemption
//! down the hierarchy and one descending pass propagates "still busy" up it.
//!
//! # Passes over the marked locations only
//!
//! The passes visit the marked locations m(i), kept as an ascending list beside the marking
//! and rebuilt only when the marking changes (a quiet cycle keeps it). This is exact because
//! the marking is closed under composites — m_F marks from the top down, step 2 unmarks whole
//! contents, step 9 re-marks every composite of a marked location — so a marked location's
//! composite is in the list and visited before it (ascending) or after it (descending), and an
//! unmarked location does nothing in any step: it has no maintenance to check, no goal, no
//! transition to take, and (its contents being unmarked too) never makes its composite busy.
//! Step 9's re-marking climbs from the targets m_F marked and, over m(i), from the awaiting
//! primitives: the same closure as a descending pass over every location.
//! `reference.rs` tests the whole against Figure 5-3 run plainly.
//!
//! Measured with the conditions' answers kept across cycles (`evaluate.rs`), on the nominal
//! Mars EDL's quiet cruise cycle (52 locations; `cg.sh`): the two halves went from 8.1 k
//! instructions to about 2.4 k, the whole cycle from 51,746 to 45,993.

use std::hash::{Hash, Hasher};

use rustc_hash::FxHashMap;

use super::evaluate::{Evaluator, Memo};
use super::oracle::Entailment;
use super::thca::{Condition, Construct, FormulaId, Location, LocationId, LocationKind, Thca};
use crate::diagnostic::Span;
use crate::logic::{ClockId, Formula};

/// Something the sequencer did or saw, with the source span of the location concerned.
#[derive(Debug, Clone, PartialEq)]
pub enum Event {
    /// Step 3: a clock was started (it reads 0 at `time` and is active from the next cycle).
    ClockStarted {
        /// The clock.
        clock: ClockId,
        /// Its initialisation time.
        time: f64,
        /// The location that initialised it.
        location: LocationId,
        /// Where the initialisation is written.
        span: Span,
    },
    /// Step 2: a marked composite's maintenance constraint is violated; everything inside it was
    /// unmarked (reactive preemption) and its exits are taken this cycle.
    Preempted {
        /// The composite.
        location: LocationId,
        /// Its construct's text.
        span: Span,
        /// Which construct it is (`do … watching`, `maintaining`).
        construct: Construct,
        /// The maintenance constraint ŝ(i) ∧ ω(i) violated: `⊭ c` of `do … watching c` (c
        /// became entailed) or `⊨ c` of `… maintaining c` (c is not entailed).
        condition: Condition,
    },
    /// A marked primitive location's own maintenance constraint is violated: it asserts no goal
    /// and its transitions are enabled (Figure 5-3, steps 4, 7, 8a).
    MaintenanceViolated {
        /// The primitive location.
        location: LocationId,
        /// Its construct's text.
        span: Span,
        /// Which construct it is.
        construct: Construct,
        /// The maintenance constraint violated.
        condition: Condition,
    },
    /// Step 4: two goals asserted in the same cycle cannot hold together; neither is part of
    /// the configuration goal.
    GoalConflict {
        /// The goal asserted by the location with the smaller id.
        first: GoalSource,
        /// The goal that contradicts it.
        second: GoalSource,
    },
    /// Step 7: a marked primitive location's goal is entailed by the new estimate.
    GoalAchieved {
        /// The location.
        location: LocationId,
        /// Where its goal is written.
        span: Span,
    },
    /// No location is marked any more: the program has finished.
    Completed,
}

/// A goal and the location asserting it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GoalSource {
    /// The asserting location.
    pub location: LocationId,
    /// Where the goal is written.
    pub span: Span,
}

/// One conjunct of the configuration goal.
#[derive(Debug, Clone, PartialEq)]
pub struct GoalConjunct {
    /// The location asserting it.
    pub location: LocationId,
    /// Where it is written.
    pub span: Span,
    /// The goal constraint.
    pub formula: Formula,
}

/// g(i): the conjunction of the goals of the marked primitive locations whose maintenance holds,
/// without goals that contradict each other.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigurationGoal {
    /// The conjunction (**True** when nothing is asserted).
    pub formula: Formula,
    /// Its conjuncts, by location id.
    pub conjuncts: Vec<GoalConjunct>,
}

/// What the first half of a cycle produced.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleStart {
    /// The configuration goal g(i) for mode reconfiguration.
    pub goal: ConfigurationGoal,
    /// ω(i): the value of every active clock.
    pub clocks: Vec<(ClockId, f64)>,
    /// What happened in steps 2–4.
    pub events: Vec<Event>,
}

/// What the second half of a cycle produced.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleEnd {
    /// What happened in steps 7–9.
    pub events: Vec<Event>,
    /// True when no location is marked any more.
    pub completed: bool,
}

/// Both halves of one cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct Step {
    /// Steps 1–4.
    pub start: CycleStart,
    /// Steps 7–10.
    pub end: CycleEnd,
}

/// Calls in the wrong order or with an impossible time.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SequencerError {
    /// `begin_cycle` was called twice without `end_cycle`.
    #[error("a cycle is already open: call end_cycle first")]
    CycleOpen,
    /// `end_cycle` was called without `begin_cycle`.
    #[error("no cycle is open: call begin_cycle first")]
    NoCycleOpen,
    /// The time is NaN or infinite.
    #[error("time {0} is not a finite number of seconds")]
    TimeNotFinite(f64),
    /// The time is earlier than the previous cycle's.
    #[error("time went back from {previous} s to {now} s")]
    TimeWentBack {
        /// The previous cycle's time.
        previous: f64,
        /// The time given.
        now: f64,
    },
}

/// The control sequencer: a THCA, its marking m(i) and its clock references t^init(i).
#[derive(Debug, Clone)]
pub struct Sequencer {
    thca: Thca,
    marked: Vec<bool>,
    /// The marked locations, ascending: the passes over the locations visit these only.
    marked_ids: Vec<LocationId>,
    clock_started: Vec<Option<f64>>,
    last_time: Option<f64>,
    open: Option<OpenCycle>,
    /// Whether a set of goals (sorted formula ids) is consistent with the plant model; the model
    /// does not change, so the answer is kept (Fx-hashed: looked up every cycle with two goals
    /// or more, never iterated).
    consistency: FxHashMap<Vec<FormulaId>, bool>,
    completed: bool,
    /// The half cycles' working storage, kept from one cycle to the next.
    scratch: Scratch,
    /// Answers kept across cycles (`evaluate.rs`).
    memo: Memo,
}

/// Working storage of the half cycles (a quiet cycle allocates none of it). Holds no
/// state: every buffer is overwritten before it is read.
#[derive(Debug, Clone, Default)]
struct Scratch {
    /// The evaluator's answers per formula.
    entailed: Vec<Option<bool>>,
    /// Step 2: locations inside a violated composite.
    inside_violated: Vec<bool>,
    /// Steps 7–8: composites with something inside still marked or moving.
    busy: Vec<bool>,
    /// Step 8: the enabled transitions.
    enabled: Vec<(LocationId, usize)>,
    /// The marking m(i) once m(i+1) replaced it, and an open cycle's vectors once it closed.
    marking: Vec<bool>,
    clocks: Vec<Option<f64>>,
    violated: Vec<bool>,
    /// Step 9: m_F's locations still to mark.
    pending: Vec<LocationId>,
}

/// Hashes optional times by their bits.
fn hash_times<H: Hasher>(times: &[Option<f64>], state: &mut H) {
    for time in times {
        time.map(f64::to_bits).hash(state);
    }
}

/// What the first half of a cycle leaves for the second.
#[derive(Debug, Clone)]
struct OpenCycle {
    /// ω(i), by clock id.
    clocks: Vec<Option<f64>>,
    /// Locations whose maintenance constraint ŝ(i) ∧ ω(i) violates.
    violated: Vec<bool>,
    /// The initialisations step 3 adds to t^init(i+1).
    started: Vec<(ClockId, f64)>,
}

impl Sequencer {
    /// A sequencer with the initial marking m(0) = m_F(A): the top automaton's start locations
    /// and, recursively, the start locations of the composites among them.
    pub fn new(thca: Thca) -> Self {
        let mut marked = vec![false; thca.locations().len()];
        for &start in thca.starts() {
            mark_full(&thca, start, &mut marked, &mut Vec::new());
        }
        let marked_ids = marked_ids(&thca, &marked);
        let clock_count = thca.table().clocks().len();
        Sequencer {
            clock_started: vec![None; clock_count],
            memo: Memo::new(&thca),
            thca,
            completed: marked_ids.is_empty(),
            marked,
            marked_ids,
            last_time: None,
            open: None,
            consistency: FxHashMap::default(),
            scratch: Scratch::default(),
        }
    }

    /// The automaton being executed.
    pub fn thca(&self) -> &Thca {
        &self.thca
    }

    /// The marked locations, by id.
    pub fn marking(&self) -> impl Iterator<Item = &Location> {
        self.marked_ids.iter().map(|&id| self.thca.location(id))
    }

    /// Is this location marked?
    pub fn is_marked(&self, location: LocationId) -> bool {
        self.marked.get(location.index()).copied().unwrap_or(false)
    }

    /// True once no location is marked: execution has completed (the empty marking is a fixed
    /// point).
    pub fn is_complete(&self) -> bool {
        self.completed
    }

    /// When a clock was initialised, if it has been.
    pub fn clock_start(&self, clock: ClockId) -> Option<f64> {
        self.clock_started.get(clock.index()).copied().flatten()
    }

    /// Feeds the execution state — marking m(i), clock references t^init(i), the open half
    /// cycle, completion — to `state`, for explicit-state exploration's deduplication. Times
    /// are hashed exactly: they are products of the cycle period, equal on equal paths.
    pub fn fingerprint<H: Hasher>(&self, state: &mut H) {
        self.marked.hash(state);
        hash_times(&self.clock_started, state);
        self.completed.hash(state);
        self.last_time.map(f64::to_bits).hash(state);
        if let Some(open) = &self.open {
            hash_times(&open.clocks, state);
            open.violated.hash(state);
            for (clock, time) in &open.started {
                clock.hash(state);
                time.to_bits().hash(state);
            }
        }
    }

    /// Steps 1–4 of Figure 5-3 at time t(i) with the current estimate ŝ(i): returns the
    /// configuration goal g(i) to achieve before [`Sequencer::end_cycle`].
    pub fn begin_cycle<E: Entailment>(
        &mut self,
        time: f64,
        current: &E::Estimate,
        oracle: &mut E,
    ) -> Result<CycleStart, SequencerError> {
        if self.open.is_some() {
            return Err(SequencerError::CycleOpen);
        }
        self.check_time(time)?;
        // Step 1: update active clocks, x = t_abs − t_init.
        let mut clocks = std::mem::take(&mut self.scratch.clocks);
        clocks.clear();
        clocks.extend(
            self.clock_started
                .iter()
                .map(|start| start.map(|t0| time - t0)),
        );
        let mut events = Vec::new();
        let mut evaluator = Evaluator::new(
            &self.thca,
            &clocks,
            current,
            oracle,
            (&mut self.scratch.entailed, &mut self.memo),
        );
        let mut violated = std::mem::take(&mut self.scratch.violated);
        let unmarked = check_maintenance(
            (&self.thca, &self.marked_ids),
            &mut self.marked,
            &mut evaluator,
            &mut events,
            (&mut violated, &mut self.scratch.inside_violated),
        );
        if unmarked {
            self.marked_ids = marked_ids(&self.thca, &self.marked);
        }
        let started = self.assert_clock_inits(time, &mut events);
        let conjuncts = self.goal_conjuncts(&violated);
        let goal = self.configuration_goal(conjuncts, oracle, &mut events);
        let active = clocks
            .iter()
            .enumerate()
            .filter_map(|(i, value)| value.map(|v| (ClockId(i as u32), v)))
            .collect();
        self.open = Some(OpenCycle {
            clocks,
            violated,
            started,
        });
        Ok(CycleStart {
            goal,
            clocks: active,
            events,
        })
    }

    /// Steps 7–10 of Figure 5-3 with the new estimate ŝ(i+1): advances the marking to m(i+1).
    pub fn end_cycle<E: Entailment>(
        &mut self,
        next: &E::Estimate,
        oracle: &mut E,
    ) -> Result<CycleEnd, SequencerError> {
        let open = self.open.take().ok_or(SequencerError::NoCycleOpen)?;
        let mut events = Vec::new();
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut memo = std::mem::take(&mut self.memo);
        let mut evaluator = Evaluator::new(
            &self.thca,
            &open.clocks,
            next,
            oracle,
            (&mut scratch.entailed, &mut memo),
        );
        let mut marking = std::mem::take(&mut scratch.marking);
        self.enabled_transitions(
            &mut evaluator,
            &open,
            &mut events,
            (&mut marking, &mut scratch.busy, &mut scratch.enabled),
        );
        // Step 9: mark (with m_F) the targets of every enabled transition, then re-mark the
        // composites that contain marked locations. m(i+1) then holds the awaiting
        // primitives, all marked in m(i), and what m_F marked: the first have their
        // composites re-marked by a descending pass over m(i), which holds every composite of
        // theirs (the marking is closed under composites); m_F's marks are the targets and
        // what lies inside them, so the targets' chains cover theirs. (The chains are climbed
        // after every m_F: m_F does not enter a composite already marked.)
        let targets = |&(location, transition): &(LocationId, usize)| {
            &self.thca.location(location).transitions[transition].targets
        };
        for &target in scratch.enabled.iter().flat_map(targets) {
            mark_full(&self.thca, target, &mut marking, &mut scratch.pending);
        }
        for &target in scratch.enabled.iter().flat_map(targets) {
            mark_composites(&self.thca, target, &mut marking);
        }
        for &id in self.marked_ids.iter().rev() {
            if let (true, Some(parent)) = (marking[id.index()], self.thca.location(id).parent) {
                marking[parent.index()] = true;
            }
        }
        // Step 10: t^init(i+1) keeps every reference of t^init(i) and adds step 3's.
        for &(clock, time) in &open.started {
            self.clock_started[clock.index()] = Some(time);
        }
        if marking != self.marked {
            self.marked_ids = marked_ids(&self.thca, &marking);
        }
        scratch.marking = std::mem::replace(&mut self.marked, marking);
        scratch.clocks = open.clocks;
        scratch.violated = open.violated;
        self.scratch = scratch;
        self.memo = memo;
        let was_complete = self.completed;
        self.completed = self.marked_ids.is_empty();
        if self.completed && !was_complete {
            events.push(Event::Completed);
        }
        Ok(CycleEnd {
            events,
            completed: self.completed,
        })
    }

    /// Both halves of a cycle: [`Sequencer::begin_cycle`] with ŝ(i), then
    /// [`Sequencer::end_cycle`] with ŝ(i+1).
    pub fn step<E: Entailment>(
        &mut self,
        time: f64,
        current: &E::Estimate,
        next: &E::Estimate,
        oracle: &mut E,
    ) -> Result<Step, SequencerError> {
        let start = self.begin_cycle(time, current, oracle)?;
        let end = self.end_cycle(next, oracle)?;
        Ok(Step { start, end })
    }

    fn check_time(&mut self, time: f64) -> Result<(), SequencerError> {
        if !time.is_finite() {
            return Err(SequencerError::TimeNotFinite(time));
        }
        if let Some(previous) = self.last_time.filter(|&previous| time < previous) {
            return Err(SequencerError::TimeWentBack {
                previous,
                now: time,
            });
        }
        self.last_time = Some(time);
        Ok(())
    }

    /// Step 3: every clock initialisation of a marked primitive location starts its clock at
    /// t_abs, unless the clock is already active (clock persistence: re-marking never resets).
    fn assert_clock_inits(&self, time: f64, events: &mut Vec<Event>) -> Vec<(ClockId, f64)> {
        let mut started: Vec<(ClockId, f64)> = Vec::new();
        for location in self.marking() {
            for init in location.clock_inits() {
                let active = self.clock_started[init.clock.index()].is_some()
                    || started.iter().any(|(c, _)| *c == init.clock);
                if !active {
                    started.push((init.clock, time));
                    events.push(Event::ClockStarted {
                        clock: init.clock,
                        time,
                        location: location.id,
                        span: init.span.clone(),
                    });
                }
            }
        }
        started
    }

    /// Step 4's inputs: the goals of marked primitive locations whose maintenance holds.
    fn goal_conjuncts(&self, violated: &[bool]) -> Vec<(FormulaId, GoalConjunct)> {
        self.marking()
            .filter(|l| !violated[l.id.index()])
            .filter_map(|l| {
                let goal = l.goal()?;
                let conjunct = GoalConjunct {
                    location: l.id,
                    span: goal.span.clone(),
                    formula: self.thca.formula(goal.formula).clone(),
                };
                Some((goal.formula, conjunct))
            })
            .collect()
    }

    /// Step 4: conjoin the goals. When they cannot hold together, each goal that contradicts an
    /// earlier one (by location id) is reported with the earliest goal it contradicts, and both
    /// are left out. A goal inconsistent on its own is kept: goal interpretation reports it as
    /// failed, naming the components that make it unreachable.
    fn configuration_goal<E: Entailment>(
        &mut self,
        conjuncts: Vec<(FormulaId, GoalConjunct)>,
        oracle: &mut E,
        events: &mut Vec<Event>,
    ) -> ConfigurationGoal {
        let ids: Vec<FormulaId> = conjuncts.iter().map(|(id, _)| *id).collect();
        let kept = if conjuncts.len() < 2 || self.consistent(&ids, oracle) {
            conjuncts
        } else {
            self.without_conflicts(conjuncts, oracle, events)
        };
        let conjuncts: Vec<GoalConjunct> = kept.into_iter().map(|(_, c)| c).collect();
        ConfigurationGoal {
            formula: Formula::all(conjuncts.iter().map(|c| c.formula.clone())),
            conjuncts,
        }
    }

    fn without_conflicts<E: Entailment>(
        &mut self,
        conjuncts: Vec<(FormulaId, GoalConjunct)>,
        oracle: &mut E,
        events: &mut Vec<Event>,
    ) -> Vec<(FormulaId, GoalConjunct)> {
        let mut kept: Vec<(FormulaId, GoalConjunct)> = Vec::new();
        let mut accepted: Vec<(FormulaId, GoalConjunct)> = Vec::new();
        for goal in conjuncts {
            let with = |prefix: &[(FormulaId, GoalConjunct)]| {
                let mut ids: Vec<FormulaId> = prefix.iter().map(|(id, _)| *id).collect();
                ids.push(goal.0);
                ids
            };
            if !self.consistent(&[goal.0], oracle) {
                kept.push(goal);
                continue;
            }
            if self.consistent(&with(&accepted), oracle) {
                accepted.push(goal);
                continue;
            }
            let culprit = (0..accepted.len())
                .find(|&k| !self.consistent(&with(&accepted[..=k]), oracle))
                .unwrap_or(accepted.len() - 1);
            let (_, partner) = accepted.remove(culprit);
            events.push(Event::GoalConflict {
                first: GoalSource {
                    location: partner.location,
                    span: partner.span,
                },
                second: GoalSource {
                    location: goal.1.location,
                    span: goal.1.span,
                },
            });
        }
        kept.extend(accepted);
        kept.sort_by_key(|(_, c)| c.location);
        kept
    }

    fn consistent<E: Entailment>(&mut self, ids: &[FormulaId], oracle: &mut E) -> bool {
        let mut key = ids.to_vec();
        key.sort_unstable();
        key.dedup();
        if let Some(&known) = self.consistency.get(&key) {
            return known;
        }
        let formula = Formula::all(key.iter().map(|&id| self.thca.formula(id).clone()));
        let answer = oracle.consistent(&formula);
        self.consistency.insert(key, answer);
        answer
    }

    /// Steps 7 and 8, contents before their composites. Returns the marking m(i+1) so far (the
    /// primitive locations awaiting incomplete goals) and the enabled transitions.
    fn enabled_transitions<E: Entailment>(
        &self,
        evaluator: &mut Evaluator<'_, E>,
        open: &OpenCycle,
        events: &mut Vec<Event>,
        (next, busy, enabled): (
            &mut Vec<bool>,
            &mut Vec<bool>,
            &mut Vec<(LocationId, usize)>,
        ),
    ) {
        let count = self.marked.len();
        refill(next, count);
        // A composite is busy while something inside it stays marked or moves on.
        refill(busy, count);
        enabled.clear();
        // Only marked locations can be ready, stay, or make their composite busy; their
        // composites are marked too, and visited after them.
        for &id in self.marked_ids.iter().rev() {
            let location = self.thca.location(id);
            let i = id.index();
            let ready = match &location.kind {
                LocationKind::Primitive { goal, .. } => {
                    let achieved = goal.as_ref().is_none_or(|g| evaluator.entailed(g.formula));
                    // Step 7: await an incomplete goal unless maintenance was violated.
                    next[i] = !achieved && !open.violated[i];
                    if let (true, false, Some(goal)) = (achieved, open.violated[i], goal) {
                        events.push(Event::GoalAchieved {
                            location: location.id,
                            span: goal.span.clone(),
                        });
                    }
                    // Step 8a: goal achieved or maintenance violated.
                    achieved || open.violated[i]
                }
                // Step 8a: nothing inside stays marked or has an enabled transition.
                LocationKind::Composite { .. } => !busy[i],
            };
            let mut moves = false;
            if ready {
                // Step 8b: the guard holds on ŝ(i+1) ∧ ω(i).
                for (k, transition) in location.transitions.iter().enumerate() {
                    if evaluator.guard(transition.guard.as_ref()) {
                        enabled.push((location.id, k));
                        moves = true;
                    }
                }
            }
            if let Some(parent) = location.parent {
                busy[parent.index()] |= busy[i] || next[i] || moves;
            }
        }
    }
}

/// Empties `flags` and makes it `count` times false, keeping its capacity.
fn refill(flags: &mut Vec<bool>, count: usize) {
    flags.clear();
    flags.resize(count, false);
}

/// Step 2: unmark everything inside a marked composite whose maintenance constraint
/// ŝ(i) ∧ ω(i) violates. Primitive locations' own maintenance is checked in the same pass
/// (steps 4, 7 and 8a need it). Fills `violated` with the violated locations
/// (`inside_violated` is scratch) and says whether it unmarked anything.
///
/// Visits the marked locations `ids` only, ascending: an unmarked location has nothing to
/// unmark or check, and since the marking is closed under composites, a marked location's
/// composite is marked and decided before it.
fn check_maintenance<E: Entailment>(
    (thca, ids): (&Thca, &[LocationId]),
    marked: &mut [bool],
    evaluator: &mut Evaluator<'_, E>,
    events: &mut Vec<Event>,
    (violated, inside_violated): (&mut Vec<bool>, &mut Vec<bool>),
) -> bool {
    let count = marked.len();
    refill(violated, count);
    refill(inside_violated, count);
    let mut unmarked = false;
    for &id in ids {
        let location = thca.location(id);
        let i = id.index();
        inside_violated[i] = location
            .parent
            .is_some_and(|p| inside_violated[p.index()] || violated[p.index()]);
        if inside_violated[i] {
            marked[i] = false;
            unmarked = true;
            continue;
        }
        let Some(maintenance) = location.maintenance.as_ref() else {
            continue;
        };
        if !evaluator.holds(maintenance) {
            violated[i] = true;
            events.push(Event::maintenance_failed(location, maintenance.clone()));
        }
    }
    unmarked
}

impl Event {
    /// `location`'s maintenance condition failed (Figure 5-3 step 2): a composite is preempted,
    /// a primitive location's maintenance is violated.
    pub(super) fn maintenance_failed(location: &Location, condition: Condition) -> Event {
        let (span, construct) = (location.origin.span.clone(), location.origin.construct);
        let id = location.id;
        if location.is_composite() {
            Event::Preempted {
                location: id,
                span,
                construct,
                condition,
            }
        } else {
            Event::MaintenanceViolated {
                location: id,
                span,
                construct,
                condition,
            }
        }
    }
}

/// The marked locations of `marked`, ascending.
fn marked_ids(thca: &Thca, marked: &[bool]) -> Vec<LocationId> {
    (thca.locations().iter())
        .filter(|l| marked[l.id.index()])
        .map(|l| l.id)
        .collect()
}

/// Marks every composite that contains `location`.
fn mark_composites(thca: &Thca, location: LocationId, marking: &mut [bool]) {
    let mut parent = thca.location(location).parent;
    while let Some(p) = parent {
        marking[p.index()] = true;
        parent = thca.location(p).parent;
    }
}

/// m_F: marks a location and, if it is a composite, its start locations, recursively.
/// `pending` is scratch: a program that loops in place takes a transition every quiet cycle,
/// and a fresh stack each time was 200 of the EDL cruise cycle's instructions.
fn mark_full(
    thca: &Thca,
    location: LocationId,
    marking: &mut [bool],
    pending: &mut Vec<LocationId>,
) {
    pending.clear();
    pending.push(location);
    while let Some(l) = pending.pop() {
        if !std::mem::replace(&mut marking[l.index()], true) {
            pending.extend(thca.location(l).starts());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;
    use crate::logic::{VarTable, parse_formula};
    use crate::sequencer::oracle::{AssignmentOracle, StateEstimate};
    use crate::sequencer::thca::{Construct, Goal, Origin, Sense, ThcaBuilder, Transition};

    fn table() -> VarTable {
        let mut table = VarTable::new();
        for name in ["x", "y", "ok"] {
            table.add_variable(name, ["no", "yes"]).unwrap();
        }
        table.add_clock("t").unwrap();
        table
    }

    fn origin() -> Origin {
        Origin {
            construct: Construct::Assertion,
            span: 0..0,
            call_stack: Vec::new(),
        }
    }

    struct Hand {
        builder: ThcaBuilder,
        table: VarTable,
    }

    impl Hand {
        fn new() -> Self {
            Hand {
                builder: ThcaBuilder::new("hand", table(), Source::new("hand", "")),
                table: table(),
            }
        }

        fn formula(&mut self, text: &str) -> FormulaId {
            let formula = parse_formula(text, &self.table).unwrap();
            self.builder.formula(formula)
        }

        fn condition(&mut self, text: &str, sense: Sense) -> Condition {
            Condition {
                formula: self.formula(text),
                sense,
                span: 0..0,
            }
        }

        fn primitive(&mut self, parent: Option<LocationId>, goal: Option<&str>) -> LocationId {
            let goal = goal.map(|g| Goal {
                formula: self.formula(g),
                span: 0..0,
            });
            self.builder.primitive(parent, origin(), goal, Vec::new())
        }

        fn go(&mut self, from: LocationId, guard: Option<Condition>, to: &[LocationId]) {
            let transition = Transition {
                guard,
                targets: to.to_vec(),
            };
            self.builder.add_transition(from, transition);
        }
    }

    fn estimate(assignments: &[(u32, u32)]) -> StateEstimate {
        StateEstimate::from_assignments(
            assignments
                .iter()
                .map(|&(x, v)| (crate::logic::VarId(x), crate::logic::ValueId(v))),
        )
    }

    fn numbers(sequencer: &Sequencer) -> Vec<u32> {
        sequencer.marking().map(|l| l.id.number()).collect()
    }

    #[test]
    fn a_primitive_whose_maintenance_fails_asserts_nothing_and_moves_on() {
        // Figure 5-3 steps 4, 7 and 8a: a violated primitive's goal is left out of g(i), the
        // location is not kept, and its transitions are enabled although its goal is not met.
        let mut hand = Hand::new();
        let p = hand.primitive(None, Some("x = yes"));
        let q = hand.primitive(None, Some("y = yes"));
        let keep = hand.condition("ok = yes", Sense::Entailed);
        hand.builder.set_maintenance(p, keep);
        hand.go(p, None, &[q]);
        hand.builder.add_start(None, p);
        let thca = hand.builder.build().unwrap();
        let mut oracle = AssignmentOracle::new(thca.table());

        let mut sequencer = Sequencer::new(thca.clone());
        let held = estimate(&[(2, 1)]);
        let step = sequencer.step(0.0, &held, &held, &mut oracle).unwrap();
        assert_eq!(step.start.goal.conjuncts.len(), 1, "maintenance holds");
        assert_eq!(numbers(&sequencer), [1], "step 7: awaits its goal");

        let mut sequencer = Sequencer::new(thca);
        let unknown = estimate(&[]);
        let step = sequencer
            .step(0.0, &unknown, &unknown, &mut oracle)
            .unwrap();
        assert_eq!(step.start.goal.formula, Formula::True, "step 4");
        assert!(matches!(
            step.start.events[..],
            [Event::MaintenanceViolated { .. }]
        ));
        assert_eq!(numbers(&sequencer), [2], "step 8a: progress on violation");
    }

    #[test]
    fn a_preemption_carries_the_watched_condition() {
        // Figure 5-3 step 2: `do A watching c` is a composite with maintenance ⊭ c (thesis
        // §5.2); when ŝ(i) entails c the composite is preempted, and the event names the
        // construct and the condition whose entailment preempted it.
        let mut hand = Hand::new();
        let watching = Origin {
            construct: Construct::Watching,
            ..origin()
        };
        let c = hand.builder.composite(None, watching);
        let inside = hand.primitive(Some(c), Some("y = yes"));
        let watched = Condition {
            span: 7..14,
            ..hand.condition("x = yes", Sense::NotEntailed)
        };
        hand.builder.set_maintenance(c, watched.clone());
        hand.builder.add_start(Some(c), inside);
        hand.builder.add_start(None, c);
        let thca = hand.builder.build().unwrap();
        let mut oracle = AssignmentOracle::new(thca.table());
        let mut sequencer = Sequencer::new(thca);
        let quiet = estimate(&[(0, 0)]);
        let step = sequencer.step(0.0, &quiet, &quiet, &mut oracle).unwrap();
        assert!(step.start.events.is_empty(), "x = no: the watch holds");
        let entailed = estimate(&[(0, 1)]);
        let start = sequencer.begin_cycle(1.0, &entailed, &mut oracle).unwrap();
        assert_eq!(
            start.events,
            [Event::Preempted {
                location: c,
                span: 0..0,
                construct: Construct::Watching,
                condition: watched,
            }]
        );
        assert_eq!(start.goal.formula, Formula::True, "nothing inside asserts");
    }

    #[test]
    fn a_composite_waits_while_anything_inside_moves() {
        // Figure 5-3 step 8, composites: enabled only when nothing inside is marked in m(i+1) and
        // nothing inside has an enabled transition.
        let mut hand = Hand::new();
        let c = hand.builder.composite(None, origin());
        let a = hand.primitive(Some(c), None);
        let b = hand.primitive(Some(c), None);
        let after = hand.primitive(None, Some("y = yes"));
        hand.go(a, None, &[b]);
        hand.go(c, None, &[after]);
        hand.builder.add_start(Some(c), a);
        hand.builder.add_start(None, c);
        let thca = hand.builder.build().unwrap();
        let mut oracle = AssignmentOracle::new(thca.table());
        let mut sequencer = Sequencer::new(thca);
        let none = estimate(&[]);
        assert_eq!(numbers(&sequencer), [1, 2], "m_F marks the start inside");
        sequencer.step(0.0, &none, &none, &mut oracle).unwrap();
        assert_eq!(
            numbers(&sequencer),
            [1, 3],
            "a moved to b: c stays, re-marked"
        );
        sequencer.step(1.0, &none, &none, &mut oracle).unwrap();
        assert_eq!(numbers(&sequencer), [4], "b finished: c exits");
    }

    #[test]
    fn a_bound_on_a_clock_not_yet_started_is_unknown() {
        // Clocks are active only once initialised (§5.3); an inactive clock's bound is neither
        // entailed nor refuted, so only guards true whatever its value hold.
        let mut hand = Hand::new();
        let p = hand.primitive(None, None);
        let [q, r, s] = [(); 3].map(|_| hand.primitive(None, Some("y = yes")));
        let reached = hand.condition("t >= 0", Sense::Entailed);
        let not_reached = hand.condition("t >= 0", Sense::NotEntailed);
        let tautology = hand.condition("t >= 0 or not t >= 0", Sense::Entailed);
        hand.go(p, Some(reached), &[q]);
        hand.go(p, Some(not_reached), &[r]);
        hand.go(p, Some(tautology), &[s]);
        hand.builder.add_start(None, p);
        let thca = hand.builder.build().unwrap();
        let mut oracle = AssignmentOracle::new(thca.table());
        let mut sequencer = Sequencer::new(thca);
        let none = estimate(&[]);
        sequencer.step(0.0, &none, &none, &mut oracle).unwrap();
        let marked: Vec<LocationId> = sequencer.marking().map(|l| l.id).collect();
        assert_eq!(marked, [r, s]);
        assert!(!sequencer.is_marked(q));
    }
}
