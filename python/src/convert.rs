//! Python values to dcol's inputs: float64 arrays of a required shape, poses (7-vectors
//! `[x, y, z, qw, qx, qy, qz]`) and the query options given as keyword arguments.
//!
//! Wrong shapes and types are `ValueError` / `TypeError` (Python's own mistakes, with no C
//! counterpart); values dcol rejects (NaN, a zero quaternion, a negative tolerance) are
//! `dcol.Error` with the C function's status and message.

use dcol::{Method, Options, Pose};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyList, PyString, PyTuple};

use crate::errors::{api_error, dcol_error};

/// `numpy.ascontiguousarray`, imported once.
static ASCONTIGUOUS: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

/// `obj` as a C-contiguous float64 array (itself when it already is one, else converted by
/// `numpy.ascontiguousarray(obj, dtype="float64")`).
pub fn f64_array<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(a) = obj.cast::<PyArrayDyn<f64>>() {
        if a.is_c_contiguous() {
            return Ok(a.clone());
        }
    }
    let py = obj.py();
    let f = ASCONTIGUOUS.import(py, "numpy", "ascontiguousarray")?;
    let converted = f.call1((obj, "float64"))?;
    Ok(converted.cast_into::<PyArrayDyn<f64>>()?)
}

/// The numbers of `obj` (row-major) when its shape is `(rows, cols)` (`rows` free when
/// `None`); a `ValueError` naming `name` and `what` otherwise. Returns the numbers and rows.
pub fn matrix(
    obj: &Bound<'_, PyAny>,
    name: &str,
    rows: Option<usize>,
    cols: usize,
    what: &str,
) -> PyResult<(Vec<f64>, usize)> {
    let a = f64_array(obj)?;
    let shape = a.shape().to_vec();
    let ok = shape.len() == 2 && shape[1] == cols && rows.is_none_or(|r| shape[0] == r);
    if !ok {
        return Err(PyValueError::new_err(format!(
            "{name} must be {what}, got an array of shape {}",
            shape_text(&shape)
        )));
    }
    let ro = a.readonly();
    Ok((ro.as_slice()?.to_vec(), shape[0]))
}

/// The numbers of a 1-D `obj` of `len` elements (any length when `None`).
pub fn vector(obj: &Bound<'_, PyAny>, name: &str, len: Option<usize>) -> PyResult<Vec<f64>> {
    let a = f64_array(obj)?;
    let shape = a.shape().to_vec();
    if shape.len() != 1 || len.is_some_and(|n| shape[0] != n) {
        let want = len.map_or("a 1-D array".to_string(), |n| format!("{n} numbers"));
        return Err(PyValueError::new_err(format!(
            "{name} must be {want}, got an array of shape {}",
            shape_text(&shape)
        )));
    }
    let ro = a.readonly();
    Ok(ro.as_slice()?.to_vec())
}

/// A shape as Python writes it: `(7,)`, `(3, 7)`, `()`.
pub fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The 7 numbers of a pose argument: a list or tuple of 7 numbers, or anything numpy makes a
/// float64 array of shape (7,).
pub fn pose_numbers(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 7]> {
    // Lists and tuples first: item by item, without building an array.
    let items = if let Ok(l) = obj.cast::<PyList>() {
        Some(l.as_sequence().clone())
    } else {
        obj.cast::<PyTuple>().ok().map(|t| t.as_sequence().clone())
    };
    if let Some(seq) = items {
        if seq.len()? == 7 {
            let mut v = [0.0; 7];
            for (i, x) in v.iter_mut().enumerate() {
                if let Ok(f) = seq.get_item(i)?.extract::<f64>() {
                    *x = f;
                } else {
                    return pose_from_array(obj, name);
                }
            }
            return Ok(v);
        }
    }
    pose_from_array(obj, name)
}

