//! The Jacobian of `(x*, α*)` in closed form for a sphere against a box, a capsule, a
//! cylinder, a cone, an ellipsoid, a polytope, an unpadded hull or a padded polygon, where the
//! general feature solve (`crate::solver::sensitivity`) costs several thousand instructions
//! beyond proximity (`docs/derivatives.md`). [`projection_jacobian`] also serves
//! `super::ball_jacobian` (a ball off its shape's origin, of radius zero at a vertex).
//!
//! With the sphere `s` (radius `R`, centre `r_s`) and the other shape `B` (origin `r_b`,
//! attitude `Q`), the scaled shapes touch where `B` scaled by α* about `r_b` is at distance
//! `α*R` from `r_s`: with `y = (r_s − r_b)/α*` and `w` the point of `Q·B` closest to `y`
//! (`w = p_b − r_b`, `p_b` the contact point on `B`), `‖y − w‖ = R` and `x* = r_b + α*w`.
//! `w = Q P(Qᵀy)` with `P` the closest-point projection onto the body shape, whose derivative
//! (world frame) is `M = (R·I + H)⁻¹H` for the support function's Hessian `H` at the unit
//! normal `n̂ = (y − w)/R`: `0` at a vertex or an apex, `ttᵀ` on an edge of direction `t`,
//! `I − n̂n̂ᵀ` on a face, and `ttᵀ + k ccᵀ` (`k = ρ/(R + ρ)`, `ρ` the radius of curvature
//! across the line `t`) on the side of a capsule, a cylinder or a cone; `k ccᵀ` on a rim
//! (`c` its tangent, `ρ` the rim's radius over `‖m_yz‖`, `m` the body normal); `k(I − n̂n̂ᵀ)` on
//! a capsule's cap; on an ellipsoid (`h(m) = √(mᵀP⁻¹m)`, `g = P⁻¹m`) the body Hessian
//! `(P⁻¹ − ggᵀ/h²)/h` at the body normal `m`, rotated, and `M` by a 3×3 inverse. A rotation `ω` of `B` moves `w` by `ω × w + M(dy − ω × y)`, so
//!
//! ```text
//! dx* = dr_b + α* dw + w dα* = M dr_s + (I − M) dr_b + α*(ω × w − M(ω × y)) + (w − My) dα*
//! ```
//!
//! with `dα*` the gradient the envelope theorem gave (its row of the Jacobian). The feature is
//! read from the optimal normal as the general solve reads it (the support pieces tied within
//! its tolerance, its disc test); close to either decision (within a factor 100) the answer is
//! `None` and the general solve decides.

use super::context::Proximity;
use super::derivatives::rotation_axes;
use super::vertex_feature::{block_finite, decide, flat_feature, Flat, DISC, TIE};
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// `uuᵀ·k`.
fn outer(u: &Vec3, k: Real) -> Mat3 {
    u * u.transpose() * k
}

/// `‖(v_y, v_z)‖`, scaled by the larger component first (any magnitude, as `hypot`, at a
/// fraction of its cost).
#[inline]
fn yz_norm(v: &Vec3) -> Real {
    let big = v.y.abs().max(v.z.abs());
    if !(big > 0.0 && big < Real::MAX) {
        return v.y.hypot(v.z);
    }
    let inv = 1.0 / big;
    let (y, z) = (v.y * inv, v.z * inv);
    big * (y * y + z * z).sqrt()
}

