//! Component types in plant files: the pieces the loader needs to expand them.
//!
//! A `Type(...)` is a component written once — attributes, modes, initial distribution,
//! transitions — with named numeric **parameters** (fault rates, probabilities, rewards) and
//! `self` standing for the component in its formulas (a number written as a parameter's name
//! is a [`NumberOrName`](crate::diagnostic::locate::NumberOrName)). `Component(name: "switch1", type:
//! "switch", parameters: { ... })` is an **instance**: loading expands it into the component the
//! type describes, named `switch1`, `self.heat` read as `switch1.heat`, each parameter name
//! read as the instance's value (or the type's default). The expansion is the plant a
//! hand-written copy of the body would give, so nothing after loading knows types exist
//! (`tests/plant_types.rs` checks this against hand-written twins).
//!
//! **Indexed names** write arrays: `b[0..14]` is `b0`, `b1`, …, `b14` (both bounds included).
//! A component name, a control, an observable, a monitor's observable or a connection may use
//! them; every range in one text has the same length and the `i`-th expansion takes the `i`-th
//! index of each (`"b[7..14].out = led[7..14].power"` is eight connections).

use crate::logic::syntax::{Expr, ExprKind, Name, Operand};

/// The most names one indexed text expands to: far above any model written by hand, far
/// below what would exhaust memory on a typo (`b[0..9999999999]`).
pub(crate) const MAX_INDEXED: usize = 100_000;

/// Why an indexed text does not expand.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct IndexError {
    /// What is wrong.
    pub(crate) message: String,
    /// What was expected.
    pub(crate) expected: &'static str,
}

/// The texts an indexed text stands for: `text` itself when it has no `[`, otherwise one text
/// per index, every `[first..last]` replaced by the index at that position of its range.
pub(crate) fn expand_indexed(text: &str) -> Result<Vec<String>, IndexError> {
    let Some(_) = text.find('[') else {
        return Ok(vec![text.to_string()]);
    };
    // The text between ranges, and the ranges.
    let mut pieces: Vec<&str> = Vec::new();
    let mut ranges: Vec<(u64, u64)> = Vec::new();
    let mut rest = text;
    while let Some(open) = rest.find('[') {
        pieces.push(&rest[..open]);
        let after = &rest[open + 1..];
        let close = after.find(']').ok_or_else(|| malformed(text))?;
        ranges.push(range(&after[..close]).ok_or_else(|| malformed(text))?);
        rest = &after[close + 1..];
    }
    pieces.push(rest);
    let length = |(first, last): (u64, u64)| (last - first).saturating_add(1);
    let count = length(ranges[0]);
    if let Some(&other) = ranges.iter().find(|&&r| length(r) != count) {
        return Err(IndexError {
            message: format!(
                "`{text}`: the ranges have different lengths ({count} and {})",
                length(other)
            ),
            expected: "ranges of one length, taken in step",
        });
    }
    if count > MAX_INDEXED as u64 {
        return Err(IndexError {
            message: format!("`{text}` stands for {count} names"),
            expected: "at most 100000 names",
        });
    }
    Ok((0..count)
        .map(|i| {
            let mut out = String::from(pieces[0]);
            for (range, piece) in ranges.iter().zip(&pieces[1..]) {
                out.push_str(&(range.0 + i).to_string());
                out.push_str(piece);
            }
            out
        })
        .collect())
}

fn malformed(text: &str) -> IndexError {
    IndexError {
        message: format!("`{text}` has a malformed index range"),
        expected: "`[first..last]`, two whole numbers with first <= last",
    }
}

/// `first..last` with first <= last.
fn range(text: &str) -> Option<(u64, u64)> {
    let (first, last) = text.split_once("..")?;
    let first: u64 = first.trim().parse().ok()?;
    let last: u64 = last.trim().parse().ok()?;
    (first <= last).then_some((first, last))
}

/// Reads `self` in a type's formula as the instance `name`: the variable `self` (the mode
/// variable) and every `self.attribute`. Values are left alone: a value may not be named `self`
/// by accident of this rule, only a variable.
pub(crate) fn rename_self(expr: &mut Expr, name: &str) {
    match &mut expr.kind {
        ExprKind::Constant(_) => {}
        ExprKind::Compare { left, right, .. } => {
            rename(left, name);
            if let Operand::Name(right) = right {
                if right.text.starts_with("self.") {
                    rename(right, name);
                }
            }
        }
        ExprKind::Confidence { variable, .. } => rename(variable, name),
        ExprKind::Not(inner) => rename_self(inner, name),
        ExprKind::And(parts) | ExprKind::Or(parts) => {
            parts.iter_mut().for_each(|p| rename_self(p, name));
        }
        ExprKind::Implies(a, b) => {
            rename_self(a, name);
            rename_self(b, name);
        }
    }
}

fn rename(variable: &mut Name, name: &str) {
    if variable.text == "self" {
        variable.text = name.to_string();
    } else if let Some(attribute) = variable.text.strip_prefix("self.") {
        variable.text = format!("{name}.{attribute}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logic::syntax::parse;

    #[test]
    fn indexed_texts_expand_in_step() {
        assert_eq!(expand_indexed("valve").unwrap(), ["valve"]);
        assert_eq!(expand_indexed("b[0..2]").unwrap(), ["b0", "b1", "b2"]);
        assert_eq!(
            expand_indexed("b[7..8].out = led[1..2].power").unwrap(),
            ["b7.out = led1.power", "b8.out = led2.power"]
        );
        assert_eq!(expand_indexed("x[3..3]_y").unwrap(), ["x3_y"]);
    }

    #[test]
    fn bad_ranges_are_refused() {
        for bad in ["b[2..1]", "b[1..]", "b[x..2]", "b[1..2", "b[1,2]"] {
            let error = expand_indexed(bad).expect_err(bad);
            assert!(error.message.contains("malformed"), "{bad}: {error:?}");
        }
        let error = expand_indexed("b[0..1].out = c[0..2].in").expect_err("lengths");
        assert!(error.message.contains("different lengths"), "{error:?}");
        let error = expand_indexed("b[0..99999999999]").expect_err("too many");
        assert!(error.message.contains("stands for"), "{error:?}");
    }

    #[test]
    fn self_is_the_instance() {
        let mut expr = parse("self.out = self.in and self != blown and self.x = selfish").unwrap();
        rename_self(&mut expr, "b3");
        let reparsed = parse("b3.out = b3.in and b3 != blown and b3.x = selfish").unwrap();
        assert_eq!(
            format!("{:?}", strip(&expr)),
            format!("{:?}", strip(&reparsed))
        );
    }

    /// The names of a formula, in order (spans differ after renaming).
    fn strip(expr: &Expr) -> Vec<String> {
        let mut names = Vec::new();
        collect(expr, &mut names);
        names
    }

    fn collect(expr: &Expr, names: &mut Vec<String>) {
        match &expr.kind {
            ExprKind::Compare { left, right, .. } => {
                names.push(left.text.clone());
                if let Operand::Name(right) = right {
                    names.push(right.text.clone());
                }
            }
            ExprKind::And(parts) | ExprKind::Or(parts) => {
                parts.iter().for_each(|p| collect(p, names));
            }
            ExprKind::Not(inner) => collect(inner, names),
            ExprKind::Implies(a, b) => {
                collect(a, names);
                collect(b, names);
            }
            ExprKind::Constant(_) | ExprKind::Confidence { .. } => {}
        }
    }
}
