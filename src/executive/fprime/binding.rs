//! The binding file: which F´ telemetry channel reports which plant observable, and which F´
//! command (with which arguments) carries which value of a plant control. RON:
//!
//! ```ron
//! Binding(
//!     telemetry: [
//!         // The channel's value, as its enumeration constant (or `true` / `false` for a
//!         // `bool` channel), maps to the observable's value.
//!         Channel(channel: "Prop.prop.Valve1Outlet", observable: "valve1.outlet",
//!                 values: { "LOW": "low", "HIGH": "high" }),
//!     ],
//!     commands: [
//!         // Each value of a control other than its idle value is sent as one command.
//!         Command(control: "PDE.cmd = on", command: "Prop.prop.PDE_ON"),
//!         Command(control: "PDE.cmd = open1", command: "Prop.prop.VALVE_OPEN", args: [Int(1)]),
//!     ],
//! )
//! ```
//!
//! `values` may be left out: each constant then maps to the observable's value of the same name,
//! compared without case, `-` or `_` (`STUCK_OPEN` → `stuck-open`). Arguments are `Int(n)`,
//! `Float(x)`, `Bool(b)`, `Enum("CONSTANT")` or `Str("text")`, one per formal parameter, in
//! order.
//!
//! [`Binding::load`] checks a binding against the dictionary and the plant, every problem
//! located in the file: each channel and command exists in the dictionary; each observable is
//! one of the plant's, bound once, and every one is bound; the channel's type is an enumeration
//! or `bool`, or a number when the plant model declares a *monitor* for the observable (the
//! monitor turns the channel's numbers into the observable's values; a numeric channel for an
//! observable without a monitor is refused); every value map entry names a constant of the
//! channel and a value of the observable; every non-idle value of every control is bound to one
//! command, whose arguments match its formal parameters in number and type (an integer within
//! its type's range, a constant of its enumeration, a string within its size).

use std::collections::BTreeMap;
use std::fmt;

use serde::Deserialize;

use super::dictionary::{Channel, Dictionary, FprimeType};
use crate::diagnostic::locate::{Entries, Locator, Step};
use crate::diagnostic::{Diagnostic, Source, SourceErrors, did_you_mean, ron_error};
use crate::executive::NamedValue;
use crate::plant::Plant;

/// One argument of a bound command.
#[derive(Debug, Clone, PartialEq)]
pub enum FprimeArg {
    /// An integer (any of `U8` … `I64`; a `U64` above `i64::MAX` cannot be bound).
    Int(i64),
    /// A float.
    Float(f64),
    /// A boolean.
    Bool(bool),
    /// An enumeration constant and its value.
    Enum {
        /// The constant's name.
        constant: String,
        /// Its value.
        value: i64,
    },
    /// A string.
    Str(String),
}

impl fmt::Display for FprimeArg {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FprimeArg::Int(n) => write!(f, "{n}"),
            FprimeArg::Float(x) => write!(f, "{x}"),
            FprimeArg::Bool(b) => write!(f, "{b}"),
            FprimeArg::Enum { constant, .. } => f.write_str(constant),
            FprimeArg::Str(s) => write!(f, "{s:?}"),
        }
    }
}

/// The F´ command a control value is sent as.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundCommand {
    /// The control assignment (`PDE.cmd = open1`).
    pub control: NamedValue,
    /// The command's qualified name (`Prop.prop.VALVE_OPEN`).
    pub command: String,
    /// Its opcode.
    pub opcode: u32,
    /// Its arguments, one per formal parameter.
    pub args: Vec<FprimeArg>,
}

impl fmt::Display for BoundCommand {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let args: Vec<String> = self.args.iter().map(ToString::to_string).collect();
        write!(
            f,
            "{}({}) [opcode {:#x}]",
            self.command,
            args.join(", "),
            self.opcode
        )
    }
}

/// A channel bound to an observable.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundChannel {
    /// The channel.
    pub channel: Channel,
    /// The observable it reports (`valve1.outlet`).
    pub observable: String,
    /// The channel's symbols (constants, `true`/`false`) and the observable value each stands for.
    values: Vec<(String, String)>,
}

