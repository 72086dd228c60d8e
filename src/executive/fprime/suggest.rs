//! A starting binding, by name similarity: each observable gets the symbolic channel whose last
//! name segment reads most like it (`valve1.outlet` ↔ `Prop.prop.Valve1Outlet`), its values the
//! constants that read like them; each control value gets the command that reads most like it
//! (`PDE.cmd = engine-standby` ↔ `ENGINE_STANDBY`, `PDE.cmd = on` ↔ `PDE_ON`, `PDE.cmd = open1`
//! ↔ `VALVE_OPEN` with the trailing `1` as its integer argument). What it cannot match it leaves
//! as a comment saying so; arguments it had to guess are marked. It is a start, to be read and
//! checked (`kairos bind --binding`), never a binding trusted as written.

use std::fmt::Write;

use super::binding::normalized;
use super::dictionary::{Command, Dictionary, FprimeType};
use crate::plant::Plant;

/// Below this similarity (Jaro–Winkler on normalized names) no match is proposed.
const THRESHOLD: f64 = 0.8;

/// The starting binding of `plant` to `dictionary`, as the text of a binding file.
pub fn suggest(dictionary: &Dictionary, plant: &Plant) -> String {
    let mut out = String::new();
    out.push_str(&format!(
        "// A starting binding of the plant model `{}` to the F´ deployment `{}`, matched by\n\
         // name similarity: read every line, then check it with `kairos bind --binding`.\n\
         Binding(\n    telemetry: [\n",
        plant.name(),
        dictionary.deployment
    ));
    telemetry(dictionary, plant, &mut out);
    out.push_str("    ],\n    commands: [\n");
    commands(dictionary, plant, &mut out);
    out.push_str("    ],\n)\n");
    out
}

fn last_segment(name: &str) -> &str {
    name.rsplit('.').next().unwrap_or(name)
}

fn similarity(a: &str, b: &str) -> f64 {
    strsim::jaro_winkler(&normalized(a), &normalized(b))
}

fn telemetry(dictionary: &Dictionary, plant: &Plant, out: &mut String) {
    let table = plant.table();
    let mut taken = Vec::new();
    for &var in plant.observables() {
        let variable = table.variable(var);
        let best = (dictionary.channels.iter())
            .filter(|c| matches!(c.ty, FprimeType::Enum { .. } | FprimeType::Bool))
            .filter(|c| !taken.contains(&c.id))
            .map(|c| (similarity(variable.name(), last_segment(&c.name)), c))
            .filter(|(score, _)| *score >= THRESHOLD)
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let Some((_, channel)) = best else {
            let _ = writeln!(
                out,
                "        // no enumeration or bool channel reads like `{}`",
                variable.name()
            );
            continue;
        };
        taken.push(channel.id);
        let values: Vec<String> = (variable.values().iter())
            .filter_map(|value| {
                let symbols = channel.ty.symbols();
                let (score, symbol) = (symbols.iter())
                    .map(|s| (similarity(value, s), *s))
                    .max_by(|a, b| a.0.total_cmp(&b.0))?;
                (score >= THRESHOLD).then(|| format!("{symbol:?}: {value:?}"))
            })
            .collect();
        let _ = writeln!(
            out,
            "        Channel(channel: {:?}, observable: {:?}, values: {{ {} }}),",
            channel.name,
            variable.name(),
            values.join(", ")
        );
    }
}

fn commands(dictionary: &Dictionary, plant: &Plant, out: &mut String) {
    let table = plant.table();
    for control in plant.controls() {
        let variable = table.variable(control.var);
        let component = variable.name().split('.').next().unwrap_or("");
        for (v, value) in variable.values().iter().enumerate() {
            if v == control.idle.index() {
                continue;
            }
            let control_text = format!("{} = {value}", variable.name());
            let best = (dictionary.commands.iter())
                .map(|c| (command_score(component, value, c), c))
                .filter(|(score, _)| *score >= THRESHOLD)
                .max_by(|a, b| a.0.total_cmp(&b.0));
            let Some((_, command)) = best else {
                let _ = writeln!(out, "        // no command reads like `{control_text}`");
                continue;
            };
            let (args, guessed) = arguments(value, command);
            let mark = if guessed {
                " // arguments guessed: check them"
            } else {
                ""
            };
            let _ = writeln!(
                out,
                "        Command(control: {control_text:?}, command: {:?}, args: [{}]),{mark}",
                command.name,
                args.join(", ")
            );
        }
    }
}

/// How much a command's name reads like `value` (or `component value`). A command whose name
/// contains the value without its trailing digits (`open` of `open1` in `VALVE_OPEN`) ranks
/// above every one that only reads alike (`PDE_ON` reads much like `PDE open1`), the closer
/// reading first among them.
fn command_score(component: &str, value: &str, command: &Command) -> f64 {
    let name = last_segment(&command.name);
    let direct = similarity(value, name).max(similarity(&format!("{component}{value}"), name));
    let stem = normalized(value.trim_end_matches(|c: char| c.is_ascii_digit()));
    if stem.len() >= 3 && normalized(name).contains(&stem) {
        1.0 + direct
    } else {
        direct
    }
}

/// The arguments of `command` for `value`: the value's trailing number for a first integer
/// parameter, and each other parameter's first value (guessed).
fn arguments(value: &str, command: &Command) -> (Vec<String>, bool) {
    let digits = &value[value.trim_end_matches(|c: char| c.is_ascii_digit()).len()..];
    let mut guessed = false;
    let args = (command.params.iter().enumerate())
        .map(|(k, (_, ty))| match ty {
            FprimeType::Integer { .. } if k == 0 && !digits.is_empty() => format!("Int({digits})"),
            ty => {
                guessed = true;
                match ty {
                    FprimeType::Integer { .. } => "Int(0)".to_string(),
                    FprimeType::Float { .. } => "Float(0.0)".to_string(),
                    FprimeType::Bool => "Bool(false)".to_string(),
                    FprimeType::Enum { constants, .. } => constants
                        .first()
                        .map_or_else(|| "Enum(\"\")".to_string(), |(c, _)| format!("Enum({c:?})")),
                    FprimeType::String { .. } => "Str(\"\")".to_string(),
                    FprimeType::Other { name } => format!("/* {name} cannot be bound */"),
                }
            }
        })
        .collect();
    (args, guessed)
}
