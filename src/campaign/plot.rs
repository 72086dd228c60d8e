//! The campaign's picture (issue 18): the pass rate with its 95 % Wilson interval, and the
//! histogram of diagnosis latencies — an SVG drawn with the `svg` crate the timeline uses, so
//! it needs no fonts or plotting backend (viewers render the text).

use svg::Document;
use svg::node::element::{Line, Rectangle, Text};

use super::Summary;

const WIDTH: f64 = 760.0;
const HEIGHT: f64 = 380.0;
/// The plots' common baseline and top, pixels.
const BASE: f64 = 320.0;
const TOP: f64 = 60.0;
/// The histogram's horizontal extent, pixels.
const HIST_LEFT: f64 = 300.0;
const HIST_RIGHT: f64 = 730.0;
/// At most this many histogram bins.
const BINS: usize = 20;

fn text(content: String, x: f64, y: f64, anchor: &str) -> Text {
    Text::new(content)
        .set("x", x)
        .set("y", y)
        .set("text-anchor", anchor)
        .set("font-family", "sans-serif")
        .set("font-size", 12)
}

fn line(x1: f64, y1: f64, x2: f64, y2: f64) -> Line {
    Line::new()
        .set("x1", x1)
        .set("y1", y1)
        .set("x2", x2)
        .set("y2", y2)
        .set("stroke", "#333")
}

fn bar(x: f64, width: f64, top: f64, fill: &str) -> Rectangle {
    Rectangle::new()
        .set("x", x)
        .set("y", top)
        .set("width", width)
        .set("height", (BASE - top).max(0.0))
        .set("fill", fill)
}

/// Height of `fraction` (0 to 1) of the plot, as a y coordinate.
fn y_of(fraction: f64) -> f64 {
    BASE - fraction.clamp(0.0, 1.0) * (BASE - TOP)
}

/// The pass-rate panel: a bar, the interval as an error bar, a 0–100 % axis.
fn pass_rate(mut doc: Document, summary: &Summary) -> Document {
    let rate = if summary.runs == 0 {
        0.0
    } else {
        summary.passed as f64 / summary.runs as f64
    };
    let (low, high) = summary.interval();
    doc = doc
        .add(line(80.0, TOP, 80.0, BASE))
        .add(line(80.0, BASE, 220.0, BASE));
    for tick in [0.0, 0.25, 0.5, 0.75, 1.0] {
        let y = y_of(tick);
        doc = doc.add(line(75.0, y, 80.0, y)).add(text(
            format!("{:.0} %", tick * 100.0),
            70.0,
            y + 4.0,
            "end",
        ));
    }
    doc.add(bar(110.0, 80.0, y_of(rate), "#4c9a5f"))
        .add(line(150.0, y_of(low), 150.0, y_of(high)).set("stroke-width", 2))
        .add(line(140.0, y_of(low), 160.0, y_of(low)).set("stroke-width", 2))
        .add(line(140.0, y_of(high), 160.0, y_of(high)).set("stroke-width", 2))
        .add(text(
            format!("pass rate {:.1} %", rate * 100.0),
            150.0,
            BASE + 20.0,
            "middle",
        ))
        .add(text(
            format!("95 % CI {:.1} – {:.1} %", low * 100.0, high * 100.0),
            150.0,
            BASE + 36.0,
            "middle",
        ))
}

/// The latency panel: counts per bin of equal width from 0 to the largest latency.
fn latencies(mut doc: Document, summary: &Summary) -> Document {
    doc = doc
        .add(line(HIST_LEFT, TOP, HIST_LEFT, BASE))
        .add(line(HIST_LEFT, BASE, HIST_RIGHT, BASE))
        .add(text(
            format!(
                "diagnosis latency, s ({} diagnosed, {} never)",
                summary.latencies.len(),
                summary.faults - summary.latencies.len() as u64
            ),
            (HIST_LEFT + HIST_RIGHT) / 2.0,
            BASE + 36.0,
            "middle",
        ));
    let Some(&max) = summary.latencies.last() else {
        return doc.add(text(
            "no fault diagnosed".to_string(),
            (HIST_LEFT + HIST_RIGHT) / 2.0,
            (TOP + BASE) / 2.0,
            "middle",
        ));
    };
    // Whole seconds per bin, so that bins line up with 1 s cycles.
    let width = (max / BINS as f64).ceil().max(1.0);
    // At least ten bins, so that a histogram of small latencies still reads as one.
    let bins = ((max / width).floor() as usize + 1).clamp(10, BINS + 1);
    let mut counts = vec![0u64; bins];
    for &latency in &summary.latencies {
        counts[((latency / width).floor() as usize).min(bins - 1)] += 1;
    }
    let most = counts.iter().copied().max().unwrap_or(1).max(1);
    let pixels = (HIST_RIGHT - HIST_LEFT) / bins as f64;
    for (i, &count) in counts.iter().enumerate() {
        let x = HIST_LEFT + i as f64 * pixels;
        doc = doc.add(bar(
            x + 1.0,
            pixels - 2.0,
            y_of(count as f64 / most as f64),
            "#4a78b5",
        ));
        if i % bins.div_ceil(10) == 0 {
            doc = doc.add(text(
                format!("{}", i as f64 * width),
                x,
                BASE + 16.0,
                "middle",
            ));
        }
    }
    doc.add(text(format!("{most}"), HIST_LEFT - 5.0, TOP + 4.0, "end"))
        .add(text("0".to_string(), HIST_LEFT - 5.0, BASE + 4.0, "end"))
}

/// The picture of a campaign, titled `title`.
pub fn render(summary: &Summary, title: &str) -> String {
    let doc = Document::new()
        .set("viewBox", (0, 0, WIDTH, HEIGHT))
        .set("width", WIDTH)
        .set("height", HEIGHT)
        .add(
            Rectangle::new()
                .set("width", WIDTH)
                .set("height", HEIGHT)
                .set("fill", "white"),
        )
        .add(
            text(
                format!("{title} — {} runs", summary.runs),
                WIDTH / 2.0,
                28.0,
                "middle",
            )
            .set("font-size", 15),
        );
    latencies(pass_rate(doc, summary), summary).to_string()
}
