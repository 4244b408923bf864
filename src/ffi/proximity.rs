//! `dcol_proximity_result`, `dcol_proximity`, `dcol_gradient` and `dcol_jacobian`.

use super::boundary::{check_out, run, Failure};
use super::cache::{cache_mut, dcol_cache};
use super::finite::{proximity_numbers, representable};
use super::options::{dcol_options, plain_tolerance, read_options};
use super::pose::{dcol_pose, read_pose};
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::math::{all_finite, finite_array, Pose, Vec3};
use crate::query::{self, Options, Proximity};
use crate::shapes::Shape;
use crate::solver::{DerivativeKind, SolveStatus, Solver};

/// The proximity of two posed shapes: the smallest uniform scaling alpha of both shapes (each
/// about its own origin) at which they touch. alpha > 1: separated, alpha < 1:
/// interpenetrating, alpha = 1: touching; alpha = 0 only when the two origins coincide, or when
/// one shape is a half-space and the other's origin lies in it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_proximity_result {
    /// alpha*, the optimal scaling.
    pub alpha: f64,
    /// x*, an optimal intersection point of the scaled shapes (world).
    pub point: [f64; 3],
    /// p1 = r1 + (x* - r1) / alpha*, on the boundary of shape 1 (world); r1 when alpha* = 0.
    pub contact1: [f64; 3],
    /// p2 = r2 + (x* - r2) / alpha*, on the boundary of shape 2 (world); r2 when alpha* = 0.
    pub contact2: [f64; 3],
    /// Interior-point iterations used (0 when another solver answered: see `solver`).
    pub iterations: u32,
    /// Which solver answered: DCOL_SOLVER_INTERIOR_POINT (0), DCOL_SOLVER_RAY_CAST (1, the ray
    /// cast on support maps closed its certified bracket), DCOL_SOLVER_POLISH (2, the ray cast
    /// then a Newton polish on the contact features it identified) or DCOL_SOLVER_CLOSED_FORM
    /// (3). (Appended after the original fields.)
    pub solver: u32,
    /// What kind of derivatives the query returned: DCOL_DERIVATIVES_NONE (0, none asked for),
    /// DCOL_DERIVATIVES_EXACT (1), DCOL_DERIVATIVES_SMOOTHED (2: the barrier-smoothed
    /// derivatives of the central-path point, where x* is not unique and the exact Jacobian
    /// does not exist, or when dcol_options.smoothing asked for them) or
    /// DCOL_DERIVATIVES_SUBGRADIENT (3: alpha* is not differentiable and one element of its
    /// generalised gradient is returned: zero at coincident origins; flat against flat, the
    /// envelope formula at the contact point when the smoothed one could not be computed).
    /// (Appended after `solver`.)
    pub derivatives: u32,
}

/// dcol_proximity_result.derivatives: no derivatives were asked for.
pub const DCOL_DERIVATIVES_NONE: u32 = 0;
/// dcol_proximity_result.derivatives: the exact derivatives.
pub const DCOL_DERIVATIVES_EXACT: u32 = 1;
/// dcol_proximity_result.derivatives: the barrier-smoothed derivatives of the central path.
pub const DCOL_DERIVATIVES_SMOOTHED: u32 = 2;
/// dcol_proximity_result.derivatives: one element of the generalised gradient.
pub const DCOL_DERIVATIVES_SUBGRADIENT: u32 = 3;

/// dcol_proximity_result.solver: the interior-point solver.
pub const DCOL_SOLVER_INTERIOR_POINT: u32 = 0;
/// dcol_proximity_result.solver: a certified ray cast on support maps (portal refinement, or
/// GJK on the cores of spheres, capsules and padded polygons against polytopes and each other).
pub const DCOL_SOLVER_RAY_CAST: u32 = 1;
/// dcol_proximity_result.solver: the ray cast and a Newton polish on the contact features.
pub const DCOL_SOLVER_POLISH: u32 = 2;
/// dcol_proximity_result.solver: a closed form for the pair (spheres, capsules, a sphere and a
/// box, cylinder or cone, and every pair with a half-space).
pub const DCOL_SOLVER_CLOSED_FORM: u32 = 3;

