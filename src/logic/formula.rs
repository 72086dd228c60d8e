//! Resolved formulas: propositional state logic over finite-domain variables, with clock bounds
//! and confidence atoms (thesis §5.1.1, DESIGN.md §4).

use std::fmt;
use std::hash::{Hash, Hasher};

use super::syntax::CmpOp;
use super::vars::{ClockId, ValueId, VarId, VarTable};

/// A number compared exactly and hashable (formulas are hashed to cache their SAT encodings).
/// Parsed numbers are never NaN.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd)]
pub struct Number(pub f64);

impl Eq for Number {}

impl Hash for Number {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

/// An atomic proposition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Atom {
    /// `x = v`.
    Is(VarId, ValueId),
    /// `x = y`: two variables hold values with the same name (interconnections such as
    /// `driver.dcmd_out = valve.vcmd_in`).
    Same(VarId, VarId),
    /// `clock op seconds`, true or false once the clock's value is known.
    Clock {
        /// The clock.
        clock: ClockId,
        /// The comparison.
        op: CmpOp,
        /// The bound, in seconds.
        seconds: Number,
    },
    /// `P(x = v) op p`: the estimator's belief in an assignment.
    Confidence {
        /// The variable.
        var: VarId,
        /// The value.
        value: ValueId,
        /// The comparison.
        op: CmpOp,
        /// The probability threshold.
        probability: Number,
    },
}

impl Atom {
    /// True for atoms decided outside the constraint store (clocks, confidence).
    pub fn is_external(&self) -> bool {
        matches!(self, Atom::Clock { .. } | Atom::Confidence { .. })
    }
}

/// A formula whose names have been resolved against a [`VarTable`].
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Formula {
    /// `true`
    True,
    /// `false`
    False,
    /// An atomic proposition.
    Atom(Atom),
    /// `not f`
    Not(Box<Formula>),
    /// `f1 and f2 and ...` (empty: true)
    And(Vec<Formula>),
    /// `f1 or f2 or ...` (empty: false)
    Or(Vec<Formula>),
    /// `f1 => f2`
    Implies(Box<Formula>, Box<Formula>),
}

impl Formula {
    /// `x = v`.
    pub fn is(var: VarId, value: ValueId) -> Formula {
        Formula::Atom(Atom::Is(var, value))
    }

    /// `not f`, folding constants and double negation.
    pub fn negate(self) -> Formula {
        match self {
            Formula::True => Formula::False,
            Formula::False => Formula::True,
            Formula::Not(inner) => *inner,
            other => Formula::Not(Box::new(other)),
        }
    }

    /// The conjunction of formulas, flattening nested conjunctions and dropping `true`.
    pub fn all(parts: impl IntoIterator<Item = Formula>) -> Formula {
        let mut out = Vec::new();
        for part in parts {
            match part {
                Formula::True => {}
                Formula::False => return Formula::False,
                Formula::And(inner) => out.extend(inner),
                other => out.push(other),
            }
        }
        match out.len() {
            0 => Formula::True,
            1 => out.remove(0),
            _ => Formula::And(out),
        }
    }

    /// Every atom, in order of appearance.
    pub fn atoms(&self) -> Vec<&Atom> {
        let mut out = Vec::new();
        self.visit_atoms(&mut |a| out.push(a));
        out
    }

    fn visit_atoms<'a>(&'a self, visit: &mut impl FnMut(&'a Atom)) {
        match self {
            Formula::True | Formula::False => {}
            Formula::Atom(atom) => visit(atom),
            Formula::Not(f) => f.visit_atoms(visit),
            Formula::And(fs) | Formula::Or(fs) => fs.iter().for_each(|f| f.visit_atoms(visit)),
            Formula::Implies(a, b) => {
                a.visit_atoms(visit);
                b.visit_atoms(visit);
            }
        }
    }

