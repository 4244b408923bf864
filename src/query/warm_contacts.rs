//! The signed distance's and the contact manifold's warm start (`super::warm::Cache`): a
//! separating normal kept from the pair's last answer bounds the distance below with two
//! support calls (`d ≥ n·(r₂ − r₁) − h₁(n) − h₂(−n)` for any unit `n`), which decides a pair
//! apart by more than the margin (no contact points) at once; a separated pair's distance comes
//! from the cache's distance part (`super::warm_distance`).

use super::contact::{contact_manifold, manifold, Manifold};
use super::context::{Options, SignedDistance};
use super::distance::distance_query_warm;
use super::signed::signed_distance;
use super::warm::Cache;
use crate::error::Error;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, SupportMap};

/// A lower bound on the distance of the shapes (world) from the unit normal `n` (from shape 1
/// to shape 2).
fn gap_below(shapes: [&Shape; 2], poses: [&Pose; 2], n: &Vec3) -> Real {
    let h = |i: usize, m: Vec3| {
        let (r, q) = (poses[i].rotation(), poses[i].position());
        let (p, _) = shapes[i].support(&r.tr_mul(&m));
        m.dot(&(r * p + q))
    };
    // The largest point of shape 1 along n and the smallest of shape 2.
    -h(1, -n) - h(0, *n)
}

/// The bound of the separating normal the cache gives this call (`super::warm::Cache::separating`,
/// its back-off told how it fared), when it proves the shapes apart by more than `margin`.
fn proven_apart(
    cache: &mut Cache,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    margin: Real,
) -> Option<(Vec3, Real)> {
    let n = cache.separating()?;
    let gap = gap_below(shapes, poses, &n);
    cache.separating_tried(gap > margin);
    (gap > margin).then_some((n, gap))
}

/// [`crate::signed_distance`] with a warm start: between two polytopes the kept separating
/// normal proves apart, the distance ([`crate::distance_cached`]), else the cold signed
/// distance. The same answer, certified the same way; the cache keeps this one.
pub fn signed_distance_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<SignedDistance, Error> {
    let (shapes, poses) = ([shape1, shape2], [pose1, pose2]);
    // Only where the distance itself starts warm (two polytopes): elsewhere the cold signed
    // distance tries GJK's distance first anyway, and the bound would only add its cost.
    let polytopes = shapes.iter().all(|s| s.vertex_pieces().is_some());
    let apart = polytopes
        && options.method == crate::Method::Auto
        && proven_apart(cache, shapes, poses, 0.0).is_some();
    signed_proven(shapes, poses, options, cache, polytopes, apart)
}

/// [`signed_distance_cached`] once the kept normal was tried (`polytopes`: two polytopes;
/// `apart`: the normal proved them apart). Inlined: as a call it cost the other pairs, which go
/// straight to the cold signed distance, about 2 % (measured on `benches/warm`).
#[inline]
fn signed_proven(
    [shape1, shape2]: [&Shape; 2],
    [pose1, pose2]: [&Pose; 2],
    options: &Options,
    cache: &mut Cache,
    polytopes: bool,
    apart: bool,
) -> Result<SignedDistance, Error> {
    if apart {
        let (d, _) = distance_query_warm(shape1, pose1, shape2, pose2, options, false, cache)?;
        if d.distance > 0.0 && d.status.is_converged() {
            cache.keep_separating(Some(&d.normal));
            return Ok(SignedDistance {
                distance: d.distance,
                normal: d.normal,
                closest1: d.closest1,
                closest2: d.closest2,
                iterations: d.iterations,
                status: d.status,
                path: d.path,
            });
        }
    }
    let sd = signed_distance(shape1, pose1, shape2, pose2, options)?;
    if polytopes {
        cache.keep_separating((sd.distance > 0.0).then_some(&sd.normal));
    }
    Ok(sd)
}

/// [`crate::contact_manifold`] with a warm start: two polytopes the kept separating normal
/// proves apart by more than `margin` have no contact points, and their signed distance is the
/// distance ([`crate::distance_cached`]); other pairs are answered cold (the C function, which
/// needs no exact distance there, takes the bound for every pair). The same manifold; the cache
/// keeps this one's normal where it separates the shapes.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn contact_manifold_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    margin: Real,
    max_points: usize,
    options: &Options,
    cache: &mut Cache,
) -> Result<Manifold, Error> {
    let (shapes, poses) = ([shape1, shape2], [pose1, pose2]);
    // Its signed distance must be exact: the bound pays only where that distance starts warm
    // (two polytopes).
    let polytopes = shapes.iter().all(|s| s.vertex_pieces().is_some());
    let proven = if polytopes && margin.is_finite() {
        proven_apart(cache, shapes, poses, margin)
    } else {
        None
    };
    if let Some((_, gap)) = proven {
        let apart = options.method == crate::Method::Auto && gap > 0.0;
        let sd = signed_proven(shapes, poses, options, cache, true, apart)?;
        if sd.distance > margin {
            let mut m = Manifold::empty();
            m.normal = sd.normal;
            m.signed_distance = sd.distance;
            m.status = sd.status;
            m.iterations = sd.iterations;
            return Ok(m);
        }
    }
    let m = contact_manifold(shape1, pose1, shape2, pose2, margin, max_points, options)?;
    if polytopes {
        cache.keep_separating((m.signed_distance > 0.0).then_some(&m.normal));
    }
    Ok(m)
}

/// The C function's manifold (`super::contact::manifold` with `exact_distance` false: a pair
/// apart by more than the margin carries only a lower bound above it) with the warm start of
/// [`contact_manifold_cached`]: the kept separating normal's bound, when above the margin, is
/// that lower bound.
#[allow(clippy::too_many_arguments)]
pub(crate) fn manifold_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    margin: Real,
    max_points: usize,
    options: &Options,
    out: &mut Manifold,
    cache: &mut Cache,
) -> Result<(), Error> {
    if margin.is_finite() && margin >= 0.0 {
        if let Some((n, gap)) = proven_apart(cache, [shape1, shape2], [pose1, pose2], margin) {
            *out = Manifold::empty();
            out.normal = n;
            out.signed_distance = gap;
            return Ok(());
        }
    }
    manifold(
        shape1, pose1, shape2, pose2, margin, max_points, options, false, out,
    )?;
    cache.keep_separating((out.signed_distance > 0.0).then_some(&out.normal));
    Ok(())
}
