//! RMPL's syntax tree and parser (`grammar/rmpl.pest`, combined with `grammar/constraint.pest`).
//!
//! The parser knows nothing about which programs or variables exist; [`link`](mod@super::link) checks the
//! names. Every node keeps the byte span of its text so that later errors, THCA locations and
//! traces point back at the program. Conditions and goals are delimited by the combined grammar
//! and then parsed into [`Expr`]s by the constraint language's own parser
//! ([`crate::logic::syntax::parse_at`]).
//!
//! A file is parsed one definition at a time: after a syntax error the parser resumes at the next
//! line that starts a definition (`Name(...) ::`), so one run reports an error per broken
//! definition, not only the first.

use pest::Parser;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pair;

use crate::diagnostic::{Diagnostic, Span, did_you_mean};
use crate::logic::Expr;
use crate::logic::syntax::{Name, Operand, TimeUnit, parse_at};

mod grammar {
    #![allow(missing_docs)]
    /// The generated parser for `grammar/rmpl.pest`, which uses the rules of
    /// `grammar/constraint.pest`.
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/constraint.pest"]
    #[grammar = "../grammar/rmpl.pest"]
    pub struct RmplParser;
}
use grammar::{RmplParser, Rule};

/// How deeply blocks and combinators may nest. Deeper programs are refused with a located error
/// rather than risking the stack of the recursive passes that follow parsing.
pub const MAX_NESTING: usize = 100;

/// The RMPL keywords, for suggestions when a word is not one of them.
pub const KEYWORDS: [&str; 12] = [
    "do",
    "watching",
    "maintaining",
    "if",
    "thennext",
    "elsenext",
    "unless",
    "when",
    "whenever",
    "donext",
    "always",
    "next",
];

/// A parsed RMPL file: its program definitions, in order.
#[derive(Debug, Clone, PartialEq)]
pub struct ProgramFile {
    /// `Name(params) :: { ... }`, in the order written.
    pub definitions: Vec<Definition>,
}

impl ProgramFile {
    /// The definition with this name (the first, if it is defined twice).
    pub fn definition(&self, name: &str) -> Option<&Definition> {
        self.definitions.iter().find(|d| d.name.text == name)
    }
}

/// One program: `Name(params) :: { body }`.
#[derive(Debug, Clone, PartialEq)]
pub struct Definition {
    /// The program's name.
    pub name: Name,
    /// Its parameters, replaced by the arguments of each invocation.
    pub params: Vec<Name>,
    /// The body (the block's contents).
    pub body: Node,
    /// The whole definition.
    pub span: Span,
}

/// An RMPL expression with where it is written.
#[derive(Debug, Clone, PartialEq)]
pub struct Node {
    /// Which construct.
    pub kind: NodeKind,
    /// Its text.
    pub span: Span,
}

/// The constructs of RMPL (thesis §5.1.3: primitives and derived combinators).
#[derive(Debug, Clone, PartialEq)]
pub enum NodeKind {
    /// A goal to achieve (`engine = standby`), a clock initialisation (`t1 = 0`), or a
    /// conjunction of both. Which is which is decided when linking.
    Assertion(Expr),
    /// `Name(arguments)`: inlined when linking.
    Invocation {
        /// The invoked program.
        program: Name,
        /// Names or times, one per parameter.
        arguments: Vec<Operand>,
    },
    /// `A, B, ...`: run concurrently, starting together.
    Parallel(Vec<Node>),
    /// `A; B; ...`: each starts the instant after the previous completes.
    Sequence(Vec<Node>),
    /// `A maintaining c`.
    Maintaining {
        /// A.
        body: Box<Node>,
        /// c, which must stay entailed.
        condition: Expr,
    },
    /// `do A watching c`.
    Watching {
        /// A.
        body: Box<Node>,
        /// c, whose entailment preempts A.
        condition: Expr,
    },
    /// `if c thennext A` or `if c thennext A elsenext B`.
    If {
        /// c.
        condition: Expr,
        /// A.
        then: Box<Node>,
        /// B.
        otherwise: Option<Box<Node>>,
    },
    /// `unless c thennext A`.
    Unless {
        /// c.
        condition: Expr,
        /// A.
        then: Box<Node>,
    },
    /// `when c donext A`.
    When {
        /// c.
        condition: Expr,
        /// A.
        body: Box<Node>,
    },
    /// `whenever c donext A`.
    Whenever {
        /// c.
        condition: Expr,
        /// A.
        body: Box<Node>,
    },
    /// `always A`.
    Always(Box<Node>),
    /// `next A`.
    Next(Box<Node>),
}

