//! The constraint language's syntax tree and parser (`grammar/constraint.pest`).
//!
//! Parsing knows nothing about which names exist; [`super::resolve`] turns an [`Expr`] into a
//! [`super::Formula`] against a [`super::VarTable`]. Every node keeps its byte span so errors found
//! later still point at the text.

use pest::Parser;
use pest::error::{ErrorVariant, InputLocation};
use pest::iterators::Pair;

use crate::diagnostic::{Diagnostic, Span};

mod grammar {
    #![allow(missing_docs)]
    /// The generated parser for `grammar/constraint.pest`.
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/constraint.pest"]
    pub struct ConstraintParser;
}
use grammar::{ConstraintParser, Rule};

/// A name as written, with where it was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Name {
    /// The text (`engine.temp`).
    pub text: String,
    /// Where it is.
    pub span: Span,
}

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    /// `=`
    Eq,
    /// `!=`, `≠`
    Ne,
    /// `<`
    Lt,
    /// `<=`, `≤`
    Le,
    /// `>`
    Gt,
    /// `>=`, `≥`
    Ge,
}

impl CmpOp {
    /// Applies an ordering comparison to two numbers (`Eq`/`Ne` compare exactly).
    pub fn holds(self, left: f64, right: f64) -> bool {
        match self {
            CmpOp::Eq => left == right,
            CmpOp::Ne => left != right,
            CmpOp::Lt => left < right,
            CmpOp::Le => left <= right,
            CmpOp::Gt => left > right,
            CmpOp::Ge => left >= right,
        }
    }

    /// The ASCII spelling.
    pub fn symbol(self) -> &'static str {
        match self {
            CmpOp::Eq => "=",
            CmpOp::Ne => "!=",
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
        }
    }

    /// True for `<`, `<=`, `>`, `>=`.
    pub fn is_ordering(self) -> bool {
        !matches!(self, CmpOp::Eq | CmpOp::Ne)
    }
}

/// A time unit on a clock bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeUnit {
    /// `ms`
    Milliseconds,
    /// `s`, `sec`, or no unit
    Seconds,
    /// `min`, `mins`
    Minutes,
    /// `h`
    Hours,
}

impl TimeUnit {
    /// The unit a symbol of the grammar's `unit` rule names (`ms`, `s`, `sec`, `min`, `mins`,
    /// `h`); RMPL reads the units of invocation arguments with it.
    pub fn from_symbol(symbol: &str) -> Option<TimeUnit> {
        Some(match symbol {
            "ms" => TimeUnit::Milliseconds,
            "s" | "sec" => TimeUnit::Seconds,
            "min" | "mins" => TimeUnit::Minutes,
            "h" => TimeUnit::Hours,
            _ => return None,
        })
    }

    /// How many seconds one unit is.
    pub fn seconds(self) -> f64 {
        match self {
            TimeUnit::Milliseconds => 0.001,
            TimeUnit::Seconds => 1.0,
            TimeUnit::Minutes => 60.0,
            TimeUnit::Hours => 3600.0,
        }
    }
}

/// The right-hand side of a comparison.
#[derive(Debug, Clone, PartialEq)]
pub enum Operand {
    /// A value or a variable name.
    Name(Name),
    /// A number with an optional unit.
    Quantity {
        /// The number as written.
        value: f64,
        /// The unit, if one was written.
        unit: Option<TimeUnit>,
        /// Where it is.
        span: Span,
    },
}

/// A parsed, unresolved formula.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What kind of formula.
    pub kind: ExprKind,
    /// Where it is.
    pub span: Span,
}

/// The forms of [`Expr`].
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// `true` or `false`.
    Constant(bool),
    /// `left op right`.
    Compare {
        /// The variable or clock compared.
        left: Name,
        /// The operator.
        op: CmpOp,
        /// A value, another variable, or a time.
        right: Operand,
    },
    /// `P(variable = value) op probability`.
    Confidence {
        /// The variable.
        variable: Name,
        /// The value.
        value: Name,
        /// The operator.
        op: CmpOp,
        /// The threshold.
        probability: f64,
        /// Where the threshold is.
        probability_span: Span,
    },
    /// `not e`.
    Not(Box<Expr>),
    /// `a and b and ...` (two or more).
    And(Vec<Expr>),
    /// `a or b or ...` (two or more).
    Or(Vec<Expr>),
    /// `a => b`.
    Implies(Box<Expr>, Box<Expr>),
}