fn arr(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl From<&Proximity> for dcol_proximity_result {
    fn from(p: &Proximity) -> Self {
        dcol_proximity_result {
            alpha: p.alpha,
            point: arr(&p.point),
            contact1: arr(&p.contact1),
            contact2: arr(&p.contact2),
            iterations: p.iterations,
            solver: match p.solver {
                Solver::InteriorPoint => DCOL_SOLVER_INTERIOR_POINT,
                Solver::RayCast => DCOL_SOLVER_RAY_CAST,
                Solver::Polish => DCOL_SOLVER_POLISH,
                Solver::ClosedForm => DCOL_SOLVER_CLOSED_FORM,
            },
            derivatives: match p.derivatives {
                DerivativeKind::None => DCOL_DERIVATIVES_NONE,
                DerivativeKind::Exact => DCOL_DERIVATIVES_EXACT,
                DerivativeKind::Smoothed => DCOL_DERIVATIVES_SMOOTHED,
                DerivativeKind::Subgradient => DCOL_DERIVATIVES_SUBGRADIENT,
            },
        }
    }
}

/// The validated, copied inputs of a query.
pub(crate) struct Inputs<'a> {
    pub shape1: &'a Shape,
    pub pose1: Pose,
    pub shape2: &'a Shape,
    pub pose2: Pose,
    pub options: Options,
}

impl Inputs<'_> {
    /// `DCOL_ERROR_NOT_CONVERGED` for a solve that ended with `status`, or `Ok`.
    pub(crate) fn outcome(&self, status: SolveStatus, iterations: u32) -> Result<(), Failure> {
        outcome(&self.options, status, iterations)
    }

    /// `DCOL_ERROR_INVALID_POSE` unless every number in `parts` (the answer about to be
    /// written) is finite.
    pub(crate) fn representable(&self, finite: bool) -> Result<(), Failure> {
        representable(finite, self.pose1.position(), self.pose2.position())
    }
}

/// `DCOL_ERROR_NOT_CONVERGED` for a solve with `options` that ended with `status`, or `Ok`.
pub(crate) fn outcome(
    options: &Options,
    status: SolveStatus,
    iterations: u32,
) -> Result<(), Failure> {
    if status.is_converged() {
        Ok(())
    } else {
        Err(Failure::NotConverged {
            status,
            iterations,
            max_iterations: options.max_iterations,
            tolerance: options.tolerance,
        })
    }
}

/// Checks the four input pointers for NULL, then copies and validates the poses and options.
/// Output pointers must be NULL-checked by the caller *between* the two steps; hence two parts.
///
/// # Safety
/// Each pointer must be NULL or valid for its type (shapes live for `'a`).
pub(crate) unsafe fn check_inputs<'a>(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
) -> Result<(&'a Shape, &'a Shape), Failure> {
    // SAFETY: forwarded from this function's contract.
    let s1 = unsafe { shape_ref(shape1, "shape1") }?;
    if pose1.is_null() {
        return Err(Failure::Null("pose1"));
    }
    // SAFETY: forwarded from this function's contract.
    let s2 = unsafe { shape_ref(shape2, "shape2") }?;
    if pose2.is_null() {
        return Err(Failure::Null("pose2"));
    }
    Ok((s1, s2))
}

/// Copies and validates poses and options (pointers already checked by `check_inputs`).
///
/// # Safety
/// `pose1`, `pose2` must be valid; `options` NULL or valid.
#[inline(always)]
pub(crate) unsafe fn read_inputs<'a>(
    shapes: (&'a Shape, &'a Shape),
    pose1: *const dcol_pose,
    pose2: *const dcol_pose,
    options: *const dcol_options,
) -> Result<Inputs<'a>, Failure> {
    // SAFETY: forwarded from this function's contract.
    let (p1, p2, options) = unsafe {
        (
            read_pose(pose1, "pose1", "pose1->")?,
            read_pose(pose2, "pose2", "pose2->")?,
            read_options(options)?,
        )
    };
    Ok(Inputs {
        shape1: shapes.0,
        pose1: p1,
        shape2: shapes.1,
        pose2: p2,
        options,
    })
}

