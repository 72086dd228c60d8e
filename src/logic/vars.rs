//! Variables with finite domains, and clocks: the names formulas are resolved against.

use std::collections::HashMap;
use std::fmt;

/// A finite-domain variable in a [`VarTable`] (a mode, an attribute, an OCSP variable).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct VarId(pub u32);

/// A value of one variable's domain, by position in that domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ValueId(pub u32);

/// A real-valued clock (an RMPL program clock such as `t1`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ClockId(pub u32);

impl VarId {
    /// Position in the table, for indexing per-variable arrays.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl ValueId {
    /// Position in the domain, for indexing per-value arrays.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

impl ClockId {
    /// Position in the table's clock list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// A named variable and its finite domain.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variable {
    name: String,
    values: Vec<String>,
}

impl Variable {
    /// The variable's name (`engine`, `engine.temp`).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The domain, in declaration order.
    pub fn values(&self) -> &[String] {
        &self.values
    }

    /// Size of the domain.
    pub fn domain_size(&self) -> usize {
        self.values.len()
    }

    /// The value with this name, if it is in the domain.
    pub fn value(&self, name: &str) -> Option<ValueId> {
        self.values
            .iter()
            .position(|v| v == name)
            .map(|i| ValueId(i as u32))
    }

    /// The name of a value of this domain.
    pub fn value_name(&self, value: ValueId) -> &str {
        &self.values[value.index()]
    }

    /// Every value of the domain.
    pub fn value_ids(&self) -> impl Iterator<Item = ValueId> + use<> {
        (0..self.values.len() as u32).map(ValueId)
    }
}

/// Why a declaration was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DeclarationError {
    /// The name is already a variable or a clock.
    #[error("`{0}` is declared twice")]
    Duplicate(String),
    /// A domain lists the same value twice.
    #[error("value `{value}` appears twice in the domain of `{variable}`")]
    DuplicateValue {
        /// The variable being declared.
        variable: String,
        /// The repeated value.
        value: String,
    },
    /// A variable with no values can never be assigned.
    #[error("`{0}` has an empty domain")]
    EmptyDomain(String),
    /// A name the constraint language could not write.
    #[error("`{0}` is not a valid name (letters, digits, `_`, `-`; dots between parts)")]
    BadName(String),
}

/// The finite-domain variables and clocks that formulas may mention.
///
/// Variables are numbered in declaration order; that order is the order of every per-variable
/// array elsewhere (the SAT encoding, OPSAT's decision list).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct VarTable {
    variables: Vec<Variable>,
    clocks: Vec<String>,
    by_name: HashMap<String, Name>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Name {
    Variable(VarId),
    Clock(ClockId),
}

impl VarTable {
    /// An empty table.
    pub fn new() -> Self {
        VarTable::default()
    }

    /// Declares a finite-domain variable.
    pub fn add_variable<S: Into<String>>(
        &mut self,
        name: impl Into<String>,
        values: impl IntoIterator<Item = S>,
    ) -> Result<VarId, DeclarationError> {
        let name = name.into();
        if !is_name(&name) {
            return Err(DeclarationError::BadName(name));
        }
        let values: Vec<String> = values.into_iter().map(Into::into).collect();
        if values.is_empty() {
            return Err(DeclarationError::EmptyDomain(name));
        }
        for (i, value) in values.iter().enumerate() {
            if !is_value_name(value) {
                return Err(DeclarationError::BadName(value.clone()));
            }
            if values[..i].contains(value) {
                return Err(DeclarationError::DuplicateValue {
                    variable: name,
                    value: value.clone(),
                });
            }
        }
        let id = VarId(self.variables.len() as u32);
        self.claim(&name, Name::Variable(id))?;
        self.variables.push(Variable { name, values });
        Ok(id)
    }

    /// Declares a clock.
    pub fn add_clock(&mut self, name: impl Into<String>) -> Result<ClockId, DeclarationError> {
        let name = name.into();
        if !is_name(&name) {
            return Err(DeclarationError::BadName(name));
        }
        let id = ClockId(self.clocks.len() as u32);
        self.claim(&name, Name::Clock(id))?;
        self.clocks.push(name);
        Ok(id)
    }

    fn claim(&mut self, name: &str, what: Name) -> Result<(), DeclarationError> {
        if self.by_name.contains_key(name) {
            return Err(DeclarationError::Duplicate(name.to_string()));
        }
        self.by_name.insert(name.to_string(), what);
        Ok(())
    }