/// Parses a whole RMPL file, reporting every syntax error it can find (one per definition).
pub fn parse(text: &str) -> Result<ProgramFile, Vec<Diagnostic>> {
    let mut definitions = Vec::new();
    let mut errors = Vec::new();
    let mut pos = 0;
    while !only_comments(&text[pos..]) {
        let rest = &text[pos..];
        match RmplParser::parse(Rule::next_definition, rest) {
            Ok(mut pairs) => {
                let mut builder = Builder {
                    text,
                    offset: pos,
                    errors: &mut errors,
                };
                let Some(definition) = pairs.next().and_then(|p| p.into_inner().next()) else {
                    break;
                };
                pos += definition.as_span().end();
                definitions.push(builder.definition(definition));
            }
            Err(error) => {
                let diagnostic = syntax_error(rest, &error).shifted(pos);
                let resume = resume_after(text, pos, diagnostic.span.start);
                errors.push(diagnostic);
                match resume {
                    Some(next) => pos = next,
                    None => break,
                }
            }
        }
    }
    if definitions.is_empty() && errors.is_empty() {
        errors.push(
            Diagnostic::new("the file defines no program", text.len()..text.len())
                .expected("a program definition `Name() :: { ... }`"),
        );
    }
    if errors.is_empty() {
        Ok(ProgramFile { definitions })
    } else {
        Err(errors)
    }
}

/// Whether `text` holds only whitespace and comments (the grammar's `WHITESPACE` and `COMMENT`).
/// A scan rather than a pest rule: a failed pest parse locates its error by scanning from the
/// end of the input back to the error, which made a file of 10,000 programs quadratic.
fn only_comments(text: &str) -> bool {
    let trivia: &[char] = &[' ', '\t', '\n', '\r'];
    let mut rest = text.trim_start_matches(trivia);
    while !rest.is_empty() {
        rest = if let Some(line) = rest.strip_prefix("//") {
            line.find(['\n', '\r']).map_or("", |end| &line[end..])
        } else if let Some(block) = rest.strip_prefix("/*") {
            match block.find("*/") {
                Some(end) => &block[end + 2..],
                None => return false,
            }
        } else {
            return false;
        }
        .trim_start_matches(trivia);
    }
    true
}

/// Where to resume after a syntax error at `error` in the definition that starts at `start`:
/// the error position itself or the next line start, after `start`, where a definition header
/// (`Name(...) ::`) begins.
fn resume_after(text: &str, start: usize, error: usize) -> Option<usize> {
    let line_starts = text
        .char_indices()
        .filter(|&(_, c)| c == '\n')
        .map(|(i, _)| i + 1);
    std::iter::once(error)
        .chain(line_starts.filter(|&i| i > error))
        .filter(|&candidate| candidate > start && candidate < text.len())
        .find(|&candidate| RmplParser::parse(Rule::definition_header, &text[candidate..]).is_ok())
}

