//! `dcol_pose`.

use super::boundary::{read, Failure};
use crate::math::Pose;

/// Where a shape is: its body frame's origin and attitude in the world.
///
/// A body point b sits at position + Q(quaternion) b. The quaternion is [w, x, y, z], scalar
/// first, world-from-body, and need not be unit length: it is normalised internally (and
/// derivatives are taken through that normalisation, with respect to the numbers given). Any
/// finite, non-zero quaternion is accepted. Positions are in metres (any consistent unit).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_pose {
    /// r, the body origin in world coordinates.
    pub position: [f64; 3],
    /// [w, x, y, z], world-from-body; normalised internally.
    pub quaternion: [f64; 4],
}

/// Copies and validates the pose behind `ptr`; `name` is the C argument's name.
///
/// # Safety
/// `ptr` must be NULL or point to a valid `dcol_pose`.
#[inline(always)]
pub(crate) unsafe fn read_pose(
    ptr: *const dcol_pose,
    name: &'static str,
    context: &'static str,
) -> Result<Pose, Failure> {
    // SAFETY: forwarded from this function's contract.
    let p = unsafe { read(ptr, name) }?;
    Pose::new(p.position, p.quaternion).map_err(Failure::api_in(context))
}
