//! A mission's XGoals as bars on their state variables' lanes (DESIGN.md
//! §15.3): an XGoal is drawn from the cycle it was dispatched until its end point fired — or
//! until the next XGoal on the same state variable took over, or the drawn window ends — in a
//! band under the lane's modes, so that what the executive was asked to hold sits right under
//! what it believed. A bar whose goal failed is outlined in the fault colour from the failure on.
//! A time point's mark (`marks`) carries the window it had when it fired, drawn here as a
//! whisker through the mark.

use svg::node::element::{Group, Rectangle, Title};

use crate::executive::{Event, EventKind};
use crate::plant::{Component, Plant};

use super::labels::{CHAR_WIDTH, clean, ident, shorten};
use super::scale::Clock;
use super::{Picture, px, r, segment, text};

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
            // A promotion took it off its lane.
            EventKind::XGoalWithdrawn { sv, .. } => {
                if let Some(k) = open.iter().position(|o| o.lane == sv.index()) {
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

/// Drawing the goal network: the time points' windows and the XGoal bands.
impl Picture<'_> {
    /// A time point's window `[earliest, latest]` as a whisker through its mark, clipped to the
    /// drawn window; a bound inside it gets an end cap, an open or clipped side has none.
    pub(super) fn whisker(&self, (earliest, latest): (f64, f64), y: f64, colour: &str) -> Group {
        let (start, end) = self.window;
        let (from, to) = (earliest.max(start), latest.min(end));
        let mut group = Group::new().set("class", "window");
        if from > to {
            return group;
        }
        let (x0, x1) = (self.scale.x(from), self.scale.x(to));
        group = group.add(segment(x0, y, x1, y).set("stroke", colour.to_string()));
        for (bound, x) in [(earliest, x0), (latest, x1)] {
            if bound >= start && bound <= end {
                group =
                    group.add(segment(x, y - 4.0, x, y + 4.0).set("stroke", colour.to_string()));
            }
        }
        group
    }

    /// The XGoal bars of one lane, in the band under it (empty when it has none). Bars on one
    /// state variable follow each other, so their labels, each kept inside its bar (and clear of
    /// the breaks), cannot overlap.
    pub(super) fn xgoal_band(&self, lane: usize, component: &Component, y: f64) -> Group {
        let mut group = Group::new().set("class", "xgoals");
        for (k, bar) in self
            .xgoals
            .iter()
            .enumerate()
            .filter(|(_, b)| b.lane == lane)
        {
            let (x0, x1) = (self.scale.x(bar.from), self.scale.x(bar.to));
            let rect = |class: &str, x0: f64, x1: f64| {
                Rectangle::new()
                    .set("class", class.to_string())
                    .set("x", r(x0))
                    .set("y", r(y + 1.0))
                    .set("width", r((x1 - x0).max(2.0)))
                    .set("height", px::XGOAL - 3.0)
            };
            let mut item = Group::new()
                .set("class", "xgoal")
                .set("data-time", bar.from)
                .add(Title::new(clean(&bar.tooltip)))
                .add(rect("xgoal-bar", x0, x1));
            if let Some(failed) = bar.failed {
                item = item.add(rect("xgoal-bar failed", self.scale.x(failed), x1));
            }
            let room = |(left, right): &(f64, f64)| {
                ((right - left - 6.0) / (px::SMALL * CHAR_WIDTH)).floor() as usize
            };
            if let Some(part) = self.visible(x0, x1).into_iter().find(|p| room(p) >= 6) {
                let words = shorten(&bar.label, room(&part));
                item = item.add(
                    text(&words, part.0 + 3.0, y + 10.5)
                        .set("class", "xgoal-label")
                        .set("id", format!("xgoal-{}-{k}", ident(component.name()))),
                );
            }
            group = group.add(item);
        }
        group
    }
}
