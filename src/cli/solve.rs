//! `kairos solve FILE.ron [-k K] [--json]`.

use std::path::Path;

use kairos::opsat::file::{self, Objective};
use serde_json::json;

use super::{Failure, read_source};

/// Loads the OCSP, asks OPSAT for the `k` best solutions and prints them.
pub fn run(path: &Path, k: usize, as_json: bool) -> Result<(), Failure> {
    let source = read_source(path)?;
    let mut instance = file::load(&source).map_err(Failure::bad_input)?;
    let found = instance.ocsp.best(&mut instance.theory, k);
    let table = instance.theory.table();
    let probability =
        |cost: f64| (instance.objective == Objective::Probability).then(|| (-cost).exp());
    if as_json {
        let solutions: Vec<_> = found
            .solutions
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let assignment: serde_json::Map<String, serde_json::Value> = s
                    .assignment
                    .iter()
                    .map(|&(x, v)| {
                        let variable = table.variable(x);
                        (variable.name().to_string(), json!(variable.value_name(v)))
                    })
                    .collect();
                json!({
                    "rank": i + 1,
                    "cost": s.cost,
                    "probability": probability(s.cost),
                    "assignment": assignment,
                })
            })
            .collect();
        let stats = found.stats;
        let out = json!({
            "solutions": solutions,
            "complete": found.cut.is_none(),
            "stats": {
                "nodes": stats.nodes,
                "consistency_checks": stats.consistency_checks,
                "conflicts": stats.conflicts,
                "components": stats.components,
            },
        });
        println!("{}", serde_json::to_string_pretty(&out).unwrap_or_default());
        return Ok(());
    }
    if found.solutions.is_empty() {
        println!("no solution: the constraints admit no assignment of the decision variables");
    }
    for (i, solution) in found.solutions.iter().enumerate() {
        let p = probability(solution.cost).map_or(String::new(), |p| format!("  p {p:.6}"));
        println!(
            "{:>3}. cost {:.6}{p}  {}",
            i + 1,
            solution.cost,
            solution.describe(table)
        );
    }
    if let Some(cut) = found.cut {
        println!("(search cut by its {cut:?} budget: these are the best found so far)");
    }
    let stats = found.stats;
    println!(
        "{} consistency checks, {} conflicts learned, {} nodes, {} independent sub-problems",
        stats.consistency_checks, stats.conflicts, stats.nodes, stats.components
    );
    Ok(())
}
