//! The order of one timeline's points (mds-goal-networks.md §2.2 step 2b; GP §3.6: fixed per
//! timeline): a total order consistent with the STN, each consecutive pair bound by
//! `[0, +∞)`, found depth first — candidates by increasing earliest time, then those that no
//! remaining point precedes by a constraint (a point a constraint puts at or after another
//! remaining point goes after it among equals: placing it first would force the two to
//! coincide and each would wait for the other to fire, as Heater's `TP_H → TP_A ∈ [0, 5]`),
//! then creation order — backtracking when an order does not fit, within [`ORDER_BUDGET`] tries.
//!
//! **Cost.** The search keeps the candidates in a `BTreeSet` keyed by that order and the
//! network in place: a step tries the first candidate by adding its constraint to the network
//! itself ([`Stn::try_constraint`]: relaxed from the new edge, touching only the points whose
//! earliest time moves) and re-keys only those points and the points the placed one preceded;
//! backtracking undoes exactly that ([`Stn::undo`]). A timeline of `n` points whose first
//! candidates fit costs `O(n log n)` plus the relaxations, where the search it replaces copied
//! the network, propagated it in full and sorted every candidate with a scan of every
//! constraint at each step.
//!
//! **Same answer.** The candidates of a step are tried in the order of the keys at that step;
//! after an undo the set holds exactly those keys again, so the next candidate is the next key.
//! The keys are those of the search it replaces (earliest time by `f64::total_cmp`, whether a
//! remaining point precedes it by a constraint of minimum ≥ 0, the point's id), the trials
//! succeed and fail on the same networks, and the budget is spent one per candidate tried, so
//! the order found — or the failure — is the same.

use std::collections::BTreeSet;
use std::ops::Bound::{Excluded, Unbounded};

use rustc_hash::FxHashMap;

use super::ScheduleError;
use crate::goalnet::goal::GoalId;
use crate::goalnet::network::GoalNetwork;
use crate::goalnet::stn::{Inconsistency, Stn, Trial};
use crate::goalnet::temporal_constraint::{Provenance, TemporalConstraint};
use crate::goalnet::time_point::TimePointId;

/// Orderings of one timeline tried before giving up (a depth-first search with backtracking).
pub(super) const ORDER_BUDGET: usize = 10_000;

/// A total order of the goals' points consistent with the STN, added to it (§2.2 step 2b).
pub(super) fn order(
    network: &mut GoalNetwork,
    goals: &[GoalId],
) -> Result<Vec<TimePointId>, ScheduleError> {
    let mut points: Vec<TimePointId> = goals
        .iter()
        .flat_map(|g| [network.goal(*g).start, network.goal(*g).end])
        .collect();
    points.sort_unstable();
    points.dedup();
    let mut search = OrderSearch::new(network.stn(), points);
    let found = search.run(network.stn_mut());
    match found {
        Some(order) => Ok(order),
        None => Err(ScheduleError::Inconsistent(search.last_failure())),
    }
}

/// A candidate's place in a step's order: earliest time (as `f64::total_cmp` orders it),
/// whether a remaining point precedes it, its id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Key {
    earliest: u64,
    follows: bool,
    point: TimePointId,
}

/// The bits of `x` ordered as `f64::total_cmp` orders `x`.
fn total_order_bits(x: f64) -> u64 {
    let bits = x.to_bits();
    if bits >> 63 == 1 {
        !bits
    } else {
        bits | (1 << 63)
    }
}

/// One placed point: its key when it was placed and the trial that ordered it after the
/// previous one (none for the first).
struct Level {
    key: Key,
    trial: Option<Trial>,
}

/// The depth-first search for a timeline's order.
struct OrderSearch {
    budget: usize,
    /// The network a refused order was last tried on, with the refused constraint.
    last_failure: Option<(Stn, TemporalConstraint)>,
    /// The timeline's points, and each one's index among them.
    points: Vec<TimePointId>,
    local: FxHashMap<TimePointId, usize>,
    /// Per point: the points a constraint of minimum ≥ 0 puts at or after it (with repeats).
    successors: Vec<Vec<usize>>,
    /// Per point: how many remaining points precede it so.
    preceded: Vec<usize>,
    /// Per point: its key while it remains (`None` once placed).
    keys: Vec<Option<Key>>,
    remaining: BTreeSet<Key>,
}

impl OrderSearch {
    fn new(stn: &Stn, points: Vec<TimePointId>) -> Self {
        let local: FxHashMap<TimePointId, usize> =
            points.iter().enumerate().map(|(i, &p)| (p, i)).collect();
        let mut successors = vec![Vec::new(); points.len()];
        let mut preceded = vec![0; points.len()];
        for c in stn.constraints() {
            if c.min < 0.0 || c.from == c.to {
                continue;
            }
            if let (Some(&from), Some(&to)) = (local.get(&c.from), local.get(&c.to)) {
                successors[from].push(to);
                preceded[to] += 1;
            }
        }
        let mut search = OrderSearch {
            budget: ORDER_BUDGET,
            last_failure: None,
            keys: vec![None; points.len()],
            points,
            local,
            successors,
            preceded,
            remaining: BTreeSet::new(),
        };
        for i in 0..search.points.len() {
            search.rekey(stn, i, true);
        }
        search
    }

