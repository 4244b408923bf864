//! The Jacobian of `(x*, α*)` in closed form where an ellipsoid touches a flat face: a box's,
//! a polytope's, an unpadded hull's or a padded polygon's. Those pairs' Jacobian went through
//! the general feature solve (`crate::solver::sensitivity`, ~7 000 instructions beyond
//! proximity).
//!
//! The face of `B` (origin `r_b`) has the outward unit normal `a` (turning with `B`:
//! `da = ω_b × a`); scaled by α about `r_b` it stays parallel to itself. The ellipsoid `E`
//! (origin `r_e`) scaled by α touches it at its support point in the direction `−a`,
//! `x* = r_e + α p` with `p = ∇h_E(−a)` (relative to `r_e`, unit scale). `p` turns with `E` and
//! moves with the direction by the support function's Hessian `H` (world, at `−a`):
//! `dp = ω_e × p + H(ω_e × a − ω_b × a)`, so
//!
//! ```text
//! dx* = dr_e + p dα* + α(ω_e × p + H(ω_e × a) − H(ω_b × a))
//! ```
//!
//! with `dα*` the envelope theorem's gradient (the α row). Which face touches is read from the
//! optimal normal as the general solve reads it (support pieces tied within its tolerance);
//! within a factor 100 of that decision the answer is `None` and the general solve decides.
//! Where the feature is an unpadded edge, `super::edge_jacobian` gives the answer.

use super::context::Proximity;
use super::edge_jacobian::{edge_jacobian, support_hessian};
use super::vertex_feature::{block_finite, decide, flat_feature, Flat, TIE};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// The feature of `B` an ellipsoid touches (world).
pub(super) enum Touch {
    /// A face: its outward unit normal.
    Face(Vec3),
    /// An edge (unpadded): its unit direction.
    Edge(Vec3),
}

/// The face or unpadded edge `shape` touches by at its outward unit normal `out`; `None` for
/// other features or shapes, or a decision within the margin.
pub(super) fn touching_feature(shape: &Shape, pose: &Pose, out: &Vec3, tau: Real) -> Option<Touch> {
    let rot = pose.rotation();
    let m = rot.tr_mul(out);
    if let Some(e) = shape.centred_box() {
        // Vertices flipped along axis i tie when 2eᵢ|mᵢ| is within the tolerance: a face
        // where two axes tie, an edge (along that axis) where one does.
        let mut tied = [false; 3];
        for i in 0..3 {
            tied[i] = decide(2.0 * e[i] * m[i].abs(), tau)?;
        }
        return match tied {
            [true, true, false] => Some(Touch::Face(rot.column(2) * m[2].signum())),
            [true, false, true] => Some(Touch::Face(rot.column(1) * m[1].signum())),
            [false, true, true] => Some(Touch::Face(rot.column(0) * m[0].signum())),
            [true, false, false] => Some(Touch::Edge(rot.column(0).into_owned())),
            [false, true, false] => Some(Touch::Edge(rot.column(1).into_owned())),
            [false, false, true] => Some(Touch::Edge(rot.column(2).into_owned())),
            _ => None,
        };
    }
    match flat_feature(shape, &m, tau)? {
        (Flat::Face(a), _) => Some(Touch::Face(rot * a)),
        (Flat::Edge(t), 0.0) => Some(Touch::Edge(rot * t)),
        _ => None,
    }
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` into `j` (every entry written) where an ellipsoid touches a
/// face of a box, a polytope, an unpadded hull or a padded polygon, from the geometric answer
/// and its gradient `g` (the α row); `None` (with `j` holding garbage) for other pairs or
/// features, an undecided feature or a non-finite answer.
pub(crate) fn face_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    let kinds = shapes.map(|s| s.solver_kind());
    let (e, b) = match kinds {
        [ShapeKind::Ellipsoid, ShapeKind::Ellipsoid] => return None,
        [ShapeKind::Ellipsoid, _] => (0, 1),
        [_, ShapeKind::Ellipsoid] => (1, 0),
        _ => return None,
    };
    if !matches!(
        kinds[b],
        ShapeKind::Polytope | ShapeKind::Polygon | ShapeKind::ConvexHull
    ) {
        return None;
    }
    let alpha = prox.alpha;
    let norm = dalpha_dd.norm();
    if !(alpha > 0.0 && alpha.is_finite() && norm > 0.0 && norm.is_finite()) {
        return None;
    }
    // ∂α*/∂r₂ points from shape 1 to shape 2: shape 1's outward normal.
    let nu = dalpha_dd / norm;
    let out = if b == 0 { nu } else { -nu };
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let a = match touching_feature(shapes[b], poses[b], &out, TIE * ell)? {
        Touch::Face(a) => a,
        Touch::Edge(t) => {
            return edge_jacobian(prox, g, [e, b], shapes, poses, axes, -out, t, j);
        }
    };
    let hess = support_hessian(shapes[e], poses[e], &-a)?;
    let re = poses[e].position();
    let p = [prox.contact1, prox.contact2][e] - re;
    let (ce, cb) = (7 * e, 7 * b);
    for c in 0..3 {
        for i in 0..3 {
            let id = if i == c { 1.0 } else { 0.0 };
            j[i][ce + c] = id + p[i] * g[ce + c];
            j[i][cb + c] = p[i] * g[cb + c];
        }
    }
    for (k, omega) in axes[e].iter().enumerate() {
        let dx = (omega.cross(&p) + hess * omega.cross(&a)) * alpha + p * g[ce + 3 + k];
        for i in 0..3 {
            j[i][ce + 3 + k] = dx[i];
        }
    }
    for (k, omega) in axes[b].iter().enumerate() {
        let dx = p * g[cb + 3 + k] - hess * omega.cross(&a) * alpha;
        for i in 0..3 {
            j[i][cb + 3 + k] = dx[i];
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}