    /// The variable with this name.
    pub fn variable_id(&self, name: &str) -> Option<VarId> {
        match self.by_name.get(name)? {
            Name::Variable(id) => Some(*id),
            Name::Clock(_) => None,
        }
    }

    /// The clock with this name.
    pub fn clock_id(&self, name: &str) -> Option<ClockId> {
        match self.by_name.get(name)? {
            Name::Clock(id) => Some(*id),
            Name::Variable(_) => None,
        }
    }

    /// A variable by id. Ids come from this table, so they are always in range.
    pub fn variable(&self, id: VarId) -> &Variable {
        &self.variables[id.index()]
    }

    /// A clock's name.
    pub fn clock_name(&self, id: ClockId) -> &str {
        &self.clocks[id.index()]
    }

    /// All variables, in declaration order.
    pub fn variables(&self) -> impl ExactSizeIterator<Item = (VarId, &Variable)> {
        self.variables
            .iter()
            .enumerate()
            .map(|(i, v)| (VarId(i as u32), v))
    }

    /// Number of finite-domain variables.
    pub fn len(&self) -> usize {
        self.variables.len()
    }

    /// True when no variable is declared.
    pub fn is_empty(&self) -> bool {
        self.variables.is_empty()
    }

    /// All clocks, in declaration order.
    pub fn clocks(&self) -> impl ExactSizeIterator<Item = (ClockId, &str)> {
        self.clocks
            .iter()
            .enumerate()
            .map(|(i, c)| (ClockId(i as u32), c.as_str()))
    }

    /// Every variable and clock name, for "did you mean" suggestions.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.variables
            .iter()
            .map(|v| v.name.as_str())
            .chain(self.clocks.iter().map(String::as_str))
    }

    /// `var = value` for display.
    pub fn assignment(&self, var: VarId, value: ValueId) -> Assignment<'_> {
        Assignment {
            table: self,
            var,
            value,
        }
    }
}

/// Displays `var = value` with names.
pub struct Assignment<'a> {
    table: &'a VarTable,
    var: VarId,
    value: ValueId,
}

impl fmt::Display for Assignment<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let variable = self.table.variable(self.var);
        write!(
            f,
            "{} = {}",
            variable.name(),
            variable.value_name(self.value)
        )
    }
}

fn is_ident(s: &str) -> bool {
    let mut chars = s.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
        && !is_keyword(s)
}

fn is_keyword(s: &str) -> bool {
    matches!(s, "and" | "or" | "not")
        || s.eq_ignore_ascii_case("true")
        || s.eq_ignore_ascii_case("false")
}

/// True when `s` can be written as a variable or clock name in the constraint language.
pub fn is_name(s: &str) -> bool {
    s.split('.').all(is_ident)
}

/// True when `s` can be written as a value in the constraint language.
pub fn is_value_name(s: &str) -> bool {
    is_ident(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variables_and_clocks_share_one_namespace() {
        let mut table = VarTable::new();
        let engine = table.add_variable("engine", ["off", "standby"]).unwrap();
        let t1 = table.add_clock("t1").unwrap();
        assert_eq!(table.variable_id("engine"), Some(engine));
        assert_eq!(table.clock_id("t1"), Some(t1));
        assert_eq!(table.variable_id("t1"), None);
        assert_eq!(
            table.add_clock("engine"),
            Err(DeclarationError::Duplicate("engine".into()))
        );
        assert_eq!(table.variable(engine).value("standby"), Some(ValueId(1)));
    }

    #[test]
    fn bad_declarations_are_refused() {
        let mut table = VarTable::new();
        assert!(matches!(
            table.add_variable("x", Vec::<String>::new()),
            Err(DeclarationError::EmptyDomain(_))
        ));
        assert!(matches!(
            table.add_variable("x", ["a", "a"]),
            Err(DeclarationError::DuplicateValue { .. })
        ));
        assert!(matches!(
            table.add_variable("1x", ["a"]),
            Err(DeclarationError::BadName(_))
        ));
        assert!(matches!(
            table.add_variable("x", ["and"]),
            Err(DeclarationError::BadName(_))
        ));
        assert!(
            table
                .add_variable("engine.temp", ["cold", "nominal-hot"])
                .is_ok()
        );
    }
}
