//! The checks of DESIGN.md §6.1 that need the model's theory: a mode whose constraint
//! contradicts the model (no way to stay in it or leave it), a guard that can never hold in its
//! source mode, and outgoing probabilities that add up to more than 1 for some combination of
//! guards and clock values. Name, probability, window and distribution checks happen while
//! loading ([`super::file`]).

use super::file::{TOLERANCE, mode_path, transition_path};
use super::{Component, Plant, TransitionSource};
use crate::diagnostic::Diagnostic;
use crate::diagnostic::locate::Locator;
use crate::diagnostic::locate::Step;
use crate::logic::{Formula, ValueId};
use crate::opsat::{Consistency, Literal, Theory};

/// Every problem found, located in the file.
pub(super) fn check(plant: &Plant, locate: &Locator) -> Vec<Diagnostic> {
    let mut theory = match plant.theory() {
        Ok(theory) => theory,
        Err(e) => return vec![Diagnostic::new(e.to_string(), 0..0)],
    };
    let mut errors = Vec::new();
    for (c, component) in plant.components().iter().enumerate() {
        for m in 0..component.modes().len() {
            let mode = ValueId(m as u32);
            let here = Literal::Is(component.mode_var(), mode);
            if let Consistency::Conflict(_) = theory.consistent(&[here]) {
                errors.push(unsatisfiable_mode(component, c, m, locate));
                continue;
            }
            errors.extend(never_enabled_guards(
                &mut theory,
                component,
                c,
                mode,
                locate,
            ));
            if let Some(error) = overfull_mode(&mut theory, component, c, mode, locate) {
                errors.push(error);
            }
        }
    }
    errors
}

fn unsatisfiable_mode(component: &Component, c: usize, m: usize, locate: &Locator) -> Diagnostic {
    Diagnostic::new(
        format!(
            "component `{}`, mode `{}` can never hold: its constraint contradicts the model",
            component.name(),
            component.modes()[m].name
        ),
        locate.at(&mode_path(c, m, "constraint")),
    )
    .expected("a constraint consistent with the interconnections and the other modes")
    .note("the component would have no way to stay in this mode or to leave it")
}

/// Transitions declared from `mode` whose guard contradicts the mode and the model.
fn never_enabled_guards(
    theory: &mut Theory,
    component: &Component,
    c: usize,
    mode: ValueId,
    locate: &Locator,
) -> Vec<Diagnostic> {
    let mut errors = Vec::new();
    for (t, transition) in component.transitions().iter().enumerate() {
        if transition.source != TransitionSource::Mode(mode) || transition.guard == Formula::True {
            continue;
        }
        let here = Literal::Is(component.mode_var(), mode);
        let Ok(guard) = theory.define(&transition.guard) else {
            continue;
        };
        if let Consistency::Conflict(_) = theory.consistent(&[here, guard]) {
            let target = &component.mode(transition.target).name;
            errors.push(
                Diagnostic::new(
                    format!(
                        "component `{}`, transition `{}` -> `{target}` can never be enabled",
                        component.name(),
                        component.mode(mode).name
                    ),
                    locate.at(&transition_path(c, t, &[Step::Field("guard")])),
                )
                .expected(format!(
                    "a guard that can hold while `{}` is `{}`",
                    component.name(),
                    component.mode(mode).name
                )),
            );
        }
    }
    errors
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
    locate: &Locator,
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
        Diagnostic::new(
            format!(
                "component `{}`, mode `{}`: outgoing probabilities can add up to {total}",
                component.name(),
                component.mode(mode).name
            ),
            locate.at(&mode_path(c, mode.index(), "name")),
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
