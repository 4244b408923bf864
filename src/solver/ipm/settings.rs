//! Solver settings, validated.

use crate::error::{Error, ErrorDetail};
use crate::math::Real;

/// Default stopping tolerance on the relative duality gap (and the residuals).
pub const DEFAULT_TOLERANCE: Real = 1e-9;
/// Default iteration limit.
pub const DEFAULT_MAX_ITERATIONS: u32 = 50;

/// Stopping rules for the interior-point method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Stop when the duality gap, relative to `max(1, |objective|)`, and the scaled primal and
    /// dual residuals are all below this. For proximity the objective is α*, so this bounds the
    /// relative error of α* directly.
    pub tolerance: Real,
    /// Iteration limit; reaching it gives [`super::SolveStatus::MaxIterations`].
    pub max_iterations: u32,
    /// Which solvers a query may use (the default: the geometric solvers with the
    /// interior-point fallback). The exact distance of separated shapes is GJK's under `Auto`
    /// and the interior-point program's under `InteriorPoint`; touching and overlapping shapes'
    /// distance is the interior-point program's whatever this says.
    pub method: crate::solver::Method,
    /// 0 (the default): exact answers. A positive value μ asks proximity and its derivatives
    /// (gradient, Jacobian, their MRP forms, the batch) for the *smoothed* answer: the point
    /// of the interior-point method's central path at barrier parameter μ, with its exact
    /// derivatives, which are smooth everywhere (across edges, corners and face-against-face
    /// contact, where α* has kinks). μ is in the normalised units of the cone program, where
    /// α' ≥ 1: the smoothed α* exceeds the exact one by at most ν·μ relative, with ν the
    /// barrier degree (the number of orthant rows and cones of the two shapes, ≤ 2 + twice the
    /// facet count). The interior-point solver answers; `tolerance` still bounds the residuals.
    /// Boolean queries, bounds and the distance ignore it.
    pub smoothing: Real,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            method: crate::solver::Method::Auto,
            smoothing: 0.0,
        }
    }
}

impl Settings {
    /// Checks that the tolerance is positive and finite, the smoothing zero or positive and
    /// finite, and the iteration limit non-zero.
    pub fn validate(&self) -> Result<(), Error> {
        if !self.tolerance.is_finite() || self.tolerance <= 0.0 {
            return Err(Error::InvalidOptions(ErrorDetail::new(
                "tolerance",
                self.tolerance,
                "must be positive and finite",
            )));
        }
        if !self.smoothing.is_finite() || self.smoothing < 0.0 {
            return Err(Error::InvalidOptions(ErrorDetail::new(
                "smoothing",
                self.smoothing,
                "must be zero (exact answers) or positive and finite",
            )));
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidOptions(ErrorDetail::new(
                "max_iterations",
                0.0,
                "must be at least 1",
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation() {
        assert!(Settings::default().validate().is_ok());
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let s = Settings {
                tolerance: t,
                ..Settings::default()
            };
            assert!(matches!(s.validate(), Err(Error::InvalidOptions(_))));
        }
        for m in [-1e-6, f64::NAN, f64::INFINITY] {
            let s = Settings {
                smoothing: m,
                ..Settings::default()
            };
            assert!(matches!(s.validate(), Err(Error::InvalidOptions(_))));
        }
        let s = Settings {
            max_iterations: 0,
            ..Settings::default()
        };
        assert!(s.validate().is_err());
    }
}
