//! `dcol.Error` (defined in Python, `dcol/_errors.py`) raised from dcol's errors, unconverged
//! solves and caught panics, with the C ABI's status numbers and messages.

use std::any::Any;
use std::panic::{catch_unwind, AssertUnwindSafe};

use dcol::ffi::boundary::{error_message, not_converged_message, status_of};
use dcol::ffi::dcol_status;
use dcol::{Options, SolveStatus};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;

/// `dcol._errors.Error`, imported once.
static ERROR: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// A `dcol.Error(message, status, result)`.
pub fn dcol_error(
    py: Python<'_>,
    status: dcol_status,
    message: String,
    result: Option<Py<PyAny>>,
) -> PyErr {
    let made = ERROR
        .import(py, "dcol._errors", "Error")
        .and_then(|ty| ty.call1((message, status as i32, result)));
    match made {
        Ok(value) => PyErr::from_value(value),
        Err(e) => e,
    }
}

/// The `dcol.Error` for a rejected input: the C function `func`'s status and message, the
/// value read from the C argument `context` (`"pose1->"`, `"options->"` or `""`).
pub fn api_error(py: Python<'_>, func: &str, context: &'static str, e: dcol::Error) -> PyErr {
    dcol_error(py, status_of(&e), error_message(func, context, e), None)
}

/// The `dcol.Error` of status 5 (not converged) for `func`, carrying the last iterate as
/// `.result`, as the C function's outputs carry it.
pub fn not_converged(
    py: Python<'_>,
    func: &str,
    status: SolveStatus,
    iterations: u32,
    options: &Options,
    result: Py<PyAny>,
) -> PyErr {
    dcol_error(
        py,
        dcol_status::DCOL_ERROR_NOT_CONVERGED,
        not_converged_message(func, status, iterations, options),
        Some(result),
    )
}

fn panic_text(payload: &(dyn Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&'static str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "(non-string payload)"
    }
}

/// Runs `body`, turning a panic into `dcol.Error` of status 6 (internal), worded as the C
/// boundary words it.
pub fn guard<T>(py: Python<'_>, func: &str, body: impl FnOnce() -> T) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(body)).map_err(|payload| {
        let message = format!(
            "{func}: internal error: a panic was caught at the Python boundary: {}",
            panic_text(payload.as_ref())
        );
        dcol_error(py, dcol_status::DCOL_ERROR_INTERNAL, message, None)
    })
}
