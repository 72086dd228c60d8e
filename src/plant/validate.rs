//! The checks of DESIGN.md §6.1 that need the model's theory: a mode whose constraint
//! contradicts the model (no way to stay in it or leave it), a guard that can never hold in its
//! source mode, and outgoing probabilities that add up to more than 1 for some combination of
//! guards and clock values. Name, probability, window and distribution checks happen while
//! loading ([`super::file`]).

use std::collections::HashSet;

use super::file::{Places, TOLERANCE};
use super::{Component, Plant, TransitionSource};
use crate::diagnostic::Diagnostic;
use crate::diagnostic::locate::Step;
use crate::logic::{Formula, ValueId};
use crate::opsat::{Consistency, Literal, Theory};

/// Every problem found, located in the file.
pub(super) fn check(plant: &Plant, places: &Places) -> Vec<Diagnostic> {
    let mut theory = match plant.theory() {
        Ok(theory) => theory,
        Err(e) => return vec![Diagnostic::new(e.to_string(), 0..0)],
    };
    let modes_hold = modes_can_hold(&mut theory, plant);
    let guards_hold = guards_can_hold(&mut theory, plant, &modes_hold);
    let mut errors = Vec::new();
    for (c, component) in plant.components().iter().enumerate() {
        for (m, &holds) in modes_hold[c].iter().enumerate() {
            if !holds {
                errors.push(unsatisfiable_mode(component, c, m, places));
                continue;
            }
            let mode = ValueId(m as u32);
            for &(t, holds) in &guards_hold[c] {
                if !holds && component.transitions()[t].source == TransitionSource::Mode(mode) {
                    errors.push(never_enabled(component, c, t, places));
                }
            }
            if let Some(error) = overfull_mode(&mut theory, component, c, mode, places) {
                errors.push(error);
            }
        }
    }
    errors
}

/// Per component and mode, whether the mode can hold with the model.
fn modes_can_hold(theory: &mut Theory, plant: &Plant) -> Vec<Vec<bool>> {
    let checks: Vec<Vec<Vec<Literal>>> = plant
        .components()
        .iter()
        .map(|component| {
            (0..component.modes().len())
                .map(|m| vec![Literal::Is(component.mode_var(), ValueId(m as u32))])
                .collect()
        })
        .collect();
    consistent_each(theory, &checks)
}

/// Per component, its guarded transitions out of a mode that can hold, each with whether its
/// guard can hold in that mode.
fn guards_can_hold(
    theory: &mut Theory,
    plant: &Plant,
    modes_hold: &[Vec<bool>],
) -> Vec<Vec<(usize, bool)>> {
    let mut transitions = Vec::new();
    let mut checks = Vec::new();
    for (c, component) in plant.components().iter().enumerate() {
        let (mut mine, mut queries) = (Vec::new(), Vec::new());
        for (t, transition) in component.transitions().iter().enumerate() {
            let TransitionSource::Mode(mode) = transition.source else {
                continue;
            };
            if transition.guard == Formula::True || !modes_hold[c][mode.index()] {
                continue;
            }
            let Ok(guard) = theory.define(&transition.guard) else {
                continue;
            };
            mine.push(t);
            queries.push(vec![Literal::Is(component.mode_var(), mode), guard]);
        }
        transitions.push(mine);
        checks.push(queries);
    }
    let results = consistent_each(theory, &checks);
    transitions
        .into_iter()
        .zip(results)
        .map(|(mine, holds)| mine.into_iter().zip(holds).collect())
        .collect()
}

/// Whether each check (assumptions on one component, grouped by component) is consistent with
/// the theory. One SAT call per check made validation quadratic in the size of the plant — each
/// call assigns every variable — so the checks are asked in batches, one check per component
/// at a time: a consistent batch settles all its checks at once; when a batch conflicts, the
/// checks in the conflict are asked alone and the others wait for the next batch. A plant whose
/// components are independent takes as many SAT calls as a component has checks.
fn consistent_each(theory: &mut Theory, checks: &[Vec<Vec<Literal>>]) -> Vec<Vec<bool>> {
    let mut results: Vec<Vec<bool>> = checks.iter().map(|c| vec![false; c.len()]).collect();
    let mut next = vec![0usize; checks.len()];
    loop {
        let batch: Vec<usize> = (0..checks.len())
            .filter(|&c| next[c] < checks[c].len())
            .collect();
        if batch.is_empty() {
            return results;
        }
        let assumptions: Vec<Literal> = batch
            .iter()
            .flat_map(|&c| checks[c][next[c]].iter().copied())
            .collect();
        match theory.consistent(&assumptions) {
            Consistency::Consistent => {
                for &c in &batch {
                    results[c][next[c]] = true;
                    next[c] += 1;
                }
            }
            // The model alone is inconsistent: nothing can hold (and no batch would progress).
            Consistency::Conflict(core) if core.is_empty() => return results,
            Consistency::Conflict(core) => {
                let core: HashSet<Literal> = core.into_iter().collect();
                for &c in &batch {
                    let check = &checks[c][next[c]];
                    if check.iter().any(|literal| core.contains(literal)) {
                        results[c][next[c]] = theory.consistent(check).is_consistent();
                        next[c] += 1;
                    }
                }
            }
        }
    }
}

