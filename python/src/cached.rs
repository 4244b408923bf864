//! Warm starts: `dcol.Cache`, a per-pair cache of the pair's last answer (`dcol::Cache`), and
//! the queries that read and update it (`proximity_cached`, ..., `distance_gradient_cached`,
//! `intersect_cached`).
//! Each takes the plain query's arguments and options plus the cache, gives the plain query's
//! answer (certified the same way, the same result classes), and raises what the C function of
//! the same name would (`dcol_proximity_cached`, ...).

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::convert::Kw;
use crate::queries::{
    derivatives_value, distance_gradient_value, distance_value, finish, gradient_value, inputs,
    jacobian_value, proximity_value, run,
};
use crate::shapes::PyShape;

/// A per-pair warm-start cache, cold when made: keep one per pair of shapes and pass it to
/// every `*_cached` query on that pair. It then holds the pair's last answer, and a query on
/// poses that moved a little since starts from it (between polytopes: boxes, polytopes,
/// unpadded hulls); the answer is the plain query's either way. A cache used for another pair
/// costs one cold query and is then that pair's: it never makes an answer wrong.
///
/// `copy.copy` (and `copy.deepcopy`) give an independent cache holding the same answer; a cache
/// cannot be pickled (it is a warm start, not data: make a new one).
#[pyclass(module = "dcol", name = "Cache")]
pub struct PyCache {
    inner: dcol::Cache,
}

#[pymethods]
impl PyCache {
    /// A cold cache.
    #[new]
    fn new() -> Self {
        PyCache {
            inner: dcol::Cache::new(),
        }
    }

    /// Whether the cache holds an answer to start from (False: the next query is cold).
    #[getter]
    fn is_warm(&self) -> bool {
        self.inner.is_warm()
    }

    /// Forgets what the cache holds (the next query is cold).
    fn clear(&mut self) {
        self.inner.clear();
    }

    /// An independent cache holding the same answer.
    fn __copy__(&self) -> Self {
        PyCache { inner: self.inner }
    }

    /// An independent cache holding the same answer (as `__copy__`: it holds no objects).
    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> Self {
        PyCache { inner: self.inner }
    }

    /// Refuses to pickle: a cache is a warm start, not data worth storing.
    fn __reduce__(&self) -> PyResult<()> {
        Err(PyTypeError::new_err(
            "cannot pickle 'dcol.Cache': it is a warm start, not data; make a new dcol.Cache() \
             (cold) where the pair is queried again",
        ))
    }

    fn __repr__(&self) -> String {
        let warm = if self.inner.is_warm() {
            "True"
        } else {
            "False"
        };
        format!("dcol.Cache(is_warm={warm})")
    }
}

/// Declares one cached query: the plain query's signature with `cache` after the poses, the
/// Rust function `$rust` called with the cache, the answer returned as `$value` returns it.
macro_rules! cached_query {
    ($(#[$doc:meta])* $name:ident, $func:literal, $rust:path, $value:ident) => {
        $(#[$doc])*
        #[pyfunction]
        #[pyo3(signature = (shape1, pose1, shape2, pose2, cache, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
        #[allow(clippy::too_many_arguments)]
        pub fn $name<'py>(
            py: Python<'py>,
            shape1: &Bound<'py, PyShape>,
            pose1: &Bound<'py, PyAny>,
            shape2: &Bound<'py, PyShape>,
            pose2: &Bound<'py, PyAny>,
            mut cache: PyRefMut<'py, PyCache>,
            tolerance: Option<f64>,
            max_iterations: Option<i64>,
            method: Option<&Bound<'py, PyAny>>,
            smoothing: Option<f64>,
        ) -> PyResult<Bound<'py, PyAny>> {
            let func = $func;
            let kw = Kw {
                tolerance,
                max_iterations,
                method,
                smoothing,
            };
            let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
            let c = &mut cache.inner;
            let answer = run(py, func, &q, |q| $rust(q.s1, &q.p1, q.s2, &q.p2, &q.opts, c))?;
            $value(py, func, &q, answer)
        }
    };
}

