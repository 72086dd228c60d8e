//! Deep trees in the input are refused at a documented limit, and trees at the limit are
//! processed, all on a test thread's 2 MiB stack (DESIGN.md §13: no panic, no abort on any input).
//! The black-box campaign aborted the binary with stack overflows on 10,000
//! chained `maintaining` constructs, a 10,000-long `=>` chain and 10,000 programs each invoking
//! the next; each is run here at that real depth. The limits: `logic::syntax::MAX_NESTING`
//! (parentheses, negations in a row), `logic::syntax::MAX_DEPTH` (nested formula operators),
//! `rmpl::syntax::MAX_NESTING` (blocks, combinators and `maintaining` links of one definition),
//! `rmpl::MAX_INLINED_DEPTH` and `rmpl::MAX_INLINED_SIZE` (the program once inlined).

use kairos::diagnostic::Source;
use kairos::logic::syntax::MAX_DEPTH;
use kairos::plant::Plant;
use kairos::rmpl::{self, LinkOptions, MAX_INLINED_DEPTH};
use kairos::sequencer::{AssignmentOracle, Sequencer, StateEstimate, dot};

/// The real depth the campaign used.
const DEEP: usize = 10_000;

/// Loads a program (linked against the names it uses); on success also prints it, draws it and
/// runs its sequencer for a few cycles, every pass over the compiled automaton.
fn load_and_run(text: &str) -> Result<(), String> {
    let source = Source::new("deep.rmpl", text);
    let thca = rmpl::load(&source, &LinkOptions::default()).map_err(|e| e.to_string())?;
    assert!(!thca.to_string().is_empty());
    assert!(!dot::graph(&thca, &[]).render().is_empty());
    let table = thca.table().clone();
    let mut oracle = AssignmentOracle::new(&table);
    let mut sequencer = Sequencer::new(thca);
    let estimate = StateEstimate::new();
    for cycle in 0..3 {
        sequencer
            .step(f64::from(cycle), &estimate, &estimate, &mut oracle)
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}

fn refused(text: &str, message: &str) {
    match load_and_run(text) {
        Ok(()) => panic!("a program past the limit was accepted"),
        Err(shown) => assert!(shown.contains(message), "missing `{message}` in:\n{shown}"),
    }
}

#[test]
fn ten_thousand_chained_maintaining_are_refused() {
    let chain = " maintaining y = on".repeat(DEEP);
    refused(
        &format!("Main() :: {{ x = on{chain} }}"),
        "blocks and combinators are nested too deeply",
    );
}

#[test]
fn maintaining_chains_up_to_the_limit_run() {
    // The program's block is the first level.
    let chain = " maintaining y = on".repeat(rmpl::syntax::MAX_NESTING - 1);
    assert_eq!(
        load_and_run(&format!("Main() :: {{ x = on{chain} }}")),
        Ok(())
    );
}

#[test]
fn a_ten_thousand_long_implication_chain_is_refused() {
    let chain = " => x = on".repeat(DEEP);
    refused(
        &format!("Main() :: {{ x = on{chain} }}"),
        "formula nested too deeply",
    );
    refused(
        &format!("Main() :: {{ when x = on{chain} donext y = on }}"),
        "formula nested too deeply",
    );
}

#[test]
fn implication_chains_up_to_the_limit_run() {
    let chain = " => x = on".repeat(MAX_DEPTH);
    assert_eq!(
        load_and_run(&format!(
            "Main() :: {{ when x = on{chain} donext y = on; x = on{chain} }}"
        )),
        Ok(())
    );
}

/// Negations and parentheses each within their own limit but interleaved: the formula's depth
/// is their product, which only the operator limit bounds.
#[test]
fn interleaved_negations_and_parentheses_are_refused_past_the_operator_limit() {
    let mut formula = "x = on".to_string();
    for _ in 0..90 {
        formula = format!("{}(x = on and {formula})", "not ".repeat(99));
    }
    refused(
        &format!("Main() :: {{ when {formula} donext y = on }}"),
        "formula nested too deeply",
    );
}

#[test]
fn ten_thousand_programs_invoking_each_other_in_a_chain_are_refused() {
    let mut text: String = (0..DEEP)
        .map(|i| format!("P{i}() :: {{ P{}() }}\n", i + 1))
        .collect();
    text.push_str(&format!("P{DEEP}() :: {{ x = on }}\n"));
    refused(
        &text,
        "program nested too deeply once its invocations are inlined",
    );
}

/// A program that invokes another twice, which invokes a third twice, ...: 2^30 constructs.
#[test]
fn doubling_invocations_are_refused_by_size() {
    let mut text: String = (0..30)
        .map(|i| format!("P{i}() :: {{ P{n}(); P{n}() }}\n", n = i + 1))
        .collect();
    text.push_str("P30() :: { x = on }\n");
    refused(&text, "program too large once its invocations are inlined");
}

/// Each program nests one combinator around its invocation, two levels of the inlined tree:
/// the deepest inlined tree the limit allows.
#[test]
fn inlined_programs_up_to_the_limit_run() {
    let programs = MAX_INLINED_DEPTH / 2 - 1;
    let mut text: String = (0..programs)
        .map(|i| format!("P{i}() :: {{ do P{}() watching x = off }}\n", i + 1))
        .collect();
    text.push_str(&format!("P{programs}() :: {{ x = on }}\n"));
    assert_eq!(load_and_run(&text), Ok(()));
}

/// The driver/valve model with the driver's `turning-on` constraint replaced.
fn plant_with_constraint(constraint: &str) -> Result<Plant, String> {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/models/driver_valve.ron"
    ))
    .expect("the shipped model");
    let original = r#"Mode(name: "turning-on", constraint: "true""#;
    assert!(text.contains(original));
    let text = text.replace(
        original,
        &format!(r#"Mode(name: "turning-on", constraint: "{constraint}""#),
    );
    let plant = Plant::load(&Source::new("deep.ron", text)).map_err(|e| e.to_string())?;
    plant.theory().map_err(|e| e.to_string())?;
    Ok(plant)
}

#[test]
fn a_ten_thousand_long_implication_chain_in_a_plant_constraint_is_refused() {
    let chain = " => driver.dcmd_out = on".repeat(DEEP);
    let shown = plant_with_constraint(&format!("driver.dcmd_out = on{chain}"))
        .err()
        .unwrap_or_default();
    assert!(shown.contains("formula nested too deeply"), "{shown}");
    assert!(shown.contains("deep.ron:"), "{shown}");
}

#[test]
fn plant_constraints_up_to_the_limit_load() {
    let chain = " => driver.dcmd_out = on".repeat(MAX_DEPTH);
    assert!(plant_with_constraint(&format!("driver.dcmd_out = on{chain}")).is_ok());
}
