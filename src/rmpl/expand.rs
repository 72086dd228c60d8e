//! Inlining: program invocations are replaced by the invoked program's body with its parameters
//! substituted (thesis §5.1.3: "within the invoked procedure, each parameter is replaced by the
//! appropriate argument"). Unknown programs, wrong argument counts and recursion are located
//! errors; expansion goes on after each so one run reports them all.
//!
//! A substituted name takes the span of the argument it came from, so a later "unknown variable"
//! points at the invocation that supplied it.

use std::collections::HashMap;

use super::program::{AssertionId, ConditionId, Process, ProcessKind};
use super::syntax::{Definition, Node, NodeKind, ProgramFile};
use crate::diagnostic::{Diagnostic, Source, Span, did_you_mean};
use crate::logic::syntax::{Name, Operand};
use crate::logic::{Expr, ExprKind};

/// How deeply constructs may nest once invocations are inlined, each invocation counting as a
/// level: every pass over the inlined tree (linking, the clock analysis, compilation, `Drop`) is
/// recursive, and a chain of 10,000 programs each invoking the next overflowed the stack (issue
/// 12). Four times the nesting one definition may have ([`super::syntax::MAX_NESTING`]).
pub const MAX_INLINED_DEPTH: usize = 4 * super::syntax::MAX_NESTING;

/// How many constructs a program may have once invocations are inlined: a program that invokes
/// another twice, which invokes a third twice, ... doubles with every level.
pub const MAX_INLINED_SIZE: usize = 100_000;

/// Parameter name → argument, for one invocation.
type Arguments = HashMap<String, Operand>;

/// The result of expanding one or more programs of a file: the trees refer to these conditions
/// and assertions by index.
pub(crate) struct Expansion<'f> {
    file: &'f ProgramFile,
    source: &'f Source,
    /// Conditions after substitution, by [`ConditionId`].
    pub conditions: Vec<Expr>,
    /// Assertions after substitution, by [`AssertionId`].
    pub assertions: Vec<Expr>,
    /// Everything wrong found so far.
    pub errors: Vec<Diagnostic>,
    /// The definitions by name, the first of each.
    by_name: HashMap<&'f str, &'f Definition>,
    /// The programs being expanded, outermost first.
    active: Vec<&'f str>,
    /// How many constructs enclose the one being expanded.
    depth: usize,
    /// How many constructs have been expanded.
    size: usize,
    /// Whether a limit was reached (reported once: every construct after it is beyond it too).
    limit_reached: bool,
}

impl<'f> Expansion<'f> {
    /// Starts an expansion of `file`, checking its definitions (duplicate programs, duplicate
    /// parameters).
    pub fn new(file: &'f ProgramFile, source: &'f Source) -> Self {
        let mut expansion = Expansion {
            file,
            source,
            conditions: Vec::new(),
            assertions: Vec::new(),
            errors: Vec::new(),
            by_name: HashMap::new(),
            active: Vec::new(),
            depth: 0,
            size: 0,
            limit_reached: false,
        };
        expansion.check_definitions();
        expansion
    }

    fn line_of(&self, span: &Span) -> usize {
        self.source.line_col(span.start).0
    }

    /// Indexes the definitions by name (the first of each; a file may hold thousands, so no
    /// scans per name) and reports duplicates.
    fn check_definitions(&mut self) {
        let file = self.file;
        for definition in &file.definitions {
            let first = *self
                .by_name
                .entry(&definition.name.text)
                .or_insert(definition);
            if !std::ptr::eq(first, definition) {
                let line = self.line_of(&first.name.span);
                self.errors.push(
                    Diagnostic::new(
                        format!("program `{}` is defined twice", definition.name.text),
                        definition.name.span.clone(),
                    )
                    .expected("a name no other program has")
                    .note(format!("the first definition is at line {line}")),
                );
            }
            for (j, param) in definition.params.iter().enumerate() {
                if definition.params[..j].iter().any(|p| p.text == param.text) {
                    self.errors.push(
                        Diagnostic::new(
                            format!("parameter `{}` appears twice", param.text),
                            param.span.clone(),
                        )
                        .expected("distinct parameter names"),
                    );
                }
            }
        }
    }

