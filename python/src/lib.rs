//! `dcol._dcol`: the Python bindings of dcol, on the Rust API directly (not through the C ABI).
//!
//! The Python package `dcol` (`python/dcol/`) re-exports everything here and adds the batch
//! results' named tuples and `dcol.jax`. What the bindings keep from the C ABI: every error is
//! a `dcol.Error` carrying the C status number (`dcol_status`) and the very sentence
//! `dcol_last_error_message` would give (formatted by `dcol::ffi::boundary`, not copied), and a
//! Rust panic never reaches Python as anything but a `dcol.Error` of status 6 (internal).
//!
//! - [`shapes`]: `dcol.Shape` and its constructors (`Sphere`, `Box`, ...);
//! - [`convert`]: poses, arrays and options from Python values;
//! - [`errors`]: `dcol.Error` from dcol's errors, statuses and panics;
//! - [`results`]: the result classes (`Proximity`, `Distance`, ...);
//! - [`queries`]: one pair at a time (`proximity`, `gradient`, ..., `contacts`);
//! - [`cached`]: `dcol.Cache` and the warm-started queries (`proximity_cached`, ...);
//! - [`shape_gradients`]: the derivatives with respect to the shapes' parameters;
//! - [`batch`]: many pairs on numpy arrays, without the GIL, on dcol's thread pool.

mod batch;
mod cached;
mod convert;
mod errors;
mod queries;
mod results;
mod shape_gradients;
mod shapes;

use pyo3::prelude::*;

/// The extension module.
#[pymodule]
fn _dcol(m: &Bound<'_, PyModule>) -> PyResult<()> {
    shapes::register(m)?;
    results::register(m)?;
    queries::register(m)?;
    cached::register(m)?;
    shape_gradients::register(m)?;
    batch::register(m)?;
    m.add("MAX_CONTACTS", dcol::query::MAX_CONTACTS)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
