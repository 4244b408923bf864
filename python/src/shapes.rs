//! `dcol.Shape` and its constructors. Each constructor is a subclass (`dcol.Sphere(0.5)` is a
//! `dcol.Shape`) that keeps its arguments as read-only attributes; the base class holds the
//! validated `dcol::Shape`, immutable and shared by every query and thread.

use dcol::{Shape, ShapeKind};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::convert::{matrix, vector};
use crate::errors::{api_error, guard};

/// A convex shape, built by one of the constructors below; immutable, hashable by identity,
/// and safe to share between threads.
#[pyclass(frozen, subclass, module = "dcol", name = "Shape")]
pub struct PyShape {
    pub inner: Shape,
    repr: String,
}

impl PyShape {
    fn build(
        py: Python<'_>,
        func: &str,
        make: impl FnOnce() -> Result<Shape, dcol::Error>,
        repr: String,
    ) -> PyResult<PyShape> {
        let shape = guard(py, func, make)?.map_err(|e| api_error(py, func, "", e))?;
        Ok(PyShape { inner: shape, repr })
    }
}

fn kind_name(k: ShapeKind) -> &'static str {
    match k {
        ShapeKind::Sphere => "sphere",
        ShapeKind::Ellipsoid => "ellipsoid",
        ShapeKind::Polytope => "polytope",
        ShapeKind::Capsule => "capsule",
        ShapeKind::Cylinder => "cylinder",
        ShapeKind::Cone => "cone",
        ShapeKind::Polygon => "polygon",
        ShapeKind::Halfspace => "halfspace",
        ShapeKind::ConvexHull => "convex_hull",
    }
}

#[pymethods]
impl PyShape {
    /// The primitive: "sphere", "ellipsoid", "polytope" (boxes too), "capsule", "cylinder",
    /// "cone", "polygon", "halfspace" or "convex_hull".
    #[getter]
    fn kind(&self) -> &'static str {
        kind_name(self.inner.kind())
    }

    /// Radius of the smallest ball about the body origin that holds the shape (inf for a
    /// half-space).
    #[getter]
    fn bounding_radius(&self) -> f64 {
        self.inner.bounding_radius()
    }

    /// Radius of a ball about the body origin inside the shape.
    #[getter]
    fn inscribed_radius(&self) -> f64 {
        self.inner.inscribed_radius()
    }

    /// The numbers the constructor was given, in its order (`dcol_shape_parameters`): the
    /// shape gradients are taken with respect to them. Sphere: radius; Ellipsoid: P row-major
    /// (symmetrised, (P + Pᵀ)/2); Polytope: A row-major, then b; Box: the half extents;
    /// Capsule, Cylinder: radius, length; Cone: height, half_angle; Polygon: C row-major, d,
    /// radius; HalfSpace: depth; ConvexHull: the points row-major, then radius.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let p = guard(py, "dcol_shape_parameters", || self.inner.parameters())?;
        Ok(PyArray1::from_vec(py, p))
    }

    /// How many numbers `parameters` holds (`dcol_shape_parameter_count`).
    #[getter]
    fn parameter_count(&self) -> usize {
        self.inner.parameter_count()
    }

    fn __repr__(&self) -> String {
        self.repr.clone()
    }
}

fn rows<const D: usize>(flat: &[f64]) -> Vec<[f64; D]> {
    flat.chunks_exact(D)
        .map(|c| std::array::from_fn(|i| c[i]))
        .collect()
}

fn array2<'py>(py: Python<'py>, flat: &[f64], cols: usize) -> Bound<'py, PyArray2<f64>> {
    let rows = flat.len() / cols;
    Array2::from_shape_vec((rows, cols), flat.to_vec())
        .expect("the stored arrays have whole rows")
        .into_pyarray(py)
}

/// A ball of `radius` about the body origin.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Sphere {
    /// The radius.
    #[pyo3(get)]
    radius: f64,
}

#[pymethods]
impl Sphere {
    #[new]
    fn new(py: Python<'_>, radius: f64) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_sphere",
            || Shape::sphere(radius),
            format!("Sphere({radius:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Sphere { radius }))
    }
}

/// The ellipsoid `{b : bᵀ P b ≤ 1}` (body frame), `P` a symmetric positive definite 3×3
/// matrix.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Ellipsoid {
    p: Vec<f64>,
}

