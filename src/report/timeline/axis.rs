//! The time axis: ticks whose labels fit, the grid, and the zig-zag bands of compressed idle
//! stretches (the compression itself is `scale`'s).

use svg::node::element::path::Data;
use svg::node::element::{Group, Path, Rectangle, Title};

use super::draw::{r, segment, text};
use super::labels::{clean, text_width};
use super::scale::{Clock, Tick, format_duration};
use super::{Picture, px};

impl Picture<'_> {
    pub(super) fn breaks(&self) -> Group {
        let mut group = Group::new().set("id", "breaks");
        let top = self.rows.first().map_or(self.lanes_top, |l| l.top);
        let bottom = self.lanes_bottom + 4.0;
        for piece in self.scale.breaks() {
            let (x0, x1) = piece.band(px::PAD);
            let idle = piece.t1 - piece.t0;
            let words = format!("≈ {} idle", format_duration(idle));
            let label = if text_width(&words, px::FONT) + 12.0 <= bottom - top {
                words
            } else {
                format!("≈ {}", format_duration(idle))
            };
            let (cx, cy) = ((x0 + x1) / 2.0, (top + bottom) / 2.0);
            let tooltip = format!(
                "idle from {} to {} ({}): no mode change, command or event",
                self.clock.precise(piece.t0),
                self.clock.precise(piece.t1),
                format_duration(idle)
            );
            group = group.add(
                Group::new()
                    .set("class", "idle-break")
                    .set("data-from", piece.t0)
                    .set("data-until", piece.t1)
                    .add(Title::new(clean(&tooltip)))
                    .add(
                        Rectangle::new()
                            .set("class", "break-band")
                            .set("x", r(x0))
                            .set("y", r(top))
                            .set("width", r(x1 - x0))
                            .set("height", r(bottom - top)),
                    )
                    .add(zigzag(x0, top, bottom))
                    .add(zigzag(x1, top, bottom))
                    .add(
                        text(&label, cx, cy + 4.0)
                            .set("class", "break-label")
                            .set("text-anchor", "middle")
                            .set("transform", format!("rotate(-90 {} {})", r(cx), r(cy))),
                    ),
            );
        }
        group
    }

    pub(super) fn axes(&self) -> Group {
        let bounds = (self.plot_left - 4.0, self.options.width - px::MARGIN);
        let ticks = readable_ticks(&self.scale.ticks(px::TICK_SPACING), &self.clock, bounds);
        let mut group = Group::new().set("id", "axis");
        let unit = if self.clock.hours { "h:mm:ss" } else { "m:ss" };
        group = group.add(
            text(
                &format!("time ({unit})"),
                self.plot_left - 8.0,
                self.lanes_top - 8.0,
            )
            .set("class", "row-name")
            .set("text-anchor", "end"),
        );
        for (y, below) in [(self.lanes_top, false), (self.lanes_bottom, true)] {
            group = group.add(self.axis(&ticks, y, below));
        }
        let mut grid = Group::new().set("class", "grid");
        for label in &ticks {
            let x = label.tick.x;
            grid = grid.add(segment(x, self.lanes_top, x, self.lanes_bottom));
        }
        group.add(grid)
    }

    pub(super) fn axis(&self, ticks: &[TickLabel], y: f64, below: bool) -> Group {
        let mut group = Group::new().set("class", "axis");
        for segment_piece in self.scale.segments() {
            group = group.add(
                segment(
                    segment_piece.x0 - px::PAD / 2.0,
                    y,
                    segment_piece.x1 + px::PAD / 2.0,
                    y,
                )
                .set("class", "axis-line"),
            );
        }
        let (tick_end, label_y, outward) = if below {
            (y + 4.0, y + 15.0, px::SMALL + 1.0)
        } else {
            (y - 4.0, y - 7.0, -(px::SMALL + 1.0))
        };
        for label in ticks {
            let tick = label.tick;
            group = group
                .add(segment(tick.x, y, tick.x, tick_end).set("class", "axis-line"))
                .add(
                    text(
                        &label.text,
                        label.left,
                        label_y + label.line as f64 * outward,
                    )
                    .set("class", if tick.major { "tick major" } else { "tick" }),
                );
        }
        group
    }
}

