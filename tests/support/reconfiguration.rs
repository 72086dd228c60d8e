//! Helpers for the mode reconfiguration tests: loading models, writing states and goals by
//! name, running goal interpretation and the nominal planner. Included with `#[path]` by the
//! `reconfiguration_*` tests and the benchmarks.
#![allow(dead_code)] // each includer uses a different part

use kairos::diagnostic::Source;
use kairos::logic::{Formula, ValueId, parse_formula};
use kairos::opsat::Theory;
use kairos::plant::Plant;
use kairos::reconfiguration::{Action, GoalState, NominalRun, Reconfiguration};

/// `models/NAME.ron`, loaded.
pub fn model(name: &str) -> Plant {
    let path = format!("{}/models/{name}.ron", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    plant_from(&path, &text)
}

/// A plant from RON text.
pub fn plant_from(name: &str, text: &str) -> Plant {
    Plant::load(&Source::new(name, text)).unwrap_or_else(|e| panic!("{e}"))
}

/// A plant, its compiled reconfiguration and its theory.
pub struct Setup {
    pub plant: Plant,
    pub reconfiguration: Reconfiguration,
    pub theory: Theory,
}

impl Setup {
    pub fn new(plant: Plant) -> Setup {
        let reconfiguration = Reconfiguration::compile(&plant).expect("compiles");
        let theory = plant.theory().expect("theory");
        Setup {
            plant,
            reconfiguration,
            theory,
        }
    }

    pub fn model(name: &str) -> Setup {
        Setup::new(model(name))
    }

    /// A state from `component = mode` pairs; other components in their first initial mode.
    pub fn state(&self, named: &[(&str, &str)]) -> Vec<ValueId> {
        self.plant
            .components()
            .iter()
            .map(|c| {
                match named.iter().find(|(n, _)| *n == c.name()) {
                    Some((_, m)) => c.mode_named(m),
                    None => c
                        .initial()
                        .iter()
                        .position(|&p| p > 0.0)
                        .map(|i| ValueId(i as u32)),
                }
                .unwrap_or_else(|| panic!("no mode for `{}`", c.name()))
            })
            .collect()
    }

    /// One component's mode by name.
    pub fn mode(&self, component: &str, mode: &str) -> ValueId {
        let id = self.plant.component_named(component).expect(component);
        self.plant.component(id).mode_named(mode).expect(mode)
    }

    /// The mode names of a state, `component = mode, ...`.
    pub fn describe(&self, modes: &[ValueId]) -> String {
        kairos::plant::describe_modes(&self.plant, modes)
    }

    pub fn formula(&self, text: &str) -> Formula {
        parse_formula(text, self.plant.table()).unwrap_or_else(|e| panic!("{e:?}"))
    }

    /// Goal interpretation from `state` for the goal `text`.
    pub fn interpret(
        &mut self,
        state: &[ValueId],
        text: &str,
    ) -> Result<GoalState, kairos::reconfiguration::GoalFailed> {
        let goal = self.formula(text);
        self.reconfiguration
            .interpret(&mut self.theory, state, &goal)
    }

    /// Goal interpretation from `state`, keeping unnamed components in the modes of `keep`.
    pub fn interpret_keeping(
        &mut self,
        state: &[ValueId],
        text: &str,
        keep: &[ValueId],
    ) -> Result<GoalState, kairos::reconfiguration::GoalFailed> {
        let goal = self.formula(text);
        self.reconfiguration
            .interpret_keeping(&mut self.theory, state, &goal, keep)
    }

    /// The nominal run from `state` to `goal`.
    pub fn run(&mut self, state: &[ValueId], goal: &GoalState) -> NominalRun {
        self.reconfiguration
            .simulate_nominal(&mut self.theory, state, goal, 100)
            .expect("simulates")
    }

    /// The actions of a run, described.
    pub fn actions(&self, run: &NominalRun) -> Vec<String> {
        run.steps
            .iter()
            .map(|s| s.action.describe(&self.plant))
            .collect()
    }

    /// The planner's next action, described.
    pub fn next(&self, state: &[ValueId], goal: &GoalState) -> String {
        self.reconfiguration
            .next_action(state, goal)
            .describe(&self.plant)
    }

    pub fn next_action(&self, state: &[ValueId], goal: &GoalState) -> Action {
        self.reconfiguration.next_action(state, goal)
    }
}
