//! Derivatives with respect to the shapes' own parameters (a radius, a half extent, an
//! ellipsoid's matrix, a polytope's planes, a hull's points: the numbers given to the
//! constructor, in the order [`Shape::parameters`] gives them) of α*, the distance and the
//! signed distance.
//!
//! α* = max over n of n·d/(h₁(n) + h₂(−n)), so by the envelope theorem
//! `∂α*/∂θ = −α* ∂h_K(ñ)/∂θ` at `ñ = n*/h_K(n*)`, and each shape gives `∂h(m)/∂θ` at the support
//! point the query found (`crate::shapes::Shape::support_gradient`): a few flops on top of the
//! pose gradient. Where the contact points are not unique the interior-point path answers
//! (its multipliers, or with smoothing its central path), as for the pose gradient
//! (`docs/derivatives.md`, "Derivatives with respect to the shapes").

use super::context::{Distance, Options, Proximity, ShapeSink, SignedDistance, Want};
use super::distance::distance;
use super::geometric::support_gradients;
use super::proximity::query_full;
use super::signed::signed_distance;
use crate::error::{Error, ErrorDetail};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;
use crate::solver::SolveStatus;

/// Checks that each wanted buffer holds its shape's parameters.
fn check_buffers(shapes: [&Shape; 2], d: [&Option<&mut [Real]>; 2]) -> Result<(), Error> {
    for i in 0..2 {
        if let Some(d) = d[i] {
            if d.len() < shapes[i].parameter_count() {
                return Err(Error::InvalidOptions(ErrorDetail::new(
                    if i == 0 { "d_shape1" } else { "d_shape2" },
                    d.len() as Real,
                    "has fewer entries than the shape has parameters (Shape::parameter_count)",
                )));
            }
        }
    }
    Ok(())
}

/// α*, x* and the contact points, and `∂α*/∂θᵢ` with respect to each shape's parameters
/// ([`Shape::parameters`], in that order) into `d_shape1` and `d_shape2` (each `None`, or at
/// least [`Shape::parameter_count`] entries; only that many are written). The derivatives are
/// with respect to the numbers exactly as given to the constructor, so a finite difference on
/// the constructor's arguments checks them (an ellipsoid's `P` enters through `(P + Pᵀ)/2`: a
/// symmetric change of the pair `P_ij`, `P_ji` changes α* by the sum of their two entries).
///
/// `Proximity::derivatives` says their kind, as for [`crate::gradient`]: `Exact` where the
/// contact points are unique (the envelope theorem on the geometric answer), `Smoothed` where
/// they are not (flat against flat: the interior-point path's multipliers) or with
/// `Options::smoothing` (the central path's exact derivatives), `Subgradient` where α* is not
/// differentiable in a shape's parameters although the contact is unique (a corner where more
/// than three of a polytope's planes meet, a hull's facet of more than three corners, a hull
/// corner given twice: one element of the generalised gradient is returned) and at coincident
/// origins (zeros). Costs a few flops beyond [`crate::gradient`] (a scan of the rows for
/// polytopes, of the facets for hulls).
///
/// ```
/// use dcol::{shape_gradient, Options, Pose, Shape};
/// let (a, b) = (Shape::sphere(1.0).unwrap(), Shape::cuboid(0.5, 1.0, 1.0).unwrap());
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([3.0, 0.0, 0.0]).unwrap();
/// let (mut g1, mut g2) = ([0.0; 1], [0.0; 3]);
/// let p = shape_gradient(&a, &pa, &b, &pb, &Options::default(), Some(&mut g1), Some(&mut g2))
///     .unwrap();
/// // α* = 3/(R + h_x) = 2: ∂α*/∂R = ∂α*/∂h_x = −α*/(R + h_x); h_y, h_z do not matter.
/// assert!((p.alpha - 2.0).abs() < 1e-12);
/// assert!((g1[0] + 4.0 / 3.0).abs() < 1e-9 && (g2[0] + 4.0 / 3.0).abs() < 1e-9);
/// assert!(g2[1].abs() < 1e-12 && g2[2].abs() < 1e-12);
/// ```
pub fn shape_gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    d_shape1: Option<&mut [Real]>,
    d_shape2: Option<&mut [Real]>,
) -> Result<Proximity, Error> {
    let shapes = [shape1, shape2];
    check_buffers(shapes, [&d_shape1, &d_shape2])?;
    let mut sink = ShapeSink::new([d_shape1, d_shape2]);
    let full = query_full(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        Want::Gradient,
        None,
        Some(&mut sink),
        None,
    )?;
    let mut prox = full.prox;
    if !sink.written {
        // No derivatives came with the answer. When the answer itself is finite: zeros, as the
        // pose gradient gives; when it is not representable (α* = +inf, a point beyond the
        // largest double) the buffers stay untouched (the C functions then write nothing and
        // return DCOL_ERROR_INVALID_POSE). Either way the status says so.
        if prox.is_representable() {
            sink.zero(shapes);
        }
        if prox.status.is_converged() {
            prox.status = SolveStatus::NumericalFailure;
        }
    }
    if !sink.finite {
        prox.status = SolveStatus::NumericalFailure;
    }
    Ok(prox)
}

