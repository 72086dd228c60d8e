//! No panic, no abort, no hang on any input (DESIGN.md §13): each finding of the
//! black-box campaign against the release binary, run through `kairos` as a user would, must end
//! with a located error or a bounded run.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/large_plant.rs"]
mod large_plant;

use std::path::PathBuf;

use cli::kairos;

/// Writes `bytes` to a file of this test binary's scratch directory and returns its path.
fn scratch(name: &str, bytes: impl AsRef<[u8]>) -> String {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, bytes).expect("the scratch directory is writable");
    path.display().to_string()
}

/// Invalid UTF-8 in a file named on the command line: the first invalid byte's line:column and
/// byte offset, with the line shown, by the one reader every subcommand uses.
#[test]
fn invalid_utf8_is_located_at_its_first_byte() {
    let mut bytes = b"Main() :: {\n    x = on\xff;\n}\n".to_vec();
    bytes.extend_from_slice(b"\xfe more\n");
    let path = scratch("not_utf8.rmpl", &bytes);
    for args in [
        vec!["check", path.as_str()],
        vec!["compile", path.as_str()],
        vec!["graph", path.as_str()],
        vec!["solve", path.as_str()],
        vec!["run", path.as_str()],
    ] {
        let (code, _, stderr) = kairos(&args);
        assert_eq!(code, 2, "{args:?}: {stderr}");
        assert!(stderr.contains("not_utf8.rmpl:2:11"), "{args:?}: {stderr}");
        assert!(
            stderr.contains("byte 0xff at byte offset 22"),
            "{args:?}: {stderr}"
        );
        assert!(
            stderr.contains("text encoded in UTF-8"),
            "{args:?}: {stderr}"
        );
    }
}

/// A file a scenario names (here its plant model) that is not UTF-8 is located in that file.
#[test]
fn invalid_utf8_in_a_file_a_scenario_names_is_located_in_that_file() {
    let plant = scratch("not_utf8_plant.ron", b"(components: [\xc3(]\n");
    let root = env!("CARGO_MANIFEST_DIR");
    let scenario = scratch(
        "names_a_bad_plant.ron",
        format!(
            "Scenario(program: \"{root}/programs/propulsion_fire.rmpl\", plant: \"{plant}\", \
             cycle: 1.0, end: 10.0)"
        ),
    );
    let (code, _, stderr) = kairos(&["run", &scenario]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("not_utf8_plant.ron:1:15"), "{stderr}");
    assert!(stderr.contains("byte 0xc3 at byte offset 14"), "{stderr}");
}

/// An estimation log with a repeated time is refused at the repeated time, as a decreasing one
/// is: each line is one cycle (`src/estimation/log.rs`), so three lines at t = 1.0 were three
/// estimation steps of length zero.
#[test]
fn an_estimation_log_with_a_repeated_time_is_refused() {
    let line = |t: &str| {
        format!("{{\"time\": {t}, \"observations\": {{\"valve.flow_out\": \"zero\"}}}}\n")
    };
    let log = scratch(
        "repeated_time.jsonl",
        [line("0.0"), line("1.0"), line("1.0"), line("1.0")].concat(),
    );
    let (code, stdout, stderr) = kairos(&[
        "estimate",
        "--plant",
        "models/driver_valve.ron",
        "--log",
        &log,
    ]);
    assert_eq!(code, 2, "{stdout}");
    assert!(stdout.is_empty(), "{stdout}");
    for expected in [
        "repeated_time.jsonl:3:3",
        "time 1 s repeats the time of line 2",
        "repeated_time.jsonl:4:3",
        "time 1 s repeats the time of line 3",
        "one cycle per line",
    ] {
        assert!(
            stderr.contains(expected),
            "missing `{expected}` in\n{stderr}"
        );
    }
}

