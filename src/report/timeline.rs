//! The SVG timeline: one picture of a run (DESIGN.md §12).
//!
//! From what a finished or ongoing run has — the plant, the program, the executive's
//! [`Timelines`] and the [`Event`]s of every step — [`render`] draws:
//!
//! - a **swimlane per state variable** (component), in the plant's order, with its most likely
//!   mode over time as coloured segments labelled with the mode's name where there is room: the
//!   component's initial mode neutral grey, its other nominal modes in colours, **fault modes
//!   red**; a segment is paler the less likely its mode was at its least likely cycle
//!   (`min_probability`) and outlined dashed if that fell below one half;
//! - three rows of **marks** above the lanes: the *program* (goals asserted, each with its text
//!   and program line and a bar to the cycle it was achieved; failures, conflicts, preemptions,
//!   completion), *commands* (repairs in orange) and *faults* (diagnoses, inconsistent
//!   observations, planning failures). Labels are stacked on levels so that none overlaps
//!   another; past a few levels they are thinned (the mark and its tooltip stay). Commands and
//!   diagnoses draw a faint guide down through the lanes;
//! - for a mission, a *network* row of its **time points** as they fire, each
//!   with the window it had then as a whisker (a point forced at its latest time in the fault
//!   colour, numbered in the notes), and its **XGoals as bars** in a band under their state
//!   variable's lane, from dispatch to their end point, labelled inside the bar with their kind
//!   and merged constraint and outlined in the fault colour from a goal's failure (`xgoals`);
//! - a **time axis** in mission elapsed time in which long idle stretches — no mode change, no
//!   command, no drawn event for longer than a threshold (1 min by default) — are compressed to
//!   a fixed-width zig-zag break marked with the idle duration (`≈ 4 h 30 min idle`), while the
//!   rest of the run shares one linear scale, ticked in each segment (see `scale`).
//!
//! Every mark, mode segment and break has a `<title>` (its full text on hover). The document is
//! built with the `svg` crate, which escapes text; characters XML forbids are dropped first.
//! Lanes are `<g class="lane" data-component="…">`, marks `<g class="event …">`, breaks
//! `<g class="idle-break">`, so tools and tests can read the picture back.
//!
//! Nothing here panics: empty runs, a single cycle, zero-length intervals, events outside the
//! window, unknown components or values, and huge times (clamped to ±10¹⁵ s) all draw.

mod axis;
mod draw;
mod labels;
mod lanes;
mod legend;
mod marks;
mod scale;
mod xgoals;

use std::collections::HashMap;

use svg::Document;
use svg::node::element::{Group, Line, Rectangle, Style, Title};

use crate::executive::{Event, Interval, Timelines};
use crate::plant::Plant;
use crate::sequencer::Thca;
use crate::simulation::{CycleRecord, FaultDrawn, PlantEventKind, RunOutcome, Scenario};

use axis::zigzag;
use draw::{plural, r, segment, symbol_at, text};
use labels::{Placement, Request, clean, file_name, place, text_width};
use lanes::is_fault;
pub(super) use lanes::mode_colours;
use legend::{LEGEND_TOP, header_height, legend_key, legend_lines};
use marks::{Marks, Row, Sources, colour};
pub(crate) use scale::hours_minutes_seconds;
use scale::{Clock, Compression, Scale, format_duration};

/// What a run has, for [`render`]; independent of how the run was driven.
#[derive(Debug, Clone, Copy)]
pub struct TimelineInput<'a> {
    /// The plant model: one lane per component.
    pub plant: &'a Plant,
    /// The program, for goal lines and preemption conditions (optional).
    pub program: Option<&'a Thca>,
    /// The executive's state timelines and command history
    /// ([`Executive::timelines`](crate::executive::Executive::timelines)).
    pub timelines: &'a Timelines,
    /// The events of every step, in any order.
    pub events: &'a [Event],
    /// The faults the simulation injected (scripted rules marked `fault: true` taking effect),
    /// drawn on a row of their own; empty for a real plant.
    pub injected: &'a [InjectedFault],
    /// When the drawn window starts (seconds; usually the first cycle's time).
    pub start: f64,
    /// When it ends (usually the last cycle's time).
    pub end: f64,
    /// The picture's title.
    pub title: &'a str,
}

