//! The timeline's time axis: a piecewise-linear map from time to x in which long idle stretches
//! are compressed to a fixed width, the axis's ticks, and how times and durations are written.
//!
//! The run's *activity times* (mode changes, commands, drawn events, start and end) cut time into
//! gaps. A gap longer than the idle threshold is an idle stretch: it gets a fixed-width break.
//! The rest — the *segments*, runs of activity separated by idle stretches — share the remaining
//! width at one common scale (pixels per second), so durations compare honestly everywhere
//! except across a break, and each segment's ticks read in that scale. When there are more idle
//! stretches than breaks fit (at most 40% of the width goes to breaks), only the longest are
//! compressed.

/// Fraction of the plot width that breaks may take at most.
const MAX_BREAK_SHARE: f64 = 0.4;

/// One piece of the axis: a time range drawn over an x range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Piece {
    /// First time.
    pub t0: f64,
    /// Last time.
    pub t1: f64,
    /// x of `t0`.
    pub x0: f64,
    /// x of `t1`.
    pub x1: f64,
    /// A compressed idle stretch (a break) rather than a linear segment.
    pub idle: bool,
}

impl Piece {
    /// The x range of the break's band (the piece without its padding).
    pub fn band(&self, pad: f64) -> (f64, f64) {
        (self.x0 + pad, self.x1 - pad)
    }
}

/// How idle stretches are compressed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Compression {
    /// A gap with nothing in it longer than this (seconds) is compressed.
    pub threshold: f64,
    /// Width of a break's band.
    pub break_width: f64,
    /// Space kept on both sides of a break (and at both ends of the axis).
    pub pad: f64,
}

/// A tick of the axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Tick {
    /// Its time.
    pub time: f64,
    /// Its x.
    pub x: f64,
    /// The first time of a segment (always labelled, drawn bold).
    pub major: bool,
    /// Seconds between neighbouring ticks of its segment (sets the label's precision).
    pub step: f64,
}

/// The time → x map.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Scale {
    pieces: Vec<Piece>,
}

impl Scale {
    /// The scale of `times` (sorted, distinct, finite; at least one) drawn between `left` and
    /// `right`.
    pub fn new(times: &[f64], left: f64, right: f64, compression: &Compression) -> Scale {
        let times: &[f64] = if times.is_empty() { &[0.0] } else { times };
        let pad = compression.pad;
        let slot = compression.break_width + 2.0 * pad;
        let plot = (right - left).max(0.0);
        let segments = segments(times, compression.threshold, plot, slot);
        let breaks = segments.len().saturating_sub(1) as f64;
        let available = (plot - 2.0 * pad - breaks * slot).max(0.0);
        let widths = widths(&segments, available);
        let mut pieces = Vec::with_capacity(2 * segments.len());
        let mut x = left + pad;
        for (i, (&(t0, t1), width)) in segments.iter().zip(widths).enumerate() {
            pieces.push(Piece {
                t0,
                t1,
                x0: x,
                x1: x + width,
                idle: false,
            });
            x += width;
            if let Some(&(next, _)) = segments.get(i + 1) {
                pieces.push(Piece {
                    t0: t1,
                    t1: next,
                    x0: x,
                    x1: x + slot,
                    idle: true,
                });
                x += slot;
            }
        }
        Scale { pieces }
    }

    /// x of time `t`; times outside the axis are drawn at its ends.
    pub fn x(&self, t: f64) -> f64 {
        let Some(last) = self.pieces.len().checked_sub(1) else {
            return 0.0;
        };
        let i = self.pieces.partition_point(|p| p.t1 < t).min(last);
        let piece = &self.pieces[i];
        let span = piece.t1 - piece.t0;
        if span > 0.0 {
            let fraction = ((t - piece.t0) / span).clamp(0.0, 1.0);
            piece.x0 + fraction * (piece.x1 - piece.x0)
        } else {
            piece.x0
        }
    }

    /// x where the drawn run ends (a value still held at the end is drawn to here).
    pub fn end_x(&self) -> f64 {
        self.pieces.last().map_or(0.0, |p| p.x1)
    }

    /// The compressed idle stretches.
    pub fn breaks(&self) -> impl Iterator<Item = &Piece> {
        self.pieces.iter().filter(|p| p.idle)
    }

