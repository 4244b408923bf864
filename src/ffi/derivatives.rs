//! `dcol_derivatives_result`, `dcol_derivatives` (everything differentiable in one solve), and
//! the modified-Rodrigues-parameter variants `dcol_gradient_mrp` and `dcol_jacobian_mrp`.

use super::boundary::{check_out, read_array, run, Failure};
use super::cache::{cache_mut, dcol_cache};
use super::finite::{proximity_numbers, representable};
use super::options::{dcol_options, read_options};
use super::pose::dcol_pose;
use super::proximity::{check_inputs, dcol_proximity_result, outcome, read_inputs};
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::error::{Error, ErrorDetail};
use crate::math::{all_finite, finite_array, finite_lanes};
use crate::query::{self, Derivatives, Options};
use crate::shapes::Shape;

/// Everything differentiable about a proximity query, from one solve (dcol_derivatives).
/// Columns are always (r1, q1, r2, q2): 14, the quaternion columns with respect to the four
/// numbers given (through the normalisation), as in dcol_gradient. Matrices are row-major
/// (jacobian[row][column]).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_derivatives_result {
    /// alpha*, x* and the contact points, as dcol_proximity.
    pub proximity: dcol_proximity_result,
    /// d alpha* / d(r1, q1, r2, q2), as dcol_gradient.
    pub gradient: [f64; 14],
    /// d(x*, alpha*) / d(r1, q1, r2, q2): 4 x 14, rows (x1, x2, x3, alpha), as dcol_jacobian.
    pub jacobian: [[f64; 14]; 4],
    /// d p1 / d(r1, q1, r2, q2): 3 x 14, the Jacobian of contact point 1
    /// (p1 = r1 + (x* - r1) / alpha*, by the chain rule); all zeros when alpha* = 0.
    pub contact_jacobian1: [[f64; 14]; 3],
    /// d p2 / d(r1, q1, r2, q2): 3 x 14, the Jacobian of contact point 2; all zeros when
    /// alpha* = 0.
    pub contact_jacobian2: [[f64; 14]; 3],
}

/// Whether every derivative in `d` is finite.
fn derivatives_finite(d: &Derivatives) -> bool {
    finite_lanes(&d.dalpha)
        && finite_lanes(d.jacobian.as_flattened())
        && finite_lanes(d.dcontact1.as_flattened())
        && finite_lanes(d.dcontact2.as_flattened())
}

/// alpha*, x*, the contact points and all their derivatives with respect to (r1, q1, r2, q2)
/// in one solve: the gradient of alpha*, the Jacobian of (x*, alpha*) and the Jacobians of both
/// contact points (see dcol_derivatives_result). The gradient and Jacobian are those of
/// dcol_gradient and dcol_jacobian, bit for bit.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result. On DCOL_ERROR_NOT_CONVERGED
/// fills result->proximity with the last iterate, and the derivative fields only if all of them
/// are finite (otherwise they are left untouched). On any other status nothing is written.
/// Does not allocate.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `result` NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_derivatives(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_derivatives_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        derivatives_in(
            "dcol_derivatives",
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

/// dcol_derivatives with a warm start: `cache` is the pair's `dcol_cache` (DCOL_CACHE_INIT the first
/// time, then what the last call on the pair left in it). The answer is certified as dcol_derivatives's
/// and agrees with it to the solver's tolerance; the cache then holds this answer. A cache
/// of another pair or of changed shapes is harmless (that call runs cold).
///
/// # Safety
/// As dcol_derivatives; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_derivatives_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_derivatives_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        derivatives_in(
            "dcol_derivatives_cached",
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

/// The body of `dcol_derivatives` and `dcol_derivatives_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_derivatives`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn derivatives_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_derivatives_result,
) -> dcol_status {
    run(name, || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        // Written in place (not returned: the answer is ~1.3 kB).
        let mut d = Derivatives::default();
        let (s1, s2) = (q.shape1, q.shape2);
        query::derivatives_into(s1, &q.pose1, s2, &q.pose2, &q.options, warm, &mut d)
            .map_err(Failure::api)?;
        q.representable(finite_array(&proximity_numbers(&d.proximity)))?;
        if d.proximity.status.is_converged() && !derivatives_finite(&d) {
            return Err(Failure::api(query::not_representable(
                q.pose1.position(),
                q.pose2.position(),
            )));
        }
        let proximity = dcol_proximity_result::from(&d.proximity);
        if d.proximity.status.is_converged() || derivatives_finite(&d) {
            let out = dcol_derivatives_result {
                proximity,
                gradient: d.dalpha,
                jacobian: d.jacobian,
                contact_jacobian1: d.dcontact1,
                contact_jacobian2: d.dcontact2,
            };
            // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
            unsafe { result.write(out) };
        } else {
            // SAFETY: `result` is non-NULL (checked) and valid for writes (contract);
            // `addr_of_mut!` projects to the field without creating a reference.
            unsafe { std::ptr::addr_of_mut!((*result).proximity).write(proximity) };
        }
        q.outcome(d.proximity.status, d.proximity.iterations)
    })
}

