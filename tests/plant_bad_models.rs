//! The plant loader's errors on malformed models ("snapshot tests of the loader's errors
//! for ≥ 10 malformed models"; DESIGN.md §6.1's validation list, §13). Each file in
//! `tests/bad_models/` says in its first comment what is wrong with it; its snapshot shows every
//! error located at file:line:col with the offending text and what was expected.

#[path = "support/bad_files.rs"]
#[macro_use]
mod bad_files;

use std::process::Command;

use kairos::diagnostic::Source;
use kairos::plant::Plant;

/// The model at `path`, read as `kairos check` reads it.
fn load_model(path: &std::path::Path) -> Result<Plant, String> {
    let source = Source::read(path).map_err(|e| e.to_string())?;
    Plant::load(&source).map_err(|errors| errors.to_string())
}

macro_rules! bad_model {
    ($($case:tt)+) => { bad_file!(load_model, "tests/bad_models", $($case)+); };
}

bad_model!(
    syntax_error,
    "bad_models/syntax_error.ron:9:17",
    "malformed RON"
);
bad_model!(unknown_field, "unknown_field.ron:11:41", "gaurd");
bad_model!(
    unknown_mode,
    "has no mode `stanby`",
    "did you mean `standby`?"
);
bad_model!(
    unknown_names_in_formulas,
    "unknown variable `engine.tmp`",
    "`hot` is not a value of `engine.temp`",
    "unknown variable `engin.cmd`",
    "`valve.temp` is not a value of `engine.temp`"
);
bad_model!(
    probability_out_of_range,
    "probability 1.2 is outside [0, 1]",
    "initial probability 1.5 is outside [0, 1]",
    "rate -0.001 is not a finite rate"
);
bad_model!(
    outgoing_exceeds_one,
    "component `driver`, mode `off`: outgoing probabilities can add up to 1.089",
    "transitions to `on` (0.989), `failed` (0.1) can be enabled together"
);
bad_model!(initial_not_one, "initial probabilities sum to 0.8, not 1");
bad_model!(
    bad_windows,
    "window [60, 30] is inverted",
    "window [30, 30] is empty",
    "before the mode is entered",
    "Gaussian(100, 0) has no spread",
    "a timed transition has no rate"
);
bad_model!(
    duplicate_names,
    "mode `closed` is declared twice",
    "component `valve` is declared twice",
    "value `zero` appears twice"
);
bad_model!(
    controls_and_observables,
    "`engine` is a component's mode variable",
    "`idle` is not a value of `engine.cmd`",
    "`engine.pressure` is not an attribute, so it cannot be an observable",
    "`engine.temp` is both a control and an observable"
);
bad_model!(
    mode_never_holds,
    "mode `open` can never hold",
    "transition `closed` -> `open` can never be enabled"
);
bad_model!(
    transition_shapes,
    "a transition to its own source",
    "both a probability and a rate",
    "no probability",
    "cannot mention a confidence"
);

#[test]
fn check_exits_2_on_a_bad_model_and_0_on_a_good_one() {
    let run = |file: &str| {
        Command::new(env!("CARGO_BIN_EXE_kairos"))
            .args(["check", file])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("the kairos binary runs")
    };
    let bad = run("tests/bad_models/unknown_mode.ron");
    assert_eq!(bad.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(stderr.contains("unknown_mode.ron:11:"), "{stderr}");
    let good = run("models/driver_valve.ron");
    assert_eq!(good.status.code(), Some(0));
}
bad_model!(
    type_body_errors,
    "unknown variable `valve1.flwo`",
    "in `valve1`, an instance of type `valve`",
    "has no mode `opne`",
    "no parameter `stuk`",
    "did you mean `stuck`?",
    "the same in 2 other instances"
);
bad_model!(
    type_instances,
    "no type `swich`",
    "did you mean `switch`?",
    "type `switch` has no parameter `stick`",
    "`s3` is an instance of a type and has `modes` of its own",
    "`s[4..]` has a malformed index range",
    "`t[1..2]`: only instances of a type have indexed names",
    "`bonus` is not a number (parameter names are for types)",
    "the ranges have different lengths (2 and 3)"
);
