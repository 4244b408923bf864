//! A shape's parameters (`dcol_shape_parameter_count`, `dcol_shape_parameters`) and the
//! derivatives with respect to them (`dcol_shape_gradient`, `dcol_distance_shape_gradient`,
//! `dcol_signed_distance_shape_gradient`).

use super::boundary::{catch, check_out, run, Failure};
use super::distance::{
    dcol_distance_result, dcol_signed_distance_result, numbers as distance_numbers,
};
use super::finite::proximity_numbers;
use super::options::dcol_options;
use super::pose::dcol_pose;
use super::proximity::{check_inputs, dcol_proximity_result, read_inputs, Inputs};
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::error::{Error, ErrorDetail};
use crate::math::finite_array;
use crate::query;
use crate::shapes::Shape;

/// How many numbers describe `shape`: the arguments its constructor was given, in the order
/// given (dcol_shape_parameters writes them; the shape gradients are taken with respect to
/// them). sphere 1 (radius); ellipsoid 9 (P, row-major); polytope 4m (A row-major, then b);
/// box 3 (half_x, half_y, half_z); capsule and cylinder 2 (radius, length); cone 2 (height,
/// half_angle); padded polygon 3m + 1 (C row-major, then d, then radius); half-space 1 (depth);
/// convex hull 3n + 1 (the points row-major, then radius). 0 for a NULL shape.
///
/// # Safety
/// `shape` must be NULL or a live shape.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_parameter_count(shape: *const dcol_shape) -> usize {
    catch("dcol_shape_parameter_count", 0, || {
        // SAFETY: forwarded from this function's contract.
        unsafe { shape_ref(shape, "shape") }.map_or(0, Shape::parameter_count)
    })
}

/// Writes the shape's parameters (see dcol_shape_parameter_count for their number and order)
/// into out[0..count]: the numbers its constructor was given (an ellipsoid's P symmetrised,
/// (P + P^T)/2). DCOL_ERROR_INVALID_OPTIONS when `capacity` is below the count (nothing is
/// written).
///
/// # Safety
/// `shape` must be NULL or a live shape; `out` NULL or valid for writing `capacity` doubles.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_parameters(
    shape: *const dcol_shape,
    out: *mut f64,
    capacity: usize,
) -> dcol_status {
    run("dcol_shape_parameters", || {
        // SAFETY: forwarded from this function's contract.
        let s = unsafe { shape_ref(shape, "shape") }?;
        check_out(out, "out")?;
        let count = s.parameter_count();
        if capacity < count {
            return Err(Failure::api(Error::InvalidOptions(ErrorDetail::new(
                "capacity",
                capacity as f64,
                "is smaller than the shape's number of parameters \
                 (dcol_shape_parameter_count)",
            ))));
        }
        // SAFETY: `out` is non-NULL (checked) and valid for `capacity >= count` doubles (the
        // caller's contract), aligned for f64; nothing else refers to it during this call.
        let buf = unsafe { std::slice::from_raw_parts_mut(out, count) };
        s.write_parameters(buf);
        Ok(())
    })
}

/// The caller's buffer for shape `shape`'s derivatives (`count` doubles), or `None` for NULL.
///
/// # Safety
/// `ptr` must be NULL or valid for writing `count` doubles, and not overlap any other buffer
/// alive at the same time.
unsafe fn buffer<'a>(ptr: *mut f64, count: usize) -> Option<&'a mut [f64]> {
    // SAFETY: non-NULL here; valid for `count` writable, f64-aligned doubles and unaliased
    // (this function's contract).
    (!ptr.is_null()).then(|| unsafe { std::slice::from_raw_parts_mut(ptr, count) })
}

/// Rejects two derivative buffers that share memory (they are written at once).
fn check_disjoint(d1: *mut f64, n1: usize, d2: *mut f64, n2: usize) -> Result<(), Failure> {
    if d1.is_null() || d2.is_null() {
        return Ok(());
    }
    let (a, b) = (d1 as usize, d2 as usize);
    let size = std::mem::size_of::<f64>();
    if a < b + n2 * size && b < a + n1 * size {
        return Err(Failure::api(Error::InvalidOptions(ErrorDetail::new(
            "d_shape2",
            n2 as f64,
            "overlaps d_shape1 (the two buffers must not share memory)",
        ))));
    }
    Ok(())
}

/// A caller's derivative buffer, or `None` for NULL.
type Buffer<'a> = Option<&'a mut [f64]>;

/// The common inputs of the three shape-gradient functions: the shapes, poses and options read
/// and checked, `result` checked non-NULL, and the two derivative buffers (NULL or sized by
/// their shape's parameter count, checked disjoint).
///
/// # Safety
/// As dcol_shape_gradient: the shape, pose and options pointers as dcol_proximity's, each
/// buffer NULL or valid for writing its shape's parameter count of doubles.
unsafe fn shape_inputs<'a, R>(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    (result, d_shape1, d_shape2): (*mut R, *mut f64, *mut f64),
) -> Result<(Inputs<'a>, Buffer<'a>, Buffer<'a>), Failure> {
    // SAFETY: forwarded from this function's contract.
    let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
    check_out(result, "result")?;
    // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
    let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
    let (n1, n2) = (q.shape1.parameter_count(), q.shape2.parameter_count());
    check_disjoint(d_shape1, n1, d_shape2, n2)?;
    // SAFETY: each NULL or valid for its count (contract), and disjoint (checked).
    let (g1, g2) = unsafe { (buffer(d_shape1, n1), buffer(d_shape2, n2)) };
    Ok((q, g1, g2))
}

