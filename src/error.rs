//! API errors: what was wrong with the caller's input.
//!
//! A solve that ran but did not converge is not an error: it is an *outcome*, reported as
//! [`crate::solver::SolveStatus`] inside the result.

use std::fmt;

/// Which argument was rejected, its value, and the rule it broke. Allocation free.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ErrorDetail {
    /// The argument's name as in the API (`radius`, `P`, `A`, `tolerance`, ...).
    pub argument: &'static str,
    /// Index of the offending element for array arguments (row-major flat index).
    pub index: Option<usize>,
    /// The offending value (for whole-matrix rules, a representative number, e.g. an eigenvalue).
    pub value: f64,
    /// The rule that was broken, as a phrase ("must be positive and finite").
    pub requirement: &'static str,
}

impl ErrorDetail {
    /// A detail for a scalar argument.
    pub const fn new(argument: &'static str, value: f64, requirement: &'static str) -> Self {
        ErrorDetail {
            argument,
            index: None,
            value,
            requirement,
        }
    }

    /// A detail for element `index` of an array argument.
    pub const fn at(
        argument: &'static str,
        index: usize,
        value: f64,
        requirement: &'static str,
    ) -> Self {
        ErrorDetail {
            argument,
            index: Some(index),
            value,
            requirement,
        }
    }
}

impl fmt::Display for ErrorDetail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.index {
            Some(i) => write!(
                f,
                "argument `{}[{}]` = {:e}: {}",
                self.argument, i, self.value, self.requirement
            ),
            None => write!(
                f,
                "argument `{}` = {:e}: {}",
                self.argument, self.value, self.requirement
            ),
        }
    }
}

/// An error in the caller's input, or an internal bug.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Error {
    /// The geometry was rejected (non-finite, non-positive size, P not SPD, empty, unbounded...).
    InvalidShape(ErrorDetail),
    /// A pose had a non-finite position or attitude, or a zero quaternion.
    InvalidPose(ErrorDetail),
    /// Options were out of range (tolerance not positive and finite, zero iteration limit).
    InvalidOptions(ErrorDetail),
    /// A bug: an impossible state was reached. The text says where.
    Internal(&'static str),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::InvalidShape(d) => write!(f, "invalid shape: {d}"),
            Error::InvalidPose(d) => write!(f, "invalid pose: {d}"),
            Error::InvalidOptions(d) => write!(f, "invalid options: {d}"),
            Error::Internal(s) => write!(f, "internal error: {s}"),
        }
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_argument_and_value() {
        let e = Error::InvalidShape(ErrorDetail::new("radius", -1.0, "must be positive"));
        assert_eq!(
            e.to_string(),
            "invalid shape: argument `radius` = -1e0: must be positive"
        );
        let e = Error::InvalidPose(ErrorDetail::at("position", 2, f64::NAN, "must be finite"));
        assert_eq!(
            e.to_string(),
            "invalid pose: argument `position[2]` = NaN: must be finite"
        );
    }
}
