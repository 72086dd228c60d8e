//! The scenario's `deliver`: orders of simultaneous deliveries a run follows, as
//! `kairos explore` writes them into a counterexample (the plant's side is
//! `script::open`).

use super::format::DeliverFile;
use super::load::FileCtx;
use super::script::{Script, TIME_EPSILON};
use crate::diagnostic::locate::Step;
use crate::diagnostic::{Diagnostic, did_you_mean};

/// Each `(at:, order:)` entry: `at` the time of a cycle of the run, `order` rules of the
/// script (`period` and `end` are the scenario's cycle period and end).
pub(super) fn deliveries(
    ctx: &mut FileCtx,
    deliver: &[DeliverFile],
    script: &Script,
    (period, end): (f64, f64),
) -> Vec<(f64, Vec<usize>)> {
    let mut out = Vec::new();
    for (k, entry) in deliver.iter().enumerate() {
        let at = entry.at;
        let cycle = (at / period).round();
        let on_a_cycle = at.is_finite() && (cycle * period - at).abs() <= TIME_EPSILON;
        if !(on_a_cycle && at >= 0.0 && at <= end + TIME_EPSILON) {
            let path = [Step::Field("deliver"), Step::Index(k), Step::Field("at")];
            let diagnostic = Diagnostic::new(
                format!("{at} s is not the time of a cycle of the run"),
                ctx.span(&path),
            )
            .expected(format!(
                "a multiple of the cycle period ({period} s) from 0 to the end ({end} s)"
            ));
            ctx.push(diagnostic);
            continue;
        }
        let order: Vec<Option<usize>> = (entry.order.iter().enumerate())
            .map(|(i, name)| rule(ctx, script, name, k, i))
            .collect();
        if let Some(order) = order.into_iter().collect::<Option<Vec<usize>>>() {
            out.push((at, order));
        }
    }
    out
}

/// The rule named `name` (the `i`th of entry `k`), or a located error.
fn rule(ctx: &mut FileCtx, script: &Script, name: &str, k: usize, i: usize) -> Option<usize> {
    if let Some(rule) = script.rule_named(name) {
        return Some(rule);
    }
    let path = [
        Step::Field("deliver"),
        Step::Index(k),
        Step::Field("order"),
        Step::Index(i),
    ];
    let names = script.rules.iter().map(|r| r.name.as_str());
    let mut diagnostic = Diagnostic::new(format!("no rule `{name}`"), ctx.span(&path))
        .expected("the name of a rule of the scenario or its includes");
    if let Some(close) = did_you_mean(name, names) {
        diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
    }
    ctx.push(diagnostic);
    None
}
