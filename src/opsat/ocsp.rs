//! Optimal constraint satisfaction problems and their answers (thesis §6.2.3).

use std::time::{Duration, Instant};

use super::theory::Literal;
use crate::logic::{ValueId, VarId, VarTable};

/// One value a decision variable may take, and what choosing it costs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choice {
    /// The value.
    pub value: ValueId,
    /// Its cost: −log p for estimation, −reward for goal interpretation.
    pub cost: f64,
}

/// A decision variable: a theory variable; the values OPSAT may choose for it are
/// [`Ocsp::choices`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Decision {
    /// The theory variable.
    pub var: VarId,
    /// Where its choices lie in the OCSP's list of all choices.
    start: u32,
    end: u32,
}

/// Why an OCSP could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OcspError {
    /// Each variable is decided once.
    #[error("variable {0:?} is already a decision variable")]
    DuplicateDecision(VarId),
    /// Costs are added up and ordered; NaN has no place in either.
    #[error("a cost is not a number")]
    NanCost,
}

/// An OCSP ⟨x, f, C⟩: decision variables `x` with an additive cost per value (mutually
/// preferentially independent), constraints `C` given by a [`super::Theory`] plus per-problem
/// assumptions. Solutions are full assignments of the decision variables consistent with `C`,
/// cheapest first. Variables of the theory that are not decisions are free (existentially
/// quantified).
///
/// Each variable is decided once, and [`Ocsp::decide`] refuses a second decision on it. It
/// used to find one by scanning the decisions made so far: estimation builds an OCSP over every
/// component's next mode for each source state it expands, so on Livingstone 2's 255-breaker
/// tree (383 components) that was 73 k comparisons per source, 4.9 % of a replay's CPU at κ = 10
/// and quadratic in the plant. The decided variables are kept as a bit set by variable index
/// instead: one test per decision, the same decisions in the same order. Measured: CPU at 255
/// breakers, κ = 10, 0.945 of before (`farm-bench --vs`, 5 pairs, median, load 2–3); on the
/// 15-breaker log 6.936 G → 6.935 G instructions (CPU 1.02, 0.94–1.15, 7 pairs: noise); beliefs
/// and SAT calls byte-identical.
///
/// # All choices in one list
/// The decisions' choices are kept one decision after another in one list, each decision
/// naming its stretch of it ([`Ocsp::choices`]), rather than a list per decision: on
/// Livingstone 2's 255-breaker tree at κ = 10 the per-decision lists were 1.55 M allocations
/// (383 per source OCSP, 4,053 OCSPs), the largest source of allocations in the replay, and
/// freeing them fragmented the allocator's free lists. A decision's choices are filtered and
/// sorted in place at the list's end by the same stable sort with the same comparison, so every
/// decision has the very choices in the very order it had: searches, beliefs and SAT calls are
/// unchanged. The search reads a member's choice through the stretch it keeps per member
/// (`search.rs`): read through [`Ocsp::choices`] (a slice made per read, in the innermost loop
/// that sums a node's cost) the same replay took 8 % more instructions than before, not fewer.
/// Measured (callgrind, whole process, κ = 10): the 255-breaker log 27.51 G → 26.35 G
/// instructions, CPU 0.983 of before (0.967–0.995, `farm-bench --vs`, 5 pairs, load ≈ 3); the
/// 15-breaker log 6.726 G → 6.710 G, CPU 0.980 (0.92–1.00, 7 pairs).
#[derive(Debug, Clone, Default)]
pub struct Ocsp {
    decisions: Vec<Decision>,
    /// Every decision's choices, one decision after another (see [`Decision`]).
    choices: Vec<Choice>,
    assumptions: Vec<Literal>,
    /// Bit `v` set: variable `VarId(v)` is a decision.
    decided: Vec<u64>,
}

impl PartialEq for Ocsp {
    /// Equal decisions with equal choices, and equal assumptions (`decided` is a function of
    /// the decisions; the stretches are laid out in decision order, so equal stretches and
    /// equal lists mean equal choices per decision).
    fn eq(&self, other: &Self) -> bool {
        self.decisions == other.decisions
            && self.choices == other.choices
            && self.assumptions == other.assumptions
    }
}

impl Ocsp {
    /// An OCSP with no decision variables and no assumptions.
    pub fn new() -> Self {
        Ocsp::default()
    }

    /// An empty OCSP with room for `decisions` decision variables without reallocating.
    pub fn with_capacity(decisions: usize) -> Self {
        Ocsp {
            decisions: Vec::with_capacity(decisions),
            ..Ocsp::default()
        }
    }

