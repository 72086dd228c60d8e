//! The scheduler as it was before its cost was made near-linear, kept as the oracle of the
//! property test below: it copies the network for every trial and propagates it in full, sorts
//! every candidate of every step with a scan of the constraints, and asks Bellman–Ford whether
//! each pair of consecutive points coincides. The property: on random small missions (random
//! points, constraints, goals of every kind on the thermostat's state variables, fired points)
//! and on the generated workloads, [`schedule`](super::schedule) gives the same answer —
//! the same timelines, the same constraints added in the same order, the same windows, or the
//! same error.

use super::{Fired, ScheduleError, order::ORDER_BUDGET, project, require_intervals, reversed};
use crate::goalnet::goal::GoalId;
use crate::goalnet::network::{ExecutableNetwork, GoalNetwork, Timeline};
use crate::goalnet::stn::{Inconsistency, Stn};
use crate::goalnet::temporal_constraint::{Provenance, TemporalConstraint};
use crate::goalnet::time_point::TimePointId;
use crate::goalnet::xgoal::XGoal;
use crate::logic::ValueId;
use crate::plant::ComponentId;
use crate::reconfiguration::Reconfiguration;

/// The scheduler before: the same steps, each the slow way.
pub(super) fn schedule(
    network: &GoalNetwork,
    reconfiguration: &Reconfiguration,
    current: &[ValueId],
) -> Result<ExecutableNetwork, ScheduleError> {
    let given = network.stn().constraints().len();
    let mut network = network.clone();
    network.propagate().map_err(ScheduleError::Inconsistent)?;
    require_intervals(&mut network)?;
    network
        .propagate()
        .map_err(|inconsistency| reversed(&network, given, inconsistency))?;
    let plant = reconfiguration.plant();
    let fired = Fired::of(&network);
    let mut timelines = Vec::new();
    for &sv in reconfiguration.upstream_first() {
        let goals: Vec<GoalId> = network.goals_on(sv).map(|(id, _)| id).collect();
        if goals.is_empty() {
            continue;
        }
        serialise(&mut network, sv, &goals)?;
        let points = order(&mut network, &goals)?;
        let domain = plant.component(sv).modes().len();
        let xgoals = xgoals(&network, sv, domain, &goals, &points, &fired)?;
        let timeline = Timeline { sv, points, xgoals };
        project(reconfiguration, &timeline, current[sv.index()], &fired)?;
        timelines.push(timeline);
    }
    Ok(ExecutableNetwork { network, timelines })
}

fn serialise(
    network: &mut GoalNetwork,
    sv: ComponentId,
    goals: &[GoalId],
) -> Result<(), ScheduleError> {
    for (i, &a) in goals.iter().enumerate() {
        for &b in &goals[i + 1..] {
            match serialised(network, a, b) {
                Pairing::Merge => {}
                Pairing::Serialised(stn) => *network.stn_mut() = stn,
                Pairing::Conflict => {
                    let conflicts = (goals.iter().copied())
                        .filter(|&c| {
                            c != b && matches!(serialised(network, c, b), Pairing::Conflict)
                        })
                        .collect();
                    return Err(ScheduleError::Unmergeable {
                        sv,
                        goal: b,
                        conflicts,
                    });
                }
            }
        }
    }
    Ok(())
}

/// How two goals on one SV can share its timeline.
enum Pairing {
    /// Their constraints merge: no ordering needed.
    Merge,
    /// They do not merge; one ends before the other starts (the STN with that added).
    Serialised(Stn),
    /// They do not merge and cannot be serialised either way.
    Conflict,
}

/// Whether goals `a` and `b` merge, or else a copy of the STN with `end(a) ≤ start(b)` or else
/// `end(b) ≤ start(a)` added and propagated in full (the first consistent).
fn serialised(network: &GoalNetwork, a: GoalId, b: GoalId) -> Pairing {
    let (ga, gb) = (network.goal(a), network.goal(b));
    if !ga.constraint.merge(&gb.constraint).is_empty() {
        return Pairing::Merge;
    }
    let first = (
        ga.end,
        gb.start,
        format!("end({}) ≤ start({})", ga.name, gb.name),
    );
    let second = (
        gb.end,
        ga.start,
        format!("end({}) ≤ start({})", gb.name, ga.name),
    );
    let stn = [first, second]
        .into_iter()
        .find_map(|(end, start, reason)| {
            let mut trial = network.stn().clone();
            let constraint =
                TemporalConstraint::before(end, start, Provenance::Scheduled { reason });
            trial.add_constraint(constraint).ok()?;
            trial.propagate().ok()?;
            Some(trial)
        });
    stn.map_or(Pairing::Conflict, Pairing::Serialised)
}

fn order(network: &mut GoalNetwork, goals: &[GoalId]) -> Result<Vec<TimePointId>, ScheduleError> {
    let mut points: Vec<TimePointId> = goals
        .iter()
        .flat_map(|g| [network.goal(*g).start, network.goal(*g).end])
        .collect();
    points.sort_unstable();
    points.dedup();
    let mut search = OrderSearch {
        budget: ORDER_BUDGET,
        last_failure: None,
    };
    match search.place(network.stn().clone(), Vec::new(), points) {
        Some((stn, order)) => {
            *network.stn_mut() = stn;
            Ok(order)
        }
        None => Err(ScheduleError::Inconsistent(
            search
                .last_failure
                .unwrap_or(Inconsistency { cycle: Vec::new() }),
        )),
    }
}