    /// Expands a definition run on its own (the entry program, or a program checked alone).
    pub fn root(&mut self, definition: &'f Definition) -> Process {
        self.active.push(&definition.name.text);
        let process = self.node(&definition.body, &Arguments::new(), &[]);
        self.active.pop();
        process
    }

    /// Expands one construct, within [`MAX_INLINED_DEPTH`] and [`MAX_INLINED_SIZE`]: beyond
    /// them, a located error (once) and a placeholder that does nothing.
    fn node(&mut self, node: &Node, arguments: &Arguments, call_stack: &[Span]) -> Process {
        if self.depth >= MAX_INLINED_DEPTH || self.size >= MAX_INLINED_SIZE {
            if !self.limit_reached {
                self.limit_reached = true;
                let error = self.too_large(node.span.clone(), call_stack);
                self.errors.push(error);
            }
            return Process {
                kind: ProcessKind::Parallel(Vec::new()),
                span: node.span.clone(),
                call_stack: call_stack.to_vec(),
            };
        }
        self.depth += 1;
        self.size += 1;
        let process = self.construct(node, arguments, call_stack);
        self.depth -= 1;
        process
    }

    /// The error for a construct past [`MAX_INLINED_DEPTH`] or [`MAX_INLINED_SIZE`], located at
    /// the outermost invocation (where the program can be changed) with the invocation chain.
    fn too_large(&self, span: Span, call_stack: &[Span]) -> Diagnostic {
        let (problem, limit) = if self.depth >= MAX_INLINED_DEPTH {
            (
                "nested too deeply",
                format!("at most {MAX_INLINED_DEPTH} nested constructs and invocations"),
            )
        } else {
            (
                "too large",
                format!("at most {MAX_INLINED_SIZE} constructs once invocations are inlined"),
            )
        };
        let names: Vec<String> = self.active.iter().map(|name| format!("{name}()")).collect();
        let chain = if names.len() > 6 {
            let skipped = names.len() - 4;
            format!(
                "{} → ({skipped} more) → {}",
                names[..2].join(" → "),
                names[names.len() - 2..].join(" → ")
            )
        } else {
            names.join(" → ")
        };
        let at = call_stack.first().cloned().unwrap_or(span);
        Diagnostic::new(
            format!("program {problem} once its invocations are inlined"),
            at.start..at.start,
        )
        .expected(limit)
        .note(format!("invocation chain: {chain}"))
    }

    fn construct(&mut self, node: &Node, arguments: &Arguments, call_stack: &[Span]) -> Process {
        let kind = match &node.kind {
            NodeKind::Assertion(expr) => {
                let expr = self.substitute(expr, arguments);
                self.assertions.push(expr);
                ProcessKind::Assert(AssertionId(self.assertions.len() - 1))
            }
            NodeKind::Invocation {
                program,
                arguments: given,
            } => {
                return self.invoke(program, given, node.span.clone(), arguments, call_stack);
            }
            NodeKind::Parallel(parts) => ProcessKind::Parallel(
                parts
                    .iter()
                    .map(|p| self.node(p, arguments, call_stack))
                    .collect(),
            ),
            NodeKind::Sequence(parts) => ProcessKind::Sequence(
                parts
                    .iter()
                    .map(|p| self.node(p, arguments, call_stack))
                    .collect(),
            ),
            NodeKind::Maintaining { body, condition } => ProcessKind::Maintaining {
                condition: self.condition(condition, arguments),
                body: self.boxed(body, arguments, call_stack),
            },
            NodeKind::Watching { body, condition } => ProcessKind::Watching {
                condition: self.condition(condition, arguments),
                body: self.boxed(body, arguments, call_stack),
            },
            NodeKind::If {
                condition,
                then,
                otherwise,
            } => ProcessKind::If {
                condition: self.condition(condition, arguments),
                then: self.boxed(then, arguments, call_stack),
                otherwise: otherwise
                    .as_ref()
                    .map(|o| self.boxed(o, arguments, call_stack)),
            },
            NodeKind::Unless { condition, then } => ProcessKind::Unless {
                condition: self.condition(condition, arguments),
                then: self.boxed(then, arguments, call_stack),
            },
            NodeKind::When { condition, body } => ProcessKind::When {
                condition: self.condition(condition, arguments),
                body: self.boxed(body, arguments, call_stack),
            },
            NodeKind::Whenever { condition, body } => ProcessKind::Whenever {
                condition: self.condition(condition, arguments),
                body: self.boxed(body, arguments, call_stack),
            },
            NodeKind::Always(body) => ProcessKind::Always(self.boxed(body, arguments, call_stack)),
            NodeKind::Next(body) => ProcessKind::Next(self.boxed(body, arguments, call_stack)),
        };
        Process {
            kind,
            span: node.span.clone(),
            call_stack: call_stack.to_vec(),
        }
    }

