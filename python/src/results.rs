//! The result classes: plain read-only records; vectors come out as new numpy arrays.

use dcol::{
    Contact, DerivativeKind, Derivatives, Distance, DistancePath, Proximity, SignedDistance,
    SolveStatus, Solver, Vec3,
};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;

fn v3(v: &Vec3) -> [f64; 3] {
    [v.x, v.y, v.z]
}

fn arr<'py>(py: Python<'py>, v: &[f64; 3]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, v)
}

/// A `(rows, cols)` numpy array of `m`.
pub fn matrix<'py, const R: usize, const C: usize>(
    py: Python<'py>,
    m: &[[f64; C]; R],
) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = m.iter().flatten().copied().collect();
    Array2::from_shape_vec((R, C), flat)
        .expect("R * C numbers")
        .into_pyarray(py)
}

fn solver_name(s: Solver) -> &'static str {
    match s {
        Solver::InteriorPoint => "interior_point",
        Solver::RayCast => "ray_cast",
        Solver::Polish => "polish",
        Solver::ClosedForm => "closed_form",
    }
}

fn derivative_name(d: DerivativeKind) -> &'static str {
    match d {
        DerivativeKind::None => "none",
        DerivativeKind::Exact => "exact",
        DerivativeKind::Smoothed => "smoothed",
        DerivativeKind::Subgradient => "subgradient",
    }
}

fn path_name(p: DistancePath) -> &'static str {
    match p {
        DistancePath::InteriorPoint => "interior_point",
        DistancePath::Gjk => "gjk",
        DistancePath::GjkPolish => "gjk_polish",
        DistancePath::ClosedForm => "closed_form",
        DistancePath::Epa => "epa",
        DistancePath::EpaPolish => "epa_polish",
        DistancePath::Segments => "segments",
        DistancePath::SeparatingAxes => "separating_axes",
    }
}

/// The answer of `dcol.proximity`: α* (> 1 separated, < 1 overlapping), the touching point x*
/// of the scaled shapes, and the contact point on each unscaled shape.
#[pyclass(frozen, module = "dcol", name = "Proximity")]
pub struct PyProximity {
    /// α*, the smallest scale at which the shapes touch.
    #[pyo3(get)]
    alpha: f64,
    point: [f64; 3],
    contact1: [f64; 3],
    contact2: [f64; 3],
    /// Interior-point iterations (0 when another solver answered).
    #[pyo3(get)]
    iterations: u32,
    /// Which solver answered: "closed_form", "ray_cast", "polish" or "interior_point".
    #[pyo3(get)]
    solver: &'static str,
    /// The derivatives' kind: "none" (proximity alone), "exact", "smoothed" or "subgradient".
    #[pyo3(get)]
    derivatives: &'static str,
    /// False only on the `.result` of a `dcol.Error` of status 5 (the last iterate).
    #[pyo3(get)]
    converged: bool,
}

impl From<&Proximity> for PyProximity {
    fn from(p: &Proximity) -> Self {
        PyProximity {
            alpha: p.alpha,
            point: v3(&p.point),
            contact1: v3(&p.contact1),
            contact2: v3(&p.contact2),
            iterations: p.iterations,
            solver: solver_name(p.solver),
            derivatives: derivative_name(p.derivatives),
            converged: p.status == SolveStatus::Converged,
        }
    }
}

#[pymethods]
impl PyProximity {
    /// x*, the point where the scaled shapes touch (world), shape (3,).
    #[getter]
    fn point<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.point)
    }

    /// The contact point on shape 1, `r1 + (x* - r1)/α*` (world), shape (3,).
    #[getter]
    fn contact1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.contact1)
    }

    /// The contact point on shape 2, `r2 + (x* - r2)/α*` (world), shape (3,).
    #[getter]
    fn contact2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.contact2)
    }

    fn __repr__(&self) -> String {
        format!(
            "Proximity(alpha={:?}, point={:?}, solver={:?})",
            self.alpha, self.point, self.solver
        )
    }
}

/// The answer of `dcol.distance`: the exact distance (0 when touching or overlapping), the
/// closest points and the unit normal from shape 1 to shape 2.
#[pyclass(frozen, module = "dcol", name = "Distance")]
pub struct PyDistance {
    /// The distance; 0 when the shapes touch or overlap.
    #[pyo3(get)]
    distance: f64,
    closest1: [f64; 3],
    closest2: [f64; 3],
    normal: [f64; 3],
    /// Interior-point iterations.
    #[pyo3(get)]
    iterations: u32,
    /// Which solver answered ("gjk", "gjk_polish", "closed_form", "interior_point", ...).
    #[pyo3(get)]
    path: &'static str,
    /// False only on the `.result` of a `dcol.Error` of status 5 (the last iterate).
    #[pyo3(get)]
    converged: bool,
}

impl From<&Distance> for PyDistance {
    fn from(d: &Distance) -> Self {
        PyDistance {
            distance: d.distance,
            closest1: v3(&d.closest1),
            closest2: v3(&d.closest2),
            normal: v3(&d.normal),
            iterations: d.iterations,
            path: path_name(d.path),
            converged: d.status == SolveStatus::Converged,
        }
    }
}

