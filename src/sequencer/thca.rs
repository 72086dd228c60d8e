//! Timed Hierarchical Constraint Automata (thesis §5.2.1; DESIGN.md §5.2).
//!
//! A THCA ⟨Σ, Θ, Π, G, I, M, T⟩ is stored flat: every location, primitive or composite, is one
//! [`Location`] in a vector, numbered in the order it was created; a composite lists its children
//! and its start locations Θ; the top automaton has its own start locations. Goals (G), clock
//! initialisations (I), maintenance constraints (M) and transitions (T) hang off the locations.
//! Formulas are interned once per automaton ([`FormulaId`]) so the sequencer can cache "is it
//! entailed?" per formula and cycle.
//!
//! Every location records where it came from in the program ([`Origin`]), so markings and events
//! can be reported against the source.

use std::collections::HashMap;
use std::fmt;

use crate::diagnostic::{Source, Span};
use crate::logic::{ClockId, Formula, VarTable};

/// A location of a [`Thca`]. Locations are numbered from 1 in creation order when displayed,
/// as in the thesis's Figure 3-4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LocationId(u32);

impl LocationId {
    /// Position in [`Thca::locations`].
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// The 1-based number shown to people (the thesis numbers the Mars entry THCA 1..12).
    pub fn number(self) -> u32 {
        self.0 + 1
    }
}

impl fmt::Display for LocationId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.number())
    }
}

/// A formula interned in a [`Thca`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct FormulaId(u32);

impl FormulaId {
    /// Position in the automaton's formula list.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Whether a condition asks for entailment (`c`) or non-entailment (`c̄`) (thesis §5.2.1: "not
/// entailed" is not "negation entailed").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sense {
    /// Holds when the formula is entailed.
    Entailed,
    /// Holds when the formula is not entailed.
    NotEntailed,
}

/// A guard or maintenance constraint: `⊨ c` or `⊭ c`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Condition {
    /// The formula c.
    pub formula: FormulaId,
    /// Entailed or not entailed.
    pub sense: Sense,
    /// Where c is written.
    pub span: Span,
}

/// A goal constraint G(σ): what the plant must progress towards while σ is marked.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Goal {
    /// The constraint, over plant state variables only.
    pub formula: FormulaId,
    /// Where it is written.
    pub span: Span,
}

/// A clock initialisation `t = 0`, part of I(σ).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ClockInit {
    /// The clock.
    pub clock: ClockId,
    /// Where it is written.
    pub span: Span,
}

/// A transition (l, targets): when enabled, every target is marked (with its start
/// sub-automata) in the next cycle. `guard: None` is the label **True**.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Transition {
    /// The guard l.
    pub guard: Option<Condition>,
    /// The locations marked when it is taken (thesis §5.2.1 feature 7: several).
    pub targets: Vec<LocationId>,
}

/// Primitive or composite, with what each kind holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum LocationKind {
    /// A primitive location σp.
    Primitive {
        /// G(σp); `None` is **True**.
        goal: Option<Goal>,
        /// I(σp).
        clock_inits: Vec<ClockInit>,
    },
    /// A composite location σc: a sub-automaton.
    Composite {
        /// Its locations (direct children).
        children: Vec<LocationId>,
        /// Its start locations Θ.
        starts: Vec<LocationId>,
    },
}

/// The RMPL construct a location was compiled from (for drawings and traces).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Construct {
    /// The program itself (the outermost composite).
    Program,
    /// A composite around the left operand of `;` whose completion is not one location's exit.
    Group,
    /// A goal and/or clock initialisation.
    Assertion,
    /// `do A watching c`.
    Watching,
    /// `A maintaining c`.
    Maintaining,
    /// `if c thennext A`.
    If,
    /// `if c thennext A elsenext B`.
    IfElse,
    /// `unless c thennext A`.
    Unless,
    /// `when c donext A`.
    When,
    /// `whenever c donext A`.
    Whenever,
    /// `always A`.
    Always,
    /// `next A`.
    Next,
}

