//! `dcol_proximity_batch`: many proximity queries in one call, with per-pair statuses, results
//! in caller arrays, optionally spread over threads.
//!
//! The pairs are read straight from the caller's arrays (no per-pair or per-call Vec): each
//! pair runs exactly the code of `dcol_proximity` (`query::proximity`), so the results are bit
//! for bit those of the single call, on any number of threads.

use std::ops::Range;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::boundary::{run, Failure};
use super::finite::{proximity_numbers, representable};
use super::options::{dcol_options, read_options};
use super::pose::{dcol_pose, read_pose};
use super::proximity::dcol_proximity_result;
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::batch::{for_each_parallel, CHUNK};
use crate::math::finite_array;
use crate::query::{self, Options};

/// The most threads one dcol_proximity_batch call uses, the calling thread included; a larger
/// `threads` argument is treated as this value.
pub const DCOL_BATCH_MAX_THREADS: u32 = 256;

/// The caller's arrays, all with `count` elements (checked non-NULL when `count > 0`).
struct Arrays {
    shapes1: *const *const dcol_shape,
    poses1: *const dcol_pose,
    shapes2: *const *const dcol_shape,
    poses2: *const dcol_pose,
    results: *mut dcol_proximity_result,
    statuses: *mut dcol_status,
    options: Options,
}

// SAFETY: the workers only read the input arrays and the shapes (immutable once built and
// documented as shareable between threads), and write `results[i]`, `statuses[i]` for indices
// `i` in disjoint ranges, so sharing the pointers between the pool's threads is free of data
// races; the caller's contract keeps the memory valid for the whole call, and the call returns
// only once every task on the pool has finished.
unsafe impl Sync for Arrays {}

impl Arrays {
    /// Pair `i`: its proximity result written to `results[i]` on success or non-convergence;
    /// the status returned.
    ///
    /// # Safety
    /// `i < count`, and the arrays are valid as in `dcol_proximity_batch`'s contract.
    unsafe fn pair(&self, i: usize) -> dcol_status {
        let body = || -> Result<dcol_status, Failure> {
            // SAFETY: `i < count` and the arrays hold `count` elements (contract); each shape
            // pointer and pose is NULL-checked by the helpers before it is used.
            let (s1, p1, s2, p2) = unsafe {
                (
                    shape_ref(self.shapes1.add(i).read(), "shapes1[i]")?,
                    read_pose(self.poses1.add(i), "poses1", "poses1[i].")?,
                    shape_ref(self.shapes2.add(i).read(), "shapes2[i]")?,
                    read_pose(self.poses2.add(i), "poses2", "poses2[i].")?,
                )
            };
            let prox = query::proximity(s1, &p1, s2, &p2, &self.options).map_err(Failure::api)?;
            representable(
                finite_array(&proximity_numbers(&prox)),
                p1.position(),
                p2.position(),
            )?;
            // SAFETY: `i < count` and `results` holds `count` writable elements (contract);
            // no other thread writes index `i`.
            unsafe { self.results.add(i).write((&prox).into()) };
            Ok(if prox.status.is_converged() {
                dcol_status::DCOL_OK
            } else {
                dcol_status::DCOL_ERROR_NOT_CONVERGED
            })
        };
        // A panic in one pair is that pair's DCOL_ERROR_INTERNAL; the others are unaffected
        // (the solver keeps no state between calls).
        match catch_unwind(AssertUnwindSafe(body)) {
            Ok(Ok(st)) => st,
            Ok(Err(failure)) => failure.status(),
            Err(_) => dcol_status::DCOL_ERROR_INTERNAL,
        }
    }

    /// Runs the pairs in `range`.
    ///
    /// # Safety
    /// `range.end <= count`, the arrays valid as in `dcol_proximity_batch`'s contract, and no
    /// other thread works on an overlapping range.
    unsafe fn run_range(&self, range: Range<usize>) {
        for i in range {
            // SAFETY: `i < count` (forwarded from this function's contract).
            let st = unsafe { self.pair(i) };
            // SAFETY: `i < count`, `statuses` holds `count` writable elements, and no other
            // thread writes index `i`.
            unsafe { self.statuses.add(i).write(st) };
        }
    }
}