/// The three stack overflows of the campaign, through the binary: each is a located error and
/// exit code 2, not an abort (the limits and the library-level tests: `tests/deep_input.rs`).
#[test]
fn deep_programs_are_located_errors_not_aborts() {
    let maintaining = format!(
        "Main() :: {{ x = on{} }}\n",
        " maintaining y = on".repeat(10_000)
    );
    let implications = format!("Main() :: {{ x = on{} }}\n", " => x = on".repeat(10_000));
    let mut chain: String = (0..10_000)
        .map(|i| format!("P{i}() :: {{ P{}() }}\n", i + 1))
        .collect();
    chain.push_str("P10000() :: { x = on }\n");
    for (name, text, message, at) in [
        (
            "maintaining.rmpl",
            maintaining,
            "blocks and combinators are nested too deeply",
            "maintaining.rmpl:1:1901",
        ),
        (
            "implications.rmpl",
            implications,
            "formula nested too deeply",
            "implications.rmpl:1:2013",
        ),
        (
            "chain.rmpl",
            chain,
            "program nested too deeply once its invocations are inlined",
            "chain.rmpl:1:11",
        ),
    ] {
        let path = scratch(name, text);
        for command in ["check", "compile"] {
            let (code, _, stderr) = kairos(&[command, &path]);
            assert_eq!(code, 2, "{command} {name}: {stderr}");
            assert!(stderr.contains(message), "{command} {name}: {stderr}");
            assert!(stderr.contains(at), "{command} {name}: {stderr}");
        }
    }
}

/// `cycle: 1e-8, end: 10` is 10⁹ cycles: refused before the run, at `end`, with the count and a
/// rough wall time (the cap, `simulation::MAX_CYCLES`, is documented in `src/simulation/mod.rs`).
#[test]
fn a_run_of_a_billion_cycles_is_refused_before_it_starts() {
    let (code, stdout, stderr) = kairos(&["run", "tests/bad_scenarios/too_many_cycles.ron"]);
    assert_eq!(code, 2, "{stdout}");
    for expected in [
        "too_many_cycles.ron:7:10",
        "1.000e9 cycles, more than the 10000000 a scenario may run",
        "about 8.6 hours",
        "the cycle period is set at line 6, column 12",
    ] {
        assert!(
            stderr.contains(expected),
            "missing `{expected}` in\n{stderr}"
        );
    }
}

/// The progress bar is for a person at a terminal: standard error captured (not a terminal)
/// carries no bar, with or without `--quiet`, and the log on standard output is unchanged.
#[test]
fn no_progress_bar_when_standard_error_is_not_a_terminal() {
    for quiet in [false, true] {
        let mut args = vec!["run", "scenarios/propulsion/nominal.ron"];
        if quiet {
            args.push("--quiet");
        }
        let (code, stdout, stderr) = kairos(&args);
        assert_eq!(code, 0, "{stderr}");
        assert!(stderr.is_empty(), "{stderr}");
        assert!(!stdout.contains("cycles (eta"), "{stdout}");
    }
}

/// A plant above `LARGE_PLANT_VARIABLES` (1,000; here 260 components, 1,040 variables): `kairos
/// estimate` says how large it is before the long part starts, and still estimates.
#[test]
fn estimation_on_a_large_plant_says_so_before_it_starts() {
    let plant = scratch("chain260.ron", large_plant::chain(260));
    let log = scratch(
        "chain260.jsonl",
        "{\"time\": 0.0, \"observations\": {\"c0.out\": \"zero\"}}\n\
         {\"time\": 1.0, \"observations\": {\"c0.out\": \"zero\"}}\n",
    );
    let (code, stdout, stderr) = kairos(&["estimate", "--plant", &plant, "--log", &log]);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        stderr.starts_with("note: ")
            && stderr.contains("260 components, 1040 variables, 780 transitions")
            && stderr.contains("grows faster than linearly"),
        "{stderr}"
    );
    assert!(stdout.contains("t = 1"), "{stdout}");
}

/// A device or a directory given where a file is expected is refused at once, not read until
/// memory runs out (`/dev/zero` never ends): every loader reads through `Source::read`, which
/// takes regular files only.
#[test]
fn a_device_or_directory_is_not_read_as_a_file() {
    for args in [
        vec!["run", "/dev/zero"],
        vec!["graph", "/dev/zero"],
        vec!["schedule", "/dev/zero"],
        vec!["run", "tests"],
    ] {
        let (code, stdout, stderr) = kairos(&args);
        assert_eq!(code, 2, "{args:?}: {stdout}{stderr}");
        assert!(stderr.contains("not a regular file"), "{args:?}: {stderr}");
    }
}