#[pymethods]
impl PyDistance {
    /// The closest point on shape 1 (world), shape (3,).
    #[getter]
    fn closest1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.closest1)
    }

    /// The closest point on shape 2 (world), shape (3,).
    #[getter]
    fn closest2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.closest2)
    }

    /// The unit normal from shape 1 to shape 2 (zero when the distance is 0), shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.normal)
    }

    fn __repr__(&self) -> String {
        format!(
            "Distance(distance={:?}, closest1={:?}, closest2={:?})",
            self.distance, self.closest1, self.closest2
        )
    }
}

/// The answer of `dcol.signed_distance`: the distance, or minus the penetration depth, with
/// the normal from shape 1 to shape 2 and the witness points (`closest2 - closest1 =
/// distance * normal`).
#[pyclass(frozen, module = "dcol", name = "SignedDistance")]
pub struct PySignedDistance {
    /// The distance when separated, minus the penetration depth when overlapping.
    #[pyo3(get)]
    distance: f64,
    normal: [f64; 3],
    closest1: [f64; 3],
    closest2: [f64; 3],
    /// Iterations of the solver that answered.
    #[pyo3(get)]
    iterations: u32,
    /// Which solver answered ("gjk", "epa", "separating_axes", ...).
    #[pyo3(get)]
    path: &'static str,
    /// False only on the `.result` of a `dcol.Error` of status 5 (the best answer found).
    #[pyo3(get)]
    converged: bool,
}

impl From<&SignedDistance> for PySignedDistance {
    fn from(d: &SignedDistance) -> Self {
        PySignedDistance {
            distance: d.distance,
            normal: v3(&d.normal),
            closest1: v3(&d.closest1),
            closest2: v3(&d.closest2),
            iterations: d.iterations,
            path: path_name(d.path),
            converged: d.status == SolveStatus::Converged,
        }
    }
}

#[pymethods]
impl PySignedDistance {
    /// The unit normal from shape 1 to shape 2, shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.normal)
    }

    /// The witness point on shape 1 (world), shape (3,).
    #[getter]
    fn closest1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.closest1)
    }

    /// The witness point on shape 2 (world), shape (3,).
    #[getter]
    fn closest2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.closest2)
    }

    fn __repr__(&self) -> String {
        format!(
            "SignedDistance(distance={:?}, normal={:?})",
            self.distance, self.normal
        )
    }
}

/// One point of a contact manifold (`dcol.contacts`).
#[pyclass(frozen, module = "dcol", name = "Contact")]
pub struct PyContact {
    position: [f64; 3],
    normal: [f64; 3],
    /// Penetration depth here: > 0 overlapping, < 0 apart (within the margin).
    #[pyo3(get)]
    depth: f64,
}

impl From<&Contact> for PyContact {
    fn from(c: &Contact) -> Self {
        PyContact {
            position: v3(&c.position),
            normal: v3(&c.normal),
            depth: c.depth,
        }
    }
}

#[pymethods]
impl PyContact {
    /// The world point midway between the surfaces, shape (3,).
    #[getter]
    fn position<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.position)
    }

    /// The manifold's unit normal from shape 1 to shape 2, shape (3,).
    #[getter]
    fn normal<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        arr(py, &self.normal)
    }

    fn __repr__(&self) -> String {
        format!(
            "Contact(position={:?}, normal={:?}, depth={:?})",
            self.position, self.normal, self.depth
        )
    }
}

/// Everything differentiable about one proximity query (`dcol.derivatives`).
#[pyclass(frozen, module = "dcol", name = "Derivatives")]
pub struct PyDerivatives {
    /// The proximity result.
    #[pyo3(get)]
    proximity: Py<PyProximity>,
    gradient: [f64; 14],
    jacobian: [[f64; 14]; 4],
    dcontact1: [[f64; 14]; 3],
    dcontact2: [[f64; 14]; 3],
}

impl PyDerivatives {
    pub fn new(py: Python<'_>, d: &Derivatives) -> PyResult<Self> {
        Ok(PyDerivatives {
            proximity: Py::new(py, PyProximity::from(&d.proximity))?,
            gradient: d.dalpha,
            jacobian: d.jacobian,
            dcontact1: d.dcontact1,
            dcontact2: d.dcontact2,
        })
    }
}

#[pymethods]
impl PyDerivatives {
    /// ∂α*/∂(r1, q1, r2, q2), shape (14,).
    #[getter]
    fn gradient<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.gradient)
    }

    /// ∂(x*, α*)/∂(r1, q1, r2, q2), rows (x1, x2, x3, α), shape (4, 14).
    #[getter]
    fn jacobian<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.jacobian)
    }

    /// ∂(contact point 1)/∂(r1, q1, r2, q2), shape (3, 14).
    #[getter]
    fn dcontact1<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.dcontact1)
    }

    /// ∂(contact point 2)/∂(r1, q1, r2, q2), shape (3, 14).
    #[getter]
    fn dcontact2<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.dcontact2)
    }
}

/// Adds the classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyProximity>()?;
    m.add_class::<PyDistance>()?;
    m.add_class::<PySignedDistance>()?;
    m.add_class::<PyContact>()?;
    m.add_class::<PyDerivatives>()?;
    Ok(())
}
