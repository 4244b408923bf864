//! The C ABI's closed-form lane: proximity and the distance for the pairs answered in closed
//! form (for proximity sphere and capsule pairs and a sphere with a centred box, a cylinder or a
//! cone; for the distance those, a sphere with any polytope, an ellipsoid or a cone, and a
//! capsule with a centred box, a cylinder or a cone) straight from the poses' numbers, without forming [`Pose`](crate::math::Pose)s (a sphere's rotation matrix is never
//! used) or passing through the full query's dispatch.
//!
//! It answers only where the full query would answer by the same closed form, with the same
//! arithmetic (`super::geometric::closed_form` and `super::geometric::in_world` on the same
//! inputs), and says `None` everywhere else (another pair, a pose `Pose::new` would reject or
//! rescale, coincident or overflowing origins, a closed form that declines, a number that is
//! not finite): the caller then runs the full query, which also reports every error. Measured
//! through the C ABI with callgrind (`docs/geometric-solver.md`).

use super::context::{Distance, DistancePath, Proximity};
use super::dispatch::{route, Stage};
use super::distance::MAX_OFFSET_RATIO;
use super::geometric::{closed_form, in_world};
use super::separated::{self, MARGIN, TOL_FLOOR};
use crate::math::{
    finite_array, plain_pose, robust_norm, rotation_from_quaternion, Mat3, Real, Vec3,
};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::raycast::Pair;

/// A pose's numbers as the C ABI passes them: position and quaternion `[w, x, y, z]`.
pub(crate) type RawPose<'a> = (&'a [Real; 3], &'a [Real; 4]);

/// The attitude a shape's closed forms read: none for a sphere (its answers do not depend on
/// it; the identity stands in), else the rotation `Pose::new` forms from the same numbers.
#[inline(always)]
fn attitude(kind: ShapeKind, quaternion: &[Real; 4]) -> Mat3 {
    if kind == ShapeKind::Sphere {
        Mat3::identity()
    } else {
        rotation_from_quaternion(*quaternion)
    }
}

/// Whether the pair `(one, two)` may take the lane: bounded shapes whose proximity starts with
/// a closed form.
#[inline(always)]
pub(crate) fn takes(one: &Shape, two: &Shape) -> bool {
    let bounded = |s: &Shape| s.solver_kind() != ShapeKind::Halfspace;
    bounded(one) && bounded(two) && route(one, two).proximity.has(Stage::ClosedForm)
}

/// The proximity of `shape1` at `pose1` and `shape2` at `pose2` by its closed form, exactly as
/// `super::proximity` answers it with the default method and no smoothing (the closed forms
/// use no tolerance or iteration limit); `None` where the full query must answer.
#[inline(always)]
pub(crate) fn proximity(
    shape1: &Shape,
    pose1: RawPose<'_>,
    shape2: &Shape,
    pose2: RawPose<'_>,
) -> Option<Proximity> {
    if !(takes(shape1, shape2) && plain_pose(pose1.0, pose1.1) && plain_pose(pose2.0, pose2.1)) {
        return None;
    }
    let r1 = Vec3::from(*pose1.0);
    let r2 = Vec3::from(*pose2.0);
    // As `super::proximity::plain_offset` and `super::geometric::proximity`.
    let dist = robust_norm(&(r2 - r1));
    if !(dist > 0.0 && dist.is_finite()) {
        return None;
    }
    let rot1 = attitude(shape1.solver_kind(), pose1.1);
    let rot2 = attitude(shape2.solver_kind(), pose2.1);
    let ray = (r2 - r1) / dist;
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    let inv = 1.0 / ell;
    let pair = Pair::new([shape1, shape2], [&rot1, &rot2], inv);
    let ans = closed_form(&pair, &ray)?;
    in_world(&ans, [&r1, &r2], ell, dist * inv)
}

/// The distance of `shape1` at `pose1` and `shape2` at `pose2` as `super::distance` answers
/// it with the default method on a pair with a closed form where that answer needs no solver:
/// the inscribed balls overlapping, or the closed form (`super::separated`'s, certified
/// to `tolerance`: the distance, or an overlap it found), on the same inputs with the same
/// arithmetic; `None` where the full query must answer (a half-space, poses `Pose::new` would
/// not take as they are, offsets the distance program rejects, a pair without a closed form or
/// whose closed form declines, a number that is not finite).
#[inline(always)]
pub(crate) fn distance(
    shape1: &Shape,
    pose1: RawPose<'_>,
    shape2: &Shape,
    pose2: RawPose<'_>,
    tolerance: Real,
) -> Option<Distance> {
    let bounded = |s: &Shape| s.solver_kind() != ShapeKind::Halfspace;
    // Only pairs with a closed form: others pay nothing here but this test (the inscribed
    // balls' overlap below is theirs too, but taking it only moved ~180 instructions of a
    // separated box–box distance into the lane and back out).
    if !(bounded(shape1)
        && bounded(shape2)
        && route(shape1, shape2).distance.has(Stage::ClosedForm)
        && plain_pose(pose1.0, pose1.1)
        && plain_pose(pose2.0, pose2.1))
    {
        return None;
    }
    let r1 = Vec3::from(*pose1.0);
    let r2 = Vec3::from(*pose2.0);
    // As `super::distance::distance_query_until`: overlap certified by the inscribed balls,
    // else the offset within what the distance program represents.
    let offset = r2 - r1;
    let len = robust_norm(&offset);
    if !len.is_finite() {
        return None;
    }
    let (i1, i2) = (shape1.inscribed_radius(), shape2.inscribed_radius());
    if len < i1 + i2 {
        return overlap(r1 + offset * (i1 / (i1 + i2)), DistancePath::InteriorPoint);
    }
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    if !(len / ell <= MAX_OFFSET_RATIO) {
        return None;
    }
    // As `super::separated::separated`.
    let rot1 = attitude(shape1.solver_kind(), pose1.1);
    let rot2 = attitude(shape2.solver_kind(), pose2.1);
    let inv = 1.0 / ell;
    let pair = Pair::new([shape1, shape2], [&rot1, &rot2], inv);
    let d = (r2 - r1) * inv;
    let tol = (tolerance * MARGIN).max(TOL_FLOOR);
    match separated::closed_form(&pair, &d, tol) {
        Ok(s) => {
            let answer = separated::in_world(&s?, [&r1, &r2], ell)?;
            let n = &answer.normal;
            finite_array(&[n.x, n.y, n.z]).then_some(answer)
        }
        // A certified overlap, at the common point `a` (normalised, relative to r₁).
        Err(a) => overlap(r1 + a * ell, DistancePath::Gjk),
    }
}

/// `super::distance`'s answer for overlapping shapes with the common point `w` (`None` unless
/// it is finite), found by `path`.
#[inline(always)]
fn overlap(w: Vec3, path: DistancePath) -> Option<Distance> {
    finite_array(&[w.x, w.y, w.z]).then_some(Distance {
        path,
        ..super::distance::overlap(w, 0)
    })
}
