//! `dcol_options` and `dcol_options_default`.

use super::boundary::{catch, read, Failure};
use crate::query::Options;

/// Solver options. Start from dcol_options_default() and change what you need; every query
/// takes options == NULL as the defaults.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct dcol_options {
    /// Solver stopping tolerance on the duality measure (relative to max(1, alpha)): positive and
    /// finite. The default is in dcol_options_default().
    pub tolerance: f64,
    /// Interior-point iteration limit, at least 1. The default is in dcol_options_default().
    pub max_iterations: u32,
}

impl From<Options> for dcol_options {
    fn from(o: Options) -> Self {
        dcol_options {
            tolerance: o.tolerance,
            max_iterations: o.max_iterations,
        }
    }
}

/// The default options (never fails).
#[no_mangle]
pub extern "C" fn dcol_options_default() -> dcol_options {
    let d = dcol_options::from(Options::default());
    catch("dcol_options_default", d, || d)
}

/// Copies and validates the options behind `ptr`; NULL means the defaults.
///
/// # Safety
/// `ptr` must be NULL or point to a valid `dcol_options`.
pub(crate) unsafe fn read_options(ptr: *const dcol_options) -> Result<Options, Failure> {
    if ptr.is_null() {
        return Ok(Options::default());
    }
    // SAFETY: forwarded from this function's contract (non-NULL here).
    let o = unsafe { read(ptr, "options") }?;
    let opts = Options {
        tolerance: o.tolerance,
        max_iterations: o.max_iterations,
    };
    opts.validate().map_err(Failure::api_in("options->"))?;
    Ok(opts)
}
