//! The constraint language (DESIGN.md §4; thesis §5.1.1): finite-domain variables, clocks,
//! formulas, and their parser. Reference for users: `docs/reference/constraint-language.md`.
//!
//! Text goes through two stages: [`syntax`] parses it into an [`Expr`] that still holds names and
//! spans; [`resolve`] checks every name against a [`VarTable`] and yields a [`Formula`] that refers
//! to variables and values by id. Plant models, OCSP files and RMPL programs all use this one
//! grammar (`grammar/constraint.pest`).

mod formula;
mod resolve;
pub mod syntax;
mod vars;

pub use formula::{Atom, Formula, FormulaDisplay, Number};
pub use resolve::{parse_formula, resolve};
pub use syntax::{CmpOp, Expr, ExprKind};
pub use vars::{
    Assignment, ClockId, DeclarationError, ValueId, VarId, VarTable, Variable, is_name,
    is_value_name,
};
