//! Property tests of the foundation against brute force (DESIGN.md §7, "correctness is checked
//! against brute-force enumeration on many random small OCSPs").

mod support;

#[path = "support/seeded.rs"]
mod seeded;
use kairos::logic::{Formula, ValueId, VarId};
use kairos::opsat::{
    Budget, ConflictStore, Consistency, Cut, Literal, Ocsp, SearchOptions, Solution, TheoryOptions,
};
use proptest::prelude::*;
use support::random_ocsp::{RandomOcsp, random_ocsp, random_ocsp_with_assumptions};

const TIE: f64 = 1e-9;

fn as_indices(solution: &Solution) -> Vec<usize> {
    solution.assignment.iter().map(|(_, v)| v.index()).collect()
}

/// `found` must be the first `found.len()` entries of `expected` up to the order within groups of
/// exactly tied costs: costs agree position by position, and each complete tie group holds the
/// same assignments.
fn assert_prefix_up_to_ties(found: &[Solution], expected: &[(Vec<usize>, f64)]) {
    assert!(found.len() <= expected.len(), "more solutions than exist");
    for (i, solution) in found.iter().enumerate() {
        assert!(
            (solution.cost - expected[i].1).abs() < TIE,
            "solution {i} costs {} but the {i}-th cheapest costs {}",
            solution.cost,
            expected[i].1
        );
        let tied: Vec<&Vec<usize>> = expected
            .iter()
            .filter(|(_, c)| (c - solution.cost).abs() < TIE)
            .map(|(a, _)| a)
            .collect();
        assert!(
            tied.contains(&&as_indices(solution)),
            "solution {i} {:?} is not a feasible assignment of that cost",
            as_indices(solution)
        );
    }
    let mut seen: Vec<Vec<usize>> = found.iter().map(as_indices).collect();
    seen.sort();
    seen.dedup();
    assert_eq!(seen.len(), found.len(), "an assignment was returned twice");
}

fn all_option_combinations() -> Vec<(TheoryOptions, SearchOptions)> {
    let mut out = Vec::new();
    for minimize_conflicts in [true, false] {
        for use_conflicts in [true, false] {
            for decompose in [true, false] {
                out.push((
                    TheoryOptions { minimize_conflicts },
                    SearchOptions {
                        use_conflicts,
                        decompose,
                        budget: Budget::default(),
                    },
                ));
            }
        }
    }
    out
}

fn random_literals(problem: &RandomOcsp, picks: &[(usize, usize, bool)]) -> Vec<Literal> {
    let domains = problem.domains();
    picks
        .iter()
        .map(|&(x, v, positive)| {
            let x = x % domains.len();
            let lit = Literal::Is(VarId(x as u32), ValueId((v % domains[x]) as u32));
            if positive { lit } else { !lit }
        })
        .collect()
}

/// Brute-force consistency of literals (over all variables) with the clauses.
fn brute_consistent(problem: &RandomOcsp, literals: &[Literal]) -> bool {
    let domains = problem.domains();
    let mut values = vec![0; domains.len()];
    loop {
        let holds = |l: &Literal| match *l {
            Literal::Is(x, v) => values[x.index()] == v.index(),
            Literal::IsNot(x, v) => values[x.index()] != v.index(),
            _ => unreachable!("only assignments are generated"),
        };
        if literals.iter().all(holds) && problem.satisfies(&values) {
            return true;
        }
        let mut i = 0;
        loop {
            if i == values.len() {
                return false;
            }
            values[i] += 1;
            if values[i] < domains[i] {
                break;
            }
            values[i] = 0;
            i += 1;
        }
    }
}

/// `ocsp` with each decision's choices narrowed to those `keep` marks (cycled over the
/// decisions' choices in order; a decision left with none keeps its cheapest), same
/// assumptions: another source's OCSP under the same observation, as TimedME asks.
fn narrowed(ocsp: &Ocsp, keep: &[bool]) -> Ocsp {
    let mut marks = keep.iter().cycle();
    let mut out = Ocsp::new();
    for (d, decision) in ocsp.decisions().iter().enumerate() {
        let mut kept: Vec<(ValueId, f64)> = (ocsp.choices(d).iter())
            .filter(|_| *marks.next().unwrap_or(&true))
            .map(|c| (c.value, c.cost))
            .collect();
        if kept.is_empty() {
            kept.extend(ocsp.choices(d).first().map(|c| (c.value, c.cost)));
        }
        out.decide(decision.var, kept).expect("distinct variables");
    }
    for &literal in ocsp.assumptions() {
        out.assume(literal);
    }
    out
}

