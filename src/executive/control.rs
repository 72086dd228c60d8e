//! The executive's control program (DESIGN.md §3 step 3, §15.3): an RMPL program, whose THCA the
//! sequencer runs, or a mission, whose scheduled goal network is fired and monitored. Either one
//! answers the cycle's question — what is the configuration goal now? — from ŝ.

use super::mission::{MissionControl, ScheduledMission};
use crate::goalnet::{ExecutableNetwork, Mission};
use crate::logic::{Atom, Formula, ValueId, VarId, VarTable};
use crate::sequencer::{LocationId, Sequencer, Thca};

/// What an executive runs: build one from a linked [`Thca`] or a [`ScheduledMission`]
/// (`Executive::builder(plant, thca)` and `Executive::builder(plant, scheduled)` both convert).
#[derive(Debug, Clone)]
pub struct ControlProgram(pub(super) Program);

/// The two kinds of control program.
#[derive(Debug, Clone)]
pub(super) enum Program {
    /// RMPL: the sequencer over the program's THCA (boxed, as the mission: the two differ in
    /// size and a program is moved only when it is built).
    Rmpl(Box<Sequencer>),
    /// A goal network and its execution state.
    Mission(Box<MissionControl>),
}

impl From<Thca> for ControlProgram {
    fn from(thca: Thca) -> Self {
        ControlProgram(Program::Rmpl(Box::new(Sequencer::new(thca))))
    }
}

impl From<ScheduledMission> for ControlProgram {
    fn from(mission: ScheduledMission) -> Self {
        ControlProgram(Program::Mission(Box::new(MissionControl::new(mission))))
    }
}

impl ControlProgram {
    /// The RMPL program's automaton (`None` for a mission).
    pub fn thca(&self) -> Option<&Thca> {
        match &self.0 {
            Program::Rmpl(sequencer) => Some(sequencer.thca()),
            Program::Mission(_) => None,
        }
    }

    /// The mission as loaded (`None` for an RMPL program).
    pub fn mission(&self) -> Option<&Mission> {
        match &self.0 {
            Program::Rmpl(_) => None,
            Program::Mission(control) => Some(control.mission()),
        }
    }

    /// The mission's network as it is being executed: windows shrink as points fire (`None` for
    /// an RMPL program).
    pub fn executable(&self) -> Option<&ExecutableNetwork> {
        match &self.0 {
            Program::Rmpl(_) => None,
            Program::Mission(control) => Some(control.executable()),
        }
    }

    /// True once the program has completed: no RMPL location is marked, or every time point of
    /// the mission has fired.
    pub fn is_complete(&self) -> bool {
        match &self.0 {
            Program::Rmpl(sequencer) => sequencer.is_complete(),
            Program::Mission(control) => control.is_complete(),
        }
    }

    /// Feeds the program's state to `state` (`Executive::fingerprint`).
    pub(super) fn fingerprint<H: std::hash::Hasher>(&self, state: &mut H) {
        match &self.0 {
            Program::Rmpl(sequencer) => sequencer.fingerprint(state),
            Program::Mission(control) => control.fingerprint(state),
        }
    }

    /// The marked program locations (none for a mission).
    pub(super) fn marking(&self) -> Vec<LocationId> {
        match &self.0 {
            Program::Rmpl(sequencer) => sequencer.marking().map(|l| l.id).collect(),
            Program::Mission(_) => Vec::new(),
        }
    }

    /// The variables the program was resolved against (checked against the plant's).
    pub(super) fn table(&self) -> &VarTable {
        match &self.0 {
            Program::Rmpl(sequencer) => sequencer.thca().table(),
            Program::Mission(control) => control.mission().plant.table(),
        }
    }

    /// The (variable, value) pairs the program's confidence atoms `P(x = v) op p` read (a
    /// mission's knowledge goals read the belief directly: none).
    pub(super) fn confidence_atoms(&self) -> Vec<(VarId, ValueId)> {
        let Program::Rmpl(sequencer) = &self.0 else {
            return Vec::new();
        };
        let mut pairs: Vec<(VarId, ValueId)> = sequencer
            .thca()
            .formulas()
            .iter()
            .flat_map(Formula::atoms)
            .filter_map(|atom| match atom {
                Atom::Confidence { var, value, .. } => Some((*var, *value)),
                _ => None,
            })
            .collect();
        pairs.sort_unstable();
        pairs.dedup();
        pairs
    }
}