    /// Makes `var` a decision variable with these values and costs. A value with an infinite
    /// cost (probability zero) is left out.
    pub fn decide(
        &mut self,
        var: VarId,
        choices: impl IntoIterator<Item = (ValueId, f64)>,
    ) -> Result<&mut Self, OcspError> {
        let (word, bit) = (var.0 as usize / 64, 1u64 << (var.0 % 64));
        if self.decided.get(word).is_some_and(|w| w & bit != 0) {
            return Err(OcspError::DuplicateDecision(var));
        }
        let start = self.choices.len();
        self.choices.extend(
            choices
                .into_iter()
                .filter(|&(_, cost)| cost != f64::INFINITY)
                .map(|(value, cost)| Choice { value, cost }),
        );
        if self.choices[start..].iter().any(|c| c.cost.is_nan()) {
            self.choices.truncate(start);
            return Err(OcspError::NanCost);
        }
        self.choices[start..].sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.value.cmp(&b.value)));
        if self.decided.len() <= word {
            self.decided.resize(word + 1, 0);
        }
        self.decided[word] |= bit;
        let span = |at: usize| u32::try_from(at).expect("fewer than 2³² choices in an OCSP");
        self.decisions.push(Decision {
            var,
            start: span(start),
            end: span(self.choices.len()),
        });
        Ok(self)
    }

    /// Adds a literal every solution must be consistent with (an observation, a goal).
    pub fn assume(&mut self, literal: Literal) -> &mut Self {
        self.assumptions.push(literal);
        self
    }

    /// The decision variables, in the order they were declared.
    pub fn decisions(&self) -> &[Decision] {
        &self.decisions
    }

    /// The allowed values of the `d`-th decision variable, cheapest first (ties in value
    /// order). Panics if there is no such decision.
    pub fn choices(&self, d: usize) -> &[Choice] {
        let decision = self.decisions[d];
        &self.choices[decision.start as usize..decision.end as usize]
    }

    /// Where the `d`-th decision's choices lie in [`Ocsp::all_choices`]: (first, count).
    /// Panics if there is no such decision.
    pub(crate) fn stretch(&self, d: usize) -> (u32, u32) {
        let decision = &self.decisions[d];
        (decision.start, decision.end - decision.start)
    }

    /// Every decision's choices, one decision after another ([`Ocsp::stretch`] says where).
    pub(crate) fn all_choices(&self) -> &[Choice] {
        &self.choices
    }

    /// The per-problem assumptions.
    pub fn assumptions(&self) -> &[Literal] {
        &self.assumptions
    }
}

/// A feasible full assignment of the decision variables.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// One value per decision variable, in declaration order.
    pub assignment: Vec<(VarId, ValueId)>,
    /// The summed cost.
    pub cost: f64,
}

impl Solution {
    /// `x = v, y = w, ...` with names.
    pub fn describe(&self, table: &VarTable) -> String {
        self.assignment
            .iter()
            .map(|&(x, v)| table.assignment(x, v).to_string())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The literals stating this assignment.
    pub fn literals(&self) -> Vec<Literal> {
        self.assignment
            .iter()
            .map(|&(x, v)| Literal::Is(x, v))
            .collect()
    }
}

/// Limits on one call; when one is reached the call returns what it has found.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Budget {
    /// At most this many search nodes (candidates examined).
    pub max_nodes: Option<u64>,
    /// At most this much time.
    pub max_time: Option<Duration>,
    /// Until this instant: a deadline several calls share (the executive gives every search of
    /// a cycle's mode estimation the same one). Reported as [`Cut::Time`].
    pub until: Option<Instant>,
}

/// Which limit stopped a search early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// [`Budget::max_nodes`] was reached.
    Nodes,
    /// [`Budget::max_time`] was reached, or [`Budget::until`] passed.
    Time,
}

/// How OPSAT searches. The defaults are conflict-directed A* with decomposition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SearchOptions {
    /// Learn conflicts from inconsistent candidates and jump over every candidate containing
    /// them. Off, the search tests candidates one by one in best-first order (the baseline the
    /// benchmarks compare against).
    pub use_conflicts: bool,
    /// Solve independent sub-problems separately and merge their solution streams.
    pub decompose: bool,
    /// Limits for the call.
    pub budget: Budget,
}

impl Default for SearchOptions {
    fn default() -> Self {
        SearchOptions {
            use_conflicts: true,
            decompose: true,
            budget: Budget::default(),
        }
    }
}

/// Work done by one call.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SearchStats {
    /// Search nodes popped from the frontier.
    pub nodes: u64,
    /// Candidates tested against the theory.
    pub consistency_checks: u64,
    /// Conflicts learned.
    pub conflicts: u64,
    /// Independent sub-problems the OCSP split into.
    pub components: u64,
}

/// The answer to [`Ocsp::best`](super::Ocsp::best): solutions, cheapest first.
#[derive(Debug, Clone, PartialEq)]
pub struct Solutions {
    /// The solutions found, in non-decreasing cost, each assignment once.
    pub solutions: Vec<Solution>,
    /// Set when a budget stopped the search before `k` solutions were found or the space was
    /// exhausted; the solutions are then the best found so far, still in order.
    pub cut: Option<Cut>,
    /// Work done.
    pub stats: SearchStats,
}

