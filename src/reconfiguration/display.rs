//! Policy tables for people ("an engineer can review them like Table 6.2"): rows are
//! current modes, columns the nominal target modes, and a cell says what the policy does —
//! `Idle`, `Failure`, or the conditions of the next transition's guard: mode sub-goals on
//! upstream components, then the component's inputs a command sets (`valve1 = open, valve2 =
//! open, engine.cmd = fire`). Below each table, every step says how the planner meets those
//! conditions: which command, once which sub-goals hold.

use std::fmt::Write;

use super::Reconfiguration;
use super::policy::{ConcurrentPolicy, PolicyEntry, PolicyStep};
use super::requirement::{Condition, Requirement};
use crate::logic::ValueId;
use crate::plant::{ComponentId, ModeKind, Plant};

/// `u = v, ...` for sub-goals.
fn modes_text(plant: &Plant, modes: &[(ComponentId, ValueId)]) -> String {
    modes
        .iter()
        .map(|&(u, v)| {
            format!(
                "{} = {}",
                plant.component(u).name(),
                plant.component(u).mode(v).name
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The conditions of a requirement as Table 6.2 writes them.
fn conditions_text(plant: &Plant, requirement: &Requirement) -> String {
    let mut items: Vec<String> = requirement
        .conditions
        .iter()
        .map(|condition| match condition {
            Condition::Mode(u, v) => modes_text(plant, &[(*u, *v)]),
            Condition::Input(formula) => formula.display(plant.table()).to_string(),
        })
        .collect();
    if requirement.is_idle() {
        items.push(
            if items.is_empty() {
                "Idle"
            } else {
                "then Idle"
            }
            .to_string(),
        );
    }
    items.join(", ")
}

/// How the planner takes a step of `component`: its command (or wait) and the sub-goals
/// before it.
fn step_text(plant: &Plant, component: ComponentId, step: &PolicyStep) -> String {
    let requirement = match &step.requirement {
        Ok(requirement) => requirement,
        Err(unplannable) => return format!("unplannable: {}", unplannable.reason),
    };
    let mut text = if requirement.is_idle() {
        let law = plant.component(component).transitions()[step.transition].law;
        format!("wait, {law}")
    } else {
        let table = plant.table();
        let assignments: Vec<String> = requirement
            .controls
            .iter()
            .map(|&(x, v)| table.assignment(x, v).to_string())
            .collect();
        format!("command {}", assignments.join(", "))
    };
    if !requirement.modes.is_empty() {
        write!(text, " once {}", modes_text(plant, &requirement.modes)).ok();
    }
    if step.repair {
        text.push_str(" (repair)");
    }
    text
}

impl ConcurrentPolicy {
    /// The text of the cell (`current`, `target`), as Table 6.2 writes it; a repair or an
    /// irreversible step is marked.
    pub fn cell(&self, plant: &Plant, current: ValueId, target: ValueId) -> String {
        match self.entry(current, target) {
            PolicyEntry::Stay => "Idle".to_string(),
            PolicyEntry::Failure => "Failure".to_string(),
            PolicyEntry::Next { step, irreversible } => {
                let step = &self.steps()[step];
                let mut text = match &step.requirement {
                    Ok(requirement) => conditions_text(plant, requirement),
                    Err(_) => "Failure".to_string(),
                };
                if step.repair {
                    text.push_str(" (repair)");
                }
                if irreversible {
                    text.push_str(" (irreversible)");
                }
                text
            }
        }
    }

    /// The policy as a table: a row per mode, a column per nominal mode (fault modes are
    /// never targets), then one line per step saying how the planner takes it.
    pub fn table(&self, plant: &Plant) -> String {
        let component = plant.component(self.component());
        let modes: Vec<ValueId> = (0..component.modes().len() as u32).map(ValueId).collect();
        let targets: Vec<ValueId> = modes
            .iter()
            .copied()
            .filter(|&m| component.mode(m).kind == ModeKind::Nominal)
            .collect();
        let mut rows = vec![
            std::iter::once("current \\ target".to_string())
                .chain(targets.iter().map(|&t| component.mode(t).name.clone()))
                .collect::<Vec<_>>(),
        ];
        for &m in &modes {
            rows.push(
                std::iter::once(component.mode(m).name.clone())
                    .chain(targets.iter().map(|&t| self.cell(plant, m, t)))
                    .collect(),
            );
        }
        let mut out = aligned(&rows);
        out.push_str(if self.steps().is_empty() {
            "steps: none\n"
        } else {
            "steps:\n"
        });
        let width = self
            .steps()
            .iter()
            .map(|s| component.mode(s.source).name.len() + component.mode(s.target).name.len())
            .max()
            .unwrap_or(0)
            + 4;
        for step in self.steps() {
            let movement = format!(
                "{} -> {}",
                component.mode(step.source).name,
                component.mode(step.target).name
            );
            writeln!(
                out,
                "  {movement:<width$}  {}",
                step_text(plant, self.component(), step)
            )
            .ok();
        }
        out
    }
}

/// Rows of cells as a table with a rule under the header.
fn aligned(rows: &[Vec<String>]) -> String {
    let columns = rows.iter().map(Vec::len).max().unwrap_or(0);
    let widths: Vec<usize> = (0..columns)
        .map(|i| {
            rows.iter()
                .filter_map(|r| r.get(i))
                .map(|c| c.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut out = String::new();
    for (r, row) in rows.iter().enumerate() {
        let line: Vec<String> = row
            .iter()
            .zip(&widths)
            .map(|(cell, &w)| format!("{cell:<w$}"))
            .collect();
        writeln!(out, "{}", line.join(" | ").trim_end()).ok();
        if r == 0 {
            let rule: Vec<String> = widths.iter().map(|&w| "-".repeat(w)).collect();
            writeln!(out, "{}", rule.join("-+-")).ok();
        }
    }
    out
}

impl Reconfiguration {
    /// The causal graph and every component's concurrent policy, for review (`kairos plan
    /// --policies`).
    pub fn describe_policies(&self) -> String {
        let plant = self.plant();
        let graph = self.causal_graph();
        let name = |c: ComponentId| plant.component(c).name().to_string();
        let mut out = format!(
            "plant {}: causal graph and concurrent policies\n\n",
            plant.name()
        );
        out.push_str(
            "causal graph (an edge from a component whose mode its target's guards depend on):\n",
        );
        let edges = graph.edges();
        if edges.is_empty() {
            out.push_str("  no edges\n");
        }
        for (from, to) in edges {
            writeln!(out, "  {} -> {}", name(from), name(to)).ok();
        }
        let units: Vec<String> = graph
            .units()
            .iter()
            .map(|unit| {
                unit.iter()
                    .map(|&c| name(c))
                    .collect::<Vec<_>>()
                    .join(" + ")
            })
            .collect();
        writeln!(out, "causal units, upstream first: {}", units.join(", ")).ok();
        let order: Vec<String> = graph.downstream_first().iter().map(|&c| name(c)).collect();
        writeln!(out, "goals are achieved in the order: {}", order.join(", ")).ok();
        for policy in self.policies() {
            let c = policy.component();
            let upstream: Vec<String> = graph.upstream(c).into_iter().map(name).collect();
            let upstream = if upstream.is_empty() {
                "none".to_string()
            } else {
                upstream.join(", ")
            };
            writeln!(out, "\n{} (upstream: {upstream})", name(c)).ok();
            out.push_str(&policy.table(plant));
        }
        out
    }
}
