//! The plant's names as C strings, made once when the handle is created and shared (by `Arc`)
//! with every step it returns: a step's commands, modes and estimates are then indices into this
//! table, and reading them costs no allocation. A step holds its own reference, so it stays
//! readable after its handle is freed.

use std::ffi::{CString, c_char};
use std::ptr;

use kairos::logic::{ValueId, VarId};
use kairos::plant::Plant;

use crate::raw::c_string;

/// `variable = value` as two C strings owned by the step (or the handle) it came from; both
/// NULL when the index asked for is out of range.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct KairosNamedValue {
    /// The variable (`PDE.cmd`) or the component (`valve1`).
    pub variable: *const c_char,
    /// Its value (`open1`) or mode (`stuck-closed`).
    pub value: *const c_char,
}

impl KairosNamedValue {
    pub(crate) const NONE: KairosNamedValue = KairosNamedValue {
        variable: ptr::null(),
        value: ptr::null(),
    };
}

/// A name and the names of its values.
struct Named {
    name: CString,
    values: Vec<CString>,
}

impl Named {
    fn get(&self, value: u32) -> KairosNamedValue {
        match self.values.get(value as usize) {
            Some(v) => KairosNamedValue {
                variable: self.name.as_ptr(),
                value: v.as_ptr(),
            },
            None => KairosNamedValue::NONE,
        }
    }
}

/// Every variable with its values, and every component with its modes, in the plant's order.
pub(crate) struct Names {
    variables: Vec<Named>,
    components: Vec<Named>,
}

impl Names {
    pub(crate) fn new(plant: &Plant) -> Names {
        let table = plant.table();
        let variables = (0..table.len() as u32)
            .map(|v| {
                let variable = table.variable(VarId(v));
                Named {
                    name: c_string(variable.name()),
                    values: variable.values().iter().map(|s| c_string(s)).collect(),
                }
            })
            .collect();
        let components = (plant.components().iter())
            .map(|c| Named {
                name: c_string(c.name()),
                values: c.modes().iter().map(|m| c_string(&m.name)).collect(),
            })
            .collect();
        Names {
            variables,
            components,
        }
    }

    /// `variable = value`.
    pub(crate) fn assignment(&self, (var, value): (VarId, ValueId)) -> KairosNamedValue {
        (self.variables.get(var.index())).map_or(KairosNamedValue::NONE, |v| v.get(value.0))
    }

    /// `component = mode`.
    pub(crate) fn mode(&self, component: usize, mode: ValueId) -> KairosNamedValue {
        (self.components.get(component)).map_or(KairosNamedValue::NONE, |c| c.get(mode.0))
    }

    /// How many components the plant has.
    pub(crate) fn components(&self) -> usize {
        self.components.len()
    }
}
