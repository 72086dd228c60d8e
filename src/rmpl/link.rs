//! Linking: an RMPL file becomes a [`LinkedProgram`] whose formulas refer to variables by id.
//!
//! 1. Invocations are inlined (`expand`) from the entry program and from every other
//!    program without parameters that no program invokes, so `kairos check` sees them all.
//! 2. Clocks are the names assigned `= 0` in an assertion.
//! 3. The variable table is the plant's (ids unchanged, so the executive can hand the formulas to
//!    the plant's theory) or, without a plant, one built from the program: each `x = v` adds `v`
//!    to the domain of `x`. The clocks are added to it.
//! 4. Every condition and assertion is resolved; goals may not bound clocks or test beliefs.
//! 5. Every clock must be initialised on every path before a condition reads it.
//!
//! Every error is collected and returned, located, in source order.

use std::collections::{BTreeSet, HashMap, HashSet};

use super::expand::{Expansion, invoked_programs};
use super::program::{LinkedProgram, Process, ProcessKind, ResolvedAssertion, ResolvedCondition};
use super::syntax::{Definition, ProgramFile};
use crate::diagnostic::{Diagnostic, Source, Span};
use crate::logic::syntax::{CmpOp, Name, Operand};
use crate::logic::{ClockId, Expr, ExprKind, Formula, VarTable, resolve};

/// What to link against.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinkOptions<'a> {
    /// The program to run; the file's first program when `None`.
    pub entry: Option<&'a str>,
    /// The plant's variables; names are inferred from the program when `None`.
    pub plant: Option<&'a VarTable>,
}

/// Links the entry program of `file` (parsed from `source`), reporting every error found.
pub fn link(
    source: &Source,
    file: &ProgramFile,
    options: &LinkOptions<'_>,
) -> Result<LinkedProgram, Vec<Diagnostic>> {
    let entry = entry_definition(file, options.entry)?;
    let mut expansion = Expansion::new(file, source);
    let process = expansion.root(entry);
    let others: Vec<Process> = other_roots(file, entry)
        .into_iter()
        .map(|definition| expansion.root(definition))
        .collect();
    let Expansion {
        conditions,
        assertions,
        mut errors,
        ..
    } = expansion;

    let clocks = clock_names(&assertions);
    let table = program_table(
        options.plant,
        &conditions,
        &assertions,
        &clocks,
        &mut errors,
    );
    let resolved_conditions: Vec<ResolvedCondition> = conditions
        .iter()
        .map(|expr| resolve_condition(expr, &table, &mut errors))
        .collect();
    let resolved_assertions: Vec<ResolvedAssertion> = assertions
        .iter()
        .map(|expr| resolve_assertion(expr, &table, &mut errors))
        .collect();

    let mut check = ClockCheck {
        source,
        table: &table,
        clock_reads: conditions.iter().map(|c| clock_reads(c, &table)).collect(),
        assertions: &resolved_assertions,
        errors: &mut errors,
    };
    for root in std::iter::once(&process).chain(&others) {
        check.process(root, &Initialised::none());
    }

    if !errors.is_empty() {
        // Programs expanded more than once (invoked twice, or checked as roots too) repeat their
        // errors: keep one of each.
        errors.sort_by(|a, b| {
            (a.span.start, a.span.end, &a.message).cmp(&(b.span.start, b.span.end, &b.message))
        });
        errors.dedup();
        return Err(errors);
    }
    Ok(LinkedProgram {
        name: entry.name.text.clone(),
        span: entry.span.clone(),
        table,
        process,
        conditions: resolved_conditions,
        assertions: resolved_assertions,
    })
}

