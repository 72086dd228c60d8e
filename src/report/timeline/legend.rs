//! The timeline's legend: every colour and symbol the picture can use, keyed,
//! wrapped onto as many lines as the picture's width needs.

use svg::node::element::{Group, Rectangle};

use super::labels::text_width;
use super::marks::{Symbol, colour};
use super::{fill, px, r, segment, symbol_at, zigzag};

/// What a legend entry shows.
#[derive(Debug, Clone, Copy)]
pub(super) enum LegendKey {
    /// A mode segment's fill, opacity, dashed outline.
    Swatch(&'static str, f64, bool),
    /// The nominal palette, one small swatch per colour.
    Palette,
    /// A goal's bar.
    Bar,
    /// A mark.
    Mark(Symbol, &'static str),
    /// A compressed stretch.
    Break,
    /// A time point's window, a whisker.
    Window,
    /// An XGoal's bar.
    XGoal,
}

impl LegendKey {
    /// Width of the key's drawing.
    pub(super) fn width(self) -> f64 {
        match self {
            LegendKey::Palette => 6.0 * fill::NOMINAL.len() as f64,
            _ => 16.0,
        }
    }
}

/// Baseline of the legend's first line.
pub(super) const LEGEND_TOP: f64 = 62.0;

/// Every legend entry, in reading order.
const LEGEND: [(LegendKey, &str); 17] = [
    (LegendKey::Swatch(fill::INITIAL, 1.0, false), "initial mode"),
    (LegendKey::Palette, "other nominal modes"),
    (LegendKey::Swatch(fill::FAULT, 1.0, false), "fault mode"),
    (
        LegendKey::Swatch(fill::NOMINAL[0], 0.45, true),
        "probability < 0.5 at times",
    ),
    (LegendKey::Mark(Symbol::Down, colour::GOAL), "goal"),
    (LegendKey::Bar, "until achieved"),
    (LegendKey::Mark(Symbol::Check, colour::DONE), "achieved"),
    (
        LegendKey::Mark(Symbol::Hollow, colour::PREEMPTED),
        "preempted",
    ),
    (LegendKey::Mark(Symbol::Square, colour::DONE), "completed"),
    (LegendKey::Mark(Symbol::Up, colour::COMMAND), "command"),
    (LegendKey::Mark(Symbol::Up, colour::REPAIR), "repair"),
    (LegendKey::Mark(Symbol::Ring, colour::WAIT), "waiting"),
    (
        LegendKey::Mark(Symbol::Star, colour::INJECTED),
        "fault injected",
    ),
    (LegendKey::Mark(Symbol::Diamond, colour::FAULT), "diagnosis"),
    (
        LegendKey::Mark(Symbol::Cross, colour::FAULT),
        "failure, conflict, inconsistency",
    ),
    (LegendKey::Break, "idle stretch, compressed"),
    (LegendKey::Swatch("#ffffff", 1.0, true), "[n]: note below"),
];

/// The entries of a mission's goal network, keyed only when the picture has one (an RMPL run's
/// legend is not cluttered with what it cannot show).
const NETWORK_LEGEND: [(LegendKey, &str); 4] = [
    (
        LegendKey::Mark(Symbol::Dot, colour::POINT),
        "time point fired",
    ),
    (LegendKey::Mark(Symbol::Dot, colour::FAULT), "forced"),
    (LegendKey::Window, "its window"),
    (LegendKey::XGoal, "XGoal"),
];

/// The legend's entries laid out in lines no wider than the picture: (left, key, label); with
/// the goal network's entries when `network`.
pub(super) fn legend_lines(width: f64, network: bool) -> Vec<Vec<(f64, LegendKey, &'static str)>> {
    let mut lines: Vec<Vec<(f64, LegendKey, &'static str)>> = vec![Vec::new()];
    let mut x = px::MARGIN;
    let network = NETWORK_LEGEND.iter().filter(|_| network);
    for &(key, label) in LEGEND.iter().chain(network) {
        let span = key.width() + 4.0 + text_width(label, px::FONT);
        let line_is_empty = lines.last().is_none_or(Vec::is_empty);
        if x + span > width - px::MARGIN && !line_is_empty {
            lines.push(Vec::new());
            x = px::MARGIN;
        }
        if let Some(line) = lines.last_mut() {
            line.push((x, key, label));
        }
        x += span + 16.0;
    }
    lines
}

/// Height of the title, subtitle and legend (with the goal network's entries when `network`).
pub(super) fn header_height(width: f64, network: bool) -> f64 {
    let extra = legend_lines(width, network).len().saturating_sub(1) as f64;
    px::HEADER + extra * px::LEGEND_LINE
}

/// A legend entry's drawing with its left edge at x, on the baseline y.
pub(super) fn legend_key(key: LegendKey, x: f64, y: f64) -> Group {
    let swatch = |x: f64, width: f64, fill: &str, opacity: f64| {
        Rectangle::new()
            .set("x", r(x))
            .set("y", r(y - 9.0))
            .set("width", r(width))
            .set("height", 10)
            .set("fill", fill.to_string())
            .set("fill-opacity", opacity)
    };
    let group = Group::new().set("class", "key");
    match key {
        LegendKey::Swatch(fill, opacity, dashed) => {
            let rect = swatch(x, 16.0, fill, opacity);
            group.add(if dashed {
                rect.set("stroke", "#555555").set("stroke-dasharray", "2,2")
            } else {
                rect
            })
        }
        LegendKey::Palette => fill::NOMINAL
            .iter()
            .enumerate()
            .fold(group, |g, (i, colour)| {
                g.add(swatch(x + 6.0 * i as f64, 6.0, colour, 1.0))
            }),
        LegendKey::Bar => group.add(swatch(x, 16.0, "none", 1.0).set("class", "goal-bar")),
        LegendKey::Mark(symbol, colour) => group.add(symbol_at(symbol, x + 8.0, y - 4.0, colour)),
        LegendKey::Break => group.add(zigzag(x + 8.0, y - 11.0, y + 2.0)),
        LegendKey::Window => group.add(
            Group::new()
                .set("class", "window")
                .add(segment(x, y - 4.0, x + 16.0, y - 4.0).set("stroke", colour::POINT))
                .add(segment(x, y - 8.0, x, y).set("stroke", colour::POINT))
                .add(segment(x + 16.0, y - 8.0, x + 16.0, y).set("stroke", colour::POINT)),
        ),
        LegendKey::XGoal => group.add(swatch(x, 16.0, "none", 1.0).set("class", "xgoal-bar")),
    }
}
