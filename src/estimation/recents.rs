//! What [`Expander::choices`](super::expand::Expander::choices) remembers between sources and
//! steps: each component's next-mode distribution per step and input ([`StepMemo`], its
//! clockless tier shared by inputs through [`Clockless`]), and the recent sources' choices
//! ([`Recents`]). Each is certified to hold a pure function of its key (documented on the type),
//! so a lookup gives the very distributions a recomputation would.

use std::hash::{Hash, Hasher};
use std::sync::Arc;

use rustc_hash::{FxHashMap, FxHasher};

use super::expand::{CACHE_LIMIT, Choices, NextMode, next_modes};
use crate::logic::ValueId;
use crate::plant::{
    Commands, Component, Enabled, Plant, SystemState, component_distribution,
    distribution_steady_at as steady,
};

/// The clockless tier of [`StepMemo`] holds one item per component an entry; past this many
/// items in all it starts afresh too, so that its memory does not grow with the plant (it is
/// pure, and refilled from [`Clockless`] by lookups).
const UNTIMED_ITEMS: usize = 1 << 21;

/// Next-mode distributions already computed. Certified: a component's distribution is
/// [`component_distribution`] of (component, mode, enabled transitions, clock, step length) and
/// nothing else — the step's end points enter only through its length `to − from` — so an entry
/// whose inputs match (the clock and the length bit for bit) is the very distribution a
/// recomputation would give.
///
/// Two tiers, because clock readings move with the step's start and nothing else does: entries
/// with a clock reading serve the current step only (they would not be met again); entries
/// without one — every component whose clock does not matter in its mode, as estimation forgets
/// such clocks — serve every later step of the same length too, so a quiet cycle computes only
/// the distributions of running clocks. The clockless tier is keyed by the source's enabled
/// transitions *by address* and the step length: the enabled transitions are cached per
/// (modes, μ), one allocation per key, and the entry holds that allocation so the address
/// cannot be reused; an address therefore names one (modes, μ), which fixes every component's
/// mode and enabled transitions.
///
/// The clockless tier's distributions are themselves shared ([`Clockless`]): a new (modes, μ)
/// mostly repeats the distributions of states met before, component by component (a breaker
/// tree's sources differ in one or two breakers), and computing and allocating each component's
/// afresh for every address was a quarter of a 255-breaker replay's memory.
#[derive(Default)]
pub(super) struct StepMemo {
    /// The step (`from`, `to`) the timed entries belong to, as bits.
    step: (u64, u64),
    /// Per component, the distributions with a clock reading computed in this step.
    pub(super) timed: Vec<Vec<Memo>>,
    /// (address of the enabled transitions, step length as bits) → per component, its
    /// distribution without a clock, once computed.
    pub(super) untimed: FxHashMap<(usize, u64), Untimed>,
    /// The clockless distributions by their inputs.
    pub(super) clockless: Clockless,
}

/// Clockless distributions by their inputs — component, mode, its enabled transitions and the
/// step's length — which are all [`component_distribution`] depends on without a clock: an
/// entry is the very distribution a recomputation would give, shared.
#[derive(Default)]
pub(super) struct Clockless {
    /// [component, mode, step length as bits, delivered, enabled transitions…] → distribution.
    by_inputs: FxHashMap<Vec<u64>, Arc<[NextMode]>>,
    /// The key being looked up (a lookup allocates nothing).
    key: Vec<u64>,
}

/// Past this many entries [`Clockless`] starts afresh (an entry is a few dozen bytes).
const CLOCKLESS_LIMIT: usize = 1 << 17;

