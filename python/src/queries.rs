//! One pair at a time: each function reads its inputs as the C function of the same name reads
//! them (pose 1, pose 2, then the options), calls the Rust API, and raises what the C function
//! would return: `dcol.Error` with its status and message, the last iterate as `.result` when
//! the solve did not converge (status 5).

use dcol::ffi::boundary::representable;
use dcol::{Distance, Options, Pose, Proximity, Shape, SolveStatus};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyList;

use crate::convert::{pose, Kw};
use crate::errors::{api_error, guard, not_converged};
use crate::results::{matrix, PyContact, PyDerivatives, PyDistance, PyProximity, PySignedDistance};
use crate::shapes::PyShape;

/// The inputs of one query, validated.
pub struct Inputs<'a> {
    pub s1: &'a Shape,
    pub p1: Pose,
    pub s2: &'a Shape,
    pub p2: Pose,
    pub opts: Options,
}

pub fn inputs<'a>(
    func: &str,
    shape1: &'a Bound<'_, PyShape>,
    pose1: &Bound<'_, PyAny>,
    shape2: &'a Bound<'_, PyShape>,
    pose2: &Bound<'_, PyAny>,
    kw: Kw<'_, '_>,
) -> PyResult<Inputs<'a>> {
    let p1 = pose(pose1, "pose1", func, "pose1->")?;
    let p2 = pose(pose2, "pose2", func, "pose2->")?;
    let opts = kw.options(shape1.py(), func)?;
    Ok(Inputs {
        s1: &shape1.get().inner,
        p1,
        s2: &shape2.get().inner,
        p2,
        opts,
    })
}

/// Runs `query` on the inputs under the panic guard; a rejected input becomes `dcol.Error`.
pub fn run<T>(
    py: Python<'_>,
    func: &str,
    q: &Inputs<'_>,
    query: impl FnOnce(&Inputs<'_>) -> Result<T, dcol::Error>,
) -> PyResult<T> {
    guard(py, func, || query(q))?.map_err(|e| api_error(py, func, "", e))
}

/// Refuses an answer a double cannot hold (`values`, about to be returned), as the C function
/// `func` refuses to write it: `dcol.Error` of status 3 naming the position.
pub fn check<'py>(py: Python<'py>, func: &str, q: &Inputs<'_>, values: &[&[f64]]) -> PyResult<()> {
    answer_representable(values, &q.p1, &q.p2).map_err(|e| api_error(py, func, "", e))
}

/// `Ok` when every number of `parts` is finite, otherwise the error the C functions return
/// for an answer a double cannot hold (`dcol::ffi::boundary::representable`'s). The common case
/// in one branch-free pass: x·0 is 0 for a finite x and NaN otherwise, so the sum is 0 exactly
/// when every number is finite.
pub fn answer_representable(parts: &[&[f64]], p1: &Pose, p2: &Pose) -> Result<(), dcol::Error> {
    let zero = |part: &[f64]| part.iter().fold(0.0, |sum, v| sum + v * 0.0) == 0.0;
    if parts.iter().all(|part| zero(part)) {
        return Ok(());
    }
    let all = parts.iter().flat_map(|part| part.iter().copied());
    representable(all, p1.position(), p2.position())
}

/// α*, x* and the contact points: the numbers of a proximity result the C functions check.
pub fn proximity_numbers(p: &Proximity) -> [f64; 10] {
    let [x, y, z] = [p.point, p.contact1, p.contact2];
    [p.alpha, x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z]
}

/// The distance, closest points and normal: the numbers of a distance result the C functions
/// check.
pub fn distance_numbers(d: &Distance) -> [f64; 10] {
    let [x, y, z] = [d.closest1, d.closest2, d.normal];
    [d.distance, x.x, x.y, x.z, y.x, y.y, y.z, z.x, z.y, z.z]
}

/// `values` when `converged`, none otherwise (a derivative the C functions check only when
/// the solve converged).
fn if_converged(converged: bool, values: &[f64]) -> &[f64] {
    if converged {
        values
    } else {
        &[]
    }
}

/// `value` when `status` converged; otherwise `dcol.Error` of status 5 with `value` as
/// `.result`.
pub fn finish<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    status: SolveStatus,
    iterations: u32,
    value: Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    if status.is_converged() {
        Ok(value)
    } else {
        Err(not_converged(
            py,
            func,
            status,
            iterations,
            &q.opts,
            value.unbind(),
        ))
    }
}