fn entry_definition<'f>(
    file: &'f ProgramFile,
    entry: Option<&str>,
) -> Result<&'f Definition, Vec<Diagnostic>> {
    let definition = match entry {
        None => file.definitions.first(),
        Some(name) => file.definition(name),
    };
    let Some(definition) = definition else {
        let names: Vec<&str> = file
            .definitions
            .iter()
            .map(|d| d.name.text.as_str())
            .collect();
        return Err(vec![
            Diagnostic::new(
                format!("no program `{}` in this file", entry.unwrap_or_default()),
                0..0,
            )
            .expected("the name of a program defined in this file")
            .note(format!("the programs are: {}", names.join(", "))),
        ]);
    };
    if let Some(first) = definition.params.first() {
        return Err(vec![
            Diagnostic::new(
                format!(
                    "the entry program `{}` takes parameters",
                    definition.name.text
                ),
                first.span.clone(),
            )
            .expected("a program without parameters to run (or one that invokes this one)"),
        ]);
    }
    Ok(definition)
}

/// Programs without parameters that no program invokes: checked as if each were run.
fn other_roots<'f>(file: &'f ProgramFile, entry: &Definition) -> Vec<&'f Definition> {
    let mut invoked = Vec::new();
    for definition in &file.definitions {
        invoked_programs(&definition.body, &mut invoked);
    }
    // A set: a file of thousands of programs must not cost a scan of them all per program.
    let invoked: HashSet<String> = invoked.into_iter().collect();
    file.definitions
        .iter()
        .filter(|d| d.name.text != entry.name.text && d.params.is_empty())
        .filter(|d| !invoked.contains(&d.name.text))
        .collect()
}

/// The conjuncts of an assertion (`a and b and c` → a, b, c).
fn conjuncts(expr: &Expr) -> Vec<&Expr> {
    match &expr.kind {
        ExprKind::And(parts) => parts.iter().collect(),
        _ => vec![expr],
    }
}

/// `t = 0`: the clock initialised and the number it is set to.
fn initialisation(expr: &Expr) -> Option<(&Name, f64)> {
    match &expr.kind {
        ExprKind::Compare {
            left,
            op: CmpOp::Eq,
            right: Operand::Quantity { value, .. },
        } => Some((left, *value)),
        _ => None,
    }
}

/// Names initialised to 0 by some assertion, in order of first appearance.
fn clock_names(assertions: &[Expr]) -> Vec<Name> {
    let mut names: Vec<Name> = Vec::new();
    for (clock, value) in assertions
        .iter()
        .flat_map(conjuncts)
        .filter_map(initialisation)
    {
        if value == 0.0 && !names.iter().any(|n| n.text == clock.text) {
            names.push(clock.clone());
        }
    }
    names
}

/// The plant's table, or one inferred from the program, with the program's clocks added.
fn program_table(
    plant: Option<&VarTable>,
    conditions: &[Expr],
    assertions: &[Expr],
    clocks: &[Name],
    errors: &mut Vec<Diagnostic>,
) -> VarTable {
    let mut table = match plant {
        Some(plant) => plant.clone(),
        None => {
            let mut exprs: Vec<&Expr> = conditions.iter().chain(assertions).collect();
            exprs.sort_by_key(|e| e.span.start);
            inferred_table(exprs.into_iter(), clocks)
        }
    };
    for clock in clocks {
        if table.add_clock(clock.text.clone()).is_err() {
            errors.push(
                Diagnostic::new(
                    format!("`{}` is a variable of the plant, not a clock", clock.text),
                    clock.span.clone(),
                )
                .expected("a clock name that no plant variable has"),
            );
        }
    }
    table
}

