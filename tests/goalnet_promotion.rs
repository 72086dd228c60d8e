//! Promotion (mds-goal-networks.md §2.3 steps a–j): on random small
//! missions — random proposals of points, temporal constraints and goals promoted over a
//! running thermostat network at a random time from a random estimate — a promotion never
//! leaves the running network inconsistent, keeps every fired point fired at its time and
//! every id meaning the same point, and a failed promotion changes nothing.

#[path = "support/seeded.rs"]
mod seeded;

use std::path::Path;

use kairos::goalnet::{
    ConstraintSet, EstimateView, Goal, GoalController, GoalKind, MissionEvent, Provenance,
    TemporalConstraint, TimePointId, Timeline, Window, mission,
};
use kairos::logic::ValueId;
use kairos::plant::{ComponentId, Plant};
use kairos::reconfiguration::Reconfiguration;
use proptest::prelude::*;

/// One edit of a proposal; indices are taken modulo what exists when it is applied.
#[derive(Debug, Clone)]
enum Edit {
    Point,
    Constraint {
        from: usize,
        to: usize,
        min: i32,
        length: i32,
    },
    Goal {
        sv: usize,
        kind: u8,
        mask: u8,
        start: usize,
        end: usize,
    },
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        Just(Edit::Point),
        (0..12usize, 0..12usize, -20..120i32, 0..60i32).prop_map(|(from, to, min, length)| {
            Edit::Constraint {
                from,
                to,
                min,
                length,
            }
        }),
        (0..4usize, 0..3u8, 1..16u8, 0..12usize, 0..12usize).prop_map(
            |(sv, kind, mask, start, end)| Edit::Goal {
                sv,
                kind,
                mask,
                start,
                end,
            }
        ),
    ]
}

/// Everything a promotion may change, to compare before and after.
#[derive(Debug, PartialEq)]
struct Fingerprint {
    points: Vec<String>,
    windows: Vec<Option<Window>>,
    fired: Vec<Option<f64>>,
    constraints: usize,
    goals: Vec<String>,
    timelines: Vec<Timeline>,
}

fn fingerprint(controller: &GoalController) -> Fingerprint {
    let network = controller.network();
    let ids = (0..network.points().len() as u32).map(TimePointId);
    Fingerprint {
        points: network.points().iter().map(|p| p.name.clone()).collect(),
        windows: ids.clone().map(|p| network.stn().window(p)).collect(),
        fired: ids.map(|p| controller.execution().fired_at(p)).collect(),
        constraints: network.stn().constraints().len(),
        goals: network.goals().iter().map(|g| g.name.clone()).collect(),
        timelines: controller.execution().executable().timelines.clone(),
    }
}

/// ŝ: a mode per component (taken modulo its modes), each certain.
fn estimate(plant: &Plant, modes: &[usize]) -> (Vec<ValueId>, Vec<Vec<f64>>) {
    let values: Vec<ValueId> = plant
        .components()
        .iter()
        .zip(modes)
        .map(|(c, m)| ValueId((m % c.modes().len()) as u32))
        .collect();
    let beliefs = plant
        .components()
        .iter()
        .zip(&values)
        .map(|(c, v)| {
            (0..c.modes().len())
                .map(|i| if i == v.index() { 1.0 } else { 0.0 })
                .collect()
        })
        .collect();
    (values, beliefs)
}

proptest! {
    #![proptest_config(seeded::config(96))]

    /// Promotion is atomic: either the proposal runs, consistent, with the old network's
    /// history (its points, their firing times) intact, or nothing changed at all.
    #[test]
    fn promotion_keeps_the_running_network_consistent_or_changes_nothing(
        rounds in prop::collection::vec(
            (prop::collection::vec(edit(), 1..8), 1..60u32, prop::collection::vec(0..6usize, 4)),
            1..4,
        ),
    ) {
        std::env::set_current_dir(env!("CARGO_MANIFEST_DIR")).expect("the crate root exists");
        let mission = mission::load(Path::new("missions/thermostat_know_all.ron")).expect("loads");
        let plant = mission.plant.clone();
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let (modes, beliefs) = estimate(&plant, &[0, 0, 0, 0]);
        let view = EstimateView { modes: &modes, beliefs: &beliefs };
        let mut controller = GoalController::new(&mission, &reconfiguration, 0.0, view);
        let mut now = 0.0;
        for (edits, wait, modes) in rounds {
            let (modes, beliefs) = estimate(&plant, &modes);
            let view = EstimateView { modes: &modes, beliefs: &beliefs };
            for _ in 0..wait {
                controller.step(now, view, &reconfiguration);
                now += 1.0;
            }
            let before = fingerprint(&controller);
            let mut proposal = controller.propose();
            for (i, e) in edits.iter().enumerate() {
                apply(&mut proposal, &plant, e, i);
            }
            let events = controller.promote(proposal, now, view, &reconfiguration);
            let after = fingerprint(&controller);
            let promoted = events.iter().any(|e| matches!(e, MissionEvent::Promoted { .. }));
            let failed = events.iter().any(|e| matches!(e, MissionEvent::PromotionFailed { .. }));
            prop_assert!(promoted != failed, "{events:?}");
            if failed {
                prop_assert_eq!(&after, &before);
            } else {
                let mut stn = controller.network().stn().clone();
                prop_assert!(stn.propagate().is_ok());
                prop_assert!(after.windows.iter().all(Option::is_some));
                let n = before.points.len();
                prop_assert_eq!(&after.points[..n], &before.points[..]);
                prop_assert_eq!(&after.fired[..n], &before.fired[..]);
                // No new point in the past (step b).
                for w in &after.windows[n..] {
                    prop_assert!(w.as_ref().is_some_and(|w| w.ub >= now), "{w:?} before {now}");
                }
            }
        }
    }
}

fn apply(proposal: &mut kairos::goalnet::Proposal, plant: &Plant, edit: &Edit, i: usize) {
    let points = proposal.network().points().len();
    let point = |k: usize| TimePointId((k % points) as u32);
    match *edit {
        Edit::Point => {
            proposal.add_point(&format!("p{i}"), 0..0);
        }
        Edit::Constraint {
            from,
            to,
            min,
            length,
        } => {
            let (min, max) = (f64::from(min), f64::from(min + length));
            let c =
                TemporalConstraint::new(point(from), point(to), min, max, Provenance::Submitted);
            // Bounds are valid and the points exist: accepted (consistency is promotion's).
            let _ = proposal.add_constraint(c);
        }
        Edit::Goal {
            sv,
            kind,
            mask,
            start,
            end,
        } => {
            let sv = ComponentId((sv % plant.components().len()) as u32);
            let domain = plant.component(sv).modes().len();
            let kind = [
                GoalKind::Maintain,
                GoalKind::Transition,
                GoalKind::Knowledge,
            ][kind as usize];
            let constraint = match kind {
                GoalKind::Knowledge => ConstraintSet::unconstrained(domain).with_known(),
                _ => ConstraintSet::control(domain, |v| mask & (1 << (v.index() % 4)) != 0),
            };
            let goal = Goal {
                name: format!("g{i}"),
                sv: Some(sv),
                kind,
                constraint,
                delegate: None,
                text: String::new(),
                start: point(start),
                end: point(end),
                parent: None,
                priority: 0,
                span: 0..0,
            };
            proposal.add_goal(goal, None);
        }
    }
}