    /// The linear segments.
    pub fn segments(&self) -> impl Iterator<Item = &Piece> {
        self.pieces.iter().filter(|p| !p.idle)
    }

    /// Ticks at "nice" times of each segment, about `spacing` pixels apart or more, plus each
    /// segment's first time.
    pub fn ticks(&self, spacing: f64) -> Vec<Tick> {
        let mut ticks = Vec::new();
        for segment in self.segments() {
            let width = segment.x1 - segment.x0;
            let duration = segment.t1 - segment.t0;
            let count = (width / spacing.max(1.0)).floor().clamp(1.0, 1000.0);
            let step = nice_step(duration / count);
            ticks.push(Tick {
                time: segment.t0,
                x: segment.x0,
                major: true,
                step,
            });
            if duration <= 0.0 || width < spacing {
                continue;
            }
            let first = (segment.t0 / step).ceil() * step;
            for k in 0..=(count as usize + 1) {
                let time = first + k as f64 * step;
                if time > segment.t1 {
                    break;
                }
                let x = self.x(time);
                if x - segment.x0 >= spacing / 2.0 {
                    ticks.push(Tick {
                        time,
                        x,
                        major: false,
                        step,
                    });
                }
            }
        }
        ticks
    }
}

/// The linear segments: `times` cut at the idle gaps that fit as breaks (longest first).
fn segments(times: &[f64], threshold: f64, plot: f64, slot: f64) -> Vec<(f64, f64)> {
    let max_breaks = if slot > 0.0 {
        (MAX_BREAK_SHARE * plot / slot).floor() as usize
    } else {
        0
    };
    let mut idle: Vec<(usize, f64)> = times
        .windows(2)
        .enumerate()
        .map(|(i, w)| (i, w[1] - w[0]))
        .filter(|&(_, gap)| gap > threshold)
        .collect();
    idle.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    idle.truncate(max_breaks);
    let mut cuts: Vec<usize> = idle.into_iter().map(|(i, _)| i).collect();
    cuts.sort_unstable();
    let mut segments = Vec::with_capacity(cuts.len() + 1);
    let mut start = times[0];
    for i in cuts {
        segments.push((start, times[i]));
        start = times[i + 1];
    }
    segments.push((start, times[times.len() - 1]));
    segments
}

/// Each segment's width: its share of `available` at one common scale; when no segment lasts
/// any time (a single cycle), equal shares.
fn widths(segments: &[(f64, f64)], available: f64) -> Vec<f64> {
    let total: f64 = segments.iter().map(|(t0, t1)| t1 - t0).sum();
    if total > 0.0 && total.is_finite() {
        segments
            .iter()
            .map(|(t0, t1)| (t1 - t0) / total * available)
            .collect()
    } else {
        let share = available / segments.len().max(1) as f64;
        vec![share; segments.len()]
    }
}

/// The smallest readable step at least `raw` seconds: 1-2-5 decimals below a second, clock
/// steps (seconds, minutes, hours) up to a day, 1-2-5 days beyond.
pub(super) fn nice_step(raw: f64) -> f64 {
    const CLOCK: [f64; 18] = [
        1.0, 2.0, 5.0, 10.0, 15.0, 30.0, 60.0, 120.0, 300.0, 600.0, 900.0, 1800.0, 3600.0, 7200.0,
        10800.0, 21600.0, 43200.0, 86400.0,
    ];
    if !raw.is_finite() || raw <= 0.0 {
        return 1.0;
    }
    if raw <= 1.0 {
        return decimal_step(raw);
    }
    if let Some(&step) = CLOCK.iter().find(|&&s| s >= raw) {
        return step;
    }
    86400.0 * decimal_step(raw / 86400.0)
}

/// The smallest of 1, 2, 5 × 10^k at least `raw` (> 0).
fn decimal_step(raw: f64) -> f64 {
    let power = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * power)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * power)
}

/// How times are written on the axis and in tooltips: mission elapsed time, `h:mm:ss` for runs
/// of an hour or more, `m:ss` otherwise, with as many decimals as the precision asks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Clock {
    /// Write hours.
    pub hours: bool,
}

impl Clock {
    /// The clock for a run ending at `end`.
    pub fn for_run(start: f64, end: f64) -> Clock {
        Clock {
            hours: start.abs().max(end.abs()) >= 3600.0,
        }
    }