/// Parses a whole text as one formula.
pub fn parse(text: &str) -> Result<Expr, Diagnostic> {
    parse_at(text, 0)
}

/// How deeply a formula may nest: parentheses inside parentheses, or negations in a row. Deeper
/// formulas are refused with a located error instead of exhausting the stack of the recursive
/// parser and of the passes over the tree (resolution, grounding, evaluation).
pub const MAX_NESTING: usize = 100;

/// How many operators (`not`, `and`, `or`, `=>`) a formula may nest, one inside the other: the
/// depth of its tree, which every pass over a formula (resolution, grounding, evaluation, the
/// Tseitin encoding, `Drop`) walks recursively. A chain of `=>` nests one level per arrow, so this
/// bounds chains that [`MAX_NESTING`]'s text scan cannot see (a 10,000-long chain
/// overflowed the stack).
pub const MAX_DEPTH: usize = 2 * MAX_NESTING;

/// Parses a fragment that sits at byte `offset` of a larger file: spans in the result, and in the
/// error, are positions in that file. The RMPL parser uses this for the guards and goals it finds.
pub fn parse_at(fragment: &str, offset: usize) -> Result<Expr, Diagnostic> {
    if let Some(at) = too_deep(fragment) {
        return Err(nested_too_deeply(at + offset));
    }
    let mut pairs = ConstraintParser::parse(Rule::formula, fragment)
        .map_err(|e| syntax_error(&e).shifted(offset))?;
    let formula = pairs.next().and_then(|p| p.into_inner().next());
    match formula {
        Some(expr) => build_expr(expr, offset, 0),
        None => Err(Diagnostic::new("empty formula", offset..offset).expected("a formula")),
    }
}

/// The error for a formula that nests deeper than the limits, at byte `at`.
fn nested_too_deeply(at: usize) -> Diagnostic {
    Diagnostic::new("formula nested too deeply", at..at).expected(format!(
        "at most {MAX_NESTING} nested parentheses, {MAX_NESTING} negations in a row and \
         {MAX_DEPTH} nested operators"
    ))
}

/// Where a fragment first nests deeper than [`MAX_NESTING`], if it does. A cheap scan of the text:
/// it may count a parenthesis or `not` inside a comment, which only matters for absurd comments.
fn too_deep(fragment: &str) -> Option<usize> {
    let bytes = fragment.as_bytes();
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'-';
    let (mut depth, mut negations, mut skip_to) = (0usize, 0usize, 0usize);
    for (i, c) in fragment.char_indices() {
        if i < skip_to {
            continue;
        }
        let not_word = fragment[i..].starts_with("not")
            && (i == 0 || !is_word(bytes[i - 1]))
            && !bytes.get(i + 3).is_some_and(|&b| is_word(b));
        match c {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            '¬' => negations += 1,
            '!' if bytes.get(i + 1) != Some(&b'=') => negations += 1,
            _ if not_word => {
                negations += 1;
                skip_to = i + 3;
            }
            c if c.is_whitespace() => {}
            _ => negations = 0,
        }
        if depth > MAX_NESTING || negations > MAX_NESTING {
            return Some(i);
        }
    }
    None
}

fn syntax_error(error: &pest::error::Error<Rule>) -> Diagnostic {
    let span = match error.location {
        InputLocation::Pos(p) => p..p,
        InputLocation::Span((a, b)) => a..b,
    };
    let expected = match &error.variant {
        ErrorVariant::ParsingError { positives, .. } => describe_expected(positives),
        ErrorVariant::CustomError { message } => message.clone(),
    };
    Diagnostic::new("syntax error in formula", span).expected(expected)
}

/// Turns the grammar rules pest could have accepted into words.
fn describe_expected(rules: &[Rule]) -> String {
    let mut words: Vec<&str> = rules.iter().filter_map(|r| rule_words(*r)).collect();
    words.dedup();
    match words.as_slice() {
        [] => "end of formula".to_string(),
        [one] => format!("expected {one}"),
        [rest @ .., last] => format!("expected {} or {last}", rest.join(", ")),
    }
}

