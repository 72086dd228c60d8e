//! Latent faults of the model-driven plant: whether a fault it drew could yet have been seen.
//!
//! A campaign counts a fault that was never diagnosed as a miss. Some never can be: a valve
//! that sticks closed while it is closed shows nothing until it is commanded open, a fault of a
//! component that is switched off shows nothing until it is switched on — and a run may end
//! before that. Those faults are *latent*, and a summary that counted them as missed
//! diagnoses would blame the estimator for the model's (or the run's) unobservability.
//!
//! # The counterfactual
//! When a component enters a fault mode, the plant starts a *nominal shadow* of the whole
//! system: the state it would be in had that fault not happened. The shadow starts as the
//! state before the fault. Each cycle, every component of the shadow takes a step under the
//! command the plant received:
//! - if the shadow component is where the true one was (same mode, same clock) and its
//!   distribution over next modes (Step_TCCA, the numbers the plant draws from) is the true
//!   one's, the fault changed nothing for it this cycle, and it follows the true component —
//!   whatever the truth drew, a timed transition at a random moment or another fault;
//! - otherwise — the faulty component itself, always, or one whose guards the fault changed (a valve
//!   the faulty driver no longer commands) — it takes its most probable nominal transition
//!   (staying on a tie).
//!
//! So a stuck-closed valve's shadow opens when `open` is commanded, the valve behind a failed
//! driver opens in the shadow of the driver's fault, and an unrelated engine heats in the shadow
//! exactly as it does in truth. The fault is *revealed* at the first cycle whose observation
//! (drawn before noise, so that noise reveals nothing) the plant's theory finds inconsistent
//! with the shadow's modes. Until then, what was observed is what the expected nominal system
//! would have shown. A fault whose component leaves the fault mode (a repair, a second fault)
//! before it is revealed stays unrevealed and is no longer followed.

use std::sync::Arc;

use super::model_cache::ModelCache;
use super::model_plant::FaultDrawn;
use crate::logic::{ValueId, VarId};
use crate::opsat::{Consistency, Literal, Theory};
use crate::plant::{Commands, ComponentId, ModeKind, Plant, SystemState, component_distribution};

/// What the shadow of a fault needs from the model-driven plant in one cycle.
pub(super) struct World<'a> {
    /// The plant model.
    pub(super) plant: &'a Plant,
    /// Its theory.
    pub(super) theory: &'a mut Theory,
    /// The plant's cache of enabled transitions and observation assumptions.
    pub(super) cache: &'a mut ModelCache,
    /// The command the plant received for this step.
    pub(super) commands: &'a Commands,
}

/// A fault that nothing observed has shown yet.
pub(super) struct Latent {
    /// Its index in the plant's fault list.
    pub(super) fault: usize,
    /// The component.
    component: ComponentId,
    /// The nominal shadow of the system.
    shadow: SystemState,
    /// The last shadow modes and observation checked: a quiet cycle asks the theory nothing
    /// again.
    checked: Option<Checked>,
}

/// Shadow modes and an observation found consistent together.
type Checked = (Vec<ValueId>, Vec<(VarId, ValueId)>);

/// What a cycle showed of a latent fault.
pub(super) enum Verdict {
    /// Still not observable.
    Latent,
    /// The observation contradicts the nominal shadow.
    Revealed,
    /// The component left the fault mode before anything showed it.
    Over,
}

impl Latent {
    /// A fault, the `fault`th the plant drew, of `component`, entered in the step from
    /// `before`.
    pub(super) fn new(fault: usize, component: ComponentId, before: &SystemState) -> Latent {
        Latent {
            fault,
            component,
            shadow: before.clone(),
            checked: None,
        }
    }

    /// Steps the shadow from `before` to `now` over `(from, to)` seconds and judges
    /// `observation`, drawn in `now` before noise.
    pub(super) fn step(
        &mut self,
        world: &mut World<'_>,
        fault: &FaultDrawn,
        (before, now): (&SystemState, &SystemState),
        observation: &[(VarId, ValueId)],
        (from, to): (f64, f64),
    ) -> Verdict {
        if now.modes[self.component.index()] != fault.mode {
            return Verdict::Over;
        }
        if self.advance(world, (before, now), (from, to)).is_err() {
            // A guard the theory cannot decide fails the plant's own step too, which reports
            // it; the shadow learns nothing this cycle.
            return Verdict::Latent;
        }
        let mut observed = observation.to_vec();
        observed.sort_unstable();
        let modes = &self.shadow.modes;
        if (self.checked.as_ref()).is_some_and(|(m, o)| m[..] == modes[..] && *o == observed) {
            return Verdict::Latent;
        }
        let mut assumed = (world.cache)
            .observations(world.plant, world.theory, modes, world.commands)
            .assumed
            .clone();
        assumed.extend(observed.iter().map(|&(var, value)| Literal::Is(var, value)));
        if world.theory.consistent(&assumed) == Consistency::Consistent {
            self.checked = Some((modes.to_vec(), observed));
            Verdict::Latent
        } else {
            Verdict::Revealed
        }
    }

    /// One step of the shadow (see the module documentation), from the true `before` to the
    /// true `now` over `(from, to)`.
    fn advance(
        &mut self,
        world: &mut World<'_>,
        (before, now): (&SystemState, &SystemState),
        (from, to): (f64, f64),
    ) -> Result<(), String> {
        let truth = (world.cache)
            .enabled(world.plant, world.theory, &before.modes, world.commands)?
            .to_vec();
        let shadow = (world.cache).enabled(
            world.plant,
            world.theory,
            &self.shadow.modes,
            world.commands,
        )?;
        let mut next = self.shadow.clone();
        let (next_modes, next_starts) = (
            Arc::make_mut(&mut next.modes),
            Arc::make_mut(&mut next.clock_starts),
        );
        for (id, component) in world.plant.component_ids() {
            let c = id.index();
            let (mode, clock) = (self.shadow.modes[c], self.shadow.clock(id, from));
            let expected = component_distribution(component, mode, &shadow[c], clock, to - from);
            // The faulty component never follows the truth: the shadow is the world in which
            // its fault did not happen.
            let undisturbed = id != self.component
                && mode == before.modes[c]
                && self.shadow.clock_starts[c] == before.clock_starts[c]
                && expected
                    == component_distribution(
                        component,
                        before.modes[c],
                        &truth[c],
                        before.clock(id, from),
                        to - from,
                    );
            if undisturbed {
                next_modes[c] = now.modes[c];
                next_starts[c] = now.clock_starts[c];
                continue;
            }
            let likeliest = (expected.iter())
                .filter(|&&(target, _)| component.mode(target).kind != ModeKind::Fault)
                .max_by(|a, b| {
                    a.1.total_cmp(&b.1)
                        .then_with(|| (a.0 == mode).cmp(&(b.0 == mode)))
                });
            if let Some(&(target, _)) = likeliest
                && target != mode
            {
                next_modes[c] = target;
                next_starts[c] = Some(to);
            }
        }
        self.shadow = next;
        Ok(())
    }
}