impl fmt::Display for Construct {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Construct::Program => "program",
            Construct::Group => "group",
            Construct::Assertion => "assertion",
            Construct::Watching => "do … watching",
            Construct::Maintaining => "maintaining",
            Construct::If => "if … thennext",
            Construct::IfElse => "if … thennext … elsenext",
            Construct::Unless => "unless … thennext",
            Construct::When => "when … donext",
            Construct::Whenever => "whenever … donext",
            Construct::Always => "always",
            Construct::Next => "next",
        })
    }
}

/// Where a location comes from in the program text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Origin {
    /// The construct.
    pub construct: Construct,
    /// Its text in the program.
    pub span: Span,
    /// The invocations it was inlined through, outermost first (empty in the entry program).
    pub call_stack: Vec<Span>,
}

/// One location σ ∈ Σ.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// Its identity.
    pub id: LocationId,
    /// The composite it belongs to; `None` for the top automaton.
    pub parent: Option<LocationId>,
    /// Primitive (goal, clock initialisations) or composite (children, starts).
    pub kind: LocationKind,
    /// M(σ); `None` is **True**. On a composite it applies to everything inside.
    pub maintenance: Option<Condition>,
    /// T(σ).
    pub transitions: Vec<Transition>,
    /// Where it comes from.
    pub origin: Origin,
}

impl Location {
    /// True for composite locations.
    pub fn is_composite(&self) -> bool {
        matches!(self.kind, LocationKind::Composite { .. })
    }

    /// The goal of a primitive location.
    pub fn goal(&self) -> Option<&Goal> {
        match &self.kind {
            LocationKind::Primitive { goal, .. } => goal.as_ref(),
            LocationKind::Composite { .. } => None,
        }
    }

    /// The clock initialisations of a primitive location.
    pub fn clock_inits(&self) -> &[ClockInit] {
        match &self.kind {
            LocationKind::Primitive { clock_inits, .. } => clock_inits,
            LocationKind::Composite { .. } => &[],
        }
    }

    /// The start locations of a composite (empty for a primitive).
    pub fn starts(&self) -> &[LocationId] {
        match &self.kind {
            LocationKind::Composite { starts, .. } => starts,
            LocationKind::Primitive { .. } => &[],
        }
    }
}

/// A timed hierarchical constraint automaton, ready to execute.
///
/// Invariant (checked by [`ThcaBuilder::build`]): a location's parent was created before it, so
/// ascending ids visit every composite before its contents and descending ids visit contents
/// before their composite.
#[derive(Debug, Clone, PartialEq)]
pub struct Thca {
    name: String,
    locations: Vec<Location>,
    starts: Vec<LocationId>,
    formulas: Vec<Formula>,
    table: VarTable,
    source: Source,
}

impl Thca {
    /// The program's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Every location, by id.
    pub fn locations(&self) -> &[Location] {
        &self.locations
    }

    /// One location.
    pub fn location(&self, id: LocationId) -> &Location {
        &self.locations[id.index()]
    }

    /// Start locations of the top automaton, Θ(A).
    pub fn starts(&self) -> &[LocationId] {
        &self.starts
    }

    /// An interned formula.
    pub fn formula(&self, id: FormulaId) -> &Formula {
        &self.formulas[id.index()]
    }

    /// Number of interned formulas.
    pub fn formula_count(&self) -> usize {
        self.formulas.len()
    }

    /// Every interned formula (goals, guards, maintenance conditions).
    pub fn formulas(&self) -> &[Formula] {
        &self.formulas
    }

    /// The variables and clocks the formulas use: the plant's table (ids unchanged) with the
    /// program's clocks added.
    pub fn table(&self) -> &VarTable {
        &self.table
    }

    /// The program text the origins point into.
    pub fn source(&self) -> &Source {
        &self.source
    }

    /// `line:col` of a location's construct in the program.
    pub fn position(&self, id: LocationId) -> (usize, usize) {
        self.source.line_col(self.location(id).origin.span.start)
    }