proptest! {
    #![proptest_config(seeded::config(96))]

    /// Conflicts shared between searches under the same assumptions (src/opsat/shared.rs; issue
    /// 15 direction 2) change neither the solutions nor their order: several narrowed copies of
    /// one OCSP, enumerated in turns on one theory with one store, give exactly what each gives
    /// alone on a fresh theory — with conflicts, and without any (which tests candidates one by
    /// one: the canonical order of equal costs, src/opsat/search.rs "Order").
    #[test]
    fn shared_conflicts_change_no_solution_and_no_order(
        problem in random_ocsp_with_assumptions(7, 3, 10, 3),
        keeps in prop::collection::vec(prop::collection::vec(any::<bool>(), 1..12), 1..5),
    ) {
        let (_, base) = problem.build(TheoryOptions::default());
        let ocsps: Vec<Ocsp> = keeps.iter().map(|keep| narrowed(&base, keep)).collect();
        for decompose in [true, false] {
            let options = SearchOptions { decompose, ..SearchOptions::default() };
            let mut theory = problem.build(TheoryOptions::default()).0;
            let mut store = ConflictStore::default();
            store.assume(base.assumptions());
            let mut enumerations: Vec<_> =
                ocsps.iter().map(|ocsp| ocsp.enumerate(&theory, options)).collect();
            let mut shared: Vec<Vec<Solution>> = vec![Vec::new(); ocsps.len()];
            let mut running: Vec<bool> = vec![true; ocsps.len()];
            while running.contains(&true) {
                for (k, enumeration) in enumerations.iter_mut().enumerate() {
                    if !running[k] {
                        continue;
                    }
                    match enumeration.next_sharing(&mut theory, &mut store) {
                        Ok(Some(solution)) => shared[k].push(solution),
                        Ok(None) => running[k] = false,
                        Err(cut) => prop_assert!(false, "no budget, yet cut: {:?}", cut),
                    }
                }
            }
            for use_conflicts in [true, false] {
                for (ocsp, shared) in ocsps.iter().zip(&shared) {
                    let mut fresh = problem.build(TheoryOptions::default()).0;
                    let alone = SearchOptions { use_conflicts, ..options };
                    let found = ocsp.best_with(&mut fresh, usize::MAX, alone);
                    prop_assert_eq!(&found.solutions, shared, "decompose {}", decompose);
                }
            }
        }
    }

    /// best(all) equals brute-force enumeration, for every backend and search variant:
    /// decomposed and undecomposed, with and without conflicts, agree.
    #[test]
    fn best_all_equals_brute_force(problem in random_ocsp(8, 3, 10)) {
        let expected = problem.brute_force();
        for (theory_options, search_options) in all_option_combinations() {
            let (mut theory, ocsp) = problem.build(theory_options);
            let found = ocsp.best_with(&mut theory, usize::MAX, search_options);
            prop_assert!(found.cut.is_none());
            prop_assert_eq!(found.solutions.len(), expected.len(),
                "{:?} {:?}", theory_options, search_options);
            assert_prefix_up_to_ties(&found.solutions, &expected);
        }
    }

    /// Negative costs (goal interpretation's −reward) too: the search then sums every child's
    /// cost when it creates it rather than queueing it at a partial sum, which bounds it from
    /// below only when no cost is negative (src/opsat/search.rs, "Order").
    #[test]
    fn negative_costs_equal_brute_force(problem in random_ocsp(8, 3, 10)) {
        let mut problem = problem;
        for costs in &mut problem.decision_costs {
            for cost in costs.iter_mut() {
                *cost -= 3.0;
            }
        }
        let expected = problem.brute_force();
        let (mut theory, ocsp) = problem.build(TheoryOptions::default());
        let found = ocsp.best_with(&mut theory, usize::MAX, SearchOptions::default());
        prop_assert_eq!(found.solutions.len(), expected.len());
        assert_prefix_up_to_ties(&found.solutions, &expected);
    }

    /// Per-problem assumptions — on decision variables too — restrict the solutions exactly as
    /// the same literals would as constraints.
    #[test]
    fn assumptions_restrict_the_solutions(problem in random_ocsp_with_assumptions(6, 2, 8, 3)) {
        let expected = problem.brute_force();
        for decompose in [true, false] {
            let (mut theory, ocsp) = problem.build(TheoryOptions::default());
            let options = SearchOptions { decompose, ..SearchOptions::default() };
            let found = ocsp.best_with(&mut theory, usize::MAX, options);
            prop_assert_eq!(found.solutions.len(), expected.len());
            assert_prefix_up_to_ties(&found.solutions, &expected);
        }
    }

    /// best(k) is the k-prefix of the full order (up to ties), for any k.
    #[test]
    fn best_k_is_a_prefix(problem in random_ocsp(8, 2, 10), k in 0usize..20) {
        let expected = problem.brute_force();
        let (mut theory, ocsp) = problem.build(TheoryOptions::default());
        let found = ocsp.best(&mut theory, k);
        prop_assert_eq!(found.solutions.len(), k.min(expected.len()));
        assert_prefix_up_to_ties(&found.solutions, &expected);
    }

    /// A budget cuts the search but what it returns is still a best-first prefix.
    #[test]
    fn a_cut_search_returns_the_best_so_far(problem in random_ocsp(8, 2, 10), nodes in 1u64..30) {
        let expected = problem.brute_force();
        let (mut theory, ocsp) = problem.build(TheoryOptions::default());
        let options = SearchOptions {
            budget: Budget { max_nodes: Some(nodes), ..Budget::default() },
            ..SearchOptions::default()
        };
        let found = ocsp.best_with(&mut theory, usize::MAX, options);
        assert_prefix_up_to_ties(&found.solutions, &expected);
        if found.cut.is_none() {
            prop_assert_eq!(found.solutions.len(), expected.len());
        }
        prop_assert!(found.stats.nodes <= nodes);
    }

    /// A deadline shared by calls (`Budget::until`): one that has passed stops a search before
    /// its first node, and says so; one far ahead changes nothing (the answer is brute force's).
    #[test]
    fn a_passed_deadline_stops_the_search_and_a_far_one_does_not(problem in random_ocsp(8, 2, 10)) {
        let expected = problem.brute_force();
        let now = std::time::Instant::now();
        for (until, cut) in [(now, Some(Cut::Time)), (now + std::time::Duration::from_secs(3600), None)] {
            let (mut theory, ocsp) = problem.build(TheoryOptions::default());
            let options = SearchOptions {
                budget: Budget { until: Some(until), ..Budget::default() },
                ..SearchOptions::default()
            };
            let found = ocsp.best_with(&mut theory, usize::MAX, options);
            if cut.is_some() {
                prop_assert_eq!(found.stats.nodes, 0);
                prop_assert!(found.solutions.is_empty());
            }
            // A search that needs no node (no solution: the problem is refuted before its
            // first) ends uncut even past the deadline; every other is cut.
            if found.cut.is_none() {
                assert_prefix_up_to_ties(&found.solutions, &expected);
                prop_assert_eq!(found.solutions.len(), expected.len());
            }
            prop_assert!(found.cut == cut || expected.is_empty(), "{:?} {}", found.cut, expected.len());
        }
    }

    /// consistent() agrees with brute force, and every conflict it returns is a subset of the
    /// assumptions that is itself inconsistent.
    #[test]
    fn conflicts_are_inconsistent_subsets(
        problem in random_ocsp(6, 3, 12),
        picks in prop::collection::vec((0usize..16, 0usize..4, prop::bool::weighted(0.7)), 0..8),
        minimize in any::<bool>(),
    ) {
        let literals = random_literals(&problem, &picks);
        let options = TheoryOptions { minimize_conflicts: minimize };
        let (mut theory, _) = problem.build(options);
        match theory.consistent(&literals) {
            Consistency::Consistent => prop_assert!(brute_consistent(&problem, &literals)),
            Consistency::Conflict(conflict) => {
                prop_assert!(!brute_consistent(&problem, &literals));
                prop_assert!(conflict.iter().all(|l| literals.contains(l)));
                prop_assert!(!brute_consistent(&problem, &conflict));
                if minimize {
                    for i in 0..conflict.len() {
                        let mut smaller = conflict.clone();
                        smaller.remove(i);
                        prop_assert!(brute_consistent(&problem, &smaller), "not minimal");
                    }
                }
            }
        }
    }

    /// entails(A, f) holds exactly when A and not f are inconsistent, by brute force.
    #[test]
    fn entailment_is_refutation_of_the_negation(
        problem in random_ocsp(5, 2, 8),
        picks in prop::collection::vec((0usize..16, 0usize..4, prop::bool::weighted(0.8)), 0..5),
        goal in prop::collection::vec((0usize..16, 0usize..4, any::<bool>()), 1..4),
    ) {
        let assumptions = random_literals(&problem, &picks);
        let goal_literals = random_literals(&problem, &goal);
        let formula = Formula::Or(goal_literals.iter().map(|l| match *l {
            Literal::Is(x, v) => Formula::is(x, v),
            Literal::IsNot(x, v) => Formula::is(x, v).negate(),
            _ => unreachable!(),
        }).collect());
        let (mut theory, _) = problem.build(TheoryOptions::default());
        let entailed = theory.entails(&assumptions, &formula).unwrap();
        // A and not f: every goal literal negated.
        let mut counter = assumptions.clone();
        counter.extend(goal_literals.iter().map(|&l| !l));
        prop_assert_eq!(entailed, !brute_consistent(&problem, &counter));
    }
}
