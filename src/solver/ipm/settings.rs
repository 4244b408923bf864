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
    /// and the interior-point program's under `InteriorPoint`. The Jacobian and the scene's
    /// early exits run the interior-point solver whatever this says.
    pub method: crate::solver::Method,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            method: crate::solver::Method::Auto,
        }
    }
}

impl Settings {
    /// Checks that the tolerance is positive and finite and the iteration limit non-zero.
    pub fn validate(&self) -> Result<(), Error> {
        if !self.tolerance.is_finite() || self.tolerance <= 0.0 {
            return Err(Error::InvalidOptions(ErrorDetail::new(
                "tolerance",
                self.tolerance,
                "must be positive and finite",
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
        let s = Settings {
            max_iterations: 0,
            ..Settings::default()
        };
        assert!(s.validate().is_err());
    }
}