/// `M` (world) for `B` touched by a sphere of radius `radius` at the unit normal `n` (outward
/// from `B`) and the contact point `w` (world, relative to `B`'s origin), ties decided within
/// `TIE·ℓ` (`ℓ` the pair's length scale, as the general solve); `None` for other shapes or
/// undecided features.
pub(super) fn projection_jacobian(
    b: &Shape,
    pose: &Pose,
    n: &Vec3,
    w: &Vec3,
    radius: Real,
    ell: Real,
) -> Option<Mat3> {
    let rot = pose.rotation();
    let m = rot.tr_mul(n);
    let tau = TIE * ell;
    let axis = rot.column(0).into_owned();
    // A line of direction `t` with radius of curvature `rho` across it (∞ along it).
    let side = |t: Vec3, rho: Real| {
        let c = t.cross(n).normalize();
        outer(&t, 1.0) + outer(&c, rho / (radius + rho))
    };
    // A circle of radius `rho` about the axis, seen at the normal: radius of curvature
    // `rho/‖m_yz‖` along its tangent `c`, taken from the contact point's azimuth (the normal's
    // is ill-conditioned where it is close to the axis: up to 1e-12 off).
    // `‖m_yz‖` without `hypot` (~50 instructions each): away from the disc (decided first,
    // `1 − |mₓ| ≥ 1e-11`) its square is at least 2e-11.
    let rim = |rho: Real| {
        let p = rot.tr_mul(w);
        let s = (m.y * m.y + m.z * m.z).sqrt();
        let c = rot * (Vec3::new(0.0, -p.z, p.y) / yz_norm(&p));
        let h = rho / s;
        outer(&c, h / (radius + h))
    };
    let face = |a: Vec3| Mat3::identity() - outer(&a, 1.0);
    match b.solver_kind() {
        ShapeKind::Polytope if b.centred_box().is_none() => {
            flat_projection(b, rot, &m, n, radius, tau)
        }
        ShapeKind::Polygon | ShapeKind::ConvexHull => flat_projection(b, rot, &m, n, radius, tau),
        ShapeKind::Polytope => {
            let e = b.centred_box()?;
            let mut zero = [false; 3];
            for i in 0..3 {
                zero[i] = decide(2.0 * e[i] * m[i].abs(), tau)?;
            }
            match zero.iter().filter(|z| **z).count() {
                0 => Some(Mat3::zeros()),
                1 => {
                    let i = zero.iter().position(|z| *z)?;
                    Some(outer(&rot.column(i).into_owned(), 1.0))
                }
                2 => {
                    let k = zero.iter().position(|z| !*z)?;
                    Some(face(rot.column(k).into_owned()))
                }
                _ => None,
            }
        }
        ShapeKind::Capsule => {
            let (h, rho) = b.rounded_segment()?;
            if decide(2.0 * h * m.x.abs(), tau)? {
                Some(side(axis, rho))
            } else {
                let k = rho / (radius + rho);
                Some((Mat3::identity() - outer(n, 1.0)) * k)
            }
        }
        ShapeKind::Cylinder => {
            let (rho, h) = b.cylinder_dims()?;
            if decide(1.0 - m.x.abs(), DISC)? {
                return Some(face(axis));
            }
            if decide(2.0 * h * m.x.abs(), tau)? {
                Some(side(axis, rho))
            } else {
                Some(rim(rho))
            }
        }
        ShapeKind::Cone => {
            let (section, _) = b.revolution_section()?;
            let (apex_x, (base_x, rho)) = (section[0].0, section[2]);
            if decide(1.0 - m.x, DISC)? {
                return Some(face(axis));
            }
            // The apex's support value against the rim's.
            let s = (m.y * m.y + m.z * m.z).sqrt();
            let gap = base_x * m.x + rho * s - apex_x * m.x;
            if decide(gap.abs(), tau)? {
                // A generator: curvature radius ρ_p/‖m_yz‖ across it at the contact point,
                // ρ_p its distance from the axis.
                let c = axis.cross(n) / s;
                let g = c.cross(n);
                let hc = yz_norm(&rot.tr_mul(w)) / s;
                Some(outer(&g, 1.0) + outer(&c, hc / (radius + hc)))
            } else if gap < 0.0 {
                Some(Mat3::zeros())
            } else {
                Some(rim(rho))
            }
        }
        // Touched by a point (a vertex: `R = 0`), `(R·I + H)⁻¹H` tends to the projection
        // onto the tangent plane (H's range).
        ShapeKind::Ellipsoid if radius == 0.0 => Some(face(*n)),
        ShapeKind::Ellipsoid => {
            // h(m) = √(mᵀP⁻¹m): with g = P⁻¹m, ∇²h = (P⁻¹ − ggᵀ/h²)/h (body frame).
            let p_inv = b.ellipsoid_inverse()?;
            let g = p_inv * m;
            let h = m.dot(&g).sqrt();
            let hess = rot * ((p_inv - g * g.transpose() / (h * h)) / h) * rot.transpose();
            Some((Mat3::identity() * radius + hess).try_inverse()? * hess)
        }
        _ => None,
    }
}

