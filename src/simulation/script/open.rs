//! The nondeterminism of a scripted plant beyond optional rules, which `kairos explore` leaves
//! open and a run resolves one documented way:
//!
//! - **Where a timed response lands.** A rule with `after: Between(from, to)` lands its effect
//!   at a cycle whose time is in [fired + from, fired + to]. A run takes `from` (the effect
//!   shows at the first cycle at least `from` after the firing, as `Seconds(from)` would) unless
//!   the scenario's `choose` pins the rule's delay. Under exploration the landing is
//!   [`Due::Open`] until the explorer [`land`](ScriptedPlant::land)s it. The delay is chosen
//!   once per rule and path, at its first firing, and kept for later firings: an interval
//!   models an uncertain property of the device (how long a heater takes), not jitter, and a
//!   single delay is what `choose` can pin, so every counterexample replays.
//! - **The order of simultaneous deliveries.** Effects due in one cycle are applied in the
//!   order their rules fired. The order matters only through the values left once all are
//!   applied: every condition and trigger is tested after the cycle's due effects are all
//!   applied (time rules fire after them, command and estimate rules after the executive's
//!   step), so nothing observes an intermediate value. Two effects *contend* when they write a
//!   common name (an observable or hidden variable set or dropped, a garbled word) differently;
//!   [`ScriptedPlant::delivery_orders`] gives one order per distinct outcome of permuting the
//!   contending effects (the others keep their place), the fired order first. No contention:
//!   one order, no branching.

use super::{Delay, Due, Effect, Held, Script, ScriptedPlant, TIME_EPSILON, due_at};
use crate::executive::Value;
use crate::logic::ValueId;

/// At most this many contending effects of one cycle are permuted (6! = 720 orders); beyond
/// it the later ones keep their fired order.
const MAX_CONTENDING: usize = 6;

/// A rule's effect fired with an interval whose landing is still open.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenLanding {
    /// The rule, by index into [`Script::rules`].
    pub rule: usize,
    /// The time it fired at.
    pub fired: f64,
    /// The first cycle the effect may show at (the next one for command and estimate rules).
    pub not_before: u64,
}

impl ScriptedPlant<'_> {
    /// Leaves every interval's landing open (pending until [`land`](Self::land)) for
    /// `kairos explore` to choose, except those `choose` pins.
    pub fn leave_open(&mut self) {
        self.open = true;
    }

    /// The first effect whose landing is open, if any.
    pub fn open_landing(&self) -> Option<OpenLanding> {
        self.pending.iter().find_map(|p| match p.due {
            Due::Open { fired, not_before } => Some(OpenLanding {
                rule: p.rule,
                fired,
                not_before,
            }),
            _ => None,
        })
    }

    /// Fixes rule `rule`'s delay on this path to `delay` seconds: its open effects land at the
    /// first cycle at least `delay` after their firing, and so will its later firings.
    pub fn land(&mut self, rule: usize, delay: f64) {
        self.landing[rule] = Some(delay);
        for pending in self.pending.iter_mut().filter(|p| p.rule == rule) {
            if let Due::Open { fired, not_before } = pending.due {
                pending.due = Due::Time {
                    at: fired + delay,
                    not_before,
                };
            }
        }
    }

    /// Applies the effects due at the next cycle in this order (the rules, one entry per
    /// effect): a permutation of what is due, as [`delivery_orders`](Self::delivery_orders)
    /// gives.
    pub fn force_order(&mut self, order: &[usize]) {
        self.order = Some(order.to_vec());
    }

    /// The rules whose effects are due at `cycle` (at `time`), in the order they fired.
    pub fn due_at(&self, cycle: u64, time: f64) -> Vec<usize> {
        (self.pending.iter())
            .filter(|p| due_at(p.due, cycle, time))
            .map(|p| p.rule)
            .collect()
    }

    /// One order of the effects due at `cycle` per distinct outcome, the fired order first.
    pub fn delivery_orders(&self, cycle: u64, time: f64) -> Vec<Vec<usize>> {
        distinct_orders(self.script, &self.due_at(cycle, time))
    }

    /// When the rule fired now (at cycle `cycle`, its effect not before `earliest`) shows.
    pub(super) fn due(&self, rule: usize, cycle: u64, earliest: u64) -> Due {
        let script = self.script;
        let pinned = (script.pinned.iter()).find_map(|&(r, delay)| (r == rule).then_some(delay));
        let chosen = self.landing[rule].or(pinned);
        let interval = script.rules[rule].interval.is_some();
        let delay = match chosen {
            Some(seconds) if interval => Delay::Seconds(seconds),
            None if interval && self.open => {
                return Due::Open {
                    fired: self.time,
                    not_before: earliest,
                };
            }
            _ => script.rules[rule].delay,
        };
        match delay {
            Delay::Cycles(n) => Due::Cycle((cycle + n).max(earliest)),
            Delay::Seconds(s) => Due::Time {
                at: self.time + s,
                not_before: earliest,
            },
        }
    }

    /// The order to apply the effects of `fired` (the due rules, in fired order) in: the
    /// forced one, else the one `deliver` pins for this cycle, when it is a permutation of
    /// them (a replay that diverged from its path keeps the fired order).
    pub(super) fn delivery_order(&self, fired: Vec<usize>) -> Vec<usize> {
        let time = self.time;
        let pinned = (self.script.deliveries.iter())
            .find(|(at, _)| (at - time).abs() <= TIME_EPSILON)
            .map(|(_, order)| order);
        match self.order.as_ref().or(pinned) {
            Some(order) if is_permutation(order, &fired) => order.clone(),
            _ => fired,
        }
    }
}

