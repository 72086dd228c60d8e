//! State constraints on one state variable and their algebra (mds-goal-networks.md §1.4; seed
//! 000 AG §3.4 `mergeFrom`/`mergeWith`/`isSubset`).
//!
//! A constraint set has two independent parts:
//! - the **control** part, the set of the SV's values it admits (written in the constraint
//!   language: `switch1 = closed or switch1 = stuck-closed`, `temperature != cold`);
//! - the **knowledge** part, how well the value must be known: `known` (the most likely value's
//!   probability reaches the mission's knowledge threshold) and, per value, a least belief
//!   (`P(sensor = healthy) >= 0.9`).
//!
//! Merging intersects the control sets and keeps the stronger knowledge requirement, part by
//! part (`known` if either is, the larger least belief per value). Each part is a lattice, so
//! merge is commutative, associative and idempotent, `Unconstrained` (every value, no knowledge)
//! is its identity, and `a ⊆ b ⇔ merge(a, b) = a` (the laws the seed's unit tests check "in all
//! the combinations", AG §12.2.4.1; `tests/goalnet_properties.rs`).
//!
//! Knowledge is kept as a product of two parts rather than mds-goal-networks.md's chain
//! `None < Known < Confidence(p)` because `Known` (about the most likely value, at the mission's
//! threshold) and `P(x = v) ≥ p` (about one value) are incomparable: neither implies the other,
//! and a chain would make merge depend on the threshold.

use crate::logic::ValueId;

/// A constraint on the values of one state variable (a component's mode variable).
#[derive(Debug, Clone, PartialEq)]
pub struct ConstraintSet {
    /// Per value of the SV's domain, whether the control part admits it.
    admitted: Vec<bool>,
    /// The estimate must be known (P of the most likely value ≥ the knowledge threshold).
    known: bool,
    /// Per value, the least belief required in it (0 = no requirement).
    least_belief: Vec<f64>,
}

impl ConstraintSet {
    /// Every value, no knowledge requirement: the identity of merge.
    pub fn unconstrained(domain: usize) -> Self {
        ConstraintSet {
            admitted: vec![true; domain],
            known: false,
            least_belief: vec![0.0; domain],
        }
    }

    /// A control constraint admitting exactly the values for which `admit` holds.
    pub fn control(domain: usize, admit: impl Fn(ValueId) -> bool) -> Self {
        let mut set = Self::unconstrained(domain);
        for (i, slot) in set.admitted.iter_mut().enumerate() {
            *slot = admit(ValueId(i as u32));
        }
        set
    }

    /// Adds the requirement that the estimate be known.
    pub fn with_known(mut self) -> Self {
        self.known = true;
        self
    }

    /// Adds the requirement `P(x = value) ≥ probability` (the stronger of it and any already
    /// there).
    pub fn with_belief(mut self, value: ValueId, probability: f64) -> Self {
        if let Some(slot) = self.least_belief.get_mut(value.index()) {
            *slot = slot.max(probability);
        }
        self
    }

    /// The size of the SV's domain.
    pub fn domain(&self) -> usize {
        self.admitted.len()
    }

    /// Whether the control part admits `value`.
    pub fn admits(&self, value: ValueId) -> bool {
        self.admitted.get(value.index()).copied().unwrap_or(false)
    }

