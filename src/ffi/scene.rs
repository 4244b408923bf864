//! `dcol_scene`: a set of bodies for repeated "which pairs have alpha* <= t?" queries, with its
//! pair and statistics structs.
//!
//! The C scene owns a Rust [`Scene`] and the `Vec` its steps report into, reused across steps,
//! so a step allocates only when the scene or the number of reported pairs outgrows every
//! earlier step.

use super::boundary::{check_out, run, Failure};
use super::options::{dcol_options, read_options};
use super::pose::{dcol_pose, read_pose};
use super::proximity::dcol_proximity_result;
use super::shape::{dcol_shape, shape_ref};
use super::status::dcol_status;
use crate::scene::{Scene, ScenePair, StepStats};

/// An opaque set of bodies (a shape and a pose each) for repeated all-pairs threshold queries
/// (dcol_scene_pairs_within). Made by dcol_scene_new, released with dcol_scene_free; bodies are
/// added with dcol_scene_add and moved with dcol_scene_set_pose.
///
/// Not thread-safe: a scene must be used by one thread at a time (no call on a scene may run
/// concurrently with another call on the same scene, including dcol_scene_size). Different
/// scenes are independent and may be used by different threads at once.
pub struct dcol_scene {
    scene: Scene,
    /// The pairs of the last step, reused across steps.
    pairs: Vec<ScenePair>,
}

/// One pair reported by dcol_scene_pairs_within.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct dcol_scene_pair {
    /// The lower body id (body1 < body2).
    pub body1: usize,
    /// The higher body id.
    pub body2: usize,
    /// The proximity of (body1, body2), as dcol_proximity with the bodies' shapes and poses in
    /// that order.
    pub proximity: dcol_proximity_result,
    /// DCOL_OK, or DCOL_ERROR_NOT_CONVERGED when the pair's solve hit the iteration limit and
    /// `proximity` holds the last iterate (reported because that iterate's alpha is <= the
    /// threshold).
    pub status: dcol_status,
}

/// How many pairs each level of a dcol_scene_pairs_within step handled, cheapest level first.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct dcol_scene_stats {
    /// N (N - 1) / 2 for N bodies.
    pub pairs_total: usize,
    /// Pairs whose sweep-and-prune intervals (x extent of the bounding spheres scaled by the
    /// threshold) overlap.
    pub sweep_candidates: usize,
    /// Of those, pairs whose scaled bounding spheres overlap.
    pub sphere_candidates: usize,
    /// Of those, pairs proven below the threshold by the inscribed-sphere bound (then solved
    /// fully).
    pub proven_by_bounds: usize,
    /// Pairs whose solve stopped early once alpha* > threshold was proven.
    pub early_exits: usize,
    /// Pairs solved to convergence.
    pub full_solves: usize,
    /// Pairs reported (alpha* <= threshold).
    pub reported: usize,
}

impl From<&StepStats> for dcol_scene_stats {
    fn from(s: &StepStats) -> Self {
        dcol_scene_stats {
            pairs_total: s.pairs_total,
            sweep_candidates: s.sweep_candidates,
            sphere_candidates: s.sphere_candidates,
            proven_by_bounds: s.proven_by_bounds,
            early_exits: s.early_exits,
            full_solves: s.full_solves,
            reported: s.reported,
        }
    }
}

impl From<&ScenePair> for dcol_scene_pair {
    fn from(p: &ScenePair) -> Self {
        dcol_scene_pair {
            body1: p.body1,
            body2: p.body2,
            proximity: (&p.proximity).into(),
            status: if p.proximity.status.is_converged() {
                dcol_status::DCOL_OK
            } else {
                dcol_status::DCOL_ERROR_NOT_CONVERGED
            },
        }
    }
}

/// Borrows the scene behind `ptr` mutably after checking it for NULL.
///
/// # Safety
/// `ptr` must be NULL or a live pointer returned by `dcol_scene_new`, not used by any other
/// thread or reference for the lifetime `'a`.
unsafe fn scene_mut<'a>(ptr: *mut dcol_scene) -> Result<&'a mut dcol_scene, Failure> {
    if ptr.is_null() {
        return Err(Failure::Null("scene"));
    }
    // SAFETY: non-NULL; the caller guarantees it came from `Box::into_raw` in `dcol_scene_new`,
    // is live, and is not used concurrently (a scene is used by one thread at a time).
    Ok(unsafe { &mut *ptr })
}

