//! The single panic boundary, the pointer helpers and the per-thread last error message.
//!
//! Every exported function runs its body through `run` (status-returning functions) or
//! `catch` (the few that return a value), so a Rust panic never unwinds into C.

use std::cell::RefCell;
use std::fmt::{self, Write as _};
use std::os::raw::c_char;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::status::dcol_status;
use crate::error::{Error, ErrorDetail, Value};
use crate::math::Vec3;
use crate::solver::SolveStatus;

/// Size of the per-thread message buffer, NUL included. Longer messages are truncated.
const MESSAGE_CAPACITY: usize = 512;

thread_local! {
    /// This thread's last error message, NUL-terminated. A fixed array: setting it never
    /// allocates, and the pointer handed to C stays valid for the thread's lifetime.
    static LAST_ERROR: RefCell<[u8; MESSAGE_CAPACITY]> = const { RefCell::new([0; MESSAGE_CAPACITY]) };
}

/// Why an exported function did not return `DCOL_OK`.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Failure {
    /// The named pointer argument was NULL.
    Null(&'static str),
    /// The core rejected an input. `context` names the C argument it came from
    /// (`"pose2->"`, `"options->"`) or is empty.
    Api { error: Error, context: &'static str },
    /// A caller buffer is too small: the argument `argument` (its capacity) is `given`, but
    /// `needed` elements (`what`) were found; the output `*count` holds `needed`.
    Capacity {
        argument: &'static str,
        given: usize,
        needed: usize,
        what: &'static str,
        count: &'static str,
    },
    /// The solve ran but did not converge; the outputs hold the last iterate.
    NotConverged {
        status: SolveStatus,
        iterations: u32,
        max_iterations: u32,
        tolerance: f64,
    },
}

impl Failure {
    /// A core error without a C argument to name.
    pub(crate) fn api(error: Error) -> Failure {
        Failure::Api { error, context: "" }
    }

    /// A core error that came from the C argument `context` (e.g. `"pose1->"`).
    pub(crate) fn api_in(context: &'static str) -> impl Fn(Error) -> Failure {
        move |error| Failure::Api { error, context }
    }

    /// The status code this failure maps to.
    pub(crate) fn status(&self) -> dcol_status {
        match self {
            Failure::Null(_) => dcol_status::DCOL_ERROR_NULL_POINTER,
            Failure::Api { error, .. } => status_of(error),
            Failure::Capacity { .. } => dcol_status::DCOL_ERROR_INVALID_OPTIONS,
            Failure::NotConverged { .. } => dcol_status::DCOL_ERROR_NOT_CONVERGED,
        }
    }
}

/// The status code of a core error (public for bindings that report the C statuses: the
/// Python package).
pub fn status_of(error: &Error) -> dcol_status {
    match error {
        Error::InvalidShape(_) => dcol_status::DCOL_ERROR_INVALID_SHAPE,
        Error::InvalidPose(_) => dcol_status::DCOL_ERROR_INVALID_POSE,
        Error::InvalidOptions(_) => dcol_status::DCOL_ERROR_INVALID_OPTIONS,
        Error::Internal(_) => dcol_status::DCOL_ERROR_INTERNAL,
    }
}

/// `Ok` when every number in `values` (an answer about to be returned) is finite, otherwise
/// the error the C functions return for an answer a double cannot hold: `InvalidPose` naming
/// the largest coordinate of the origins `r1`, `r2` (shapes placed within their size of the
/// largest double). The C functions check their outputs with it before writing them; public
/// for the bindings that bind the Rust API and refuse what the C ABI refuses (the Python
/// package).
///
/// ```
/// use dcol::{ffi::boundary::representable, Vec3};
/// let (r1, r2) = (Vec3::new(1.7e308, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0));
/// assert!(representable([1.0, 2.0], &r1, &r2).is_ok());
/// assert!(matches!(
///     representable([1.0, f64::INFINITY], &r1, &r2),
///     Err(dcol::Error::InvalidPose(d)) if d.value == 1.7e308
/// ));
/// ```
pub fn representable(
    values: impl IntoIterator<Item = f64>,
    r1: &Vec3,
    r2: &Vec3,
) -> Result<(), Error> {
    if values.into_iter().all(f64::is_finite) {
        return Ok(());
    }
    Err(crate::query::not_representable(r1, r2))
}

fn write_detail(w: &mut impl fmt::Write, context: &str, d: &ErrorDetail) -> fmt::Result {
    write!(w, "argument `{context}{}", d.argument)?;
    if let Some(i) = d.index {
        write!(w, "[{i}]")?;
    }
    write!(w, "` = {}: {}", Value(d.value), d.requirement)?;
    if let Some([x, y, z]) = d.point {
        write!(w, " ({}, {}, {})", Value(x), Value(y), Value(z))?;
    }
    Ok(())
}

/// Writes the sentence for `failure` in function `func`.
fn describe(w: &mut impl fmt::Write, func: &str, failure: &Failure) -> fmt::Result {
    write!(w, "{func}: ")?;
    match failure {
        Failure::Null(arg) => write!(w, "argument `{arg}` = NULL: must be a valid pointer"),
        Failure::Api { error, context } => match error {
            Error::InvalidShape(d) => {
                w.write_str("invalid shape: ")?;
                write_detail(w, context, d)
            }
            Error::InvalidPose(d) => {
                w.write_str("invalid pose: ")?;
                write_detail(w, context, d)
            }
            Error::InvalidOptions(d) => {
                w.write_str("invalid options: ")?;
                write_detail(w, context, d)
            }
            Error::Internal(s) => write!(w, "internal error: {s}"),
        },
        Failure::Capacity {
            argument,
            given,
            needed,
            what,
            count,
        } => write!(
            w,
            "invalid options: argument `{argument}` = {given}: too small for the {needed} {what} \
             found (`*{count}` holds the number needed; nothing else was written)"
        ),
        Failure::NotConverged {
            status,
            iterations,
            max_iterations,
            tolerance,
        } => {
            let why = match status {
                SolveStatus::MaxIterations => "reached the iteration limit",
                SolveStatus::NumericalFailure => "could not take another step",
                SolveStatus::Converged => "converged",
            };
            write!(
                w,
                "the solver {why} after {iterations} iterations without converging \
                 (argument `options->max_iterations` = {max_iterations}, \
                 `options->tolerance` = {}); the result holds the last iterate",
                Value(*tolerance)
            )
        }
    }
}

/// The sentence `dcol_last_error_message` gives after the C function `func` (e.g.
/// `"dcol_proximity"`) rejected `error`, read from the C argument `context` (`"pose1->"`,
/// `"options->"`, or `""` when the error names its argument itself). Public for bindings in
/// other languages that bind the Rust API but report the C ABI's statuses and messages (the
/// Python package); it allocates, unlike the C path.
///
/// ```
/// use dcol::{ffi::boundary::error_message, Pose};
/// let e = Pose::new([0.0, f64::NAN, 0.0], [1.0, 0.0, 0.0, 0.0]).unwrap_err();
/// assert_eq!(
///     error_message("dcol_proximity", "pose2->", e),
///     "dcol_proximity: invalid pose: argument `pose2->position[1]` = NaN: must be finite"
/// );
/// ```
pub fn error_message(func: &str, context: &'static str, error: Error) -> String {
    let mut s = String::new();
    // Formatting into a String cannot fail.
    let _ = describe(&mut s, func, &Failure::Api { error, context });
    s
}

/// The sentence `dcol_last_error_message` gives when `func`'s solve ended with `status` (not
/// converged) after `iterations` iterations, under the iteration limit and tolerance of
/// `options` (the status is `DCOL_ERROR_NOT_CONVERGED`). Public for the same bindings as
/// [`error_message`].
pub fn not_converged_message(
    func: &str,
    status: SolveStatus,
    iterations: u32,
    options: &crate::query::Options,
) -> String {
    let failure = Failure::NotConverged {
        status,
        iterations,
        max_iterations: options.max_iterations,
        tolerance: options.tolerance,
    };
    let mut s = String::new();
    // Formatting into a String cannot fail.
    let _ = describe(&mut s, func, &failure);
    s
}

/// A `fmt::Write` into a fixed buffer that truncates at a character boundary and always leaves
/// room for the terminating NUL.
struct Cursor<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl fmt::Write for Cursor<'_> {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let room = self.buf.len() - 1 - self.len;
        let mut n = s.len().min(room);
        while !s.is_char_boundary(n) {
            n -= 1;
        }
        self.buf[self.len..self.len + n].copy_from_slice(&s.as_bytes()[..n]);
        self.len += n;
        if n < s.len() {
            Err(fmt::Error)
        } else {
            Ok(())
        }
    }
}