/// The exact distance ([`crate::distance`]) and `∂d*/∂θᵢ` with respect to each shape's
/// parameters (as [`shape_gradient`]): `−∂hᵢ/∂θᵢ` at the distance's unit normal and witness
/// points (`d* = max over unit n of n·d − h₁(n) − h₂(−n)`). Zero when the shapes touch or
/// overlap (the distance is 0 there, as [`crate::distance_gradient`] returns). Where the
/// witness points are not unique (flat against flat) the derivatives with respect to
/// parameters that tilt a face are those at the witnesses returned.
pub fn distance_shape_gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    d_shape1: Option<&mut [Real]>,
    d_shape2: Option<&mut [Real]>,
) -> Result<Distance, Error> {
    let shapes = [shape1, shape2];
    check_buffers(shapes, [&d_shape1, &d_shape2])?;
    let mut d = distance(shape1, pose1, shape2, pose2, options)?;
    let numbers = [d.distance].into_iter().chain(d.closest1.iter().copied());
    let numbers = numbers.chain(d.closest2.iter().copied());
    if !numbers.chain(d.normal.iter().copied()).all(Real::is_finite) {
        // Not representable (origins near the largest double): no derivatives, buffers
        // untouched, and the status says so.
        d.status = SolveStatus::NumericalFailure;
        return Ok(d);
    }
    let apart = d.distance > 0.0;
    let w = Witnesses {
        normal: &d.normal,
        closest: [&d.closest1, &d.closest2],
    };
    if !witness_gradients(apart, w, shapes, [pose1, pose2], [d_shape1, d_shape2]) {
        d.status = SolveStatus::NumericalFailure;
    }
    Ok(d)
}

/// The signed distance ([`crate::signed_distance`]) and `∂sd/∂θᵢ` with respect to each
/// shape's parameters (as [`shape_gradient`]): `−∂hᵢ/∂θᵢ` at its unit normal and witness
/// points (`sd = max over unit n of n·d − h₁(n) − h₂(−n)`, separated or overlapping).
pub fn signed_distance_shape_gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    d_shape1: Option<&mut [Real]>,
    d_shape2: Option<&mut [Real]>,
) -> Result<SignedDistance, Error> {
    let shapes = [shape1, shape2];
    check_buffers(shapes, [&d_shape1, &d_shape2])?;
    let mut sd = signed_distance(shape1, pose1, shape2, pose2, options)?;
    let w = Witnesses {
        normal: &sd.normal,
        closest: [&sd.closest1, &sd.closest2],
    };
    if !witness_gradients(true, w, shapes, [pose1, pose2], [d_shape1, d_shape2]) {
        sd.status = SolveStatus::NumericalFailure;
    }
    Ok(sd)
}

/// A distance's unit normal and witness points.
struct Witnesses<'a> {
    normal: &'a Vec3,
    closest: [&'a Vec3; 2],
}

/// `−∂hᵢ/∂θᵢ` at a distance's normal and witnesses into the buffers (zeros where `wanted` is
/// false or the normal is zero); false when a derivative came out not finite.
fn witness_gradients(
    wanted: bool,
    w: Witnesses<'_>,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    buffers: [Option<&mut [Real]>; 2],
) -> bool {
    let mut sink = ShapeSink::new(buffers);
    sink.zero(shapes);
    if wanted && w.normal.norm() > 0.0 {
        support_gradients(w.normal, w.closest, shapes, poses, -1.0, &mut sink);
    }
    sink.finite
}