impl<'a> TimelineInput<'a> {
    /// The whole of a scenario's run, from its first to its last cycle, titled with the
    /// scenario's name — what `kairos run --timeline` and `--report` draw.
    pub fn of_run(
        scenario: &'a Scenario,
        outcome: &'a RunOutcome,
        injected: &'a [InjectedFault],
    ) -> Self {
        TimelineInput {
            plant: &scenario.plant,
            program: scenario.program.thca(),
            timelines: &outcome.timelines,
            events: &outcome.events,
            injected,
            start: outcome.start,
            end: outcome.last_time,
            title: &scenario.name,
        }
    }
}

/// A fault the simulation injected into the plant: a scripted rule marked `fault: true` taking
/// effect (`simulation` module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct InjectedFault {
    /// When it took effect (seconds).
    pub time: f64,
    /// The rule's name.
    pub name: String,
    /// What it did to the plant, as the mission log says it.
    pub effect: String,
}

impl InjectedFault {
    /// The faults injected in one cycle of a scripted run: its rules marked `fault: true` that
    /// took effect.
    pub fn of_cycle(scenario: &Scenario, record: &CycleRecord<'_>) -> Vec<InjectedFault> {
        let rules = scenario.script.rules();
        record
            .plant_events
            .iter()
            .filter(|e| e.kind == PlantEventKind::Applied)
            .filter_map(|e| rules.get(e.rule).map(|rule| (e, rule)))
            .filter(|(_, rule)| rule.fault)
            .map(|(e, rule)| InjectedFault {
                time: e.time,
                name: rule.name.clone(),
                effect: rule.effect.describe(scenario.script.variables()),
            })
            .collect()
    }

    /// A fault the model-driven plant drew from the model's probabilities or was forced into.
    pub fn drawn(plant: &Plant, fault: &FaultDrawn) -> InjectedFault {
        let component = plant.components().get(fault.component.index());
        let name = component.map_or("?", |c| c.name());
        let mode = component
            .and_then(|c| c.modes().get(fault.mode.index()))
            .map_or("?", |m| m.name.as_str());
        InjectedFault {
            time: fault.time,
            name: format!("{name} = {mode}"),
            effect: if fault.forced {
                "forced by the scenario".to_string()
            } else {
                "drawn by the model-driven plant".to_string()
            },
        }
    }
}

/// The x of each time on the picture [`render`] draws of `input` (default options): how a page
/// holding the picture puts a cursor on a cycle.
pub fn positions(input: &TimelineInput, times: &[f64]) -> Vec<f64> {
    let picture = Picture::new(input, &TimelineOptions::default());
    times
        .iter()
        .map(|&t| clamp_time(t).map_or(picture.plot_left, |t| picture.scale.x(t)))
        .collect()
}

/// How the timeline is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimelineOptions {
    /// Width of the picture in pixels (at least 480).
    pub width: f64,
    /// A stretch longer than this (seconds) with no mode change, command or drawn event is
    /// compressed into a break.
    pub idle_threshold: f64,
    /// Levels of labels per row of marks before labels are thinned.
    pub max_label_levels: usize,
}

impl Default for TimelineOptions {
    /// 1600 px wide, idle past one minute, up to 10 levels of labels.
    fn default() -> Self {
        TimelineOptions {
            width: 1600.0,
            idle_threshold: 60.0,
            max_label_levels: 10,
        }
    }
}

/// The SVG document of a run, with the default options.
pub fn render(input: &TimelineInput) -> String {
    render_with(input, &TimelineOptions::default())
}

/// The SVG document of a run.
pub fn render_with(input: &TimelineInput, options: &TimelineOptions) -> String {
    let picture = Picture::new(input, options);
    picture.document().to_string()
}

/// Times are clamped to this magnitude (seconds; about 30 million years).
const MAX_TIME: f64 = 1e15;

