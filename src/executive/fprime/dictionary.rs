//! Reading an F´ JSON dictionary, the format `fpp-to-dict` writes (the FPP JSON dictionary
//! specification, version 1.0.0): its telemetry channels (name, id, type) and its commands (name,
//! opcode, formal parameters), each type resolved through the dictionary's type definitions to
//! what a binding can check a value against. Events, parameters, data-product records and
//! containers are skipped: a binding maps channels and commands only. Fields a later version of
//! the specification adds are ignored.

use std::collections::BTreeMap;
use std::fmt;

use serde::Deserialize;

use crate::diagnostic::{Diagnostic, Source, SourceErrors, find_string_literal};

/// A value type of the dictionary, resolved through its aliases.
#[derive(Debug, Clone, PartialEq)]
pub enum FprimeType {
    /// `U8` … `I64`.
    Integer {
        /// Its name (`U8`).
        name: String,
        /// Signed or not.
        signed: bool,
        /// Its width in bits.
        bits: u32,
    },
    /// `F32`, `F64`.
    Float {
        /// Its name (`F32`).
        name: String,
    },
    /// `bool`.
    Bool,
    /// `string`, of at most `size` characters.
    String {
        /// The maximum length, when given.
        size: Option<u64>,
    },
    /// An enumeration: its qualified name and its constants with their values, in order.
    Enum {
        /// Its qualified name (`Prop.Pressure`).
        name: String,
        /// `(constant, value)`.
        constants: Vec<(String, i64)>,
    },
    /// An array or a struct: named, and not bindable to a plant variable.
    Other {
        /// Its qualified name.
        name: String,
    },
}

impl FprimeType {
    /// True for the types whose values are numbers (integers and floats).
    pub fn is_numeric(&self) -> bool {
        matches!(self, FprimeType::Integer { .. } | FprimeType::Float { .. })
    }

    /// The enumeration constant with this value.
    pub fn constant_named(&self, value: i64) -> Option<&str> {
        match self {
            FprimeType::Enum { constants, .. } => (constants.iter())
                .find(|(_, v)| *v == value)
                .map(|(name, _)| name.as_str()),
            _ => None,
        }
    }

    /// The names a value of this type can be written as in a binding's `values` map: the
    /// enumeration's constants, or `true` and `false`; empty for the others.
    pub fn symbols(&self) -> Vec<&str> {
        match self {
            FprimeType::Enum { constants, .. } => {
                constants.iter().map(|(c, _)| c.as_str()).collect()
            }
            FprimeType::Bool => vec!["true", "false"],
            _ => Vec::new(),
        }
    }
}

impl fmt::Display for FprimeType {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FprimeType::Integer { name, .. }
            | FprimeType::Float { name }
            | FprimeType::Enum { name, .. }
            | FprimeType::Other { name } => f.write_str(name),
            FprimeType::Bool => f.write_str("bool"),
            FprimeType::String { size: Some(size) } => write!(f, "string size {size}"),
            FprimeType::String { size: None } => f.write_str("string"),
        }
    }
}

/// A telemetry channel.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// Its qualified name (`Prop.prop.Valve1Outlet`).
    pub name: String,
    /// Its id.
    pub id: u32,
    /// Its value's type.
    pub ty: FprimeType,
}

/// A command.
#[derive(Debug, Clone, PartialEq)]
pub struct Command {
    /// Its qualified name (`Prop.prop.VALVE_OPEN`).
    pub name: String,
    /// Its opcode.
    pub opcode: u32,
    /// Its formal parameters, in order: name and type.
    pub params: Vec<(String, FprimeType)>,
}

/// The channels and commands of an F´ dictionary.
#[derive(Debug, Clone, PartialEq)]
pub struct Dictionary {
    /// The deployment it describes (`metadata.deploymentName`).
    pub deployment: String,
    /// Every telemetry channel, in the dictionary's order.
    pub channels: Vec<Channel>,
    /// Every command, in the dictionary's order.
    pub commands: Vec<Command>,
}