/// A telemetry value as F´ reports it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TelemetryValue {
    /// An enumeration's value (its representation: `Prop.Pressure.HIGH` is 1).
    Enum(i64),
    /// A boolean.
    Bool(bool),
    /// An integer.
    Integer(i64),
    /// A float.
    Float(f64),
}

impl fmt::Display for TelemetryValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TelemetryValue::Enum(v) => write!(f, "enumeration value {v}"),
            TelemetryValue::Bool(b) => write!(f, "bool {b}"),
            TelemetryValue::Integer(n) => write!(f, "integer {n}"),
            TelemetryValue::Float(x) => write!(f, "float {x}"),
        }
    }
}

/// Why a telemetry value could not be turned into an observation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TelemetryError {
    /// The id is no channel of the dictionary.
    #[error("no channel of the dictionary has id {0:#x}")]
    UnknownChannel(u32),
    /// The value is not of the channel's type.
    #[error("channel {channel} is of type {expected}, and was given a {given}")]
    WrongType {
        /// The channel's name.
        channel: String,
        /// Its type.
        expected: String,
        /// What was given.
        given: TelemetryValue,
    },
}

/// A checked binding of an F´ dictionary to a plant model.
#[derive(Debug, Clone, PartialEq)]
pub struct Binding {
    /// Every channel of the dictionary by id (a channel not bound is ignored, an id not in the
    /// dictionary is an error).
    channels: BTreeMap<u32, Channel>,
    /// The bound channels by id.
    bound: BTreeMap<u32, BoundChannel>,
    /// The bound commands.
    commands: Vec<BoundCommand>,
}

impl Binding {
    /// Reads and checks the binding in `source` against the dictionary and the plant (see the
    /// module documentation); every problem is located in `source`.
    pub fn load(
        source: &Source,
        dictionary: &Dictionary,
        plant: &Plant,
    ) -> Result<Binding, SourceErrors> {
        let located = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
        let options = ron::Options::default()
            .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
        let file: BindingFile = options
            .from_str(&source.text)
            .map_err(|e| located(vec![ron_error(source, &e)]))?;
        let mut checker = Checker {
            dictionary,
            plant,
            locate: Locator::new(&source.text),
            errors: Vec::new(),
        };
        let bound = checker.channels(&file.telemetry);
        let commands = checker.commands(&file.commands);
        if !checker.errors.is_empty() {
            return Err(located(checker.errors));
        }
        Ok(Binding {
            channels: (dictionary.channels.iter())
                .map(|c| (c.id, c.clone()))
                .collect(),
            bound: bound.into_iter().map(|b| (b.channel.id, b)).collect(),
            commands,
        })
    }

    /// The bound channels, by id.
    pub fn channels(&self) -> impl Iterator<Item = &BoundChannel> {
        self.bound.values()
    }

    /// The bound commands, in the file's order.
    pub fn commands(&self) -> &[BoundCommand] {
        &self.commands
    }

    /// The observation a telemetry value stands for: `None` for a channel of the dictionary that
    /// is not bound (telemetry the plant model does not reason about). A constant the binding
    /// does not map, or a value that is no constant of the channel's enumeration, becomes an
    /// observation whose value the executive rejects (an event, and the cycle goes on); a value
    /// of the wrong type, or an id that is no channel, is an error.
    pub fn observe(
        &self,
        id: u32,
        value: TelemetryValue,
    ) -> Result<Option<NamedValue>, TelemetryError> {
        let Some(channel) = self.channels.get(&id) else {
            return Err(TelemetryError::UnknownChannel(id));
        };
        let symbol = match (&channel.ty, value) {
            (FprimeType::Enum { name, .. }, TelemetryValue::Enum(v)) => {
                match channel.ty.constant_named(v) {
                    Some(constant) => constant.to_string(),
                    None => format!("{v} (no constant of {name})"),
                }
            }
            (FprimeType::Bool, TelemetryValue::Bool(b)) => b.to_string(),
            (FprimeType::Integer { .. }, TelemetryValue::Integer(x))
            | (FprimeType::Float { .. }, TelemetryValue::Integer(x)) => {
                // A reading for the observable's monitor (a count as a number: an integer
                // beyond 2^53 loses its last digits, far outside any monitor's range).
                return Ok(self.reading(id, x as f64));
            }
            (FprimeType::Float { .. }, TelemetryValue::Float(x)) => {
                return Ok(self.reading(id, x));
            }
            (ty, given) => {
                return Err(TelemetryError::WrongType {
                    channel: channel.name.clone(),
                    expected: ty.to_string(),
                    given,
                });
            }
        };
        let Some(bound) = self.bound.get(&id) else {
            return Ok(None);
        };
        let value = (bound.values.iter())
            .find(|(s, _)| *s == symbol)
            .map_or(symbol, |(_, v)| v.clone());
        Ok(Some(NamedValue::new(bound.observable.clone(), value)))
    }

