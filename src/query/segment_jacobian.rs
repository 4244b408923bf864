//! The Jacobian of `(x*, α*)` in closed form where both shapes touch by a segment padded by a
//! radius, the two segments crossing (not parallel): a box's edge (radius 0), a capsule's
//! side or a cylinder's side (its axis padded by its radius, as a capsule's side is where the
//! normal is perpendicular to the axis). Box–box edge contacts cost ~7 300 instructions in
//! the polytopes' closed form, the others ~7 000 in the general feature solve.
//!
//! Shape `i` (origin `rᵢ`) touches by the segment of direction `tᵢ` (unit, world) through the
//! point `pᵢ` (relative to `rᵢ`, unit scale), padded by `ρᵢ`; scaled by α about `rᵢ`. With
//! `n = t₁ × t₂`, the unit normal `n̂ = σn/‖n‖` (`σ = ±1`, from shape 1 to shape 2) and
//! `ρ = ρ₁ + ρ₂`, the scaled features touch where
//!
//! ```text
//!     F = r₁ − r₂ + α(p₁ − p₂ + ρn̂) = 0,     x* = r₁ + α(p₁ + ρ₁n̂)
//! ```
//!
//! with `p₁` free along `t₁` and `p₂` along `t₂` (`dpᵢ = ωᵢ × pᵢ + dsᵢ tᵢ`). Dotting `dF = 0`
//! with `k = (t₂ × n)/‖n‖²` (`k·t₁ = 1`, `k·t₂ = k·n = 0`) gives `α ds₁ = −k·(b + dα e)`, with
//! `e = (r₂ − r₁)/α` and `b = dr₁ − dr₂ + α(ω₁ × p₁ − ω₂ × p₂) + αρ dn̂`, and so, with
//! `L = I − t₁kᵀ`, `q₁ = p₁ + ρ₁n̂` and `v = q₁ − t₁(k·e)`:
//!
//! ```text
//!     r₁ along e:   L e + v dα               r₂ along e:   (I − L) e + v dα
//!     q₁ along ω:   v dα + α L(ω × p₁) + α(ρ₁δ − ρ t₁(k·δ)),   δ = σP((ω × t₁) × t₂)/‖n‖
//!     q₂ along ω:   v dα + α t₁ k·(ω × p₂) + α(ρ₁δ − ρ t₁(k·δ)),   δ = σP(t₁ × (ω × t₂))/‖n‖
//! ```
//!
//! (`P = I − n̂n̂ᵀ`), `dα` the envelope theorem's gradient (the α row). Which feature touches is
//! read from the optimal normal as the general solve reads it (support pieces tied within its
//! tolerance, its disc test); within a factor 100 of a decision, or segments closer to
//! parallel than 100 times the general solve's sine, the answer is `None`.

use super::context::Proximity;
use super::vertex_feature::{block_finite, decide, flat_feature, Flat, DISC, MARGIN, TIE};
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::sensitivity::PARALLEL_SIN;

