//! The `acknowledgements:` section of a plant file: the observable that reports flight
//! software's answer to each control's last command ([`crate::plant::acknowledgement`] has the
//! semantics).
//!
//! ```ron
//! // PDE's attributes include "ack": ["none", "accepted", "rejected"]
//! acknowledgements: { "PDE.cmd": "PDE.ack" },
//! ```
//! The key is a control, the value an attribute of some component, neither a control nor an
//! observable, answering for no other control, with the values `none`, `accepted` and
//! `rejected` and optionally `completed` and `failed` (no other), and mentioned by no constraint,
//! guard or connection (it is evidence about the command, not about a mode). An indexed key
//! pairs with an indexed value of as many names (`"valve[1..4].cmd": "valve[1..4].ack"`).

use std::collections::HashSet;

use super::Loader;
use crate::diagnostic::locate::{Entries, Step};
use crate::logic::{Formula, VarId};
use crate::plant::{Acknowledgement, Answer, Component, Control};

impl Loader {
    /// The acknowledgement observables, checked against the controls and observables.
    pub(super) fn acknowledgements(
        &mut self,
        file: &Entries<String>,
        controls: &[Control],
        observables: &[VarId],
    ) -> Vec<Acknowledgement> {
        let mut out: Vec<Acknowledgement> = Vec::new();
        for (written, observable) in &file.0 {
            let key = [Step::Field("acknowledgements"), Step::Key(written)];
            let value = [Step::Field("acknowledgements"), Step::Value(written)];
            let (Some(keys), Some(values)) = (
                self.indexed(&key, written),
                self.indexed(&value, observable),
            ) else {
                continue;
            };
            if keys.len() != values.len() {
                let message = format!(
                    "`{written}` names {} controls but `{observable}` {} observables",
                    keys.len(),
                    values.len()
                );
                self.error(&value, message, "as many acknowledgements as controls");
                continue;
            }
            for (control, observable) in keys.iter().zip(&values) {
                let control = self.attribute(&key, control, "acknowledged");
                let observable = self.attribute(&value, observable, "an acknowledgement");
                let (Some(control), Some(observable)) = (control, observable) else {
                    continue;
                };
                let name = |var: VarId| self.table.variable(var).name().to_string();
                let problem = if controls.iter().all(|c| c.var != control) {
                    let message = format!("`{}` is acknowledged but not a control", name(control));
                    Some((&key, message, "a control listed in `controls`"))
                } else if out.iter().any(|a| a.control == control) {
                    let message = format!("`{}` is acknowledged twice", name(control));
                    Some((&key, message, "one acknowledgement per control"))
                } else if out.iter().any(|a| a.observable == observable) {
                    let message =
                        format!("`{}` already answers for another control", name(observable));
                    Some((&value, message, "an acknowledgement observable per control"))
                } else if controls.iter().any(|c| c.var == observable)
                    || observables.contains(&observable)
                {
                    let message = format!(
                        "`{}` is an acknowledgement, so it cannot also be a control or an observable",
                        name(observable)
                    );
                    Some((&value, message, "an attribute kept for the answer alone"))
                } else {
                    None
                };
                match problem {
                    Some((path, message, expected)) => self.error(path, message, expected),
                    None => out.extend(self.acknowledgement(&value, control, observable)),
                }
            }
        }
        out
    }

    /// The acknowledgement of `control` by `observable` (written at `path`), if the
    /// observable's values are answers, the required ones among them.
    fn acknowledgement(
        &mut self,
        path: &[Step],
        control: VarId,
        observable: VarId,
    ) -> Option<Acknowledgement> {
        let variable = self.table.variable(observable);
        let values = variable.values();
        let answers: Vec<Option<Answer>> = values.iter().map(|v| Answer::named(v)).collect();
        let missing: Vec<&str> = (Answer::REQUIRED.into_iter())
            .filter(|name| !values.iter().any(|v| v == name))
            .collect();
        let foreign: Vec<&str> = (values.iter().zip(&answers))
            .filter(|(_, answer)| answer.is_none())
            .map(|(v, _)| v.as_str())
            .collect();
        if missing.is_empty() && foreign.is_empty() {
            let answers = answers.into_iter().flatten().collect();
            return Some(Acknowledgement::new(control, observable, answers));
        }
        let name = variable.name();
        let problem = if missing.is_empty() {
            format!(
                "`{name}` has values that are not answers: {}",
                foreign.join(", ")
            )
        } else {
            format!("`{name}` lacks the answers {}", missing.join(", "))
        };
        let expected = "an attribute with the values none, accepted, rejected, and optionally completed, failed";
        self.error(path, problem, expected);
        None
    }

    /// Refuses a constraint, guard or connection that mentions an acknowledgement observable.
    pub(super) fn refuse_acknowledgements_in_constraints(
        &mut self,
        acknowledgements: &[Acknowledgement],
        components: &[Component],
        connections: &[Formula],
    ) {
        if acknowledgements.is_empty() {
            return;
        }
        let answers: HashSet<VarId> = acknowledgements.iter().map(|a| a.observable).collect();
        let formulas = components
            .iter()
            .flat_map(|c| {
                let modes = c.modes().iter().map(|m| &m.constraint);
                modes.chain(c.transitions().iter().map(|t| &t.guard))
            })
            .chain(connections);
        let mut mentioned: Vec<VarId> = formulas
            .flat_map(Formula::variables)
            .filter(|v| answers.contains(v))
            .collect();
        mentioned.sort_unstable();
        mentioned.dedup();
        for var in mentioned {
            let name = self.table.variable(var).name();
            let message = format!("`{name}` is an acknowledgement, but a constraint mentions it");
            let expected = "no constraint, guard or connection on an acknowledgement: it is evidence about the command, not about a mode";
            self.error(&[Step::Field("acknowledgements")], message, expected);
        }
    }
}
