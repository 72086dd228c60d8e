//! `kairos check FILES...`: validates plant models, OCSP files, missions, scenarios and rover
//! scenarios (`.ron`, told apart by their top-level struct name) and parses and links RMPL
//! programs (`.rmpl`), reporting every error in each file. A scenario is checked as `kairos run`
//! loads it: with its plant, its program or mission (linked and scheduled) and its scripts. Programs are linked against every plant model given on the same command line, or
//! against the names they use when no model is given.

use std::path::Path;

use kairos::exploration::deep;
use kairos::plant::Plant;
use kairos::rmpl::{self, LinkOptions};
use kairos::simulation::{Scenario, ScenarioProgram};

use super::{Failure, load_plant, read_source};

/// Checks each file; prints a line per good file and fails with every error of the bad ones.
pub fn run(paths: &[impl AsRef<Path>]) -> Result<(), Failure> {
    let (models, programs): (Vec<&Path>, Vec<&Path>) = paths
        .iter()
        .map(AsRef::as_ref)
        .partition(|p| extension(p) == Some("ron"));
    let mut problems = Vec::new();
    let mut plants = Vec::new();
    for path in models {
        let source = match read_source(path) {
            Ok(source) => source,
            Err(failure) => {
                problems.push(failure.message);
                continue;
            }
        };
        match ron_struct_name(&source.text) {
            Some("Mission") => {
                check_file(path, kairos::goalnet::mission::load(path), |mission| {
                    format!(
                        "mission on {} ({}, {})",
                        mission.plant_path,
                        count(mission.network.points().len(), "time point"),
                        count(mission.network.goals().len(), "goal")
                    )
                })
                .unwrap_or_else(|problem| problems.push(problem));
                continue;
            }
            Some("Ocsp") => {
                check_file(path, kairos::opsat::file::load(&source), |instance| {
                    format!(
                        "OCSP ({}, {})",
                        count(instance.ocsp.decisions().len(), "decision variable"),
                        count(instance.theory.table().len(), "variable")
                    )
                })
                .unwrap_or_else(|problem| problems.push(problem));
                continue;
            }
            Some("Scenario") => {
                check_file(path, kairos::simulation::load(path), scenario_summary)
                    .unwrap_or_else(|problem| problems.push(problem));
                continue;
            }
            Some("RoverScenario") => {
                check_file(path, kairos::protocol::scenario::load(path), |rover| {
                    format!(
                        "rover scenario ({})",
                        count(rover.constraints.len(), "constraint")
                    )
                })
                .unwrap_or_else(|problem| problems.push(problem));
                continue;
            }
            Some("Plant") => {}
            other => {
                problems.push(format!(
                    "error: cannot check {}: its top-level value is {}; expected one of `Plant(…)`, \
                     `Ocsp(…)`, `Mission(…)`, `Scenario(…)` or `RoverScenario(…)`",
                    path.display(),
                    other.map_or("not a named struct".to_string(), |name| format!("`{name}(…)`"))
                ));
                continue;
            }
        }
        match load_plant(path) {
            Ok(plant) => {
                println!("ok: {}", model_summary(path, &plant));
                plants.push((path, plant));
            }
            Err(failure) => problems.push(failure.message),
        }
    }
    for path in programs {
        let linked_against: Vec<Option<(&Path, &Plant)>> = if plants.is_empty() {
            vec![None]
        } else {
            plants.iter().map(|(p, plant)| Some((*p, plant))).collect()
        };
        for plant in linked_against {
            match check_program(path, plant) {
                Ok(summary) => println!("ok: {summary}"),
                Err(failure) => problems.push(failure.message),
            }
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(Failure::bad_input(problems.join("\n\n")))
    }
}

/// `ok: PATH: SUMMARY` for a file that loaded, or its errors.
fn check_file<T, E: std::fmt::Display>(
    path: &Path,
    loaded: Result<T, E>,
    summary: impl FnOnce(&T) -> String,
) -> Result<(), String> {
    let loaded = loaded.map_err(|errors| errors.to_string())?;
    println!("ok: {}: {}", path.display(), summary(&loaded));
    Ok(())
}

/// What a scenario that loaded holds: its plant, its program or mission, its rules and
/// expectations (loading links and schedules them all, so a scenario that loads runs).
fn scenario_summary(scenario: &Scenario) -> String {
    let program = match &scenario.program {
        ScenarioProgram::Rmpl(_) => "program",
        ScenarioProgram::Mission(_) => "mission",
    };
    format!(
        "scenario {} ({} {} on {}; {}, {})",
        scenario.name,
        program,
        scenario.program_source.name,
        scenario.plant_path,
        count(scenario.script.rules().len(), "rule"),
        count(scenario.expectations.len(), "expectation"),
    )
}

/// The name of a RON file's top-level struct (`Plant`, `Ocsp`), skipping comments.
fn ron_struct_name(text: &str) -> Option<&str> {
    let mut rest = text;
    loop {
        rest = rest.trim_start();
        if let Some(after) = rest.strip_prefix("//") {
            rest = after.split_once('\n').map_or("", |(_, next)| next);
        } else if let Some(after) = rest.strip_prefix("/*") {
            rest = after.split_once("*/").map_or("", |(_, next)| next);
        } else {
            break;
        }
    }
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
}

fn extension(path: &Path) -> Option<&str> {
    path.extension().and_then(|e| e.to_str())
}

fn model_summary(path: &Path, plant: &Plant) -> String {
    let components = plant.components();
    let modes: usize = components.iter().map(|c| c.modes().len()).sum();
    let transitions: usize = components.iter().map(|c| c.transitions().len()).sum();
    format!(
        "{}: plant {} ({}, {}, {}, {}, {})",
        path.display(),
        plant.name(),
        count(components.len(), "component"),
        count(modes, "mode"),
        count(transitions, "transition"),
        count(plant.controls().len(), "control"),
        count(plant.observables().len(), "observable"),
    )
}

fn check_program(path: &Path, plant: Option<(&Path, &Plant)>) -> Result<String, Failure> {
    if extension(path) != Some("rmpl") {
        return Err(Failure::bad_input(format!(
            "error: cannot check {}: expected a .ron file (plant model, OCSP, mission, scenario) or an RMPL program (.rmpl)",
            path.display()
        )));
    }
    let source = read_source(path)?;
    let options = LinkOptions {
        plant: plant.map(|(_, p)| p.table()),
        ..LinkOptions::default()
    };
    let thca = rmpl::load(&source, &options).map_err(Failure::bad_input)?;
    let against = plant.map_or(String::new(), |(p, _)| {
        format!(", linked against {}", p.display())
    });
    Ok(format!(
        "{}: program {} ({}, {}, {}{against})",
        path.display(),
        thca.name(),
        count(thca.locations().len(), "location"),
        count(thca.table().len(), "variable"),
        count(thca.table().clocks().len(), "clock"),
    ))
}

/// At most this many markings are enumerated per program (the output says when it stopped).
const DEEP_MARKINGS: usize = 200_000;

/// `kairos check --deep PROGRAM... MODEL...`: each program linked against each model and
/// checked statically (`kairos::exploration::deep`); every finding located in its file.
pub fn run_deep(paths: &[impl AsRef<Path>]) -> Result<(), Failure> {
    let (models, programs): (Vec<&Path>, Vec<&Path>) = paths
        .iter()
        .map(AsRef::as_ref)
        .partition(|p| extension(p) == Some("ron"));
    if models.is_empty() || programs.is_empty() {
        return Err(Failure::bad_input(
            "error: --deep checks programs against plant models: give at least one .rmpl program and one .ron model",
        ));
    }
    let mut findings = Vec::new();
    for model in models {
        let source = read_source(model)?;
        let plant = Plant::load(&source).map_err(Failure::bad_input)?;
        for &program in &programs {
            let text = read_source(program)?;
            let options = LinkOptions {
                plant: Some(plant.table()),
                ..LinkOptions::default()
            };
            let thca = rmpl::load(&text, &options).map_err(Failure::bad_input)?;
            let found = deep::deep_check(&thca, &plant, DEEP_MARKINGS)
                .map_err(|e| Failure::bad_input(format!("error: {}: {e}", model.display())))?;
            println!(
                "{}: {}: against {}: {} reachable, {}, {}{}{}",
                if found.conflicts.is_empty()
                    && found.unreachable.is_empty()
                    && found.restless.is_empty()
                {
                    "ok"
                } else {
                    "findings"
                },
                program.display(),
                model.display(),
                count(found.markings, "marking"),
                count(found.conflicts.len(), "goal conflict"),
                count(found.unreachable.len(), "unreachable mode"),
                match found.restless.len() {
                    0 => String::new(),
                    n => format!(", {} the plant leaves by itself", count(n, "goal")),
                },
                match (found.complete, found.undecided) {
                    (false, _) => format!(
                        "; stopped at {DEEP_MARKINGS} markings: conflicts beyond them are not looked for"
                    ),
                    (true, 0) => String::new(),
                    (true, n) => format!(
                        "; {} with clock or confidence atoms not decided",
                        count(n, "goal pair")
                    ),
                }
            );
            let described = deep::describe(&found, &thca, &plant, &source);
            if !described.is_empty() {
                findings.push(described);
            }
        }
    }
    if findings.is_empty() {
        Ok(())
    } else {
        Err(Failure::failed(findings.join("\n")))
    }
}

pub(super) fn count(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}
