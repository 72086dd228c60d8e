//! Text on the timeline: made safe for XML, measured, shortened, and labels placed on stacked
//! levels so that none overlaps another.
//!
//! The picture uses a monospace font, so a label's width is its character count times a fixed
//! advance; placement can then guarantee no overlap without font metrics.

/// Advance of one character of the monospace font, as a fraction of the font size (DejaVu Sans
/// Mono, Menlo and Consolas are all about 0.6; rounded up).
pub(super) const CHAR_WIDTH: f64 = 0.62;

/// Width of `text` at font size `size`.
pub(super) fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * size * CHAR_WIDTH
}

/// `text` without the characters XML 1.0 forbids (control characters, U+FFFE, U+FFFF), with
/// line breaks and tabs as spaces. The SVG crate escapes `&`, `<`, `>` and quotes.
pub(super) fn clean(text: &str) -> String {
    text.chars()
        .filter_map(|c| match c {
            '\n' | '\r' | '\t' => Some(' '),
            '\u{FFFE}' | '\u{FFFF}' => None,
            c if c < ' ' => None,
            c => Some(c),
        })
        .collect()
}

/// `text` cleaned and cut to at most `max` characters, an ellipsis marking the cut.
pub(super) fn shorten(text: &str, max: usize) -> String {
    let text = clean(text);
    if text.chars().count() <= max {
        return text;
    }
    let mut short: String = text.chars().take(max.saturating_sub(1)).collect();
    short.push('…');
    short
}

/// `text` as an identifier fragment for `id` attributes: letters, digits, `-` and `_` kept,
/// anything else `_`.
pub(super) fn ident(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The last component of a path: programs are named by file, not by where they were loaded from.
pub(super) fn file_name(path: &str) -> &str {
    path.rsplit(['/', '\\']).next().unwrap_or(path)
}

/// `text` cleaned and broken at spaces into lines of at most `columns` characters (a word
/// longer than that is cut), every line after the first starting with `indent`.
pub(super) fn wrap(text: &str, columns: usize, indent: &str) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    let mut empty = true;
    for word in clean(text).split(' ').filter(|w| !w.is_empty()) {
        if !empty && line.chars().count() + 1 + word.chars().count() > columns {
            lines.push(std::mem::take(&mut line));
            line.push_str(indent);
            empty = true;
        }
        if !empty {
            line.push(' ');
        }
        line.push_str(word);
        empty = false;
    }
    if !empty {
        lines.push(line);
    }
    lines
        .into_iter()
        .map(|l| shorten(&l, columns.max(2)))
        .collect()
}

/// A label to place next to a mark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Request {
    /// The mark's x.
    pub x: f64,
    /// The label's width.
    pub width: f64,
    /// How far right something attached to the label reaches (a goal's bar), at least `x`.
    pub reach: f64,
}

/// Where a label goes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Placement {
    /// Its level: 0 nearest the marks.
    pub level: usize,
    /// x where its text starts.
    pub left: f64,
}

/// Space between a mark and its label, and between labels on one level.
const GAP: f64 = 3.0;

/// Places labels left to right, each on the lowest level where it overlaps nothing: text to the
/// right of its mark, or to the left when it would pass `right_edge`. A label that finds no
/// free level among `max_levels` is thinned (`None`): its mark and tooltip stay.
pub(super) fn place(
    requests: &[Request],
    right_edge: f64,
    max_levels: usize,
) -> Vec<Option<Placement>> {
    let mut order: Vec<usize> = (0..requests.len()).collect();
    order.sort_by(|&a, &b| requests[a].x.total_cmp(&requests[b].x));
    let mut levels: Vec<f64> = Vec::new();
    let mut placements = vec![None; requests.len()];
    for i in order {
        let request = requests[i];
        let left = if request.x + GAP + request.width <= right_edge {
            request.x + GAP
        } else {
            request.x - GAP - request.width
        };
        let start = left.min(request.x);
        let end = (left + request.width).max(request.reach);
        let free = levels.iter().position(|&taken| taken + GAP <= start);
        let level = match free {
            Some(level) => level,
            None if levels.len() < max_levels => {
                levels.push(f64::NEG_INFINITY);
                levels.len() - 1
            }
            None => continue,
        };
        levels[level] = end;
        placements[i] = Some(Placement { level, left });
    }
    placements
}

/// How many levels the placements use.
pub(super) fn levels_used(placements: &[Option<Placement>]) -> usize {
    placements
        .iter()
        .flatten()
        .map(|p| p.level + 1)
        .max()
        .unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(x: f64, width: f64) -> Request {
        Request { x, width, reach: x }
    }

    #[test]
    fn labels_stack_on_levels_and_never_overlap() {
        let requests: Vec<Request> = (0..5).map(|i| request(f64::from(i), 50.0)).collect();
        let placed = place(&requests, 1000.0, 10);
        let levels: Vec<usize> = placed.iter().flatten().map(|p| p.level).collect();
        assert_eq!(levels, [0, 1, 2, 3, 4]);
        // Far enough right, a label reuses level 0.
        let placed = place(&[request(0.0, 50.0), request(60.0, 50.0)], 1000.0, 10);
        assert_eq!(placed[1].map(|p| p.level), Some(0));
        assert_eq!(levels_used(&placed), 1);
    }

    #[test]
    fn labels_past_the_right_edge_go_left_of_their_mark() {
        let placed = place(&[request(990.0, 100.0)], 1000.0, 3);
        assert_eq!(placed[0].map(|p| p.left), Some(887.0));
    }

    #[test]
    fn labels_beyond_the_last_level_are_thinned() {
        let requests: Vec<Request> = (0..4).map(|i| request(f64::from(i), 50.0)).collect();
        let placed = place(&requests, 1000.0, 2);
        assert_eq!(placed.iter().filter(|p| p.is_none()).count(), 2);
    }

    #[test]
    fn a_bar_keeps_its_level_taken() {
        let bar = Request {
            x: 0.0,
            width: 20.0,
            reach: 500.0,
        };
        let placed = place(&[bar, request(100.0, 20.0)], 1000.0, 5);
        assert_eq!(placed[1].map(|p| p.level), Some(1));
    }

    #[test]
    fn notes_wrap_at_spaces_with_an_indent() {
        assert_eq!(
            wrap("[1] lander = unsuccessful-attempt from 4:34:52", 22, "  "),
            ["[1] lander =", "  unsuccessful-attempt", "  from 4:34:52"]
        );
        assert_eq!(wrap("short", 20, "  "), ["short"]);
        assert!(wrap("", 20, "  ").is_empty());
        // A word longer than a line is cut, the cut marked.
        assert_eq!(wrap("abcdefghij", 5, ""), ["abcd…"]);
    }

    #[test]
    fn text_is_made_safe_and_short() {
        assert_eq!(clean("a\u{1}b\nc\u{FFFF}"), "ab c");
        assert_eq!(shorten("engine = standby", 8), "engine …");
        assert_eq!(shorten("short", 8), "short");
        assert_eq!(ident("alt 40m\"trigger"), "alt_40m_trigger");
        assert!((text_width("abc", 10.0) - 18.6).abs() < 1e-9);
        assert_eq!(file_name("programs/mars_edl.rmpl"), "mars_edl.rmpl");
        assert_eq!(file_name("edl.rmpl"), "edl.rmpl");
    }
}