    /// The finite-domain variables the formula mentions (sorted, without repeats); confidence
    /// atoms do not count, since they constrain the belief, not the state.
    pub fn variables(&self) -> Vec<VarId> {
        let mut vars = Vec::new();
        self.visit_atoms(&mut |atom| match atom {
            Atom::Is(x, _) => vars.push(*x),
            Atom::Same(x, y) => vars.extend([*x, *y]),
            Atom::Clock { .. } | Atom::Confidence { .. } => {}
        });
        vars.sort_unstable();
        vars.dedup();
        vars
    }

    /// True when some atom is a clock bound or a confidence atom.
    pub fn has_external_atoms(&self) -> bool {
        self.atoms().iter().any(|a| a.is_external())
    }

    /// Replaces every atom `decide` gives a truth value for by that constant, and simplifies.
    /// The sequencer grounds clock bounds with the clock values and the executive grounds
    /// confidence atoms with the belief, leaving a formula over state variables only.
    pub fn ground(&self, decide: &mut impl FnMut(&Atom) -> Option<bool>) -> Formula {
        match self {
            Formula::True => Formula::True,
            Formula::False => Formula::False,
            Formula::Atom(atom) => match decide(atom) {
                Some(true) => Formula::True,
                Some(false) => Formula::False,
                None => self.clone(),
            },
            Formula::Not(f) => f.ground(decide).negate(),
            Formula::And(fs) => Formula::all(fs.iter().map(|f| f.ground(decide))),
            Formula::Or(fs) => {
                let mut out = Vec::new();
                for f in fs {
                    match f.ground(decide) {
                        Formula::True => return Formula::True,
                        Formula::False => {}
                        other => out.push(other),
                    }
                }
                match out.len() {
                    0 => Formula::False,
                    1 => out.remove(0),
                    _ => Formula::Or(out),
                }
            }
            Formula::Implies(a, b) => match (a.ground(decide), b.ground(decide)) {
                (Formula::False, _) | (_, Formula::True) => Formula::True,
                (Formula::True, b) => b,
                (a, Formula::False) => a.negate(),
                (a, b) => Formula::Implies(Box::new(a), Box::new(b)),
            },
        }
    }

    /// Three-valued evaluation (Kleene): `Some(truth)` when the atoms `value_of` can decide fix
    /// the formula's value, `None` when it depends on atoms left undecided.
    pub fn eval(&self, value_of: &impl Fn(&Atom) -> Option<bool>) -> Option<bool> {
        match self {
            Formula::True => Some(true),
            Formula::False => Some(false),
            Formula::Atom(atom) => value_of(atom),
            Formula::Not(f) => f.eval(value_of).map(|b| !b),
            Formula::And(fs) => {
                let mut all_known = true;
                for f in fs {
                    match f.eval(value_of) {
                        Some(false) => return Some(false),
                        Some(true) => {}
                        None => all_known = false,
                    }
                }
                all_known.then_some(true)
            }
            Formula::Or(fs) => {
                let mut all_known = true;
                for f in fs {
                    match f.eval(value_of) {
                        Some(true) => return Some(true),
                        Some(false) => {}
                        None => all_known = false,
                    }
                }
                all_known.then_some(false)
            }
            Formula::Implies(a, b) => match (a.eval(value_of), b.eval(value_of)) {
                (Some(false), _) | (_, Some(true)) => Some(true),
                (Some(true), Some(false)) => Some(false),
                _ => None,
            },
        }
    }

    /// Evaluates against a (possibly partial) assignment of state variables by value name. Clock
    /// and confidence atoms are undecided.
    pub fn eval_assignment(
        &self,
        table: &VarTable,
        value: &impl Fn(VarId) -> Option<ValueId>,
    ) -> Option<bool> {
        self.eval(&|atom| match atom {
            Atom::Is(x, v) => value(*x).map(|w| w == *v),
            Atom::Same(x, y) => {
                let (vx, vy) = (value(*x)?, value(*y)?);
                Some(table.variable(*x).value_name(vx) == table.variable(*y).value_name(vy))
            }
            Atom::Clock { .. } | Atom::Confidence { .. } => None,
        })
    }