/// Geometry, in pixels.
mod px {
    pub const MARGIN: f64 = 12.0;
    pub const FONT: f64 = 11.0;
    pub const SMALL: f64 = 10.0;
    pub const TITLE: f64 = 16.0;
    pub const HEADER: f64 = 78.0;
    pub const LEGEND_LINE: f64 = 16.0;
    pub const LEVEL: f64 = 14.0;
    pub const MARKS: f64 = 18.0;
    pub const ROW_GAP: f64 = 4.0;
    pub const AXIS: f64 = 24.0;
    pub const LANE: f64 = 20.0;
    /// The band of XGoal bars under a state variable's lane.
    pub const XGOAL: f64 = 16.0;
    pub const FOOTER_LINE: f64 = 15.0;
    pub const BREAK: f64 = 28.0;
    pub const PAD: f64 = 8.0;
    pub const TICK_SPACING: f64 = 90.0;
    /// Narrowest fault segment: a fault reset within a cycle still shows.
    pub const MIN_FAULT: f64 = 4.0;
}

/// Colours of mode segments.
mod fill {
    /// A component's initial mode.
    pub const INITIAL: &str = "#dedede";
    /// Its other nominal modes, in declaration order.
    pub const NOMINAL: [&str; 8] = [
        "#9ecae1", "#a1d99b", "#fdd49e", "#c6b8e0", "#99d8c9", "#f2e08c", "#c6dbef", "#d4d79b",
    ];
    /// Fault modes.
    pub const FAULT: &str = "#d62728";
}

/// A mode interval's segment's probability below which it is outlined dashed.
const UNCERTAIN: f64 = 0.5;

/// A row of marks, laid out.
struct RowLayout {
    row: Row,
    /// Indices into the marks.
    marks: Vec<usize>,
    /// Label placement, by position in `marks`.
    placements: Vec<Option<Placement>>,
    top: f64,
    /// y of the marks.
    mark_y: f64,
    bottom: f64,
}

/// Everything needed to draw, computed once.
struct Picture<'a> {
    input: &'a TimelineInput<'a>,
    options: TimelineOptions,
    window: (f64, f64),
    clock: Clock,
    marks: Marks,
    scale: Scale,
    plot_left: f64,
    plot_right: f64,
    rows: Vec<RowLayout>,
    /// A mission's XGoals, drawn under their lanes.
    xgoals: Vec<xgoals::XGoalBar>,
    /// The top of each lane (a lane with XGoals is taller by their band).
    lane_tops: Vec<f64>,
    lanes_top: f64,
    lanes_bottom: f64,
    height: f64,
    /// The notes under the picture: the full text of every fault-related mark and fault
    /// segment, numbered, so that the static picture says what the tooltips say.
    notes: Vec<String>,
    /// The note number of each fault segment, by (lane, interval index).
    segment_notes: HashMap<(usize, usize), usize>,
}

