//! Goals over a state variable's attributes and derived states (DESIGN.md §15.1; the constraint
//! language RMPL goals use): `payload.current = nominal` on the SV `payload` admits the modes
//! of `payload` whose constraints, with the model, *entail* it — whatever the other components
//! do. A mode that merely allows it (the attribute also depends on components upstream) is not
//! admitted: the goal would not be guaranteed by holding the SV's mode. When no mode entails
//! it, the goal cannot be a constraint on this SV and the loader says how to write it instead.

use crate::logic::{Formula, ValueId};
use crate::opsat::Literal;
use crate::plant::{ComponentId, Plant};

/// Why a formula cannot be read as a constraint on the SV's modes: the message and what was
/// expected, for a located error.
pub(super) struct Refused {
    pub message: String,
    pub expected: String,
}

/// Per mode of `sv`, whether it admits `formula` (over `sv`'s mode and attributes): the mode
/// entails it under the model.
pub(super) fn admitted(
    plant: &Plant,
    sv: ComponentId,
    formula: &Formula,
) -> Result<Vec<bool>, Refused> {
    let component = plant.component(sv);
    let name = component.name();
    let own = |x| x == component.mode_var() || component.attributes().contains(&x);
    if let Some(&other) = formula.variables().iter().find(|&&x| !own(x)) {
        return Err(Refused {
            message: format!(
                "a goal on `{name}` may only constrain `{name}` and its attributes, not `{}`",
                plant.table().variable(other).name()
            ),
            expected: format!(
                "a formula over `{name} = mode` and `{name}.attribute = value` atoms; a goal on \
                 another component goes on that component's state variable"
            ),
        });
    }
    let refused = |why: String| Refused {
        message: why,
        expected: format!("a constraint on `{name}`'s modes, or on what its modes decide"),
    };
    let mut theory = plant
        .theory()
        .map_err(|e| refused(format!("the model cannot be encoded: {e}")))?;
    let admitted = (0..component.modes().len() as u32)
        .map(|v| {
            let mode = [Literal::Is(component.mode_var(), ValueId(v))];
            theory.entails(&mode, formula)
        })
        .collect::<Result<Vec<bool>, _>>()
        .map_err(|e| refused(format!("the goal cannot be checked against the model: {e}")))?;
    if admitted.iter().any(|&a| a) {
        Ok(admitted)
    } else {
        Err(refused(format!(
            "no mode of `{name}` guarantees this: it depends on other components (write the goal \
             on the state variables that decide it, or as `{name} = mode`)"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::admitted;
    use crate::diagnostic::Source;
    use crate::logic::parse_formula;
    use crate::plant::Plant;

    fn power() -> Plant {
        let path = format!("{}/models/power.ron", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("the power model is shipped");
        Plant::load(&Source::new(path, text)).expect("it loads")
    }

    /// A derived state the SV's modes decide is admitted by exactly those modes; one that
    /// depends on other components is refused with how to write it.
    #[test]
    fn an_attribute_goal_admits_the_modes_that_entail_it() {
        let plant = power();
        let payload = plant.component_named("payload").expect("payload");
        let current = parse_formula("payload.current = nominal", plant.table()).expect("formula");
        let modes = admitted(&plant, payload, &current).ok().expect("admitted");
        let powered = plant
            .component(payload)
            .mode_named("powered")
            .expect("mode");
        let names: Vec<usize> = (0..modes.len()).filter(|&v| modes[v]).collect();
        assert_eq!(names, [powered.index()]);
        let switch = plant.component_named("load_switch").expect("switch");
        let out = parse_formula("load_switch.out = nominal", plant.table()).expect("formula");
        let refused = admitted(&plant, switch, &out).expect_err("refused");
        assert!(
            refused.message.contains("depends on other components"),
            "{}",
            refused.message
        );
        let other = parse_formula("bus.voltage = nominal", plant.table()).expect("formula");
        let refused = admitted(&plant, switch, &other).expect_err("refused");
        assert!(
            refused.message.contains("not `bus.voltage`"),
            "{}",
            refused.message
        );
    }
}
