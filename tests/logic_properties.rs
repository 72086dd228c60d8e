//! Robustness and round-trip properties of the constraint language (DESIGN.md §4, §13: "no
//! input makes the parser panic"; and the parser round-trips).

#[path = "support/seeded.rs"]
mod seeded;
use kairos::logic::{Formula, ValueId, VarId, VarTable, parse_formula};
use proptest::prelude::*;

fn table() -> VarTable {
    let mut table = VarTable::new();
    table
        .add_variable("engine", ["off", "heating", "standby"])
        .unwrap();
    table.add_variable("engine.temp", ["cold", "hot"]).unwrap();
    table
        .add_variable("valve", ["open", "closed", "stuck-closed"])
        .unwrap();
    table.add_clock("t1").unwrap();
    table
}

/// Random formulas over `table()`'s variables.
fn formula() -> impl Strategy<Value = Formula> {
    let leaf = prop_oneof![
        Just(Formula::True),
        Just(Formula::False),
        (0u32..3, 0u32..2).prop_map(|(x, v)| Formula::is(VarId(x), ValueId(v))),
    ];
    leaf.prop_recursive(4, 24, 3, |inner| {
        prop_oneof![
            inner.clone().prop_map(|f| Formula::Not(Box::new(f))),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Formula::And),
            prop::collection::vec(inner.clone(), 2..4).prop_map(Formula::Or),
            (inner.clone(), inner).prop_map(|(a, b)| Formula::Implies(Box::new(a), Box::new(b))),
        ]
    })
}

proptest! {
    #![proptest_config(seeded::config(512))]

    /// Anything at all: an error or a formula, never a panic.
    #[test]
    fn arbitrary_text_never_panics(text in "\\PC{0,60}") {
        let _ = parse_formula(&text, &table());
    }

    /// Text made of the language's own tokens reaches deeper into the grammar.
    #[test]
    fn token_soup_never_panics(tokens in prop::collection::vec(prop_oneof![
        Just("engine"), Just("engine.temp"), Just("t1"), Just("off"), Just("hot"), Just("="),
        Just("!="), Just(">="), Just("≤"), Just("and"), Just("∨"), Just("not"), Just("=>"),
        Just("("), Just(")"), Just("P("), Just("0.5"), Just("270"), Just("min"), Just("true"),
        Just("-"), Just("."), Just("//"), Just("/*"), Just("*/"), Just("\n"),
    ], 0..16)) {
        let _ = parse_formula(&tokens.join(" "), &table());
    }

    /// Printing a formula and parsing it back gives the same formula.
    #[test]
    fn display_then_parse_is_identity(f in formula()) {
        let table = table();
        let shown = f.display(&table).to_string();
        let again = parse_formula(&shown, &table);
        prop_assert_eq!(Ok(f), again, "{}", shown);
    }
}
