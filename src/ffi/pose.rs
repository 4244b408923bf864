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
#[inline]
pub(crate) unsafe fn read_pose(
    ptr: *const dcol_pose,
    name: &'static str,
    context: &'static str,
) -> Result<Pose, Failure> {
    // SAFETY: forwarded from this function's contract.
    let p = unsafe { read(ptr, name) }?;
    Pose::new(p.position, p.quaternion).map_err(Failure::api_in(context))
}

/// Where a shape is, with its attitude as a rotation matrix (for engines that keep one: ODE's
/// dGeomGetRotation, Bullet's btTransform basis): a body point b sits at position + R b.
///
/// `rotation` is R by rows (R[i][j] at rotation[3 * i + j]), world-from-body, used as given:
/// it must be a rotation to 1e-12 (every entry of R R^T - I at most 1e-12 in magnitude, and
/// det R > 0), as a matrix computed from a unit quaternion, or a product of a few such, is to
/// about 1e-15. Anything else is rejected (DCOL_ERROR_INVALID_POSE), never normalised.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_pose_matrix {
    /// r, the body origin in world coordinates.
    pub position: [f64; 3],
    /// R by rows, world-from-body.
    pub rotation: [f64; 9],
}

/// A pose argument of a query: a `dcol_pose` or a `dcol_pose_matrix`.
pub(crate) trait PoseInput: Copy {
    /// Copies and validates the pose behind `ptr`; `name` is the C argument's name.
    ///
    /// # Safety
    /// `ptr` must be NULL or point to a valid `Self`.
    unsafe fn read_pose(
        ptr: *const Self,
        name: &'static str,
        context: &'static str,
    ) -> Result<Pose, Failure>;
}

impl PoseInput for dcol_pose {
    #[inline]
    unsafe fn read_pose(
        ptr: *const Self,
        name: &'static str,
        context: &'static str,
    ) -> Result<Pose, Failure> {
        // SAFETY: forwarded from this function's contract.
        unsafe { read_pose(ptr, name, context) }
    }
}

impl PoseInput for dcol_pose_matrix {
    #[inline]
    unsafe fn read_pose(
        ptr: *const Self,
        name: &'static str,
        context: &'static str,
    ) -> Result<Pose, Failure> {
        // SAFETY: forwarded from this function's contract.
        let p = unsafe { read(ptr, name) }?;
        let r = &p.rotation;
        let rows = [[r[0], r[1], r[2]], [r[3], r[4], r[5]], [r[6], r[7], r[8]]];
        Pose::from_rotation(p.position, rows).map_err(Failure::api_in(context))
    }
}
