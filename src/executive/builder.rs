//! Building an executive: its options ([`ExecutiveOptions`]) and [`ExecutiveBuilder`], which
//! checks that the program was linked against the plant, encodes the plant's theory and
//! compiles the reconfiguration policies before the first cycle.

use std::sync::Arc;
use std::time::Duration;

use super::control::ControlProgram;
use super::faithful::Faithful;
use super::monitoring::Monitoring;
use super::observations::LastObservation;
use super::oracle::{AnswerCache, VersionedEstimate};
use super::timeline::{Retention, Timelines};
use super::{Executive, Reported};
use crate::diagnostic::Source;
use crate::estimation::{DEFAULT_HISTORY, PlantGrouping, Rerun, TimedMe, TimedMeOptions};
use crate::logic::{VarId, VarTable};
use crate::opsat::{Budget, TheoryError};
use crate::plant::{Commands, Plant};
use crate::reconfiguration::{Ambiguity, AmbiguityOptions, Reconfiguration};

/// How an executive runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExecutiveOptions {
    /// κ: how many system states mode estimation tracks.
    pub kappa: usize,
    /// How many recent steps mode estimation keeps to estimate again tracking 8κ states
    /// ([`TimedMeOptions::history`]); 0 turns the history window off.
    pub history: usize,
    /// Which occasions re-run the history window ([`TimedMeOptions::rerun`]): the choice
    /// between accuracy ([`Rerun::Doubt`], the default) and cost ([`Rerun::Surprise`]).
    pub rerun: Rerun,
    /// A cycle that takes longer than this (wall time) raises a deadline-overrun event.
    pub cycle_deadline: Option<Duration>,
    /// OPSAT's budget for mode estimation, per tracked state.
    pub estimation_budget: Budget,
    /// Mode estimation stops this long after the cycle starts (goals submitted since the last
    /// cycle count against it): every OPSAT search of the cycle's estimation — one per tracked
    /// state, and any re-estimation of the history window or fall-back expansion — stops at
    /// that instant, and the belief is the best found, reported by a search-cut event. It
    /// bounds mode estimation as a whole, the phase that varies most; the sequencer and the
    /// planner have no budget.
    pub estimation_deadline: Option<Duration>,
    /// How much state, command and observation history to keep.
    pub retention: Retention,
    /// When the goal is unreachable from ŝ: how probable another tracked plant state must be to
    /// be acted on, and how many commands per goal may be sent on such states.
    pub ambiguity: AmbiguityOptions,
    /// N of the `Chatter` event (DESIGN.md §9): a component commanded back into a mode it was
    /// commanded out of within this many cycles, with no diagnosis in between, chatters.
    pub chatter_cycles: u64,
}

/// The default of [`ExecutiveOptions::chatter_cycles`].
pub const CHATTER_CYCLES: u64 = 10;

impl Default for ExecutiveOptions {
    fn default() -> Self {
        ExecutiveOptions {
            kappa: 10,
            history: DEFAULT_HISTORY,
            rerun: Rerun::Doubt,
            cycle_deadline: None,
            estimation_budget: Budget::default(),
            estimation_deadline: None,
            retention: Retention::default(),
            ambiguity: AmbiguityOptions::default(),
            chatter_cycles: CHATTER_CYCLES,
        }
    }
}

/// Why an executive could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BuildError {
    /// The program was linked against other variables than the plant's.
    #[error(
        "the program was not linked against this plant model (its variables differ at `{0}`): link it with the plant's variable table"
    )]
    NotLinkedToPlant(String),
    /// The plant's constraints could not be encoded.
    #[error("the plant model cannot be encoded: {0}")]
    Theory(#[from] TheoryError),
}

/// Builds an [`Executive`]; see [`Executive::builder`].
pub struct ExecutiveBuilder {
    pub(super) plant: Plant,
    pub(super) program: ControlProgram,
    pub(super) options: ExecutiveOptions,
    pub(super) source: Option<Arc<Source>>,
}

impl ExecutiveBuilder {
    /// Keeps the text of the program or mission the executive runs, so that its events name
    /// their source lines ([`Event::named`](super::Event::named)). [`Executive::load`] and
    /// [`Executive::load_mission`] set it.
    pub fn source(mut self, source: Source) -> Self {
        self.source = Some(Arc::new(source));
        self
    }