impl<'a> Picture<'a> {
    fn new(input: &'a TimelineInput<'a>, options: &TimelineOptions) -> Picture<'a> {
        let options = sanitize(options);
        let window = window(input);
        let clock = Clock::for_run(window.0, window.1);
        let marks = marks::collect(&Sources {
            plant: input.plant,
            program: input.program,
            timelines: input.timelines,
            events: input.events,
            injected: input.injected,
            clock,
            window,
        });
        let plot_left = px::MARGIN + names_width(input.plant) + 8.0;
        let plot_right = options.width - px::MARGIN - 4.0;
        let compression = Compression {
            threshold: options.idle_threshold,
            break_width: px::BREAK,
            pad: px::PAD,
        };
        let activity = activity(input, &marks, window);
        let scale = Scale::new(&activity, plot_left, plot_right, &compression);
        let mut picture = Picture {
            input,
            options,
            window,
            clock,
            marks,
            scale,
            plot_left,
            plot_right,
            rows: Vec::new(),
            xgoals: xgoals::collect(input.plant, input.events, window, clock),
            lane_tops: Vec::new(),
            lanes_top: 0.0,
            lanes_bottom: 0.0,
            height: 0.0,
            notes: Vec::new(),
            segment_notes: HashMap::new(),
        };
        picture.number_notes();
        picture.lay_out();
        picture
    }

    /// Numbers the notes: the injected faults, the faults row's marks and the forced time
    /// points in time order (their labels take the number), then the fault segments lane by lane.
    fn number_notes(&mut self) {
        for mark in &mut self.marks.marks {
            let forced = mark.class == "time-point forced";
            if !matches!(mark.row, Row::Injected | Row::Faults) && !forced {
                continue;
            }
            let n = self.notes.len() + 1;
            self.notes.push(format!("[{n}] {}", mark.tooltip));
            if let Some(label) = &mut mark.label {
                *label = format!("[{n}] {label}");
            }
        }
        let plant = self.input.plant;
        for (lane, component) in plant.components().iter().enumerate() {
            let Some(timeline) = self.input.timelines.state(lane) else {
                continue;
            };
            let intervals: Vec<&Interval> = timeline.intervals().collect();
            for d in self.drawn_intervals(&intervals) {
                let interval = intervals[d.k];
                if is_fault(component, interval) {
                    let n = self.notes.len() + 1;
                    let tooltip = self.segment_tooltip(component, interval, (d.from, d.to));
                    self.notes.push(format!("[{n}] {tooltip}"));
                    self.segment_notes.insert((lane, d.k), n);
                }
            }
        }
    }

    /// The footer's lines: the scale, the hint, what was not drawn, the notes (wrapped).
    fn footer_lines(&self) -> Vec<String> {
        let mut lines = vec![self.compression_note()];
        lines.push(
            "Hover a mark, a mode or a break for its details. Commands and diagnoses are traced down through the lanes."
                .to_string(),
        );
        if !self.marks.omitted.is_empty() {
            let counts: Vec<String> = self
                .marks
                .omitted
                .iter()
                .map(|(what, n)| format!("{what}: {n}"))
                .collect();
            lines.push(format!(
                "Not drawn (see the mission log): {}.",
                counts.join(", ")
            ));
        }
        let columns = ((self.options.width - 2.0 * px::MARGIN) / (px::FONT * labels::CHAR_WIDTH))
            .floor()
            .max(20.0) as usize;
        for note in &self.notes {
            lines.extend(labels::wrap(note, columns, "    "));
        }
        lines
    }

    /// True when the run has a goal network to draw (time points or XGoals).
    fn has_network(&self) -> bool {
        !self.xgoals.is_empty() || self.marks.marks.iter().any(|m| m.row == Row::Network)
    }

    /// Places the rows' labels and stacks rows, axis, lanes and footer. The network row is
    /// drawn only for a mission (a run with time points).
    fn lay_out(&mut self) {
        let mut y = header_height(self.options.width, self.has_network());
        for row in Row::ALL {
            let layout = self.lay_out_row(row, y);
            if row == Row::Network && layout.marks.is_empty() {
                continue;
            }
            y = layout.bottom;
            self.rows.push(layout);
        }
        self.lanes_top = y + px::AXIS;
        let mut top = self.lanes_top;
        for lane in 0..self.input.plant.components().len() {
            self.lane_tops.push(top);
            top += px::LANE;
            if self.xgoals.iter().any(|b| b.lane == lane) {
                top += px::XGOAL;
            }
        }
        self.lanes_bottom = top;
        let footer_lines = self.footer_lines().len() as f64;
        self.height = self.lanes_bottom + px::AXIS + footer_lines * px::FOOTER_LINE + px::MARGIN;
    }

    fn lay_out_row(&self, row: Row, top: f64) -> RowLayout {
        let marks: Vec<usize> = (0..self.marks.marks.len())
            .filter(|&i| self.marks.marks[i].row == row)
            .collect();
        let requests: Vec<Request> = marks
            .iter()
            .map(|&i| {
                let mark = &self.marks.marks[i];
                let x = self.scale.x(mark.time);
                let width = mark
                    .label
                    .as_deref()
                    .map_or(0.0, |l| text_width(l, px::FONT));
                let reach = mark.until.map_or(x, |t| self.scale.x(t).max(x));
                Request { x, width, reach }
            })
            .collect();
        let labelled: Vec<usize> = (0..marks.len())
            .filter(|&k| self.marks.marks[marks[k]].label.is_some())
            .collect();
        let subset: Vec<Request> = labelled.iter().map(|&k| requests[k]).collect();
        let placed = place(&subset, self.plot_right, self.options.max_label_levels);
        let mut placements = vec![None; marks.len()];
        for (k, placement) in labelled.into_iter().zip(placed) {
            placements[k] = placement;
        }
        let levels = labels::levels_used(&placements).max(1) as f64;
        let mark_y = top + levels * px::LEVEL + px::MARKS / 2.0 + 2.0;
        RowLayout {
            row,
            marks,
            placements,
            top,
            mark_y,
            bottom: mark_y + px::MARKS / 2.0 + px::ROW_GAP,
        }
    }

    fn document(&self) -> Document {
        let width = self.options.width;
        Document::new()
            .set("width", r(width))
            .set("height", r(self.height))
            .set("viewBox", (0, 0, r(width), r(self.height)))
            .add(Title::new(clean(self.input.title)))
            .add(Style::new(stylesheet()))
            .add(
                Rectangle::new()
                    .set("width", "100%")
                    .set("height", "100%")
                    .set("fill", "#ffffff"),
            )
            .add(self.header())
            .add(self.lanes())
            .add(self.guides())
            .add(self.breaks())
            .add(self.axes())
            .add(self.event_rows())
            .add(self.footer())
    }

    // ----- header -----

    fn header(&self) -> Group {
        let input = self.input;
        let (start, end) = self.window;
        let commands = self.count("command");
        let diagnoses = self.count("diagnosis");
        let mut facts = vec![input.plant.name().to_string()];
        if let Some(program) = input.program {
            facts.push(file_name(&program.source().name).to_string());
        }
        facts.push(format!(
            "{} – {} ({})",
            self.clock.precise(start),
            self.clock.precise(end),
            format_duration(end - start)
        ));
        facts.push(format!(
            "{} state variables",
            input.plant.components().len()
        ));
        facts.push(plural(commands, "command"));
        facts.push(plural(diagnoses, "diagnosis"));
        Group::new()
            .set("id", "header")
            .add(text(input.title, px::MARGIN, 24.0).set("class", "title"))
            .add(text(&facts.join(" · "), px::MARGIN, 43.0).set("class", "subtitle"))
            .add(self.legend(LEGEND_TOP))
    }

    fn count(&self, class: &str) -> usize {
        self.marks
            .marks
            .iter()
            .filter(|m| m.class.split(' ').next() == Some(class))
            .count()
    }

    /// The legend, wrapped onto as many lines as the width needs: every colour and symbol the
    /// picture can use is keyed, the nominal palette as one strip.
    fn legend(&self, top: f64) -> Group {
        let mut group = Group::new().set("id", "legend");
        let lines = legend_lines(self.options.width, self.has_network());
        for (line, entries) in lines.iter().enumerate() {
            let y = top + line as f64 * px::LEGEND_LINE;
            for &(x, key, label) in entries {
                group = group.add(legend_key(key, x, y));
                group = group.add(text(label, x + key.width() + 4.0, y).set("class", "legend"));
            }
        }
        group
    }

    // ----- rows of marks -----

    fn event_rows(&self) -> Group {
        let mut group = Group::new().set("id", "events");
        for layout in &self.rows {
            group = group.add(self.event_row(layout));
        }
        group
    }

    fn event_row(&self, layout: &RowLayout) -> Group {
        let name = layout.row.name();
        let mut group = Group::new()
            .set("class", format!("row {name}"))
            .add(
                Line::new()
                    .set("x1", r(self.plot_left))
                    .set("x2", r(self.plot_right))
                    .set("y1", r(layout.mark_y))
                    .set("y2", r(layout.mark_y))
                    .set("class", "baseline"),
            )
            .add(
                text(name, self.plot_left - 8.0, layout.mark_y + 4.0)
                    .set("class", "row-name")
                    .set("text-anchor", "end"),
            );
        if layout.marks.is_empty() {
            group = group.add(
                text("none", self.plot_left + px::PAD, layout.mark_y - 6.0).set("class", "none"),
            );
        }
        let mut leaders = Group::new().set("class", "leaders");
        for (k, &i) in layout.marks.iter().enumerate() {
            if let Some(placement) = layout.placements[k] {
                let x = self.scale.x(self.marks.marks[i].time);
                let top = level_baseline(layout, placement.level) + 3.0;
                leaders = leaders.add(segment(x, layout.mark_y - 5.0, x, top));
            }
        }
        group = group.add(leaders);
        for (k, &i) in layout.marks.iter().enumerate() {
            group = group.add(self.event_mark(layout, i, layout.placements[k]));
        }
        group
    }

    fn event_mark(
        &self,
        layout: &RowLayout,
        mark_index: usize,
        placement: Option<Placement>,
    ) -> Group {
        let mark = &self.marks.marks[mark_index];
        let x = self.scale.x(mark.time);
        let mut group = Group::new()
            .set("class", format!("event {}", mark.class))
            .set("data-time", mark.time)
            .add(Title::new(clean(&mark.tooltip)));
        if let Some(window) = mark.window {
            group = group.add(self.whisker(window, layout.mark_y, mark.colour));
        }
        if let (Some(placement), Some(label)) = (placement, &mark.label) {
            let baseline = level_baseline(layout, placement.level);
            if let Some(until) = mark.until {
                let end = self.scale.x(until).max(x + 1.0);
                group = group.add(
                    Rectangle::new()
                        .set("class", "goal-bar")
                        .set("x", r(x))
                        .set("y", r(baseline - 10.0))
                        .set("width", r(end - x))
                        .set("height", 13),
                );
            }
            group = group.add(
                text(label, placement.left, baseline)
                    .set("class", "label")
                    .set("id", format!("label-{}-{}", layout.row.name(), mark_index))
                    // A style, not a `fill` attribute: the sheet's `text { fill }` outranks attributes.
                    .set("style", format!("fill: {}", mark.colour)),
            );
        }
        group.add(symbol_at(mark.symbol, x, layout.mark_y, mark.colour))
    }

    /// Faint lines from commands and diagnoses down through the lanes.
    fn guides(&self) -> Group {
        let mut group = Group::new().set("id", "guides");
        let Some(from) = self.rows.iter().find(|l| l.row == Row::Commands) else {
            return group;
        };
        for mark in self.marks.marks.iter().filter(|m| m.guide) {
            let x = self.scale.x(mark.time);
            group = group.add(
                segment(x, from.top, x, self.lanes_bottom)
                    .set("stroke", mark.colour)
                    .set("class", "guide"),
            );
        }
        group
    }

    fn footer(&self) -> Group {
        let mut y = self.lanes_bottom + px::AXIS + px::FOOTER_LINE;
        let mut group = Group::new().set("id", "footer");
        for line in self.footer_lines() {
            group = group.add(text(&line, px::MARGIN, y).set("class", "note"));
            y += px::FOOTER_LINE;
        }
        group
    }

    fn compression_note(&self) -> String {
        let breaks = self.scale.breaks().count();
        let rate = self
            .scale
            .segments()
            .find(|s| s.t1 > s.t0)
            .map(|s| (s.x1 - s.x0) / (s.t1 - s.t0));
        let scale = match rate {
            Some(rate) if rate >= 1.0 => format!("1 s = {rate:.1} px"),
            Some(rate) if rate > 0.0 => format!("1 min = {:.1} px", rate * 60.0),
            _ => "a single instant".to_string(),
        };
        let threshold = format_duration(self.options.idle_threshold);
        match breaks {
            0 => format!("Time scale: {scale}; no idle stretch longer than {threshold}."),
            n => format!(
                "Time scale: {scale}, except {} longer than {threshold} with no mode change, command or event, compressed (zig-zag).",
                plural(n, "idle stretch")
            ),
        }
    }
}