/// A new, empty scene. On success *out receives a scene owned by the caller (release it with
/// dcol_scene_free); on error *out is set to NULL. Allocates.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_new(out: *mut *mut dcol_scene) -> dcol_status {
    run("dcol_scene_new", || {
        check_out(out, "out")?;
        let scene = Box::new(dcol_scene {
            scene: Scene::new(),
            pairs: Vec::new(),
        });
        // SAFETY: `out` is non-NULL (checked above) and valid for writes (caller's contract).
        unsafe { out.write(Box::into_raw(scene)) };
        Ok(())
    })
}

/// Releases a scene made by dcol_scene_new, with its copies of the bodies' shapes. NULL is a
/// no-op. The scene must not be in use by another thread, and must not be used or freed again
/// afterwards. The shapes passed to dcol_scene_add are not affected (the scene holds copies).
///
/// # Safety
/// `scene` must be NULL or a live pointer returned by `dcol_scene_new`.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_free(scene: *mut dcol_scene) {
    super::boundary::catch("dcol_scene_free", (), || {
        if !scene.is_null() {
            // SAFETY: the pointer came from `Box::into_raw` in `dcol_scene_new` and is live and
            // unshared (caller's contract), so ownership can be taken back exactly once.
            drop(unsafe { Box::from_raw(scene) });
        }
    })
}

/// Adds a body with a copy of `shape` at `pose` and writes its id to *id. Ids are consecutive
/// from 0 in the order of addition and never change. The scene keeps its own copy of the shape:
/// the caller may free `shape` at once. Allocates (the copy, and the scene's arrays as they
/// grow).
///
/// Returns DCOL_OK; or DCOL_ERROR_NULL_POINTER (`scene`, `shape`, `pose` or `id` NULL) or
/// DCOL_ERROR_INVALID_POSE (naming e.g. `pose->position[0]`), with the scene and *id
/// untouched.
///
/// # Safety
/// `scene` must be NULL or a live scene not used by another thread; `shape` NULL or a live
/// shape; `pose` NULL or valid; `id` NULL or valid for writing one size_t.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_add(
    scene: *mut dcol_scene,
    shape: *const dcol_shape,
    pose: *const dcol_pose,
    id: *mut usize,
) -> dcol_status {
    run("dcol_scene_add", || {
        // SAFETY: forwarded from this function's contract.
        let s = unsafe { scene_mut(scene) }?;
        // SAFETY: forwarded from this function's contract.
        let shape = unsafe { shape_ref(shape, "shape") }?;
        if pose.is_null() {
            return Err(Failure::Null("pose"));
        }
        check_out(id, "id")?;
        // SAFETY: forwarded from this function's contract (non-NULL checked).
        let pose = unsafe { read_pose(pose, "pose", "pose->") }?;
        let new_id = s.scene.add(shape.clone(), pose);
        // SAFETY: `id` is non-NULL (checked) and valid for writes (contract).
        unsafe { id.write(new_id) };
        Ok(())
    })
}

/// Moves body `id` to `pose`. Does not allocate.
///
/// Returns DCOL_OK; or DCOL_ERROR_NULL_POINTER (`scene` or `pose` NULL), DCOL_ERROR_INVALID_POSE
/// (naming e.g. `pose->quaternion`), or DCOL_ERROR_INVALID_OPTIONS when `id` is not a body of
/// this scene (id >= dcol_scene_size), with the scene unchanged.
///
/// # Safety
/// `scene` must be NULL or a live scene not used by another thread; `pose` NULL or valid.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_set_pose(
    scene: *mut dcol_scene,
    id: usize,
    pose: *const dcol_pose,
) -> dcol_status {
    run("dcol_scene_set_pose", || {
        // SAFETY: forwarded from this function's contract.
        let s = unsafe { scene_mut(scene) }?;
        if pose.is_null() {
            return Err(Failure::Null("pose"));
        }
        // SAFETY: forwarded from this function's contract (non-NULL checked).
        let pose = unsafe { read_pose(pose, "pose", "pose->") }?;
        s.scene.set_pose(id, pose).map_err(Failure::api)
    })
}

/// Writes the number of bodies in the scene to *size. Does not allocate.
///
/// # Safety
/// `scene` must be NULL or a live scene not used by another thread; `size` NULL or valid for
/// writing one size_t.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_size(
    scene: *const dcol_scene,
    size: *mut usize,
) -> dcol_status {
    run("dcol_scene_size", || {
        if scene.is_null() {
            return Err(Failure::Null("scene"));
        }
        check_out(size, "size")?;
        // SAFETY: non-NULL (checked) and a live scene not mutated concurrently (contract).
        let n = unsafe { (*scene).scene.len() };
        // SAFETY: `size` is non-NULL (checked) and valid for writes (contract).
        unsafe { size.write(n) };
        Ok(())
    })
}