fn rule_words(rule: Rule) -> Option<&'static str> {
    match rule {
        Rule::EOI => Some("end of formula"),
        _ => describe_rule(&format!("{rule:?}")),
    }
}

/// What a rule of `grammar/constraint.pest`, named as pest names it, stands for in an error
/// message ("expected a value or a number"). Grammars that include the constraint rules (RMPL)
/// describe those rules with this too; pest gives each grammar its own `Rule` type, so the
/// rules are matched by name.
pub fn describe_rule(name: &str) -> Option<&'static str> {
    Some(match name {
        "expr" | "disjunction" | "conjunction" | "negation" => "a formula",
        "comparison" | "name" | "ident" => "a name",
        "constant" => "`true`/`false`",
        "confidence" => "`P(x = v)`",
        "not_op" => "`not`",
        "and_op" => "`and`",
        "or_op" => "`or`",
        "implies_op" => "`=>`",
        "cmp_op" | "eq_op" => "a comparison (`=`, `!=`, `>=`, ...)",
        "operand" | "quantity" => "a value or a number",
        "number" => "a number",
        "unit" => "a time unit",
        _ => return None,
    })
}

fn span_of(pair: &Pair<'_, Rule>, offset: usize) -> Span {
    let s = pair.as_span();
    s.start() + offset..s.end() + offset
}

fn build_name(pair: Pair<'_, Rule>, offset: usize) -> Name {
    Name {
        span: span_of(&pair, offset),
        text: pair.as_str().to_string(),
    }
}

// The builders below walk a tree the grammar has already validated, so the shape of each rule's
// children is known; `next_child` documents that and degrades to a panic-free default otherwise.
fn next_child<'i>(pairs: &mut pest::iterators::Pairs<'i, Rule>) -> Pair<'i, Rule> {
    pairs
        .next()
        .unwrap_or_else(|| unreachable!("the constraint grammar fixes the children of every rule"))
}