    /// A numeric channel's value as a reading of the monitored observable it is bound to
    /// (`None` when it is not bound).
    fn reading(&self, id: u32, x: f64) -> Option<NamedValue> {
        (self.bound.get(&id)).map(|bound| NamedValue::new(bound.observable.clone(), x))
    }

    /// The command a control assignment is sent as (`None` for an idle value, or an assignment
    /// of another plant).
    pub fn command(&self, assignment: &NamedValue) -> Option<&BoundCommand> {
        self.commands.iter().find(|c| c.control == *assignment)
    }
}

#[derive(Deserialize)]
#[serde(rename = "Binding", deny_unknown_fields)]
struct BindingFile {
    #[serde(default)]
    telemetry: Vec<ChannelFile>,
    #[serde(default)]
    commands: Vec<CommandFile>,
}

#[derive(Deserialize)]
#[serde(rename = "Channel", deny_unknown_fields)]
struct ChannelFile {
    channel: String,
    observable: String,
    values: Option<Entries<String>>,
}

#[derive(Deserialize)]
#[serde(rename = "Command", deny_unknown_fields)]
struct CommandFile {
    control: String,
    command: String,
    #[serde(default)]
    args: Vec<ArgFile>,
}

#[derive(Deserialize)]
enum ArgFile {
    Int(i64),
    Float(f64),
    Bool(bool),
    Enum(String),
    Str(String),
}

/// Names compared as a binding's default value map and the suggestion compare them: without
/// case, `-`, `_`, `.` or spaces.
pub(super) fn normalized(name: &str) -> String {
    (name.chars())
        .filter(|c| c.is_alphanumeric())
        .flat_map(char::to_lowercase)
        .collect()
}

struct Checker<'a> {
    dictionary: &'a Dictionary,
    plant: &'a Plant,
    locate: Locator,
    errors: Vec<Diagnostic>,
}