    /// A condition as the thesis's drawings write it: `⊨ c` (entailed) or `⊭ c` (not entailed).
    pub fn condition_text(&self, condition: &Condition) -> String {
        let sign = match condition.sense {
            Sense::Entailed => "⊨",
            Sense::NotEntailed => "⊭",
        };
        format!(
            "{sign} {}",
            self.formula(condition.formula).display(&self.table)
        )
    }

    /// What a location asserts and maintains, one line each: `goal: …`, `init: t = 0`,
    /// `maintain ⊭ …`.
    pub fn labels(&self, location: &Location) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(goal) = location.goal() {
            let formula = self.formula(goal.formula).display(&self.table);
            lines.push(format!("goal: {formula}"));
        }
        for init in location.clock_inits() {
            lines.push(format!("init: {} = 0", self.table.clock_name(init.clock)));
        }
        if let Some(maintenance) = &location.maintenance {
            lines.push(format!("maintain {}", self.condition_text(maintenance)));
        }
        lines
    }
}

/// A listing of the automaton: one location per line, indented under its composite, with its
/// construct, its position in the program, what it asserts and its transitions.
impl fmt::Display for Thca {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let clocks: Vec<&str> = self.table.clocks().map(|(_, name)| name).collect();
        writeln!(
            f,
            "THCA {} ({}): {} locations; clocks: {}",
            self.name,
            self.source.name,
            self.locations.len(),
            if clocks.is_empty() {
                "none".to_string()
            } else {
                clocks.join(", ")
            }
        )?;
        for location in &self.locations {
            let mut depth = 0;
            let mut up = location.parent;
            while let Some(parent) = up {
                depth += 1;
                up = self.location(parent).parent;
            }
            let indent = "  ".repeat(depth);
            let (line, col) = self.position(location.id);
            let kind = if location.is_composite() {
                "composite "
            } else {
                ""
            };
            writeln!(
                f,
                "{indent}{}: {kind}{} at {line}:{col}",
                location.id, location.origin.construct
            )?;
            for label in self.labels(location) {
                writeln!(f, "{indent}    {label}")?;
            }
            if location.is_composite() {
                let starts: Vec<String> = location.starts().iter().map(|s| s.to_string()).collect();
                writeln!(f, "{indent}    starts: {}", starts.join(", "))?;
            }
            for transition in &location.transitions {
                let guard = transition
                    .guard
                    .as_ref()
                    .map_or("true".to_string(), |g| self.condition_text(g));
                let targets: Vec<String> =
                    transition.targets.iter().map(|t| t.to_string()).collect();
                writeln!(f, "{indent}    {guard} -> {}", targets.join(", "))?;
            }
        }
        Ok(())
    }
}

/// Why [`ThcaBuilder::build`] refused an automaton.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ThcaError {
    /// A location id that the builder never handed out.
    #[error("location {0} does not exist")]
    NoSuchLocation(u32),
    /// A parent that is not a composite created before its child.
    #[error("location {child} cannot belong to location {parent}: not an earlier composite")]
    BadParent {
        /// The child's number.
        child: u32,
        /// The parent's number.
        parent: u32,
    },
    /// A start location that is not a child of the automaton it starts.
    #[error("location {start} is not inside the automaton it is a start location of")]
    StartOutside {
        /// The start location's number.
        start: u32,
    },
    /// A formula id that was not interned by this builder.
    #[error("formula {0} was not interned in this automaton")]
    NoSuchFormula(u32),
    /// Start locations were added to a location that is not a composite.
    #[error("location {0} is not a composite and cannot have start locations")]
    NotComposite(u32),
}

/// Assembles a [`Thca`]; the RMPL compiler uses it, and tests build automata by hand with it.
#[derive(Debug, Clone)]
pub struct ThcaBuilder {
    name: String,
    locations: Vec<Location>,
    starts: Vec<LocationId>,
    formulas: Vec<Formula>,
    interned: HashMap<Formula, FormulaId>,
    table: VarTable,
    source: Source,
    /// The first misuse of the builder's methods, reported by `build`.
    misuse: Option<ThcaError>,
}