    /// The admitted values, in domain order.
    pub fn admitted(&self) -> impl Iterator<Item = ValueId> + '_ {
        self.admitted
            .iter()
            .enumerate()
            .filter(|(_, a)| **a)
            .map(|(i, _)| ValueId(i as u32))
    }

    /// Whether the control part admits every value (no control requirement).
    pub fn is_control_free(&self) -> bool {
        self.admitted.iter().all(|a| *a)
    }

    /// Whether the estimate must be known.
    pub fn requires_known(&self) -> bool {
        self.known
    }

    /// The least beliefs required, `(value, p)` with `p > 0`.
    pub fn least_beliefs(&self) -> impl Iterator<Item = (ValueId, f64)> + '_ {
        self.least_belief
            .iter()
            .enumerate()
            .filter(|(_, p)| **p > 0.0)
            .map(|(i, p)| (ValueId(i as u32), *p))
    }

    /// Whether it asks for any knowledge.
    pub fn has_knowledge(&self) -> bool {
        self.known || self.least_belief.iter().any(|p| *p > 0.0)
    }

    /// Whether it constrains nothing (the identity of merge).
    pub fn is_unconstrained(&self) -> bool {
        self.is_control_free() && !self.has_knowledge()
    }

    /// No value satisfies the control part: goals merged into this cannot hold together.
    pub fn is_empty(&self) -> bool {
        !self.admitted.iter().any(|a| *a)
    }

    /// The merge (AG `mergeWith`): the intersection of the control sets and the stronger
    /// knowledge requirement. Both sets must be over the same SV.
    pub fn merge(&self, other: &ConstraintSet) -> ConstraintSet {
        debug_assert_eq!(
            self.domain(),
            other.domain(),
            "merge across state variables"
        );
        ConstraintSet {
            admitted: zip(&self.admitted, &other.admitted, |a, b| a && b),
            known: self.known || other.known,
            least_belief: zip(&self.least_belief, &other.least_belief, f64::max),
        }
    }

    /// `self ⊆ other` (AG `isSubset`): every value `self` admits `other` admits, and `self` asks
    /// for at least the knowledge `other` asks for.
    pub fn is_subset(&self, other: &ConstraintSet) -> bool {
        self.admitted
            .iter()
            .zip(&other.admitted)
            .all(|(a, b)| !a || *b)
            && (self.known || !other.known)
            && self
                .least_belief
                .iter()
                .zip(&other.least_belief)
                .all(|(a, b)| a >= b)
    }

    /// Whether a value with the given belief in it satisfies the set: admitted by the control
    /// part, and the knowledge part met by `belief` (the estimate's distribution over the SV's
    /// values) and `threshold` (the mission's knowledge threshold).
    pub fn satisfied_by(&self, value: ValueId, belief: &[f64], threshold: f64) -> bool {
        self.admits(value) && self.knowledge_met(belief, threshold)
    }

    /// Whether the knowledge part holds for this belief over the SV's values.
    pub fn knowledge_met(&self, belief: &[f64], threshold: f64) -> bool {
        let most_likely = belief.iter().copied().fold(0.0, f64::max);
        (!self.known || most_likely >= threshold)
            && self
                .least_belief
                .iter()
                .enumerate()
                .all(|(i, p)| belief.get(i).copied().unwrap_or(0.0) >= *p)
    }
}

fn zip<T: Copy>(a: &[T], b: &[T], f: impl Fn(T, T) -> T) -> Vec<T> {
    a.iter().zip(b).map(|(x, y)| f(*x, *y)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_intersects_control_and_keeps_the_stronger_knowledge() {
        let closed = ConstraintSet::control(4, |v| v.0 == 1 || v.0 == 3);
        let known = ConstraintSet::unconstrained(4)
            .with_known()
            .with_belief(ValueId(1), 0.9);
        let merged = closed.merge(&known);
        assert_eq!(
            merged.admitted().collect::<Vec<_>>(),
            [ValueId(1), ValueId(3)]
        );
        assert!(merged.requires_known());
        assert_eq!(
            merged.least_beliefs().collect::<Vec<_>>(),
            [(ValueId(1), 0.9)]
        );
        assert!(merged.is_subset(&closed) && merged.is_subset(&known));
        let open = ConstraintSet::control(4, |v| v.0 == 0);
        assert!(closed.merge(&open).is_empty());
    }

    #[test]
    fn knowledge_is_judged_on_the_belief() {
        let set = ConstraintSet::unconstrained(2).with_known();
        assert!(set.satisfied_by(ValueId(0), &[0.95, 0.05], 0.9));
        assert!(!set.satisfied_by(ValueId(0), &[0.6, 0.4], 0.9));
        let belief = ConstraintSet::unconstrained(2).with_belief(ValueId(1), 0.5);
        assert!(!belief.knowledge_met(&[0.6, 0.4], 0.9));
        assert!(belief.knowledge_met(&[0.4, 0.6], 0.9));
    }
}