/// A proximity answer as `dcol.proximity` returns it (refused when a double cannot hold it,
/// raised when the solve did not converge).
pub fn proximity_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    p: Proximity,
) -> PyResult<Bound<'py, PyAny>> {
    check(py, func, q, &[&proximity_numbers(&p)])?;
    let value = Bound::new(py, PyProximity::from(&p))?.into_any();
    finish(py, func, q, p.status, p.iterations, value)
}

/// A gradient answer as `dcol.gradient` returns it, `(Proximity, ndarray (14,))`.
pub fn gradient_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    (p, g): (Proximity, [f64; 14]),
) -> PyResult<Bound<'py, PyAny>> {
    let grad = if_converged(p.status.is_converged(), &g);
    check(py, func, q, &[&proximity_numbers(&p), grad])?;
    let value = (PyProximity::from(&p), PyArray1::from_slice(py, &g))
        .into_pyobject(py)?
        .into_any();
    finish(py, func, q, p.status, p.iterations, value)
}

/// A Jacobian answer as `dcol.jacobian` returns it, `(Proximity, ndarray (4, 14))`.
pub fn jacobian_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    (p, j): (Proximity, [[f64; 14]; 4]),
) -> PyResult<Bound<'py, PyAny>> {
    let jac = if_converged(p.status.is_converged(), j.as_flattened());
    check(py, func, q, &[&proximity_numbers(&p), jac])?;
    let value = (PyProximity::from(&p), matrix(py, &j))
        .into_pyobject(py)?
        .into_any();
    finish(py, func, q, p.status, p.iterations, value)
}

/// A derivatives answer as `dcol.derivatives` returns it, `Derivatives`.
pub fn derivatives_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    d: dcol::Derivatives,
) -> PyResult<Bound<'py, PyAny>> {
    check(py, func, q, &[&proximity_numbers(&d.proximity)])?;
    if d.proximity.status.is_converged() {
        let all = [
            &d.dalpha[..],
            d.jacobian.as_flattened(),
            d.dcontact1.as_flattened(),
            d.dcontact2.as_flattened(),
        ];
        check(py, func, q, &all)?;
    }
    let value = Bound::new(py, PyDerivatives::new(py, &d)?)?.into_any();
    let p = d.proximity;
    finish(py, func, q, p.status, p.iterations, value)
}

/// A distance answer as `dcol.distance` returns it, `Distance`.
pub fn distance_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    d: Distance,
) -> PyResult<Bound<'py, PyAny>> {
    check(py, func, q, &[&distance_numbers(&d)])?;
    let value = Bound::new(py, PyDistance::from(&d))?.into_any();
    finish(py, func, q, d.status, d.iterations, value)
}

/// A distance-gradient answer as `dcol.distance_gradient` returns it, `(Distance, ndarray
/// (14,))`.
pub fn distance_gradient_value<'py>(
    py: Python<'py>,
    func: &str,
    q: &Inputs<'_>,
    (d, g): (Distance, [f64; 14]),
) -> PyResult<Bound<'py, PyAny>> {
    let grad = if_converged(d.status.is_converged(), &g);
    check(py, func, q, &[&distance_numbers(&d), grad])?;
    let value = (PyDistance::from(&d), PyArray1::from_slice(py, &g))
        .into_pyobject(py)?
        .into_any();
    finish(py, func, q, d.status, d.iterations, value)
}

/// α*, x* and the contact points of two posed shapes (`dcol_proximity`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn proximity<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_proximity";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let p = run(py, func, &q, |q| {
        dcol::proximity(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    proximity_value(py, func, &q, p)
}

/// `(result, gradient)`: proximity and ∂α*/∂(r1, q1, r2, q2), shape (14,) (`dcol_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn gradient<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let answer = run(py, func, &q, |q| {
        dcol::gradient(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    gradient_value(py, func, &q, answer)
}

/// `(result, jacobian)`: proximity and ∂(x*, α*)/∂(r1, q1, r2, q2), shape (4, 14)
/// (`dcol_jacobian`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn jacobian<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_jacobian";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let answer = run(py, func, &q, |q| {
        dcol::jacobian(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    jacobian_value(py, func, &q, answer)
}

/// Proximity, gradient, Jacobian and the contact points' Jacobians in one solve
/// (`dcol_derivatives`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn derivatives<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_derivatives";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let d = run(py, func, &q, |q| {
        dcol::derivatives(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    derivatives_value(py, func, &q, d)
}

/// The exact distance, closest points and normal (`dcol_distance`); 0 when touching or
/// overlapping.
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn distance<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_distance";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let d = run(py, func, &q, |q| {
        dcol::distance(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    distance_value(py, func, &q, d)
}

