//! Unit tests of [`super`] (`propagate.rs`).

use super::*;

fn lit(var: u32, positive: bool) -> SatLit {
    SatLit::new(var, positive)
}

/// A set-kept propagator given `clauses`.
fn kept_as_set_with(clauses: &[Vec<SatLit>]) -> Propagator {
    let mut propagator = Propagator::kept_as_set();
    for clause in clauses {
        propagator.add_clause(clause);
    }
    propagator
}

/// A fixed-seed xorshift: the same "random" clauses and questions on every run.
struct Xorshift(u64);

impl Xorshift {
    fn below(&mut self, n: u64) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0 % n
    }
}

/// The closure kept as a set (retracting what a dropped assumption derived) is the closure
/// from scratch: the same conflict or no conflict, and then the same value of every
/// variable — over a long run of overlapping assumption sets on random clauses, each
/// differing from the last by a few literals ("Two closures, kept apart").
#[test]
fn a_closure_kept_as_a_set_is_the_closure_from_scratch() {
    const VARS: u32 = 40;
    let mut rng = Xorshift(0x9e37_79b9_7f4a_7c15);
    let mut clauses = Vec::new();
    for _ in 0..70 {
        let len = 2 + rng.below(3) as usize;
        let clause: Vec<SatLit> = (0..len)
            .map(|_| lit(rng.below(VARS as u64) as u32, rng.below(2) == 0))
            .collect();
        clauses.push(clause);
    }
    let mut kept = kept_as_set_with(&clauses);
    let mut assumptions: Vec<SatLit> = Vec::new();
    let (mut conflicts, mut consistent) = (0, 0);
    for _ in 0..3000 {
        // Drop, add or flip a few assumptions; sometimes ask the same list again.
        for _ in 0..rng.below(4) {
            match rng.below(3) {
                0 if !assumptions.is_empty() => {
                    let at = rng.below(assumptions.len() as u64) as usize;
                    assumptions.remove(at);
                }
                1 if !assumptions.is_empty() => {
                    let at = rng.below(assumptions.len() as u64) as usize;
                    assumptions[at] = !assumptions[at];
                }
                _ if assumptions.len() < 12 => {
                    let at = rng.below(assumptions.len() as u64 + 1) as usize;
                    let var = rng.below(VARS as u64) as u32;
                    assumptions.insert(at, lit(var, rng.below(2) == 0));
                }
                _ => {}
            }
        }
        let mut fresh = Propagator::default();
        for clause in &clauses {
            fresh.add_clause(clause);
        }
        let expected = fresh.closure_of(&assumptions);
        assert_eq!(kept.closure_of(&assumptions), expected, "{assumptions:?}");
        if expected {
            consistent += 1;
            for var in 0..VARS {
                let x = lit(var, true);
                assert_eq!(
                    kept.value(x),
                    fresh.value(x),
                    "x{var} under {assumptions:?}"
                );
            }
            // An extension taken back leaves the closure as it was.
            let mark = kept.mark();
            kept.extend(lit(rng.below(VARS as u64) as u32, true));
            kept.undo(mark);
        } else {
            conflicts += 1;
        }
    }
    // Both kinds of answer were exercised.
    assert!(
        conflicts > 100 && consistent > 100,
        "{conflicts} / {consistent}"
    );
}

/// A random assignment of `vars` variables and `count` random clauses of two to four
/// literals that it satisfies (the assignment drawn first, then the clauses, from `rng`).
fn planted_clauses(rng: &mut Xorshift, vars: u32, count: usize) -> (Vec<bool>, Vec<Vec<SatLit>>) {
    let planted: Vec<bool> = (0..vars).map(|_| rng.below(2) == 0).collect();
    let mut clauses = Vec::new();
    while clauses.len() < count {
        let len = 2 + rng.below(3) as usize;
        let clause: Vec<SatLit> = (0..len)
            .map(|_| lit(rng.below(u64::from(vars)) as u32, rng.below(2) == 0))
            .collect();
        if clause
            .iter()
            .any(|l| planted[l.var() as usize] == l.is_positive())
        {
            clauses.push(clause);
        }
    }
    (planted, clauses)
}

