//! The derivatives with respect to the shapes' own parameters (the numbers given to their
//! constructors, `Shape.parameters`): `shape_gradient`, `distance_shape_gradient` and
//! `signed_distance_shape_gradient`, each reading its inputs and checking its answer as the C
//! function of the same name does (`dcol_shape_gradient`, ...).

use dcol::{Options, Pose, Shape};
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::convert::Kw;
use crate::queries::{check, distance_numbers, finish, inputs, proximity_numbers, run, Inputs};
use crate::results::{PyDistance, PyProximity, PySignedDistance};
use crate::shapes::PyShape;

/// The two derivative buffers of a query on `q`, zeroed, each its shape's parameter count long.
fn buffers(q: &Inputs<'_>) -> (Vec<f64>, Vec<f64>) {
    let (n1, n2) = (q.s1.parameter_count(), q.s2.parameter_count());
    (vec![0.0; n1], vec![0.0; n2])
}

/// A Rust shape-gradient query: the inputs, then the two derivative buffers.
type Query<T> = fn(
    &Shape,
    &Pose,
    &Shape,
    &Pose,
    &Options,
    Option<&mut [f64]>,
    Option<&mut [f64]>,
) -> Result<T, dcol::Error>;

/// Runs `query` on the validated inputs with both buffers wanted (as a C caller passing both):
/// the answer and the two derivative vectors.
fn solve<T>(
    py: Python<'_>,
    func: &str,
    q: &Inputs<'_>,
    query: Query<T>,
) -> PyResult<(T, Vec<f64>, Vec<f64>)> {
    let (mut d1, mut d2) = buffers(q);
    let value = run(py, func, q, |q| {
        query(
            q.s1,
            &q.p1,
            q.s2,
            &q.p2,
            &q.opts,
            Some(&mut d1),
            Some(&mut d2),
        )
    })?;
    Ok((value, d1, d2))
}

/// `(result, d1, d2)` as a Python tuple `(result, ndarray (n1,), ndarray (n2,))`.
fn triple<'py, R: IntoPyObject<'py>>(
    py: Python<'py>,
    result: R,
    d1: &[f64],
    d2: &[f64],
) -> PyResult<Bound<'py, PyAny>> {
    let out = (
        result,
        PyArray1::from_slice(py, d1),
        PyArray1::from_slice(py, d2),
    );
    Ok(out.into_pyobject(py)?.into_any())
}

/// `(result, d1, d2)`: proximity and ∂α*/∂θ with respect to each shape's parameters
/// (`Shape.parameters`), shapes (n1,) and (n2,) (`dcol_shape_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn shape_gradient<'py>(
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
    let func = "dcol_shape_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let (p, d1, d2) = solve(py, func, &q, dcol::shape_gradient)?;
    // As the C function: the answer's numbers are checked; the derivatives are finite (zeros
    // and a status saying so where they would not be).
    check(py, func, &q, &[&proximity_numbers(&p)])?;
    let value = triple(py, PyProximity::from(&p), &d1, &d2)?;
    finish(py, func, &q, p.status, p.iterations, value)
}

/// `(result, d1, d2)`: the distance and its derivatives with respect to each shape's
/// parameters, zeros when touching or overlapping (`dcol_distance_shape_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn distance_shape_gradient<'py>(
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
    let func = "dcol_distance_shape_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let (d, d1, d2) = solve(py, func, &q, dcol::distance_shape_gradient)?;
    check(py, func, &q, &[&distance_numbers(&d)])?;
    let value = triple(py, PyDistance::from(&d), &d1, &d2)?;
    finish(py, func, &q, d.status, d.iterations, value)
}

/// `(result, d1, d2)`: the signed distance and its derivatives with respect to each shape's
/// parameters, separated or overlapping (`dcol_signed_distance_shape_gradient`).
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn signed_distance_shape_gradient<'py>(
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
    let func = "dcol_signed_distance_shape_gradient";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let (d, d1, d2) = solve(py, func, &q, dcol::signed_distance_shape_gradient)?;
    // As the C function (and `signed_distance`): no check of the answer's numbers.
    let value = triple(py, PySignedDistance::from(&d), &d1, &d2)?;
    finish(py, func, &q, d.status, d.iterations, value)
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(shape_gradient, m)?)?;
    m.add_function(wrap_pyfunction!(distance_shape_gradient, m)?)?;
    m.add_function(wrap_pyfunction!(signed_distance_shape_gradient, m)?)?;
    Ok(())
}