/// alpha*, x* and the contact points of two posed shapes.
///
/// `options` may be NULL (defaults). Returns DCOL_OK and fills *result; or
/// DCOL_ERROR_NOT_CONVERGED and fills *result with the last iterate (the interior-point
/// method's feasible start, an upper bound on alpha*, when that iterate is not representable);
/// or an error status, the last error message set, and *result untouched.
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `result` NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_proximity(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        proximity_in(
            "dcol_proximity",
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

/// dcol_proximity with a warm start: `cache` is the pair's `dcol_cache` (DCOL_CACHE_INIT the first
/// time, then what the last call on the pair left in it). The answer is certified as dcol_proximity's
/// and agrees with it to the solver's tolerance; the cache then holds this answer. A cache
/// of another pair or of changed shapes is harmless (that call runs cold).
///
/// # Safety
/// As dcol_proximity; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_proximity_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_proximity_result,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        proximity_in(
            "dcol_proximity_cached",
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

/// The body of `dcol_proximity` and `dcol_proximity_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_proximity`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn proximity_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_proximity_result,
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
        let prox = match warm {
            Some(c) => {
                query::proximity_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            }
            None => query::proximity(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        q.representable(finite_array(&proximity_numbers(&prox)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        q.outcome(prox.status, prox.iterations)
    })
}

/// The closed-form lane (`query::closed_lane`): the answer of a pair with a closed form when
/// every pointer is non-NULL, the options are plain ([`plain_tolerance`]) and the lane answers
/// (the same numbers the full path gives, all finite, converged); `None` sends the call to the
/// full path, which answers the same or reports the error. About half of a sphere–sphere call
/// was the full path's dispatch around the closed form (`docs/geometric-solver.md`).
///
/// # Safety
/// As `dcol_proximity`.
#[inline(always)]
pub(crate) unsafe fn closed_lane(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
) -> Option<dcol_proximity_result> {
    if pose1.is_null() || pose2.is_null() || result.is_null() {
        return None;
    }
    // SAFETY: forwarded from this function's contract (NULL is checked by `shape_ref` and above).
    let (s1, s2, p1, p2, plain) = unsafe {
        (
            shape_ref(shape1, "shape1").ok()?,
            shape_ref(shape2, "shape2").ok()?,
            &*pose1,
            &*pose2,
            plain_tolerance(options).is_some(),
        )
    };
    if !plain {
        return None;
    }
    let prox = query::closed_lane::proximity(
        s1,
        (&p1.position, &p1.quaternion),
        s2,
        (&p2.position, &p2.quaternion),
    )?;
    Some((&prox).into())
}

/// The gradient of alpha* with respect to (r1, q1, r2, q2): 14 numbers, in that order, the
/// quaternion columns with respect to the four numbers given (through the normalisation).
/// result->derivatives says its kind: exact where the contact points are unique (from the
/// geometric solution by default), the interior-point method's smoothed one flat against flat,
/// or the central path's with dcol_options.smoothing.
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and gradient[0..14]. On
/// DCOL_ERROR_NOT_CONVERGED fills *result with the last iterate and writes that iterate's
/// gradient (from its multipliers) only if all 14 entries are finite. On any other status
/// nothing is written.
///
/// # Safety
/// As dcol_proximity; `gradient` must be NULL or valid for writing 14 doubles.
#[no_mangle]
pub unsafe extern "C" fn dcol_gradient(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
    gradient: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        gradient_in(
            "dcol_gradient",
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

/// dcol_gradient with a warm start: `cache` is the pair's `dcol_cache` (DCOL_CACHE_INIT the first
/// time, then what the last call on the pair left in it). The answer is certified as dcol_gradient's
/// and agrees with it to the solver's tolerance; the cache then holds this answer. A cache
/// of another pair or of changed shapes is harmless (that call runs cold).
///
/// # Safety
/// As dcol_gradient; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_gradient_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_proximity_result,
    gradient: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        gradient_in(
            "dcol_gradient_cached",
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

/// The body of `dcol_gradient` and `dcol_gradient_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_gradient`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn gradient_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_proximity_result,
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
        let (prox, g) = match warm {
            Some(c) => {
                query::gradient_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            }
            None => query::gradient(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        let converged = prox.status.is_converged();
        q.representable(
            finite_array(&proximity_numbers(&prox)) && (!converged || finite_array(&g)),
        )?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        if prox.status.is_converged() || finite_array(&g) {
            // SAFETY: non-NULL (checked); the caller guarantees 14 writable doubles, and
            // `[f64; 14]` has the alignment of `f64`.
            unsafe { gradient.cast::<[f64; 14]>().write(g) };
        }
        q.outcome(prox.status, prox.iterations)
    })
}

/// The Jacobian of (x*, alpha*) with respect to (r1, q1, r2, q2): 4 x 14, row-major (56
/// doubles), rows (x1, x2, x3, alpha), columns as in dcol_gradient. By default it comes from
/// the geometric solution's contact features where x* is unique (DCOL_DERIVATIVES_EXACT);
/// where it is not (flat against flat) the exact Jacobian does not exist and the interior-point
/// method's barrier-smoothed one is returned (DCOL_DERIVATIVES_SMOOTHED in
/// result->derivatives).
///
/// `options` may be NULL (defaults). On DCOL_OK fills *result and jacobian[0..56]. On
/// DCOL_ERROR_NOT_CONVERGED fills *result with the last iterate and writes that iterate's
/// (barrier-smoothed) Jacobian only if all 56 entries are finite. On any other status nothing
/// is written.
///
/// # Safety
/// As dcol_proximity; `jacobian` must be NULL or valid for writing 56 doubles.
#[no_mangle]
pub unsafe extern "C" fn dcol_jacobian(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    result: *mut dcol_proximity_result,
    jacobian: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        jacobian_in(
            "dcol_jacobian",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            None,
            result,
            jacobian,
        )
    }
}

/// dcol_jacobian with a warm start: `cache` is the pair's `dcol_cache` (DCOL_CACHE_INIT the first
/// time, then what the last call on the pair left in it). The answer is certified as dcol_jacobian's
/// and agrees with it to the solver's tolerance; the cache then holds this answer. A cache
/// of another pair or of changed shapes is harmless (that call runs cold).
///
/// # Safety
/// As dcol_jacobian; `cache` NULL or valid for reads and writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_jacobian_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    result: *mut dcol_proximity_result,
    jacobian: *mut f64,
) -> dcol_status {
    // SAFETY: forwarded from this function's contract.
    unsafe {
        jacobian_in(
            "dcol_jacobian_cached",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            Some(cache),
            result,
            jacobian,
        )
    }
}

/// The body of `dcol_jacobian` and `dcol_jacobian_cached` (`cache`: `None` for the first).
///
/// # Safety
/// As `dcol_jacobian`; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments)]
unsafe fn jacobian_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    result: *mut dcol_proximity_result,
    jacobian: *mut f64,
) -> dcol_status {
    run(name, || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        check_out(result, "result")?;
        check_out(jacobian, "jacobian")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let (prox, j) = match warm {
            Some(c) => {
                query::jacobian_cached(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options, c)
            }
            None => query::jacobian(q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options),
        }
        .map_err(Failure::api)?;
        let converged = prox.status.is_converged();
        q.representable(finite_array(&proximity_numbers(&prox)) && (!converged || all_finite(&j)))?;
        // SAFETY: `result` is non-NULL (checked) and valid for writes (contract).
        unsafe { result.write((&prox).into()) };
        if prox.status.is_converged() || all_finite(&j) {
            // SAFETY: non-NULL (checked); the caller guarantees 56 writable doubles, and
            // `[[f64; 14]; 4]` is 56 contiguous doubles (row-major) with `f64` alignment.
            unsafe { jacobian.cast::<[[f64; 14]; 4]>().write(j) };
        }
        q.outcome(prox.status, prox.iterations)
    })
}