/// A tick and its label's text, left edge and line (0 next to the axis, 1 further out).
pub(super) struct TickLabel {
    pub(super) tick: Tick,
    pub(super) text: String,
    pub(super) left: f64,
    pub(super) line: usize,
}

/// Space kept between neighbouring tick labels.
pub(super) const TICK_GAP: f64 = 8.0;

/// The ticks whose labels fit, left to right, each label centred on its tick but kept between
/// `left` and `right` (so the first one clears the axis's name). A segment's first time is
/// never dropped, since a reader needs it after a break: it goes on a second line when the
/// first is taken, and it replaces an ordinary tick it would overlap.
pub(super) fn readable_ticks(
    ticks: &[Tick],
    clock: &Clock,
    (left, right): (f64, f64),
) -> Vec<TickLabel> {
    let mut kept: Vec<TickLabel> = Vec::new();
    // Where each line's last label ends.
    let mut ends = [f64::NEG_INFINITY; 2];
    for tick in ticks {
        let text = clock.format(tick.time, tick.step);
        let width = text_width(&text, px::SMALL);
        let start = (tick.x - width / 2.0).min(right - width).max(left);
        let free = |line: usize, ends: &[f64; 2]| start >= ends[line] + TICK_GAP;
        let line = if free(0, &ends) {
            Some(0)
        } else if tick.major && free(1, &ends) {
            Some(1)
        } else if tick.major && kept.last().is_some_and(|l| !l.tick.major && l.line == 0) {
            kept.pop();
            ends[0] = kept
                .iter()
                .rfind(|l| l.line == 0)
                .map_or(f64::NEG_INFINITY, |l| {
                    l.left + text_width(&l.text, px::SMALL)
                });
            free(0, &ends).then_some(0)
        } else {
            None
        };
        if let Some(line) = line {
            ends[line] = start + width;
            kept.push(TickLabel {
                tick: *tick,
                text,
                left: start,
                line,
            });
        }
    }
    kept
}

/// A vertical zig-zag line at x from `top` to `bottom`: the mark of a break.
pub(super) fn zigzag(x: f64, top: f64, bottom: f64) -> Path {
    let mut data = Data::new().move_to((r(x), r(top)));
    let mut y = top;
    let mut side = 1.0;
    while y + 4.0 < bottom {
        y += 4.0;
        data = data.line_to((r(x + 3.0 * side), r(y)));
        side = -side;
    }
    data = data.line_to((r(x), r(bottom)));
    Path::new().set("class", "zigzag").set("d", data)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tick(x: f64, major: bool) -> Tick {
        Tick {
            time: x,
            x,
            major,
            step: 1.0,
        }
    }

    #[test]
    fn tick_labels_clear_the_edges_and_never_drop_a_segment_start() {
        let clock = Clock { hours: false };
        // "0:00" is 24.8 px wide at 10 px: centred on 100 it would start at 87.6.
        let labels = readable_ticks(&[tick(100.0, true)], &clock, (95.0, 1000.0));
        assert_eq!(labels[0].left, 95.0);
        let labels = readable_ticks(&[tick(990.0, false)], &clock, (0.0, 1000.0));
        assert!((labels[0].left + text_width(&labels[0].text, px::SMALL) - 1000.0).abs() < 1e-9);

        // Two segment starts too close for one line: the second goes on the next line.
        let labels = readable_ticks(&[tick(100.0, true), tick(110.0, true)], &clock, (0.0, 1e3));
        let lines: Vec<usize> = labels.iter().map(|l| l.line).collect();
        assert_eq!(lines, [0, 1]);

        // With both lines taken, an ordinary tick gives way to a segment start.
        let ticks = [
            tick(100.0, true),
            tick(105.0, true),
            tick(135.0, false),
            tick(137.0, true),
        ];
        let labels = readable_ticks(&ticks, &clock, (0.0, 1e3));
        let kept: Vec<(f64, usize)> = labels.iter().map(|l| (l.tick.x, l.line)).collect();
        assert_eq!(kept, [(100.0, 0), (105.0, 1), (137.0, 0)]);
    }
}
