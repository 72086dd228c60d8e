//! Unit tests of [`super`] (`theory.rs`).

use super::*;
use crate::logic::parse_formula;

/// Table 6.1's driver in miniature: a driver relays `on` only when it is on.
fn driver() -> Theory {
    let mut table = VarTable::new();
    table
        .add_variable("driver", ["off", "on", "failed"])
        .unwrap();
    table
        .add_variable("driver.cmd_out", ["none", "on"])
        .unwrap();
    table.add_variable("valve.cmd_in", ["none", "on"]).unwrap();
    table.add_variable("valve", ["closed", "open"]).unwrap();
    let constraints = [
        "driver = off => driver.cmd_out = none",
        "driver = on => driver.cmd_out = on",
        "driver.cmd_out = valve.cmd_in",
        "valve = open => valve.cmd_in = on",
    ]
    .map(|c| parse_formula(c, &table).unwrap());
    Theory::new(table, &constraints).unwrap()
}

fn is(theory: &Theory, var: &str, value: &str) -> Literal {
    let table = theory.table();
    let x = table.variable_id(var).unwrap();
    Literal::Is(x, table.variable(x).value(value).unwrap())
}

fn formula(theory: &Theory, text: &str) -> Formula {
    parse_formula(text, theory.table()).unwrap()
}

#[test]
fn conflicts_are_subsets_of_the_assumptions_and_inconsistent() {
    let mut theory = driver();
    let assumptions = [
        is(&theory, "valve", "open"),
        is(&theory, "driver", "off"),
        is(&theory, "valve.cmd_in", "on"),
    ];
    let Consistency::Conflict(conflict) = theory.consistent(&assumptions) else {
        panic!("an open valve needs an `on` command, which an off driver never relays");
    };
    assert!(conflict.iter().all(|l| assumptions.contains(l)));
    assert!(matches!(
        theory.consistent(&conflict),
        Consistency::Conflict(_)
    ));
    // Minimal on request: driver = off together with either of the others already conflicts.
    let Consistency::Conflict(minimal) = theory.minimal_conflict(&assumptions) else {
        panic!("the same assumptions are still inconsistent");
    };
    assert_eq!(minimal.len(), 2, "{minimal:?}");
    assert!(minimal.contains(&is(&theory, "driver", "off")));
}

/// The product encoding (domains above `PAIRWISE_AT_MOST_ONE`) keeps "exactly one value":
/// every value alone is consistent, no two together, and some value always holds.
#[test]
fn large_domains_hold_exactly_one_value() {
    let mut table = VarTable::new();
    let values: Vec<String> = (0..3 * PAIRWISE_AT_MOST_ONE)
        .map(|v| format!("v{v}"))
        .collect();
    let x = table.add_variable("x", values.clone()).unwrap();
    let mut theory = Theory::new(table, &[]).unwrap();
    let n = values.len() as u32;
    for a in 0..n {
        assert!(
            theory
                .consistent(&[Literal::Is(x, ValueId(a))])
                .is_consistent()
        );
        for b in a + 1..n {
            let both = [Literal::Is(x, ValueId(a)), Literal::Is(x, ValueId(b))];
            assert!(!theory.consistent(&both).is_consistent(), "{a} and {b}");
        }
    }
    let none: Vec<Literal> = (0..n).map(|v| Literal::IsNot(x, ValueId(v))).collect();
    assert!(!theory.consistent(&none).is_consistent());
    let all_but_one = &none[1..];
    assert!(theory.consistent(all_but_one).is_consistent());
}

