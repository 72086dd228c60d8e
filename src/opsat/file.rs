//! The RON file format for a stand-alone OCSP (`kairos solve FILE.ron`). Reference for users:
//! `docs/reference/ocsp.md`.
//!
//! ```ron
//! Ocsp(
//!     // `Cost` (default): the numbers are costs, summed and minimised.
//!     // `Probability`: the numbers are probabilities; cost = −ln p, so the cheapest solution is
//!     // the most probable one (values with probability 0 are never chosen).
//!     objective: Probability,
//!     decisions: [
//!         Decision(name: "X1", values: [("ok", 0.99), ("broken", 0.01)]),
//!     ],
//!     // Variables the constraints mention but that are not decided (existentially quantified).
//!     auxiliary: [
//!         Variable(name: "w1", values: ["lo", "hi"]),
//!     ],
//!     // Formulas of the constraint language (DESIGN.md §4) that every solution satisfies.
//!     constraints: [
//!         "X1 = ok => (w1 = hi => not a = b)",
//!     ],
//! )
//! ```
//! Names and values are identifiers of the constraint language (letters, digits, `_`, `-`; a
//! name may have dotted parts). Every error points into the file.

use serde::Deserialize;

use super::{Ocsp, Theory, TheoryOptions};
use crate::diagnostic::{
    Diagnostic, Source, SourceErrors, find_string_literal, find_string_literals, ron_error,
};
use crate::logic::{self, DeclarationError, VarId, VarTable};

/// What the per-value numbers of a file mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
pub enum Objective {
    /// Costs, minimised.
    #[default]
    Cost,
    /// Probabilities, maximised (cost −ln p).
    Probability,
}

#[derive(Deserialize)]
#[serde(rename = "Ocsp", deny_unknown_fields)]
struct OcspFile {
    #[serde(default)]
    objective: Objective,
    decisions: Vec<DecisionSpec>,
    #[serde(default)]
    auxiliary: Vec<VariableSpec>,
    #[serde(default)]
    constraints: Vec<String>,
}

#[derive(Deserialize)]
#[serde(rename = "Decision", deny_unknown_fields)]
struct DecisionSpec {
    name: String,
    values: Vec<(String, f64)>,
}

#[derive(Deserialize)]
#[serde(rename = "Variable", deny_unknown_fields)]
struct VariableSpec {
    name: String,
    values: Vec<String>,
}

/// A loaded OCSP: the theory of its constraints and the problem over it.
pub struct OcspInstance {
    /// The constraints, encoded.
    pub theory: Theory,
    /// The decision variables and their costs.
    pub ocsp: Ocsp,
    /// How the file's numbers were read.
    pub objective: Objective,
}

/// Reads an OCSP file, reporting every problem found with its location.
pub fn load(source: &Source) -> Result<OcspInstance, SourceErrors> {
    load_with(source, TheoryOptions::default())
}

/// Reads an OCSP file and encodes its theory with the given options (benchmarks compare
/// conflict minimisation on the shipped examples).
pub fn load_with(source: &Source, options: TheoryOptions) -> Result<OcspInstance, SourceErrors> {
    let fail = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
    let file: OcspFile =
        ron::from_str(&source.text).map_err(|e| fail(vec![ron_error(source, &e)]))?;
    let mut errors = Vec::new();
    let at = |content: &str| find_string_literal(&source.text, content).unwrap_or(0..0);

    let mut table = VarTable::new();
    let mut decision_vars = Vec::new();
    for decision in &file.decisions {
        let values = decision.values.iter().map(|(v, _)| v.clone());
        match table.add_variable(decision.name.clone(), values) {
            Ok(var) => decision_vars.push(Some(var)),
            Err(e) => {
                errors.push(declaration_error(&e, source, &decision.name));
                decision_vars.push(None);
            }
        }
    }
    for variable in &file.auxiliary {
        if let Err(e) = table.add_variable(variable.name.clone(), variable.values.clone()) {
            errors.push(declaration_error(&e, source, &variable.name));
        }
    }

    let mut ocsp = Ocsp::new();
    for (decision, var) in file.decisions.iter().zip(&decision_vars) {
        let Some(var) = *var else { continue };
        match choices(decision, var, &table, file.objective) {
            Ok(choices) => {
                if ocsp.decide(var, choices).is_err() {
                    errors.push(Diagnostic::new(
                        "a cost is not a number",
                        at(&decision.name),
                    ));
                }
            }
            Err(value) => errors.push(
                Diagnostic::new(
                    format!(
                        "`{}` of `{}` has a number out of range",
                        value, decision.name
                    ),
                    at(&value),
                )
                .expected(match file.objective {
                    Objective::Probability => "a probability between 0 and 1",
                    Objective::Cost => "a finite cost",
                }),
            ),
        }
    }

    let mut constraints = Vec::new();
    for text in &file.constraints {
        let offset = at(text).start;
        match logic::syntax::parse_at(text, offset)
            .map_err(|d| vec![d])
            .and_then(|expr| logic::resolve(&expr, &table))
        {
            Ok(formula) if formula.has_external_atoms() => errors.push(
                Diagnostic::new(
                    "clocks and confidences have no value in an OCSP",
                    offset..offset + text.len(),
                )
                .expected("a formula over the declared variables"),
            ),
            Ok(formula) => constraints.push(formula),
            Err(diagnostics) => errors.extend(diagnostics),
        }
    }
    if !errors.is_empty() {
        return Err(fail(errors));
    }
    let theory = Theory::with_options(table, &constraints, options)
        .map_err(|e| fail(vec![Diagnostic::new(e.to_string(), 0..0)]))?;
    Ok(OcspInstance {
        theory,
        ocsp,
        objective: file.objective,
    })
}

