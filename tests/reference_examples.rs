//! The reference cannot rot (`docs/reference/`, `docs/modelling.md`): every file under
//! `docs/examples/` loads with the loader of its format — and does what it is shown doing (a
//! scenario's expectations hold, a rover scenario's properties hold on every interleaving, a log
//! replays, a summary is the summary of its records) — every example a page shows is the file
//! it names, verbatim, and the trace page names every key `kairos run --trace` writes. The
//! pages' field tables are checked against the loaders by the unit tests
//! `the_reference_documents_every_field` (`diagnostic::reference` states the convention).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use kairos::campaign::{RunRecord, Summary};
use kairos::diagnostic::Source;
use kairos::estimation::log::{parse_log, replay};
use kairos::estimation::{TimedMe, TimedMeOptions};
use kairos::exploration::Budget;
use kairos::exploration::protocol::explore;
use kairos::plant::Plant;
use kairos::protocol::CoaController;
use kairos::report::trace::Trace;
use kairos::rmpl::{self, LinkOptions};
use kairos::simulation::{self, Outcome, RunOptions};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Every file under `dir`, sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                pending.push(path);
            } else {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The name of a RON file's top-level struct, comments skipped.
fn top_level(text: &str) -> &str {
    let code = text
        .lines()
        .find(|l| !l.trim().is_empty() && !l.trim_start().starts_with("//"))
        .unwrap_or("");
    code.trim().split('(').next().unwrap_or("")
}

/// Loads a scenario and runs it: every expectation must hold.
fn run_scenario(path: &Path) {
    let scenario = simulation::load(path).unwrap_or_else(|e| panic!("{e}"));
    let outcome = simulation::run(&scenario, RunOptions::default(), &mut |_| {})
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    for verdict in &outcome.verdicts {
        if let Outcome::Failed { reason } = &verdict.outcome {
            panic!("{}: {} failed: {reason}", path.display(), verdict.label);
        }
    }
}

/// Loads a RON example by its top-level struct; `Script` files are loaded by the scenarios that
/// include them, so one must.
fn load_ron(path: &Path, scenarios: &[PathBuf]) {
    let source = Source::read(path).unwrap_or_else(|e| panic!("{e}"));
    match top_level(&source.text) {
        "Plant" => {
            Plant::load(&source).unwrap_or_else(|e| panic!("{e}"));
        }
        "Scenario" => run_scenario(path),
        "Script" => {
            let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("");
            let included = scenarios.iter().any(|s| {
                std::fs::read_to_string(s).is_ok_and(|text| {
                    text.contains(&format!("/{name}\"")) || text.contains(&format!("\"{name}\""))
                })
            });
            assert!(
                included,
                "{}: no example scenario includes it",
                path.display()
            );
        }
        "Mission" => {
            kairos::goalnet::mission::load(path).unwrap_or_else(|e| panic!("{e}"));
        }
        "Ocsp" => {
            kairos::opsat::file::load(&source).unwrap_or_else(|e| panic!("{e}"));
        }
        "RoverScenario" => {
            let rover = kairos::protocol::scenario::load(path).unwrap_or_else(|e| panic!("{e}"));
            let explored = explore(
                &rover,
                CoaController::new(rover.initial_value()),
                Budget::Unbounded,
                u64::MAX,
            );
            assert!(explored.holds(), "{}: a property fails", path.display());
        }
        other => panic!("{}: no loader for `{other}(...)`", path.display()),
    }
}

/// A campaign's records; the summary beside them (after its two header lines, which hold the
/// machine's speed) is theirs.
fn load_records(path: &Path) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{e}"));
    let records: Vec<RunRecord> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{}: {e}", path.display())))
        .collect();
    assert!(!records.is_empty(), "{}: no record", path.display());
    let summary = path.with_file_name("summary.txt");
    if let Ok(written) = std::fs::read_to_string(&summary) {
        let body: Vec<&str> = written.lines().skip(2).collect();
        let expected = Summary::of(&records).to_string();
        assert_eq!(
            body.join("\n"),
            expected.trim_end(),
            "{}",
            summary.display()
        );
    }
}

/// An estimation log, replayed against the plant its first comment line names
/// (`--plant FILE`, relative to the log).
fn replay_log(path: &Path) {
    let source = Source::read(path).unwrap_or_else(|e| panic!("{e}"));
    let plant_name = source
        .text
        .split_whitespace()
        .skip_while(|w| *w != "--plant")
        .nth(1)
        .unwrap_or_else(|| panic!("{}: its first line names no `--plant`", path.display()));
    let plant_path = path.with_file_name(plant_name);
    let plant = Plant::load(&Source::read(&plant_path).unwrap_or_else(|e| panic!("{e}")))
        .unwrap_or_else(|e| panic!("{e}"));
    let records = parse_log(&source, &plant).unwrap_or_else(|e| panic!("{e}"));
    let mut theory = plant.theory().expect("the plant encodes");
    let mut estimator = TimedMe::new(TimedMeOptions::kappa(10));
    let updates = replay(&plant, &mut theory, &mut estimator, &records)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(updates.len(), records.len());
}