    /// `t` written to the precision of `step` seconds (0 to 3 decimals).
    pub fn format(&self, t: f64, step: f64) -> String {
        let decimals = if step.is_nan() || step <= 0.0 || step >= 1.0 {
            0
        } else {
            ((-step.log10() - 1e-9).ceil() as usize).min(3)
        };
        if !t.is_finite() || t.abs() >= 1e9 {
            return format!("{t:.3e} s");
        }
        let sign = if t < 0.0 { "-" } else { "" };
        let unit = 10f64.powi(decimals as i32);
        let total = (t.abs() * unit).round() / unit;
        let hours = (total / 3600.0).floor();
        let minutes = ((total - hours * 3600.0) / 60.0).floor();
        let seconds = (total - hours * 3600.0 - minutes * 60.0).max(0.0);
        let width = if decimals > 0 { 3 + decimals } else { 2 };
        if self.hours || hours > 0.0 {
            format!("{sign}{hours}:{minutes:02}:{seconds:0width$.decimals$}")
        } else {
            format!("{sign}{minutes}:{seconds:0width$.decimals$}")
        }
    }

    /// `t` to a tenth of a second (tooltips).
    pub fn precise(&self, t: f64) -> String {
        self.format(t, 0.1)
    }
}

/// `t` as mission elapsed time to the millisecond, always with hours: `4:45:10.000` (the mission
/// log's cycle headers and summary, beside the seconds).
pub(crate) fn hours_minutes_seconds(t: f64) -> String {
    Clock { hours: true }.format(t, 0.001)
}

