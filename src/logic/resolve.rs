//! Name resolution: a parsed [`Expr`] becomes a [`Formula`] over a [`VarTable`], or a list of
//! located errors (every problem in the formula, not only the first).

use super::formula::{Atom, Formula, Number};
use super::syntax::{self, CmpOp, Expr, ExprKind, Name, Operand, TimeUnit};
use super::vars::{ValueId, VarId, VarTable};
use crate::diagnostic::{Diagnostic, did_you_mean};

/// Parses and resolves a formula in one go.
pub fn parse_formula(text: &str, table: &VarTable) -> Result<Formula, Vec<Diagnostic>> {
    let expr = syntax::parse(text).map_err(|d| vec![d])?;
    resolve(&expr, table)
}

/// Resolves every name in `expr` against `table`.
pub fn resolve(expr: &Expr, table: &VarTable) -> Result<Formula, Vec<Diagnostic>> {
    let mut errors = Vec::new();
    let formula = Resolver {
        table,
        errors: &mut errors,
    }
    .formula(expr);
    if errors.is_empty() {
        Ok(formula)
    } else {
        Err(errors)
    }
}

struct Resolver<'a> {
    table: &'a VarTable,
    errors: &'a mut Vec<Diagnostic>,
}

impl Resolver<'_> {
    fn formula(&mut self, expr: &Expr) -> Formula {
        match &expr.kind {
            ExprKind::Constant(true) => Formula::True,
            ExprKind::Constant(false) => Formula::False,
            ExprKind::Not(inner) => Formula::Not(Box::new(self.formula(inner))),
            ExprKind::And(parts) => Formula::And(parts.iter().map(|p| self.formula(p)).collect()),
            ExprKind::Or(parts) => Formula::Or(parts.iter().map(|p| self.formula(p)).collect()),
            ExprKind::Implies(a, b) => {
                Formula::Implies(Box::new(self.formula(a)), Box::new(self.formula(b)))
            }
            ExprKind::Compare { left, op, right } => self.comparison(left, *op, right),
            ExprKind::Confidence {
                variable,
                value,
                op,
                probability,
                probability_span,
            } => {
                if !(0.0..=1.0).contains(probability) {
                    self.errors.push(
                        Diagnostic::new(
                            format!("probability {probability} is outside [0, 1]"),
                            probability_span.clone(),
                        )
                        .expected("a probability between 0 and 1"),
                    );
                }
                if !op.is_ordering() {
                    self.errors.push(
                        Diagnostic::new("a confidence is compared with `=`", expr.span.clone())
                            .expected("`>=`, `>`, `<=` or `<`"),
                    );
                }
                match self.assignment(variable, value) {
                    Some((var, value)) => Formula::Atom(Atom::Confidence {
                        var,
                        value,
                        op: *op,
                        probability: Number(*probability),
                    }),
                    None => Formula::False,
                }
            }
        }
    }

    fn comparison(&mut self, left: &Name, op: CmpOp, right: &Operand) -> Formula {
        if let Some(clock) = self.table.clock_id(&left.text) {
            return match right {
                Operand::Quantity { value, unit, .. } if op.is_ordering() => {
                    let unit = unit.unwrap_or(TimeUnit::Seconds);
                    Formula::Atom(Atom::Clock {
                        clock,
                        op,
                        seconds: Number(value * unit.seconds()),
                    })
                }
                Operand::Quantity { span, .. } | Operand::Name(Name { span, .. }) => {
                    let what = if op.is_ordering() {
                        "a clock is compared with a time"
                    } else {
                        "a clock is compared with `<`, `<=`, `>` or `>=`"
                    };
                    self.errors.push(
                        Diagnostic::new(format!("`{}` is a clock", left.text), span.clone())
                            .expected(what.to_string()),
                    );
                    Formula::False
                }
            };
        }
        let Some(var) = self.variable(left) else {
            return Formula::False;
        };
        let value = match right {
            Operand::Name(name) if !op.is_ordering() => name,
            Operand::Name(Name { span, .. }) | Operand::Quantity { span, .. } => {
                let expected = if op.is_ordering() {
                    format!("`=` or `!=`: `{}` is not a clock", left.text)
                } else {
                    format!("a value of `{}`", left.text)
                };
                self.errors.push(
                    Diagnostic::new(
                        format!("cannot compare `{}` this way", left.text),
                        span.clone(),
                    )
                    .expected(expected)
                    .note(self.domain_note(var)),
                );
                return Formula::False;
            }
        };
        let atom = match self.table.variable(var).value(&value.text) {
            Some(v) => Atom::Is(var, v),
            None => match self.table.variable_id(&value.text) {
                Some(other) => Atom::Same(var, other),
                None => {
                    self.unknown_value(var, value);
                    return Formula::False;
                }
            },
        };
        let atom = Formula::Atom(atom);
        if op == CmpOp::Ne {
            Formula::Not(Box::new(atom))
        } else {
            atom
        }
    }

    fn assignment(&mut self, variable: &Name, value: &Name) -> Option<(VarId, ValueId)> {
        let var = self.variable(variable)?;
        match self.table.variable(var).value(&value.text) {
            Some(v) => Some((var, v)),
            None => {
                self.unknown_value(var, value);
                None
            }
        }
    }

    fn variable(&mut self, name: &Name) -> Option<VarId> {
        let found = self.table.variable_id(&name.text);
        if found.is_none() {
            let mut diagnostic = Diagnostic::new(
                format!("unknown variable `{}`", name.text),
                name.span.clone(),
            )
            .expected("a declared variable or clock");
            if let Some(close) = did_you_mean(&name.text, self.table.names()) {
                diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
            }
            self.errors.push(diagnostic);
        }
        found
    }

    fn unknown_value(&mut self, var: VarId, value: &Name) {
        let variable = self.table.variable(var);
        let mut diagnostic = Diagnostic::new(
            format!("`{}` is not a value of `{}`", value.text, variable.name()),
            value.span.clone(),
        )
        .expected(format!("a value of `{}`", variable.name()))
        .note(self.domain_note(var));
        let values = variable.values().iter().map(String::as_str);
        if let Some(close) = did_you_mean(&value.text, values) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        self.errors.push(diagnostic);
    }

    fn domain_note(&self, var: VarId) -> String {
        let variable = self.table.variable(var);
        format!(
            "`{}` takes one of: {}",
            variable.name(),
            variable.values().join(", ")
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::Source;

    fn table() -> VarTable {
        let mut table = VarTable::new();
        table
            .add_variable("engine", ["off", "heating", "standby", "firing"])
            .unwrap();
        table
            .add_variable("driver.dcmd_out", ["none", "on"])
            .unwrap();
        table
            .add_variable("valve.vcmd_in", ["none", "on", "open"])
            .unwrap();
        table.add_clock("t1").unwrap();
        table
    }

    fn resolve_ok(text: &str) -> Formula {
        parse_formula(text, &table()).unwrap_or_else(|e| panic!("{text}: {e:?}"))
    }

    fn errors(text: &str) -> String {
        let diagnostics = parse_formula(text, &table()).unwrap_err();
        Source::new("f", text).render(&diagnostics)
    }

    #[test]
    fn display_round_trips_through_the_parser() {
        let table = table();
        for text in [
            "engine = standby",
            "not engine = off and (engine = heating or engine = firing)",
            "engine = off => driver.dcmd_out = none => valve.vcmd_in = none",
            "(engine = off => engine = off) => engine = firing",
            "driver.dcmd_out = valve.vcmd_in",
            "t1 >= 16200 s or P(engine = firing) >= 0.9",
            "not (engine = off or engine = firing) and true",
        ] {
            let formula = resolve_ok(text);
            let shown = formula.display(&table).to_string();
            let again = parse_formula(&shown, &table).unwrap();
            assert_eq!(formula, again, "{text} -> {shown}");
        }
    }

    #[test]
    fn not_equal_is_negated_equality() {
        assert_eq!(resolve_ok("engine != off"), resolve_ok("not engine = off"));
        assert_eq!(resolve_ok("engine ≠ off"), resolve_ok("¬(engine = off)"));
    }

    #[test]
    fn clock_bounds_are_in_seconds() {
        let Formula::Atom(Atom::Clock { seconds, op, .. }) = resolve_ok("t1 ≥ 270 min") else {
            panic!()
        };
        assert_eq!((seconds.0, op), (16200.0, CmpOp::Ge));
    }

    #[test]
    fn a_name_that_is_not_a_value_but_a_variable_makes_an_equality_of_variables() {
        assert!(matches!(
            resolve_ok("driver.dcmd_out = valve.vcmd_in"),
            Formula::Atom(Atom::Same(_, _))
        ));
    }

    #[test]
    fn unknown_names_are_located_with_suggestions() {
        let text = errors("engne = standby");
        assert!(text.contains("unknown variable `engne`"), "{text}");
        assert!(text.contains("f:1:1"), "{text}");
        assert!(text.contains("did you mean `engine`?"), "{text}");

        let text = errors("engine = standbye");
        assert!(
            text.contains("`standbye` is not a value of `engine`"),
            "{text}"
        );
        assert!(text.contains("f:1:10"), "{text}");
        assert!(text.contains("off, heating, standby, firing"), "{text}");
    }

    #[test]
    fn every_error_is_reported_not_only_the_first() {
        let diagnostics = parse_formula("x = a and engine = b and t1 = 4", &table()).unwrap_err();
        assert_eq!(diagnostics.len(), 3, "{diagnostics:?}");
    }

    #[test]
    fn clocks_and_variables_are_compared_their_own_way() {
        assert!(errors("t1 = on").contains("`t1` is a clock"));
        assert!(errors("engine >= 4").contains("cannot compare `engine`"));
        assert!(errors("P(engine = on) >= 0.5").contains("`on` is not a value"));
        assert!(errors("P(engine = off) >= 1.5").contains("outside [0, 1]"));
    }
}