/// Every file under `docs/examples/` loads with its format's loader and does what it is shown
/// doing.
#[test]
fn every_example_loads() {
    let all = files(&root().join("docs/examples"));
    let scenarios: Vec<PathBuf> = all
        .iter()
        .filter(|p| {
            p.extension().is_some_and(|e| e == "ron")
                && std::fs::read_to_string(p).is_ok_and(|t| top_level(&t) == "Scenario")
        })
        .cloned()
        .collect();
    for path in &all {
        match path.extension().and_then(|e| e.to_str()) {
            Some("ron") => load_ron(path, &scenarios),
            Some("rmpl") => {
                let source = Source::read(path).unwrap_or_else(|e| panic!("{e}"));
                rmpl::load(&source, &LinkOptions::default()).unwrap_or_else(|e| panic!("{e}"));
            }
            Some("jsonl") if path.file_name().is_some_and(|n| n == "runs.jsonl") => {
                load_records(path)
            }
            Some("jsonl") => replay_log(path),
            Some("txt") => assert!(
                path.with_file_name("runs.jsonl").exists(),
                "{}: a summary without its records",
                path.display()
            ),
            _ => panic!("{}: no loader for this file", path.display()),
        }
    }
}

/// The example file a fenced block shows: named on its first line (`// docs/examples/...`,
/// `# docs/examples/...`) or by a `<!-- example: docs/examples/... -->` line before the fence.
fn named_file(before: &str, first: &str) -> Option<String> {
    if let Some(path) = before
        .trim()
        .strip_prefix("<!-- example: ")
        .and_then(|r| r.strip_suffix(" -->"))
    {
        return Some(path.to_string());
    }
    let rest = first
        .strip_prefix("// ")
        .or_else(|| first.strip_prefix("# "))?;
    let path = rest.split([':', ' ']).next()?;
    path.starts_with("docs/examples/").then(|| path.to_string())
}

/// Every example a page shows is the file it names, verbatim; every reference page but the
/// index, the constraint language (formulas live in the other formats) and the trace (an
/// output) shows one.
#[test]
fn pages_show_the_example_files() {
    let mut pages = files(&root().join("docs/reference"));
    pages.push(root().join("docs/modelling.md"));
    for page in &pages {
        let text = std::fs::read_to_string(page).unwrap_or_else(|e| panic!("{e}"));
        let lines: Vec<&str> = text.lines().collect();
        let mut shown = 0;
        let mut i = 0;
        while i < lines.len() {
            if lines[i].starts_with("```") && lines[i].len() > 3 {
                let end = (i + 1..lines.len())
                    .find(|&j| lines[j].starts_with("```"))
                    .unwrap_or_else(|| panic!("{}: an unclosed block", page.display()));
                let before = if i > 0 { lines[i - 1] } else { "" };
                if let Some(name) = named_file(before, lines.get(i + 1).copied().unwrap_or("")) {
                    let file = std::fs::read_to_string(root().join(&name))
                        .unwrap_or_else(|e| panic!("{}: {name}: {e}", page.display()));
                    let block = lines[i + 1..end].join("\n");
                    assert_eq!(
                        block,
                        file.trim_end(),
                        "{} shows {name} other than it is",
                        page.display()
                    );
                    shown += 1;
                }
                i = end + 1;
            } else {
                i += 1;
            }
        }
        let name = page.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if !["README.md", "constraint-language.md", "trace.md"].contains(&name) {
            assert!(shown > 0, "{} shows no example file", page.display());
        }
    }
}

/// The index lists every reference page.
#[test]
fn the_index_lists_every_page() {
    let index = std::fs::read_to_string(root().join("docs/reference/README.md")).expect("index");
    for page in files(&root().join("docs/reference")) {
        let name = page.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name != "README.md" {
            assert!(
                index.contains(&format!("({name})")),
                "README.md does not link {name}"
            );
        }
    }
}

/// The keys of a trace line's objects (the estimate and a belief's `modes` are maps keyed by
/// component names, `monitored` by observables: their keys are data, not fields).
fn keys(value: &serde_json::Value, out: &mut BTreeSet<String>) {
    match value {
        serde_json::Value::Object(map) => {
            for (key, inner) in map {
                out.insert(key.clone());
                if key != "estimate" && key != "modes" && key != "monitored" {
                    keys(inner, out);
                }
            }
        }
        serde_json::Value::Array(items) => items.iter().for_each(|i| keys(i, out)),
        _ => {}
    }
}

/// `docs/reference/trace.md` has a row for every key the full trace of a run writes, and every
/// key it has a row for is written: the runs are `docs/examples/intermittent/stall.ron`, which
/// has a diagnosis with another candidate, a preemption, rules and commands, and
/// `scenarios/thermostat/telemetry.ron`, whose plant has a monitor.
#[test]
fn the_trace_page_documents_every_key() {
    let mut written = BTreeSet::new();
    for example in [
        "docs/examples/intermittent/stall.ron",
        "scenarios/thermostat/telemetry.ron",
    ] {
        let scenario = simulation::load(&root().join(example)).unwrap_or_else(|e| panic!("{e}"));
        let mut trace = Trace::full();
        simulation::run(&scenario, RunOptions::default(), &mut |record| {
            let line: serde_json::Value =
                serde_json::from_str(&trace.line(&scenario, record)).expect("a JSON line");
            keys(&line, &mut written);
        })
        .unwrap_or_else(|e| panic!("{e}"));
    }
    let page = std::fs::read_to_string(root().join("docs/reference/trace.md")).expect("page");
    let documented: BTreeSet<String> = page
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .map(str::to_string)
        .collect();
    let missing: Vec<&String> = written.difference(&documented).collect();
    let stale: Vec<&String> = documented.difference(&written).collect();
    assert!(
        missing.is_empty() && stale.is_empty(),
        "trace.md lacks {missing:?}; documents keys never written: {stale:?}"
    );
}
