//! A program with its invocations inlined and its names resolved: what the linker produces and the
//! compiler turns into a THCA.
//!
//! The tree ([`Process`]) refers to its conditions and assertions by index, so the same tree
//! serves before resolution (the indices point at parsed [`Expr`](crate::logic::Expr)s) and after
//! (they point at [`Formula`]s in the [`LinkedProgram`]).

use crate::diagnostic::Span;
use crate::logic::{ClockId, Formula, VarTable};

/// A condition (guard, watched or maintained constraint) of a [`LinkedProgram`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ConditionId(pub(crate) usize);

/// An assertion (goal and/or clock initialisations) of a [`LinkedProgram`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct AssertionId(pub(crate) usize);

/// One construct of an inlined program.
#[derive(Debug, Clone, PartialEq)]
pub struct Process {
    /// Which construct.
    pub kind: ProcessKind,
    /// Its text (in the body of the program that defines it).
    pub span: Span,
    /// The invocations it was inlined through, outermost first.
    pub call_stack: Vec<Span>,
}

/// The constructs left once invocations are inlined (thesis §5.1.3).
#[derive(Debug, Clone, PartialEq)]
pub enum ProcessKind {
    /// A goal and/or clock initialisations.
    Assert(AssertionId),
    /// `A, B, ...`.
    Parallel(Vec<Process>),
    /// `A; B; ...`.
    Sequence(Vec<Process>),
    /// `A maintaining c`.
    Maintaining {
        /// A.
        body: Box<Process>,
        /// c.
        condition: ConditionId,
    },
    /// `do A watching c`.
    Watching {
        /// A.
        body: Box<Process>,
        /// c.
        condition: ConditionId,
    },
    /// `if c thennext A [elsenext B]`.
    If {
        /// c.
        condition: ConditionId,
        /// A.
        then: Box<Process>,
        /// B.
        otherwise: Option<Box<Process>>,
    },
    /// `unless c thennext A`.
    Unless {
        /// c.
        condition: ConditionId,
        /// A.
        then: Box<Process>,
    },
    /// `when c donext A`.
    When {
        /// c.
        condition: ConditionId,
        /// A.
        body: Box<Process>,
    },
    /// `whenever c donext A`.
    Whenever {
        /// c.
        condition: ConditionId,
        /// A.
        body: Box<Process>,
    },
    /// `always A`.
    Always(Box<Process>),
    /// `next A`.
    Next(Box<Process>),
}

/// A resolved condition.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedCondition {
    /// The formula (it may bound clocks and test beliefs).
    pub formula: Formula,
    /// Where it is written.
    pub span: Span,
}

/// A resolved assertion: what a primitive location asserts.
#[derive(Debug, Clone, PartialEq)]
pub struct ResolvedAssertion {
    /// The goal on plant state and where it is written; `None` for a pure clock initialisation.
    pub goal: Option<(Formula, Span)>,
    /// The clocks it starts, each with where `t = 0` is written.
    pub clocks: Vec<(ClockId, Span)>,
}

/// A program ready to compile: the entry program with every invocation inlined and every name
/// resolved against the program's variable table.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkedProgram {
    /// The entry program's name.
    pub name: String,
    /// The entry program's definition.
    pub span: Span,
    /// The plant's variables (ids unchanged) or those inferred from the program, plus the
    /// program's clocks.
    pub table: VarTable,
    /// The entry program's body.
    pub process: Process,
    /// Conditions by [`ConditionId`].
    pub conditions: Vec<ResolvedCondition>,
    /// Assertions by [`AssertionId`].
    pub assertions: Vec<ResolvedAssertion>,
}

impl LinkedProgram {
    /// A condition.
    pub fn condition(&self, id: ConditionId) -> &ResolvedCondition {
        &self.conditions[id.0]
    }

    /// An assertion.
    pub fn assertion(&self, id: AssertionId) -> &ResolvedAssertion {
        &self.assertions[id.0]
    }
}