/// Replaces this thread's last error message with the output of `f` (truncated to fit).
fn set_message(f: impl FnOnce(&mut Cursor<'_>) -> fmt::Result) {
    // `try_with` fails only while the thread is being torn down; there is nothing to report to.
    let _ = LAST_ERROR.try_with(|cell| {
        if let Ok(mut buf) = cell.try_borrow_mut() {
            let mut cursor = Cursor {
                buf: &mut buf[..],
                len: 0,
            };
            // A formatting error only means the message was truncated.
            let _ = f(&mut cursor);
            let end = cursor.len;
            buf[end] = 0;
        }
    });
}

/// Records `failure` as this thread's last error.
pub(crate) fn set_last_error(func: &str, failure: &Failure) {
    set_message(|w| describe(w, func, failure));
}

/// A pointer to this thread's last error message (NUL-terminated, "" before any error).
pub(crate) fn last_error_ptr() -> *const c_char {
    LAST_ERROR
        .try_with(|cell| cell.as_ptr() as *const c_char)
        .unwrap_or(c"".as_ptr())
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> &str {
    if let Some(s) = payload.downcast_ref::<&'static str>() {
        s
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s
    } else {
        "(non-string payload)"
    }
}

/// Runs the body of the exported function `func`: maps its failure to a status code and the
/// thread's last error message, and turns a panic into `DCOL_ERROR_INTERNAL`.
pub(crate) fn run(func: &'static str, body: impl FnOnce() -> Result<(), Failure>) -> dcol_status {
    // AssertUnwindSafe: after a panic nothing the body touched is used again (shapes are
    // immutable, outputs are written last), so no broken invariant can be observed.
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => dcol_status::DCOL_OK,
        Ok(Err(failure)) => {
            set_last_error(func, &failure);
            failure.status()
        }
        Err(payload) => {
            set_message(|w| {
                write!(
                    w,
                    "{func}: internal error: a panic was caught at the C boundary: {}",
                    panic_text(payload.as_ref())
                )
            });
            dcol_status::DCOL_ERROR_INTERNAL
        }
    }
}

