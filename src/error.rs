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
    /// A point the rule refers to (for a hull that does not surround its origin: the centroid
    /// of its corners), when there is one.
    pub point: Option<[f64; 3]>,
}

impl ErrorDetail {
    /// A detail for a scalar argument.
    pub const fn new(argument: &'static str, value: f64, requirement: &'static str) -> Self {
        ErrorDetail {
            argument,
            index: None,
            value,
            requirement,
            point: None,
        }
    }

    /// A detail naming a point (e.g. the centroid to shift a hull's points by).
    pub const fn with_point(
        argument: &'static str,
        value: f64,
        requirement: &'static str,
        point: [f64; 3],
    ) -> Self {
        ErrorDetail {
            argument,
            index: None,
            value,
            requirement,
            point: Some(point),
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
            point: None,
        }
    }
}

/// A value as a person would write it: plain decimal for moderate magnitudes (`-1`, `0.25`,
/// `1024`), scientific notation for tiny or huge ones (`1e-20`, `2.5e255`), `NaN`, `inf`.
pub(crate) struct Value(pub(crate) f64);

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

impl fmt::Display for ErrorDetail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = Value(self.value);
        if let Some([x, y, z]) = self.point {
            return write!(
                f,
                "argument `{}` = {}: {} ({}, {}, {})",
                self.argument,
                v,
                self.requirement,
                Value(x),
                Value(y),
                Value(z)
            );
        }
        match self.index {
            Some(i) => write!(
                f,
                "argument `{}[{}]` = {}: {}",
                self.argument, i, v, self.requirement
            ),
            None => write!(
                f,
                "argument `{}` = {}: {}",
                self.argument, v, self.requirement
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
            "invalid shape: argument `radius` = -1: must be positive"
        );
        let e = Error::InvalidPose(ErrorDetail::at("position", 2, f64::NAN, "must be finite"));
        assert_eq!(
            e.to_string(),
            "invalid pose: argument `position[2]` = NaN: must be finite"
        );
    }

    #[test]
    fn values_are_written_plainly_unless_tiny_or_huge() {
        for (v, text) in [
            (-1.0, "-1"),
            (0.0, "0"),
            (0.25, "0.25"),
            (300.0, "300"),
            (1e-20, "1e-20"),
            (2.5e255, "2.5e255"),
            (-1e15, "-1e15"),
            (5e-324, "5e-324"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ] {
            assert_eq!(Value(v).to_string(), text);
        }
    }
}
