//! `dcol_options` and `dcol_options_default`.

use super::boundary::{catch, read, Failure};
use crate::error::{Error, ErrorDetail};
use crate::query::Options;
use crate::solver::Method;

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
    /// Which solvers a query may use: DCOL_METHOD_AUTO (0, the default: closed forms and the
    /// certified ray cast on support maps, with the interior-point solver as the fallback) or
    /// DCOL_METHOD_INTERIOR_POINT (1: the interior-point solver only). Other values are
    /// rejected with DCOL_ERROR_INVALID_OPTIONS. (Appended after the two original fields, so an
    /// initializer that sets only those two selects DCOL_METHOD_AUTO.)
    pub method: u32,
    /// 0 (the default): exact answers. A positive value mu asks proximity, the gradient, the
    /// Jacobian, dcol_derivatives, their MRP forms and the batch for the smoothed answer: the
    /// point of the interior-point method's central path at barrier parameter mu, with its
    /// derivatives, smooth everywhere (also across edges, corners and face-against-face
    /// contact). mu is in the cone program's normalised units (alpha' >= 1): the smoothed
    /// alpha* exceeds the exact one by at most nu * mu relative, nu the barrier degree (the
    /// two shapes' orthant rows and cones). Negative, NaN or infinite values are rejected with
    /// DCOL_ERROR_INVALID_OPTIONS. Intersection tests, bounds and the distance ignore it.
    /// (Appended after `method`: an initializer that leaves it out asks for exact answers.)
    pub smoothing: f64,
}

/// dcol_options.method: closed forms and the certified ray cast, interior point as fallback.
pub const DCOL_METHOD_AUTO: u32 = 0;
/// dcol_options.method: the interior-point solver only.
pub const DCOL_METHOD_INTERIOR_POINT: u32 = 1;

fn method_code(m: Method) -> u32 {
    match m {
        Method::Auto => DCOL_METHOD_AUTO,
        Method::InteriorPoint => DCOL_METHOD_INTERIOR_POINT,
    }
}

impl From<Options> for dcol_options {
    fn from(o: Options) -> Self {
        dcol_options {
            tolerance: o.tolerance,
            max_iterations: o.max_iterations,
            method: method_code(o.method),
            smoothing: o.smoothing,
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
    let method = match o.method {
        DCOL_METHOD_AUTO => Method::Auto,
        DCOL_METHOD_INTERIOR_POINT => Method::InteriorPoint,
        other => {
            return Err(Failure::api(Error::InvalidOptions(ErrorDetail::new(
                "options->method",
                other as f64,
                "must be DCOL_METHOD_AUTO (0) or DCOL_METHOD_INTERIOR_POINT (1)",
            ))))
        }
    };
    let opts = Options {
        tolerance: o.tolerance,
        max_iterations: o.max_iterations,
        method,
        smoothing: o.smoothing,
    };
    opts.validate().map_err(Failure::api_in("options->"))?;
    Ok(opts)
}

/// The tolerance of the options behind `ptr` (NULL: the defaults') when they are valid and ask
/// for the default method without smoothing: [`read_options`] would accept them, and the
/// closed-form lane (`crate::query::closed_lane`, which uses no iteration limit) gives the full
/// query's answer under them. `None` otherwise.
///
/// # Safety
/// `ptr` must be NULL or point to a valid `dcol_options`.
#[inline(always)]
pub(crate) unsafe fn plain_tolerance(ptr: *const dcol_options) -> Option<f64> {
    if ptr.is_null() {
        return Some(Options::default().tolerance);
    }
    // SAFETY: non-NULL; validity and alignment are the caller's contract.
    let o = unsafe { &*ptr };
    // `Options::validate` without its messages: the tolerance positive and finite, at least one
    // iteration (a smoothing of exactly 0 is valid).
    let plain = o.method == DCOL_METHOD_AUTO
        && o.smoothing == 0.0
        && o.tolerance.is_finite()
        && o.tolerance > 0.0
        && o.max_iterations >= 1;
    plain.then_some(o.tolerance)
}