/// Variables and domains from the program's own comparisons: each `x = v`, `x != v` and
/// `P(x = v)` adds `v` to the domain of `x` (clocks excluded), in the order given.
fn inferred_table<'e>(exprs: impl Iterator<Item = &'e Expr>, clocks: &[Name]) -> VarTable {
    let mut domains: Vec<(String, Vec<String>)> = Vec::new();
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut add = |variable: &Name, value: &Name| {
        if clocks.iter().any(|c| c.text == variable.text) {
            return;
        }
        let i = *index.entry(variable.text.clone()).or_insert_with(|| {
            domains.push((variable.text.clone(), Vec::new()));
            domains.len() - 1
        });
        let values = &mut domains[i].1;
        if crate::logic::is_value_name(&value.text) && !values.contains(&value.text) {
            values.push(value.text.clone());
        }
    };
    for expr in exprs {
        visit_atoms(expr, &mut |atom| match &atom.kind {
            ExprKind::Compare {
                left,
                op: CmpOp::Eq | CmpOp::Ne,
                right: Operand::Name(value),
            } => add(left, value),
            ExprKind::Confidence {
                variable, value, ..
            } => add(variable, value),
            _ => {}
        });
    }
    let mut table = VarTable::new();
    for (name, values) in domains.into_iter().filter(|(_, values)| !values.is_empty()) {
        // Names and values come from the grammar, so the table accepts them.
        let _ = table.add_variable(name, values);
    }
    table
}

/// Calls `visit` on every comparison and confidence atom of a formula.
fn visit_atoms<'e>(expr: &'e Expr, visit: &mut impl FnMut(&'e Expr)) {
    match &expr.kind {
        ExprKind::Constant(_) => {}
        ExprKind::Compare { .. } | ExprKind::Confidence { .. } => visit(expr),
        ExprKind::Not(inner) => visit_atoms(inner, visit),
        ExprKind::And(parts) | ExprKind::Or(parts) => {
            parts.iter().for_each(|p| visit_atoms(p, visit));
        }
        ExprKind::Implies(a, b) => {
            visit_atoms(a, visit);
            visit_atoms(b, visit);
        }
    }
}

/// The clocks a condition reads, with where.
fn clock_reads(expr: &Expr, table: &VarTable) -> Vec<(ClockId, Span)> {
    let mut reads = Vec::new();
    visit_atoms(expr, &mut |atom| {
        if let ExprKind::Compare { left, .. } = &atom.kind
            && let Some(clock) = table.clock_id(&left.text)
        {
            reads.push((clock, left.span.clone()));
        }
    });
    reads
}

fn resolve_into(expr: &Expr, table: &VarTable, errors: &mut Vec<Diagnostic>) -> Formula {
    resolve(expr, table).unwrap_or_else(|found| {
        errors.extend(found);
        Formula::False
    })
}

fn resolve_condition(
    expr: &Expr,
    table: &VarTable,
    errors: &mut Vec<Diagnostic>,
) -> ResolvedCondition {
    let first_error = errors.len();
    let formula = resolve_into(expr, table, errors);
    // A bound on a name that is neither a variable nor a clock is most likely a clock that is
    // never started: say how clocks are started.
    let mut unstarted = Vec::new();
    visit_atoms(expr, &mut |atom| {
        if let ExprKind::Compare {
            left,
            right: Operand::Quantity { .. },
            ..
        } = &atom.kind
        {
            unstarted.push(left.clone());
        }
    });
    for diagnostic in &mut errors[first_error..] {
        if let Some(name) = unstarted.iter().find(|n| n.span == diagnostic.span) {
            diagnostic.notes.push(format!(
                "clocks are names started by an assertion `{} = 0`; no assertion starts `{}`",
                name.text, name.text
            ));
        }
    }
    ResolvedCondition {
        formula,
        span: expr.span.clone(),
    }
}

/// Splits an assertion into clock initialisations and a goal on plant state, and resolves the goal.
fn resolve_assertion(
    expr: &Expr,
    table: &VarTable,
    errors: &mut Vec<Diagnostic>,
) -> ResolvedAssertion {
    let mut clocks = Vec::new();
    let mut goal_parts = Vec::new();
    for part in conjuncts(expr) {
        let start = initialisation(part)
            .and_then(|(name, value)| Some((name, value, table.clock_id(&name.text)?)));
        match start {
            Some((_, 0.0, clock)) => clocks.push((clock, part.span.clone())),
            Some((name, value, _)) => errors.push(
                Diagnostic::new(
                    format!("clock `{}` is set to {value}", name.text),
                    part.span.clone(),
                )
                .expected(format!(
                    "`{} = 0`: a clock can only be started at 0",
                    name.text
                )),
            ),
            None => goal_parts.push(part),
        }
    }
    let goal = (!goal_parts.is_empty()).then(|| {
        goal_parts
            .iter()
            .for_each(|part| reject_non_state(part, table, errors));
        let formula = Formula::all(goal_parts.iter().map(|p| resolve_into(p, table, errors)));
        let span = if goal_parts.len() == 1 {
            goal_parts[0].span.clone()
        } else {
            expr.span.clone()
        };
        (formula, span)
    });
    ResolvedAssertion { goal, clocks }
}

