//! Compiling a linked RMPL program to a THCA (thesis §5.2.2, Figure 5-2; DESIGN.md §5.2).
//!
//! Each construct compiles to a *fragment*: its start locations, and — when its completion is the
//! exit of single locations — those exits, to be wired to whatever follows it with `;`:
//! - a goal / clock initialisation: one primitive location; it exits when its goal is achieved;
//! - `A; B`: A's exits lead to B's starts. A left operand whose completion is not a location's
//!   exit (a parallel composition, or anything containing one) is wrapped in a composite, which
//!   exits when nothing inside is marked or moving (Figure 5-3, step 8);
//! - `A, B`: the starts of both;
//! - `do A watching c` / `A maintaining c`: a composite around A with maintenance `⊭ c` / `⊨ c`;
//!   it exits when A completes or is preempted;
//! - `if c thennext A [elsenext B]`, `unless c thennext A`: a goal-less location whose transitions
//!   go to A's starts on `⊨ c` (`⊭ c` for `unless`) and to B's starts (or, without `elsenext`, out
//!   of the construct: the thread ends) otherwise;
//! - `when c donext A`: a goal-less location looping on `⊭ c`, going to A's starts on `⊨ c`;
//! - `whenever c donext A`: the same, but the `⊨ c` transition also re-marks the location;
//! - `always A`: a goal-less location whose transition marks itself and A's starts every instant;
//!   A also starts in the first instant ("starts A at each instant of time");
//! - `next A`: a goal-less location whose transition (True) marks A's starts.
//!
//! Locations are created in program order, construct before contents, so the Mars entry program
//! of Figure 3-2 compiles to Figure 3-4's locations 1..12 in the same numbering. The program
//! itself is the outermost composite.

use super::program::{AssertionId, ConditionId, LinkedProgram, Process, ProcessKind};
use crate::diagnostic::Source;
use crate::sequencer::{
    ClockInit, Condition, Construct, Goal, LocationId, Origin, Sense, Thca, ThcaBuilder, ThcaError,
    Transition,
};

/// Compiles `program` (linked from `source`) to a THCA.
pub fn compile(program: &LinkedProgram, source: &Source) -> Result<Thca, ThcaError> {
    let mut compiler = Compiler {
        program,
        builder: ThcaBuilder::new(&program.name, program.table.clone(), source.clone()),
    };
    let origin = Origin {
        construct: Construct::Program,
        span: program.span.clone(),
        call_stack: Vec::new(),
    };
    let root = compiler.builder.composite(None, origin);
    compiler.builder.add_start(None, root);
    let body = compiler.process(&program.process, root);
    for start in body.starts {
        compiler.builder.add_start(Some(root), start);
    }
    compiler.builder.build()
}

/// A transition to be added once we know where it leads: out of `from` under `guard`.
struct Exit {
    from: LocationId,
    guard: Option<Condition>,
}

/// What a construct compiled to.
struct Fragment {
    starts: Vec<LocationId>,
    /// The exits that fire exactly when the construct completes (none if it never completes);
    /// `None` when completion is not a location's exit and needs a composite to detect.
    exits: Option<Vec<Exit>>,
}

struct Compiler<'p> {
    program: &'p LinkedProgram,
    builder: ThcaBuilder,
}

