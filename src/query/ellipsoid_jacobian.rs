//! The Jacobian of `(x*, α*)` in closed form for two ellipsoids, where the general feature solve
//! (`crate::solver::sensitivity`: both features identified, each piece evaluated with its
//! Hessian, a reduced system factorised and solved for four right-hand sides) cost about 6 500
//! instructions beyond a proximity of ~2 900 (`docs/derivatives-cost.md`).
//!
//! Both shapes are smooth and strictly convex, so each touches by one point and the contact
//! normal is the only unknown: with the unit normal `n` (from shape 1 towards shape 2), shape
//! `i`'s world support function `hᵢ(m) = √(mᵀWᵢm)` (`Wᵢ = RᵢPᵢ⁻¹Rᵢᵀ`), its support point
//! `gᵢ(m) = Wᵢm/hᵢ(m)` (relative to `rᵢ`) and Hessian `Hᵢ(m) = (Wᵢ − gᵢgᵢᵀ)/hᵢ(m)` (even in
//! `m`, and `Hᵢn = 0`), the scaled shapes touch where
//!
//! ```text
//!     d = r₂ − r₁ = α* y,   y = g₁(n) − g₂(−n),   x* = r₁ + α* g₁(n).
//! ```
//!
//! A rotation `ω` of shape 1 moves `g₁(n)` by `δ₁ = ω × g₁ − H₁(ω × n)`, of shape 2 moves
//! `g₂(−n)` by `δ₂ = ω × g₂ + H₂(ω × n)`, and a change `dn ⟂ n` of the normal moves `y` by
//! `Y dn` with `Y = H₁ + H₂`. Differentiating `d = α*y`: along `n`, the envelope theorem's `dα*`
//! (the gradient, the Jacobian's α row); across it, `α*Y dn = P(dd − y dα* − α*(δ₁ − δ₂))`
//! with `P = I − nnᵀ`, solved as `dn = G P(…)/α*` with `G = (Y + τnnᵀ)⁻¹ − nnᵀ/τ`, `τ = tr Y`
//! (`Y` is regular on the tangent plane; `G` is its inverse there and `Gn = 0`). With
//! `N = H₁GP` and `c₀ = g₁ − Ny`,
//!
//! ```text
//!     dx* = dr₁ + g₁dα* + α*(H₁dn + δ₁) = dr₁ + N dd + c₀ dα* + α*(I − N)δ₁ + α*Nδ₂
//! ```
//!
//! so the columns of `r₂` are `N e + c₀ dα*`, those of `r₁` `e − N e + c₀ dα*`, and along a
//! rotation axis `ω` of shape `i`, `Tᵢω + c₀ dα*` with `T₁ = α*(I − N)(H₁[n]× − [g₁]×)` and
//! `T₂ = −α*N([g₂]× + H₂[n]×)` (`δᵢ` written as matrices acting on `ω`).

use super::context::Proximity;
use super::vertex_feature::block_finite;
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` for two ellipsoids into `j` (every entry written), from the
/// geometric answer, its gradient `g` (the α row) and `∂α*/∂d`; `None` (with `j` holding
/// garbage) for other pairs, a singular system or a non-finite answer.
pub(crate) fn ellipsoid_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    if shapes
        .iter()
        .any(|s| s.solver_kind() != ShapeKind::Ellipsoid)
    {
        return None;
    }
    let alpha = prox.alpha;
    let norm = dalpha_dd.norm();
    if !(alpha > 0.0 && alpha.is_finite() && norm > 0.0 && norm.is_finite()) {
        return None;
    }
    // ∂α*/∂r₂ is K's outward normal: from shape 1 towards shape 2.
    let n = dalpha_dd / norm;
    // Shape i's support point at n and its Hessian (the same at −n, where the point is −g).
    let side = |i: usize| -> Option<(Vec3, Mat3)> {
        let rot = poses[i].rotation();
        let w = mul(&mul(rot, shapes[i].ellipsoid_inverse()?), &rot.transpose());
        let wn = w * n;
        let h = n.dot(&wn).sqrt();
        let gi = wn / h;
        Some((gi, (w - gi * gi.transpose()) / h))
    };
    let (g1, h1) = side(0)?;
    let (g2, h2) = side(1)?;
    let g2 = -g2;
    let nn = n * n.transpose();
    // Y's pseudo-inverse on the tangent plane, (Y + τnnᵀ)⁻¹ − nnᵀ/τ for any τ > 0: τ = tr Y
    // (a length, as Y) keeps the matrix inverted as well conditioned at every size as at unit
    // size (τ = 1 lost the tangent block for sizes far from 1: wrong columns at 1e-20, 1e20).
    let y = h1 + h2;
    let tau = y.trace();
    if !(tau > 0.0 && tau.is_finite()) {
        return None;
    }
    let gm = (y + nn * tau).try_inverse()? - nn / tau;
    let nm = mul(&h1, &gm);
    let c0 = g1 - nm * (g1 - g2);
    for col in 0..3 {
        let (ga, gb) = (g[col], g[7 + col]);
        for i in 0..3 {
            let id = if i == col { 1.0 } else { 0.0 };
            let nic = nm[(i, col)];
            j[i][col] = id - nic + c0[i] * ga;
            j[i][7 + col] = nic + c0[i] * gb;
        }
    }
    let t1 = mul(
        &(Mat3::identity() - nm),
        &(mul(&h1, &n.cross_matrix()) - g1.cross_matrix()),
    ) * alpha;
    let t2 = mul(&nm, &(g2.cross_matrix() + mul(&h2, &n.cross_matrix()))) * -alpha;
    for (i, t) in [t1, t2].iter().enumerate() {
        for (k, omega) in axes[i].iter().enumerate() {
            let c = 7 * i + 3 + k;
            let dx = t * omega + c0 * g[c];
            for r in 0..3 {
                j[r][c] = dx[r];
            }
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}

/// `ab`, written out (nalgebra's generic product is a call per product here).
#[inline(always)]
fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let e =
        |i: usize, k: usize| a[(i, 0)] * b[(0, k)] + a[(i, 1)] * b[(1, k)] + a[(i, 2)] * b[(2, k)];
    Mat3::new(
        e(0, 0),
        e(0, 1),
        e(0, 2),
        e(1, 0),
        e(1, 1),
        e(1, 2),
        e(2, 0),
        e(2, 1),
        e(2, 2),
    )
}