/// A variable left unencoded is outside the solver until first mentioned, then a variable
/// like any other: the answers are those of the theory that encoded it from the start.
#[test]
fn an_unencoded_variable_is_encoded_when_first_mentioned() {
    let encoded = driver();
    let mut table = encoded.table().clone();
    let ack = table
        .add_variable("driver.ack", ["none", "accepted", "rejected"])
        .unwrap();
    let constraints: Vec<Formula> = [
        "driver = off => driver.cmd_out = none",
        "driver = on => driver.cmd_out = on",
        "driver.cmd_out = valve.cmd_in",
        "valve = open => valve.cmd_in = on",
    ]
    .iter()
    .map(|c| parse_formula(c, &table).unwrap())
    .collect();
    let mut full = Theory::new(table.clone(), &constraints).unwrap();
    let mut lazy =
        Theory::with_unencoded(table, &constraints, TheoryOptions::default(), &[ack]).unwrap();
    assert!(lazy.value_lits[ack.index()].is_empty());
    let open = is(&lazy, "valve", "open");
    let off = is(&lazy, "driver", "off");
    let on = formula(&lazy, "valve.cmd_in = on");
    for theory in [&mut full, &mut lazy] {
        assert!(!theory.consistent(&[open, off]).is_consistent());
        assert!(theory.entails(&[open], &on).unwrap());
    }
    assert!(lazy.value_lits[ack.index()].is_empty(), "not mentioned yet");
    let answer = |v| Literal::Is(ack, ValueId(v));
    let not = |v| Literal::IsNot(ack, ValueId(v));
    let accepted = Formula::is(ack, ValueId(1));
    for theory in [&mut full, &mut lazy] {
        assert!(theory.consistent(&[answer(1), open]).is_consistent());
        assert!(!theory.consistent(&[answer(1), answer(2)]).is_consistent());
        assert!(!theory.consistent(&[not(0), not(1), not(2)]).is_consistent());
        assert!(theory.entails(&[not(0), not(2)], &accepted).unwrap());
        assert!(!theory.entails(&[open], &accepted).unwrap());
    }
    assert_eq!(lazy.value_lits[ack.index()].len(), 3);
}

#[test]
fn a_literal_assumed_twice_still_gives_a_minimal_conflict() {
    let mut theory = driver();
    let off = is(&theory, "driver", "off");
    let on = is(&theory, "driver", "on");
    let Consistency::Conflict(conflict) = theory.minimal_conflict(&[off, off, on, on]) else {
        panic!("a driver cannot be off and on");
    };
    assert_eq!(conflict, vec![off, on]);
}

#[test]
fn not_entailed_is_not_the_negation_entailed() {
    // §5.1.1: with the driver failed, nothing is known about the valve command.
    let mut theory = driver();
    let failed = [is(&theory, "driver", "failed")];
    let on = formula(&theory, "valve.cmd_in = on");
    let not_on = formula(&theory, "not valve.cmd_in = on");
    assert!(!theory.entails(&failed, &on).unwrap());
    assert!(!theory.entails(&failed, &not_on).unwrap());
    // With the driver on, the interconnection entails the command reaches the valve.
    let on_driver = [is(&theory, "driver", "on")];
    assert!(theory.entails(&on_driver, &on).unwrap());
    assert!(!theory.entails(&on_driver, &not_on).unwrap());
}

#[test]
fn defined_formulas_are_encoded_once_and_assumable_both_ways() {
    let mut theory = driver();
    let f = formula(&theory, "driver = on or driver = failed");
    let holds = theory.define(&f).unwrap();
    assert_eq!(theory.define(&f).unwrap(), holds);
    let off = is(&theory, "driver", "off");
    assert!(matches!(
        theory.consistent(&[holds, off]),
        Consistency::Conflict(_)
    ));
    assert_eq!(theory.consistent(&[!holds, off]), Consistency::Consistent);
}

#[test]
fn external_atoms_are_refused() {
    let mut table = VarTable::new();
    table.add_variable("x", ["a", "b"]).unwrap();
    table.add_clock("t").unwrap();
    let f = parse_formula("t >= 3 and x = a", &table).unwrap();
    let mut theory = Theory::new(table, &[]).unwrap();
    assert_eq!(theory.entails(&[], &f), Err(TheoryError::ExternalAtom));
    let grounded = f.ground(&mut |atom| atom.is_external().then_some(true));
    assert_eq!(theory.define(&grounded).map(|_| ()), Ok(()));
}