struct OrderSearch {
    budget: usize,
    last_failure: Option<Inconsistency>,
}

impl OrderSearch {
    fn place(
        &mut self,
        stn: Stn,
        placed: Vec<TimePointId>,
        remaining: Vec<TimePointId>,
    ) -> Option<(Stn, Vec<TimePointId>)> {
        if remaining.is_empty() {
            return Some((stn, placed));
        }
        let mut candidates = remaining.clone();
        let earliest = |p: &TimePointId| stn.window(*p).map_or(0.0, |w| w.lb);
        let follows = |p: &TimePointId| {
            stn.constraints()
                .iter()
                .any(|c| c.to == *p && c.from != *p && c.min >= 0.0 && remaining.contains(&c.from))
        };
        candidates.sort_by(|a, b| {
            earliest(a)
                .total_cmp(&earliest(b))
                .then(follows(a).cmp(&follows(b)))
                .then(a.cmp(b))
        });
        for candidate in candidates {
            if self.budget == 0 {
                return None;
            }
            self.budget -= 1;
            let mut trial = stn.clone();
            if let Some(&last) = placed.last() {
                let reason = "the state variable's timeline is ordered".to_string();
                let constraint =
                    TemporalConstraint::before(last, candidate, Provenance::Scheduled { reason });
                if trial.add_constraint(constraint).is_err() {
                    continue;
                }
                if let Err(inconsistency) = trial.propagate() {
                    self.last_failure = Some(inconsistency);
                    continue;
                }
            }
            let mut next_placed = placed.clone();
            next_placed.push(candidate);
            let rest = remaining
                .iter()
                .copied()
                .filter(|p| *p != candidate)
                .collect();
            if let Some(found) = self.place(trial, next_placed, rest) {
                return Some(found);
            }
        }
        None
    }
}

