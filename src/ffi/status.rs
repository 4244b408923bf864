//! `dcol_status`, the result of every fallible function. Its text, the last error message and
//! the version are in [`super::info`].

/// The result of every fallible function. The values are fixed and never change meaning.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum dcol_status {
    /// Success.
    DCOL_OK = 0,
    /// A required pointer argument was NULL.
    DCOL_ERROR_NULL_POINTER = 1,
    /// Geometry rejected: non-finite, non-positive size, P not SPD, polytope/polygon empty,
    /// unbounded or origin not strictly inside, too many facets or points, ...
    DCOL_ERROR_INVALID_SHAPE = 2,
    /// Non-finite position or attitude, zero quaternion, or shapes placed so near the largest
    /// double that the answer (a point, a distance, alpha*) is not representable.
    DCOL_ERROR_INVALID_POSE = 3,
    /// Non-finite or non-positive tolerance, zero iteration limit.
    DCOL_ERROR_INVALID_OPTIONS = 4,
    /// Iteration limit reached (or no further step possible): the result holds the last
    /// iterate.
    DCOL_ERROR_NOT_CONVERGED = 5,
    /// A bug: a caught panic or an impossible state.
    DCOL_ERROR_INTERNAL = 6,
}
