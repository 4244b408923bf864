//! `dcol_distance_result`, `dcol_distance` and `dcol_distance_gradient`.

use super::boundary::{check_out, run, Failure};
use super::cache::{cache_mut, dcol_cache};
use super::options::{dcol_options, plain_tolerance};
use super::pose::dcol_pose;
use super::proximity::{check_inputs, read_inputs};
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::math::{finite_array, Vec3};
use crate::query::{self, Distance, SignedDistance};

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

/// The numbers of a distance result.
#[inline]
pub(crate) fn numbers(d: &Distance) -> [f64; 10] {
    let (a, b, n) = (&d.closest1, &d.closest2, &d.normal);
    [d.distance, a.x, a.y, a.z, b.x, b.y, b.z, n.x, n.y, n.z]
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
    // SAFETY: forwarded from this function's contract.
    unsafe {
        distance_in(
            "dcol_distance",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            None,
            result,
        )
    }
}

/// dcol_distance with a warm start from `cache`, the pair's dcol_cache (see dcol_cache): the same
/// answer, certified the same way; the cache then holds this one.
///
/// # Safety
/// As dcol_distance; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_distance_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_distance_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        distance_in(
            "dcol_distance_cached",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            Some(cache),
            result,
        )
    }
}

/// The body of `dcol_distance` and `dcol_distance_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_distance`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn distance_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_distance_result,
) -> dcol_status {
    run(name, || {
        // The closed-form lane answers the cached call too, the cache untouched (a closed form
        // has nothing to keep; the full cached path cost 1.65-2.0x the cold call on sphere
        // pairs in bench_trajectory): only with a non-NULL cache, which the full path would
        // otherwise refuse.
        if cache.map_or(true, |c| !c.is_null()) {
            // SAFETY: forwarded from this function's contract.
            if let Some(r) = unsafe { closed_lane(shape1, pose1, shape2, pose2, options, result) } {
                // SAFETY: the lane answers only with `result` non-NULL; valid for writes
                // (contract).
                unsafe { result.write(r) };
                return Ok(());
            }
        }
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let d = match warm {
            Some(c) => {
                query::distance_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            }
            None => query::distance(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        q.representable(finite_array(&numbers(&d)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        q.outcome(d.status, d.iterations)
    })
}

/// The closed-form lane of `dcol_distance` (`query::closed_lane::distance`): the answer of a
/// separated pair with a closed form when every pointer is non-NULL, the options are plain
/// (`plain_tolerance`) and the lane answers (the same numbers the full path gives, all finite,
/// converged); `None` sends the call to the full path, which answers the same or reports the
/// error.
///
/// # Safety
/// As `dcol_distance`.
#[inline(always)]
unsafe fn closed_lane(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_distance_result,
) -> Option<dcol_distance_result> {
    if pose1.is_null() || pose2.is_null() || result.is_null() {
        return None;
    }
    // SAFETY: forwarded from this function's contract (NULL is checked by `shape_ref` and above).
    let (s1, s2, p1, p2, tolerance) = unsafe {
        (
            shape_ref(shape1, "shape1").ok()?,
            shape_ref(shape2, "shape2").ok()?,
            &*pose1,
            &*pose2,
            plain_tolerance(options)?,
        )
    };
    let d = query::closed_lane::distance(
        s1,
        (&p1.position, &p1.quaternion),
        s2,
        (&p2.position, &p2.quaternion),
        tolerance,
    )?;
    Some((&d).into())
}

/// The signed distance (as dcol_signed_distance) and its gradient with respect to
/// (r1, q1, r2, q2): 14 numbers, in that order, the quaternion columns with respect to the
/// four numbers given (through the normalisation): d/d r2 = normal = -d/d r1, the rotation
/// columns from the witness points. Exact where the normal and witness points are unique.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and gradient[0..14]. On
/// DCOL_ERROR_NOT_CONVERGED fills *result with the best answer found and writes its gradient
/// only if all 14 entries are finite. On any other status nothing is written. Allocates as
/// dcol_signed_distance (at most once per thread).
///
/// # Safety
/// As dcol_signed_distance; `gradient` must be NULL or valid for writing 14 doubles.
#[no_mangle]
pub unsafe extern "C" fn dcol_signed_distance_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_signed_distance_result,
    gradient: *mut f64,
) -> dcol_status {
    run("dcol_signed_distance_gradient", || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        check_out(gradient, "gradient")?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let (d, g) =
            query::signed_distance_gradient(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options)
                .map_err(Failure::api)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        if d.status.is_converged() || finite_array(&g) {
            // SAFETY: non-NULL (checked); the caller guarantees 14 writable doubles, and
            // `[f64; 14]` has the alignment of `f64`.
            unsafe { gradient.cast::<[f64; 14]>().write(g) };
        }
        q.outcome(d.status, d.iterations)
    })
}

/// The distance (as dcol_distance) and its gradient with respect to (r1, q1, r2, q2): 14
/// numbers, in that order, the quaternion columns with respect to the four numbers given
/// (through the normalisation). For touching or overlapping shapes the distance is 0 and the
/// gradient is all zeros (the distance is not differentiable there; alpha* from dcol_gradient
/// is the smooth measure to use).
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and gradient[0..14]. On
/// DCOL_ERROR_NOT_CONVERGED fills *result with the last iterate and writes the gradient only if
/// all 14 entries are finite. On any other status nothing is written. Does not allocate (as
/// dcol_distance).
///
/// # Safety
/// As dcol_distance; `gradient` must be NULL or valid for writing 14 doubles.
#[no_mangle]
pub unsafe extern "C" fn dcol_distance_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_distance_result,
    gradient: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        distance_gradient_in(
            "dcol_distance_gradient",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            None,
            result,
            gradient,
        )
    }
}