impl ThcaBuilder {
    /// An empty automaton named `name` over `table`, whose origins point into `source`.
    pub fn new(name: impl Into<String>, table: VarTable, source: Source) -> Self {
        ThcaBuilder {
            name: name.into(),
            locations: Vec::new(),
            starts: Vec::new(),
            formulas: Vec::new(),
            interned: HashMap::new(),
            table,
            source,
            misuse: None,
        }
    }

    /// Interns a formula (the same formula always gets the same id).
    pub fn formula(&mut self, formula: Formula) -> FormulaId {
        if let Some(&id) = self.interned.get(&formula) {
            return id;
        }
        let id = FormulaId(self.formulas.len() as u32);
        self.formulas.push(formula.clone());
        self.interned.insert(formula, id);
        id
    }

    /// Interns `formula` and makes a condition of it.
    pub fn condition(&mut self, formula: Formula, sense: Sense, span: Span) -> Condition {
        Condition {
            formula: self.formula(formula),
            sense,
            span,
        }
    }

    /// Adds a primitive location inside `parent` (or at the top).
    pub fn primitive(
        &mut self,
        parent: Option<LocationId>,
        origin: Origin,
        goal: Option<Goal>,
        clock_inits: Vec<ClockInit>,
    ) -> LocationId {
        self.push(
            parent,
            origin,
            LocationKind::Primitive { goal, clock_inits },
        )
    }

    /// Adds a composite location inside `parent` (or at the top), with no starts yet.
    pub fn composite(&mut self, parent: Option<LocationId>, origin: Origin) -> LocationId {
        let kind = LocationKind::Composite {
            children: Vec::new(),
            starts: Vec::new(),
        };
        self.push(parent, origin, kind)
    }

    fn push(
        &mut self,
        parent: Option<LocationId>,
        origin: Origin,
        kind: LocationKind,
    ) -> LocationId {
        let id = LocationId(self.locations.len() as u32);
        self.locations.push(Location {
            id,
            parent,
            kind,
            maintenance: None,
            transitions: Vec::new(),
            origin,
        });
        id
    }

    /// Sets the maintenance constraint of a location.
    pub fn set_maintenance(&mut self, location: LocationId, condition: Condition) {
        if let Some(l) = self.existing(location) {
            l.maintenance = Some(condition);
        }
    }

    /// Makes `start` a start location of the composite `automaton`, or of the top automaton.
    pub fn add_start(&mut self, automaton: Option<LocationId>, start: LocationId) {
        let Some(automaton) = automaton else {
            self.starts.push(start);
            return;
        };
        match self.existing(automaton).map(|l| &mut l.kind) {
            Some(LocationKind::Composite { starts, .. }) => starts.push(start),
            Some(LocationKind::Primitive { .. }) => {
                self.misuse
                    .get_or_insert(ThcaError::NotComposite(automaton.number()));
            }
            None => {}
        }
    }

    /// Adds a transition out of `from`.
    pub fn add_transition(&mut self, from: LocationId, transition: Transition) {
        if let Some(l) = self.existing(from) {
            l.transitions.push(transition);
        }
    }

    /// The location with this id, or `None` after recording the misuse for `build`.
    fn existing(&mut self, id: LocationId) -> Option<&mut Location> {
        if id.index() >= self.locations.len() {
            self.misuse
                .get_or_insert(ThcaError::NoSuchLocation(id.number()));
        }
        self.locations.get_mut(id.index())
    }

    /// Checks the structure and returns the automaton.
    pub fn build(mut self) -> Result<Thca, ThcaError> {
        if let Some(misuse) = self.misuse.take() {
            return Err(misuse);
        }
        self.check()?;
        for i in 0..self.locations.len() {
            if let Some(parent) = self.locations[i].parent {
                let id = self.locations[i].id;
                if let LocationKind::Composite { children, .. } =
                    &mut self.locations[parent.index()].kind
                {
                    children.push(id);
                }
            }
        }
        Ok(Thca {
            name: self.name,
            locations: self.locations,
            starts: self.starts,
            formulas: self.formulas,
            table: self.table,
            source: self.source,
        })
    }

