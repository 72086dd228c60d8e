//! No input makes the RMPL front end or the sequencer panic (DESIGN.md §13):
//! arbitrary text, soups of RMPL tokens, and mutilated copies of the shipped programs are parsed,
//! linked and, when they compile, executed for a few cycles on arbitrary estimates.
//! `KAIROS_CASES=N` raises the number of cases.

#[path = "support/seeded.rs"]
mod seeded;
use kairos::diagnostic::Source;
use kairos::logic::ValueId;
use kairos::rmpl::{self, LinkOptions};
use kairos::sequencer::{AssignmentOracle, Sequencer, StateEstimate};
use proptest::prelude::*;

/// Runs the whole front end, and a few cycles if it compiles; returns whether it compiled.
fn exercise(text: &str, estimates: &[Vec<(u32, u32)>]) -> bool {
    let source = Source::new("fuzz.rmpl", text);
    let Ok(thca) = rmpl::load(&source, &LinkOptions::default()) else {
        return false;
    };
    let _ = thca.to_string();
    let table = thca.table().clone();
    let mut oracle = AssignmentOracle::new(&table);
    let mut sequencer = Sequencer::new(thca);
    let estimate = |assignments: &Vec<(u32, u32)>| {
        let mut estimate = StateEstimate::new();
        for &(x, v) in assignments {
            if let Some((var, variable)) = table.variables().nth(x as usize % table.len().max(1)) {
                let value = v as usize % variable.domain_size();
                estimate.set(var, ValueId(value as u32));
            }
        }
        estimate
    };
    let mut current = StateEstimate::new();
    for (cycle, assignments) in estimates.iter().enumerate() {
        let next = estimate(assignments);
        let time = cycle as f64 * 7.5;
        sequencer
            .step(time, &current, &next, &mut oracle)
            .expect("well-ordered calls");
        current = next;
    }
    true
}

const TOKENS: &[&str] = &[
    "P() :: {",
    "Q(a, b) :: {",
    "{",
    "}",
    "(",
    ")",
    ";",
    ",",
    "::",
    "do",
    "watching",
    "maintaining",
    "if",
    "thennext",
    "elsenext",
    "unless",
    "when",
    "whenever",
    "donext",
    "always",
    "next",
    "x",
    "y",
    "t",
    "a",
    "b",
    "=",
    "!=",
    "≥",
    ">=",
    "<",
    "0",
    "5",
    "2.5",
    "min",
    "s",
    "on",
    "off",
    "and",
    "∧",
    "or",
    "¬",
    "not",
    "=>",
    "true",
    "P(x = on) >= 0.5",
    "Q(on, 3 s)",
    "P()",
    "R()",
    "\n",
    " ",
    "// c\n",
    "/* c */",
    "é",
    "x.y",
];

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..60).prop_map(|tokens| tokens.join(" "))
}

fn estimates() -> impl Strategy<Value = Vec<Vec<(u32, u32)>>> {
    prop::collection::vec(prop::collection::vec((0u32..20, 0u32..6), 0..6), 0..6)
}

fn shipped_program() -> impl Strategy<Value = String> {
    prop::sample::select(&["mars_entry", "mars_edl", "spacecraft_deployment"][..]).prop_map(
        |name| {
            let path = format!("{}/programs/{name}.rmpl", env!("CARGO_MANIFEST_DIR"));
            std::fs::read_to_string(path).expect("shipped program")
        },
    )
}

/// A shipped program with a few characters deleted, replaced or inserted.
fn mutilated() -> impl Strategy<Value = String> {
    (
        shipped_program(),
        prop::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<char>()), 1..6),
    )
        .prop_map(|(text, edits)| {
            let mut chars: Vec<char> = text.chars().collect();
            for (at, kind, c) in edits {
                let i = at.index(chars.len().max(1)).min(chars.len());
                match kind {
                    0 if i < chars.len() => {
                        chars.remove(i);
                    }
                    1 if i < chars.len() => chars[i] = c,
                    _ => chars.insert(i, c),
                }
            }
            chars.into_iter().collect()
        })
}

/// Cases per property unless `KAIROS_CASES` says otherwise.
const DEFAULT_CASES: u32 = 256;

proptest! {
    #![proptest_config(seeded::config(DEFAULT_CASES))]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC*", estimates in estimates()) {
        exercise(&text, &estimates);
    }

    #[test]
    fn token_soups_never_panic(text in token_soup(), estimates in estimates()) {
        exercise(&text, &estimates);
    }

    #[test]
    fn mutilated_programs_never_panic(text in mutilated(), estimates in estimates()) {
        exercise(&text, &estimates);
    }
}

#[test]
fn the_generators_reach_the_sequencer() {
    // The token soups are only useful if some of them compile; make sure the shapes above do.
    assert!(exercise(
        "P() :: { do { always (x = on) } watching (y = off); t = 0; when (t >= 5 s) donext x = off }",
        &[vec![(0, 1)], vec![(1, 0)], vec![]],
    ));
}

#[test]
fn pathological_nesting_is_an_error_not_a_crash() {
    for depth in [150, 2_000, 50_000] {
        for (open, close) in [
            ("{", "}"),
            ("always ", ""),
            ("next ", ""),
            ("(y = on; ", ")"),
        ] {
            let text = format!(
                "P() :: {{ {}x = on{} }}",
                open.repeat(depth),
                close.repeat(depth)
            );
            assert!(!exercise(&text, &[]), "depth {depth} of {open:?} compiled");
        }
        // Parentheses around a goal are the formula's, and formulas may nest deeply.
        let goal = format!(
            "P() :: {{ {}x = on{} }}",
            "(".repeat(depth),
            ")".repeat(depth)
        );
        exercise(&goal, &[]);
        let condition = format!(
            "P() :: {{ when {}x = on{} donext y = on }}",
            "(".repeat(depth),
            ")".repeat(depth)
        );
        exercise(&condition, &[]);
        let negations = format!(
            "P() :: {{ when {}x = on donext y = on }}",
            "not ".repeat(depth)
        );
        exercise(&negations, &[]);
    }
}
