//! OPSAT: optimal constraint satisfaction by conflict-directed A* (DESIGN.md §7; thesis §6.2.3,
//! §6.3.1; Williams & Ragno, "Conflict-directed A* and its role in model-based embedded systems").
//!
//! An [`Ocsp`] names decision variables of a [`Theory`] with a cost per value, and assumptions that
//! hold in every solution. [`Ocsp::best`] returns the `k` cheapest full assignments of the decision
//! variables that are consistent with the theory, cheapest first, each once:
//! - [`Theory`] answers "consistent?" with a *conflict* when not — a small set of the candidate's
//!   assignments that cannot hold together (SAT with failed-assumption cores, minimised);
//! - the search (module `search`) jumps over every candidate containing a known conflict by expanding
//!   nodes along the conflict's constituent kernels, systematically, so nothing is visited twice;
//! - independent sub-problems are solved apart and their streams merged best-first (module `merge`);
//! - a [`Budget`] bounds a call; a cut search returns the best found so far and says so.
//!
//! Mode estimation (costs −log p), goal interpretation (costs −reward) and `kairos solve` all
//! run through this one engine.

pub mod file;
mod merge;
mod ocsp;
mod propagate;
mod sat;
mod search;
mod shared;
mod theory;

pub use merge::Enumeration;
pub use ocsp::{
    Budget, Choice, Cut, Decision, Ocsp, OcspError, SearchOptions, SearchStats, Solution, Solutions,
};
pub(crate) use search::Cost;
pub use shared::ConflictStore;
pub use theory::{
    Consistency, Definition, Literal, Theory, TheoryError, TheoryOptions, TheoryStats,
};

impl Ocsp {
    /// The `k` cheapest solutions, cheapest first, by conflict-directed A* with decomposition.
    pub fn best(&self, theory: &mut Theory, k: usize) -> Solutions {
        self.best_with(theory, k, SearchOptions::default())
    }

    /// The `k` cheapest solutions, searched as `options` say.
    pub fn best_with(&self, theory: &mut Theory, k: usize, options: SearchOptions) -> Solutions {
        let mut enumeration = self.enumerate(theory, options);
        let mut solutions = Vec::new();
        let mut cut = None;
        while solutions.len() < k {
            match enumeration.next(theory) {
                Ok(Some(solution)) => solutions.push(solution),
                Ok(None) => break,
                Err(reason) => {
                    cut = Some(reason);
                    break;
                }
            }
        }
        Solutions {
            solutions,
            cut,
            stats: enumeration.stats(),
        }
    }

    /// A lazy enumeration of all solutions, cheapest first, for callers that do not know `k` in
    /// advance (merging several problems' streams).
    pub fn enumerate<'a>(&'a self, theory: &Theory, options: SearchOptions) -> Enumeration<'a> {
        Enumeration::new(self, theory, options)
    }
}
