//! A submission written as a `Network(...)` outside a mission file — a scenario rule's
//! `submit:` (`simulation` module documentation) — resolved against the plant by the mission
//! loader itself: its points, constraints and goals are read by the same code as a mission's, so
//! a goal's constraint means and is checked exactly as in a mission (DESIGN.md §15.4). Reference
//! for users: `docs/reference/scenario.md` (`submit:`) and `docs/reference/mission.md`.

use super::{GoalNetwork, Item, Loader, NetworkFile};
use crate::diagnostic::locate::{Locator, Step};
use crate::diagnostic::{Diagnostic, Source, SourceErrors, ron_error};
use crate::goalnet::{Submission, SubmittedConstraint, SubmittedGoal};
use crate::plant::Plant;

/// The submission written at `at` in `source`, resolved against `plant`. Its goals and
/// constraints may name the points of `network` (the mission's, as loaded) and its own; a
/// submission adds goals only, so macros and goal types are errors. Whether it schedules with the
/// running network is decided when it is submitted (a refusal is an event, not a load error).
pub(crate) fn resolve_submission(
    source: &Source,
    at: &[Step],
    plant: &Plant,
    network: &GoalNetwork,
    file: &NetworkFile,
) -> Result<Submission, Vec<Diagnostic>> {
    let mut loader = Loader {
        source,
        locate: Locator::new(&source.text),
        errors: Vec::new(),
        // Goals on controlled state variables are not submitted (the controllers are the
        // mission's, and a submitted goal names a component).
        controllers: Vec::new(),
    };
    // The submission is read into a copy of the mission's network, so that its names resolve
    // and clash as they will in the running network; what it added is read back out.
    let mut scratch = network.clone();
    let first_goal = scratch.goals().len();
    loader.points(&mut scratch, file, at);
    loader.constraints(&mut scratch, file, at);
    if !file.macros.is_empty() {
        loader.error(
            &[at, &[Step::Field("macros")]].concat(),
            "a submission adds goals, not macros".to_string(),
            "`points`, `constraints` and `goals` only",
        );
    }
    for (k, spec) in file.goals.iter().enumerate() {
        let item = Item {
            prefix: [at, &[Step::Field("goals"), Step::Index(k)]].concat(),
        };
        if spec.goal_type.is_some() {
            loader.error(
                &item.path("type"),
                format!("submitted goal `{}` has a type", spec.name),
                "no `type`: a submitted goal is not elaborated",
            );
        }
        loader.goal(plant, &mut scratch, item, spec);
    }
    if !loader.errors.is_empty() {
        return Err(loader.errors);
    }
    let name = |id| scratch.point(id).name.clone();
    let goals = scratch.goals()[first_goal..]
        .iter()
        .filter_map(|goal| {
            Some(SubmittedGoal {
                name: goal.name.clone(),
                sv: goal.sv?,
                kind: goal.kind,
                constraint: goal.constraint.clone(),
                text: goal.text.clone(),
                start: name(goal.start),
                end: name(goal.end),
                parent: goal.parent.map(|p| scratch.goal(p).name.clone()),
                priority: goal.priority,
            })
        })
        .collect();
    let constraints = file
        .constraints
        .iter()
        .map(|c| {
            let (min, max) = c.bounds();
            SubmittedConstraint {
                from: c.from.clone(),
                to: c.to.clone(),
                min,
                max,
            }
        })
        .collect();
    Ok(Submission {
        points: file.points.clone(),
        constraints,
        goals,
    })
}

/// A submission written on its own as a `Network(points: [...], constraints: [...], goals:
/// [...])` — what an embedder hands a running mission ([`Executive::submit`]) — read and resolved
/// against `mission` (its plant and its network as loaded), every problem located in `source`.
///
/// [`Executive::submit`]: crate::executive::Executive::submit
pub fn parse_submission(
    source: &Source,
    mission: &super::Mission,
) -> Result<Submission, SourceErrors> {
    let options =
        ron::Options::default().with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME);
    let located = |diagnostics| SourceErrors::new(source.clone(), diagnostics);
    let file: NetworkFile = options
        .from_str(&source.text)
        .map_err(|e| located(vec![ron_error(source, &e)]))?;
    resolve_submission(source, &[], &mission.plant, &mission.network, &file).map_err(located)
}
