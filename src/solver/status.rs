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

/// Which solver produced an answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Solver {
    /// The interior-point solver of the cone program (the fallback, or chosen by
    /// [`Method::InteriorPoint`]).
    #[default]
    InteriorPoint,
    /// A ray cast on the support maps closed its bracket on its own: portal refinement, or
    /// (spheres, capsules and padded polygons against polytopes and each other) GJK on the
    /// shapes' cores with the exact value on the feature it found.
    RayCast,
    /// The ray cast identified the contact features and the Newton polish on them closed the
    /// bracket.
    Polish,
    /// A closed form for the pair (spheres, capsules, a sphere and a box, cylinder or cone, a
    /// half-space and any other shape).
    ClosedForm,
}

/// What kind of derivatives a query returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum DerivativeKind {
    /// None were asked for (a plain proximity query).
    #[default]
    None,
    /// The exact derivatives of α* and x* (x* unique there; the gradient needs only the
    /// optimal normal to be unique).
    Exact,
    /// The barrier-smoothed derivatives of the central-path point: where x* is not unique (flat
    /// against flat) and the exact Jacobian does not exist, or when
    /// [`crate::Options::smoothing`] asked for them.
    Smoothed,
    /// α* is not differentiable there and one element of its generalised gradient is returned:
    /// zero at exactly coincident origins (α* = 0 is the gauge of the Minkowski difference,
    /// homogeneous of degree one); flat against flat, when the interior-point solve for the
    /// smoothed gradient did not converge, the envelope formula at the geometric contact point.
    Subgradient,
}

/// Which solvers a query may use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Method {
    /// Closed forms, then the certified ray cast and polish on support maps, with the
    /// interior-point solver as the fallback when they cannot certify the answer.
    #[default]
    Auto,
    /// The interior-point solver only (for comparison, and for its smoothed derivatives).
    InteriorPoint,
}