/// Builds the tree of a formula whose root sits under `depth` operators; refuses one that would
/// nest deeper than [`MAX_DEPTH`] before building it, so no deep tree is ever made (or dropped).
fn build_expr(pair: Pair<'_, Rule>, offset: usize, depth: usize) -> Result<Expr, Diagnostic> {
    let span = span_of(&pair, offset);
    Ok(match pair.as_rule() {
        Rule::expr => {
            // `a => b => c` is `a => (b => c)`: the i-th arrow sits under i others, and so does
            // its left operand; the last operand under as many as there are arrows.
            let parts: Vec<Pair<'_, Rule>> = pair
                .into_inner()
                .filter(|p| p.as_rule() != Rule::implies_op)
                .collect();
            let arrows = parts.len() - 1;
            if arrows > MAX_DEPTH.saturating_sub(depth) {
                let first_too_deep = &parts[MAX_DEPTH.saturating_sub(depth)];
                return Err(nested_too_deeply(first_too_deep.as_span().start() + offset));
            }
            let mut built = Vec::with_capacity(parts.len());
            for (i, part) in parts.into_iter().enumerate() {
                built.push(build_expr(part, offset, depth + (i + 1).min(arrows))?);
            }
            let Some(mut expr) = built.pop() else {
                unreachable!("the constraint grammar gives `expr` at least one operand")
            };
            for left in built.into_iter().rev() {
                expr = Expr {
                    span: left.span.start..span.end,
                    kind: ExprKind::Implies(Box::new(left), Box::new(expr)),
                };
            }
            expr
        }
        Rule::disjunction | Rule::conjunction => {
            let is_or = pair.as_rule() == Rule::disjunction;
            let pairs: Vec<Pair<'_, Rule>> = pair
                .into_inner()
                .filter(|p| !matches!(p.as_rule(), Rule::or_op | Rule::and_op))
                .collect();
            if pairs.len() == 1 {
                return build_expr(pairs[0].clone(), offset, depth);
            }
            if depth >= MAX_DEPTH {
                return Err(nested_too_deeply(span.start));
            }
            let parts = pairs
                .into_iter()
                .map(|p| build_expr(p, offset, depth + 1))
                .collect::<Result<Vec<Expr>, Diagnostic>>()?;
            let kind = if is_or {
                ExprKind::Or(parts)
            } else {
                ExprKind::And(parts)
            };
            Expr { kind, span }
        }
        Rule::negation => {
            let children: Vec<Pair<'_, Rule>> = pair.into_inner().collect();
            let (nots, primary) = children.split_at(children.len() - 1);
            // The i-th `not` sits under i others.
            if let Some(first_too_deep) = nots.get(MAX_DEPTH.saturating_sub(depth)) {
                return Err(nested_too_deeply(first_too_deep.as_span().start() + offset));
            }
            let mut expr = build_expr(primary[0].clone(), offset, depth + nots.len())?;
            for not in nots.iter().rev() {
                let start = not.as_span().start() + offset;
                expr = Expr {
                    span: start..expr.span.end,
                    kind: ExprKind::Not(Box::new(expr)),
                };
            }
            expr
        }
        Rule::constant => Expr {
            kind: ExprKind::Constant(pair.as_str().eq_ignore_ascii_case("true")),
            span,
        },
        Rule::comparison => {
            let mut inner = pair.into_inner();
            let left = build_name(next_child(&mut inner), offset);
            let op = build_op(next_child(&mut inner).as_str());
            let right = build_operand(next_child(&mut inner), offset);
            Expr {
                kind: ExprKind::Compare { left, op, right },
                span,
            }
        }
        Rule::confidence => {
            let mut inner = pair.into_inner();
            let variable = build_name(next_child(&mut inner), offset);
            let _eq = next_child(&mut inner);
            let value = build_name(next_child(&mut inner), offset);
            let op = build_op(next_child(&mut inner).as_str());
            let number = next_child(&mut inner);
            Expr {
                kind: ExprKind::Confidence {
                    variable,
                    value,
                    op,
                    probability: parse_number(number.as_str()),
                    probability_span: span_of(&number, offset),
                },
                span,
            }
        }
        rule => unreachable!("rule {rule:?} is not a formula"),
    })
}

fn build_operand(pair: Pair<'_, Rule>, offset: usize) -> Operand {
    let inner = next_child(&mut pair.into_inner());
    match inner.as_rule() {
        Rule::name => Operand::Name(build_name(inner, offset)),
        _ => {
            let span = span_of(&inner, offset);
            let mut parts = inner.into_inner();
            let value = parse_number(next_child(&mut parts).as_str());
            let unit = parts
                .next()
                .map(|u| TimeUnit::from_symbol(u.as_str()).unwrap_or(TimeUnit::Seconds));
            Operand::Quantity { value, unit, span }
        }
    }
}

fn parse_number(text: &str) -> f64 {
    // The grammar only admits decimal numbers, which always parse.
    text.parse().unwrap_or(f64::NAN)
}