/// dcol_distance_gradient with a warm start from `cache`, the pair's dcol_cache (see dcol_cache): the same
/// answer, certified the same way; the cache then holds this one.
///
/// # Safety
/// As dcol_distance_gradient; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_distance_gradient_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_distance_result,
    gradient: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        distance_gradient_in(
            "dcol_distance_gradient_cached",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            Some(cache),
            result,
            gradient,
        )
    }
}

/// The body of `dcol_distance_gradient` and `dcol_distance_gradient_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_distance_gradient`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn distance_gradient_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_distance_result,
    gradient: *mut f64,
) -> dcol_status {
    run(name, || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        check_out(gradient, "gradient")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let (d, g) = match warm {
            Some(c) => query::distance_gradient_cached(
                q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c,
            ),
            None => query::distance_gradient(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        let converged = d.status.is_converged();
        q.representable(finite_array(&numbers(&d)) && (!converged || finite_array(&g)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        if d.status.is_converged() || finite_array(&g) {
            // SAFETY: non-NULL (checked); the caller guarantees 14 writable doubles, and
            // `[f64; 14]` has the alignment of `f64`.
            unsafe { gradient.cast::<[f64; 14]>().write(g) };
        }
        q.outcome(d.status, d.iterations)
    })
}

/// The signed distance of two posed shapes: the Euclidean distance when separated, minus the
/// penetration depth (the minimum translation distance) when overlapping.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_signed_distance_result {
    /// Signed distance: > 0 separated, < 0 overlapping (minus the depth), 0 touching.
    pub distance: f64,
    /// Unit normal from shape 1 to shape 2 (world): moving shape 2 by depth·normal separates
    /// overlapping shapes.
    pub normal: [f64; 3],
    /// Witness point on shape 1 (world), its support point at `normal`.
    pub closest1: [f64; 3],
    /// Witness point on shape 2 (world), its support point at `-normal`;
    /// closest2 - closest1 = distance·normal.
    pub closest2: [f64; 3],
    /// Iterations of the solver that answered (EPA support calls for overlapping pairs).
    pub iterations: u32,
}

impl From<&SignedDistance> for dcol_signed_distance_result {
    fn from(d: &SignedDistance) -> Self {
        dcol_signed_distance_result {
            distance: d.distance,
            normal: arr(&d.normal),
            closest1: arr(&d.closest1),
            closest2: arr(&d.closest2),
            iterations: d.iterations,
        }
    }
}

/// The signed distance, the normal from shape 1 to shape 2 and the witness points.
///
/// `options` may be NULL (defaults). Returns DCOL_OK and fills *result; or
/// DCOL_ERROR_NOT_CONVERGED (the certified bracket did not close) and fills *result with the
/// best answer found; or an error status, the last error message set, and *result untouched.
/// Does not allocate, except once per thread: the first overlap on a thread whose certificate
/// needs more than 250 support points (about 3 in 10000 random deep overlaps of curved shapes)
/// reserves a buffer of about 0.9 MB that the thread's later queries reuse.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `result` NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_signed_distance(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_signed_distance_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        signed_distance_in(
            "dcol_signed_distance",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            None,
            result,
        )
    }
}

/// dcol_signed_distance with a warm start from `cache`, the pair's dcol_cache (see dcol_cache): the same
/// answer, certified the same way; the cache then holds this one.
///
/// # Safety
/// As dcol_signed_distance; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_signed_distance_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_signed_distance_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        signed_distance_in(
            "dcol_signed_distance_cached",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            Some(cache),
            result,
        )
    }
}

/// The body of `dcol_signed_distance` and `dcol_signed_distance_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_signed_distance`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn signed_distance_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_signed_distance_result,
) -> dcol_status {
    run(name, || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let d = match warm {
            Some(c) => {
                query::signed_distance_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            }
            None => query::signed_distance(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        q.outcome(d.status, d.iterations)
    })
}
