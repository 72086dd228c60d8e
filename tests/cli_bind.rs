//! `kairos bind` (DESIGN.md §10, §12, §13; docs/embedding.md, "The binding file"): the committed
//! F´ binding of the propulsion plant checks; a binding with mistakes of every kind gets every
//! one located in its file, with what was expected; without a binding, the suggestion by name
//! similarity is itself a binding that checks — the committed one, entry for entry.

#[path = "support/cli.rs"]
mod cli;

use std::path::PathBuf;

use cli::kairos;
use kairos::diagnostic::Source;
use kairos::executive::fprime::{Binding, Dictionary};
use kairos::plant::Plant;

const DICT: &str = "models/fprime/PropulsionTopologyDictionary.json";
const BINDING: &str = "models/fprime/propulsion.binding.ron";

/// `kairos bind` of `dictionary` against the propulsion plant, with `binding` when given (a
/// suggestion otherwise): exit code, stdout, stderr.
fn bind(dictionary: &str, binding: Option<&str>) -> (i32, String, String) {
    let mut args = vec![
        "bind",
        "--fprime-dict",
        dictionary,
        "--plant",
        "models/propulsion.ron",
    ];
    args.extend(binding.iter().flat_map(|b| ["--binding", b]));
    kairos(&args)
}

fn scratch(name: &str, text: &str) -> String {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::write(&path, text).expect("the scratch directory is writable");
    path.display().to_string()
}

#[test]
fn the_committed_binding_checks() {
    let (code, stdout, stderr) = bind(DICT, Some(BINDING));
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(
        stdout.trim(),
        "models/fprime/propulsion.binding.ron: ok (5 channel(s) bound to the observables of propulsion, 10 command(s) to its control values)"
    );
}

/// Every kind of mistake, each located: an unknown channel and command (with a did-you-mean), an
/// observable that is not one, a numeric channel (no monitor), a constant and a value that do
/// not exist, an argument out of its type's range and of the wrong type, a missing argument, an
/// idle value, two control values sent as one command.
#[test]
fn every_mistake_in_a_binding_is_located() {
    let text = r#"Binding(
    telemetry: [
        Channel(channel: "Prop.prop.Valve1Outlt", observable: "valve1.outlet"),
        Channel(channel: "Prop.prop.Valve2Outlet", observable: "valve2.outlt"),
        Channel(channel: "Prop.prop.Tank1Pressure", observable: "engine.power"),
        Channel(channel: "Prop.prop.EngineTemp", observable: "engine.temp",
                values: { "LUKEWARM": "low", "NOMINAL": "hot" }),
    ],
    commands: [
        Command(control: "PDE.cmd = on", command: "Prop.prop.PDE_ONN"),
        Command(control: "PDE.cmd = open1", command: "Prop.prop.VALVE_OPEN", args: [Int(256)]),
        Command(control: "PDE.cmd = open2", command: "Prop.prop.VALVE_OPEN", args: [Bool(true)]),
        Command(control: "PDE.cmd = close1", command: "Prop.prop.VALVE_CLOSE"),
        Command(control: "PDE.cmd = none", command: "Prop.prop.PDE_OFF"),
        Command(control: "PDE.cmd = off", command: "Prop.prop.PDE_OFF"),
        Command(control: "PDE.cmd = reset", command: "Prop.prop.PDE_OFF"),
    ],
)
"#;
    let path = scratch("bad.binding.ron", text);
    let (code, _, stderr) = bind(DICT, Some(&path));
    assert_eq!(code, 2, "{stderr}");
    insta::assert_snapshot!(stderr.replace(&path, "bad.binding.ron"));
}

/// Every observable and every non-idle control value unbound is named, at the list that lacks it.
#[test]
fn an_incomplete_binding_names_what_is_unbound() {
    let path = scratch("empty.binding.ron", "Binding()\n");
    let (code, _, stderr) = bind(DICT, Some(&path));
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("no channel reports valve1.outlet, valve2.outlet, engine.power, engine.temp, engine.thrust"),
        "{stderr}"
    );
    assert!(
        stderr.contains("no command sends PDE.cmd = on, PDE.cmd = off, PDE.cmd = reset"),
        "{stderr}"
    );
}

/// A dictionary that is not one is a located error, not a panic.
#[test]
fn a_file_that_is_not_a_dictionary_is_located() {
    let path = scratch(
        "not-a-dictionary.json",
        "{ \"metadata\": { \"deploymentName\": 3 } }\n",
    );
    let (code, _, stderr) = bind(&path, None);
    assert_eq!(code, 2, "{stderr}");
    assert!(
        stderr.contains("not an F´ JSON dictionary") && stderr.contains(":1:"),
        "{stderr}"
    );
}

/// The suggestion checks, and binds exactly what the committed binding binds.
#[test]
fn the_suggested_binding_is_the_committed_one() {
    let (code, suggested, stderr) = bind(DICT, None);
    assert_eq!(code, 0, "{stderr}");
    assert!(
        !suggested.contains("guessed") && !suggested.contains("// no "),
        "{suggested}"
    );
    let read = |path: &str| Source::read(std::path::Path::new(path)).expect("committed");
    let dictionary = Dictionary::load(&read(DICT)).expect("the dictionary loads");
    let plant = Plant::load(&read("models/propulsion.ron")).expect("the plant loads");
    let suggested = Binding::load(&Source::new("suggested", suggested), &dictionary, &plant)
        .expect("the suggestion checks");
    let committed =
        Binding::load(&read(BINDING), &dictionary, &plant).expect("the committed binding checks");
    assert_eq!(suggested, committed);
}
