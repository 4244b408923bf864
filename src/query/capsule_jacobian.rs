//! The Jacobian of `(x*, α*)` in closed form for two capsules, where the general feature solve
//! (`crate::solver::sensitivity`) costs several times a proximity of ~900 instructions (about
//! 7 000 beyond proximity even after its reduced solve, `docs/derivatives.md`).
//!
//! Capsule `i` has its origin `rᵢ`, unit axis `aᵢ = Rᵢe_x`, half length `hᵢ` and radius `ρᵢ`;
//! scaled by α about `rᵢ`, its segment is `rᵢ + α s aᵢ` (`|s| ≤ hᵢ`) and its radius `αρᵢ`. At
//! α* the scaled segments' closest points `p₁ = r₁ + α s a₁`, `p₂ = r₂ + α t a₂` are `αρ` apart
//! (`ρ = ρ₁ + ρ₂`): with `d = r₂ − r₁`,
//!
//! ```text
//!     w = d + α(t a₂ − s a₁),   ‖w‖ = αρ,   ν = w/‖w‖,   x* = r₁ + α(s a₁ + ρ₁ν)
//! ```
//!
//! and, where a segment's parameter is inside its range (the capsule touches by its side:
//! `ν ⟂ aᵢ`), the stationarity `w·a₁ = 0` (or `w·a₂ = 0`); where it is at an end, the parameter
//! is that end (a cap's ball). Differentiating, with `c = a₁·a₂`,
//! `b = dd + dα(t a₂ − s a₁) + α(t da₂ − s da₁)` and `eᵢ = b·aᵢ + w·daᵢ`:
//!
//! ```text
//!     both sides:   ds = (e₁ − c e₂)/(α(1 − c²)),   dt = (c e₁ − e₂)/(α(1 − c²))
//!     one side:     ds = e₁/α  (t at an end)   or   dt = −e₂/α  (s at an end)
//!     dw = b + α(dt a₂ − ds a₁),   dν = (I − ννᵀ)dw/(αρ)
//!     dx* = dr₁ + dα(s a₁ + ρ₁ν) + α(ds a₁ + s da₁ + ρ₁dν)
//! ```
//!
//! with `dα` the envelope theorem's gradient (the Jacobian's α row) and `daᵢ = ωᵢₖ × aᵢ` along
//! a quaternion's rotation axes. Which end or side touches is read from the optimal normal as
//! the general solve reads it (the two caps' balls tie within its tolerance); close to that
//! decision (a factor 100), or two sides closer to parallel than 100 times the general solve's
//! sine, the answer is `None` and the general solve decides.

