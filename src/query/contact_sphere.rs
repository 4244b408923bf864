//! A sphere touching or overlapping another shape: the signed distance the contact manifold is
//! built from, by the signed distance's own closed forms called directly.
//!
//! `super::signed::signed_distance_validated` answers a sphere pair that touches or overlaps
//! from its closed forms (two rounded segments: a sphere against a sphere or a capsule; else
//! `crate::solver::closed_form::sphere_solid`: a sphere against a centred box, a cylinder, a
//! cone, an ellipsoid or a polytope about its centre) in every branch it takes: early when
//! neither the inscribed test nor the probe sends it on, late otherwise, and the general solvers
//! only when the closed form has no answer or finds the shapes apart. [`sphere_pair`] computes
//! the same closed form with the same normalisation (`d = (r₂ − r₁)/ℓ`, `ℓ` the larger bounding
//! radius) and the same scaling back, floor and checks, so its answer is the signed distance's
//! to the last bit, without its preamble (the half-space split, the offset's robust norm, the
//! route's stages read twice, the inscribed and probe tests): a resting sphere on a box in ODE,
//! 2 265 instructions a `dCollide` before, 1 915 after (`docs/engines.md`, round 8). Where it has no answer (`None`), the signed distance answers.
//!
//! A pair the closed form finds apart is left to the signed distance (its distance query's
//! status, which depends on the options' method and iteration limit, is the C function's status
//! too: a shortcut answering "apart, converged" there failed the fuzz driver's status check
//! with the interior-point method at 2 to 4 iterations), told not to compute the closed form
//! again (which had made separated sphere pairs' contacts 15–22 % dearer in instructions).

use super::context::{DistancePath, SignedDistance};
use super::dispatch::{route, Stage};
use super::distance::MAX_OFFSET_RATIO;
use crate::math::{Pose, Real};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::closed_form::{closest_segment_points, sphere_solid, RoundedSegment};
use crate::solver::raycast::Pair;
use crate::solver::SolveStatus;

/// What [`sphere_pair`] found.
pub(super) enum SphereAnswer {
    /// The closed form's signed distance of a pair that touches or overlaps.
    Touching(SignedDistance),
    /// The closed form finds the shapes apart: the signed distance answers, without computing
    /// the closed form again (`super::signed::signed_distance_after`).
    Apart,
}

/// The closed form of a pair with a sphere (see the module's notes); `None` for other pairs and
/// where the closed form has no answer.
#[inline]
pub(super) fn sphere_pair(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
) -> Option<SphereAnswer> {
    let sphere = |s: &Shape| s.kind() == ShapeKind::Sphere;
    let plane = |s: &Shape| s.kind() == ShapeKind::Halfspace;
    if !(sphere(shape1) || sphere(shape2)) || plane(shape1) || plane(shape2) {
        return None;
    }
    if !route(shape1, shape2).signed.has(Stage::ClosedForm) {
        return None;
    }
    let (r1, r2) = (*pose1.position(), *pose2.position());
    let offset = r2 - r1;
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    // The signed distance rejects offsets beyond 1e100 sizes (and overflowing ones): its error.
    let len = offset.norm();
    if !(len.is_finite() && len / ell <= 1e-3 * MAX_OFFSET_RATIO) {
        return None;
    }
    let inv = 1.0 / ell;
    let pair = Pair::new([shape1, shape2], [pose1.rotation(), pose2.rotation()], inv);
    let d = offset * inv;
    // As `signed::closed_forms`: two rounded segments, else a sphere against a solid.
    let (sd, normal, a, b, path) =
        match (RoundedSegment::of(&pair.one), RoundedSegment::of(&pair.two)) {
            (Some(one), Some(two)) => {
                let (x1, x2) = closest_segment_points(&one, &d, &two);
                let diff = x2 - x1;
                let len = diff.norm();
                if !(len > 1e-6) {
                    return None;
                }
                let n = diff / len;
                let sd = len - one.radius - two.radius;
                let (a, b) = (x1 + n * one.radius, x2 - d - n * two.radius);
                (sd, n, a, b, DistancePath::Segments)
            }
            _ => {
                let ss = sphere_solid(&pair, &d)?;
                (ss.sd, ss.normal, ss.a, ss.b, DistancePath::ClosedForm)
            }
        };
    if sd > 0.0 {
        return Some(SphereAnswer::Apart);
    }
    // Touching: within rounding of 0 (as the signed distance's floor).
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let sd = if sd.abs() <= floor { 0.0 } else { sd };
    let out = SignedDistance {
        distance: sd * ell,
        normal,
        closest1: r1 + a * ell,
        closest2: r2 + b * ell,
        iterations: 0,
        status: SolveStatus::Converged,
        path,
    };
    super::signed::finite(&out).then_some(SphereAnswer::Touching(out))
}