    /// The key of point `i` in the network as it is.
    fn key(&self, stn: &Stn, i: usize) -> Key {
        let point = self.points[i];
        Key {
            earliest: total_order_bits(stn.earliest(point).unwrap_or(0.0)),
            follows: self.preceded[i] > 0,
            point,
        }
    }

    /// Brings point `i`'s key up to date (`insert`: it remains; else it was placed).
    fn rekey(&mut self, stn: &Stn, i: usize, insert: bool) {
        if let Some(old) = self.keys[i].take() {
            self.remaining.remove(&old);
        }
        if insert {
            let key = self.key(stn, i);
            self.remaining.insert(key);
            self.keys[i] = Some(key);
        }
    }

    /// Re-keys the remaining points among `moved` (whose earliest times changed).
    fn rekey_moved(&mut self, stn: &Stn, moved: &[(TimePointId, f64)]) {
        for (point, _) in moved {
            if let Some(&i) = self.local.get(point)
                && self.keys[i].is_some()
            {
                self.rekey(stn, i, true);
            }
        }
    }

    /// Takes point `i` out of the remaining ones (`placed`) or puts it back.
    fn set_placed(&mut self, stn: &Stn, i: usize, placed: bool) {
        self.rekey(stn, i, !placed);
        for k in 0..self.successors[i].len() {
            let s = self.successors[i][k];
            if placed {
                self.preceded[s] -= 1;
            } else {
                self.preceded[s] += 1;
            }
            if self.keys[s].is_some() {
                self.rekey(stn, s, true);
            }
        }
    }

    /// The search, iteratively (a timeline may have thousands of points): the placed points
    /// are the stack. `None` when no order fits or the budget is spent.
    fn run(&mut self, stn: &mut Stn) -> Option<Vec<TimePointId>> {
        let mut stack: Vec<Level> = Vec::new();
        let mut cursor = self.remaining.first().copied();
        loop {
            let key = match cursor {
                Some(key) => key,
                None if self.remaining.is_empty() => {
                    return Some(stack.iter().map(|l| l.key.point).collect());
                }
                None => {
                    // Every candidate of this step failed: take back the last placement and try
                    // the candidate after it.
                    let level = stack.pop()?;
                    let key = level.key;
                    self.unplace(stn, level);
                    cursor = self.after(key);
                    continue;
                }
            };
            if self.budget == 0 {
                return None;
            }
            self.budget -= 1;
            let last = stack.last().map(|l| l.key.point);
            match self.place(stn, last, key) {
                Some(level) => {
                    stack.push(level);
                    cursor = self.remaining.first().copied();
                }
                None => cursor = self.after(key),
            }
        }
    }

    /// The candidate after `key` in this step's order.
    fn after(&self, key: Key) -> Option<Key> {
        self.remaining
            .range((Excluded(key), Unbounded))
            .next()
            .copied()
    }

    /// Places the candidate `key` after `last`: `None` when the network refuses the order.
    fn place(&mut self, stn: &mut Stn, last: Option<TimePointId>, key: Key) -> Option<Level> {
        let trial = match last {
            None => None,
            Some(last) => {
                let reason = "the state variable's timeline is ordered".to_string();
                let constraint =
                    TemporalConstraint::before(last, key.point, Provenance::Scheduled { reason });
                match stn.try_constraint(constraint.clone()) {
                    Ok(trial) => Some(trial),
                    Err(_) => {
                        self.last_failure = Some((stn.clone(), constraint));
                        return None;
                    }
                }
            }
        };
        let i = self.local[&key.point];
        self.set_placed(stn, i, true);
        if let Some(trial) = &trial {
            let moved = trial.moved(stn);
            self.rekey_moved(stn, &moved);
        }
        Some(Level { key, trial })
    }

    /// Takes back a placement.
    fn unplace(&mut self, stn: &mut Stn, level: Level) {
        if let Some(trial) = level.trial {
            let moved = trial.moved(stn);
            stn.undo(trial);
            self.rekey_moved(stn, &moved);
        }
        let i = self.local[&level.key.point];
        self.set_placed(stn, i, false);
    }

    /// The inconsistency of the last order refused (none when no order was refused: the budget
    /// ran out), named by its cycle as a propagation of that network names it.
    fn last_failure(&self) -> Inconsistency {
        let empty = || Inconsistency { cycle: Vec::new() };
        let Some((stn, constraint)) = &self.last_failure else {
            return empty();
        };
        let mut stn = stn.clone();
        if stn.add_constraint(constraint.clone()).is_err() {
            return empty();
        }
        stn.propagate().err().unwrap_or_else(empty)
    }
}