impl Dictionary {
    /// Reads a dictionary from its JSON text; errors point into it.
    pub fn load(source: &Source) -> Result<Dictionary, SourceErrors> {
        let located = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
        let file: DictionaryFile = serde_json::from_str(&source.text).map_err(|e| {
            let at = source.offset_of(e.line(), e.column());
            let message = format!("not an F´ JSON dictionary: {e}");
            located(vec![Diagnostic::new(message, at..at).expected(
                "the JSON `fpp-to-dict` writes (FPP JSON dictionary 1.0.0)",
            )])
        })?;
        let types: BTreeMap<&str, &TypeDefinition> = (file.type_definitions.iter())
            .map(|t| (t.qualified_name.as_str(), t))
            .collect();
        let mut errors = Vec::new();
        let mut resolve = |owner: &str, ty: &TypeRef| match resolve(&types, ty, 0) {
            Ok(ty) => Some(ty),
            Err(message) => {
                let span = find_string_literal(&source.text, owner).unwrap_or(0..0);
                errors.push(Diagnostic::new(format!("`{owner}`: {message}"), span));
                None
            }
        };
        let channels = (file.telemetry_channels.iter())
            .filter_map(|c| {
                Some(Channel {
                    name: c.name.clone(),
                    id: c.id,
                    ty: resolve(&c.name, &c.ty)?,
                })
            })
            .collect();
        let commands = (file.commands.iter())
            .filter_map(|c| {
                let params = (c.formal_params.iter())
                    .map(|p| Some((p.name.clone(), resolve(&c.name, &p.ty)?)))
                    .collect::<Option<Vec<_>>>()?;
                Some(Command {
                    name: c.name.clone(),
                    opcode: c.opcode,
                    params,
                })
            })
            .collect();
        if !errors.is_empty() {
            return Err(located(errors));
        }
        Ok(Dictionary {
            deployment: file.metadata.deployment_name,
            channels,
            commands,
        })
    }

    /// The channel with this qualified name.
    pub fn channel_named(&self, name: &str) -> Option<&Channel> {
        self.channels.iter().find(|c| c.name == name)
    }

    /// The command with this qualified name.
    pub fn command_named(&self, name: &str) -> Option<&Command> {
        self.commands.iter().find(|c| c.name == name)
    }
}

/// Aliases nest; a dictionary whose aliases loop is refused rather than followed forever.
const MAX_ALIAS_DEPTH: usize = 32;

fn resolve(
    types: &BTreeMap<&str, &TypeDefinition>,
    ty: &TypeRef,
    depth: usize,
) -> Result<FprimeType, String> {
    let name = ty.name.clone();
    Ok(match ty.kind.as_str() {
        "integer" => FprimeType::Integer {
            name,
            signed: ty.signed.unwrap_or(false),
            bits: ty.size.and_then(|s| u32::try_from(s).ok()).unwrap_or(32),
        },
        "float" => FprimeType::Float { name },
        "bool" => FprimeType::Bool,
        "string" => FprimeType::String { size: ty.size },
        "qualifiedIdentifier" => {
            let Some(definition) = types.get(ty.name.as_str()) else {
                return Err(format!("type `{}` has no definition", ty.name));
            };
            match definition.kind.as_str() {
                "alias" if depth < MAX_ALIAS_DEPTH => {
                    let Some(target) = &definition.underlying_type else {
                        return Err(format!("alias `{}` names no type", ty.name));
                    };
                    resolve(types, target, depth + 1)?
                }
                "alias" => return Err(format!("alias `{}` does not resolve", ty.name)),
                "enum" => FprimeType::Enum {
                    name,
                    constants: (definition.enumerated_constants.iter())
                        .map(|c| (c.name.clone(), c.value))
                        .collect(),
                },
                _ => FprimeType::Other { name },
            }
        }
        other => {
            return Err(format!(
                "type `{}` is of an unknown kind `{other}`",
                ty.name
            ));
        }
    })
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct DictionaryFile {
    metadata: Metadata,
    #[serde(default)]
    type_definitions: Vec<TypeDefinition>,
    #[serde(default)]
    commands: Vec<CommandFile>,
    #[serde(default)]
    telemetry_channels: Vec<ChannelFile>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct Metadata {
    deployment_name: String,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct TypeDefinition {
    kind: String,
    qualified_name: String,
    underlying_type: Option<TypeRef>,
    #[serde(default)]
    enumerated_constants: Vec<ConstantFile>,
}

#[derive(Deserialize)]
struct ConstantFile {
    name: String,
    value: i64,
}

#[derive(Deserialize)]
struct TypeRef {
    name: String,
    kind: String,
    size: Option<u64>,
    signed: Option<bool>,
}

#[derive(Deserialize)]
#[serde(rename_all = "camelCase")]
struct CommandFile {
    name: String,
    opcode: u32,
    #[serde(default)]
    formal_params: Vec<ParamFile>,
}

#[derive(Deserialize)]
struct ParamFile {
    name: String,
    #[serde(rename = "type")]
    ty: TypeRef,
}

#[derive(Deserialize)]
struct ChannelFile {
    name: String,
    id: u32,
    #[serde(rename = "type")]
    ty: TypeRef,
}