/// Turns a pest error into a located diagnostic that says what was expected in words, and
/// recognises the commonest mistake pest cannot name: a word used as a combinator that is not one.
fn syntax_error(text: &str, error: &pest::error::Error<Rule>) -> Diagnostic {
    let at = match error.location {
        InputLocation::Pos(p) | InputLocation::Span((p, _)) => p,
    };
    let positives: &[Rule] = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => positives,
        ErrorVariant::CustomError { .. } => &[],
    };
    // pest's only custom errors are its call and stack limits, reached by absurd nesting.
    if let ErrorVariant::CustomError { message } = &error.variant {
        return Diagnostic::new(
            format!("program nested too deeply to parse ({message})"),
            at..at,
        )
        .expected(format!(
            "at most {MAX_NESTING} nested blocks and combinators"
        ));
    }
    if let Some(diagnostic) = unknown_combinator(text, at, positives) {
        return diagnostic;
    }
    let word = word_at(text, at);
    let span = at..at + word.map_or(0, str::len);
    let found = match word {
        Some(word) => format!("unexpected `{word}`"),
        None if at >= text.len() => "unexpected end of file".to_string(),
        None => {
            let c = text[at..].chars().next().unwrap_or(' ');
            format!("unexpected `{c}`")
        }
    };
    let mut diagnostic = Diagnostic::new(found, span).expected(describe_expected(positives));
    let expected_keywords = positives.iter().filter_map(|r| keyword_of(*r));
    if let Some(close) = word.and_then(|w| did_you_mean(w, expected_keywords)) {
        diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
    }
    let starts_a_definition = RmplParser::parse(Rule::definition_header, &text[at..]).is_ok();
    if positives.contains(&Rule::rbrace) && starts_a_definition {
        diagnostic = diagnostic.note("a `}` closing the program before this one may be missing");
    }
    diagnostic
}

/// `wen (x = on) donext ...`: an identifier followed by `(` or `{` where a unit was expected,
/// which pest reports as a missing comparison after the name `wen`.
fn unknown_combinator(text: &str, at: usize, positives: &[Rule]) -> Option<Diagnostic> {
    if !positives.contains(&Rule::cmp_op) {
        return None;
    }
    let before = text[..at].trim_end();
    let word_length = before
        .bytes()
        .rev()
        .take_while(|&b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'.')
        .count();
    let start = before.len() - word_length;
    let word = &before[start..];
    let follows = text[at..].trim_start().chars().next();
    let looks_like_a_combinator = !word.is_empty()
        && word.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && matches!(follows, Some('(' | '{'));
    if !looks_like_a_combinator {
        return None;
    }
    let mut diagnostic = Diagnostic::new(
        format!("unknown combinator `{word}`"),
        start..start + word.len(),
    )
    .expected(
        "a combinator (do, if, unless, when, whenever, always, next), an assertion `x = v` or an \
         invocation `Name(...)`",
    );
    if let Some(close) = did_you_mean(word, KEYWORDS) {
        diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
    } else if follows == Some('(') {
        diagnostic = diagnostic.note(format!(
            "to invoke a program, write `{word}(` without a space before the parenthesis"
        ));
    }
    Some(diagnostic)
}

/// The identifier-like word starting at `at`, if any.
fn word_at(text: &str, at: usize) -> Option<&str> {
    let rest = text.get(at..)?;
    let end = rest
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.'))
        .unwrap_or(rest.len());
    (end > 0).then(|| &rest[..end])
}

/// Turns the grammar rules pest could have accepted into words, deduplicated, in a stable order.
fn describe_expected(rules: &[Rule]) -> String {
    let mut words: Vec<&str> = rules.iter().filter_map(|r| rule_words(*r)).collect();
    words.sort_unstable();
    words.dedup();
    match words.as_slice() {
        [] => "a well-formed program".to_string(),
        [one] => format!("expected {one}"),
        [rest @ .., last] => format!("expected {} or {last}", rest.join(", ")),
    }
}

fn keyword_of(rule: Rule) -> Option<&'static str> {
    Some(match rule {
        Rule::kw_do => "do",
        Rule::kw_watching => "watching",
        Rule::kw_maintaining => "maintaining",
        Rule::kw_if => "if",
        Rule::kw_thennext => "thennext",
        Rule::kw_elsenext => "elsenext",
        Rule::kw_unless => "unless",
        Rule::kw_when => "when",
        Rule::kw_whenever => "whenever",
        Rule::kw_donext => "donext",
        Rule::kw_always => "always",
        Rule::kw_next => "next",
        _ => return None,
    })
}