cached_query!(
    /// `dcol.proximity` with a warm start from `cache` (a `dcol.Cache`, one per pair), which
    /// then holds this answer (`dcol_proximity_cached`). Between polytopes on poses that moved
    /// a little since the pair's last answer, the answer is found from the kept contact
    /// features (`result.solver == "polish"`); it is certified as the plain one and agrees with
    /// it to the solver's tolerance.
    proximity_cached,
    "dcol_proximity_cached",
    dcol::proximity_cached,
    proximity_value
);

cached_query!(
    /// `dcol.gradient` with a warm start from `cache` (see `proximity_cached`):
    /// `(Proximity, ndarray (14,))` (`dcol_gradient_cached`).
    gradient_cached,
    "dcol_gradient_cached",
    dcol::gradient_cached,
    gradient_value
);

cached_query!(
    /// `dcol.jacobian` with a warm start from `cache` (see `proximity_cached`):
    /// `(Proximity, ndarray (4, 14))` (`dcol_jacobian_cached`).
    jacobian_cached,
    "dcol_jacobian_cached",
    dcol::jacobian_cached,
    jacobian_value
);

cached_query!(
    /// `dcol.derivatives` with a warm start from `cache` (see `proximity_cached`):
    /// `Derivatives` (`dcol_derivatives_cached`).
    derivatives_cached,
    "dcol_derivatives_cached",
    dcol::derivatives_cached,
    derivatives_value
);

cached_query!(
    /// `dcol.distance` with a warm start from `cache` (a `dcol.Cache`, one per pair), which
    /// then holds this answer (`dcol_distance_cached`). Between polytopes the closest features
    /// of the pair's last answer are re-solved in closed form and certified as GJK's answer is
    /// (`result.path == "gjk_polish"`); the same distance to the tolerance.
    distance_cached,
    "dcol_distance_cached",
    dcol::distance_cached,
    distance_value
);

cached_query!(
    /// `dcol.distance_gradient` with a warm start from `cache` (see `distance_cached`):
    /// `(Distance, ndarray (14,))` (`dcol_distance_gradient_cached`).
    distance_gradient_cached,
    "dcol_distance_gradient_cached",
    dcol::distance_gradient_cached,
    distance_gradient_value
);

/// `dcol.intersect` with a warm start from `cache` (a `dcol.Cache`, one per pair), which then
/// holds what this call found (`dcol_intersect_cached`): a separating normal kept from the
/// pair's last answer that still separates the shapes answers `False` from two support calls;
/// between polytopes the kept contact is re-solved in closed form; otherwise the plain query
/// answers. Always the plain query's decision.
#[pyfunction]
#[pyo3(signature = (shape1, pose1, shape2, pose2, cache, *, tolerance=None, max_iterations=None, method=None, smoothing=None))]
#[allow(clippy::too_many_arguments)]
pub fn intersect_cached<'py>(
    py: Python<'py>,
    shape1: &Bound<'py, PyShape>,
    pose1: &Bound<'py, PyAny>,
    shape2: &Bound<'py, PyShape>,
    pose2: &Bound<'py, PyAny>,
    mut cache: PyRefMut<'py, PyCache>,
    tolerance: Option<f64>,
    max_iterations: Option<i64>,
    method: Option<&Bound<'py, PyAny>>,
    smoothing: Option<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let func = "dcol_intersect_cached";
    let kw = Kw {
        tolerance,
        max_iterations,
        method,
        smoothing,
    };
    let q = inputs(func, shape1, pose1, shape2, pose2, kw)?;
    let c = &mut cache.inner;
    let d = run(py, func, &q, |q| {
        dcol::intersect_cached(q.s1, &q.p1, q.s2, &q.p2, &q.opts, c)
    })?;
    let value = pyo3::types::PyBool::new(py, d.below).to_owned().into_any();
    finish(py, func, &q, d.status, d.iterations, value)
}

/// Adds `Cache` and the cached queries to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyCache>()?;
    m.add_function(wrap_pyfunction!(proximity_cached, m)?)?;
    m.add_function(wrap_pyfunction!(gradient_cached, m)?)?;
    m.add_function(wrap_pyfunction!(jacobian_cached, m)?)?;
    m.add_function(wrap_pyfunction!(derivatives_cached, m)?)?;
    m.add_function(wrap_pyfunction!(distance_cached, m)?)?;
    m.add_function(wrap_pyfunction!(distance_gradient_cached, m)?)?;
    m.add_function(wrap_pyfunction!(intersect_cached, m)?)?;
    Ok(())
}
