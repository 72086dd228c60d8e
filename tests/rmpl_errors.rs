//! Error messages for malformed programs (snapshot tests of at least ten; every
//! error located at file:line:col with the source line, a caret and what was expected; several
//! errors per run). Programs are linked against the Mars lander's variables so that unknown
//! variables and values can be recognised.

#[path = "support/rmpl.rs"]
mod rmpl_support;

use kairos::diagnostic::{Source, SourceErrors};
use kairos::rmpl::{self, LinkOptions};
use rmpl_support::mars_lander_plant;

fn errors_of(path: &str) -> SourceErrors {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&full).unwrap_or_else(|e| panic!("{full}: {e}"));
    let plant = mars_lander_plant();
    let options = LinkOptions {
        entry: None,
        plant: Some(&plant),
    };
    match rmpl::load(&Source::new(path, text), &options) {
        Ok(_) => panic!("{path} compiled"),
        Err(errors) => errors,
    }
}

/// Each malformed program, and how many errors it must report.
const MALFORMED: [(&str, usize); 16] = [
    ("rmpl_missing_brace", 1),
    ("rmpl_unknown_combinator", 1),
    ("rmpl_misspelt_keyword", 1),
    ("rmpl_bad_condition", 1),
    ("rmpl_missing_double_colon", 1),
    ("rmpl_two_broken_programs", 2),
    ("rmpl_unknown_variable", 1),
    ("rmpl_value_not_in_domain", 1),
    ("rmpl_recursion", 1),
    ("rmpl_unknown_program", 1),
    ("rmpl_argument_count", 1),
    ("rmpl_clock_before_init", 1),
    ("rmpl_clock_never_started", 1),
    ("rmpl_goal_on_clock", 2),
    ("rmpl_duplicate_program", 1),
    ("rmpl_several_link_errors", 4),
];

#[test]
fn malformed_programs_get_located_errors() {
    for (name, count) in MALFORMED {
        let path = format!("tests/bad_input/{name}.rmpl");
        let errors = errors_of(&path);
        let text = errors.to_string();
        assert_eq!(errors.diagnostics.len(), count, "{text}");
        for diagnostic in &errors.diagnostics {
            assert!(
                !diagnostic.expected.is_empty(),
                "{path}: no expectation in {text}"
            );
        }
        assert!(text.contains(&format!("--> {path}:")), "{text}");
        insta::assert_snapshot!(name, text);
    }
}