#[pymethods]
impl Ellipsoid {
    #[new]
    #[allow(non_snake_case)]
    fn new(py: Python<'_>, P: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Self>> {
        let (p, _) = matrix(P, "P", Some(3), 3, "a 3x3 matrix")?;
        let r = rows::<3>(&p);
        let base = PyShape::build(
            py,
            "dcol_shape_new_ellipsoid",
            || Shape::ellipsoid([r[0], r[1], r[2]]),
            format!("Ellipsoid({r:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Ellipsoid { p }))
    }

    /// The matrix P (3×3).
    #[getter(P)]
    fn p<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(py, &self.p, 3)
    }
}

/// The bounded polytope `{b : A b ≤ b}`: `A` of shape (m, 3), `b` of m positive numbers (the
/// body origin strictly inside).
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Polytope {
    a: Vec<f64>,
    b: Vec<f64>,
}

fn check_rows(name_a: &str, rows_a: usize, name_b: &str, len_b: usize) -> PyResult<()> {
    if rows_a != len_b {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{name_a} has {rows_a} rows but {name_b} has {len_b} numbers: one per row"
        )));
    }
    Ok(())
}

#[pymethods]
impl Polytope {
    #[new]
    #[allow(non_snake_case)]
    fn new(
        py: Python<'_>,
        A: &Bound<'_, PyAny>,
        b: &Bound<'_, PyAny>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (a, m) = matrix(A, "A", None, 3, "an (m, 3) array")?;
        let bv = vector(b, "b", None)?;
        check_rows("A", m, "b", bv.len())?;
        let r = rows::<3>(&a);
        let base = PyShape::build(
            py,
            "dcol_shape_new_polytope",
            || Shape::polytope(&r, &bv),
            format!("Polytope(<{m} planes>)"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Polytope { a, b: bv }))
    }

    /// The plane normals A, shape (m, 3).
    #[getter(A)]
    fn a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(py, &self.a, 3)
    }

    /// The plane offsets b, shape (m,).
    #[getter]
    fn b<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.b)
    }
}

/// A box of half-extents `half_x`, `half_y`, `half_z` centred at the body origin (a polytope of
/// six planes).
#[pyclass(frozen, extends = PyShape, module = "dcol", name = "Box")]
pub struct BoxShape {
    /// Half-extent along body x.
    #[pyo3(get)]
    half_x: f64,
    /// Half-extent along body y.
    #[pyo3(get)]
    half_y: f64,
    /// Half-extent along body z.
    #[pyo3(get)]
    half_z: f64,
}

#[pymethods]
impl BoxShape {
    #[new]
    fn new(
        py: Python<'_>,
        half_x: f64,
        half_y: f64,
        half_z: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_box",
            || Shape::cuboid(half_x, half_y, half_z),
            format!("Box({half_x:?}, {half_y:?}, {half_z:?})"),
        )?;
        let b = BoxShape {
            half_x,
            half_y,
            half_z,
        };
        Ok(PyClassInitializer::from(base).add_subclass(b))
    }
}

/// Points within `radius` of the segment from `-length/2` to `+length/2` on body x.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Capsule {
    /// The radius.
    #[pyo3(get)]
    radius: f64,
    /// The length of the segment (the capsule is `length + 2 radius` long).
    #[pyo3(get)]
    length: f64,
}

#[pymethods]
impl Capsule {
    #[new]
    fn new(py: Python<'_>, radius: f64, length: f64) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_capsule",
            || Shape::capsule(radius, length),
            format!("Capsule({radius:?}, {length:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Capsule { radius, length }))
    }
}

/// A cylinder of `radius` and `length` along body x, centred at the body origin.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Cylinder {
    /// The radius.
    #[pyo3(get)]
    radius: f64,
    /// The length along body x.
    #[pyo3(get)]
    length: f64,
}