/// True when `a` and `b` hold the same rules the same number of times.
fn is_permutation(a: &[usize], b: &[usize]) -> bool {
    let mut a = a.to_vec();
    let mut b = b.to_vec();
    a.sort_unstable();
    b.sort_unstable();
    a == b
}

/// What an effect leaves on one name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum Write {
    Set(ValueId),
    /// A reading, by its bits (two effects that write the same number agree).
    Read(u64),
    Dropped,
    Garbled(Value),
    Ungarbled,
}

/// Every name an effect writes and what it leaves there.
fn writes(script: &Script, effect: &Effect) -> Vec<(String, Write)> {
    let name = |var| script.world.variable(var).name().to_string();
    let mut out: Vec<(String, Write)> = Vec::new();
    out.extend(effect.set.iter().map(|&(v, held)| {
        let write = match held {
            Held::Value(x) => Write::Set(x),
            Held::Reading(x) => Write::Read(x.to_bits()),
        };
        (name(v), write)
    }));
    out.extend(effect.drop.iter().map(|&v| (name(v), Write::Dropped)));
    out.extend(
        effect
            .ungarble
            .iter()
            .map(|n| (n.clone(), Write::Ungarbled)),
    );
    let garbled = effect.garble.iter();
    out.extend(garbled.map(|g| (g.variable.clone(), Write::Garbled(g.value.clone()))));
    out
}

/// True when two effects write a common name differently.
fn contend(a: &[(String, Write)], b: &[(String, Write)]) -> bool {
    a.iter()
        .any(|(n, w)| b.iter().any(|(m, x)| n == m && w != x))
}

/// One permutation of `due` per distinct outcome (the last write on each contended name), the
/// fired order first; see the module documentation.
pub(crate) fn distinct_orders(script: &Script, due: &[usize]) -> Vec<Vec<usize>> {
    if due.len() < 2 {
        // The common case, every cycle of a search: nothing to order.
        return vec![due.to_vec()];
    }
    let effects: Vec<Vec<(String, Write)>> = (due.iter())
        .map(|&rule| writes(script, &script.rules[rule].effect))
        .collect();
    let contending: Vec<usize> = (0..due.len())
        .filter(|&i| (0..due.len()).any(|j| j != i && contend(&effects[i], &effects[j])))
        .take(MAX_CONTENDING)
        .collect();
    if contending.len() < 2 {
        return vec![due.to_vec()];
    }
    let mut outcomes: Vec<Vec<(String, Write)>> = Vec::new();
    let mut orders = Vec::new();
    let mut permutation: Vec<usize> = contending.clone();
    loop {
        let mut order: Vec<usize> = (0..due.len()).collect();
        for (&slot, &effect) in contending.iter().zip(&permutation) {
            order[slot] = effect;
        }
        let outcome = last_writes(&order, &effects);
        if !outcomes.contains(&outcome) {
            outcomes.push(outcome);
            orders.push(order.iter().map(|&k| due[k]).collect());
        }
        if !next_permutation(&mut permutation) {
            return orders;
        }
    }
}