/// Counts nodes and watches the clock for one call.
#[derive(Debug)]
pub(crate) struct Meter {
    budget: Budget,
    started: Instant,
    pub(crate) stats: SearchStats,
}

impl Meter {
    pub(crate) fn new(budget: Budget) -> Self {
        Meter {
            budget,
            started: Instant::now(),
            stats: SearchStats::default(),
        }
    }

    /// Charges one node; says which limit is exceeded, if any.
    pub(crate) fn charge_node(&mut self) -> Result<(), Cut> {
        if self
            .budget
            .max_nodes
            .is_some_and(|max| self.stats.nodes >= max)
        {
            return Err(Cut::Nodes);
        }
        if self
            .budget
            .max_time
            .is_some_and(|max| self.started.elapsed() >= max)
            || self.budget.until.is_some_and(|t| Instant::now() >= t)
        {
            return Err(Cut::Time);
        }
        self.stats.nodes += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each variable is decided once: a second decision is refused whatever the variables in
    /// between (across the bit set's words too), and one refused for a NaN cost leaves the
    /// variable undecided. Checked against the decisions' own list.
    #[test]
    fn a_variable_is_decided_once() {
        let mut ocsp = Ocsp::new();
        let mut plain: Vec<VarId> = Vec::new();
        // A fixed walk over 0..200 that revisits every variable once.
        for i in 0..400u32 {
            let var = VarId(i * 37 % 200);
            let twice = plain.contains(&var);
            let answer = ocsp.decide(var, [(ValueId(0), 1.0)]).map(|_| ());
            assert_eq!(answer.is_err(), twice, "{var:?}");
            if twice {
                assert_eq!(answer, Err(OcspError::DuplicateDecision(var)));
            } else {
                plain.push(var);
            }
        }
        let vars: Vec<VarId> = ocsp.decisions().iter().map(|d| d.var).collect();
        assert_eq!(vars, plain, "the same decisions in the same order");
        let fresh = VarId(1_000);
        let nan = ocsp.decide(fresh, [(ValueId(0), f64::NAN)]).map(|_| ());
        assert_eq!(nan, Err(OcspError::NanCost));
        assert!(ocsp.decide(fresh, [(ValueId(0), 0.5)]).is_ok());
    }

    proptest::proptest! {
        #![proptest_config(crate::seeded::config(256))]

        /// "All choices in one list": every decision's stretch holds exactly the choices a list
        /// of its own would — infinite costs left out, sorted by cost then value by the same
        /// stable sort — whatever the decisions before it; a decision refused for a NaN cost
        /// leaves the list as it was; [`Ocsp::stretch`] and [`Ocsp::all_choices`] give the
        /// same stretch. Checked against a plain list built per decision.
        #[test]
        fn each_decisions_stretch_is_its_own_sorted_list(
            decisions in proptest::collection::vec(
                proptest::collection::vec((0u32..6, 0u8..8), 0..6),
                1..12,
            ),
        ) {
            // Few distinct costs, so ties in cost (broken by value) and repeated values occur.
            let cost = |k: u8| match k {
                0 => f64::INFINITY,
                1 => f64::NAN,
                2 => 0.0,
                k => f64::from(k % 3) * 0.5,
            };
            let mut ocsp = Ocsp::new();
            let mut plain: Vec<Vec<Choice>> = Vec::new();
            for (i, values) in decisions.iter().enumerate() {
                let given: Vec<(ValueId, f64)> =
                    values.iter().map(|&(v, k)| (ValueId(v), cost(k))).collect();
                let before = ocsp.clone();
                let answer = ocsp.decide(VarId(i as u32), given.clone()).map(|_| ());
                if given.iter().any(|(_, c)| c.is_nan()) {
                    proptest::prop_assert_eq!(answer, Err(OcspError::NanCost));
                    proptest::prop_assert_eq!(&ocsp, &before);
                    proptest::prop_assert_eq!(ocsp.all_choices().len(), before.all_choices().len());
                    continue;
                }
                proptest::prop_assert!(answer.is_ok());
                let mut own: Vec<Choice> = given
                    .iter()
                    .map(|&(value, cost)| Choice { value, cost })
                    .collect();
                own.retain(|c| c.cost != f64::INFINITY);
                own.sort_by(|a, b| a.cost.total_cmp(&b.cost).then(a.value.cmp(&b.value)));
                plain.push(own);
            }
            proptest::prop_assert_eq!(ocsp.decisions().len(), plain.len());
            for (d, own) in plain.iter().enumerate() {
                proptest::prop_assert_eq!(ocsp.choices(d), &own[..]);
                let (first, count) = ocsp.stretch(d);
                let stretch = &ocsp.all_choices()[first as usize..(first + count) as usize];
                proptest::prop_assert_eq!(stretch, &own[..]);
            }
        }
    }
}
