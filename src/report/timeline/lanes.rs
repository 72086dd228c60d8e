//! The swimlanes: one per state variable, its most likely mode over time as segments, fault
//! segments with a callout, a lane's XGoal band under it (see the parent module's doc).

use svg::node::element::{Group, Rectangle, Text, Title};

use super::draw::{r, r2, text};
use super::labels::{clean, ident, text_width};
use super::scale::format_duration;
use super::{Picture, UNCERTAIN, fill, px};
use crate::executive::Interval;
use crate::plant::{Component, ModeKind};

impl Picture<'_> {
    pub(super) fn lanes(&self) -> Group {
        let plant = self.input.plant;
        let mut group = Group::new().set("id", "lanes");
        for (index, component) in plant.components().iter().enumerate() {
            let y = self.lane_tops[index];
            let timeline = self.input.timelines.state(index);
            let intervals: Vec<&Interval> = timeline
                .map(|t| t.intervals().collect())
                .unwrap_or_default();
            group = group.add(self.lane(index, component, &intervals, y));
            if self.xgoals.iter().any(|b| b.lane == index) {
                group = group.add(self.xgoal_band(index, component, y + px::LANE));
            }
        }
        group
    }

    pub(super) fn lane(
        &self,
        index: usize,
        component: &Component,
        intervals: &[&Interval],
        y: f64,
    ) -> Group {
        let faulty = intervals.iter().any(|i| is_fault(component, i));
        let stripe = if index % 2 == 0 { "#f7f7f7" } else { "#ffffff" };
        let mut group = Group::new()
            .set("class", "lane")
            .set("id", format!("lane-{}", ident(component.name())))
            .set("data-component", clean(component.name()))
            .add(
                Rectangle::new()
                    .set("x", r(px::MARGIN))
                    .set("y", r(y))
                    .set("width", r(self.plot_right - px::MARGIN))
                    .set("height", px::LANE)
                    .set("fill", stripe),
            )
            .add(
                text(component.name(), self.plot_left - 8.0, y + 14.0)
                    .set(
                        "class",
                        if faulty {
                            "lane-name faulty"
                        } else {
                            "lane-name"
                        },
                    )
                    .set("text-anchor", "end"),
            );
        if intervals.is_empty() {
            return group
                .add(text("no estimate", self.plot_left + px::PAD, y + 14.0).set("class", "none"));
        }
        let colours = mode_colours(component);
        let drawn = self.drawn_intervals(intervals);
        // A fault too brief for its name inside gets it beside the segment (a callout); the
        // nominal names keep clear of it (the fault is labelled, nothing
        // overlaps).
        let callouts: Vec<Callout> = drawn
            .iter()
            .filter(|d| is_fault(component, intervals[d.k]))
            .filter_map(|d| self.callout(index, component, intervals[d.k], d, y))
            .collect();
        let reserved: Vec<(f64, f64)> = callouts.iter().map(|c| (c.left, c.right)).collect();
        // Faults are drawn after the nominal segments so that a brief one stays on top.
        let mut faults = Vec::new();
        for d in &drawn {
            let interval = intervals[d.k];
            let fill = colours
                .get(interval.value.index())
                .copied()
                .unwrap_or(fill::INITIAL);
            let segment = self.segment(index, component, interval, d, y, fill, &reserved);
            if is_fault(component, interval) {
                faults.push(segment);
            } else {
                group = group.add(segment);
            }
        }
        let group = faults.into_iter().fold(group, Group::add);
        callouts.into_iter().fold(group, |g, c| g.add(c.text))
    }

    /// The intervals inside the window with their times and x, clipped to it.
    pub(super) fn drawn_intervals(&self, intervals: &[&Interval]) -> Vec<Drawn> {
        let (start, end) = self.window;
        let mut drawn = Vec::new();
        for (k, interval) in intervals.iter().enumerate() {
            let next = intervals.get(k + 1).map(|n| n.from);
            if interval.from > end || next.is_some_and(|n| n < start) {
                continue;
            }
            let (from, to) = (interval.from.max(start), next.unwrap_or(end).min(end));
            let x0 = self.scale.x(from);
            // A value still held at the end runs into the padding after it, so that one
            // estimated at the last cycle shows.
            let x1 = match next {
                Some(n) if n <= end => self.scale.x(n),
                _ => self.scale.end_x() + px::PAD,
            };
            drawn.push(Drawn {
                k,
                from,
                to,
                x0,
                x1,
            });
        }
        drawn
    }

    /// The text of a fault segment: its note number and its mode.
    pub(super) fn fault_text(
        &self,
        lane: usize,
        component: &Component,
        interval: &Interval,
        k: usize,
    ) -> String {
        let mode = mode_name(component, interval);
        match self.segment_notes.get(&(lane, k)) {
            Some(n) => format!("[{n}] {mode}"),
            None => mode,
        }
    }

    /// The label beside a fault segment too narrow for it: right of the segment, or left of it
    /// when that would pass the plot's edge.
    pub(super) fn callout(
        &self,
        lane: usize,
        component: &Component,
        interval: &Interval,
        d: &Drawn,
        y: f64,
    ) -> Option<Callout> {
        let words = self.fault_text(lane, component, interval, d.k);
        let width = text_width(&words, px::SMALL);
        let fits_inside = self
            .visible(d.x0, d.x1)
            .iter()
            .any(|(l, r)| r - l >= width + 6.0);
        if fits_inside {
            return None;
        }
        // Right of the segment, else left of it, wherever the text stays clear of the breaks'
        // bands and inside the plot; where neither has room for the name, the note's number
        // alone (the note under the picture has the rest).
        let room = self.visible(self.plot_left, self.plot_right);
        let right_end = d.x0 + (d.x1 - d.x0).max(px::MIN_FAULT);
        let number = self
            .segment_notes
            .get(&(lane, d.k))
            .map(|n| format!("[{n}]"));
        let (words, left) = [Some(words), number]
            .into_iter()
            .flatten()
            .find_map(|words| {
                let width = text_width(&words, px::SMALL);
                [right_end + 3.0, d.x0 - 3.0 - width]
                    .into_iter()
                    .find(|&left| room.iter().any(|&(a, b)| left >= a && left + width <= b))
                    .map(|left| (words, left))
            })?;
        let width = text_width(&words, px::SMALL);
        let text = text(&words, left, y + 13.5)
            .set("class", "mode callout")
            .set(
                "id",
                format!("fault-label-{}-{}", ident(component.name()), d.k),
            );
        Some(Callout {
            left,
            right: left + width,
            text,
        })
    }

    /// One interval's segment in a lane: rectangle, tooltip, and its mode's name in every
    /// stretch between breaks wide enough for it and clear of the lane's callouts.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn segment(
        &self,
        lane: usize,
        component: &Component,
        interval: &Interval,
        d: &Drawn,
        y: f64,
        fill: &str,
        reserved: &[(f64, f64)],
    ) -> Group {
        let fault = is_fault(component, interval);
        let min_p = probability(interval.min_probability);
        let uncertain = min_p < UNCERTAIN;
        let class = match (fault, uncertain) {
            (true, true) => "interval fault uncertain",
            (true, false) => "interval fault",
            (false, true) => "interval uncertain",
            (false, false) => "interval",
        };
        let tooltip = self.segment_tooltip(component, interval, (d.from, d.to));
        let mut rect = Rectangle::new()
            .set("class", class)
            .set("data-mode", clean(&mode_name(component, interval)))
            .set("x", r(d.x0))
            .set("y", r(y + 2.0))
            .set(
                "width",
                r((d.x1 - d.x0).max(if fault { px::MIN_FAULT } else { 1.0 })),
            )
            .set("height", px::LANE - 4.0)
            .set("fill", fill.to_string())
            .set("fill-opacity", r2(0.3 + 0.7 * min_p))
            .add(Title::new(clean(&tooltip)));
        if uncertain {
            rect = rect.set("stroke", "#555555").set("stroke-dasharray", "3,2");
        }
        let mut group = Group::new().add(rect);
        let words = if fault {
            self.fault_text(lane, component, interval, d.k)
        } else {
            mode_name(component, interval)
        };
        let width = text_width(&words, px::SMALL);
        for (part, (left, right)) in self.visible(d.x0, d.x1).into_iter().enumerate() {
            let Some(start) = clear_of(left + 3.0, width, right - 3.0, reserved) else {
                continue;
            };
            let label = text(&words, start, y + 13.5)
                .set("class", if fault { "mode fault" } else { "mode" })
                .set(
                    "id",
                    format!("mode-{}-{}-{part}", ident(component.name()), d.k),
                );
            group = group.add(label);
        }
        group
    }

    /// A mode segment's full description (its tooltip, and a note when it is a fault).
    pub(super) fn segment_tooltip(
        &self,
        component: &Component,
        interval: &Interval,
        (from, to): (f64, f64),
    ) -> String {
        let fault = is_fault(component, interval);
        format!(
            "{} = {}{} from {} to {} ({}): probability {:.3} at its last cycle, {:.3} at its lowest",
            component.name(),
            mode_name(component, interval),
            if fault { " (fault mode)" } else { "" },
            self.clock.precise(from),
            self.clock.precise(to),
            format_duration(to - from),
            probability(interval.probability),
            probability(interval.min_probability),
        )
    }

    /// The parts of `[x0, x1]` not under a break's band.
    pub(super) fn visible(&self, x0: f64, x1: f64) -> Vec<(f64, f64)> {
        let mut parts = Vec::new();
        let mut left = x0;
        for piece in self.scale.breaks() {
            let (band0, band1) = piece.band(px::PAD);
            if band1 <= left || band0 >= x1 {
                continue;
            }
            if band0 > left {
                parts.push((left, band0));
            }
            left = band1;
        }
        if x1 > left {
            parts.push((left, x1));
        }
        parts
    }
}

