//! Derivatives of the proximity solution with respect to both poses.

use super::proximity::{Options, Proximity};
use crate::error::Error;
use crate::math::Pose;
use crate::shapes::Shape;

/// ∂α*/∂(r₁, q₁, r₂, q₂): 14 numbers, `q` as given (through the normalisation).
pub fn gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [f64; 14]), Error> {
    let _ = (shape1, pose1, shape2, pose2, options);
    Err(Error::Internal("gradient: not yet built"))
}

/// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂): 4×14, rows (x₁, x₂, x₃, α).
pub fn jacobian(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [[f64; 14]; 4]), Error> {
    let _ = (shape1, pose1, shape2, pose2, options);
    Err(Error::Internal("jacobian: not yet built"))
}