impl Compiler<'_> {
    fn origin(&self, construct: Construct, process: &Process) -> Origin {
        Origin {
            construct,
            span: process.span.clone(),
            call_stack: process.call_stack.clone(),
        }
    }

    fn condition(&mut self, id: ConditionId, sense: Sense) -> Condition {
        let condition = self.program.condition(id);
        self.builder
            .condition(condition.formula.clone(), sense, condition.span.clone())
    }

    /// A goal-less primitive location for a combinator.
    fn control(
        &mut self,
        construct: Construct,
        process: &Process,
        parent: LocationId,
    ) -> LocationId {
        let origin = self.origin(construct, process);
        self.builder
            .primitive(Some(parent), origin, None, Vec::new())
    }

    fn transition(&mut self, from: LocationId, guard: Option<Condition>, targets: Vec<LocationId>) {
        self.builder
            .add_transition(from, Transition { guard, targets });
    }

    fn process(&mut self, process: &Process, parent: LocationId) -> Fragment {
        match &process.kind {
            ProcessKind::Assert(id) => self.assertion(process, *id, parent),
            ProcessKind::Sequence(parts) => self.sequence(parts, parent),
            ProcessKind::Parallel(parts) => Fragment {
                starts: parts
                    .iter()
                    .flat_map(|part| self.process(part, parent).starts)
                    .collect(),
                exits: None,
            },
            ProcessKind::Watching { body, condition } => {
                let maintenance = self.condition(*condition, Sense::NotEntailed);
                let construct = Construct::Watching;
                self.composite(construct, process, body, Some(maintenance), parent)
            }
            ProcessKind::Maintaining { body, condition } => {
                let maintenance = self.condition(*condition, Sense::Entailed);
                let construct = Construct::Maintaining;
                self.composite(construct, process, body, Some(maintenance), parent)
            }
            ProcessKind::If {
                condition,
                then,
                otherwise,
            } => self.branch(process, *condition, then, otherwise.as_deref(), parent),
            ProcessKind::Unless { condition, then } => {
                self.unless(process, *condition, then, parent)
            }
            ProcessKind::When { condition, body } => {
                self.wait(Construct::When, process, *condition, body, parent)
            }
            ProcessKind::Whenever { condition, body } => {
                self.wait(Construct::Whenever, process, *condition, body, parent)
            }
            ProcessKind::Always(body) => self.always(process, body, parent),
            ProcessKind::Next(body) => {
                let location = self.control(Construct::Next, process, parent);
                let body = self.process(body, parent);
                self.transition(location, None, body.starts);
                Fragment {
                    starts: vec![location],
                    exits: body.exits,
                }
            }
        }
    }

    /// A goal and/or clock initialisations: one primitive location, which exits once its goal
    /// is achieved.
    fn assertion(&mut self, process: &Process, id: AssertionId, parent: LocationId) -> Fragment {
        let assertion = self.program.assertion(id);
        let goal = assertion.goal.clone().map(|(formula, span)| Goal {
            formula: self.builder.formula(formula),
            span,
        });
        let inits = assertion
            .clocks
            .iter()
            .map(|(clock, span)| ClockInit {
                clock: *clock,
                span: span.clone(),
            })
            .collect();
        let origin = self.origin(Construct::Assertion, process);
        let location = self.builder.primitive(Some(parent), origin, goal, inits);
        Fragment {
            starts: vec![location],
            exits: Some(vec![Exit {
                from: location,
                guard: None,
            }]),
        }
    }

    /// `unless c thennext A`: on to A when c is not entailed, out of the construct otherwise.
    fn unless(
        &mut self,
        process: &Process,
        condition: ConditionId,
        then: &Process,
        parent: LocationId,
    ) -> Fragment {
        let location = self.control(Construct::Unless, process, parent);
        let then = self.process(then, parent);
        let go = self.condition(condition, Sense::NotEntailed);
        self.transition(location, Some(go), then.starts);
        let skip = self.condition(condition, Sense::Entailed);
        Fragment {
            starts: vec![location],
            exits: with_exit(then.exits, location, skip),
        }
    }

    /// `when c donext A` / `whenever c donext A`: wait while c is not entailed; then start A (and,
    /// for `whenever`, keep waiting for the next time).
    fn wait(
        &mut self,
        construct: Construct,
        process: &Process,
        condition: ConditionId,
        body: &Process,
        parent: LocationId,
    ) -> Fragment {
        let again = construct == Construct::Whenever;
        let location = self.control(construct, process, parent);
        let wait = self.condition(condition, Sense::NotEntailed);
        self.transition(location, Some(wait), vec![location]);
        let body = self.process(body, parent);
        let go = self.condition(condition, Sense::Entailed);
        let targets = if again {
            std::iter::once(location).chain(body.starts).collect()
        } else {
            body.starts
        };
        self.transition(location, Some(go), targets);
        Fragment {
            starts: vec![location],
            exits: if again { Some(Vec::new()) } else { body.exits },
        }
    }

    /// `always A`: A starts now and, through the location's transition, every next instant.
    fn always(&mut self, process: &Process, body: &Process, parent: LocationId) -> Fragment {
        let location = self.control(Construct::Always, process, parent);
        let body = self.process(body, parent);
        let starts: Vec<LocationId> = std::iter::once(location).chain(body.starts).collect();
        self.transition(location, None, starts.clone());
        Fragment {
            starts,
            exits: Some(Vec::new()),
        }
    }

    /// `A; B; ...`: each part's exits lead to the next part's starts.
    fn sequence(&mut self, parts: &[Process], parent: LocationId) -> Fragment {
        let mut starts = None;
        let mut exits: Option<Vec<Exit>> = None;
        for (i, part) in parts.iter().enumerate() {
            let followed = i + 1 < parts.len();
            let fragment = if followed && !completes_by_exit(part) {
                self.composite(Construct::Group, part, part, None, parent)
            } else {
                self.process(part, parent)
            };
            for exit in exits.take().into_iter().flatten() {
                self.transition(exit.from, exit.guard, fragment.starts.clone());
            }
            starts.get_or_insert(fragment.starts);
            exits = fragment.exits;
        }
        Fragment {
            starts: starts.unwrap_or_default(),
            exits,
        }
    }

    /// A composite location around `body`; it exits when nothing inside is marked or moving.
    fn composite(
        &mut self,
        construct: Construct,
        process: &Process,
        body: &Process,
        maintenance: Option<Condition>,
        parent: LocationId,
    ) -> Fragment {
        let origin = self.origin(construct, process);
        let composite = self.builder.composite(Some(parent), origin);
        if let Some(maintenance) = maintenance {
            self.builder.set_maintenance(composite, maintenance);
        }
        for start in self.process(body, composite).starts {
            self.builder.add_start(Some(composite), start);
        }
        Fragment {
            starts: vec![composite],
            exits: Some(vec![Exit {
                from: composite,
                guard: None,
            }]),
        }
    }

    /// `if c thennext A [elsenext B]`.
    fn branch(
        &mut self,
        process: &Process,
        condition: ConditionId,
        then: &Process,
        otherwise: Option<&Process>,
        parent: LocationId,
    ) -> Fragment {
        let construct = if otherwise.is_some() {
            Construct::IfElse
        } else {
            Construct::If
        };
        let location = self.control(construct, process, parent);
        let then = self.process(then, parent);
        let go = self.condition(condition, Sense::Entailed);
        self.transition(location, Some(go), then.starts);
        let otherwise_guard = self.condition(condition, Sense::NotEntailed);
        let exits = match otherwise {
            Some(otherwise) => {
                let otherwise = self.process(otherwise, parent);
                self.transition(location, Some(otherwise_guard), otherwise.starts);
                then.exits.zip(otherwise.exits).map(|(mut a, b)| {
                    a.extend(b);
                    a
                })
            }
            None => with_exit(then.exits, location, otherwise_guard),
        };
        Fragment {
            starts: vec![location],
            exits,
        }
    }
}

/// The exits of a body plus the exit taken when the body is skipped.
fn with_exit(exits: Option<Vec<Exit>>, from: LocationId, guard: Condition) -> Option<Vec<Exit>> {
    exits.map(|mut exits| {
        exits.push(Exit {
            from,
            guard: Some(guard),
        });
        exits
    })
}

/// Whether a construct's completion is the exit of single locations (so `;` can chain from
/// them directly), as opposed to "every one of several threads has finished".
fn completes_by_exit(process: &Process) -> bool {
    match &process.kind {
        ProcessKind::Parallel(_) => false,
        ProcessKind::Assert(_)
        | ProcessKind::Watching { .. }
        | ProcessKind::Maintaining { .. }
        | ProcessKind::Whenever { .. }
        | ProcessKind::Always(_) => true,
        ProcessKind::Sequence(parts) => parts.last().is_none_or(completes_by_exit),
        ProcessKind::If {
            then, otherwise, ..
        } => completes_by_exit(then) && otherwise.as_deref().is_none_or(completes_by_exit),
        ProcessKind::Unless { then: body, .. }
        | ProcessKind::When { body, .. }
        | ProcessKind::Next(body) => completes_by_exit(body),
    }
}
