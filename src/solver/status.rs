//! The outcome of a solve (distinct from an API error).

/// How an interior-point solve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SolveStatus {
    /// Gap and residuals below the tolerance.
    Converged,
    /// The iteration limit was reached first; the result holds the last iterate.
    MaxIterations,
    /// The iteration could not continue (singular system, no interior step); the result holds
    /// the last iterate, which is always finite.
    NumericalFailure,
}

impl SolveStatus {
    /// True for [`SolveStatus::Converged`].
    pub fn is_converged(self) -> bool {
        self == SolveStatus::Converged
    }
}
