//! A mission's XGoals as bars on their state variables' lanes (issue 13 item 5; DESIGN.md
//! §15.3): an XGoal is drawn from the cycle it was dispatched until its end point fired — or
//! until the next XGoal on the same state variable took over, or the drawn window ends — in a
//! band under the lane's modes, so that what the executive was asked to hold sits right under
//! what it believed. A bar whose goal failed is outlined in the fault colour from the failure on.

use crate::executive::{Event, EventKind};
use crate::plant::Plant;

use super::labels::shorten;
use super::scale::Clock;

/// One XGoal's bar.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct XGoalBar {
    /// The lane (the state variable's component index).
    pub lane: usize,
    /// When it was dispatched (clipped to the window).
    pub from: f64,
    /// When it ended (clipped to the window).
    pub to: f64,
    /// When one of its goals failed, if one did.
    pub failed: Option<f64>,
    /// Its text inside the bar: `Maintain temp ∈ {warm}`.
    pub label: String,
    /// The full text, on hover.
    pub tooltip: String,
}

/// An XGoal dispatched and not yet ended.
struct Open {
    lane: usize,
    from: f64,
    end_point: String,
    goals: Vec<String>,
    failed: Option<f64>,
    label: String,
    /// The tooltip without its times.
    about: String,
}

/// The bars of the XGoals dispatched in `events`, clipped to `window`, in dispatch order.
pub(super) fn collect(
    plant: &Plant,
    events: &[Event],
    window: (f64, f64),
    clock: Clock,
) -> Vec<XGoalBar> {
    let mut events: Vec<&Event> = events.iter().collect();
    events.sort_by(|a, b| a.time.total_cmp(&b.time));
    let mut open: Vec<Open> = Vec::new();
    let mut bars = Vec::new();
    let close = |bar: Open, to: f64, bars: &mut Vec<XGoalBar>| {
        let (from, to) = (bar.from.max(window.0), to.min(window.1));
        if from > to {
            return;
        }
        let failed = bar
            .failed
            .map(|t| format!("; a goal failed at {}", clock.precise(t)))
            .unwrap_or_default();
        bars.push(XGoalBar {
            lane: bar.lane,
            from,
            to,
            failed: bar.failed.map(|t| t.clamp(from, to)),
            tooltip: format!(
                "{} from {} to {}{failed}",
                bar.about,
                clock.precise(from),
                clock.precise(to)
            ),
            label: bar.label,
        });
    };
    for event in events {
        let time = event.time;
        match &event.kind {
            EventKind::XGoalDispatched {
                sv,
                constraint,
                kind,
                interval,
                goals,
            } => {
                let lane = sv.index();
                if let Some(k) = open.iter().position(|o| o.lane == lane) {
                    close(open.remove(k), time, &mut bars);
                }
                let name = plant
                    .components()
                    .get(lane)
                    .map_or_else(|| format!("component {}", sv.0), |c| c.name().to_string());
                // The constraint names its state variable when it has a control part.
                let what = if constraint.starts_with(&name) {
                    constraint.clone()
                } else {
                    format!("{name} {constraint}")
                };
                open.push(Open {
                    lane,
                    from: time,
                    end_point: interval.1.clone(),
                    goals: goals.clone(),
                    failed: None,
                    label: shorten(&format!("{kind} {what}"), 60),
                    about: format!(
                        "{kind} XGoal {what} over [{}, {}] ({})",
                        interval.0,
                        interval.1,
                        goals.join(", ")
                    ),
                });
            }
            EventKind::TimePointFired { point, .. } | EventKind::TimePointForced { point, .. } => {
                while let Some(k) = open.iter().position(|o| &o.end_point == point) {
                    close(open.remove(k), time, &mut bars);
                }
            }
            EventKind::MissionGoalFailed { goal, .. } => {
                for bar in open.iter_mut().filter(|o| o.goals.contains(goal)) {
                    bar.failed.get_or_insert(time);
                }
            }
            _ => {}
        }
    }
    for bar in open {
        close(bar, window.1, &mut bars);
    }
    bars.sort_by(|a, b| a.from.total_cmp(&b.from));
    bars
}
