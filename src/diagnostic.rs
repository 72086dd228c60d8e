//! Located errors: every problem in an input file points at `file:line:col`, shows the offending
//! source line with a caret under the offending text, and says what was expected (DESIGN.md §13).
//!
//! Parsers and resolvers produce [`Diagnostic`]s that carry only a byte [`Span`]; whoever owns the
//! text wraps them with it in a [`SourceErrors`], which renders them. Rendering is done by
//! `codespan-reporting` with ASCII characters and no colour, so the output is stable enough for
//! snapshot tests and readable in any terminal or log.

pub(crate) mod locate;
#[cfg(test)]
pub(crate) mod reference;

use std::fmt;
use std::ops::Range;
use std::path::{Component, Path, PathBuf};

use codespan_reporting::diagnostic::{Diagnostic as Report, Label};
use codespan_reporting::files::SimpleFile;
use codespan_reporting::term::{self, Chars, Config};

/// A byte range in a source text.
pub type Span = Range<usize>;

/// One problem found in a source text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Diagnostic {
    /// What is wrong, in one line (`unknown variable \`engne\``).
    pub message: String,
    /// Where it is.
    pub span: Span,
    /// What was expected there, shown under the caret.
    pub expected: String,
    /// Further lines of help (suggestions, the list of known names, ...).
    pub notes: Vec<String>,
    /// Other places the problem concerns, each with what it is (the instance of a component
    /// type whose body has the error), shown beside the main location.
    pub related: Vec<(Span, String)>,
}

impl Diagnostic {
    /// A problem at `span` with no expectation or notes yet.
    pub fn new(message: impl Into<String>, span: Span) -> Self {
        Diagnostic {
            message: message.into(),
            span,
            expected: String::new(),
            notes: Vec::new(),
            related: Vec::new(),
        }
    }

    /// Says what was expected at the location.
    pub fn expected(mut self, expected: impl Into<String>) -> Self {
        self.expected = expected.into();
        self
    }

    /// Adds a line of help.
    pub fn note(mut self, note: impl Into<String>) -> Self {
        self.notes.push(note.into());
        self
    }

    /// Adds another place the problem concerns, labelled.
    pub fn related(mut self, span: Span, label: impl Into<String>) -> Self {
        self.related.push((span, label.into()));
        self
    }

    /// Moves the span by `offset` bytes: used when a fragment (a formula inside a RON string or an
    /// RMPL program) was parsed on its own and must be reported in the enclosing file.
    pub fn shifted(mut self, offset: usize) -> Self {
        self.span = self.span.start + offset..self.span.end + offset;
        self
    }
}

/// A named source text: a file on disk, or a string given on the command line.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Source {
    /// The name shown in error locations (usually the path).
    pub name: String,
    /// The whole text.
    pub text: String,
}