/// Goals are on plant state: clock bounds and beliefs cannot be achieved by commanding the plant.
fn reject_non_state(expr: &Expr, table: &VarTable, errors: &mut Vec<Diagnostic>) {
    visit_atoms(expr, &mut |atom| match &atom.kind {
        ExprKind::Compare { left, op, .. }
            if op.is_ordering() && table.clock_id(&left.text).is_some() =>
        {
            errors.push(
                Diagnostic::new(
                    format!("a goal cannot bound the clock `{}`", left.text),
                    atom.span.clone(),
                )
                .expected("a constraint on plant state to achieve (bound clocks in conditions)"),
            );
        }
        ExprKind::Confidence { .. } => errors.push(
            Diagnostic::new("a goal cannot be a belief", atom.span.clone())
                .expected("a constraint on plant state to achieve (test beliefs in conditions)"),
        ),
        _ => {}
    });
}

/// The clocks started on every path so far; `Everything` after a construct that never completes
/// (nothing after it runs, so nothing there can read a clock too early).
#[derive(Debug, Clone, PartialEq)]
enum Initialised {
    Everything,
    Clocks(BTreeSet<ClockId>),
}

impl Initialised {
    fn none() -> Self {
        Initialised::Clocks(BTreeSet::new())
    }

    fn contains(&self, clock: ClockId) -> bool {
        match self {
            Initialised::Everything => true,
            Initialised::Clocks(clocks) => clocks.contains(&clock),
        }
    }

    fn with(&self, added: impl IntoIterator<Item = ClockId>) -> Self {
        match self {
            Initialised::Everything => Initialised::Everything,
            Initialised::Clocks(clocks) => {
                let mut clocks = clocks.clone();
                clocks.extend(added);
                Initialised::Clocks(clocks)
            }
        }
    }

    /// Both branches completed (parallel composition): what either started.
    fn union(self, other: Self) -> Self {
        match (self, other) {
            (Initialised::Clocks(a), Initialised::Clocks(b)) => {
                Initialised::Clocks(a.union(&b).copied().collect())
            }
            _ => Initialised::Everything,
        }
    }

    /// One of two branches completed (`if … elsenext`): what both started.
    fn intersection(self, other: Self) -> Self {
        match (self, other) {
            (Initialised::Clocks(a), Initialised::Clocks(b)) => {
                Initialised::Clocks(a.intersection(&b).copied().collect())
            }
            (Initialised::Everything, other) | (other, Initialised::Everything) => other,
        }
    }
}

/// "Clock used before initialisation": a must-analysis over the program's control flow. A
/// construct's clocks at completion are those started on every way it can complete; a preemptible
/// body (`do … watching`, `maintaining`) or a conditional one (`if`, `unless`) may complete
/// without starting anything.
struct ClockCheck<'a> {
    source: &'a Source,
    table: &'a VarTable,
    clock_reads: Vec<Vec<(ClockId, Span)>>,
    assertions: &'a [ResolvedAssertion],
    errors: &'a mut Vec<Diagnostic>,
}