/// Rejects a non-finite position or MRP, and an MRP whose squared norm overflows, naming the C
/// argument (`position1[2]`, `mrp2[0]`, ...).
fn check_mrp_pose(
    position: &[f64; 3],
    mrp: &[f64; 3],
    position_name: &'static str,
    mrp_name: &'static str,
) -> Result<(), Failure> {
    let bad = |name, i, v, why| Failure::api(Error::InvalidPose(ErrorDetail::at(name, i, v, why)));
    for (i, &v) in position.iter().enumerate() {
        if !v.is_finite() {
            return Err(bad(position_name, i, v, "must be finite"));
        }
    }
    for (i, &v) in mrp.iter().enumerate() {
        if !v.is_finite() {
            return Err(bad(mrp_name, i, v, "must be finite"));
        }
    }
    if !mrp.iter().map(|v| v * v).sum::<f64>().is_finite() {
        let (i, &v) = mrp
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
            .unwrap_or((0, &mrp[0]));
        return Err(bad(
            mrp_name,
            i,
            v,
            "is too large: the squared norm of the MRP overflows a double",
        ));
    }
    Ok(())
}

/// The validated, copied inputs of an MRP query.
struct MrpInputs<'a> {
    shape1: &'a Shape,
    position1: [f64; 3],
    mrp1: [f64; 3],
    shape2: &'a Shape,
    position2: [f64; 3],
    mrp2: [f64; 3],
    options: Options,
}

/// Checks the six input pointers, then the outputs (`(is_null, name)` pairs), for NULL in
/// argument order; then copies and validates the positions, MRPs and options.
///
/// # Safety
/// Each pointer must be NULL or valid for its type (shapes live for `'a`, arrays hold 3
/// doubles).
#[allow(clippy::too_many_arguments)]
unsafe fn read_mrp_inputs<'a>(
    shape1: *const dcol_shape,
    position1: *const f64,
    mrp1: *const f64,
    shape2: *const dcol_shape,
    position2: *const f64,
    mrp2: *const f64,
    options: *const dcol_options,
    outputs: [(bool, &'static str); 2],
) -> Result<MrpInputs<'a>, Failure> {
    // SAFETY: every pointer is NULL-checked by the helper before it is read, and is otherwise
    // valid for its type (3 doubles for the arrays) by this function's contract.
    let (s1, r1, p1, s2, r2, p2) = unsafe {
        (
            shape_ref(shape1, "shape1")?,
            read_array::<f64, 3>(position1, "position1")?,
            read_array::<f64, 3>(mrp1, "mrp1")?,
            shape_ref(shape2, "shape2")?,
            read_array::<f64, 3>(position2, "position2")?,
            read_array::<f64, 3>(mrp2, "mrp2")?,
        )
    };
    for (is_null, name) in outputs {
        if is_null {
            return Err(Failure::Null(name));
        }
    }
    check_mrp_pose(&r1, &p1, "position1", "mrp1")?;
    check_mrp_pose(&r2, &p2, "position2", "mrp2")?;
    // SAFETY: forwarded from this function's contract.
    let options = unsafe { read_options(options) }?;
    Ok(MrpInputs {
        shape1: s1,
        position1: r1,
        mrp1: p1,
        shape2: s2,
        position2: r2,
        mrp2: p2,
        options,
    })
}