impl Checker<'_> {
    fn error(&mut self, path: &[Step], message: String, expected: impl Into<String>) {
        let span = self.locate.at(path);
        self.errors
            .push(Diagnostic::new(message, span).expected(expected));
    }

    fn channels(&mut self, files: &[ChannelFile]) -> Vec<BoundChannel> {
        // An observable left unbound by a channel entry in error is not reported twice.
        let before = self.errors.len();
        let mut bound: Vec<BoundChannel> = Vec::new();
        for (i, file) in files.iter().enumerate() {
            let at = |field| [Step::Field("telemetry"), Step::Index(i), Step::Field(field)];
            if let Some(channel) = self.channel(file, &at("channel"))
                && let Some(observable) = self.observable(&file.observable, &at("observable"))
                && self.symbolic(&channel, &observable, &at("channel"))
            {
                if bound.iter().any(|b| b.channel.id == channel.id) {
                    let message = format!("channel `{}` is bound twice", channel.name);
                    self.error(&at("channel"), message, "each channel once");
                    continue;
                }
                if bound.iter().any(|b| b.observable == observable) {
                    let message = format!("observable `{observable}` is bound to two channels");
                    self.error(&at("observable"), message, "each observable once");
                    continue;
                }
                let values = self.values(file, &channel, &observable, i);
                bound.push(BoundChannel {
                    channel,
                    observable,
                    values,
                });
            }
        }
        let table = self.plant.table();
        let unbound: Vec<&str> = (self.plant.observables().iter())
            .map(|&var| table.variable(var).name())
            .filter(|name| !bound.iter().any(|b| b.observable == *name))
            .collect();
        if !unbound.is_empty() && self.errors.len() == before {
            let message = format!("no channel reports {}", unbound.join(", "));
            self.error(
                &[Step::Field("telemetry")],
                message,
                "a `Channel(...)` for every observable of the plant model",
            );
        }
        bound
    }

    fn channel(&mut self, file: &ChannelFile, at: &[Step]) -> Option<Channel> {
        if let Some(channel) = self.dictionary.channel_named(&file.channel) {
            return Some(channel.clone());
        }
        let names = self.dictionary.channels.iter().map(|c| c.name.as_str());
        let mut diagnostic = Diagnostic::new(
            format!("no telemetry channel `{}` in the dictionary", file.channel),
            self.locate.at(at),
        )
        .expected(format!("a channel of {}", self.dictionary.deployment));
        if let Some(close) = did_you_mean(&file.channel, names) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    fn observable(&mut self, name: &str, at: &[Step]) -> Option<String> {
        let table = self.plant.table();
        let observables = self.plant.observables();
        if table
            .variable_id(name)
            .is_some_and(|var| observables.contains(&var))
        {
            return Some(name.to_string());
        }
        let names: Vec<&str> = observables
            .iter()
            .map(|&v| table.variable(v).name())
            .collect();
        let mut diagnostic = Diagnostic::new(
            format!("`{name}` is not an observable of the plant model"),
            self.locate.at(at),
        )
        .expected(format!("one of: {}", names.join(", ")));
        if let Some(close) = did_you_mean(name, names.iter().copied()) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
        None
    }

    /// A symbolic channel binds to any observable, a numeric one to an observable the plant
    /// model monitors.
    fn symbolic(&mut self, channel: &Channel, observable: &str, at: &[Step]) -> bool {
        match &channel.ty {
            FprimeType::Enum { .. } | FprimeType::Bool => true,
            ty if ty.is_numeric() => {
                let table = self.plant.table();
                let monitored = (table.variable_id(observable))
                    .is_some_and(|var| self.plant.monitor_of(var).is_some());
                if !monitored {
                    let message = format!(
                        "channel `{}` is numeric ({ty}): reporting `{observable}` from it needs a \
                         monitor turning its numbers into `{observable}`'s values, and the plant \
                         model declares none for `{observable}`",
                        channel.name
                    );
                    self.error(
                        at,
                        message,
                        "an enumeration or bool channel, or a monitored observable",
                    );
                }
                monitored
            }
            ty => {
                let message = format!(
                    "channel `{}` is of type {ty}, which cannot report a mode value",
                    channel.name
                );
                self.error(at, message, "an enumeration or bool channel");
                false
            }
        }
    }

    fn values(
        &mut self,
        file: &ChannelFile,
        channel: &Channel,
        observable: &str,
        i: usize,
    ) -> Vec<(String, String)> {
        let table = self.plant.table();
        let Some(variable) = table.variable_id(observable).map(|v| table.variable(v)) else {
            return Vec::new();
        };
        let symbols = channel.ty.symbols();
        let Some(entries) = &file.values else {
            // By name: the constants that match a value of the observable.
            return (symbols.iter())
                .filter_map(|s| {
                    let value =
                        (variable.values().iter()).find(|v| normalized(v) == normalized(s))?;
                    Some((s.to_string(), value.clone()))
                })
                .collect();
        };
        let mut values = Vec::new();
        for (symbol, value) in &entries.0 {
            let at = [
                Step::Field("telemetry"),
                Step::Index(i),
                Step::Field("values"),
            ];
            if !symbols.contains(&symbol.as_str()) {
                let message = format!(
                    "`{symbol}` is not a value of channel `{}` ({})",
                    channel.name, channel.ty
                );
                let key = [&at[..], &[Step::Key(symbol)]].concat();
                self.error(&key, message, format!("one of: {}", symbols.join(", ")));
            } else if variable.value(value).is_none() {
                let message = format!("`{value}` is not a value of `{observable}`");
                let entry = [&at[..], &[Step::Value(symbol)]].concat();
                self.error(
                    &entry,
                    message,
                    format!("one of: {}", variable.values().join(", ")),
                );
            } else if values.iter().any(|(s, _)| s == symbol) {
                let key = [&at[..], &[Step::Key(symbol)]].concat();
                self.error(
                    &key,
                    format!("`{symbol}` is mapped twice"),
                    "each constant once",
                );
            } else {
                values.push((symbol.clone(), value.clone()));
            }
        }
        values
    }

    fn commands(&mut self, files: &[CommandFile]) -> Vec<BoundCommand> {
        let before = self.errors.len();
        let mut bound: Vec<BoundCommand> = Vec::new();
        for (i, file) in files.iter().enumerate() {
            let at = |field| [Step::Field("commands"), Step::Index(i), Step::Field(field)];
            let Some(control) = self.control(&file.control, &at("control")) else {
                continue;
            };
            let Some(command) = self.dictionary.command_named(&file.command) else {
                let names = self.dictionary.commands.iter().map(|c| c.name.as_str());
                let mut diagnostic = Diagnostic::new(
                    format!("no command `{}` in the dictionary", file.command),
                    self.locate.at(&at("command")),
                )
                .expected(format!("a command of {}", self.dictionary.deployment));
                if let Some(close) = did_you_mean(&file.command, names) {
                    diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
                }
                self.errors.push(diagnostic);
                continue;
            };
            let Some(args) = self.args(file, command, i) else {
                continue;
            };
            if bound.iter().any(|b| b.control == control) {
                let message = format!("`{control}` is bound twice");
                self.error(&at("control"), message, "each control value once");
                continue;
            }
            if let Some(other) = bound
                .iter()
                .find(|b| b.opcode == command.opcode && b.args == args)
            {
                let message = format!(
                    "`{control}` is sent as the same command as `{}`: the two could not be told apart",
                    other.control
                );
                self.error(&at("command"), message, "a command or arguments of its own");
                continue;
            }
            bound.push(BoundCommand {
                control,
                command: command.name.clone(),
                opcode: command.opcode,
                args,
            });
        }
        let table = self.plant.table();
        let mut unbound = Vec::new();
        for control in self.plant.controls() {
            let variable = table.variable(control.var);
            for (v, value) in variable.values().iter().enumerate() {
                let assignment = NamedValue::new(variable.name(), value.as_str());
                if v != control.idle.index() && !bound.iter().any(|b| b.control == assignment) {
                    unbound.push(assignment.to_string());
                }
            }
        }
        if !unbound.is_empty() && self.errors.len() == before {
            let message = format!("no command sends {}", unbound.join(", "));
            self.error(
                &[Step::Field("commands")],
                message,
                "a `Command(...)` for every value of every control but its idle one",
            );
        }
        bound
    }

    /// `variable = value`, a non-idle value of one of the plant's controls.
    fn control(&mut self, text: &str, at: &[Step]) -> Option<NamedValue> {
        let table = self.plant.table();
        let expected =
            "`control = value`, a value of one of the plant's controls other than its idle value";
        let Some((variable, value)) = text.split_once('=') else {
            self.error(at, format!("`{text}` is not an assignment"), expected);
            return None;
        };
        let (variable, value) = (variable.trim(), value.trim());
        let control = table
            .variable_id(variable)
            .and_then(|var| self.plant.controls().iter().find(|c| c.var == var));
        let Some(control) = control else {
            let names: Vec<&str> = (self.plant.controls().iter())
                .map(|c| table.variable(c.var).name())
                .collect();
            let message = format!("`{variable}` is not a control of the plant model");
            self.error(at, message, format!("one of: {}", names.join(", ")));
            return None;
        };
        let var = table.variable(control.var);
        match var.value(value) {
            None => {
                let message = format!("`{value}` is not a value of `{variable}`");
                self.error(at, message, format!("one of: {}", var.values().join(", ")));
                None
            }
            Some(v) if v == control.idle => {
                let message = format!("`{value}` is `{variable}`'s idle value: it is never sent");
                self.error(at, message, expected);
                None
            }
            Some(_) => Some(NamedValue::new(variable, value)),
        }
    }

    fn args(
        &mut self,
        file: &CommandFile,
        command: &super::dictionary::Command,
        i: usize,
    ) -> Option<Vec<FprimeArg>> {
        let at = [Step::Field("commands"), Step::Index(i), Step::Field("args")];
        if file.args.len() != command.params.len() {
            let params: Vec<String> = (command.params.iter())
                .map(|(name, ty)| format!("{name}: {ty}"))
                .collect();
            let message = format!(
                "`{}` takes {} argument(s), and {} are given",
                command.name,
                command.params.len(),
                file.args.len()
            );
            self.error(&at, message, format!("({})", params.join(", ")));
            return None;
        }
        let mut args = Vec::new();
        for (k, (arg, (name, ty))) in file.args.iter().zip(&command.params).enumerate() {
            match argument(arg, ty) {
                Ok(arg) => args.push(arg),
                Err(expected) => {
                    let message =
                        format!("argument `{name}` of `{}` is of type {ty}", command.name);
                    self.error(&[&at[..], &[Step::Index(k)]].concat(), message, expected);
                }
            }
        }
        (args.len() == command.params.len()).then_some(args)
    }
}