/// [`projection_jacobian`] for a polytope other than a centred box, a convex hull or a padded
/// polygon (`rot` its attitude, `m` the body normal): zero at a vertex (`k(I − n̂n̂ᵀ)` at a
/// padded one, `k = ρ/(R + ρ)`), `ttᵀ + k ccᵀ` on an edge of direction `t`, `I − aaᵀ` on a
/// face of normal `a`; `None` where the feature is undecided.
fn flat_projection(
    b: &Shape,
    rot: &crate::math::Mat3,
    m: &Vec3,
    n: &Vec3,
    radius: Real,
    tau: Real,
) -> Option<Mat3> {
    let (flat, rho) = flat_feature(b, m, tau)?;
    let k = if rho > 0.0 { rho / (radius + rho) } else { 0.0 };
    Some(match flat {
        Flat::Vertex(_) => (Mat3::identity() - outer(n, 1.0)) * k,
        Flat::Edge(t) => {
            let t = rot * t;
            let c = t.cross(n).normalize();
            outer(&t, 1.0) + outer(&c, k)
        }
        Flat::Face(a) => Mat3::identity() - outer(&(rot * a), 1.0),
    })
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` for a sphere against a box, a capsule, a cylinder, a cone,
/// an ellipsoid, a polytope, an unpadded hull or a padded polygon (either order) into `j`
/// (every entry written), from the geometric answer and its gradient `g` (the α row); `None`
/// (with `j` holding garbage) for other pairs, undecided features or a non-finite answer.
/// The other shape's rotation axes are formed here, only once its feature is decided (the
/// sphere's columns are zero: it has none to form).
pub(crate) fn sphere_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    let round = shapes.map(|s| s.solver_kind() == ShapeKind::Sphere);
    let (s, b) = match round {
        [true, false] => (0, 1),
        [false, true] => (1, 0),
        _ => return None,
    };
    let (_, radius) = shapes[s].rounded_segment()?;
    let alpha = prox.alpha;
    if !(alpha > 0.0 && alpha.is_finite()) {
        return None;
    }
    let (rs, rb) = (poses[s].position(), poses[b].position());
    let y = (rs - rb) / alpha;
    let w = [prox.contact1, prox.contact2][b] - rb;
    // ∂α*/∂r₂ points from shape 1 to shape 2; B's outward normal points to the sphere.
    let sign = if s == 0 { -1.0 } else { 1.0 };
    let n = dalpha_dd * (sign / dalpha_dd.norm());
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let m = projection_jacobian(shapes[b], poses[b], &n, &w, radius, ell)?;
    let v = w - m * y;
    let axes = rotation_axes(poses[b]);
    let parts = Parts {
        m: &m,
        v: &v,
        w: &w,
        y: &y,
        alpha,
        g,
        axes: &axes,
    };
    // The columns at constant offsets (each order its own copy: no bounds checks, unrolled).
    if s == 0 {
        fill::<0, 7>(&parts, j);
    } else {
        fill::<7, 0>(&parts, j);
    }
    block_finite(j).then_some(())
}

/// What [`fill`] writes the Jacobian from: `M`, `v = w − My`, `w`, `y`, α*, the gradient and
/// `B`'s rotation axes.
struct Parts<'a> {
    m: &'a Mat3,
    v: &'a Vec3,
    w: &'a Vec3,
    y: &'a Vec3,
    alpha: Real,
    g: &'a [Real; 14],
    axes: &'a [Vec3; 4],
}

/// The Jacobian's every entry, the sphere's columns from `CS`, `B`'s from `CB`:
/// `M + v gᵀ` (sphere's position), `I − M + v gᵀ` (`B`'s), zero (the sphere's rotation),
/// `α*(ω × w − M(ω × y)) + v g` (`B`'s rotation), the gradient as the α row.
#[inline(always)]
fn fill<const CS: usize, const CB: usize>(p: &Parts<'_>, j: &mut [[Real; 14]; 4]) {
    let (m, v, g) = (p.m, p.v, p.g);
    for row in j.iter_mut().take(3) {
        row[CS + 3..CS + 7].fill(0.0);
    }
    for c in 0..3 {
        for i in 0..3 {
            let id = if i == c { 1.0 } else { 0.0 };
            j[i][CS + c] = m[(i, c)] + v[i] * g[CS + c];
            j[i][CB + c] = id - m[(i, c)] + v[i] * g[CB + c];
        }
    }
    for (k, omega) in p.axes.iter().enumerate() {
        let dx = (omega.cross(p.w) - m * omega.cross(p.y)) * p.alpha + v * g[CB + 3 + k];
        for i in 0..3 {
            j[i][CB + 3 + k] = dx[i];
        }
    }
    j[3] = *g;
}