#[test]
fn variables_are_linked_by_shared_constraints() {
    let theory = driver();
    let table = theory.table();
    let root = |name: &str| theory.component_root(table.variable_id(name).unwrap());
    assert_eq!(root("driver"), root("valve"));
    let mut table = VarTable::new();
    table.add_variable("a", ["x"]).unwrap();
    table.add_variable("b", ["x"]).unwrap();
    let theory = Theory::new(table, &[]).unwrap();
    assert_ne!(
        theory.component_root(VarId(0)),
        theory.component_root(VarId(1))
    );
}
/// "A search check's model, by deciding": on random theories, OPSAT-like runs of candidate
/// checks (one value per decision variable — half of them, the others free as a plant's
/// connections are — each list changing one or two of the last one's, with
/// yes/no questions in between that move the set-kept closure) get the SAT solver's answer
/// with propagation off, every conflict is a subset of the candidate and inconsistent, and
/// the set-kept closure answers some of the checks the search closure left open.
#[test]
fn search_checks_the_set_closure_decides_are_the_solvers_answers() {
    use chacha20::ChaCha8Rng;
    use rand::{RngExt, SeedableRng};
    let mut rng = ChaCha8Rng::seed_from_u64(29);
    let mut decided = 0;
    for _ in 0..300 {
        let domains: Vec<u32> = (0..8).map(|_| rng.random_range(2..4)).collect();
        let mut table = VarTable::new();
        for (x, &n) in domains.iter().enumerate() {
            let values: Vec<String> = (0..n).map(|v| format!("v{v}")).collect();
            table.add_variable(format!("x{x}"), values).unwrap();
        }
        let atom = |rng: &mut ChaCha8Rng| {
            let x = rng.random_range(0..domains.len());
            let v = rng.random_range(0..domains[x]);
            let not = if rng.random_bool(0.5) { "not " } else { "" };
            format!("{not}x{x} = v{v}")
        };
        let constraints: Vec<Formula> = (0..rng.random_range(4..16))
            .map(|_| {
                let atoms: Vec<String> = (0..rng.random_range(2..4))
                    .map(|_| atom(&mut rng))
                    .collect();
                parse_formula(&atoms.join(" or "), &table).unwrap()
            })
            .collect();
        let mut theory = Theory::new(table.clone(), &constraints).unwrap();
        let mut oracle = Theory::new(table, &constraints).unwrap();
        oracle.set_propagation(false);
        let mut candidate: Vec<u32> = vec![0; domains.len() / 2];
        for _ in 0..30 {
            for _ in 0..rng.random_range(1..3) {
                let x = rng.random_range(0..candidate.len());
                candidate[x] = rng.random_range(0..domains[x]);
            }
            let list: Vec<Literal> = (candidate.iter().enumerate())
                .map(|(x, &v)| Literal::Is(VarId(x as u32), ValueId(v)))
                .collect();
            let expected = oracle.consistent(&list).is_consistent();
            match theory.search_conflict(&list) {
                Consistency::Consistent => assert!(expected, "{list:?}"),
                Consistency::Conflict(conflict) => {
                    assert!(!expected, "{list:?}");
                    assert!(conflict.iter().all(|l| list.contains(l)), "{conflict:?}");
                    assert!(!oracle.consistent(&conflict).is_consistent());
                }
            }
            if rng.random_bool(0.5) {
                let some: Vec<Literal> = list
                    .iter()
                    .copied()
                    .filter(|_| rng.random_bool(0.5))
                    .collect();
                let expected = oracle.consistent(&some).is_consistent();
                assert_eq!(theory.is_consistent(&some), expected, "{some:?}");
            }
        }
        decided += theory.decided_checks;
    }
    assert!(decided > 0, "the set-kept closure answered no search check");
}