/// Width, height and threshold made usable.
fn sanitize(options: &TimelineOptions) -> TimelineOptions {
    let defaults = TimelineOptions::default();
    let width = if options.width.is_finite() {
        options.width.clamp(480.0, 100_000.0)
    } else {
        defaults.width
    };
    let idle_threshold = if options.idle_threshold.is_nan() {
        defaults.idle_threshold
    } else {
        options.idle_threshold.max(0.0)
    };
    TimelineOptions {
        width,
        idle_threshold,
        max_label_levels: options.max_label_levels.clamp(1, 50),
    }
}

/// A finite time, clamped to ±[`MAX_TIME`].
fn clamp_time(t: f64) -> Option<f64> {
    (!t.is_nan()).then(|| t.clamp(-MAX_TIME, MAX_TIME))
}

/// The drawn window: the input's start and end, or the data's extent where they are not numbers;
/// never reversed.
fn window(input: &TimelineInput) -> (f64, f64) {
    let data: Vec<f64> = input
        .timelines
        .states()
        .iter()
        .flat_map(|t| t.intervals().flat_map(|i| [i.from, i.until]))
        .chain(input.events.iter().map(|e| e.time))
        .filter_map(clamp_time)
        .collect();
    let lowest = data.iter().copied().reduce(f64::min);
    let highest = data.iter().copied().reduce(f64::max);
    let start = clamp_time(input.start).or(lowest).unwrap_or(0.0);
    let end = clamp_time(input.end).or(highest).unwrap_or(start);
    (start.min(end), start.max(end))
}