/// The panic boundary for functions that return a value instead of a status: `fallback` is
/// returned if `body` panics.
pub(crate) fn catch<T>(func: &'static str, fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(v) => v,
        Err(payload) => {
            set_message(|w| {
                write!(
                    w,
                    "{func}: internal error: a panic was caught at the C boundary: {}",
                    panic_text(payload.as_ref())
                )
            });
            fallback
        }
    }
}

/// Copies `*ptr` after checking it for NULL.
///
/// # Safety
/// `ptr` must be NULL or point to a valid, initialised, aligned `T`.
pub(crate) unsafe fn read<T: Copy>(ptr: *const T, name: &'static str) -> Result<T, Failure> {
    if ptr.is_null() {
        return Err(Failure::Null(name));
    }
    // SAFETY: non-NULL checked above; validity and alignment are the caller's contract.
    Ok(unsafe { ptr.read() })
}

/// Copies `N` values starting at `ptr` after checking it for NULL.
///
/// # Safety
/// `ptr` must be NULL or point to `N` valid, initialised, aligned `T`.
pub(crate) unsafe fn read_array<T: Copy, const N: usize>(
    ptr: *const T,
    name: &'static str,
) -> Result<[T; N], Failure> {
    if ptr.is_null() {
        return Err(Failure::Null(name));
    }
    // SAFETY: non-NULL checked above; `[T; N]` has the alignment of `T`, and the caller
    // guarantees `N` readable elements.
    Ok(unsafe { ptr.cast::<[T; N]>().read() })
}

/// Checks that an output pointer is not NULL.
pub(crate) fn check_out<T>(ptr: *mut T, name: &'static str) -> Result<(), Failure> {
    if ptr.is_null() {
        Err(Failure::Null(name))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    fn last() -> String {
        // SAFETY: the buffer is always NUL-terminated and lives as long as the thread.
        unsafe { CStr::from_ptr(last_error_ptr()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn messages_name_argument_and_value() {
        let e = Error::InvalidPose(ErrorDetail::at("position", 1, f64::NAN, "must be finite"));
        let st = run("dcol_proximity", || Err(Failure::api_in("pose2->")(e)));
        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_POSE);
        assert_eq!(
            last(),
            "dcol_proximity: invalid pose: argument `pose2->position[1]` = NaN: must be finite"
        );
        let st = run("dcol_shape_free", || Err(Failure::Null("out")));
        assert_eq!(st, dcol_status::DCOL_ERROR_NULL_POINTER);
        assert!(last().contains("`out` = NULL"));
    }

    #[test]
    fn capacity_failures_name_the_capacity_and_the_count() {
        let st = run("dcol_scene_pairs_within", || {
            Err(Failure::Capacity {
                argument: "capacity",
                given: 2,
                needed: 5,
                what: "pairs",
                count: "count",
            })
        });
        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_OPTIONS);
        assert_eq!(
            last(),
            "dcol_scene_pairs_within: invalid options: argument `capacity` = 2: too small for the \
             5 pairs found (`*count` holds the number needed; nothing else was written)"
        );
    }

    #[test]
    fn panics_become_internal_errors() {
        let st = run("dcol_test", || panic!("boom"));
        assert_eq!(st, dcol_status::DCOL_ERROR_INTERNAL);
        assert!(last().contains("boom"));
        assert_eq!(catch("dcol_test", 7, || panic!("bang")), 7);
    }

    #[test]
    fn long_messages_are_truncated_on_a_char_boundary() {
        set_message(|w| {
            for _ in 0..1000 {
                w.write_str("\u{2264}")?;
            }
            Ok(())
        });
        let s = last();
        assert!(s.len() < MESSAGE_CAPACITY);
        assert!(s.chars().all(|c| c == '\u{2264}'));
    }
}