    fn check(&self) -> Result<(), ThcaError> {
        let exists = |id: LocationId| {
            (id.index() < self.locations.len())
                .then_some(())
                .ok_or(ThcaError::NoSuchLocation(id.number()))
        };
        let formula_exists = |id: FormulaId| {
            (id.index() < self.formulas.len())
                .then_some(())
                .ok_or(ThcaError::NoSuchFormula(id.0))
        };
        let condition_ok =
            |c: &Option<Condition>| c.as_ref().map_or(Ok(()), |c| formula_exists(c.formula));
        for start in &self.starts {
            exists(*start)?;
            if self.locations[start.index()].parent.is_some() {
                return Err(ThcaError::StartOutside {
                    start: start.number(),
                });
            }
        }
        for location in &self.locations {
            if let Some(parent) = location.parent {
                let valid = parent < location.id && self.locations[parent.index()].is_composite();
                if !valid {
                    return Err(ThcaError::BadParent {
                        child: location.id.number(),
                        parent: parent.number(),
                    });
                }
            }
            for start in location.starts() {
                exists(*start)?;
                if self.locations[start.index()].parent != Some(location.id) {
                    return Err(ThcaError::StartOutside {
                        start: start.number(),
                    });
                }
            }
            condition_ok(&location.maintenance)?;
            if let Some(goal) = location.goal() {
                formula_exists(goal.formula)?;
            }
            for transition in &location.transitions {
                condition_ok(&transition.guard)?;
                transition.targets.iter().try_for_each(|t| exists(*t))?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn origin() -> Origin {
        Origin {
            construct: Construct::Assertion,
            span: 0..0,
            call_stack: Vec::new(),
        }
    }

    fn builder() -> ThcaBuilder {
        ThcaBuilder::new("t", VarTable::new(), Source::new("t", ""))
    }

    #[test]
    fn children_are_collected_and_formulas_interned() {
        let mut b = builder();
        let c = b.composite(None, origin());
        let p = b.primitive(Some(c), origin(), None, Vec::new());
        b.add_start(Some(c), p);
        b.add_start(None, c);
        assert_eq!(b.formula(Formula::True), b.formula(Formula::True));
        let thca = b.build().unwrap();
        assert!(matches!(
            &thca.location(c).kind,
            LocationKind::Composite { children, starts } if children == &[p] && starts == &[p]
        ));
        assert_eq!(thca.starts(), &[c]);
        assert_eq!((c.number(), p.to_string()), (1, "2".to_string()));
    }

    #[test]
    fn malformed_structures_are_refused() {
        let mut b = builder();
        let p = b.primitive(None, origin(), None, Vec::new());
        b.primitive(Some(p), origin(), None, Vec::new());
        assert!(matches!(b.build(), Err(ThcaError::BadParent { .. })));

        let mut b = builder();
        let c = b.composite(None, origin());
        let outside = b.primitive(None, origin(), None, Vec::new());
        b.add_start(Some(c), outside);
        assert!(matches!(b.build(), Err(ThcaError::StartOutside { .. })));

        let mut b = builder();
        let p = b.primitive(None, origin(), None, Vec::new());
        b.add_transition(
            p,
            Transition {
                guard: None,
                targets: vec![LocationId(9)],
            },
        );
        assert_eq!(b.build(), Err(ThcaError::NoSuchLocation(10)));

        let mut b = builder();
        let p = b.primitive(None, origin(), None, Vec::new());
        let q = b.primitive(None, origin(), None, Vec::new());
        b.add_start(Some(p), q);
        assert_eq!(b.build(), Err(ThcaError::NotComposite(1)));

        let mut b = builder();
        b.set_maintenance(
            LocationId(3),
            Condition {
                formula: FormulaId(0),
                sense: Sense::Entailed,
                span: 0..0,
            },
        );
        assert_eq!(b.build(), Err(ThcaError::NoSuchLocation(4)));
    }
}