/// An interval as drawn: its index in the lane, its clipped times and its x.
pub(super) struct Drawn {
    pub(super) k: usize,
    pub(super) from: f64,
    pub(super) to: f64,
    pub(super) x0: f64,
    pub(super) x1: f64,
}

/// A fault's label beside its segment.
pub(super) struct Callout {
    pub(super) left: f64,
    pub(super) right: f64,
    pub(super) text: Text,
}

/// Where a text of `width` starting at `start` can go before `limit` without coming within 3 px
/// of a reserved range: moved past each range it meets; `None` when it no longer fits.
pub(super) fn clear_of(
    mut start: f64,
    width: f64,
    limit: f64,
    reserved: &[(f64, f64)],
) -> Option<f64> {
    let mut sorted = reserved.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (a, b) in sorted {
        if start < b + 3.0 && start + width > a - 3.0 {
            start = b + 3.0;
        }
    }
    (start + width <= limit).then_some(start)
}

/// Each mode's fill: the initial mode (the most likely initially) neutral, other nominal modes
/// from the palette in declaration order, fault modes red.
pub(in crate::report) fn mode_colours(component: &Component) -> Vec<&'static str> {
    let initial = component
        .initial()
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i);
    let mut next = 0;
    component
        .modes()
        .iter()
        .enumerate()
        .map(|(i, mode)| {
            if mode.kind == ModeKind::Fault {
                fill::FAULT
            } else if Some(i) == initial {
                fill::INITIAL
            } else {
                next += 1;
                fill::NOMINAL[(next - 1) % fill::NOMINAL.len()]
            }
        })
        .collect()
}

pub(super) fn mode_name(component: &Component, interval: &Interval) -> String {
    component
        .modes()
        .get(interval.value.index())
        .map_or_else(|| format!("mode {}", interval.value.0), |m| m.name.clone())
}

pub(super) fn is_fault(component: &Component, interval: &Interval) -> bool {
    component
        .modes()
        .get(interval.value.index())
        .is_some_and(|m| m.kind == ModeKind::Fault)
}

/// A probability made drawable: in [0, 1], 1 when not a number.
pub(super) fn probability(p: f64) -> f64 {
    if p.is_nan() { 1.0 } else { p.clamp(0.0, 1.0) }
}