fn build_op(text: &str) -> CmpOp {
    match text {
        "=" => CmpOp::Eq,
        "!=" | "≠" => CmpOp::Ne,
        "<" => CmpOp::Lt,
        "<=" | "≤" => CmpOp::Le,
        ">" => CmpOp::Gt,
        _ => CmpOp::Ge,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kind(text: &str) -> ExprKind {
        parse(text).unwrap_or_else(|e| panic!("{text}: {e:?}")).kind
    }

    #[test]
    fn precedence_is_not_and_or_implies() {
        // a or b and not c => d  ==  (a or (b and (not c))) => d
        let ExprKind::Implies(left, _) = kind("a = x or b = x and not c = x => d = x") else {
            panic!("implication at the top");
        };
        let ExprKind::Or(parts) = left.kind else {
            panic!("or below it");
        };
        assert!(matches!(parts[1].kind, ExprKind::And(_)));
    }

    #[test]
    fn ascii_and_unicode_spellings_parse_alike() {
        let strip = |e: Expr| format!("{:?}", e.kind).replace(char::is_numeric, "");
        let ascii = parse("!(a = on) & b != off | c >= 3 => d <= 4").unwrap();
        let unicode = parse("¬(a = on) ∧ b ≠ off ∨ c ≥ 3 ⇒ d ≤ 4").unwrap();
        assert_eq!(strip(ascii), strip(unicode));
        let words = parse("not (a = on) and b != off or c >= 3 => d <= 4").unwrap();
        let ascii = parse("!(a = on) && b != off || c >= 3 => d <= 4").unwrap();
        assert_eq!(strip(words), strip(ascii));
    }

    #[test]
    fn clock_bounds_take_units() {
        let ExprKind::Compare { right, .. } = kind("t1 >= 270 min") else {
            panic!()
        };
        assert!(matches!(
            right,
            Operand::Quantity { value, unit: Some(TimeUnit::Minutes), .. } if value == 270.0
        ));
        for (text, unit) in [
            ("t >= 5ms", TimeUnit::Milliseconds),
            ("t >= 5 s", TimeUnit::Seconds),
            ("t >= 5 sec", TimeUnit::Seconds),
            ("t >= 5 mins", TimeUnit::Minutes),
            ("t >= 5 h", TimeUnit::Hours),
        ] {
            let ExprKind::Compare {
                right: Operand::Quantity { unit: u, .. },
                ..
            } = kind(text)
            else {
                panic!("{text}")
            };
            assert_eq!(u, Some(unit), "{text}");
        }
    }

    #[test]
    fn values_may_contain_dashes_and_names_dots() {
        let ExprKind::Compare { left, right, .. } = kind("att = entry-orient") else {
            panic!()
        };
        assert_eq!(left.text, "att");
        assert!(matches!(right, Operand::Name(n) if n.text == "entry-orient"));
        let ExprKind::Compare { left, .. } = kind("engine.temp = nominal") else {
            panic!()
        };
        assert_eq!(left.text, "engine.temp");
    }

    #[test]
    fn confidence_atoms_parse() {
        let ExprKind::Confidence {
            variable,
            value,
            op,
            probability,
            ..
        } = kind("P(lander = separated) >= 0.95")
        else {
            panic!()
        };
        assert_eq!(
            (variable.text.as_str(), value.text.as_str()),
            ("lander", "separated")
        );
        assert_eq!((op, probability), (CmpOp::Ge, 0.95));
    }

    #[test]
    fn keywords_are_not_names_but_prefixes_are() {
        assert!(parse("and = x").is_err());
        assert!(matches!(kind("android = x"), ExprKind::Compare { .. }));
        assert!(matches!(kind("TRUE"), ExprKind::Constant(true)));
        assert!(matches!(kind("x = notified"), ExprKind::Compare { .. }));
    }

    #[test]
    fn spans_are_shifted_by_the_fragment_offset() {
        let expr = parse_at("x = on", 10).unwrap();
        assert_eq!(expr.span, 10..16);
        let error = parse_at("x = ", 10).unwrap_err();
        assert_eq!(error.span.start, 14);
        assert!(error.expected.contains("a value or a number"), "{error:?}");
    }

    #[test]
    fn deep_nesting_is_refused_not_a_stack_overflow() {
        let deep = format!("{}x = on{}", "(".repeat(5000), ")".repeat(5000));
        let error = parse(&deep).unwrap_err();
        assert!(error.message.contains("nested too deeply"), "{error:?}");
        assert_eq!(error.span.start, MAX_NESTING);
        assert!(parse(&format!("{}x = on", "not ".repeat(5000))).is_err());
        assert!(parse(&format!("{}x = on", "¬".repeat(MAX_NESTING + 1))).is_err());
        let fine = format!(
            "{}x = on{}",
            "(".repeat(MAX_NESTING),
            ")".repeat(MAX_NESTING)
        );
        assert!(parse(&fine).is_ok());
        // Many negations that are not nested, and words containing "not", are fine.
        let flat = vec!["not x = on"; 2 * MAX_NESTING].join(" and ");
        assert!(parse(&flat).is_ok());
        assert!(parse(&format!("x = {}", "notified-".repeat(200) + "x")).is_ok());
    }

    #[test]
    fn comments_and_newlines_are_whitespace() {
        assert!(parse("x = on // the x\n and /* y */ y = off").is_ok());
    }
}