/// The argument checked against its parameter's type; what was expected otherwise.
fn argument(arg: &ArgFile, ty: &FprimeType) -> Result<FprimeArg, String> {
    match (arg, ty) {
        (ArgFile::Int(n), FprimeType::Integer { signed, bits, .. }) => {
            let (min, max) = integer_range(*signed, *bits);
            if i128::from(*n) >= min && i128::from(*n) <= max {
                Ok(FprimeArg::Int(*n))
            } else {
                Err(format!("Int(n) with {min} <= n <= {max}"))
            }
        }
        (ArgFile::Float(x), FprimeType::Float { .. }) => Ok(FprimeArg::Float(*x)),
        (ArgFile::Bool(b), FprimeType::Bool) => Ok(FprimeArg::Bool(*b)),
        (ArgFile::Enum(constant), FprimeType::Enum { constants, .. }) => (constants.iter())
            .find(|(c, _)| c == constant)
            .map(|(c, v)| FprimeArg::Enum {
                constant: c.clone(),
                value: *v,
            })
            .ok_or_else(|| {
                let names: Vec<&str> = constants.iter().map(|(c, _)| c.as_str()).collect();
                format!("Enum(\"...\") with one of: {}", names.join(", "))
            }),
        (ArgFile::Str(s), FprimeType::String { size }) => match size {
            Some(size) if s.chars().count() as u64 > *size => {
                Err(format!("Str(\"...\") of at most {size} characters"))
            }
            _ => Ok(FprimeArg::Str(s.clone())),
        },
        (_, ty) => Err(expected_arg(ty).to_string()),
    }
}