/// `(result, gradient)`: the distance and its gradient over (r1, q1, r2, q2), shape (14,)
/// (`dcol_distance_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn distance_gradient<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_distance_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let answer = run(py, func, &q, |q| {
        dcol::distance_gradient(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    distance_gradient_value(py, func, &q, answer)
}

/// The signed distance: the distance, or minus the penetration depth, with the normal and
/// witness points (`dcol_signed_distance`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn signed_distance<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_signed_distance";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let d = run(py, func, &q, |q| {
        dcol::signed_distance(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    let value = Bound::new(py, PySignedDistance::from(&d))?.into_any();
    finish(py, func, &q, d.status, d.iterations, value)
}

/// `(result, gradient)`: the signed distance and its gradient, shape (14,)
/// (`dcol_signed_distance_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn signed_distance_gradient<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_signed_distance_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let (d, g) = run(py, func, &q, |q| {
        dcol::signed_distance_gradient(q.s1, &q.p1, q.s2, &q.p2, &q.opts)
    })?;
    let value = (PySignedDistance::from(&d), PyArray1::from_slice(py, &g))
        .into_pyobject(py)?
        .into_any();
    finish(py, func, &q, d.status, d.iterations, value)
}

/// The contact manifold: a list of at most `max_points` (≤ 16) `Contact`s where the signed
/// distance is at most `margin`, sharing one normal (`dcol_contacts`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, margin=0.0, max_points=16, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn contacts<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    margin: f64,
    max_points: usize,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_contacts";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let m = run(py, func, &q, |q| {
        dcol::contact_manifold(q.s1, &q.p1, q.s2, &q.p2, margin, max_points, &q.opts)
    })?;
    let list = PyList::empty(py);
    for c in m.contacts() {
        list.append(PyContact::from(c))?;
    }
    finish(py, func, &q, m.status, m.iterations, list.into_any())
}

/// Whether α* < `threshold`, decided by bounds or an early exit when they can
/// (`dcol_alpha_below`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, threshold, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn alpha_below<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    threshold: f64,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    decide(
        py,
        "dcol_alpha_below",
        (shape1, pose1, shape2, pose2),
        threshold,
        kw,
    )
}

/// Whether the shapes overlap (α* < 1), decided by bounds or an early exit when they can
/// (`dcol_intersect`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn intersect<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    decide(
        py,
        "dcol_intersect",
        (shape1, pose1, shape2, pose2),
        1.0,
        kw,
    )
}

type Posed<'a, 'py> = (
    &'a Bound<'py, PyShape>,
    &'a Bound<'py, PyAny>,
    &'a Bound<'py, PyShape>,
    &'a Bound<'py, PyAny>,
);

fn decide<'py>(
    py: Python<'py>,
    func: &str,
    (shape1, pose1, shape2, pose2): Posed<'_, 'py>,
    threshold: f64,
    kw: Kw<'_, 'py>,
) -> PyResult<Bound<'py, PyAny>> {
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let d = run(py, func, &q, |q| {
        dcol::alpha_below(q.s1, &q.p1, q.s2, &q.p2, threshold, &q.opts)
    })?;
    let value = pyo3::types::PyBool::new(py, d.below).to_owned().into_any();
    finish(py, func, &q, d.status, d.iterations, value)
}

/// `(lower, upper)`: the closed-form bracket on α* from the shapes' bounding and inscribed
/// radii, with no solve.
#[pyfunction]
pub fn alpha_bounds<'py>(
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
) -> PyResult<(f64, f64)> {
    let func = "dcol.alpha_bounds";
    let p1 = pose(pose1, "pose1", func, "pose1->")?;
    let p2 = pose(pose2, "pose2", func, "pose2->")?;
    guard(shape1.py(), func, || {
        dcol::alpha_bounds(&shape1.get().inner, &p1, &shape2.get().inner, &p2)
    })
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(proximity, m)?)?;
    m.add_function(wrap_pyfunction!(gradient, m)?)?;
    m.add_function(wrap_pyfunction!(jacobian, m)?)?;
    m.add_function(wrap_pyfunction!(derivatives, m)?)?;
    m.add_function(wrap_pyfunction!(distance, m)?)?;
    m.add_function(wrap_pyfunction!(distance_gradient, m)?)?;
    m.add_function(wrap_pyfunction!(signed_distance, m)?)?;
    m.add_function(wrap_pyfunction!(signed_distance_gradient, m)?)?;
    m.add_function(wrap_pyfunction!(contacts, m)?)?;
    m.add_function(wrap_pyfunction!(alpha_below, m)?)?;
    m.add_function(wrap_pyfunction!(intersect, m)?)?;
    m.add_function(wrap_pyfunction!(alpha_bounds, m)?)?;
    Ok(())
}