/// A completion found by deciding is a model: the stored model afterwards satisfies every
/// clause and holds every literal of the closure, and the closure is as it was. Random
/// clauses satisfied by a planted assignment (the first stored model), random assumptions.
#[test]
fn a_completion_found_by_deciding_is_a_model_of_the_assumptions() {
    const VARS: u32 = 40;
    let mut rng = Xorshift(0x2545_f491_4f6c_dd1d);
    let (planted, clauses) = planted_clauses(&mut rng, VARS, 90);
    let mut p = kept_as_set_with(&clauses);
    p.set_model(planted);
    let mut completed = 0;
    for _ in 0..2000 {
        let assumptions: Vec<SatLit> = (0..1 + rng.below(4))
            .map(|_| lit(rng.below(VARS as u64) as u32, rng.below(2) == 0))
            .collect();
        if !p.closure_of(&assumptions) {
            continue;
        }
        let before: Vec<Value> = (0..VARS).map(|v| p.value(lit(v, true))).collect();
        if p.completes_by_deciding(16) {
            completed += 1;
            let model = p.model.clone().unwrap_or_default();
            let holds = |l: &SatLit| model[l.var() as usize] == l.is_positive();
            assert!(
                clauses.iter().all(|c| c.iter().any(holds)),
                "{assumptions:?}"
            );
            assert!(assumptions.iter().all(holds), "{assumptions:?}");
        }
        let after: Vec<Value> = (0..VARS).map(|v| p.value(lit(v, true))).collect();
        assert_eq!(before, after, "deciding leaves the closure as it was");
    }
    assert!(completed > 100, "{completed}");
}

/// The agreement kept between the stored model and the trail ("A model's agreement,
/// kept") changes no answer: a propagator that rescans the whole trail for every
/// completion (the oracle, its agreement forgotten before each question) gives the same
/// answers and ends with the same stored model, over a long run of prefix-kept and
/// set-kept closures, completions, decisions and fresh models on random clauses.
#[test]
fn the_agreement_kept_with_the_model_changes_no_completion() {
    const VARS: u32 = 40;
    let mut rng = Xorshift(0x5851_f42d_4c95_7f2d);
    let (planted, clauses) = planted_clauses(&mut rng, VARS, 80);
    for as_set in [false, true] {
        let build = || {
            let mut p = if as_set {
                Propagator::kept_as_set()
            } else {
                Propagator::default()
            };
            for clause in &clauses {
                p.add_clause(clause);
            }
            p.set_model(planted.clone());
            p
        };
        let (mut kept, mut oracle) = (build(), build());
        let mut assumptions: Vec<SatLit> = Vec::new();
        let (mut completed, mut skipped) = (0, 0);
        for round in 0..3000 {
            // Keep a prefix, then a few fresh assumptions (the search's pattern).
            let keep = rng.below(assumptions.len() as u64 + 1) as usize;
            assumptions.truncate(keep);
            for _ in 0..rng.below(4) {
                assumptions.push(lit(rng.below(VARS as u64) as u32, rng.below(2) == 0));
            }
            if round % 97 == 0 {
                // A fresh model, as the SAT solver's after a call.
                let model: Vec<bool> = (0..VARS).map(|_| rng.below(2) == 0).collect();
                if clauses
                    .iter()
                    .all(|c| c.iter().any(|l| model[l.var() as usize] == l.is_positive()))
                {
                    kept.set_model(model.clone());
                    oracle.set_model(model);
                }
            }
            let holds = kept.closure_of(&assumptions);
            assert_eq!(holds, oracle.closure_of(&assumptions), "{assumptions:?}");
            if !holds {
                continue;
            }
            oracle.agrees = 0;
            let (a, b) = if as_set && round % 2 == 0 {
                (
                    kept.completes_by_deciding(4),
                    oracle.completes_by_deciding(4),
                )
            } else {
                (kept.completes_to_model(), oracle.completes_to_model())
            };
            assert_eq!(a, b, "{assumptions:?}");
            assert_eq!(kept.model, oracle.model, "{assumptions:?}");
            if a {
                completed += 1;
            } else {
                skipped += 1;
            }
            assert!(kept.agrees <= kept.trail.len());
        }
        // Both answers were exercised.
        assert!(completed > 100 && skipped > 100, "{completed} / {skipped}");
    }
}