impl Source {
    /// A source with the given display name and text.
    pub fn new(name: impl Into<String>, text: impl Into<String>) -> Self {
        Source {
            name: name.into(),
            text: text.into(),
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    pub fn line_col(&self, offset: usize) -> (usize, usize) {
        let offset = self.clamp(offset);
        let before = &self.text[..offset];
        let line = before.matches('\n').count() + 1;
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let col = self.text[line_start..offset].chars().count() + 1;
        (line, col)
    }

    /// Byte offset of a 1-based line and column, as reported by other parsers (RON).
    pub fn offset_of(&self, line: usize, col: usize) -> usize {
        let line_start: usize = self
            .text
            .split_inclusive('\n')
            .take(line.saturating_sub(1))
            .map(str::len)
            .sum();
        let rest = &self.text[line_start.min(self.text.len())..];
        let col_bytes: usize = rest
            .chars()
            .take(col.saturating_sub(1))
            .map(char::len_utf8)
            .sum();
        (line_start + col_bytes).min(self.text.len())
    }

    /// Renders diagnostics against this source, one after the other.
    pub fn render(&self, diagnostics: &[Diagnostic]) -> String {
        let file = SimpleFile::new(self.name.as_str(), self.text.as_str());
        let config = Config {
            chars: Chars::ascii(),
            ..Config::default()
        };
        let mut out = String::new();
        for diagnostic in diagnostics {
            let span = self.clamp(diagnostic.span.start)..self.clamp(diagnostic.span.end);
            let mut labels =
                vec![Label::primary((), span.clone()).with_message(&diagnostic.expected)];
            labels.extend(diagnostic.related.iter().map(|(related, label)| {
                let related = self.clamp(related.start)..self.clamp(related.end);
                Label::secondary((), related).with_message(label)
            }));
            let report = Report::error()
                .with_message(&diagnostic.message)
                .with_labels(labels)
                .with_notes(diagnostic.notes.clone());
            match term::emit_into_string(&config, &file, &report) {
                Ok(text) => out.push_str(&text),
                // Only reachable if a span does not fall on a character boundary; still say
                // where the problem is rather than lose it.
                Err(_) => {
                    let (line, col) = self.line_col(span.start);
                    out.push_str(&format!(
                        "error: {}\n  --> {}:{line}:{col}\n",
                        diagnostic.message, self.name
                    ));
                }
            }
        }
        out
    }

    /// Clamps an offset into the text and back onto a character boundary.
    fn clamp(&self, offset: usize) -> usize {
        let mut offset = offset.min(self.text.len());
        while !self.text.is_char_boundary(offset) {
            offset -= 1;
        }
        offset
    }
}

impl Source {
    /// Reads a file, named by its path as given. The one reader of every file the CLI and the
    /// loaders read, so that bytes that are not UTF-8 are located like any other bad input: at the
    /// first invalid byte's line:column (and byte offset), not a bare "stream did not contain
    /// valid UTF-8".
    ///
    /// Only regular files of at most [`MAX_SOURCE_BYTES`] are read: a device (`/dev/zero`), a
    /// pipe or a directory given as a model would otherwise hang the loader or exhaust memory.
    pub fn read(path: &Path) -> Result<Source, ReadError> {
        let name = path.display().to_string();
        let bytes = read_regular_file(path).map_err(|error| ReadError::Io {
            name: name.clone(),
            error,
        })?;
        match String::from_utf8(bytes) {
            Ok(text) => Ok(Source::new(name, text)),
            Err(e) => Err(ReadError::NotUtf8(Box::new(not_utf8(name, e.as_bytes())))),
        }
    }
}

/// The largest source file [`Source::read`] accepts (1 GiB): far above any model, program,
/// scenario or replay log, far below what would exhaust the machine.
pub const MAX_SOURCE_BYTES: u64 = 1 << 30;

fn read_regular_file(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let metadata = file.metadata()?;
    if !metadata.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    if metadata.len() > MAX_SOURCE_BYTES {
        return Err(std::io::Error::other(format!(
            "{} bytes, more than the {MAX_SOURCE_BYTES} a source file may have",
            metadata.len()
        )));
    }
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    // The size checked above can grow while reading (a file being written): read one byte past
    // the limit at most.
    file.take(MAX_SOURCE_BYTES + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_SOURCE_BYTES {
        return Err(std::io::Error::other(
            "the file grew past the size a source may have",
        ));
    }
    Ok(bytes)
}

/// The located error for a file whose bytes are not UTF-8: shown against the text with each
/// invalid sequence replaced by U+FFFD, which keeps every byte offset before the first one.
fn not_utf8(name: String, bytes: &[u8]) -> SourceErrors {
    let (offset, byte) = match std::str::from_utf8(bytes) {
        Ok(_) => (bytes.len(), None),
        Err(e) => (e.valid_up_to(), bytes.get(e.valid_up_to()).copied()),
    };
    let source = Source::new(name, String::from_utf8_lossy(bytes).into_owned());
    let byte = byte.map_or_else(String::new, |b| format!(" 0x{b:02x}"));
    let diagnostic = Diagnostic::new(
        format!("not UTF-8 text: byte{byte} at byte offset {offset} is not valid UTF-8"),
        offset..offset + '\u{fffd}'.len_utf8(),
    )
    .expected("text encoded in UTF-8");
    SourceErrors::new(source, vec![diagnostic])
}

/// Why [`Source::read`] failed.
#[derive(Debug)]
pub enum ReadError {
    /// The file could not be read at all (missing, a directory, no permission).
    Io {
        /// The path as given.
        name: String,
        /// What the operating system said.
        error: std::io::Error,
    },
    /// The file is not UTF-8 text: located at the first invalid byte.
    NotUtf8(Box<SourceErrors>),
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ReadError::Io { name, error } => write!(f, "error: cannot read {name}: {error}"),
            ReadError::NotUtf8(errors) => write!(f, "{errors}"),
        }
    }
}

impl std::error::Error for ReadError {}

/// One or more problems in one source, with the source, so they can be printed on their own.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceErrors {
    /// The text the diagnostics point into.
    pub source: Source,
    /// The problems, in the order they were found.
    pub diagnostics: Vec<Diagnostic>,
}