impl Clockless {
    /// Component `c`'s distribution from `mode` without a clock, given its enabled transitions,
    /// over a step of length `step`.
    pub(super) fn get(
        &mut self,
        component: &Component,
        c: usize,
        mode: ValueId,
        enabled: &Enabled,
        step: f64,
    ) -> Arc<[NextMode]> {
        self.key.clear();
        let inputs = [
            c as u64,
            u64::from(mode.0),
            step.to_bits(),
            enabled.delivered as u64,
        ];
        self.key.extend(inputs);
        self.key
            .extend(enabled.transitions.iter().map(|&t| t as u64));
        if let Some(next) = self.by_inputs.get(self.key.as_slice()) {
            return Arc::clone(next);
        }
        if self.by_inputs.len() >= CLOCKLESS_LIMIT {
            self.by_inputs.clear();
        }
        let next = next_modes(component_distribution(component, mode, enabled, None, step));
        self.by_inputs.insert(self.key.clone(), Arc::clone(&next));
        next
    }
}

/// One memoised distribution of the current step.
pub(super) struct Memo {
    mode: ValueId,
    /// The source's enabled transitions (all components'; this one's at its index), shared
    /// with the cache of enabled transitions rather than copied.
    enabled: Arc<Vec<Enabled>>,
    clock: Option<u64>,
    next: Arc<[NextMode]>,
}

/// The clockless distributions of one (modes, μ) and step length.
///
/// A state with every clock forgotten (no component's clock matters: Livingstone 2's breakers,
/// untimed plants) has every component's distribution from here, so its whole choices are a
/// function of the key and are kept as one `Arc<Choices>`: such a source gets a reference count
/// rather than a vector of one per component, built and later dropped (on L2's 15-breaker log,
/// whose 8κ re-runs meet new states every step, those counts were 7 % of the time samples;
/// sharing took 10 % off its CPU time at κ = 10, 9 % at κ = 5).
/// Every state that gets it is equal to the first (the same modes, no clock start), so a
/// version of choices still names one state ([`Recents`], `replay.rs`); and since this entry
/// holds the `Arc`, the shared choices are never written in place.
pub(super) struct Untimed {
    /// The enabled transitions whose address is the key, held so that it stays unique.
    pub(super) _enabled: Arc<Vec<Enabled>>,
    /// Per component.
    pub(super) next: Vec<Option<Arc<[NextMode]>>>,
    /// The choices of the state with these modes and no clock start, once made.
    pub(super) whole: Option<Arc<Choices>>,
}

impl StepMemo {
    /// Starts the step `from`–`to` unless it is the current one.
    pub(super) fn start(&mut self, plant: &Plant, from: f64, to: f64) {
        let step = (from.to_bits(), to.to_bits());
        if self.step != step || self.timed.len() != plant.components().len() {
            self.step = step;
            // Emptied, not dropped: the lists keep their capacity from step to step.
            self.timed.iter_mut().for_each(Vec::clear);
            self.timed.resize_with(plant.components().len(), Vec::new);
            let limit = (UNTIMED_ITEMS / plant.components().len().max(1)).clamp(64, CACHE_LIMIT);
            if self.untimed.len() >= limit {
                self.untimed.clear();
            }
        }
    }
}

/// A component's distribution with a clock `reading` in the current step, from the step's memo
/// when a source already asked for it ([`StepMemo`]).
pub(super) fn timed(
    memos: &mut Vec<Memo>,
    component: &Component,
    c: usize,
    mode: ValueId,
    enabled: &Arc<Vec<Enabled>>,
    reading: f64,
    step: f64,
) -> Arc<[NextMode]> {
    let bits = Some(reading.to_bits());
    let known = memos.iter().find(|m| {
        m.mode == mode
            && m.clock == bits
            && (Arc::ptr_eq(&m.enabled, enabled) || m.enabled[c] == enabled[c])
    });
    if let Some(memo) = known {
        return Arc::clone(&memo.next);
    }
    let next = next_modes(component_distribution(
        component,
        mode,
        &enabled[c],
        Some(reading),
        step,
    ));
    memos.push(Memo {
        mode,
        enabled: Arc::clone(enabled),
        clock: bits,
        next: Arc::clone(&next),
    });
    next
}

/// Whether two distributions are the same bit for bit (`NextMode`'s `==` would call −0.0 and
/// 0.0 equal).
pub(super) fn same_bits(a: &[NextMode], b: &[NextMode]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.mode == y.mode
                && x.probability.to_bits() == y.probability.to_bits()
                && x.cost.to_bits() == y.cost.to_bits()
        })
}

