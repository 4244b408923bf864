//! `dcol_cache`: the caller-owned per-pair warm-start cache of the `_cached` queries.

use super::boundary::Failure;
use crate::query::Cache;

/// A per-pair warm-start cache for the `_cached` queries (dcol_proximity_cached,
/// dcol_gradient_cached, dcol_jacobian_cached, dcol_derivatives_cached, dcol_distance_cached,
/// dcol_distance_gradient_cached, dcol_signed_distance_cached, dcol_contacts_cached,
/// dcol_intersect_cached): plain data that dcol reads and writes, all zeros meaning
/// cold (`dcol_cache c = DCOL_CACHE_INIT;` or memset to 0). Keep one per pair of shapes, and
/// pass it to every query on that pair; copy it, zero it, or move it between threads freely.
/// Its contents are private to dcol: any bit pattern in it gives a correct answer (a cache of
/// another pair, or after a shape changed, only makes that call cold). Warm answers are
/// certified exactly as cold ones and agree with them to the solver's tolerance (alpha* and
/// distances within 1e-12 relative; a warm proximity reports DCOL_SOLVER_POLISH). A warm start is taken between two polytopes (boxes,
/// polytopes, unpadded hulls) whose poses moved less than a quarter of their size and 20
/// degrees since the pair's last answer; other pairs answer cold (and cost the same). The
/// contacts of any pair start from the last separating normal: shapes it still proves apart by
/// more than the margin get no contact points from two support calls; the signed distance of
/// two polytopes it proves apart is their (warm) distance. Where the kept answer keeps failing
/// (poses that jump), the cache backs off: up to 31 calls then neither try nor keep one.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct dcol_cache {
    /// Private to dcol.
    pub words: [u32; 25],
    /// Private to dcol.
    pub numbers: [f64; 70],
}

impl Default for dcol_cache {
    /// A cold cache (all zeros, as DCOL_CACHE_INIT).
    fn default() -> Self {
        dcol_cache {
            words: [0; 25],
            numbers: [0.0; 70],
        }
    }
}

// `dcol_cache` and `Cache` are both `repr(C)` with the same fields in the same order: the
// same layout, which `cache_mut` relies on.
const _: () = {
    assert!(std::mem::size_of::<dcol_cache>() == std::mem::size_of::<Cache>());
    assert!(std::mem::align_of::<dcol_cache>() == std::mem::align_of::<Cache>());
};

/// The Rust cache behind a C one: `None` when no cache was given (a plain query),
/// `Failure::Null` for a NULL one.
///
/// # Safety
/// `cache`, when `Some` and not NULL, must be valid for reads and writes of a `dcol_cache`
/// and not aliased for `'a`.
pub(crate) unsafe fn cache_mut<'a>(
    cache: Option<*mut dcol_cache>,
) -> Result<Option<&'a mut Cache>, Failure> {
    match cache {
        None => Ok(None),
        Some(p) if p.is_null() => Err(Failure::Null("cache")),
        // SAFETY: non-NULL and valid for reads and writes (contract); `Cache` has the layout
        // of `dcol_cache` (asserted above) and every bit pattern of its `u32` and `f64` fields
        // is a valid value.
        Some(p) => Ok(Some(unsafe { &mut *p.cast::<Cache>() })),
    }
}