/// alpha*, x* and the contact points (as dcol_proximity), and the derivatives of alpha* with
/// respect to each shape's parameters (see dcol_shape_parameter_count: the numbers exactly as
/// given to the constructor, so a finite difference on the constructor's arguments checks
/// them) into d_shape1[0..count1] and d_shape2[0..count2]. Either buffer may be NULL (not
/// wanted). An ellipsoid's P enters through (P + P^T)/2: a symmetric change of the pair P_ij,
/// P_ji moves alpha* by the sum of their two entries.
///
/// By the envelope theorem at the optimal normal, a few flops beyond dcol_gradient.
/// result->derivatives says their kind, as for dcol_gradient: DCOL_DERIVATIVES_EXACT where the
/// contact points are unique; DCOL_DERIVATIVES_SMOOTHED flat against flat (the interior-point
/// method's) or with dcol_options.smoothing (the exact derivatives of the smoothed alpha);
/// DCOL_DERIVATIVES_SUBGRADIENT where alpha* is not differentiable in a shape's parameters
/// although the contact is unique (a corner where more than three of a polytope's planes
/// meet, a hull's facet of more than three corners, a hull point given twice) and at
/// coincident origins (zeros): one element of the generalised gradient. The kind covers the
/// buffers asked for. An unpadded hull's radius (0) has the derivative of growing it.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and the buffers. On
/// DCOL_ERROR_NOT_CONVERGED fills *result and the buffers with the last iterate's (zeros where
/// they would not be finite). On any other status nothing is written. Does not allocate.
///
/// # Safety
/// As dcol_proximity; `d_shape1` and `d_shape2` must each be NULL or valid for writing
/// dcol_shape_parameter_count(shape) doubles of its shape.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_shape_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
    d_shape1: *mut f64,
    d_shape2: *mut f64,
) -> dcol_status {
    run("dcol_shape_gradient", || {
        let io = (result, d_shape1, d_shape2);
        // SAFETY: forwarded from this function's contract.
        let (q, g1, g2) = unsafe { shape_inputs(shape1, pose1, shape2, pose2, options, io) }?;
        let prox =
            query::shape_gradient(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, g1, g2)
                .map_err(Failure::api)?;
        // Not representable: the buffers were left untouched (query::shape_gradient).
        q.representable(finite_array(&proximity_numbers(&prox)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        q.outcome(prox.status, prox.iterations)
    })
}

/// The exact distance (as dcol_distance) and its derivatives with respect to each shape's
/// parameters (as dcol_shape_gradient): -dh_i/dtheta_i of the support functions at the unit
/// normal and witness points. All zeros when the shapes touch or overlap (the distance is 0
/// there, as dcol_distance_gradient). Either buffer may be NULL.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and the buffers; on
/// DCOL_ERROR_NOT_CONVERGED the last iterate's; on any other status nothing is written.
///
/// # Safety
/// As dcol_distance; `d_shape1` and `d_shape2` as for dcol_shape_gradient.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_distance_shape_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_distance_result,
    d_shape1: *mut f64,
    d_shape2: *mut f64,
) -> dcol_status {
    run("dcol_distance_shape_gradient", || {
        let io = (result, d_shape1, d_shape2);
        // SAFETY: forwarded from this function's contract.
        let (q, g1, g2) = unsafe { shape_inputs(shape1, pose1, shape2, pose2, options, io) }?;
        let d = query::distance_shape_gradient(
            q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, g1, g2,
        )
        .map_err(Failure::api)?;
        // Not representable: the buffers were left untouched (query::distance_shape_gradient).
        q.representable(finite_array(&distance_numbers(&d)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        q.outcome(d.status, d.iterations)
    })
}

/// The signed distance (as dcol_signed_distance) and its derivatives with respect to each
/// shape's parameters (as dcol_shape_gradient): -dh_i/dtheta_i of the support functions at
/// its unit normal and witness points, separated or overlapping. Either buffer may be NULL.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and the buffers; on
/// DCOL_ERROR_NOT_CONVERGED the best answer found and its derivatives; on any other status
/// nothing is written.
///
/// # Safety
/// As dcol_signed_distance; `d_shape1` and `d_shape2` as for dcol_shape_gradient.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_signed_distance_shape_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_signed_distance_result,
    d_shape1: *mut f64,
    d_shape2: *mut f64,
) -> dcol_status {
    run("dcol_signed_distance_shape_gradient", || {
        let io = (result, d_shape1, d_shape2);
        // SAFETY: forwarded from this function's contract.
        let (q, g1, g2) = unsafe { shape_inputs(shape1, pose1, shape2, pose2, options, io) }?;
        let d = query::signed_distance_shape_gradient(
            q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, g1, g2,
        )
        .map_err(Failure::api)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&d).into()) };
        q.outcome(d.status, d.iterations)
    })
}
