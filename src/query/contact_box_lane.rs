//! The C function's lane for two boxes (`dcol_contacts`, `dcol_contacts_cached`): the pair
//! rigid-body scenes meet most (a stack, a pyramid, a wall), answered by the boxes' closed form
//! (`super::contact_boxes`) and its points written straight to the caller, without the
//! manifold's dispatch (the sphere and half-space tests, the signed distance's preamble), the
//! `Manifold` and `Contact` copies between the layers, or the warm start's wrapper.
//!
//! It answers only where [`super::manifold`] (with `exact_distance` false, as the C function
//! asks) answers by the same closed form, and gives the same points in the same order, chosen
//! by the same reduction, the same finiteness test and the same cache update
//! (`super::warm_contacts::manifold_cached`'s); it declines (`None`, nothing written, the cache
//! untouched) everywhere else: another pair, a margin the manifold rejects, an answer the closed
//! form leaves to the general path (an edge pair whose points it does not find, a clipping
//! that misses the depth), a number that is not finite, a cache holding a separating normal to
//! try. The caller then runs the full query, which also reports every error. Unit tests
//! (`contact_box_lane_tests.rs`): the lane's points against `manifold`'s (`exact_distance`
//! false) and, with a cache, its points and cache against `manifold_cached`'s, bit for bit.

use super::contact::MAX_CONTACTS;
use super::contact_boxes::{boxes, Boxes, End, MAX};
use super::contact_reduce::reduce_in;
use super::warm::Cache;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;

/// The contact points of two centred boxes `shape1` at `pose1` and `shape2` at `pose2` within
/// `margin`, at most `capacity` (and [`MAX_CONTACTS`]) of them, each passed to `write` (its
/// slot, position, normal from shape 1 to shape 2, depth) once all are known to be finite;
/// their number. `None` where the full query must answer (see the module's note).
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn box_contacts(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    margin: Real,
    capacity: usize,
    cache: Option<&mut Cache>,
    mut write: impl FnMut(usize, &Vec3, &Vec3, Real),
) -> Option<usize> {
    let (h1, h2) = (shape1.centred_box()?, shape2.centred_box()?);
    if !(margin.is_finite() && margin >= 0.0) {
        return None;
    }
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    let mut b = Boxes::new();
    let End::Closed = boxes(shape1, &h1, pose1, shape2, &h2, pose2, margin, ell, &mut b) else {
        return None;
    };
    // As `super::contact::finish`: every point when they fit, else the reduction's choice;
    // `v · 0` is 0 for a finite `v` and NaN otherwise.
    let cap = capacity.min(MAX_CONTACTS);
    let n = b.pos.len().min(b.depth.len());
    let mut chosen = [0usize; MAX_CONTACTS];
    let k = if cap == 0 {
        0
    } else if n <= cap {
        for (i, c) in chosen.iter_mut().enumerate().take(n) {
            *c = i;
        }
        n
    } else {
        // At most `MAX` candidates: buffers of that size.
        reduce_in::<MAX>(&b.pos, &b.depth, cap, &mut chosen)
    };
    let zero = |v: &Vec3| v.x * 0.0 + v.y * 0.0 + v.z * 0.0;
    let mut sum = b.sd.distance * 0.0 + zero(&b.sd.normal);
    for &i in &chosen[..k] {
        sum = sum + b.depth[i] * 0.0 + zero(&b.pos[i]);
    }
    if sum != 0.0 {
        return None;
    }
    if let Some(c) = cache {
        // `manifold_cached` first tries a kept separating normal; with none (this call's back-off
        // counted down as there), its manifold is this one, and the cache keeps its normal.
        if c.separating().is_some() {
            return None;
        }
        c.keep_separating((b.sd.distance > 0.0).then_some(&b.sd.normal));
    }
    for (slot, &i) in chosen[..k].iter().enumerate() {
        write(slot, &b.pos[i], &b.sd.normal, b.depth[i]);
    }
    Some(k)
}

#[cfg(test)]
#[path = "contact_box_lane_tests.rs"]
mod tests;