    fn boxed(&mut self, node: &Node, arguments: &Arguments, call_stack: &[Span]) -> Box<Process> {
        Box::new(self.node(node, arguments, call_stack))
    }

    fn condition(&mut self, expr: &Expr, arguments: &Arguments) -> ConditionId {
        let expr = self.substitute(expr, arguments);
        self.conditions.push(expr);
        ConditionId(self.conditions.len() - 1)
    }

    /// Inlines `program(given)`; a placeholder that does nothing stands in after an error.
    fn invoke(
        &mut self,
        program: &Name,
        given: &[Operand],
        span: Span,
        arguments: &Arguments,
        call_stack: &[Span],
    ) -> Process {
        let nothing = Process {
            kind: ProcessKind::Parallel(Vec::new()),
            span: span.clone(),
            call_stack: call_stack.to_vec(),
        };
        let Some(&definition) = self.by_name.get(program.text.as_str()) else {
            self.errors.push(self.unknown_program(program));
            return nothing;
        };
        if given.len() != definition.params.len() {
            self.errors
                .push(self.wrong_argument_count(definition, given.len(), span));
            return nothing;
        }
        if self.active.contains(&program.text.as_str()) {
            self.errors.push(self.recursion(program));
            return nothing;
        }
        let inner: Arguments = definition
            .params
            .iter()
            .zip(given)
            .map(|(param, argument)| (param.text.clone(), substitute_operand(argument, arguments)))
            .collect();
        let mut inner_stack = call_stack.to_vec();
        inner_stack.push(span.clone());
        self.active.push(&definition.name.text);
        let process = self.node(&definition.body, &inner, &inner_stack);
        self.active.pop();
        process
    }

    fn unknown_program(&self, program: &Name) -> Diagnostic {
        let names = self.file.definitions.iter().map(|d| d.name.text.as_str());
        let mut diagnostic = Diagnostic::new(
            format!("unknown program `{}`", program.text),
            program.span.clone(),
        )
        .expected("the name of a program defined in this file")
        .note(format!(
            "the programs are: {}",
            names.clone().collect::<Vec<_>>().join(", ")
        ));
        if let Some(close) = did_you_mean(&program.text, names) {
            diagnostic = diagnostic.note(format!("did you mean `{close}`?"));
        }
        diagnostic
    }

    fn wrong_argument_count(
        &self,
        definition: &Definition,
        given: usize,
        span: Span,
    ) -> Diagnostic {
        let wanted = definition.params.len();
        let params: Vec<&str> = definition.params.iter().map(|p| p.text.as_str()).collect();
        Diagnostic::new(
            format!(
                "`{}` takes {wanted} argument{} but {given} {} given",
                definition.name.text,
                if wanted == 1 { "" } else { "s" },
                if given == 1 { "was" } else { "were" },
            ),
            span,
        )
        .expected(format!(
            "{wanted} argument{}",
            if wanted == 1 { "" } else { "s" }
        ))
        .note(format!(
            "`{}({})` is defined at line {}",
            definition.name.text,
            params.join(", "),
            self.line_of(&definition.name.span)
        ))
    }