#[pymethods]
impl Cylinder {
    #[new]
    fn new(py: Python<'_>, radius: f64, length: f64) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_cylinder",
            || Shape::cylinder(radius, length),
            format!("Cylinder({radius:?}, {length:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Cylinder { radius, length }))
    }
}

/// A cone of `height` and `half_angle` (radians, in (0, π/2)) along body x: apex at
/// `-3/4 height`, base at `+1/4 height` (the body origin is its centroid).
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Cone {
    /// The height.
    #[pyo3(get)]
    height: f64,
    /// The half angle at the apex (radians).
    #[pyo3(get)]
    half_angle: f64,
}

#[pymethods]
impl Cone {
    #[new]
    fn new(py: Python<'_>, height: f64, half_angle: f64) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_cone",
            || Shape::cone(height, half_angle),
            format!("Cone({height:?}, {half_angle:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Cone { height, half_angle }))
    }
}

/// Points within `radius` of the plane polygon `{(y, 0) : C y ≤ d}` in the body x-y plane: `C`
/// of shape (m, 2), `d` of m positive numbers (at most 256 edges).
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct Polygon {
    c: Vec<f64>,
    d: Vec<f64>,
    /// The padding radius.
    #[pyo3(get)]
    radius: f64,
}

#[pymethods]
impl Polygon {
    #[new]
    #[allow(non_snake_case)]
    fn new(
        py: Python<'_>,
        C: &Bound<'_, PyAny>,
        d: &Bound<'_, PyAny>,
        radius: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (c, m) = matrix(C, "C", None, 2, "an (m, 2) array")?;
        let dv = vector(d, "d", None)?;
        check_rows("C", m, "d", dv.len())?;
        let r = rows::<2>(&c);
        let base = PyShape::build(
            py,
            "dcol_shape_new_polygon",
            || Shape::polygon(&r, &dv, radius),
            format!("Polygon(<{m} edges>, radius={radius:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(Polygon { c, d: dv, radius }))
    }

    /// The edge normals C, shape (m, 2).
    #[getter(C)]
    fn c<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(py, &self.c, 2)
    }

    /// The edge offsets d, shape (m,).
    #[getter]
    fn d<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.d)
    }
}

/// The half-space `{b : b_z ≤ depth}` (outward normal +z, boundary `depth` above the body
/// origin). A floor with its top at z = 0: `HalfSpace(d)` at position `(0, 0, -d)`.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct HalfSpace {
    /// Height of the boundary plane above the body origin.
    #[pyo3(get)]
    depth: f64,
}

#[pymethods]
impl HalfSpace {
    #[new]
    fn new(py: Python<'_>, depth: f64) -> PyResult<PyClassInitializer<Self>> {
        let base = PyShape::build(
            py,
            "dcol_shape_new_halfspace",
            || Shape::halfspace(depth),
            format!("HalfSpace({depth:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(HalfSpace { depth }))
    }
}

/// The convex hull of `points` (shape (n, 3), body frame, surrounding the origin), padded by a
/// ball of `radius` ≥ 0.
#[pyclass(frozen, extends = PyShape, module = "dcol")]
pub struct ConvexHull {
    points: Vec<f64>,
    /// The padding radius.
    #[pyo3(get)]
    radius: f64,
}

#[pymethods]
impl ConvexHull {
    #[new]
    #[pyo3(signature = (points, radius = 0.0))]
    fn new(
        py: Python<'_>,
        points: &Bound<'_, PyAny>,
        radius: f64,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (p, n) = matrix(points, "points", None, 3, "an (n, 3) array")?;
        let r = rows::<3>(&p);
        let base = PyShape::build(
            py,
            "dcol_shape_new_convex_hull",
            || Shape::convex_hull(&r, radius),
            format!("ConvexHull(<{n} points>, radius={radius:?})"),
        )?;
        Ok(PyClassInitializer::from(base).add_subclass(ConvexHull { points: p, radius }))
    }

    /// The points as given, shape (n, 3).
    #[getter]
    fn points<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        array2(py, &self.points, 3)
    }
}

/// Adds the classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyShape>()?;
    m.add_class::<Sphere>()?;
    m.add_class::<Ellipsoid>()?;
    m.add_class::<Polytope>()?;
    m.add_class::<BoxShape>()?;
    m.add_class::<Capsule>()?;
    m.add_class::<Cylinder>()?;
    m.add_class::<Cone>()?;
    m.add_class::<Polygon>()?;
    m.add_class::<HalfSpace>()?;
    m.add_class::<ConvexHull>()?;
    Ok(())
}
