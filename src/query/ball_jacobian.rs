//! The Jacobian of `(x*, α*)` in closed form where one shape touches by a ball fixed in it: a
//! capsule by one of its end caps, a box, a polytope or an unpadded hull by a vertex (a ball of
//! radius zero), a padded polygon by a padded vertex, against a box, a polytope, a hull, a
//! padded polygon, a capsule, a cylinder, a cone or an ellipsoid. Those pairs' Jacobian went
//! through the general feature solve (`crate::solver::sensitivity`, ~7 000 instructions beyond
//! proximity) or the polytopes' closed form.
//!
//! It is [`super::sphere_jacobian`]'s formula with the sphere's centre moved off its shape's
//! origin. Shape `s` (origin `r_s`) touches by the ball of centre `r_s + α u` and radius `αR`
//! (`u` the ball's centre relative to `r_s`, world; both scale with α about `r_s`), against `B`
//! (origin `r_b`) scaled by α about `r_b`: with `y₀ = (r_s − r_b)/α` and `y = y₀ + u`, the point
//! `w` of `B` closest to `y` (relative to `r_b`) is at distance `R` and `x* = r_b + α w`.
//! Differentiating as there (`M` the projection's Jacobian, `super::sphere_jacobian`),
//!
//! ```text
//! dx* = M dr_s + (I − M) dr_b + α(ω_b × w − M(ω_b × y)) + α M(ω_s × u) + (w − M y₀) dα*
//! ```
//!
//! with `dα*` the gradient (the Jacobian's α row). With `R = 0` (a vertex) `M` is the limit of
//! the same expressions (the tangent plane's projection on a smooth side, a line's on an edge,
//! zero at a vertex). Which cap or vertex touches, and `B`'s feature, are read from the optimal
//! normal as the general solve reads them (support pieces tied within its tolerance, its disc
//! test); within a factor 100 of a decision on either shape the answer is `None` and the
//! general solve decides.

use super::context::Proximity;
use super::sphere_jacobian::projection_jacobian;
use super::vertex_feature::{block_finite, decide, flat_feature, Flat, TIE};
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// The ball shape `shape` touches by at its outward unit normal `n` (world): its centre
/// relative to the shape's origin (world, unit scale) and its radius; `None` where the shape
/// is not a capsule or made of vertices, touches by more than one ball (a capsule's side, an
/// edge, a face), or the decision is within the margin. `tau`: the tie tolerance (`TIE·ℓ`).
fn touching_ball(shape: &Shape, pose: &Pose, n: &Vec3, tau: Real) -> Option<(Vec3, Real)> {
    let rot = pose.rotation();
    let m = rot.tr_mul(n);
    match shape.solver_kind() {
        ShapeKind::Capsule => {
            let (h, rho) = shape.rounded_segment()?;
            // The two caps' support values differ by 2h|mₓ| (the general solve's tie test).
            if decide(2.0 * h * m.x.abs(), tau)? {
                return None;
            }
            let end = if m.x > 0.0 { h } else { -h };
            Some((rot.column(0) * end, rho))
        }
        ShapeKind::Polytope if shape.centred_box().is_none() => flat_ball(shape, rot, &m, tau),
        ShapeKind::Polygon | ShapeKind::ConvexHull => flat_ball(shape, rot, &m, tau),
        ShapeKind::Polytope => {
            let e = shape.centred_box()?;
            let mut corner = Vec3::zeros();
            for i in 0..3 {
                // Vertices flipped along axis i are 2eᵢ|mᵢ| below the support value.
                if decide(2.0 * e[i] * m[i].abs(), tau)? {
                    return None;
                }
                corner[i] = if m[i] > 0.0 { e[i] } else { -e[i] };
            }
            Some((rot * corner, 0.0))
        }
        _ => None,
    }
}

/// [`touching_ball`] for a polytope other than a centred box, a convex hull or a padded
/// polygon: its vertex (padded by its radius) where one alone ties.
fn flat_ball(shape: &Shape, rot: &Mat3, m: &Vec3, tau: Real) -> Option<(Vec3, Real)> {
    match flat_feature(shape, m, tau)? {
        (Flat::Vertex(p), r) => Some((rot * p, r)),
        _ => None,
    }
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` into `j` (every entry written) where a capsule touches by an
/// end cap, or a shape made of vertices by one vertex, against a shape other than a sphere or
/// a half-space (see the module's documentation), from the geometric answer and its gradient
/// `g` (the α row); `None` (with `j` holding garbage) for other pairs or features, undecided
/// features or a non-finite answer. Two capsules and sphere pairs have their own closed forms and are not taken here.
pub(crate) fn ball_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    let kinds = shapes.map(|s| s.solver_kind());
    let other = |k: ShapeKind| {
        matches!(
            k,
            ShapeKind::Polytope
                | ShapeKind::Capsule
                | ShapeKind::Cylinder
                | ShapeKind::Cone
                | ShapeKind::Polygon
                | ShapeKind::ConvexHull
        )
    };
    let target = |k: ShapeKind| other(k) || k == ShapeKind::Ellipsoid;
    if !(other(kinds[0]) && target(kinds[1]) || other(kinds[1]) && target(kinds[0]))
        || kinds == [ShapeKind::Capsule, ShapeKind::Capsule]
    {
        return None;
    }
    let alpha = prox.alpha;
    let norm = dalpha_dd.norm();
    if !(alpha > 0.0 && alpha.is_finite() && norm > 0.0 && norm.is_finite()) {
        return None;
    }
    // ∂α*/∂r₂ points from shape 1 to shape 2: shape 1's outward normal.
    let nu = dalpha_dd / norm;
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let tau = TIE * ell;
    // A capsule's cap first (either shape), then a vertex.
    let mut ball = None;
    for pass in 0..2 {
        for s in 0..2 {
            let wanted = if pass == 0 {
                kinds[s] == ShapeKind::Capsule
            } else {
                matches!(
                    kinds[s],
                    ShapeKind::Polytope | ShapeKind::Polygon | ShapeKind::ConvexHull
                )
            };
            if ball.is_some() || !wanted {
                continue;
            }
            let out = if s == 0 { nu } else { -nu };
            if let Some((u, radius)) = touching_ball(shapes[s], poses[s], &out, tau) {
                ball = Some((s, u, radius));
            }
        }
    }
    let (s, u, radius) = ball?;
    let b = 1 - s;
    let (rs, rb) = (poses[s].position(), poses[b].position());
    let y0 = (rs - rb) / alpha;
    let y = y0 + u;
    let w = [prox.contact1, prox.contact2][b] - rb;
    // B's outward normal points to the ball.
    let n = if s == 0 { -nu } else { nu };
    let m = projection_jacobian(shapes[b], poses[b], &n, &w, radius, ell)?;
    let v = w - m * y0;
    let (cs, cb) = (7 * s, 7 * b);
    for c in 0..3 {
        for i in 0..3 {
            let id = if i == c { 1.0 } else { 0.0 };
            j[i][cs + c] = m[(i, c)] + v[i] * g[cs + c];
            j[i][cb + c] = id - m[(i, c)] + v[i] * g[cb + c];
        }
    }
    for (k, omega) in axes[s].iter().enumerate() {
        let dx = m * omega.cross(&u) * alpha + v * g[cs + 3 + k];
        for i in 0..3 {
            j[i][cs + 3 + k] = dx[i];
        }
    }
    for (k, omega) in axes[b].iter().enumerate() {
        let dx = (omega.cross(&w) - m * omega.cross(&y)) * alpha + v * g[cb + 3 + k];
        for i in 0..3 {
            j[i][cb + 3 + k] = dx[i];
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}
