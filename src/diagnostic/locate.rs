//! Where things are in a RON file that serde has already read, and reading RON maps in order.
//!
//! serde keeps no positions, and `ron` 0.12 offers no spanned values, so loaders (plant models,
//! scenarios) read a file twice: once with serde for the values, once here for an *outline* —
//! the nesting of structs, lists, maps and scalars with their byte spans. An error about the
//! fourth transition of the second component then points at that transition's text (a
//! probability, a window bound, a guard) rather than at the first string that happens to look
//! the same. [`Locator`] turns a path (`components[2].transitions[4].after[1]`) into a span.
//!
//! The outline is only built from text serde accepted, so it is a best-effort reader: anything it
//! does not understand ends the outline early and lookups fall back to a coarser location.
//!
//! [`Entries`] reads a RON map in file order and keeps repeated keys, so that loaders can report
//! a duplicate where it is written; [`NumberOrName`] reads a value that may be either.

use std::fmt;
use std::marker::PhantomData;

use serde::Deserialize;
use serde::de::{self, Deserializer, MapAccess, Visitor};

use crate::diagnostic::Span;

/// One value of a RON text and where it is.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Node {
    /// `Name(field: value, ...)` or `(field: value, ...)`.
    Fields {
        /// The whole struct.
        span: Span,
        /// Field name and value, in order.
        fields: Vec<(String, Node)>,
    },
    /// `[a, b]`, `(a, b)`, `Name(a, b)` (tuple structs and enum variants, `Some(x)`).
    Items {
        /// The whole sequence.
        span: Span,
        /// The elements, in order.
        items: Vec<Node>,
    },
    /// `{ key: value, ... }`.
    Entries {
        /// The whole map.
        span: Span,
        /// Key and value, in order.
        entries: Vec<(Node, Node)>,
    },
    /// A string (span of its content, between the quotes), number, identifier or character.
    Scalar {
        /// The text's span (for strings, without the quotes).
        span: Span,
        /// The unescaped content for strings; the raw text otherwise.
        text: String,
    },
}

/// One step of a path into an outline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step<'a> {
    /// A struct's field.
    Field(&'a str),
    /// A sequence's element.
    Index(usize),
    /// The value of the map entry whose key is this string.
    Value(&'a str),
    /// The key of the map entry whose key is this string.
    Key(&'a str),
}

impl Node {
    /// The span of the whole node.
    pub(crate) fn span(&self) -> Span {
        match self {
            Node::Fields { span, .. }
            | Node::Items { span, .. }
            | Node::Entries { span, .. }
            | Node::Scalar { span, .. } => span.clone(),
        }
    }

    /// The node at `path`, looking through `Some(...)` wrappers.
    pub(crate) fn find(&self, path: &[Step]) -> Option<&Node> {
        let Some((step, rest)) = path.split_first() else {
            return Some(self);
        };
        let next = match (self, step) {
            (Node::Fields { fields, .. }, Step::Field(name)) => {
                fields.iter().find(|(f, _)| f == name).map(|(_, n)| n)
            }
            (Node::Items { items, .. }, Step::Index(i)) => items.get(*i),
            (Node::Entries { entries, .. }, Step::Value(key) | Step::Key(key)) => entries
                .iter()
                .find(|(k, _)| matches!(k, Node::Scalar { text, .. } if text == key))
                .map(|(k, v)| if matches!(step, Step::Key(_)) { k } else { v }),
            // `Some(x)`: look inside.
            (Node::Items { items, .. }, _) if items.len() == 1 => return items[0].find(path),
            _ => None,
        }?;
        next.find(rest)
    }
}

/// Turns paths into the file's text into spans, falling back to the nearest enclosing value the
/// outline knows.
pub(crate) struct Locator {
    outline: Option<Node>,
}

impl Locator {
    /// Reads the outline of `text`.
    pub(crate) fn new(text: &str) -> Self {
        Locator {
            outline: outline(text),
        }
    }

    /// The span of the value at `path` (for strings, their content), or of the closest enclosing
    /// value found.
    pub(crate) fn at(&self, path: &[Step]) -> Span {
        let Some(root) = &self.outline else {
            return 0..0;
        };
        (0..=path.len())
            .rev()
            .find_map(|n| root.find(&path[..n]).map(Node::span))
            .unwrap_or(0..0)
    }
}

/// A RON map read in file order, keeping repeated keys (so duplicates can be reported).
#[derive(Debug, Clone)]
pub(crate) struct Entries<V>(pub(crate) Vec<(String, V)>);

impl<V> Default for Entries<V> {
    fn default() -> Self {
        Entries(Vec::new())
    }
}

impl<'de, V: Deserialize<'de>> Deserialize<'de> for Entries<V> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct EntriesVisitor<V>(PhantomData<V>);
        impl<'de, V: Deserialize<'de>> Visitor<'de> for EntriesVisitor<V> {
            type Value = Entries<V>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a map from names, `{ \"name\": ... }`")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Entries<V>, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    entries.push(entry);
                }
                Ok(Entries(entries))
            }
        }
        deserializer.deserialize_map(EntriesVisitor(PhantomData))
    }
}