    /// Sets κ, the number of system states mode estimation tracks.
    pub fn kappa(mut self, kappa: usize) -> Self {
        self.options.kappa = kappa.max(1);
        self
    }

    /// Sets how many recent steps mode estimation keeps to estimate again
    /// ([`ExecutiveOptions::history`]; 0: none).
    pub fn history(mut self, steps: usize) -> Self {
        self.options.history = steps;
        self
    }

    /// Sets which occasions re-run mode estimation's history window
    /// ([`ExecutiveOptions::rerun`]).
    pub fn rerun(mut self, rerun: Rerun) -> Self {
        self.options.rerun = rerun;
        self
    }

    /// Sets the wall-time deadline of a cycle.
    pub fn cycle_deadline(mut self, deadline: Duration) -> Self {
        self.options.cycle_deadline = Some(deadline);
        self
    }

    /// Sets OPSAT's budget for mode estimation.
    pub fn estimation_budget(mut self, budget: Budget) -> Self {
        self.options.estimation_budget = budget;
        self
    }

    /// Sets the time after a cycle's start by which mode estimation stops
    /// ([`ExecutiveOptions::estimation_deadline`]).
    pub fn estimation_deadline(mut self, deadline: Duration) -> Self {
        self.options.estimation_deadline = Some(deadline);
        self
    }

    /// Sets how much history the timelines keep.
    pub fn retention(mut self, retention: Retention) -> Self {
        self.options.retention = retention;
        self
    }

    /// Sets how the executive acts when the goal is unreachable from ŝ but not from another
    /// tracked plant state.
    pub fn ambiguity(mut self, ambiguity: AmbiguityOptions) -> Self {
        self.options.ambiguity = ambiguity;
        self
    }

    /// Sets N of the `Chatter` event: how many cycles a component must stay out of a mode it
    /// was commanded out of before a command back into it is not chatter.
    pub fn chatter_cycles(mut self, cycles: u64) -> Self {
        self.options.chatter_cycles = cycles;
        self
    }

    /// Sets every option at once.
    pub fn options(mut self, options: ExecutiveOptions) -> Self {
        self.options = options;
        self
    }

    /// Encodes the plant, compiles the reconfiguration policies and marks the program's start
    /// locations.
    pub fn build(self) -> Result<Executive, BuildError> {
        let ExecutiveBuilder {
            plant,
            program,
            options,
            source,
        } = self;
        check_linked(&plant, program.table())?;
        let theory = plant.theory()?;
        let reconfiguration = Reconfiguration::compile(&plant)?;
        let estimation = TimedMeOptions {
            budget: options.estimation_budget,
            history: options.history,
            rerun: options.rerun,
            ..TimedMeOptions::kappa(options.kappa)
        };
        let confidence_atoms = program.confidence_atoms();
        let observables = plant.observables().to_vec();
        let timelines = Timelines::new(plant.components().len(), &observables, options.retention);
        Ok(Executive {
            last_command: Commands::idle(&plant),
            theory,
            reconfiguration,
            estimator: TimedMe::new(estimation),
            control: program,
            source,
            options,
            belief: None,
            most_likely: Arc::from([]),
            estimates: Vec::new(),
            grouping: PlantGrouping::default(),
            marginals: Vec::new(),
            estimate: VersionedEstimate::default(),
            observed: LastObservation::default(),
            monitoring: Monitoring::new(&plant),
            answers: AnswerCache::default(),
            interpretation: None,
            ambiguity: Ambiguity::default(),
            intended: None,
            intended_settled_on: None,
            faithful: Faithful::new(plant.components().len()),
            reported: Reported::default(),
            confidence_atoms,
            timelines,
            cycle: 0,
            last_time: None,
            submission_time: Duration::ZERO,
            plant,
        })
    }
}

/// The program's table must be the plant's, with clocks added (`rmpl::LinkOptions::plant`); a
/// mission's is its plant's.
fn check_linked(plant: &Plant, theirs: &VarTable) -> Result<(), BuildError> {
    let ours = plant.table();
    for (id, variable) in ours.variables() {
        let same = id.index() < theirs.len() && theirs.variable(id) == variable;
        if !same {
            return Err(BuildError::NotLinkedToPlant(variable.name().to_string()));
        }
    }
    if theirs.len() != ours.len() {
        let extra = theirs.variable(VarId(ours.len() as u32)).name().to_string();
        return Err(BuildError::NotLinkedToPlant(extra));
    }
    Ok(())
}
