//! `dcol_status_string`, `dcol_last_error_message` and `dcol_version`: what the library says
//! about a status, the last failure and itself.

use std::os::raw::c_char;

use super::boundary::{catch, last_error_ptr};

/// The text of `dcol_status_string` for each value, indexed by the status code.
const STATUS_TEXT: [&std::ffi::CStr; 7] = [
    c"DCOL_OK: success",
    c"DCOL_ERROR_NULL_POINTER: a required pointer argument was NULL",
    c"DCOL_ERROR_INVALID_SHAPE: the geometry was rejected",
    c"DCOL_ERROR_INVALID_POSE: a pose was rejected",
    c"DCOL_ERROR_INVALID_OPTIONS: the options were rejected",
    c"DCOL_ERROR_NOT_CONVERGED: the solver did not converge; the result holds the last iterate",
    c"DCOL_ERROR_INTERNAL: internal error (a bug in dcol)",
];

/// Receives the status as the raw integer a C caller passes.
///
/// The C prototype is `dcol_status_string(dcol_status status)`, but a C enum object may hold any
/// `int`, while an out-of-range value in a Rust enum is undefined behaviour. So the function
/// takes the 32-bit integer (a C enum argument is passed exactly like it) under the name
/// `dcol_status`, which cbindgen resolves by name to the enum: the header shows the prototype of
/// the contract, and any value is safe here.
mod raw {
    use super::*;
    use core::primitive::u32 as dcol_status;

    /// A static, NUL-terminated description of `status` (never NULL; unknown values give
    /// "unknown dcol_status value"). Never fails; the string must not be freed.
    #[no_mangle]
    pub extern "C" fn dcol_status_string(status: dcol_status) -> *const c_char {
        catch("dcol_status_string", c"".as_ptr(), || {
            STATUS_TEXT
                .get(status as usize)
                .copied()
                .unwrap_or(c"unknown dcol_status value")
                .as_ptr()
        })
    }
}
pub use raw::dcol_status_string;

/// This thread's last error message: one sentence naming the function, the argument and its
/// value (e.g. "dcol_shape_new_sphere: invalid shape: argument `radius` = -1: must be
/// positive"), or "" if no call on this thread has failed yet.
///
/// Every call that returns a status other than DCOL_OK replaces the message; successful calls
/// leave it unchanged. The pointer is never NULL, must not be freed, and stays valid until the
/// calling thread exits; its contents change with the next failing call on the same thread.
#[no_mangle]
pub extern "C" fn dcol_last_error_message() -> *const c_char {
    catch("dcol_last_error_message", c"".as_ptr(), last_error_ptr)
}

/// The library version, "MAJOR.MINOR.PATCH" (static, never NULL, must not be freed). Compare
/// with the DCOL_VERSION_* macros to detect a header/library mismatch.
#[no_mangle]
pub extern "C" fn dcol_version() -> *const c_char {
    catch("dcol_version", c"".as_ptr(), || {
        const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
        VERSION.as_ptr().cast()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::status::dcol_status;
    use std::ffi::CStr;

    fn text(p: *const c_char) -> String {
        // SAFETY: the functions under test return static NUL-terminated strings.
        unsafe { CStr::from_ptr(p) }.to_str().unwrap().to_owned()
    }

    #[test]
    fn status_strings() {
        for (i, t) in STATUS_TEXT.iter().enumerate() {
            assert_eq!(text(dcol_status_string(i as u32)), t.to_str().unwrap());
        }
        assert!(
            text(dcol_status_string(dcol_status::DCOL_ERROR_INTERNAL as u32))
                .starts_with("DCOL_ERROR_INTERNAL")
        );
        assert_eq!(text(dcol_status_string(7)), "unknown dcol_status value");
        assert_eq!(
            text(dcol_status_string(u32::MAX)),
            "unknown dcol_status value"
        );
    }

    #[test]
    fn version_matches_cargo() {
        assert_eq!(text(dcol_version()), env!("CARGO_PKG_VERSION"));
    }
}