/// The segment `shape` touches by at its outward unit normal `out` (world): its direction
/// (world, unit) and its padding; `None` for other shapes and features, or a decision within
/// the margin. `tau`: the tie tolerance (`TIE·ℓ`).
fn touching_segment(shape: &Shape, pose: &Pose, out: &Vec3, tau: Real) -> Option<(Vec3, Real)> {
    let rot = pose.rotation();
    let m = rot.tr_mul(out);
    let axis = || rot.column(0).into_owned();
    match shape.solver_kind() {
        ShapeKind::Polytope | ShapeKind::Polygon | ShapeKind::ConvexHull
            if shape.centred_box().is_none() =>
        {
            match flat_feature(shape, &m, tau)? {
                (Flat::Edge(t), r) => Some((rot * t, r)),
                _ => None,
            }
        }
        ShapeKind::Polytope => {
            let e = shape.centred_box()?;
            // An edge: vertices flipped along exactly one axis tie (2eᵢ|mᵢ|).
            let mut edge = None;
            for i in 0..3 {
                if decide(2.0 * e[i] * m[i].abs(), tau)? {
                    if edge.is_some() {
                        return None;
                    }
                    edge = Some(i);
                }
            }
            Some((rot.column(edge?).into_owned(), 0.0))
        }
        ShapeKind::Capsule => {
            let (h, rho) = shape.rounded_segment()?;
            decide(2.0 * h * m.x.abs(), tau)?.then(|| (axis(), rho))
        }
        ShapeKind::Cylinder => {
            let (rho, h) = shape.cylinder_dims()?;
            if decide(1.0 - m.x.abs(), DISC)? {
                return None;
            }
            decide(2.0 * h * m.x.abs(), tau)?.then(|| (axis(), rho))
        }
        _ => None,
    }
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` into `j` (every entry written) where a box's edge, a
/// capsule's side or a cylinder's side crosses another, from the geometric answer and its
/// gradient `g` (the α row); `None` (with `j` holding garbage) for other pairs or features,
/// undecided features, nearly parallel segments or a non-finite answer.
pub(crate) fn segment_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    let alpha = prox.alpha;
    let norm = dalpha_dd.norm();
    if !(alpha > 0.0 && alpha.is_finite() && norm > 0.0 && norm.is_finite()) {
        return None;
    }
    // ∂α*/∂r₂ points from shape 1 to shape 2: shape 1's outward normal.
    let nu = dalpha_dd / norm;
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let tau = TIE * ell;
    let (t1, rho1) = touching_segment(shapes[0], poses[0], &nu, tau)?;
    let (t2, rho2) = touching_segment(shapes[1], poses[1], &(-nu), tau)?;
    let n = t1.cross(&t2);
    let nn = n.norm_squared();
    let len = nn.sqrt();
    if !(len > MARGIN * PARALLEL_SIN) {
        return None;
    }
    let sigma = if nu.dot(&n) >= 0.0 { 1.0 } else { -1.0 };
    let (r1, r2) = (poses[0].position(), poses[1].position());
    let q1 = prox.contact1 - r1;
    let p1 = q1 - nu * rho1;
    let p2 = prox.contact2 - r2 + nu * rho2;
    let e = (r2 - r1) / alpha;
    let k = t2.cross(&n) / nn;
    let rho = rho1 + rho2;
    let l = Mat3::identity() - t1 * k.transpose();
    let v = q1 - t1 * k.dot(&e);
    let proj = Mat3::identity() - nu * nu.transpose();
    // The padding's term α(ρ₁δ − ρ t₁(k·δ)) for the normal's change `dn` (δ = σP dn/‖n‖).
    let pad = |dn: Vec3| {
        let delta = proj * dn * (sigma / len);
        (delta * rho1 - t1 * (rho * k.dot(&delta))) * alpha
    };
    for c in 0..3 {
        for i in 0..3 {
            let id = if i == c { 1.0 } else { 0.0 };
            j[i][c] = l[(i, c)] + v[i] * g[c];
            j[i][7 + c] = id - l[(i, c)] + v[i] * g[7 + c];
        }
    }
    for (kk, omega) in axes[0].iter().enumerate() {
        let mut dx = l * omega.cross(&p1) * alpha + v * g[3 + kk];
        if rho != 0.0 {
            dx += pad(omega.cross(&t1).cross(&t2));
        }
        for i in 0..3 {
            j[i][3 + kk] = dx[i];
        }
    }
    for (kk, omega) in axes[1].iter().enumerate() {
        let mut dx = t1 * (k.dot(&omega.cross(&p2)) * alpha) + v * g[10 + kk];
        if rho != 0.0 {
            dx += pad(t1.cross(&omega.cross(&t2)));
        }
        for i in 0..3 {
            j[i][10 + kk] = dx[i];
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}