/// The sources whose choices were computed in recent steps (a quiet step's sources
/// are mostly the last steps' states). Certified like [`StepMemo`]: a source's choices are a
/// function of its modes, its clock starts, μ (through the enabled transitions, a function of
/// the modes and μ), the step's length and its start (through the clock readings) and nothing
/// else. A source equal to a recent one (modes and clock starts bit for bit), under the same μ
/// and step length (bit for bit: a cycle's length jitters in its last bits, so a few lengths
/// alternate and each has its own entries), therefore has that source's distributions wherever
/// a component has no clock; a component whose clock runs is computed again (through the memo)
/// unless its reading is the same bit for bit, and the recent distribution is kept when the new
/// one equals it bit for bit. A clock on its steady stretch is not read again: its component's
/// distribution is the same at every steady reading (`plant::distribution_steady_at`), so an
/// entry whose distribution was computed at a steady reading already holds the one a steady
/// reading would compute (the Mars EDL's entry trigger is steady for its first 15,600 s, 91 %
/// of the nominal run's cycles). When no component changed, the source gets the very same
/// choices, of the same version, as before, which lets the replay reuse what it prepared from
/// them (`replay.rs`); when one changed, the entry's choices are written in place where no one
/// else holds them, under a new version ([`Choices`]).
/// Every version of choices [`Expander::choices`] hands out is made for one state and handed
/// out again only for states equal to it (modes and clock starts bit for bit), by its entry
/// (whose state never changes; writing the choices gives them a new version for the same
/// state) or, for a state without clock starts, by [`Untimed::whole`]: the replay takes the
/// version as naming that state.
#[derive(Default)]
pub(super) struct Recents {
    /// The step (`from`, `to`) asked last, as bits.
    step: (u64, u64),
    /// Steps started, as a clock for [`Recent::used`].
    pub(super) steps: u64,
    /// The entries, in the order they were made.
    pub(super) pool: Vec<Recent>,
    /// [`Recent::hash`] → the first entry of `pool` with that hash. An entry is made only when
    /// none equal to it is found, so at most one entry matches a lookup, and the index finds
    /// the one a scan of the pool would (a re-run of the history window at 8κ brings
    /// hundreds of entries, and scanning them for each source was an eighth of a partially
    /// observed replay's instructions).
    index: FxHashMap<u64, usize>,
    /// Where [`Recents::find`] looks first.
    next: usize,
}

/// Entries not used for this many steps are dropped (a few step lengths alternate).
pub(super) const RECENT_STEPS: u64 = 8;

/// One source state's choices, with what they are a function of.
pub(super) struct Recent {
    /// [`Recents::hash`] of `state`, `commands` and `step`.
    hash: u64,
    pub(super) state: SystemState,
    /// The components whose clock `state` knows (runs), by index, each with whether its
    /// distribution in `choices` was computed at a reading on its steady stretch
    /// (`plant::distribution_steady_at`).
    running: Vec<(usize, bool)>,
    commands: Commands,
    /// The step's length, as bits.
    step: u64,
    /// The start of the step it was last used in.
    from: f64,
    /// [`Recents::steps`] when it was last used.
    pub(super) used: u64,
    /// The enabled transitions of `state` under `commands`.
    enabled: Arc<Vec<Enabled>>,
    pub(super) choices: Arc<Choices>,
}

impl Recents {
    /// Starts the step `from`–`to` unless it is the current one, dropping the entries not used
    /// for [`RECENT_STEPS`].
    pub(super) fn start(&mut self, from: f64, to: f64) {
        let step = (from.to_bits(), to.to_bits());
        if self.step != step {
            self.step = step;
            self.steps += 1;
            let now = self.steps;
            let before = self.pool.len();
            self.pool.retain(|r| now - r.used <= RECENT_STEPS);
            if self.pool.len() != before {
                self.index.clear();
                for (at, recent) in self.pool.iter().enumerate() {
                    self.index.entry(recent.hash).or_insert(at);
                }
            }
            self.next = 0;
        }
    }

