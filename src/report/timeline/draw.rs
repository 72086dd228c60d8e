//! Drawing primitives: mark symbols, lines, texts, and coordinates rounded for compact SVG.

use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Line, Path, Text};

use super::labels::clean;
use super::marks::Symbol;

/// The shape of a mark at (x, y).
pub(super) fn symbol_at(symbol: Symbol, x: f64, y: f64, colour: &str) -> Group {
    let point = |dx: f64, dy: f64| (r(x + dx), r(y + dy));
    let closed = |points: &[(f64, f64)]| {
        let mut data = Data::new().move_to(point(points[0].0, points[0].1));
        for &(dx, dy) in &points[1..] {
            data = data.line_to(point(dx, dy));
        }
        data.close()
    };
    let shape: Box<dyn svg::Node> = match symbol {
        Symbol::Down => Box::new(filled(
            closed(&[(-5.0, -4.0), (5.0, -4.0), (0.0, 4.0)]),
            colour,
        )),
        Symbol::Up => Box::new(filled(
            closed(&[(-5.0, 4.0), (5.0, 4.0), (0.0, -4.0)]),
            colour,
        )),
        Symbol::Diamond => Box::new(filled(
            closed(&[(0.0, -5.0), (5.0, 0.0), (0.0, 5.0), (-5.0, 0.0)]),
            colour,
        )),
        Symbol::Hollow => Box::new(
            stroked(
                closed(&[(0.0, -5.0), (5.0, 0.0), (0.0, 5.0), (-5.0, 0.0)]),
                colour,
            )
            .set("fill", "#ffffff"),
        ),
        Symbol::Square => Box::new(filled(
            closed(&[(-4.0, -4.0), (4.0, -4.0), (4.0, 4.0), (-4.0, 4.0)]),
            colour,
        )),
        Symbol::Star => Box::new(filled(
            closed(&[
                (0.0, -6.0),
                (1.5, -1.5),
                (6.0, 0.0),
                (1.5, 1.5),
                (0.0, 6.0),
                (-1.5, 1.5),
                (-6.0, 0.0),
                (-1.5, -1.5),
            ]),
            colour,
        )),
        Symbol::Check => Box::new(stroked(
            Data::new()
                .move_to(point(-4.0, 0.0))
                .line_to(point(-1.0, 3.0))
                .line_to(point(4.0, -4.0)),
            colour,
        )),
        Symbol::Cross => Box::new(stroked(
            Data::new()
                .move_to(point(-4.0, -4.0))
                .line_to(point(4.0, 4.0))
                .move_to(point(4.0, -4.0))
                .line_to(point(-4.0, 4.0)),
            colour,
        )),
        Symbol::Dot => Box::new(
            Circle::new()
                .set("cx", r(x))
                .set("cy", r(y))
                .set("r", 4)
                .set("fill", colour.to_string()),
        ),
        Symbol::Ring => Box::new(
            Circle::new()
                .set("cx", r(x))
                .set("cy", r(y))
                .set("r", 3.5)
                .set("fill", "#ffffff")
                .set("stroke", colour.to_string())
                .set("stroke-width", 1.5),
        ),
    };
    Group::new().set("class", "mark").add(shape)
}

pub(super) fn filled(data: Data, colour: &str) -> Path {
    Path::new().set("d", data).set("fill", colour.to_string())
}

pub(super) fn stroked(data: Data, colour: &str) -> Path {
    Path::new()
        .set("d", data)
        .set("fill", "none")
        .set("stroke", colour.to_string())
        .set("stroke-width", 2)
}

/// A thin line.
pub(super) fn segment(x1: f64, y1: f64, x2: f64, y2: f64) -> Line {
    Line::new()
        .set("x1", r(x1))
        .set("y1", r(y1))
        .set("x2", r(x2))
        .set("y2", r(y2))
}

/// A text element with cleaned content.
pub(super) fn text(content: &str, x: f64, y: f64) -> Text {
    Text::new(clean(content)).set("x", r(x)).set("y", r(y))
}

/// A coordinate to a tenth of a pixel (0 when not a number).
pub(super) fn r(value: f64) -> f64 {
    if value.is_finite() {
        (value * 10.0).round() / 10.0
    } else {
        0.0
    }
}

/// An opacity to two decimals.
pub(super) fn r2(value: f64) -> f64 {
    (value * 100.0).round() / 100.0
}

pub(super) fn plural(n: usize, noun: &str) -> String {
    match (n, noun) {
        (1, _) => format!("1 {noun}"),
        (_, "diagnosis") => format!("{n} diagnoses"),
        (_, "idle stretch") => format!("{n} idle stretches"),
        _ => format!("{n} {noun}s"),
    }
}