/// Every pair of bodies with alpha* <= `threshold` (> 0, finite): a broad phase (sweep and
/// prune on the bounding spheres scaled by the threshold, then the exact bounding-sphere test)
/// skips the pairs it can, the inscribed-sphere bound proves some pairs close without a
/// threshold test, and the remaining solves stop as soon as alpha* > threshold is proven. Each
/// reported pair carries its full proximity, that of dcol_proximity on the two bodies (lower
/// id first): bit for bit, except between two polytopes (boxes, polytopes, unpadded hulls),
/// whose pairs keep a dcol_cache from step to step and start from their last answer (the same
/// answer to the solver's tolerance: alpha* within 1e-12 relative). Pairs within about the
/// solver tolerance of the threshold may be reported or not.
///
/// The pairs are written to pairs[0..*count] in increasing (body1, body2) order. `capacity` is
/// the number of elements `pairs` can hold; `pairs` may be NULL when capacity is 0 (to learn the
/// count). `stats` may be NULL; otherwise it receives the work done by each level.
/// `options` may be NULL (defaults).
///
/// Returns DCOL_OK with pairs[0..*count] and *stats written. If more than `capacity` pairs
/// qualify, returns DCOL_ERROR_INVALID_OPTIONS naming `capacity`, writes the number of pairs
/// needed to *count (a documented exception to "outputs only on success") and writes nothing
/// else: call again with a buffer of at least *count pairs (the step is deterministic, so the
/// same poses give the same pairs). Other errors: DCOL_ERROR_NULL_POINTER (`scene`, `count`,
/// or `pairs` with capacity > 0), DCOL_ERROR_INVALID_OPTIONS (`threshold` or *options), with
/// nothing written. A pair whose solve did not converge is reported with status
/// DCOL_ERROR_NOT_CONVERGED in its dcol_scene_pair when its last iterate is <= threshold; the
/// call still returns DCOL_OK.
///
/// Cost: O(N log N) for the sweep plus one (often truncated) solve per pair whose scaled
/// bounding spheres overlap. Allocation: the scene keeps its sweep order and the list of
/// reported pairs between steps, so a step allocates only when the number of bodies or of
/// reported pairs exceeds that of every earlier step (and a many-facet shape uses the
/// per-thread scratch buffer, allocated once).
///
/// # Safety
/// `scene` must be NULL or a live scene not used by another thread; `options` NULL or valid;
/// `pairs` NULL or valid for writing `capacity` elements; `count` NULL or valid for writing one
/// size_t; `stats` NULL or valid for writes.
#[no_mangle]
pub unsafe extern "C" fn dcol_scene_pairs_within(
    scene: *mut dcol_scene,
    threshold: f64,
    options: *const dcol_options,
    pairs: *mut dcol_scene_pair,
    capacity: usize,
    count: *mut usize,
    stats: *mut dcol_scene_stats,
) -> dcol_status {
    run("dcol_scene_pairs_within", || {
        // SAFETY: forwarded from this function's contract.
        let s = unsafe { scene_mut(scene) }?;
        if capacity > 0 {
            check_out(pairs, "pairs")?;
        }
        check_out(count, "count")?;
        // SAFETY: forwarded from this function's contract.
        let options = unsafe { read_options(options) }?;
        let step = s
            .scene
            .pairs_within(threshold, &options, &mut s.pairs)
            .map_err(Failure::api)?;
        let found = s.pairs.len();
        if found > capacity {
            // SAFETY: `count` is non-NULL (checked) and valid for writes (contract).
            unsafe { count.write(found) };
            return Err(Failure::Capacity {
                argument: "capacity",
                given: capacity,
                needed: found,
                what: "pairs",
                count: "count",
            });
        }
        for (i, p) in s.pairs.iter().enumerate() {
            // SAFETY: `i < found <= capacity`; `pairs` is non-NULL when capacity > 0 (checked)
            // and valid for writing `capacity` elements (contract).
            unsafe { pairs.add(i).write(p.into()) };
        }
        // SAFETY: `count` is non-NULL (checked) and valid for writes (contract).
        unsafe { count.write(found) };
        if !stats.is_null() {
            // SAFETY: non-NULL (checked) and valid for writes (contract).
            unsafe { stats.write((&step).into()) };
        }
        Ok(())
    })
}