use super::context::Proximity;
use super::vertex_feature::{block_finite, decide, MARGIN, TIE};
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::sensitivity::PARALLEL_SIN;

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` for two capsules into `j` (every entry written), from the
/// geometric answer, its gradient `g` (the α row) and `∂α*/∂d`; `None` (with `j` holding
/// garbage) for other pairs, undecided features, parallel sides or a non-finite answer.
///
/// The formulas of the module's documentation are linear in the change: with
/// `σ₁ = K₀₀a₁ + K₀₁a₂`, `σ₂ = K₁₀a₁ + K₁₁a₂` (so `ds = σ₁·b + K₀₀ w·da₁ + K₀₁ w·da₂`, and `dt`
/// likewise), `L = κP + u₁σ₁ᵀ + u₂σ₂ᵀ` and `c₀ = lever + L·span`, every column is
///
/// ```text
///     r₂ along e:   L e + c₀ dα            r₁ along e:   e − L e + c₀ dα
///     q₁ along ω:   c₀ dα + αs(z − Lz) + (K₀₀u₁ + K₁₀u₂)(w·z),   z = ω × a₁
///     q₂ along ω:   c₀ dα + αt Lz + (K₀₁u₁ + K₁₁u₂)(w·z),        z = ω × a₂
/// ```
///
/// so `L` and `c₀` are formed once and each column costs a few products (the columns of r₁ and
/// r₂ sum to the identity by construction, and the α row is `g`).
pub(crate) fn capsule_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    if shapes.iter().any(|s| s.solver_kind() != ShapeKind::Capsule) {
        return None;
    }
    let (h1, rho1) = shapes[0].rounded_segment()?;
    let (h2, rho2) = shapes[1].rounded_segment()?;
    let alpha = prox.alpha;
    let norm = dalpha_dd.norm();
    if !(alpha > 0.0 && alpha.is_finite() && norm > 0.0 && norm.is_finite()) {
        return None;
    }
    // ∂α*/∂r₂ is K's outward normal at d/α*: from segment 1 towards segment 2.
    let nu = dalpha_dd / norm;
    let (r1, r2) = (poses[0].position(), poses[1].position());
    let a1 = poses[0].rotation().column(0).into_owned();
    let a2 = poses[1].rotation().column(0).into_owned();
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let tau = TIE * ell;
    let (c1, c2) = (nu.dot(&a1), nu.dot(&a2));
    // A side touches when its two caps' support values tie (`2h|ν·a|` within the tolerance).
    let (side1, side2) = (
        decide(2.0 * h1 * c1.abs(), tau)?,
        decide(2.0 * h2 * c2.abs(), tau)?,
    );
    let c = a1.dot(&a2);
    let sin2 = 1.0 - c * c;
    if side1 && side2 && !(sin2.max(0.0).sqrt() > MARGIN * PARALLEL_SIN) {
        return None;
    }
    // The segments' parameters: an end's exactly, a side's from the contact point.
    let s = if side1 {
        (prox.contact1 - r1 - nu * rho1).dot(&a1)
    } else {
        h1.copysign(c1)
    };
    let t = if side2 {
        (prox.contact2 - r2 + nu * rho2).dot(&a2)
    } else {
        -h2.copysign(c2)
    };
    let rho = rho1 + rho2;
    let w = nu * (alpha * rho);
    let span = a2 * t - a1 * s;
    let lever = a1 * s + nu * rho1;
    // (ds, dt) = K (e₁, e₂) for the parameters on a side (zero at an end).
    let k = match (side1, side2) {
        (true, true) => {
            let f = 1.0 / (alpha * sin2);
            [f, -c * f, c * f, -f]
        }
        (true, false) => [1.0 / alpha, 0.0, 0.0, 0.0],
        (false, true) => [0.0, 0.0, 0.0, -1.0 / alpha],
        (false, false) => [0.0; 4],
    };
    // κP with κ = ρ₁/ρ, P = I − ννᵀ; u₁ = α(a₁ − κPa₁), u₂ = ακPa₂.
    let kappa = rho1 / rho;
    let kp = (Mat3::identity() - nu * nu.transpose()) * kappa;
    let u1 = (a1 - kp * a1) * alpha;
    let u2 = (kp * a2) * alpha;
    let (sigma1, sigma2) = (a1 * k[0] + a2 * k[1], a1 * k[2] + a2 * k[3]);
    let l = kp + u1 * sigma1.transpose() + u2 * sigma2.transpose();
    let c0 = lever + l * span;
    let (v1, v2) = (u1 * k[0] + u2 * k[2], u1 * k[1] + u2 * k[3]);
    for col in 0..3 {
        let (ga, gb) = (g[col], g[7 + col]);
        for i in 0..3 {
            let id = if i == col { 1.0 } else { 0.0 };
            let lic = l[(i, col)];
            j[i][col] = id - lic + c0[i] * ga;
            j[i][7 + col] = lic + c0[i] * gb;
        }
    }
    let (as1, at2) = (alpha * s, alpha * t);
    for (kk, omega) in axes[0].iter().enumerate() {
        let z = omega.cross(&a1);
        let dx = (z - l * z) * as1 + v1 * w.dot(&z) + c0 * g[3 + kk];
        for i in 0..3 {
            j[i][3 + kk] = dx[i];
        }
    }
    for (kk, omega) in axes[1].iter().enumerate() {
        let z = omega.cross(&a2);
        let dx = (l * z) * at2 + v2 * w.dot(&z) + c0 * g[10 + kk];
        for i in 0..3 {
            j[i][10 + kk] = dx[i];
        }
    }
    j[3] = *g;
    block_finite(j).then_some(())
}
