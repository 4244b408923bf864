//! The Jacobian of `(x*, α*)` in closed form where an ellipsoid touches an edge of a box, a
//! polytope or an unpadded hull. Those poses' Jacobian went through the general feature solve
//! (`crate::solver::sensitivity`, ~7 000 instructions beyond proximity): about half of an
//! ellipsoid's poses against a box.
//!
//! The edge of `B` (origin `r_b`), scaled by α about `r_b`, is the line `r_b + α(c + s t)`
//! (`c` a point of it and `t` its unit direction, world, both turning with `B`:
//! `dc = ω_b × c`, `dt = ω_b × t`). The ellipsoid `E` (origin `r_e`) scaled by α touches it at
//! its support point `x* = r_e + α p`, `p = ∇h_E(ν)` in the direction `ν` (E's outward unit
//! normal there, perpendicular to the edge), so with `w = c + s t` (`x* = r_b + α w`),
//! `r_e − r_b = α(w − p)` and `ν·t = 0`. `p` moves by the support function's Hessian `H`
//! (world, at `ν`, `Hν = 0`): `dp = ω_e × p + H(dν − ω_e × ν)`. Differentiating
//! `(r_e − r_b)/α + p − w = 0`,
//!
//! ```text
//! H dν − ds t = −(dr_e − dr_b)/α + (w − p) dα*/α − ω_e × p + H(ω_e × ν) + ω_b × w
//! ```
//!
//! whose component along `ν` is the envelope theorem's `dα*` (the gradient, the α row). In
//! the basis `t̂ = b × ν`, `b = ν × t/‖ν × t‖` of the plane `⊥ ν`, `dν = τ t̂ + β b` with
//! `τ = −ν·(ω_b × t)` (the edge turning keeps `ν ⊥ t`), and the equation's component along
//! `b` gives `β = (b·rhs − τ b·Ht̂)/(b·Hb)`; then
//!
//! ```text
//! dx* = dr_e + p dα* + α(ω_e × p − H(ω_e × ν) + τ Ht̂ + β Hb).
//! ```
//!
//! The edge is read from the optimal normal as the general solve reads it
//! (`super::face_jacobian::touching_feature`, its tolerances with a factor 100 of margin).

use super::context::Proximity;
use super::vertex_feature::block_finite;
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::Shape;

/// An ellipsoid's support-function Hessian (world, unit scale) at the unit direction `nu`
/// (world): `h(m) = √(mᵀP⁻¹m)`, `g = P⁻¹m`, `∇²h = (P⁻¹ − ggᵀ/h²)/h` in the body frame,
/// rotated; `None` for another shape.
pub(super) fn support_hessian(shape: &Shape, pose: &Pose, nu: &Vec3) -> Option<Mat3> {
    let rot = pose.rotation();
    let p_inv = shape.ellipsoid_inverse()?;
    let m = rot.tr_mul(nu);
    let gm = p_inv * m;
    let h = m.dot(&gm).sqrt();
    // g/h first: ggᵀ (∝ size⁴) underflows for semi-axes below ~1e-77, where (g/h)(g/h)ᵀ
    // (∝ size², as P⁻¹) does not.
    let u = gm / h;
    Some(rot * ((p_inv - u * u.transpose()) / h) * rot.transpose())
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` into `j` (every entry written) where the ellipsoid
/// `shapes[e]` touches an edge of direction `t` (unit, world) of `shapes[b]` with its outward
/// unit normal `nu`, from the geometric answer and its gradient `g` (the α row); `None` (with
/// `j` holding garbage) for a degenerate basis or a non-finite answer.
#[allow(clippy::too_many_arguments)]
pub(super) fn edge_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    [e, b]: [usize; 2],
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    nu: Vec3,
    t: Vec3,
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    let alpha = prox.alpha;
    let hess = support_hessian(shapes[e], poses[e], &nu)?;
    let contacts = [prox.contact1, prox.contact2];
    let p = contacts[e] - poses[e].position();
    let w = contacts[b] - poses[b].position();
    let bn = nu.cross(&t);
    let bl = bn.norm();
    if !(bl > 0.5) {
        return None;
    }
    let bv = bn / bl;
    let tt = bv.cross(&nu);
    let (hb, ht) = (hess * bv, hess * tt);
    let kappa = bv.dot(&hb);
    if !(kappa > 0.0) {
        return None;
    }
    let inv_k = 1.0 / kappa;
    let inv_a = 1.0 / alpha;
    // b·rhs's coefficient of dα*, and αHb/κ (the x* change per unit of b·rhs).
    let q = bv.dot(&(w - p)) * inv_a;
    let hbk = hb * (alpha * inv_k);
    let (ce, cb) = (7 * e, 7 * b);
    for c in 0..3 {
        let (ge, gb) = (g[ce + c], g[cb + c]);
        let de = p * ge + hbk * (q * ge - bv[c] * inv_a);
        let db = p * gb + hbk * (q * gb + bv[c] * inv_a);
        for i in 0..3 {
            j[i][ce + c] = de[i] + if i == c { 1.0 } else { 0.0 };
            j[i][cb + c] = db[i];
        }
    }
    for (k, omega) in axes[e].iter().enumerate() {
        let ge = g[ce + 3 + k];
        let (wp, wn) = (omega.cross(&p), omega.cross(&nu));
        let rhs = q * ge - bv.dot(&wp) + hb.dot(&wn);
        let dx = p * ge + (wp - hess * wn) * alpha + hbk * rhs;
        for i in 0..3 {
            j[i][ce + 3 + k] = dx[i];
        }
    }
    let hbt = hb.dot(&tt);
    for (k, omega) in axes[b].iter().enumerate() {
        let gb = g[cb + 3 + k];
        let tau = -nu.dot(&omega.cross(&t));
        let rhs = q * gb + bv.dot(&omega.cross(&w)) - tau * hbt;
        let dx = p * gb + ht * (alpha * tau) + hbk * rhs;
        for i in 0..3 {
            j[i][cb + 3 + k] = dx[i];
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}