    /// If the formula is a conjunction of `x = v` atoms (the goals the thesis's executive
    /// handles, §5.1.1), those assignments.
    pub fn as_assignments(&self) -> Option<Vec<(VarId, ValueId)>> {
        match self {
            Formula::True => Some(Vec::new()),
            Formula::Atom(Atom::Is(x, v)) => Some(vec![(*x, *v)]),
            Formula::And(fs) => {
                let mut out = Vec::new();
                for f in fs {
                    out.extend(f.as_assignments()?);
                }
                Some(out)
            }
            _ => None,
        }
    }

    /// Displays the formula with the table's names, in the ASCII spelling the parser reads back.
    pub fn display<'a>(&'a self, table: &'a VarTable) -> FormulaDisplay<'a> {
        FormulaDisplay {
            formula: self,
            table,
        }
    }
}

/// Writes a [`Formula`] with names; see [`Formula::display`].
pub struct FormulaDisplay<'a> {
    formula: &'a Formula,
    table: &'a VarTable,
}

/// Binding strength, loosest first, to decide where parentheses are needed.
fn strength(formula: &Formula) -> u8 {
    match formula {
        Formula::Implies(..) => 0,
        Formula::Or(fs) if fs.len() > 1 => 1,
        Formula::And(fs) if fs.len() > 1 => 2,
        _ => 3,
    }
}

impl FormulaDisplay<'_> {
    fn write(&self, f: &mut fmt::Formatter<'_>, formula: &Formula, min: u8) -> fmt::Result {
        let parenthesise = strength(formula) < min;
        if parenthesise {
            f.write_str("(")?;
        }
        self.write_bare(f, formula)?;
        if parenthesise {
            f.write_str(")")?;
        }
        Ok(())
    }

    fn write_bare(&self, f: &mut fmt::Formatter<'_>, formula: &Formula) -> fmt::Result {
        let table = self.table;
        match formula {
            Formula::True => f.write_str("true"),
            Formula::False => f.write_str("false"),
            Formula::Atom(atom) => write_atom(f, table, atom),
            Formula::Not(inner) => {
                f.write_str("not ")?;
                self.write(f, inner, 3)
            }
            Formula::And(fs) | Formula::Or(fs) if fs.is_empty() => {
                f.write_str(if matches!(formula, Formula::And(_)) {
                    "true"
                } else {
                    "false"
                })
            }
            Formula::And(fs) | Formula::Or(fs) => {
                let (op, level) = match formula {
                    Formula::And(_) => (" and ", 3),
                    _ => (" or ", 2),
                };
                for (i, part) in fs.iter().enumerate() {
                    if i > 0 {
                        f.write_str(op)?;
                    }
                    self.write(f, part, level)?;
                }
                Ok(())
            }
            Formula::Implies(a, b) => {
                self.write(f, a, 1)?;
                f.write_str(" => ")?;
                self.write(f, b, 0)
            }
        }
    }
}

fn write_atom(f: &mut fmt::Formatter<'_>, table: &VarTable, atom: &Atom) -> fmt::Result {
    match atom {
        Atom::Is(x, v) => write!(f, "{}", table.assignment(*x, *v)),
        Atom::Same(x, y) => write!(
            f,
            "{} = {}",
            table.variable(*x).name(),
            table.variable(*y).name()
        ),
        Atom::Clock { clock, op, seconds } => write!(
            f,
            "{} {} {} s",
            table.clock_name(*clock),
            op.symbol(),
            seconds.0
        ),
        Atom::Confidence {
            var,
            value,
            op,
            probability,
        } => write!(
            f,
            "P({}) {} {}",
            table.assignment(*var, *value),
            op.symbol(),
            probability.0
        ),
    }
}

impl fmt::Display for FormulaDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(f, self.formula, 0)
    }
}