/// The last write on each name when the effects are applied in `order`, sorted by name.
fn last_writes(order: &[usize], effects: &[Vec<(String, Write)>]) -> Vec<(String, Write)> {
    let mut last: Vec<(String, Write)> = Vec::new();
    for write in order.iter().flat_map(|&k| &effects[k]) {
        match last.iter_mut().find(|(name, _)| *name == write.0) {
            Some(slot) => *slot = write.clone(),
            None => last.push(write.clone()),
        }
    }
    last.sort_by(|a, b| a.0.cmp(&b.0));
    last
}

/// The next permutation in lexicographic order; false after the last.
fn next_permutation(items: &mut [usize]) -> bool {
    let Some(i) = (1..items.len()).rev().find(|&i| items[i - 1] < items[i]) else {
        return false;
    };
    let Some(j) = (i..items.len()).rev().find(|&j| items[j] > items[i - 1]) else {
        return false;
    };
    items.swap(i - 1, j);
    items[i..].reverse();
    true
}

#[cfg(test)]
mod tests {
    //! The orders of simultaneous deliveries that can matter.

    use super::*;
    use crate::simulation::testing::engine_camera;

    const RULES: &str = r#"initial: { "engine.temp": "low" },
        rules: [
            Rule(name: "a", on: Cycle(1), set: { "engine.temp": "nominal" }),
            Rule(name: "b", on: Cycle(1), set: { "engine.temp": "low" }),
            Rule(name: "c", on: Cycle(1), set: { "engine.temp": "nominal" }),
            Rule(name: "d", on: Cycle(1), set: { "camera.shutter": "open" }),
        ]"#;

    /// Contending effects are permuted, one order per outcome; the fired order comes first;
    /// effects on other names and identical writes do not branch.
    #[test]
    fn one_order_per_outcome() {
        let scenario = engine_camera(RULES);
        let script = &scenario.script;
        assert_eq!(distinct_orders(script, &[0, 3]), [vec![0, 3]]);
        assert_eq!(distinct_orders(script, &[0, 2]), [vec![0, 2]]);
        assert_eq!(distinct_orders(script, &[0, 1]), [vec![0, 1], vec![1, 0]]);
        // a, b, c on one name: the outcome is whoever writes last, `low` or `nominal`.
        assert_eq!(distinct_orders(script, &[0, 1, 2, 3]).len(), 2);
    }

    /// Complete and without repeats: every permutation of the due effects leaves the outcome
    /// of exactly one order returned, for every subset of the fixture's rules (each at most
    /// twice), checked exhaustively.
    #[test]
    fn every_outcome_once() {
        let scenario = engine_camera(RULES);
        let script = &scenario.script;
        let effects = |due: &[usize]| -> Vec<Vec<(String, Write)>> {
            (due.iter())
                .map(|&r| writes(script, &script.rules[r].effect))
                .collect()
        };
        for due in [vec![0, 1, 2, 3], vec![1, 0, 1], vec![3, 2, 1, 0, 0]] {
            let orders = distinct_orders(script, &due);
            let outcome = |order: &[usize]| {
                let positions: Vec<usize> = (0..order.len()).collect();
                last_writes(&positions, &effects(order))
            };
            let returned: Vec<_> = orders.iter().map(|o| outcome(o)).collect();
            for (i, a) in returned.iter().enumerate() {
                assert!(
                    !returned[i + 1..].contains(a),
                    "{due:?}: a repeated outcome"
                );
            }
            assert!(orders.iter().all(|o| is_permutation(o, &due)));
            assert_eq!(orders[0], due, "the fired order first");
            let mut permutation: Vec<usize> = (0..due.len()).collect();
            loop {
                let order: Vec<usize> = permutation.iter().map(|&k| due[k]).collect();
                assert!(returned.contains(&outcome(&order)), "{order:?} missed");
                if !next_permutation(&mut permutation) {
                    break;
                }
            }
        }
    }

    #[test]
    fn permutations_in_lexicographic_order() {
        let mut items = vec![0, 1, 2];
        let mut seen = vec![items.clone()];
        while next_permutation(&mut items) {
            seen.push(items.clone());
        }
        assert_eq!(seen.len(), 6);
        assert_eq!(seen[5], [2, 1, 0]);
    }
}