fn rule_words(rule: Rule) -> Option<&'static str> {
    if let Some(keyword) = keyword_of(rule) {
        return Some(match keyword {
            "do" => "`do`",
            "watching" => "`watching`",
            "maintaining" => "`maintaining`",
            "if" => "`if`",
            "thennext" => "`thennext`",
            "elsenext" => "`elsenext`",
            "unless" => "`unless`",
            "when" => "`when`",
            "whenever" => "`whenever`",
            "donext" => "`donext`",
            "always" => "`always`",
            _ => "`next`",
        });
    }
    Some(match rule {
        Rule::EOI => "end of file",
        Rule::lparen => "`(`",
        Rule::rparen => "`)`",
        Rule::lbrace => "`{`",
        Rule::rbrace => "`}`",
        Rule::comma => "`,`",
        Rule::semicolon => "`;`",
        Rule::define => "`::`",
        Rule::definition | Rule::program_name => "a program definition `Name() :: { ... }`",
        Rule::params | Rule::param => "a parameter name",
        Rule::block => "a block `{ ... }`",
        Rule::parallel
        | Rule::sequence
        | Rule::maintained
        | Rule::group
        | Rule::do_watching
        | Rule::if_then
        | Rule::unless_then
        | Rule::when_do
        | Rule::whenever_do
        | Rule::always
        | Rule::next
        | Rule::invocation
        | Rule::invocation_name => "an RMPL expression",
        Rule::assertion => "an assertion",
        Rule::condition => "a condition",
        Rule::argument => "an argument (a name or a time)",
        // The constraint grammar's own rules.
        _ => return crate::logic::syntax::describe_rule(&format!("{rule:?}")),
    })
}

/// Builds the syntax tree from the pairs of one definition parsed at `offset` of `text`.
struct Builder<'t, 'e> {
    text: &'t str,
    offset: usize,
    errors: &'e mut Vec<Diagnostic>,
}

// The builders below walk a tree the grammar has already validated, so the shape of each rule's
// children is known; `child` documents that.
fn child<'i>(pairs: &mut impl Iterator<Item = Pair<'i, Rule>>) -> Pair<'i, Rule> {
    pairs
        .next()
        .unwrap_or_else(|| unreachable!("the RMPL grammar fixes the children of every rule"))
}

/// A pair's children without punctuation.
fn children<'i>(pair: Pair<'i, Rule>) -> impl Iterator<Item = Pair<'i, Rule>> {
    pair.into_inner().filter(|p| {
        !matches!(
            p.as_rule(),
            Rule::lparen
                | Rule::rparen
                | Rule::lbrace
                | Rule::rbrace
                | Rule::comma
                | Rule::semicolon
                | Rule::define
        )
    })
}

impl Builder<'_, '_> {
    /// The pair's text, without the whitespace pest lets a rule swallow after its last token.
    fn span(&self, pair: &Pair<'_, Rule>) -> Span {
        let start = pair.as_span().start() + self.offset;
        start..start + pair.as_str().trim_end().len()
    }

    fn name(&self, pair: &Pair<'_, Rule>) -> Name {
        Name {
            text: pair.as_str().to_string(),
            span: self.span(pair),
        }
    }

    fn definition(&mut self, pair: Pair<'_, Rule>) -> Definition {
        let span = self.span(&pair);
        let mut inner = children(pair);
        let name = self.name(&child(&mut inner));
        let mut params = Vec::new();
        let mut next = child(&mut inner);
        if next.as_rule() == Rule::params {
            params = children(next).map(|p| self.name(&p)).collect();
            next = child(&mut inner);
        }
        let body = self.node(next, 0);
        Definition {
            name,
            params,
            body,
            span,
        }
    }