impl SourceErrors {
    /// Wraps diagnostics with the source they point into.
    pub fn new(source: Source, diagnostics: Vec<Diagnostic>) -> Self {
        SourceErrors {
            source,
            diagnostics,
        }
    }
}

impl fmt::Display for SourceErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.source.render(&self.diagnostics).trim_end())
    }
}

impl std::error::Error for SourceErrors {}

/// Why a file, and the files it names, could not be loaded (a scenario with its plant, program
/// or mission; a mission with its plant).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LoadErrors {
    /// The file itself cannot be read.
    Unreadable(String),
    /// The problems found, grouped by the file they are in.
    Invalid(Vec<SourceErrors>),
}

impl From<ReadError> for LoadErrors {
    /// A file that cannot be read at all is unreadable; one that is not UTF-8 is located.
    fn from(error: ReadError) -> Self {
        match error {
            ReadError::NotUtf8(errors) => LoadErrors::Invalid(vec![*errors]),
            io => LoadErrors::Unreadable(io.to_string()),
        }
    }
}

impl fmt::Display for LoadErrors {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadErrors::Unreadable(message) => f.write_str(message),
            LoadErrors::Invalid(files) => {
                for (i, errors) in files.iter().enumerate() {
                    if i > 0 {
                        writeln!(f)?;
                    }
                    write!(f, "{errors}")?;
                }
                Ok(())
            }
        }
    }
}

impl std::error::Error for LoadErrors {}

/// `dir/relative` with `.` and `name/..` removed, so file names read well in messages.
pub fn resolve_path(dir: &Path, relative: &str) -> PathBuf {
    let joined = dir.join(relative);
    let mut out: Vec<Component> = Vec::new();
    for part in joined.components() {
        match part {
            Component::CurDir => {}
            Component::ParentDir if matches!(out.last(), Some(Component::Normal(_))) => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out.iter().collect()
}

/// Turns a RON syntax or shape error into a located diagnostic.
/// An unknown enum variant or struct field (a misspelt event name in a scenario's
/// expectation, a misspelt field of a plant's mode) gets the closest accepted name as a
/// did-you-mean note, in every RON format, since every loader reports through here.
pub fn ron_error(source: &Source, error: &ron::error::SpannedError) -> Diagnostic {
    let start = source.offset_of(error.span.start.line, error.span.start.col);
    let end = source.offset_of(error.span.end.line, error.span.end.col);
    let diagnostic = Diagnostic::new(
        format!("malformed RON: {}", error.code),
        start..end.max(start),
    )
    .expected("the documented format");
    let close = match &error.code {
        ron::Error::NoSuchEnumVariant {
            expected, found, ..
        }
        | ron::Error::NoSuchStructField {
            expected, found, ..
        } => did_you_mean(found, expected.iter().copied()),
        _ => None,
    };
    match close {
        Some(close) => diagnostic.note(format!("did you mean `{close}`?")),
        None => diagnostic,
    }
}

/// Where a string literal with exactly this content first appears in a RON text: the span of
/// its content, between the quotes. Loaders deserialize with serde (which keeps no positions) and
/// then use this to point errors about a name or a formula at the text that holds it.
pub fn find_string_literal(text: &str, content: &str) -> Option<Span> {
    find_string_literals(text, content).into_iter().next()
}

/// Every string literal with exactly this content in a RON text, in order (the second is where
/// a duplicate declaration is).
pub fn find_string_literals(text: &str, content: &str) -> Vec<Span> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'/' if bytes.get(i + 1) == Some(&b'/') => {
                i = text[i..].find('\n').map_or(bytes.len(), |n| i + n);
            }
            b'/' if bytes.get(i + 1) == Some(&b'*') => {
                i = text[i + 2..].find("*/").map_or(bytes.len(), |n| i + n + 4);
            }
            b'\'' => {
                // A character literal: skip it so a quote inside does not open a string.
                let end = if bytes.get(i + 1) == Some(&b'\\') {
                    i + 3
                } else {
                    i + 2
                };
                i = text[end.min(text.len())..]
                    .find('\'')
                    .map_or(bytes.len(), |n| end + n + 1);
            }
            b'"' => {
                let start = i + 1;
                let mut j = start;
                let mut unescaped = String::new();
                while j < bytes.len() && bytes[j] != b'"' {
                    if bytes[j] == b'\\' && j + 1 < bytes.len() {
                        j += 1;
                    }
                    let c = text[j..].chars().next().unwrap_or('\0');
                    unescaped.push(c);
                    j += c.len_utf8();
                }
                if unescaped == content {
                    found.push(start..j);
                }
                i = j + 1;
            }
            _ => i += 1,
        }
    }
    found
}