fn xgoals(
    network: &GoalNetwork,
    sv: ComponentId,
    domain: usize,
    goals: &[GoalId],
    points: &[TimePointId],
    fired: &Fired,
) -> Result<Vec<XGoal>, ScheduleError> {
    let position = |p: TimePointId| points.iter().position(|q| *q == p).unwrap_or(0);
    let mut out = Vec::new();
    let mut covered = vec![false; goals.len()];
    for (i, pair) in points.windows(2).enumerate() {
        let (a, b) = (pair[0], pair[1]);
        if network.stn().distance(a, b).is_some_and(|d| d <= 0.0) {
            continue;
        }
        let covering: Vec<(GoalId, &crate::goalnet::goal::Goal)> = (goals.iter().enumerate())
            .filter_map(|(k, &id)| {
                let goal = network.goal(id);
                let covers = position(goal.start) <= i && position(goal.end) > i;
                covered[k] |= covers;
                covers.then_some((id, goal))
            })
            .collect();
        out.push(XGoal::merge(sv, a, b, domain, covering));
    }
    if let Some(k) =
        (0..goals.len()).find(|&k| !covered[k] && !fired.contains(network.goal(goals[k]).end))
    {
        return Err(ScheduleError::EmptyInterval { goal: goals[k] });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use proptest::prelude::*;

    use super::*;
    use crate::diagnostic::Source;
    use crate::goalnet::constraint_set::ConstraintSet;
    use crate::goalnet::goal::{Goal, GoalKind};
    use crate::goalnet::mission;
    use crate::plant::Plant;

    use crate::goalnet::schedule::goal_workload;
    use crate::seeded;

    fn thermostat() -> Reconfiguration {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("models/thermostat.ron");
        let source = Source::read(&path).expect("the thermostat model reads");
        let plant = Plant::load(&source).expect("the thermostat model loads");
        Reconfiguration::compile(&plant).expect("the thermostat compiles")
    }

    /// The same answer: equal errors, or equal timelines, constraints and windows.
    fn assert_same(
        new: Result<ExecutableNetwork, ScheduleError>,
        old: Result<ExecutableNetwork, ScheduleError>,
    ) -> Result<(), TestCaseError> {
        match (new, old) {
            (Err(new), Err(old)) => prop_assert_eq!(new, old),
            (Ok(new), Ok(old)) => {
                prop_assert_eq!(&new.timelines, &old.timelines);
                let (stn, reference) = (new.network.stn(), old.network.stn());
                prop_assert_eq!(stn.constraints(), reference.constraints());
                for p in 0..stn.point_count() {
                    let p = TimePointId(p as u32);
                    prop_assert_eq!(stn.window(p), reference.window(p));
                }
            }
            (new, old) => prop_assert!(false, "new {new:?}\nold {old:?}"),
        }
        Ok(())
    }

    /// A drawn goal: SV, kind, admitted modes (bits), knowledge, start and end point.
    type DrawnGoal = (usize, u8, u8, bool, u32, u32);
    /// A drawn constraint: from, to, min (or none), width (or unbounded).
    type DrawnConstraint = (u32, u32, Option<i32>, Option<u32>);

    fn mission() -> impl Strategy<Value = (u32, Vec<DrawnConstraint>, Vec<DrawnGoal>, Vec<u32>)> {
        (1..9u32).prop_flat_map(|n| {
            let point = 0..=n;
            let constraint = (
                point.clone(),
                point.clone(),
                proptest::option::weighted(0.8, -3..20i32),
                proptest::option::weighted(0.5, 0..40u32),
            );
            let goal = (
                0..4usize,
                0..4u8,
                1..16u8,
                any::<bool>(),
                point.clone(),
                point.clone(),
            );
            (
                Just(n),
                proptest::collection::vec(constraint, 0..7),
                proptest::collection::vec(goal, 1..10),
                proptest::collection::vec(point, 0..2),
            )
        })
    }

    fn network(
        reconfiguration: &Reconfiguration,
        (points, constraints, goals, fired): &(u32, Vec<DrawnConstraint>, Vec<DrawnGoal>, Vec<u32>),
    ) -> GoalNetwork {
        let mut network = GoalNetwork::new();
        for i in 1..=*points {
            network.add_point(format!("p{i}"), 0..0);
        }
        for &(from, to, min, width) in constraints {
            let min = min.map_or(f64::NEG_INFINITY, f64::from);
            let max = match (min.is_finite(), width) {
                (true, Some(width)) => min + f64::from(width),
                (false, Some(width)) => f64::from(width),
                (_, None) => f64::INFINITY,
            };
            // Mostly forward, so that most networks are consistent and get scheduled.
            let (from, to) = (from.min(to), from.max(to));
            let provenance = Provenance::Written(0..0);
            let c =
                TemporalConstraint::new(TimePointId(from), TimePointId(to), min, max, provenance);
            let _ = network.add_constraint(c);
        }
        for &p in fired {
            let at = f64::from(p * 3);
            let c = TemporalConstraint::new(
                TimePointId::ORIGIN,
                TimePointId(p),
                at,
                at,
                Provenance::Fired,
            );
            let _ = network.add_constraint(c);
        }
        let plant = reconfiguration.plant();
        for (i, &(sv, kind, admitted, known, start, end)) in goals.iter().enumerate() {
            // Mostly forward; a goal over one point or backwards now and then.
            let (start, end) = if i % 5 == 4 {
                (start, end)
            } else {
                (start.min(end), start.max(end))
            };
            let domain = plant.components()[sv].modes().len();
            let mut constraint =
                ConstraintSet::control(domain, |v| admitted >> (v.index() % 4) & 1 == 1);
            if known {
                constraint = constraint.with_known();
            }
            let kind = [
                GoalKind::Maintain,
                GoalKind::Transition,
                GoalKind::Knowledge,
                GoalKind::Unconstrained,
            ][kind as usize];
            if kind == GoalKind::Knowledge {
                constraint = ConstraintSet::unconstrained(domain).with_known();
            }
            network.add_goal(Goal {
                name: format!("g{i}"),
                sv: Some(ComponentId(sv as u32)),
                kind,
                constraint,
                delegate: None,
                text: String::new(),
                start: TimePointId(start),
                end: TimePointId(end),
                parent: None,
                priority: 0,
                span: 0..0,
            });
        }
        network
    }

    proptest! {
        #![proptest_config(seeded::config(1024))]

        /// DESIGN.md §15.2: the near-linear scheduler answers as the scheduler before did.
        #[test]
        fn the_scheduler_answers_as_before(drawn in mission(), modes in proptest::collection::vec(0..4u32, 4)) {
            let reconfiguration = thermostat();
            let network = network(&reconfiguration, &drawn);
            let plant = reconfiguration.plant();
            let current: Vec<ValueId> = (plant.components().iter().zip(&modes))
                .map(|(c, &m)| ValueId(m % c.modes().len() as u32))
                .collect();
            let new = super::super::schedule(&network, &reconfiguration, &current);
            let old = schedule(&network, &reconfiguration, &current);
            assert_same(new, old)?;
        }
    }

    /// The generated workloads (tests/support/goal_workload.rs) of every kind, at a size the
    /// scheduler before handles quickly, schedule as before.
    #[test]
    fn the_workloads_schedule_as_before() {
        let reconfiguration = thermostat();
        let current = vec![ValueId(0); reconfiguration.plant().components().len()];
        use goal_workload::Kind;
        for kind in [Kind::Knowledge, Kind::Maintain, Kind::Transition] {
            let text = goal_workload::mission(40, kind);
            let source = Source::new("workload.ron", text);
            let mission = mission::load_source(&source, goal_workload::dir()).expect("loads");
            let new = super::super::schedule(&mission.network, &reconfiguration, &current);
            let old = schedule(&mission.network, &reconfiguration, &current);
            assert!(new.is_ok(), "{kind:?}: {new:?}");
            assert_same(new, old).expect("the same schedule");
        }
    }
}