/// How an argument of type `ty` is written.
fn expected_arg(ty: &FprimeType) -> &'static str {
    match ty {
        FprimeType::Integer { .. } => "Int(n)",
        FprimeType::Float { .. } => "Float(x)",
        FprimeType::Bool => "Bool(true) or Bool(false)",
        FprimeType::Enum { .. } => "Enum(\"CONSTANT\")",
        FprimeType::String { .. } => "Str(\"text\")",
        FprimeType::Other { .. } => "nothing: arrays and structs cannot be bound",
    }
}

/// The values an integer type holds.
fn integer_range(signed: bool, bits: u32) -> (i128, i128) {
    let bits = bits.clamp(1, 64);
    if signed {
        (-(1i128 << (bits - 1)), (1i128 << (bits - 1)) - 1)
    } else {
        (0, (1i128 << bits) - 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn binding() -> Binding {
        let dictionary = Source::new(
            "PropulsionTopologyDictionary.json",
            include_str!("../../../models/fprime/PropulsionTopologyDictionary.json"),
        );
        let dictionary = Dictionary::load(&dictionary).expect("the committed dictionary loads");
        let plant = Source::new(
            "propulsion.ron",
            include_str!("../../../models/propulsion.ron"),
        );
        let plant = Plant::load(&plant).expect("the plant loads");
        let binding = Source::new(
            "propulsion.binding.ron",
            include_str!("../../../models/fprime/propulsion.binding.ron"),
        );
        Binding::load(&binding, &dictionary, &plant).expect("the committed binding checks")
    }

    /// DESIGN.md §10, §13 at the F´ boundary: a constant becomes the observable's value; a value
    /// that is no constant reaches the executive as a value it rejects (an event); an unbound
    /// numeric channel is ignored; a wrong type or an unknown id is an error.
    #[test]
    fn telemetry_becomes_observations_events_or_errors() {
        let binding = binding();
        let observe = |id, value| binding.observe(id, value);
        assert_eq!(
            observe(0x120, TelemetryValue::Enum(1)),
            Ok(Some(NamedValue::new("valve1.outlet", "high")))
        );
        assert_eq!(
            observe(0x120, TelemetryValue::Enum(7)),
            Ok(Some(NamedValue::new(
                "valve1.outlet",
                "7 (no constant of Prop.Pressure)"
            )))
        );
        assert_eq!(observe(0x125, TelemetryValue::Float(f64::NAN)), Ok(None));
        assert!(matches!(
            observe(0x120, TelemetryValue::Float(1.0)),
            Err(TelemetryError::WrongType { .. })
        ));
        assert_eq!(
            observe(0x999, TelemetryValue::Enum(0)),
            Err(TelemetryError::UnknownChannel(0x999))
        );
    }

    /// `plant::monitor` at the F´ boundary: a numeric channel binds to an observable the plant
    /// model monitors (the thermostat's sensor, in °C), and its values reach the executive as
    /// readings, integers as numbers too.
    #[test]
    fn a_numeric_channel_binds_to_a_monitored_observable_and_passes_readings() {
        let dictionary = Source::new(
            "PropulsionTopologyDictionary.json",
            include_str!("../../../models/fprime/PropulsionTopologyDictionary.json"),
        );
        let dictionary = Dictionary::load(&dictionary).expect("the committed dictionary loads");
        let plant = Source::new(
            "thermostat.ron",
            include_str!("../../../models/thermostat.ron"),
        );
        let plant = Plant::load(&plant).expect("the plant loads");
        let commands: String = (1..=2)
            .flat_map(|n| {
                [("open", "VALVE_OPEN"), ("close", "VALVE_CLOSE")].map(|(value, command)| {
                    format!(
                        "Command(control: \"switch{n}.cmd = {value}\", command: \"Prop.prop.{command}\", args: [Int({n})]),"
                    )
                })
            })
            .collect();
        let binding = Source::new(
            "thermostat.binding.ron",
            format!(
                "Binding(telemetry: [Channel(channel: \"Prop.prop.Tank1Pressure\", \
                 observable: \"sensor.reading\")], commands: [{commands}])"
            ),
        );
        let binding = Binding::load(&binding, &dictionary, &plant)
            .expect("a numeric channel binds to a monitored observable");
        assert_eq!(
            binding.observe(0x125, TelemetryValue::Float(21.4)),
            Ok(Some(NamedValue::new("sensor.reading", 21.4)))
        );
        assert_eq!(
            binding.observe(0x125, TelemetryValue::Integer(30)),
            Ok(Some(NamedValue::new("sensor.reading", 30.0)))
        );
    }

    /// A control value is sent as its command with its arguments; the idle value as nothing.
    #[test]
    fn control_values_are_sent_as_their_commands() {
        let binding = binding();
        let open2 = binding
            .command(&NamedValue::new("PDE.cmd", "open2"))
            .expect("bound");
        assert_eq!(open2.to_string(), "Prop.prop.VALVE_OPEN(2) [opcode 0x123]");
        assert_eq!(binding.command(&NamedValue::new("PDE.cmd", "none")), None);
    }
}