/// A duration in words: `45 s`, `4 min`, `4 h 30 min`, `12 d`.
pub(super) fn format_duration(seconds: f64) -> String {
    if !seconds.is_finite() || seconds >= 1e9 {
        return format!("{seconds:.2e} s");
    }
    let seconds = seconds.max(0.0);
    if seconds < 60.0 {
        return format!("{seconds:.0} s");
    }
    if seconds < 3600.0 {
        return format!("{:.0} min", (seconds / 60.0).round());
    }
    if seconds < 10.0 * 86400.0 {
        let mut hours = (seconds / 3600.0).floor();
        let mut minutes = ((seconds - hours * 3600.0) / 60.0).round();
        if minutes >= 60.0 {
            hours += 1.0;
            minutes = 0.0;
        }
        return if minutes == 0.0 {
            format!("{hours} h")
        } else {
            format!("{hours} h {minutes} min")
        };
    }
    format!("{:.0} d", seconds / 86400.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const COMPRESSION: Compression = Compression {
        threshold: 60.0,
        break_width: 28.0,
        pad: 8.0,
    };

    /// The mission log's clock: always hours, always milliseconds, so that a
    /// right-aligned column of them lines up.
    #[test]
    fn the_log_clock_writes_hours_minutes_and_seconds_to_the_millisecond() {
        assert_eq!(hours_minutes_seconds(0.0), "0:00:00.000");
        assert_eq!(hours_minutes_seconds(0.3), "0:00:00.300");
        assert_eq!(hours_minutes_seconds(17110.0), "4:45:10.000");
        assert_eq!(hours_minutes_seconds(59.9996), "0:01:00.000");
        assert_eq!(hours_minutes_seconds(999_999.999), "277:46:39.999");
    }

    #[test]
    fn an_idle_stretch_becomes_a_fixed_width_break_between_segments_at_one_scale() {
        let times = [0.0, 10.0, 40.0, 16240.0, 16300.0];
        let scale = Scale::new(&times, 0.0, 1000.0, &COMPRESSION);
        let breaks: Vec<_> = scale.breaks().collect();
        assert_eq!(breaks.len(), 1);
        assert_eq!((breaks[0].t0, breaks[0].t1), (40.0, 16240.0));
        assert_eq!(breaks[0].x1 - breaks[0].x0, 44.0);
        // 40 s + 60 s of activity share 1000 - 16 - 44 px: 9.4 px/s on both sides.
        let segments: Vec<_> = scale.segments().collect();
        let rate = |p: &Piece| (p.x1 - p.x0) / (p.t1 - p.t0);
        assert!((rate(segments[0]) - 9.4).abs() < 1e-9);
        assert!((rate(segments[1]) - 9.4).abs() < 1e-9);
        assert_eq!(scale.x(0.0), 8.0);
        assert!((scale.end_x() - 992.0).abs() < 1e-9);
        assert!(scale.x(10.0) < scale.x(40.0) && scale.x(40.0) < scale.x(16240.0));
        assert_eq!(scale.x(-5.0), scale.x(0.0));
        assert_eq!(scale.x(1e12), scale.end_x());
    }

    #[test]
    fn only_the_longest_idle_stretches_are_compressed_when_breaks_would_not_fit() {
        // 300 px wide: breaks may take 120 px, two of 44 px.
        let times: Vec<f64> = (0..20).map(|i| f64::from(i * i) * 100.0).collect();
        let scale = Scale::new(&times, 0.0, 300.0, &COMPRESSION);
        let breaks: Vec<_> = scale.breaks().map(|b| (b.t0, b.t1)).collect();
        assert_eq!(breaks, [(28900.0, 32400.0), (32400.0, 36100.0)]);
    }

    #[test]
    fn a_single_instant_takes_the_whole_width() {
        let scale = Scale::new(&[5.0], 100.0, 600.0, &COMPRESSION);
        assert_eq!(scale.x(5.0), 108.0);
        assert_eq!(scale.end_x(), 592.0);
        assert_eq!(scale.breaks().count(), 0);
        let ticks = scale.ticks(80.0);
        assert_eq!(ticks.len(), 1);
        assert!(ticks[0].major);
    }

    #[test]
    fn ticks_are_nice_times_in_each_segment() {
        let times = [0.0, 60.0, 120.0, 20000.0, 20010.0];
        let scale = Scale::new(&times, 0.0, 1000.0, &COMPRESSION);
        let ticks = scale.ticks(80.0);
        let majors: Vec<f64> = ticks.iter().filter(|t| t.major).map(|t| t.time).collect();
        assert_eq!(majors, [0.0, 20000.0]);
        let first: Vec<f64> = ticks
            .iter()
            .filter(|t| !t.major && t.time < 200.0)
            .map(|t| t.time)
            .collect();
        assert_eq!(first, [15.0, 30.0, 45.0, 60.0, 75.0, 90.0, 105.0, 120.0]);
        assert!(ticks.windows(2).all(|w| w[0].x <= w[1].x));
    }

    #[test]
    fn huge_times_and_degenerate_widths_do_not_break_the_scale() {
        let times = [1e15, 1e15 + 1.0];
        let scale = Scale::new(&times, 0.0, 10.0, &COMPRESSION);
        assert!(scale.x(1e15).is_finite());
        assert!(scale.ticks(80.0).len() <= 1002);
        let scale = Scale::new(&[], 0.0, 0.0, &COMPRESSION);
        assert_eq!(scale.x(3.0), scale.x(-3.0));
    }

    #[test]
    fn steps_are_readable() {
        assert_eq!(nice_step(0.07), 0.1);
        assert_eq!(nice_step(0.3), 0.5);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(200.0), 300.0);
        assert_eq!(nice_step(5000.0), 7200.0);
        assert_eq!(nice_step(3.0 * 86400.0), 5.0 * 86400.0);
        assert_eq!(nice_step(0.0), 1.0);
        assert_eq!(nice_step(f64::INFINITY), 1.0);
    }

    #[test]
    fn times_read_as_mission_elapsed_time() {
        let long = Clock::for_run(0.0, 17158.0);
        assert_eq!(long.format(16243.3, 0.1), "4:30:43.3");
        assert_eq!(long.format(43.0, 1.0), "0:00:43");
        let short = Clock::for_run(0.0, 120.0);
        assert_eq!(short.format(43.25, 0.01), "0:43.25");
        assert_eq!(short.format(-2.0, 1.0), "-0:02");
        assert_eq!(short.format(59.96, 0.1), "1:00.0");
        assert_eq!(short.format(3e12, 1.0), "3.000e12 s");
    }

    #[test]
    fn durations_read_in_words() {
        assert_eq!(format_duration(16200.0), "4 h 30 min");
        assert_eq!(format_duration(240.0), "4 min");
        assert_eq!(format_duration(45.2), "45 s");
        assert_eq!(format_duration(7199.0), "2 h");
        assert_eq!(format_duration(30.0 * 86400.0), "30 d");
        assert_eq!(format_duration(1e12), "1.00e12 s");
    }
}