    fn recursion(&self, program: &Name) -> Diagnostic {
        let chain: Vec<String> = self
            .active
            .iter()
            .map(|name| format!("{name}()"))
            .chain(std::iter::once(format!("{}()", program.text)))
            .collect();
        Diagnostic::new(
            format!("recursive invocation of `{}`", program.text),
            program.span.clone(),
        )
        .expected(
            "an invocation of a program that is not already running here (programs are inlined)",
        )
        .note(format!("invocation chain: {}", chain.join(" → ")))
    }

    /// Replaces parameters by arguments in a formula.
    fn substitute(&mut self, expr: &Expr, arguments: &Arguments) -> Expr {
        if arguments.is_empty() {
            return expr.clone();
        }
        let kind = match &expr.kind {
            ExprKind::Constant(value) => ExprKind::Constant(*value),
            ExprKind::Compare { left, op, right } => ExprKind::Compare {
                left: self.substitute_name(left, arguments),
                op: *op,
                right: substitute_operand(right, arguments),
            },
            ExprKind::Confidence {
                variable,
                value,
                op,
                probability,
                probability_span,
            } => ExprKind::Confidence {
                variable: self.substitute_name(variable, arguments),
                value: self.substitute_name(value, arguments),
                op: *op,
                probability: *probability,
                probability_span: probability_span.clone(),
            },
            ExprKind::Not(inner) => ExprKind::Not(Box::new(self.substitute(inner, arguments))),
            ExprKind::And(parts) => ExprKind::And(
                parts
                    .iter()
                    .map(|p| self.substitute(p, arguments))
                    .collect(),
            ),
            ExprKind::Or(parts) => ExprKind::Or(
                parts
                    .iter()
                    .map(|p| self.substitute(p, arguments))
                    .collect(),
            ),
            ExprKind::Implies(a, b) => ExprKind::Implies(
                Box::new(self.substitute(a, arguments)),
                Box::new(self.substitute(b, arguments)),
            ),
        };
        Expr {
            kind,
            span: expr.span.clone(),
        }
    }

    /// A name in a position only a name can take (a variable, a clock, a value in `P(...)`).
    fn substitute_name(&mut self, name: &Name, arguments: &Arguments) -> Name {
        match arguments.get(&name.text) {
            None => name.clone(),
            Some(Operand::Name(argument)) => argument.clone(),
            Some(Operand::Quantity { span, .. }) => {
                self.errors.push(
                    Diagnostic::new(
                        format!(
                            "parameter `{}` is given a time but used as a name",
                            name.text
                        ),
                        span.clone(),
                    )
                    .expected(format!(
                        "a name: `{}` stands for a variable, clock or value at line {}",
                        name.text,
                        self.line_of(&name.span)
                    )),
                );
                name.clone()
            }
        }
    }
}

/// A value or time position: a parameter there may stand for a value or for a time.
fn substitute_operand(operand: &Operand, arguments: &Arguments) -> Operand {
    match operand {
        Operand::Name(name) => arguments
            .get(&name.text)
            .cloned()
            .unwrap_or_else(|| operand.clone()),
        Operand::Quantity { .. } => operand.clone(),
    }
}

/// The names of the programs `definition` invokes, directly.
pub(crate) fn invoked_programs(node: &Node, out: &mut Vec<String>) {
    match &node.kind {
        NodeKind::Assertion(_) => {}
        NodeKind::Invocation { program, .. } => out.push(program.text.clone()),
        NodeKind::Parallel(parts) | NodeKind::Sequence(parts) => {
            parts.iter().for_each(|p| invoked_programs(p, out));
        }
        NodeKind::If {
            then, otherwise, ..
        } => {
            invoked_programs(then, out);
            if let Some(otherwise) = otherwise {
                invoked_programs(otherwise, out);
            }
        }
        NodeKind::Maintaining { body, .. }
        | NodeKind::Watching { body, .. }
        | NodeKind::Unless { then: body, .. }
        | NodeKind::When { body, .. }
        | NodeKind::Whenever { body, .. }
        | NodeKind::Always(body)
        | NodeKind::Next(body) => invoked_programs(body, out),
    }
}