proptest::proptest! {
    #![proptest_config(crate::seeded::config(256))]

    /// "Binary implications in one array": after any interleaving of added binary
    /// clauses, new variables and rebuilds, a rebuilt [`Implications`] gives every literal
    /// code the literals its binary clauses force, in the order they were added — the
    /// per-code lists kept alongside, checked against a brute-force reading of the clauses
    /// — and a code past the arrays forces nothing.
    #[test]
    fn binary_implications_in_one_array_are_the_clauses(
        steps in proptest::collection::vec((0u32..24, 0u32..24, 0u8..4), 1..80),
    ) {
        let mut p = Propagator::default();
        let mut clauses: Vec<(SatLit, SatLit)> = Vec::new();
        for (x, y, kind) in steps {
            let (a, b) = (lit(x, kind & 1 == 0), lit(y, kind & 2 == 0));
            p.add_clause(&[a, b]);
            if x != y {
                clauses.push((a, b));
            }
            p.implications.compile(&p.implied);
            for code in 0..2 * 24 + 4 {
                let falsified = SatLit::new(code as u32 / 2, code % 2 == 0);
                // Brute force: (l ∨ m) forces m once l is false, in the order added
                // (a clause given twice forces twice).
                let expected: Vec<SatLit> = clauses
                    .iter()
                    .flat_map(|&(a, b)| [(a, b), (b, a)])
                    .filter(|&(l, _)| l == falsified)
                    .map(|(_, m)| m)
                    .collect();
                proptest::prop_assert_eq!(p.implications.of(falsified.code()), &expected[..]);
            }
        }
    }
}

#[test]
fn chains_of_binary_and_long_clauses_propagate() {
    let mut p = Propagator::default();
    let (a, b, c, d) = (lit(0, true), lit(1, true), lit(2, true), lit(3, true));
    p.add_clause(&[!a, b]); // a => b
    p.add_clause(&[!b, !c, d]); // b and c => d
    assert!(p.closure_of(&[a]));
    assert_eq!(p.value(b), Value::True);
    assert_eq!(p.value(d), Value::Unassigned);
    let mark = p.mark();
    assert!(p.extend(c));
    assert_eq!(p.value(d), Value::True);
    p.undo(mark);
    assert_eq!(p.value(d), Value::Unassigned);
    assert!(!p.extend(!d) || p.value(c) == Value::False);
    assert!(!p.closure_of(&[a, c, !d]));
}

#[test]
fn units_and_empty_clauses_hold_in_every_propagation() {
    let mut p = Propagator::default();
    let (a, b) = (lit(0, true), lit(1, true));
    p.add_clause(&[a]);
    p.add_clause(&[!a, b]);
    assert!(p.closure_of(&[]));
    assert_eq!(p.value(b), Value::True);
    assert!(!p.closure_of(&[!b]));
    p.add_clause(&[]);
    assert!(!p.closure_of(&[]));
}

#[test]
fn a_conflict_names_the_assumptions_it_was_derived_from() {
    // a => b, (b and c) => d, e => not d; e and f are unrelated to each other.
    let mut p = Propagator::default();
    let (a, b, c, d, e, f) = (
        lit(0, true),
        lit(1, true),
        lit(2, true),
        lit(3, true),
        lit(4, true),
        lit(5, true),
    );
    p.add_clause(&[!a, b]);
    p.add_clause(&[!b, !c, d]);
    p.add_clause(&[!e, !d]);
    // The conflict arises in a long clause's propagation: f plays no part.
    assert!(!p.closure_of(&[f, e, a, c]));
    let mut core = p.conflict_assumptions();
    core.sort_unstable();
    assert_eq!(core, vec![a, c, e]);
    // An assumption already false: it and what made it false.
    assert!(!p.closure_of(&[a, c, f, !d]));
    let mut core = p.conflict_assumptions();
    core.sort_unstable();
    assert_eq!(core, vec![a, c, !d]);
    // An extension after a closure does not disturb that closure's conflict.
    assert!(p.closure_of(&[a]));
    assert!(!p.extend(!b));
    assert!(!p.in_conflict());
    // A conflict among the units names no assumption.
    p.add_clause(&[f]);
    p.add_clause(&[!f]);
    assert!(!p.closure_of(&[a]));
    assert!(p.conflict_assumptions().is_empty());
}