/// A number or a name, where a file may write either: a number or a component type's
/// parameter in a plant file, a value or a reading of a numeric observable in a script.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum NumberOrName {
    /// Written as a number.
    Number(f64),
    /// Written as a name (a string).
    Name(String),
}

impl<'de> Deserialize<'de> for NumberOrName {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct NumberVisitor;
        impl Visitor<'_> for NumberVisitor {
            type Value = NumberOrName;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or a name")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<NumberOrName, E> {
                Ok(NumberOrName::Number(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<NumberOrName, E> {
                Ok(NumberOrName::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<NumberOrName, E> {
                Ok(NumberOrName::Number(v as f64))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<NumberOrName, E> {
                Ok(NumberOrName::Name(v.to_string()))
            }
        }
        // RON says what it holds; a format that does not (the reference pages' tracer) is
        // asked for the number.
        if deserializer.is_human_readable() {
            deserializer.deserialize_any(NumberVisitor)
        } else {
            deserializer.deserialize_f64(NumberVisitor)
        }
    }
}

/// Reads the outline of a RON text; `None` when the text is not understood.
pub(crate) fn outline(text: &str) -> Option<Node> {
    let mut reader = Reader { text, pos: 0 };
    reader.skip_preamble();
    reader.value()
}

struct Reader<'a> {
    text: &'a str,
    pos: usize,
}

impl<'a> Reader<'a> {
    fn rest(&self) -> &'a str {
        &self.text[self.pos..]
    }

    /// Skips whitespace and comments (line and, possibly nested, block comments).
    fn skip_blank(&mut self) {
        loop {
            let rest = self.rest();
            let trimmed = rest.trim_start();
            self.pos += rest.len() - trimmed.len();
            if trimmed.starts_with("//") {
                self.pos += trimmed.find('\n').unwrap_or(trimmed.len());
            } else if trimmed.starts_with("/*") {
                let mut depth = 0usize;
                let bytes = self.text.as_bytes();
                while self.pos < bytes.len() {
                    if self.text[self.pos..].starts_with("/*") {
                        depth += 1;
                        self.pos += 2;
                    } else if self.text[self.pos..].starts_with("*/") {
                        depth -= 1;
                        self.pos += 2;
                        if depth == 0 {
                            break;
                        }
                    } else {
                        self.pos += self.rest().chars().next().map_or(1, char::len_utf8);
                    }
                }
            } else {
                return;
            }
        }
    }

    /// Skips `#![enable(...)]` attributes.
    fn skip_preamble(&mut self) {
        loop {
            self.skip_blank();
            if !self.rest().starts_with("#!") {
                return;
            }
            match self.rest().find(']') {
                Some(end) => self.pos += end + 1,
                None => return,
            }
        }
    }

    fn peek(&mut self) -> Option<char> {
        self.skip_blank();
        self.rest().chars().next()
    }

    fn eat(&mut self, c: char) -> bool {
        if self.peek() == Some(c) {
            self.pos += c.len_utf8();
            true
        } else {
            false
        }
    }

    fn value(&mut self) -> Option<Node> {
        let start = self.pos_after_blank();
        match self.peek()? {
            '[' => {
                self.pos += 1;
                let items = self.sequence(']')?;
                Some(Node::Items {
                    span: start..self.pos,
                    items,
                })
            }
            '{' => {
                self.pos += 1;
                self.map(start)
            }
            '(' => {
                self.pos += 1;
                self.parenthesised(start)
            }
            '"' => self.string(),
            'r' if self.rest().starts_with("r\"") || self.rest().starts_with("r#") => {
                self.raw_string()
            }
            '\'' => self.character(),
            _ => {
                let word = self.word()?;
                if self.peek() == Some('(') {
                    self.pos += 1;
                    self.parenthesised(start)
                } else {
                    Some(word)
                }
            }
        }
    }

    fn pos_after_blank(&mut self) -> usize {
        self.skip_blank();
        self.pos
    }

    /// After `(`: either `field: value, ...` or `value, ...`, up to `)`.
    fn parenthesised(&mut self, start: usize) -> Option<Node> {
        let save = self.pos;
        if let Some(Node::Scalar { text, .. }) = self.word() {
            if self.eat(':') {
                let mut fields = vec![(text, self.value()?)];
                loop {
                    self.eat(',');
                    if self.eat(')') {
                        return Some(Node::Fields {
                            span: start..self.pos,
                            fields,
                        });
                    }
                    let Node::Scalar { text, .. } = self.word()? else {
                        return None;
                    };
                    if !self.eat(':') {
                        return None;
                    }
                    fields.push((text, self.value()?));
                }
            }
        }
        self.pos = save;
        let items = self.sequence(')')?;
        Some(Node::Items {
            span: start..self.pos,
            items,
        })
    }

    /// Comma-separated values up to `close` (consumed).
    fn sequence(&mut self, close: char) -> Option<Vec<Node>> {
        let mut items = Vec::new();
        loop {
            if self.eat(close) {
                return Some(items);
            }
            items.push(self.value()?);
            if !self.eat(',') && self.peek() != Some(close) {
                return None;
            }
        }
    }

    fn map(&mut self, start: usize) -> Option<Node> {
        let mut entries = Vec::new();
        loop {
            if self.eat('}') {
                return Some(Node::Entries {
                    span: start..self.pos,
                    entries,
                });
            }
            let key = self.value()?;
            if !self.eat(':') {
                return None;
            }
            entries.push((key, self.value()?));
            if !self.eat(',') && self.peek() != Some('}') {
                return None;
            }
        }
    }

    /// A number, identifier or keyword: a run of characters that are none of RON's punctuation.
    fn word(&mut self) -> Option<Node> {
        let start = self.pos_after_blank();
        let len = self
            .rest()
            .find(|c: char| c.is_whitespace() || "()[]{}:,\"'/".contains(c))
            .unwrap_or(self.rest().len());
        if len == 0 {
            return None;
        }
        self.pos += len;
        Some(Node::Scalar {
            span: start..self.pos,
            text: self.text[start..self.pos].to_string(),
        })
    }

    fn string(&mut self) -> Option<Node> {
        self.pos += 1;
        let start = self.pos;
        let mut content = String::new();
        let mut chars = self.rest().char_indices();
        while let Some((i, c)) = chars.next() {
            match c {
                '"' => {
                    self.pos = start + i + 1;
                    return Some(Node::Scalar {
                        span: start..start + i,
                        text: content,
                    });
                }
                '\\' => content.push(unescape(chars.next()?.1)),
                c => content.push(c),
            }
        }
        None
    }

    fn raw_string(&mut self) -> Option<Node> {
        self.pos += 1;
        let hashes = self.rest().len() - self.rest().trim_start_matches('#').len();
        self.pos += hashes;
        if !self.eat('"') {
            return None;
        }
        let start = self.pos;
        let close = format!("\"{}", "#".repeat(hashes));
        let end = start + self.rest().find(&close)?;
        self.pos = end + close.len();
        Some(Node::Scalar {
            span: start..end,
            text: self.text[start..end].to_string(),
        })
    }

    fn character(&mut self) -> Option<Node> {
        let start = self.pos;
        self.pos += 1;
        if self.rest().starts_with('\\') {
            self.pos += 1;
        }
        self.pos += self.rest().chars().next()?.len_utf8();
        if !self.rest().starts_with('\'') {
            return None;
        }
        self.pos += 1;
        Some(Node::Scalar {
            span: start..self.pos,
            text: self.text[start..self.pos].to_string(),
        })
    }
}

fn unescape(c: char) -> char {
    match c {
        'n' => '\n',
        't' => '\t',
        'r' => '\r',
        '0' => '\0',
        other => other,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = r##"#![enable(implicit_some)]
// A comment with "quotes" and (parentheses).
Plant(
  name: "p", /* block /* nested */ comment */
  components: [
    Component(
      name: "engine",
      attributes: { "temp": ["low", "nominal"] },
      transitions: [
        (from: "off", to: "on", probability: 0.5),
        (from: "heating", to: "standby", after: Uniform(30.0, 60), guard: "engine.cmd != off"),
      ],
    ),
  ],
  c: 'x',
  raw: r#"a "raw" string"#,
)"##;

    fn text_at(path: &[Step]) -> &'static str {
        let root = outline(TEXT).expect("outline");
        let node = root.find(path).unwrap_or_else(|| panic!("{path:?}"));
        &TEXT[node.span()]
    }

    #[test]
    fn paths_lead_to_the_text_of_each_value() {
        use Step::*;
        let transition = |i| {
            [
                Field("components"),
                Index(0),
                Field("transitions"),
                Index(i),
            ]
        };
        let mut path = transition(0).to_vec();
        path.push(Field("probability"));
        assert_eq!(text_at(&path), "0.5");
        let mut path = transition(1).to_vec();
        path.extend([Field("after"), Index(1)]);
        assert_eq!(text_at(&path), "60");
        let mut path = transition(1).to_vec();
        path.push(Field("guard"));
        assert_eq!(text_at(&path), "engine.cmd != off");
        let attributes = [Field("components"), Index(0), Field("attributes")];
        let mut path = attributes.to_vec();
        path.push(Key("temp"));
        assert_eq!(text_at(&path), "temp");
        let mut path = attributes.to_vec();
        path.extend([Value("temp"), Index(1)]);
        assert_eq!(text_at(&path), "nominal");
        assert_eq!(text_at(&[Field("raw")]), "a \"raw\" string");
    }

    #[test]
    fn text_it_does_not_understand_gives_no_outline() {
        assert_eq!(outline("Plant(name: "), None);
        assert_eq!(outline("[1, 2"), None);
    }
}