/// The (value, cost) pairs of a decision, or the name of a value whose number is unusable.
fn choices(
    decision: &DecisionSpec,
    var: VarId,
    table: &VarTable,
    objective: Objective,
) -> Result<Vec<(logic::ValueId, f64)>, String> {
    let variable = table.variable(var);
    decision
        .values
        .iter()
        .map(|(name, number)| {
            let cost = match objective {
                Objective::Cost if number.is_finite() => *number,
                Objective::Probability if (0.0..=1.0).contains(number) => -number.ln(),
                _ => return Err(name.clone()),
            };
            let value = variable.value(name).ok_or_else(|| name.clone())?;
            Ok((value, cost))
        })
        .collect()
}

fn declaration_error(error: &DeclarationError, source: &Source, name: &str) -> Diagnostic {
    let culprit = match error {
        DeclarationError::DuplicateValue { value, .. } => value.as_str(),
        DeclarationError::BadName(bad) => bad.as_str(),
        DeclarationError::Duplicate(_) | DeclarationError::EmptyDomain(_) => name,
    };
    // A duplicate's second occurrence is the offending one.
    let occurrences = find_string_literals(&source.text, culprit);
    let nth = match error {
        DeclarationError::Duplicate(_) | DeclarationError::DuplicateValue { .. } => 1,
        _ => 0,
    };
    let span = occurrences
        .get(nth)
        .or(occurrences.first())
        .cloned()
        .unwrap_or(0..0);
    Diagnostic::new(error.to_string(), span).expected(match error {
        DeclarationError::BadName(_) => "an identifier (letters, digits, `_`, `-`)",
        DeclarationError::EmptyDomain(_) => "at least one value",
        _ => "a name not used before",
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnostic::reference;

    /// `docs/reference/ocsp.md` lists every field and variant this loader accepts, and no other.
    #[test]
    fn the_reference_documents_every_field() {
        let mut tracer = reference::tracer();
        reference::add::<Objective>(&mut tracer);
        reference::add::<OcspFile>(&mut tracer);
        reference::assert_documented(
            &reference::registry(tracer),
            &[
                ("Ocsp", "ocsp.md", "`Ocsp(...)`"),
                ("Objective", "ocsp.md", "Objectives"),
                ("Decision", "ocsp.md", "`Decision(...)`"),
                ("Variable", "ocsp.md", "`Variable(...)`"),
            ],
        );
    }

    fn errors(text: &str) -> String {
        match load(&Source::new("p.ron", text)) {
            Ok(_) => panic!("{text} loaded"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn a_minimal_file_loads_and_solves() {
        let text = r#"Ocsp(
            decisions: [Decision(name: "x", values: [("a", 2.0), ("b", 1.0)])],
            constraints: ["x != b"],
        )"#;
        let mut instance = load(&Source::new("p.ron", text)).unwrap();
        let best = instance.ocsp.best(&mut instance.theory, 5);
        assert_eq!(best.solutions.len(), 1);
        assert_eq!(best.solutions[0].cost, 2.0);
    }

    #[test]
    fn probabilities_become_negative_log_costs() {
        let text = r#"Ocsp(objective: Probability,
            decisions: [Decision(name: "x", values: [("a", 0.25), ("b", 0.0)])])"#;
        let mut instance = load(&Source::new("p.ron", text)).unwrap();
        let best = instance.ocsp.best(&mut instance.theory, 5);
        // Probability zero is never chosen.
        assert_eq!(best.solutions.len(), 1);
        assert!((best.solutions[0].cost - 4f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn errors_point_into_the_file() {
        let text = "Ocsp(\n decisions: [Decision(name: \"x\", values: [(\"a\", 1.0)])],\n constraints: [\"x = c\"],\n)";
        let shown = errors(text);
        assert!(shown.contains("p.ron:3:21"), "{shown}");
        assert!(shown.contains("`c` is not a value of `x`"), "{shown}");

        let shown = errors(
            "Ocsp(decisions: [Decision(name: \"x\", values: [(\"a\", 1.0)]), Decision(name: \"x\", values: [(\"b\", 1.0)])])",
        );
        assert!(shown.contains("declared twice"), "{shown}");
        assert!(shown.contains("p.ron:1:77"), "{shown}");

        let shown = errors("Ocsp(decisions: [Decision(nme: \"x\")])");
        assert!(shown.contains("malformed RON"), "{shown}");
        assert!(shown.contains("p.ron:1:"), "{shown}");

        let shown = errors(
            "Ocsp(objective: Probability, decisions: [Decision(name: \"x\", values: [(\"a\", 1.5)])])",
        );
        assert!(shown.contains("a probability between 0 and 1"), "{shown}");
    }
}
