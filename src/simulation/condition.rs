//! Conditions on one cycle of a run, for the invariant expectation `Always(that: …)`: what the
//! scripted plant truly holds, what the executive believes, what it reports, which mission goals
//! are active — combined with `Not`, `All`, `Any`, `Implies`, and `Once` (held at some cycle so
//! far: the past-time "once" of temporal logic, so that an invariant can speak of what came
//! before, such as "since the device was first warm").
//!
//! `Always` is checked at every cycle of a run and, by `kairos explore`, on every path: "no
//! path safes while a working heater could keep the device warm" is
//! `Always(that: Implies(Reported(Safing), Not(Plant("…a heater works…"))))`.
//!
//! Every `Once` is evaluated at every cycle, whatever the connectives around it decide, so that
//! its memory does not depend on short-circuits; the memory is one flag per `Once`, part of the
//! checker's state (and of exploration's fingerprint).

use super::format::EventName;
use crate::executive::{Event, Step};
use crate::logic::{Formula, ValueId, VarId, VarTable};
use crate::plant::Plant;

/// A condition on one cycle (the format is documented in [`crate::simulation`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Condition {
    /// The scripted plant's true values (observables and hidden variables) satisfy the formula.
    Plant(Formula),
    /// ŝ satisfies the formula (over mode variables).
    Estimated(Formula),
    /// An event of this kind is reported in the cycle.
    Reported(EventName),
    /// An XGoal merging this mission goal (by name) is active after the cycle.
    Active(String),
    /// The condition does not hold.
    Not(Box<Condition>),
    /// Every condition holds (true when there is none).
    All(Vec<Condition>),
    /// Some condition holds (false when there is none).
    Any(Vec<Condition>),
    /// The second holds when the first does.
    Implies(Box<Condition>, Box<Condition>),
    /// The condition held at this cycle or an earlier one; `slot` is its memory's index.
    Once {
        /// The condition.
        condition: Box<Condition>,
        /// Its flag in the expectation's memory.
        slot: usize,
    },
}

/// What a condition is judged on: one cycle and what the run keeps.
pub(crate) struct Cycle<'a> {
    /// The plant model (ŝ's variables).
    pub(crate) plant: &'a Plant,
    /// The scripted plant's variables.
    pub(crate) world: &'a VarTable,
    /// The executive's cycle.
    pub(crate) step: &'a Step,
    /// The scripted plant's value of an observable or hidden variable.
    pub(crate) held: &'a dyn Fn(VarId) -> Option<ValueId>,
    /// Whether an XGoal merging this goal is active.
    pub(crate) active: &'a dyn Fn(&str) -> bool,
    /// Whether an event is of this kind.
    pub(crate) is: fn(EventName, &Event) -> bool,
}

impl Condition {
    /// How many `Once` flags its memory needs.
    pub fn slots(&self) -> usize {
        match self {
            Condition::Plant(_)
            | Condition::Estimated(_)
            | Condition::Reported(_)
            | Condition::Active(_) => 0,
            Condition::Not(c) => c.slots(),
            Condition::All(cs) | Condition::Any(cs) => cs.iter().map(Condition::slots).sum(),
            Condition::Implies(a, b) => a.slots() + b.slots(),
            Condition::Once { condition, .. } => 1 + condition.slots(),
        }
    }

    /// Whether it holds at `cycle`, updating the `Once` flags in `memory`.
    pub(crate) fn holds(&self, cycle: &Cycle<'_>, memory: &mut [bool]) -> bool {
        match self {
            Condition::Plant(formula) => {
                formula.eval_assignment(cycle.world, &|var| (cycle.held)(var)) == Some(true)
            }
            Condition::Estimated(formula) => {
                let plant = cycle.plant;
                let modes = &cycle.step.most_likely;
                let mode = |var: VarId| {
                    let component = plant.component_of(var)?;
                    (plant.component(component).mode_var() == var)
                        .then(|| modes.get(component.index()).copied())
                        .flatten()
                };
                formula.eval_assignment(cycle.world, &mode) == Some(true)
            }
            Condition::Reported(name) => cycle.step.events.iter().any(|e| (cycle.is)(*name, e)),
            Condition::Active(goal) => (cycle.active)(goal),
            Condition::Not(c) => !c.holds(cycle, memory),
            // Every member is evaluated (collected first, no short-circuit), so every `Once`
            // below keeps count.
            Condition::All(cs) => {
                let held: Vec<bool> = cs.iter().map(|c| c.holds(cycle, memory)).collect();
                held.iter().all(|h| *h)
            }
            Condition::Any(cs) => {
                let held: Vec<bool> = cs.iter().map(|c| c.holds(cycle, memory)).collect();
                held.iter().any(|h| *h)
            }
            Condition::Implies(a, b) => {
                let (a, b) = (a.holds(cycle, memory), b.holds(cycle, memory));
                !a || b
            }
            Condition::Once { condition, slot } => {
                let now = condition.holds(cycle, memory);
                match memory.get_mut(*slot) {
                    Some(flag) => {
                        *flag |= now;
                        *flag
                    }
                    None => now,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    //! `Once` keeps its memory whatever the connectives around it decide.

    use super::*;
    use crate::simulation::testing::engine_camera;

    /// `All([Reported(Diagnosis), Once(Estimated("engine = off"))])`: at the first cycle the
    /// first member is false, yet `Once` notes that the engine is off; at a later cycle, the
    /// engine no longer off, `Once` still holds.
    #[test]
    fn once_is_evaluated_under_a_false_member() {
        let scenario = engine_camera("");
        let plant = &scenario.plant;
        let world = &scenario.script.world;
        let engine = plant.component_named("engine").unwrap();
        let mode = |name| plant.component(engine).mode_named(name).unwrap();
        let off = Formula::is(plant.component(engine).mode_var(), mode("off"));
        let condition = Condition::All(vec![
            Condition::Reported(EventName::Diagnosis),
            Condition::Once {
                condition: Box::new(Condition::Estimated(off)),
                slot: 0,
            },
        ]);
        let once = match &condition {
            Condition::All(members) => members[1].clone(),
            _ => unreachable!(),
        };
        let mut memory = vec![false; condition.slots()];
        let step = |modes: Vec<ValueId>| Step {
            cycle: 0,
            time: 0.0,
            command: Vec::new(),
            goal: None,
            goal_state: None,
            action: None,
            most_likely: modes.into(),
            estimates: Vec::new(),
            distance_bound: 0.0,
            marking: Vec::new(),
            events: Vec::new(),
            monitored: Vec::new(),
            completed: false,
            times: Default::default(),
        };
        let camera = plant.component_named("camera").unwrap();
        let camera_off = plant.component(camera).mode_named("off").unwrap();
        let mut modes = vec![ValueId(0); plant.components().len()];
        modes[engine.index()] = mode("off");
        modes[camera.index()] = camera_off;
        let first = step(modes.clone());
        let cycle = |step| Cycle {
            plant,
            world,
            step,
            held: &|_| None,
            active: &|_| false,
            is: |name, event| EventName::of(&event.kind) == name,
        };
        assert!(!condition.holds(&cycle(&first), &mut memory));
        assert_eq!(memory, [true], "noted under the false first member");
        modes[engine.index()] = mode("heating");
        let later = step(modes);
        assert!(once.holds(&cycle(&later), &mut memory), "remembered");
    }
}
