//! Exact Euclidean distance between the unscaled shapes.

use super::proximity::Options;
use crate::error::Error;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;
use crate::solver::SolveStatus;

/// The result of a distance query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distance {
    /// Exact distance of the unscaled shapes; 0 when they touch or overlap.
    pub distance: Real,
    /// Witness point on shape 1 (world).
    pub closest1: Vec3,
    /// Witness point on shape 2 (world).
    pub closest2: Vec3,
    /// Unit normal from shape 1 to shape 2 (zero when the distance is 0).
    pub normal: Vec3,
    /// Interior-point iterations used.
    pub iterations: u32,
    /// How the solve ended.
    pub status: SolveStatus,
}

/// Exact distance, witness points and normal.
pub fn distance(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Distance, Error> {
    let _ = (shape1, pose1, shape2, pose2, options);
    Err(Error::Internal("distance: not yet built"))
}