fn pose_from_array(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<[f64; 7]> {
    let a = f64_array(obj)?;
    let shape = a.shape().to_vec();
    if shape != [7] {
        return Err(PyValueError::new_err(format!(
            "{name} must be a pose, 7 numbers [x, y, z, qw, qx, qy, qz], got an array of shape {}",
            shape_text(&shape)
        )));
    }
    let ro = a.readonly();
    let s = ro.as_slice()?;
    let mut v = [0.0; 7];
    v.copy_from_slice(s);
    Ok(v)
}

/// A dcol pose from its 7 numbers (position, then the quaternion `[w, x, y, z]`).
pub fn pose_from(v: &[f64]) -> Result<Pose, dcol::Error> {
    Pose::new([v[0], v[1], v[2]], [v[3], v[4], v[5], v[6]])
}

/// The pose argument `name` (`"pose1"`) of the C function `func`: a `ValueError` for a wrong
/// shape, a `dcol.Error` naming `pose1->position[i]` (as the C function does) for a value dcol
/// rejects.
pub fn pose(
    obj: &Bound<'_, PyAny>,
    name: &str,
    func: &str,
    context: &'static str,
) -> PyResult<Pose> {
    let v = pose_numbers(obj, name)?;
    pose_from(&v).map_err(|e| api_error(obj.py(), func, context, e))
}

/// The options keyword arguments, as the C function `func` reads `dcol_options` (each omitted
/// one at its default).
#[derive(Clone, Copy, Default)]
pub struct Kw<'a, 'py> {
    pub tolerance: Option<f64>,
    pub max_iterations: Option<i64>,
    pub method: Option<&'a Bound<'py, PyAny>>,
    pub smoothing: Option<f64>,
}

impl Kw<'_, '_> {
    /// The validated options; errors name `options->...` as the C function's do.
    pub fn options(&self, py: Python<'_>, func: &str) -> PyResult<Options> {
        let d = Options::default();
        let max_iterations = match self.max_iterations {
            None => d.max_iterations,
            Some(n) => u32::try_from(n).map_err(|_| {
                PyValueError::new_err(format!(
                    "max_iterations must be an integer from 1 to {}, got {n}",
                    u32::MAX
                ))
            })?,
        };
        let o = Options {
            tolerance: self.tolerance.unwrap_or(d.tolerance),
            max_iterations,
            method: match self.method {
                None => d.method,
                Some(m) => method(py, func, m)?,
            },
            smoothing: self.smoothing.unwrap_or(d.smoothing),
        };
        o.validate()
            .map_err(|e| api_error(py, func, "options->", e))?;
        Ok(o)
    }
}

/// `method=`: `"auto"` or `"interior_point"` (or the C values 0 and 1, `dcol.METHOD_AUTO` and
/// `dcol.METHOD_INTERIOR_POINT`).
fn method(py: Python<'_>, func: &str, m: &Bound<'_, PyAny>) -> PyResult<Method> {
    if let Ok(s) = m.cast::<PyString>() {
        return match s.to_str()? {
            "auto" => Ok(Method::Auto),
            "interior_point" => Ok(Method::InteriorPoint),
            other => Err(dcol_error(
                py,
                dcol::ffi::dcol_status::DCOL_ERROR_INVALID_OPTIONS,
                format!(
                    "{func}: invalid options: argument `options->method` = {other:?}: must be \
                     \"auto\" or \"interior_point\""
                ),
                None,
            )),
        };
    }
    let Ok(code) = m.extract::<i64>() else {
        return Err(PyTypeError::new_err(format!(
            "method must be \"auto\" or \"interior_point\", got {}",
            m.repr()?
        )));
    };
    match code {
        0 => Ok(Method::Auto),
        1 => Ok(Method::InteriorPoint),
        // Worded by the C formatter from the C function's own rule.
        other => Err(api_error(
            py,
            func,
            "",
            dcol::Error::InvalidOptions(dcol::ErrorDetail::new(
                "options->method",
                other as f64,
                "must be DCOL_METHOD_AUTO (0) or DCOL_METHOD_INTERIOR_POINT (1)",
            )),
        )),
    }
}