/// The known name closest to `unknown`, if one is close enough to be a likely typo.
pub fn did_you_mean<'a>(
    unknown: &str,
    known: impl IntoIterator<Item = &'a str>,
) -> Option<&'a str> {
    known
        .into_iter()
        .map(|name| (strsim::jaro_winkler(unknown, name), name))
        .filter(|(score, _)| *score > 0.8)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, name)| name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, serde::Deserialize)]
    #[allow(dead_code)]
    enum Kind {
        GoalFailed,
        GoalAchieved,
    }

    #[derive(Debug, serde::Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Expect {
        event: Kind,
    }

    /// DESIGN.md §13: a misspelt variant or field in any RON file names the closest accepted one.
    #[test]
    fn misspelt_variants_and_fields_get_a_did_you_mean() {
        let cases = [
            ("(event: GoalFailled)", "did you mean `GoalFailed`?"),
            ("(evnet: GoalFailed)", "did you mean `event`?"),
        ];
        for (text, note) in cases {
            let source = Source::new("x.ron", text);
            let error = ron::from_str::<Expect>(text).expect_err("misspelt");
            let rendered = source.render(&[ron_error(&source, &error)]);
            assert!(rendered.contains(note), "{rendered}");
        }
        let text = "(event: Nothing)";
        let source = Source::new("x.ron", text);
        let error = ron::from_str::<Expect>(text).expect_err("unknown");
        let rendered = source.render(&[ron_error(&source, &error)]);
        assert!(!rendered.contains("did you mean"), "{rendered}");
    }

    #[test]
    fn line_and_column_are_one_based_and_count_characters() {
        let source = Source::new("f", "ab\n≥c d\n");
        assert_eq!(source.line_col(0), (1, 1));
        assert_eq!(source.line_col(3), (2, 1));
        // '≥' is three bytes but one column.
        assert_eq!(source.line_col(6), (2, 2));
        assert_eq!(source.offset_of(2, 2), 6);
        assert_eq!(source.offset_of(1, 1), 0);
    }

    #[test]
    fn rendering_shows_location_line_caret_and_expectation() {
        let source = Source::new("model.ron", "x = on\nengne = standby\n");
        let diagnostic = Diagnostic::new("unknown variable `engne`", 7..12)
            .expected("a variable name")
            .note("did you mean `engine`?");
        let text = source.render(&[diagnostic]);
        assert!(text.contains("model.ron:2:1"), "{text}");
        assert!(text.contains("engne = standby"), "{text}");
        assert!(text.contains("^^^^^ a variable name"), "{text}");
        assert!(text.contains("did you mean `engine`?"), "{text}");
    }

    #[test]
    fn spans_past_the_end_are_clamped_not_panicking() {
        let source = Source::new("f", "é");
        let text = source.render(&[Diagnostic::new("late", 1..99)]);
        assert!(text.contains("f:1:1"), "{text}");
    }

    #[test]
    fn string_literals_are_found_outside_comments_and_chars() {
        let text = "( // \"x = on\" in a comment\n c: '\"', a: \"x = on\", b: \"é \\\"q\\\"\")";
        let span = find_string_literal(text, "x = on").unwrap();
        assert_eq!(&text[span], "x = on");
        assert!(find_string_literal(text, "é \"q\"").is_some());
        assert_eq!(find_string_literal(text, "missing"), None);
        let twice = "(a: \"n\", b: \"n\")";
        assert_eq!(find_string_literals(twice, "n"), vec![5..6, 13..14]);
    }

    #[test]
    fn suggestions_only_for_close_names() {
        assert_eq!(did_you_mean("engne", ["engine", "nav"]), Some("engine"));
        assert_eq!(did_you_mean("zzz", ["engine", "nav"]), None);
    }
}
