//! The feature a polytope, an unpadded convex hull or a padded polygon touches by at a normal, read from
//! its vertices as the general feature solve reads it (`crate::solver::features`: the vertices,
//! or padded vertices, whose support values tie within its tolerance), for the closed-form
//! Jacobians (`super::ball_jacobian`, `super::segment_jacobian`, `super::sphere_jacobian`,
//! `super::face_jacobian`), the tolerances and margin all the closed forms decide
//! features with, and their finiteness check.

use crate::math::{Real, Vec3};
use crate::shapes::{Shape, ShapeKind, SupportMap};

/// The general solve's tie tolerance on support values, over `ℓ` (`sensitivity::TIE_TOL`).
pub(super) const TIE: Real = 1e-10;
/// The general solve's disc test: `1 − cos` of the normal and a flat face's at most this
/// (`sensitivity::DISC_COS`).
pub(super) const DISC: Real = 1e-13;
/// A decision this close (as a factor) to either tolerance is left to the general solve.
pub(super) const MARGIN: Real = 100.0;

/// How a tolerance test came out: clearly within, clearly beyond, or too close to call.
pub(super) fn decide(value: Real, tol: Real) -> Option<bool> {
    if value <= tol / MARGIN {
        Some(true)
    } else if value >= tol * MARGIN {
        Some(false)
    } else {
        None
    }
}

/// A shape's contact feature (body frame).
pub(super) enum Flat {
    /// One vertex: its point.
    Vertex(Vec3),
    /// Two tied vertices: the edge's unit direction.
    Edge(Vec3),
    /// Three or more: the face's outward unit normal.
    Face(Vec3),
}

/// The feature of a shape made of vertices padded by one radius (a polytope or an unpadded
/// hull: 0; a padded polygon: its radius) at the body unit normal `m`, and that
/// radius: the vertices within `tau` (the general solve's tie tolerance) of the support value
/// tie; `None` for other shapes, a tie within a factor 100 of that tolerance, or a face whose
/// first three tied vertices are nearly collinear.
pub(super) fn flat_feature(shape: &Shape, m: &Vec3, tau: Real) -> Option<(Flat, Real)> {
    // A padded hull is left to the general solve: against a cone its Jacobian differed from
    // the general solve's by up to 8e-12 (non-dimensional, in the α row: the gradient from
    // the iterative proximity answer against the refined feature solve).
    let (points, radius) = match (shape.vertex_pieces(), shape.ball_pieces()) {
        (Some(p), _) => (p, 0.0),
        (None, Some((p, r))) if shape.solver_kind() == ShapeKind::Polygon => (p, r),
        _ => return None,
    };
    let best = points
        .iter()
        .fold(Real::NEG_INFINITY, |b, v| b.max(v.dot(m)));
    if !best.is_finite() {
        return None;
    }
    let mut tied = [0usize; 3];
    let mut count = 0;
    for (i, v) in points.iter().enumerate() {
        if decide(best - v.dot(m), tau)? {
            if count < 3 {
                tied[count] = i;
            }
            count += 1;
        }
    }
    let p = tied.map(|i| points[i]);
    let flat = match count {
        1 => Flat::Vertex(p[0]),
        2 => Flat::Edge((p[1] - p[0]).normalize()),
        _ => {
            let (u, v) = (p[1] - p[0], p[2] - p[0]);
            let a = u.cross(&v);
            if !(a.norm() > 1e-6 * u.norm() * v.norm()) {
                return None;
            }
            let a = a.normalize();
            Flat::Face(if a.dot(m) >= 0.0 { a } else { -a })
        }
    };
    Some((flat, radius))
}

/// Whether every entry of a closed form's Jacobian is finite, cheaply: the column sums of its
/// four rows (14 independent sums the compiler vectorises), then their sum. Any infinity or
/// NaN makes it non-finite; a finite Jacobian whose sum overflows (entries near 1e307) is
/// called non-finite too, which only sends the pair to the general solve.
#[inline]
pub(super) fn block_finite(j: &[[Real; 14]; 4]) -> bool {
    let mut acc = j[0];
    for row in &j[1..] {
        for (a, v) in acc.iter_mut().zip(row) {
            *a += v;
        }
    }
    acc.iter().sum::<Real>().is_finite()
}