/// The times something happens: the window's ends, every mode change and every mark, in order.
fn activity(input: &TimelineInput, marks: &Marks, (start, end): (f64, f64)) -> Vec<f64> {
    let changes = input
        .timelines
        .states()
        .iter()
        .flat_map(|t| t.intervals().map(|i| i.from));
    let mut times: Vec<f64> = changes
        .chain(
            marks
                .marks
                .iter()
                .flat_map(|m| [Some(m.time), m.until])
                .flatten(),
        )
        .filter_map(clamp_time)
        .map(|t| t.clamp(start, end))
        .chain([start, end])
        .collect();
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

/// Width of the column of names left of the plot.
fn names_width(plant: &Plant) -> f64 {
    let longest = plant
        .components()
        .iter()
        .map(|c| c.name().chars().count())
        .chain(Row::ALL.iter().map(|r| r.name().len()))
        .chain(["time (h:mm:ss)".len()])
        .max()
        .unwrap_or(0);
    (longest as f64 * px::FONT * labels::CHAR_WIDTH).clamp(60.0, 240.0)
}

/// The baseline of a row's label level.
fn level_baseline(layout: &RowLayout, level: usize) -> f64 {
    layout.mark_y - px::MARKS / 2.0 - 3.0 - level as f64 * px::LEVEL
}

/// The picture's style sheet: fonts and the classes' looks.
fn stylesheet() -> String {
    format!(
        "text {{ font-family: 'DejaVu Sans Mono', Menlo, Consolas, monospace; font-size: {font}px; fill: #222222; }}
.title {{ font-size: {title}px; font-weight: bold; }}
.subtitle, .legend, .note {{ fill: #555555; }}
.row-name {{ fill: #555555; font-weight: bold; }}
.lane-name {{ fill: #222222; }}
.lane-name.faulty {{ fill: {fault}; font-weight: bold; }}
.mode, .tick, .break-label {{ font-size: {small}px; }}
.mode {{ fill: #333333; }}
.mode.fault {{ fill: #ffffff; font-weight: bold; }}
.mode.callout {{ fill: {fault}; font-weight: bold; paint-order: stroke; stroke: #ffffff; stroke-width: 3px; stroke-linejoin: round; }}
.tick {{ fill: #555555; }}
.tick.major {{ fill: #222222; font-weight: bold; }}
.none {{ fill: #999999; font-style: italic; }}
.label {{ paint-order: stroke; stroke: #ffffff; stroke-width: 3px; stroke-linejoin: round; }}
.xgoal-bar {{ fill: {point}; fill-opacity: 0.18; stroke: {point}; stroke-opacity: 0.8; }}
.xgoal-bar.failed {{ fill: none; stroke: {fault}; stroke-width: 2; stroke-opacity: 1; }}
.xgoal-label {{ font-size: {small}px; fill: #0b5560; }}
.window line {{ stroke-width: 1.5; stroke-opacity: 0.7; }}
.goal-bar {{ fill: {goal}; fill-opacity: 0.12; stroke: {goal}; stroke-opacity: 0.45; }}
.baseline {{ stroke: #cccccc; }}
.leaders line {{ stroke: #aaaaaa; stroke-width: 0.6; }}
.guide {{ stroke-opacity: 0.18; stroke-dasharray: 2,3; }}
.grid line {{ stroke: #000000; stroke-opacity: 0.07; }}
.axis-line {{ stroke: #777777; }}
.break-band {{ fill: #ffffff; fill-opacity: 0.88; }}
.zigzag {{ fill: none; stroke: #888888; stroke-width: 1.2; }}
.break-label {{ fill: #666666; font-style: italic; }}",
        font = px::FONT,
        small = px::SMALL,
        title = px::TITLE,
        fault = fill::FAULT,
        goal = colour::GOAL,
        point = colour::POINT,
    )
}
