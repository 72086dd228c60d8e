//! The campaign's picture: the pass rate with its 95 % Wilson interval, and the
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

/// Latencies past this quantile go to one overflow bar when they would squeeze the others
/// (a valve stuck closed while closed is diagnosed only when it is commanded open, hours
/// later, which would otherwise put every other latency in the first bin).
const SPAN_QUANTILE: f64 = 0.95;

/// The latencies the bins cover: all of them, or up to the [`SPAN_QUANTILE`] quantile when the
/// largest is more than four times it. `latencies` is sorted and not empty.
fn binned_span(latencies: &[f64]) -> f64 {
    let max = latencies[latencies.len() - 1];
    let at = ((SPAN_QUANTILE * latencies.len() as f64).ceil() as usize).clamp(1, latencies.len());
    let quantile = latencies[at - 1].max(1.0);
    if max > 4.0 * quantile { quantile } else { max }
}

/// The latency panel: counts per bin of equal width from 0 to the binned span, and the
/// latencies past it as one overflow bar, labelled.
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
    if summary.latencies.is_empty() {
        return doc.add(text(
            "no fault diagnosed".to_string(),
            (HIST_LEFT + HIST_RIGHT) / 2.0,
            (TOP + BASE) / 2.0,
            "middle",
        ));
    }
    let span = binned_span(&summary.latencies);
    let beyond = summary.latencies.iter().filter(|&&l| l > span).count() as u64;
    // Whole seconds per bin, so that bins line up with 1 s cycles.
    let width = (span / BINS as f64).ceil().max(1.0);
    // At least ten bins, so that a histogram of small latencies still reads as one — unless
    // an overflow bar follows, whose label must continue the last bin's.
    let least = if beyond > 0 { 1 } else { 10 };
    let bins = ((span / width).floor() as usize + 1).clamp(least, BINS + 1);
    let mut counts = vec![0u64; bins];
    for &latency in summary.latencies.iter().filter(|&&l| l <= span) {
        counts[((latency / width).floor() as usize).min(bins - 1)] += 1;
    }
    let most = counts.iter().copied().max().unwrap_or(1).max(beyond).max(1);
    // One slot more for the overflow bar when there is one.
    let slots = bins + usize::from(beyond > 0);
    let pixels = (HIST_RIGHT - HIST_LEFT) / slots as f64;
    if beyond > 0 {
        let x = HIST_LEFT + bins as f64 * pixels;
        let top = y_of(beyond as f64 / most as f64);
        doc = doc
            .add(bar(x + 1.0, pixels - 2.0, top, "#c0504d"))
            .add(
                text(format!("{beyond}"), x + pixels / 2.0, top - 4.0, "middle")
                    .set("font-size", 9),
            )
            .add(text(
                format!("> {span} s"),
                x + pixels / 2.0,
                BASE + 16.0,
                "middle",
            ));
    }
    for (i, &count) in counts.iter().enumerate() {
        let x = HIST_LEFT + i as f64 * pixels;
        let top = y_of(count as f64 / most as f64);
        doc = doc.add(bar(x + 1.0, pixels - 2.0, top, "#4a78b5"));
        if count > 0 {
            // Counts on the bars: a bin of a few runs next to one of thousands stays readable.
            doc = doc.add(
                text(format!("{count}"), x + pixels / 2.0, top - 4.0, "middle").set("font-size", 9),
            );
        }
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

#[cfg(test)]
mod tests {
    use super::{binned_span, render};
    use crate::campaign::Summary;

    /// A summary of these latencies, sorted as `Summary::of` keeps them.
    fn summary_with(mut latencies: Vec<f64>) -> Summary {
        latencies.sort_by(f64::total_cmp);
        let mut summary = Summary::of(&[]);
        summary.faults = latencies.len() as u64;
        summary.latencies = latencies;
        summary
    }

    /// Latencies of the same order are binned whole; a few hours-late diagnoses (a valve stuck
    /// in the position it was commanded to, seen only when next commanded) are not.
    #[test]
    fn the_bins_cover_the_quantile_when_a_few_latencies_are_far_out() {
        assert_eq!(binned_span(&[0.0, 1.0, 3.0, 12.0]), 12.0);
        let mut skewed: Vec<f64> = (0..100).map(|i| f64::from(i % 5)).collect();
        skewed.extend([5278.0, 16952.0]);
        skewed.sort_by(f64::total_cmp);
        assert_eq!(binned_span(&skewed), 4.0);
    }

    /// The campaign picture: the far-out latencies are one labelled overflow bar, counted.
    #[test]
    fn far_out_latencies_are_one_labelled_overflow_bar() {
        let mut latencies: Vec<f64> = (0..100).map(|i| f64::from(i % 5)).collect();
        latencies.extend([5278.0, 16952.0]);
        let svg = render(&summary_with(latencies), "test");
        assert!(svg.contains("&gt; 4 s"), "{svg}");
        assert!(svg.contains("#c0504d"), "{svg}");
        let even = render(&summary_with(vec![0.0, 1.0, 3.0, 12.0]), "test");
        assert!(!even.contains("#c0504d"), "{even}");
        assert!(!even.contains("&gt;"), "{even}");
    }
}