impl ClockCheck<'_> {
    /// Checks the reads in `process` given the clocks started before it; returns those started
    /// when it completes.
    fn process(&mut self, process: &Process, before: &Initialised) -> Initialised {
        match &process.kind {
            ProcessKind::Assert(id) => {
                before.with(self.assertions[id.0].clocks.iter().map(|c| c.0))
            }
            ProcessKind::Sequence(parts) => parts
                .iter()
                .fold(before.clone(), |started, part| self.process(part, &started)),
            ProcessKind::Parallel(parts) => parts
                .iter()
                .map(|part| self.process(part, before))
                .fold(before.clone(), Initialised::union),
            ProcessKind::Maintaining { body, condition }
            | ProcessKind::Watching { body, condition } => {
                self.reads(condition.0, before);
                self.process(body, before);
                before.clone()
            }
            ProcessKind::If {
                condition,
                then,
                otherwise,
            } => {
                self.reads(condition.0, before);
                let then = self.process(then, before);
                match otherwise {
                    Some(otherwise) => then.intersection(self.process(otherwise, before)),
                    None => before.clone(),
                }
            }
            ProcessKind::Unless { condition, then } => {
                self.reads(condition.0, before);
                self.process(then, before);
                before.clone()
            }
            ProcessKind::When { condition, body } => {
                self.reads(condition.0, before);
                self.process(body, before)
            }
            ProcessKind::Whenever { condition, body } => {
                self.reads(condition.0, before);
                self.process(body, before);
                Initialised::Everything
            }
            ProcessKind::Always(body) => {
                self.process(body, before);
                Initialised::Everything
            }
            ProcessKind::Next(body) => self.process(body, before),
        }
    }

    fn reads(&mut self, condition: usize, started: &Initialised) {
        for (clock, span) in &self.clock_reads[condition] {
            if started.contains(*clock) {
                continue;
            }
            let name = self.table.clock_name(*clock);
            let starts: Vec<String> = self
                .assertions
                .iter()
                .flat_map(|a| &a.clocks)
                .filter(|(c, _)| c == clock)
                .map(|(_, at)| self.source.line_col(at.start).0.to_string())
                .collect();
            self.errors.push(
                Diagnostic::new(
                    format!("clock `{name}` is read before it is started"),
                    span.clone(),
                )
                .expected(format!("`{name} = 0` before this point on every path"))
                .note(format!(
                    "`{name}` is started at line {}, which does not come first on every path \
                         (a parallel branch, an `if`/`unless` that may not run, or a preemptible \
                         `do … watching`/`maintaining` body)",
                    starts.join(", ")
                )),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rmpl::syntax::parse;

    fn link_text(text: &str, plant: Option<&VarTable>) -> Result<LinkedProgram, String> {
        let source = Source::new("p.rmpl", text);
        let file = parse(text).map_err(|d| source.render(&d))?;
        let options = LinkOptions { entry: None, plant };
        link(&source, &file, &options).map_err(|d| source.render(&d))
    }

    #[test]
    fn without_a_plant_domains_come_from_the_program() {
        let linked = link_text(
            "P() :: { x = a; when (x != b and P(y = c) >= 0.5) donext (t = 0; x = d) }",
            None,
        )
        .unwrap();
        let x = linked.table.variable_id("x").unwrap();
        assert_eq!(linked.table.variable(x).values(), ["a", "b", "d"]);
        let y = linked.table.variable_id("y").unwrap();
        assert_eq!(linked.table.variable(y).values(), ["c"]);
        assert!(linked.table.clock_id("t").is_some());
    }

    #[test]
    fn with_a_plant_variable_ids_are_the_plants() {
        let mut plant = VarTable::new();
        plant
            .add_variable("nav", ["earth-relative", "inertial"])
            .unwrap();
        plant.add_variable("engine", ["off", "standby"]).unwrap();
        let linked = link_text("P() :: { t1 = 0; engine = standby }", Some(&plant)).unwrap();
        assert_eq!(
            linked.table.variable_id("engine"),
            plant.variable_id("engine")
        );
        let goal = linked.assertions[1].goal.as_ref().unwrap();
        assert_eq!(
            goal.0,
            Formula::is(crate::logic::VarId(1), crate::logic::ValueId(1))
        );
    }

    #[test]
    fn assertions_split_into_clock_starts_and_goals() {
        let linked = link_text("P() :: { x = on and t = 0 }", None).unwrap();
        let assertion = &linked.assertions[0];
        assert_eq!(assertion.clocks.len(), 1);
        assert!(assertion.goal.is_some());
    }

    #[test]
    fn clocks_must_be_started_on_every_path() {
        for (text, ok) in [
            ("P() :: { t = 0; when (t >= 1) donext x = a }", true),
            ("P() :: { t = 0, when (t >= 1) donext x = a }", false),
            (
                "P() :: { if y = b thennext t = 0; when (t >= 1) donext x = a }",
                false,
            ),
            (
                "P() :: { if y = b thennext t = 0 elsenext t = 0; when (t >= 1) donext x = a }",
                true,
            ),
            (
                "P() :: { do t = 0 watching y = b; when (t >= 1) donext x = a }",
                false,
            ),
            (
                "P() :: { {t = 0, u = 0}; when (t >= 1 and u < 2) donext x = a }",
                true,
            ),
            (
                "P() :: { when y = b donext t = 0; when (t >= 1) donext x = a }",
                true,
            ),
            (
                "P() :: { always x = a; when (t >= 1) donext x = a; t = 0 }",
                true,
            ),
        ] {
            let outcome = link_text(text, None);
            assert_eq!(outcome.is_ok(), ok, "{text}: {outcome:?}");
            if let Err(message) = outcome {
                assert!(
                    message.contains("clock `t` is read before it is started"),
                    "{message}"
                );
            }
        }
    }

    #[test]
    fn goals_stay_on_plant_state() {
        let message = link_text("P() :: { t = 0; t >= 5 }", None).unwrap_err();
        assert!(
            message.contains("a goal cannot bound the clock `t`"),
            "{message}"
        );
        let message = link_text("P() :: { P(x = a) >= 0.5 }", None).unwrap_err();
        assert!(message.contains("a goal cannot be a belief"), "{message}");
        let message = link_text("P() :: { t = 0; t = 3 }", None).unwrap_err();
        assert!(message.contains("clock `t` is set to 3"), "{message}");
    }

    #[test]
    fn an_unstarted_clock_is_explained() {
        let message = link_text("P() :: { x = a; when (t9 >= 5) donext x = b }", None).unwrap_err();
        assert!(message.contains("unknown variable `t9`"), "{message}");
        assert!(message.contains("no assertion starts `t9`"), "{message}");
    }

    #[test]
    fn a_plant_variable_cannot_be_a_clock() {
        let mut plant = VarTable::new();
        plant.add_variable("engine", ["off"]).unwrap();
        let message = link_text("P() :: { engine = 0 }", Some(&plant)).unwrap_err();
        assert!(
            message.contains("`engine` is a variable of the plant"),
            "{message}"
        );
    }

    #[test]
    fn parameters_are_substituted_and_located_at_the_argument() {
        let mut plant = VarTable::new();
        plant.add_variable("SA_1", ["stowed", "deployed"]).unwrap();
        let text = "P() :: { Deploy(SA_1); Deploy(SA_3) }\nDeploy(panel) :: { panel = deployed }";
        let message = link_text(text, Some(&plant)).unwrap_err();
        assert!(message.contains("unknown variable `SA_3`"), "{message}");
        assert!(message.contains("p.rmpl:1:31"), "{message}");
        let linked = link_text(
            "P() :: { Wait(5 s) }\nWait(d) :: { t = 0; when (t >= d) donext x = a }",
            None,
        )
        .unwrap();
        assert!(matches!(
            &linked.conditions[0].formula,
            Formula::Atom(crate::logic::Atom::Clock { seconds, .. }) if seconds.0 == 5.0
        ));
    }

    #[test]
    fn programs_nobody_invokes_are_checked_too() {
        let message = link_text("A() :: { x = a }\nB() :: { C() }", None).unwrap_err();
        assert!(message.contains("unknown program `C`"), "{message}");
    }
}