/// Proximity (as dcol_proximity) of `count` pairs: pair i is (`shapes1[i]`, `poses1[i]`,
/// `shapes2[i]`, `poses2[i]`); its result goes to `results[i]` and its status to `statuses[i]`.
///
/// Each pair is independent: a bad pair does not fail the batch. `statuses[i]` is DCOL_OK
/// (`results[i]` written), DCOL_ERROR_NOT_CONVERGED (`results[i]` holds the last iterate),
/// DCOL_ERROR_NULL_POINTER (`shapes1[i]` or `shapes2[i]` is NULL), DCOL_ERROR_INVALID_POSE
/// (`poses1[i]` or `poses2[i]` rejected, their origins too far apart, or the answer beyond the
/// largest double) or
/// DCOL_ERROR_INTERNAL, and on these errors `results[i]` is untouched. Per-pair failures do
/// not set the last error message (the call itself succeeds): call dcol_proximity on that pair
/// for the sentence. `results[i]` is exactly what dcol_proximity returns for the pair, bit for
/// bit, whatever `threads` is.
///
/// The call returns DCOL_OK once every pair has its status; or DCOL_ERROR_NULL_POINTER if one of
/// the six arrays is NULL while count > 0, or DCOL_ERROR_INVALID_OPTIONS if *options is
/// invalid, writing nothing (statuses included). With count == 0 nothing is read or written and
/// the arrays may be NULL. `options` may be NULL (defaults).
///
/// `threads` <= 1 runs every pair on the calling thread. Otherwise at most
/// min(threads, DCOL_BATCH_MAX_THREADS) threads share the pairs, taking small chunks in turn:
/// the calling thread and the threads of a pool that the first such call creates (one thread
/// per core) and every later call reuses; the call returns when all pairs are done. The first
/// parallel call allocates the pool, each parallel call a few bytes per pool thread it uses,
/// and a shape with many facets makes each pool thread allocate its scratch buffer once;
/// nothing is allocated per pair, and with threads <= 1 the call does not allocate (as
/// dcol_proximity). If the pool cannot be started, the pairs run on the calling thread.
///
/// # Safety
/// Unless count == 0: `shapes1`, `poses1`, `shapes2`, `poses2` must each be NULL or valid for
/// reading `count` elements, each shape pointer in them NULL or a live shape; `results` and
/// `statuses` NULL or valid for writing `count` elements; none of the output arrays may overlap
/// the inputs or each other. `options` must be NULL or valid.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_proximity_batch(
    shapes1: *const *const dcol_shape,
    poses1: *const dcol_pose,
    shapes2: *const *const dcol_shape,
    poses2: *const dcol_pose,
    count: usize,
    options: *const dcol_options,
    threads: u32,
    results: *mut dcol_proximity_result,
    statuses: *mut dcol_status,
) -> dcol_status {
    run("dcol_proximity_batch", || {
        if count > 0 {
            let arrays: [(bool, &'static str); 6] = [
                (shapes1.is_null(), "shapes1"),
                (poses1.is_null(), "poses1"),
                (shapes2.is_null(), "shapes2"),
                (poses2.is_null(), "poses2"),
                (results.is_null(), "results"),
                (statuses.is_null(), "statuses"),
            ];
            if let Some((_, name)) = arrays.iter().find(|(is_null, _)| *is_null) {
                return Err(Failure::Null(name));
            }
        }
        // SAFETY: forwarded from this function's contract.
        let options = unsafe { read_options(options) }?;
        if count == 0 {
            return Ok(());
        }
        let arrays = Arrays {
            shapes1,
            poses1,
            shapes2,
            poses2,
            results,
            statuses,
            options,
        };
        let threads = if count < 2 {
            1
        } else {
            threads.min(DCOL_BATCH_MAX_THREADS) as usize
        };
        let chunks = (0..count)
            .step_by(CHUNK)
            .map(|start| start..start.saturating_add(CHUNK).min(count));
        // SAFETY: every range is within `0..count`, and the ranges are disjoint (the chunks
        // partition `0..count` and each is handed to exactly one thread).
        for_each_parallel(chunks, threads, |range| unsafe { arrays.run_range(range) });
        Ok(())
    })
}