    /// A formula delimited by the combined grammar, parsed by the constraint language's parser.
    fn formula(&mut self, pair: &Pair<'_, Rule>) -> Expr {
        let span = self.span(pair);
        match parse_at(&self.text[span.clone()], span.start) {
            Ok(expr) => expr,
            Err(diagnostic) => {
                // Unreachable in practice (both parsers use the same rules); kept as an error
                // rather than a panic.
                self.errors.push(diagnostic);
                Expr {
                    kind: crate::logic::ExprKind::Constant(true),
                    span,
                }
            }
        }
    }

    /// Records that the construct at `span` nests deeper than [`MAX_NESTING`]; an empty node
    /// stands in for it.
    fn too_deep(&mut self, span: Span) -> Node {
        self.errors.push(
            Diagnostic::new(
                "blocks and combinators are nested too deeply",
                span.start..span.start,
            )
            .expected(format!(
                "at most {MAX_NESTING} nested blocks and combinators"
            )),
        );
        Node {
            kind: NodeKind::Parallel(Vec::new()),
            span,
        }
    }

    fn node(&mut self, pair: Pair<'_, Rule>, depth: usize) -> Node {
        let span = self.span(&pair);
        if depth > MAX_NESTING {
            return self.too_deep(span);
        }
        let rule = pair.as_rule();
        let mut inner = children(pair);
        // Lists and postfix chains are not levels of their own: each sits directly in a block,
        // a group or a combinator, which are.
        if matches!(rule, Rule::block | Rule::group) {
            return self.node(child(&mut inner), depth + 1);
        }
        let kind = match rule {
            Rule::parallel | Rule::sequence => {
                let mut parts: Vec<Node> = inner.map(|p| self.node(p, depth)).collect();
                if parts.len() == 1 {
                    return parts.remove(0);
                }
                if rule == Rule::parallel {
                    NodeKind::Parallel(parts)
                } else {
                    NodeKind::Sequence(parts)
                }
            }
            Rule::maintained => {
                // `A maintaining c maintaining d` is `(A maintaining c) maintaining d`: each
                // link is a level (a 10,000-long chain overflowed the passes' stacks).
                let rest: Vec<Pair<'_, Rule>> = inner.collect();
                let first = &rest[0];
                let links = (rest.len() - 1) / 2;
                if depth + links > MAX_NESTING {
                    let keyword = &rest[2 * MAX_NESTING.saturating_sub(depth) + 1];
                    return self.too_deep(self.span(keyword));
                }
                let mut node = self.node(first.clone(), depth + links);
                let mut inner = rest.into_iter().skip(1);
                while let (Some(_keyword), Some(condition)) = (inner.next(), inner.next()) {
                    let condition = self.formula(&condition);
                    node = Node {
                        span: node.span.start..condition.span.end,
                        kind: NodeKind::Maintaining {
                            body: Box::new(node),
                            condition,
                        },
                    };
                }
                return node;
            }
            Rule::do_watching => {
                let _do = child(&mut inner);
                let body = Box::new(self.node(child(&mut inner), depth + 1));
                let _watching = child(&mut inner);
                let condition = self.formula(&child(&mut inner));
                NodeKind::Watching { body, condition }
            }
            Rule::if_then => {
                let _if = child(&mut inner);
                let condition = self.formula(&child(&mut inner));
                let _thennext = child(&mut inner);
                let then = Box::new(self.node(child(&mut inner), depth + 1));
                let otherwise = inner
                    .nth(1)
                    .map(|else_body| Box::new(self.node(else_body, depth + 1)));
                NodeKind::If {
                    condition,
                    then,
                    otherwise,
                }
            }
            Rule::unless_then | Rule::when_do | Rule::whenever_do => {
                let _keyword = child(&mut inner);
                let condition = self.formula(&child(&mut inner));
                let _next_keyword = child(&mut inner);
                let body = Box::new(self.node(child(&mut inner), depth + 1));
                match rule {
                    Rule::unless_then => NodeKind::Unless {
                        condition,
                        then: body,
                    },
                    Rule::when_do => NodeKind::When { condition, body },
                    _ => NodeKind::Whenever { condition, body },
                }
            }
            Rule::always | Rule::next => {
                let _keyword = child(&mut inner);
                let body = Box::new(self.node(child(&mut inner), depth + 1));
                if rule == Rule::always {
                    NodeKind::Always(body)
                } else {
                    NodeKind::Next(body)
                }
            }
            Rule::invocation => {
                let program = self.name(&child(&mut inner));
                let arguments = inner.map(|argument| self.argument(argument)).collect();
                NodeKind::Invocation { program, arguments }
            }
            Rule::assertion => {
                // The formula's own span, without the parentheses around it.
                let expr = self.formula(&child(&mut inner));
                return Node {
                    span: expr.span.clone(),
                    kind: NodeKind::Assertion(expr),
                };
            }
            other => unreachable!("rule {other:?} is not an RMPL expression"),
        };
        Node { kind, span }
    }

