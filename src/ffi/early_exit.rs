//! `dcol_alpha_below`, `dcol_intersect` and `dcol_intersect_cached`: threshold questions answered without a full solve
//! when closed-form bounds or certified mid-solve bounds decide.

use super::boundary::{check_out, run, Failure};
use super::cache::{cache_mut, dcol_cache};
use super::options::dcol_options;
use super::pose::dcol_pose;
use super::proximity::{check_inputs, read_inputs};
use super::shape::dcol_shape;
use super::status::dcol_status;
use crate::query;

/// The shared body of `dcol_alpha_below` and `dcol_intersect`.
///
/// # Safety
/// As `dcol_alpha_below`.
#[allow(clippy::too_many_arguments)]
unsafe fn alpha_below_body(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    threshold: f64,
    options: *const dcol_options,
    out: *mut i32,
    out_name: &'static str,
) -> Result<(), Failure> {
    // SAFETY: forwarded from this function's contract.
    let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
    check_out(out, out_name)?;
    // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
    let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
    // An invalid threshold is reported by the core as InvalidOptions naming `threshold`.
    let d = query::alpha_below(
        q.shape1, &q.pose1, q.shape2, &q.pose2, threshold, &q.options,
    )
    .map_err(Failure::api)?;
    // SAFETY: `out` is non-NULL (checked) and valid for writes (contract).
    unsafe { out.write(i32::from(d.below)) };
    q.outcome(d.status, d.iterations)
}

/// Is alpha* < `threshold`? Writes 1 to *below when it is, 0 when it is not (alpha* >=
/// threshold).
///
/// Cheaper than dcol_proximity: the closed-form bracket
/// |r2 - r1| / (rho1 + rho2) <= alpha* <= |r2 - r1| / (iota1 + iota2) (bounding and inscribed
/// radii) answers without any solve when it decides, and otherwise the solve stops as soon as
/// its certified primal/dual bounds on alpha* decide. The answer equals
/// (dcol_proximity(...).alpha < threshold) except within a band of about the solver tolerance
/// around the threshold, where either answer may be returned.
///
/// `threshold` must be positive and finite (else DCOL_ERROR_INVALID_OPTIONS naming
/// `threshold`); `options` may be NULL (defaults). Returns DCOL_OK and writes *below; or
/// DCOL_ERROR_NOT_CONVERGED when neither the bounds nor the solve could decide within
/// options->max_iterations, with *below written from the last iterate (not certain); or an
/// error status, the last error message set, and *below untouched. Does not allocate.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `below` NULL or valid for writing one int32_t.
#[no_mangle]
pub unsafe extern "C" fn dcol_alpha_below(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    threshold: f64,
    options: *const dcol_options,
    below: *mut i32,
) -> dcol_status {
    run("dcol_alpha_below", || {
        // SAFETY: forwarded from this function's contract.
        unsafe {
            alpha_below_body(
                shape1, pose1, shape2, pose2, threshold, options, below, "below",
            )
        }
    })
}

/// Do the shapes interpenetrate (alpha* < 1)? Writes 1 to *intersecting when they do, 0 when
/// they do not (alpha* >= 1: separated or touching). Exactly dcol_alpha_below with threshold 1,
/// with the same statuses and outputs; shapes that touch to within the solver tolerance may be
/// reported either way. Does not allocate.
///
/// # Safety
/// As dcol_alpha_below; `intersecting` must be NULL or valid for writing one int32_t.
#[no_mangle]
pub unsafe extern "C" fn dcol_intersect(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    intersecting: *mut i32,
) -> dcol_status {
    run("dcol_intersect", || {
        // SAFETY: forwarded from this function's contract.
        unsafe {
            alpha_below_body(
                shape1,
                pose1,
                shape2,
                pose2,
                1.0,
                options,
                intersecting,
                "intersecting",
            )
        }
    })
}

/// dcol_intersect with a warm start: `cache` is the pair's `dcol_cache` (DCOL_CACHE_INIT the
/// first time, then what the last call on the pair left in it). A separating normal kept in it
/// that still separates the shapes answers 0 from two support calls; between polytopes the kept
/// contact is re-solved in closed form and certified; otherwise dcol_intersect answers, and the
/// cache keeps the separating normal of shapes found apart. *intersecting is always
/// dcol_intersect's (within 16 times the tolerance of touching, dcol_intersect itself answers).
/// A cache of another pair or of changed shapes is harmless (that call runs cold).
///
/// # Safety
/// As dcol_intersect; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_intersect_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    intersecting: *mut i32,
) -> dcol_status {
    run("dcol_intersect_cached", || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(intersecting, "intersecting")?;
        // SAFETY: forwarded from this function's contract.
        let Some(c) = (unsafe { cache_mut(Some(cache)) })? else {
            return Err(Failure::Null("cache"));
        };
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let d = query::intersect_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            .map_err(Failure::api)?;
        // SAFETY: `intersecting` is non-NULL (checked) and valid for writes (contract).
        unsafe { intersecting.write(i32::from(d.below)) };
        q.outcome(d.status, d.iterations)
    })
}