/// The gradient of alpha* with respect to (r1, p1, r2, p2) for attitudes given as modified
/// Rodrigues parameters (MRPs) p, the quaternion being q = [1 - p.p, 2 p] / (1 + p.p)
/// ([w, x, y, z], world-from-body). 12 numbers: d/dr1 (3), d/dp1 (3), d/dr2 (3), d/dp2 (3);
/// equal to the quaternion gradient of dcol_gradient times dq/dp (chain rule).
///
/// `position1`, `mrp1`, `position2`, `mrp2` each point to 3 doubles, all finite (an MRP whose
/// squared norm overflows a double is rejected as DCOL_ERROR_INVALID_POSE; errors name the
/// argument, e.g. `mrp2[0]`). `options` may be NULL (defaults). On DCOL_OK fills *result and
/// gradient[0..12]. On DCOL_ERROR_NOT_CONVERGED fills *result with the last iterate and writes
/// the gradient only if all 12 entries are finite. On any other status nothing is written. Does
/// not allocate.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `position1`, `mrp1`, `position2`, `mrp2`
/// NULL or valid for reading 3 doubles; `options` NULL or valid; `result` NULL or valid for
/// writes; `gradient` NULL or valid for writing 12 doubles.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_gradient_mrp(
    shape1: *const dcol_shape,
    position1: *const f64,
    mrp1: *const f64,
    shape2: *const dcol_shape,
    position2: *const f64,
    mrp2: *const f64,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
    gradient: *mut f64,
) -> dcol_status {
    run("dcol_gradient_mrp", || {
        let outputs = [
            (result.is_null(), "result"),
            (gradient.is_null(), "gradient"),
        ];
        // SAFETY: forwarded from this function's contract.
        let m = unsafe {
            read_mrp_inputs(
                shape1, position1, mrp1, shape2, position2, mrp2, options, outputs,
            )
        }?;
        let (prox, g) = query::gradient_mrp(
            m.shape1,
            m.position1,
            m.mrp1,
            m.shape2,
            m.position2,
            m.mrp2,
            &m.options,
        )
        .map_err(Failure::api)?;
        let converged = prox.status.is_converged();
        let (r1, r2) = (m.position1.into(), m.position2.into());
        let finite = finite_array(&proximity_numbers(&prox));
        representable(finite && (!converged || finite_array(&g)), &r1, &r2)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        if prox.status.is_converged() || finite_array(&g) {
            // SAFETY: non-NULL (checked); the caller guarantees 12 writable doubles, and
            // `[f64; 12]` has the alignment of `f64`.
            unsafe { gradient.cast::<[f64; 12]>().write(g) };
        }
        outcome(&m.options, prox.status, prox.iterations)
    })
}

/// The Jacobian of (x*, alpha*) with respect to (r1, p1, r2, p2) for attitudes given as
/// modified Rodrigues parameters (see dcol_gradient_mrp): 4 x 12, row-major (48 doubles), rows
/// (x1, x2, x3, alpha), columns as in dcol_gradient_mrp; equal to the Jacobian of
/// dcol_jacobian times dq/dp (chain rule).
///
/// Inputs and validation as dcol_gradient_mrp. On DCOL_OK fills *result and jacobian[0..48]. On
/// DCOL_ERROR_NOT_CONVERGED fills *result with the last iterate and writes the Jacobian only if
/// all 48 entries are finite. On any other status nothing is written. Does not allocate.
///
/// # Safety
/// As dcol_gradient_mrp; `jacobian` must be NULL or valid for writing 48 doubles.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_jacobian_mrp(
    shape1: *const dcol_shape,
    position1: *const f64,
    mrp1: *const f64,
    shape2: *const dcol_shape,
    position2: *const f64,
    mrp2: *const f64,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
    jacobian: *mut f64,
) -> dcol_status {
    run("dcol_jacobian_mrp", || {
        let outputs = [
            (result.is_null(), "result"),
            (jacobian.is_null(), "jacobian"),
        ];
        // SAFETY: forwarded from this function's contract.
        let m = unsafe {
            read_mrp_inputs(
                shape1, position1, mrp1, shape2, position2, mrp2, options, outputs,
            )
        }?;
        let (prox, j) = query::jacobian_mrp(
            m.shape1,
            m.position1,
            m.mrp1,
            m.shape2,
            m.position2,
            m.mrp2,
            &m.options,
        )
        .map_err(Failure::api)?;
        let converged = prox.status.is_converged();
        let (r1, r2) = (m.position1.into(), m.position2.into());
        let finite = finite_array(&proximity_numbers(&prox));
        representable(finite && (!converged || all_finite(&j)), &r1, &r2)?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        if prox.status.is_converged() || all_finite(&j) {
            // SAFETY: non-NULL (checked); the caller guarantees 48 writable doubles, and
            // `[[f64; 12]; 4]` is 48 contiguous doubles (row-major) with `f64` alignment.
            unsafe { jacobian.cast::<[[f64; 12]; 4]>().write(j) };
        }
        outcome(&m.options, prox.status, prox.iterations)
    })
}