    /// The hash an entry for `state` under `commands` and a step of length `step` is indexed by.
    fn hash(state: &SystemState, commands: &Commands, step: f64) -> u64 {
        let mut hasher = FxHasher::default();
        state.hash(&mut hasher);
        commands.hash(&mut hasher);
        step.to_bits().hash(&mut hasher);
        hasher.finish()
    }

    /// Adds an entry (none equal to it is in the pool).
    pub(super) fn push(&mut self, recent: Recent) {
        self.index.entry(recent.hash).or_insert(self.pool.len());
        self.pool.push(recent);
    }

    /// The entry of a source equal to `state` under `commands` and a step of length `step`:
    /// the one after the entry found last first (a step's sources come in the order they came
    /// in when their entries were made), then the index. `Err` carries [`Recents::hash`] of
    /// the three for the entry to be made. The hash is computed only when the first guess
    /// misses: on a quiet step every source is found there, and hashing each source state
    /// cost the Mars lander's quiet cycle 4 k instructions.
    pub(super) fn find(
        &mut self,
        state: &SystemState,
        commands: &Commands,
        step: f64,
    ) -> Result<usize, u64> {
        let bits = step.to_bits();
        let same = |r: &Recent| r.step == bits && r.state == *state && r.commands == *commands;
        let guess = self.next;
        let found = if self.pool.get(guess).is_some_and(same) {
            Ok(guess)
        } else {
            let hash = Self::hash(state, commands, step);
            let matches = |r: &Recent| r.hash == hash && same(r);
            match self.index.get(&hash) {
                Some(&at) if matches(&self.pool[at]) => Ok(at),
                // A collision: another entry holds the hash's slot.
                Some(_) => self.pool.iter().position(matches).ok_or(hash),
                None => Err(hash),
            }
        };
        self.next = found.map_or(0, |at| at + 1);
        found
    }
}

impl Recent {
    /// The entry of `state`'s `choices` under `commands`, made in a step of length `step` from
    /// `from`, [`Recents::steps`] being `now`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        plant: &Plant,
        hash: u64,
        state: &SystemState,
        commands: &Commands,
        (step, from): (f64, f64),
        now: u64,
        enabled: Arc<Vec<Enabled>>,
        choices: &Arc<Choices>,
    ) -> Recent {
        Recent {
            hash,
            state: state.clone(),
            running: (state.clock_starts.iter().enumerate())
                .filter_map(|(c, start)| {
                    let component = &plant.components()[c];
                    let reading = from - (*start)?;
                    Some((c, steady(component, &enabled[c], Some(reading), step)))
                })
                .collect(),
            commands: commands.clone(),
            step: step.to_bits(),
            from,
            used: now,
            enabled,
            choices: Arc::clone(choices),
        }
    }

    /// Moves these choices to a step starting at `from` (same length): components with a
    /// running clock are computed again where their reading moved ([`Recents`]).
    pub(super) fn advance(
        &mut self,
        plant: &Plant,
        memos: &mut [Vec<Memo>],
        state: &SystemState,
        from: f64,
        step: f64,
    ) {
        for (c, steady_before) in &mut self.running {
            let c = *c;
            let Some(start) = state.clock_starts[c] else {
                continue;
            };
            let reading = from - start;
            if reading.to_bits() == (self.from - start).to_bits() {
                continue;
            }
            let (component, mode) = (&plant.components()[c], state.modes[c]);
            // Steady then and now: the distribution held is the one this reading gives.
            let steady_now = steady(component, &self.enabled[c], Some(reading), step);
            if std::mem::replace(steady_before, steady_now) && steady_now {
                continue;
            }
            let next = timed(
                &mut memos[c],
                component,
                c,
                mode,
                &self.enabled,
                reading,
                step,
            );
            if !same_bits(&next, &self.choices[c]) {
                // In place when no one else holds them (a new version either way: `Choices`).
                Arc::make_mut(&mut self.choices).set(c, next);
            }
        }
        self.from = from;
    }
}
