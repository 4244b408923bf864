//! `dcol_distance_result` and `dcol_distance`.

use super::boundary::{check_out, run, Failure};
use super::options::dcol_options;
use super::pose::dcol_pose;
use super::proximity::{check_inputs, read_inputs};
use super::shape::dcol_shape;
use super::status::dcol_status;
use crate::math::Vec3;
use crate::query::{self, Distance};

/// The exact Euclidean distance between two posed (unscaled) shapes, with witness points.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_distance_result {
    /// Exact Euclidean distance of the unscaled shapes; 0 when they touch or overlap.
    pub distance: f64,
    /// Witness point on shape 1 (world).
    pub closest1: [f64; 3],
    /// Witness point on shape 2 (world).
    pub closest2: [f64; 3],
    /// Interior-point iterations used.
    pub iterations: u32,
    /// Unit normal from shape 1 to shape 2 (world); zero when the distance is 0. (An addition
    /// to the contract, appended at the end.)
    pub normal: [f64; 3],
}

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl From<&Distance> for dcol_distance_result {
    fn from(d: &Distance) -> Self {
        dcol_distance_result {
            distance: d.distance,
            closest1: arr(&d.closest1),
            closest2: arr(&d.closest2),
            iterations: d.iterations,
            normal: arr(&d.normal),
        }
    }
}

/// The exact distance between the unscaled shapes, the witness points and the normal.
///
/// `options` may be NULL (defaults). Returns DCOL_OK and fills *result; or
/// DCOL_ERROR_NOT_CONVERGED and fills *result with the last iterate; or an error status, the
/// last error message set, and *result untouched.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `result` NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_distance(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_distance_result,
) -> dcol_status {
    run("dcol_distance", || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let d = query::distance(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options)
            .map_err(Failure::api)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        q.outcome(d.status, d.iterations)
    })
}