    fn argument(&mut self, pair: Pair<'_, Rule>) -> Operand {
        let value = child(&mut children(pair));
        let span = self.span(&value);
        if value.as_rule() == Rule::name {
            return Operand::Name(self.name(&value));
        }
        let mut parts = value.into_inner();
        let number = child(&mut parts).as_str().parse().unwrap_or(f64::NAN);
        let unit = parts.next().and_then(|u| TimeUnit::from_symbol(u.as_str()));
        Operand::Quantity {
            value: number,
            unit,
            span,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logic::ExprKind;

    fn parse_ok(text: &str) -> ProgramFile {
        parse(text).unwrap_or_else(|e| panic!("{text}: {e:?}"))
    }

    fn body(text: &str) -> NodeKind {
        parse_ok(text).definitions.remove(0).body.kind
    }

    fn render(text: &str) -> String {
        let diagnostics = parse(text).unwrap_err();
        crate::diagnostic::Source::new("p.rmpl", text).render(&diagnostics)
    }

    #[test]
    fn semicolon_binds_tighter_than_comma() {
        // DESIGN.md §5.1: `a; b, c` is `(a; b), c`.
        let NodeKind::Parallel(parts) = body("P() :: { x = a; y = b, z = c }") else {
            panic!("parallel at the top");
        };
        assert!(matches!(parts[0].kind, NodeKind::Sequence(_)));
        assert!(matches!(parts[1].kind, NodeKind::Assertion(_)));
    }

    #[test]
    fn groups_and_blocks_override_precedence() {
        let NodeKind::Sequence(parts) = body("P() :: { x = a; (y = b, z = c) }") else {
            panic!("sequence at the top");
        };
        assert!(matches!(parts[1].kind, NodeKind::Parallel(_)));
        let NodeKind::Sequence(parts) = body("P() :: { {x = a, y = b}; z = c; }") else {
            panic!("sequence at the top");
        };
        assert!(matches!(parts[0].kind, NodeKind::Parallel(_)));
    }

    #[test]
    fn every_combinator_parses() {
        // Thesis §5.1.3: the primitives and the derived combinators.
        let text = "P() :: {
            x = a maintaining y = b,
            do x = a watching y = b,
            if y = b thennext x = a,
            if y = b thennext x = a elsenext x = c,
            unless y = b thennext x = a,
            when y = b donext x = a,
            whenever y = b donext x = a,
            always x = a,
            next x = a,
            Q(v, 2.5 min)
        }";
        let NodeKind::Parallel(parts) = body(text) else {
            panic!()
        };
        let kinds: Vec<&str> = parts
            .iter()
            .map(|p| match &p.kind {
                NodeKind::Maintaining { .. } => "maintaining",
                NodeKind::Watching { .. } => "watching",
                NodeKind::If {
                    otherwise: None, ..
                } => "if",
                NodeKind::If { .. } => "if-else",
                NodeKind::Unless { .. } => "unless",
                NodeKind::When { .. } => "when",
                NodeKind::Whenever { .. } => "whenever",
                NodeKind::Always(_) => "always",
                NodeKind::Next(_) => "next",
                NodeKind::Invocation { .. } => "invocation",
                _ => "other",
            })
            .collect();
        assert_eq!(
            kinds,
            [
                "maintaining",
                "watching",
                "if",
                "if-else",
                "unless",
                "when",
                "whenever",
                "always",
                "next",
                "invocation"
            ]
        );
        let NodeKind::Invocation { arguments, .. } = &parts[9].kind else {
            panic!()
        };
        assert!(matches!(
            arguments[1],
            Operand::Quantity { value, unit: Some(TimeUnit::Minutes), .. } if value == 2.5
        ));
    }

    #[test]
    fn conditions_are_formulas_with_file_positions() {
        let text = "P() :: { when (t1 ≥ 270.0 min) donext nav = inertial }";
        let NodeKind::When { condition, body } = body(text) else {
            panic!()
        };
        assert_eq!(&text[condition.span.clone()], "t1 ≥ 270.0 min");
        assert!(matches!(condition.kind, ExprKind::Compare { .. }));
        assert_eq!(&text[body.span], "nav = inertial");
    }

    #[test]
    fn keywords_need_a_word_boundary() {
        // `nextval` is a variable, not `next val`; `donext` needs its own word.
        assert!(matches!(
            body("P() :: { nextval = a }"),
            NodeKind::Assertion(_)
        ));
        assert!(parse("P() :: { when x = a donextx = b }").is_err());
    }

    #[test]
    fn comments_are_whitespace() {
        parse_ok("// header\nP() :: { /* a */ x = a // b\n ; y = b }\n// trailer\n");
    }

    #[test]
    fn a_broken_definition_does_not_hide_the_next() {
        let text = "A() :: { x = a;; }\nB() :: { y = }\nC() :: { z = c }\n";
        let errors = parse(text).unwrap_err();
        assert_eq!(errors.len(), 2, "{errors:?}");
        assert!(errors[0].span.start < 18 && errors[1].span.start > 18);
    }

    #[test]
    fn unknown_combinators_are_named() {
        let text = render("P() :: { wen (x = a) donext y = b }");
        assert!(text.contains("unknown combinator `wen`"), "{text}");
        assert!(text.contains("did you mean `when`?"), "{text}");
    }

    #[test]
    fn an_invocation_with_a_space_is_explained() {
        let text = render("P() :: { DeployLGA () }\nDeployLGA() :: { x = a }");
        assert!(text.contains("unknown combinator `DeployLGA`"), "{text}");
        assert!(
            text.contains("write `DeployLGA(` without a space"),
            "{text}"
        );
    }

    #[test]
    fn a_word_after_a_multibyte_character_is_cut_at_a_character_boundary() {
        // Found by the property tests: `∨` is three bytes.
        assert!(parse("P() :: { (x = a ∨G (y = b)) }").is_err());
        assert!(render("P() :: { x = a; ∨wen (x = a) donext y = b }").contains("error"));
    }

    #[test]
    fn misspelt_keywords_get_a_suggestion() {
        let text = render("P() :: { when (x = a) dnext y = b }");
        assert!(text.contains("unexpected `dnext`"), "{text}");
        assert!(text.contains("did you mean `donext`?"), "{text}");
    }

    #[test]
    fn nesting_is_bounded_not_a_stack_overflow() {
        let deep = format!(
            "P() :: {}x = a{}",
            "{".repeat(MAX_NESTING + 5),
            "}".repeat(MAX_NESTING + 5)
        );
        let errors = parse(&deep).unwrap_err();
        assert!(
            errors[0].message.contains("nested too deeply"),
            "{errors:?}"
        );
        let fine = format!("P() :: {}x = a{}", "{".repeat(50), "}".repeat(50));
        parse_ok(&fine);
    }

    #[test]
    fn an_empty_file_defines_nothing() {
        assert!(render("// nothing\n").contains("the file defines no program"));
    }
}