/// A transition declared from a mode whose guard contradicts the mode and the model.
fn never_enabled(component: &Component, c: usize, t: usize, places: &Places) -> Diagnostic {
    let transition = &component.transitions()[t];
    let mode = match transition.source {
        TransitionSource::Mode(mode) => &component.mode(mode).name,
        TransitionSource::AnyNominal => "*",
    };
    let target = &component.mode(transition.target).name;
    places
        .diagnostic(
            c,
            &[
                Step::Field("transitions"),
                Step::Index(t),
                Step::Field("guard"),
            ],
            format!(
                "component `{}`, transition `{mode}` -> `{target}` can never be enabled",
                component.name(),
            ),
        )
        .expected(format!(
            "a guard that can hold while `{}` is `{mode}`",
            component.name(),
        ))
}

fn unsatisfiable_mode(component: &Component, c: usize, m: usize, places: &Places) -> Diagnostic {
    places
        .diagnostic(
            c,
            &[
                Step::Field("modes"),
                Step::Index(m),
                Step::Field("constraint"),
            ],
            format!(
                "component `{}`, mode `{}` can never hold: its constraint contradicts the model",
                component.name(),
                component.modes()[m].name
            ),
        )
        .expected("a constraint consistent with the interconnections and the other modes")
        .note("the component would have no way to stay in this mode or to leave it")
}

/// A transition out of a mode that may fire together with others, with its largest per-step
/// probability and its guard as an assumption (none when the guard is `true`).
struct Outgoing {
    transition: usize,
    probability: f64,
    guard: Option<Literal>,
}

/// Finds a set of transitions out of `mode` whose guards can hold together and whose largest
/// per-step probabilities add up to more than 1 (rates compete as hazards and always fit).
fn overfull_mode(
    theory: &mut Theory,
    component: &Component,
    c: usize,
    mode: ValueId,
    places: &Places,
) -> Option<Diagnostic> {
    let mut outgoing: Vec<Outgoing> = Vec::new();
    for &t in component.outgoing(mode) {
        let transition = &component.transitions()[t];
        let Some(probability) = transition.law.largest_step_probability() else {
            continue;
        };
        let guard = match &transition.guard {
            Formula::True => None,
            guard => Some(theory.define(guard).ok()?),
        };
        outgoing.push(Outgoing {
            transition: t,
            probability,
            guard,
        });
    }
    if outgoing.iter().map(|o| o.probability).sum::<f64>() <= 1.0 + TOLERANCE {
        return None;
    }
    outgoing.sort_by(|a, b| b.probability.total_cmp(&a.probability));
    let base = vec![Literal::Is(component.mode_var(), mode)];
    let together = heaviest_enabled_together(theory, &outgoing, base)?;
    let total: f64 = together.iter().map(|&i| outgoing[i].probability).sum();
    let listed: Vec<String> = together
        .iter()
        .map(|&i| {
            let transition = &component.transitions()[outgoing[i].transition];
            format!(
                "`{}` ({})",
                component.mode(transition.target).name,
                outgoing[i].probability
            )
        })
        .collect();
    Some(
        places
            .diagnostic(
                c,
                &[
                    Step::Field("modes"),
                    Step::Index(mode.index()),
                    Step::Field("name"),
                ],
                format!(
                    "component `{}`, mode `{}`: outgoing probabilities can add up to {total}",
                    component.name(),
                    component.mode(mode).name
                ),
            )
            .expected("at most 1: the mode stays with what its enabled transitions leave")
            .note(format!(
                "transitions to {} can be enabled together",
                listed.join(", ")
            )),
    )
}

/// Depth-first search, heaviest first, for transitions whose guards are consistent together and
/// whose probabilities exceed 1; branches that cannot exceed 1 are cut.
fn heaviest_enabled_together(
    theory: &mut Theory,
    outgoing: &[Outgoing],
    assumptions: Vec<Literal>,
) -> Option<Vec<usize>> {
    let mut chosen = Vec::new();
    search(theory, outgoing, 0, &mut chosen, assumptions, 0.0)
}

fn search(
    theory: &mut Theory,
    outgoing: &[Outgoing],
    next: usize,
    chosen: &mut Vec<usize>,
    assumptions: Vec<Literal>,
    sum: f64,
) -> Option<Vec<usize>> {
    if sum > 1.0 + TOLERANCE {
        return Some(chosen.clone());
    }
    let rest: f64 = outgoing[next..].iter().map(|o| o.probability).sum();
    if next == outgoing.len() || sum + rest <= 1.0 + TOLERANCE {
        return None;
    }
    let candidate = &outgoing[next];
    let mut with = assumptions.clone();
    with.extend(candidate.guard);
    if theory.consistent(&with) == Consistency::Consistent {
        chosen.push(next);
        let found = search(
            theory,
            outgoing,
            next + 1,
            chosen,
            with,
            sum + candidate.probability,
        );
        if found.is_some() {
            return found;
        }
        chosen.pop();
    }
    search(theory, outgoing, next + 1, chosen, assumptions, sum)
}
