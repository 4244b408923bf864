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
use super::derivatives::rotation_axes;
use super::sphere_jacobian::{decide, MARGIN, TIE};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::sensitivity::PARALLEL_SIN;

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` for two capsules, from the geometric answer, its gradient `g`
/// (the α row) and `∂α*/∂d`; `None` for other pairs, undecided features, parallel sides or a
/// non-finite answer.
pub(crate) fn capsule_jacobian(
    prox: &Proximity,
    g: &[Real; 14],
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> Option<[[Real; 14]; 4]> {
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
    // dx* = dr₁ + dα·lever + α s da₁ + κPb + ds·u₁ + dt·u₂ with κ = ρ₁/ρ, P = I − ννᵀ: the
    // formulas above with dw and dν substituted.
    let kappa = rho1 / rho;
    let project = |v: Vec3| (v - nu * nu.dot(&v)) * kappa;
    let u1 = (a1 - project(a1)) * alpha;
    let u2 = project(a2) * alpha;
    // One column: the changes of d, r₁ and the axes, and α's.
    let column = |dd: Vec3, dr1: Vec3, da1: Vec3, da2: Vec3, dalpha: Real| -> Vec3 {
        let b = dd + span * dalpha + (da2 * t - da1 * s) * alpha;
        let e1 = b.dot(&a1) + w.dot(&da1);
        let e2 = b.dot(&a2) + w.dot(&da2);
        let (ds, dt) = (k[0] * e1 + k[1] * e2, k[2] * e1 + k[3] * e2);
        dr1 + lever * dalpha + da1 * (alpha * s) + project(b) + u1 * ds + u2 * dt
    };
    let mut j = [[0.0; 14]; 4];
    let zero = Vec3::zeros();
    let mut put = |col: usize, dx: Vec3| {
        for i in 0..3 {
            j[i][col] = dx[i];
        }
    };
    for k in 0..3 {
        let mut e = Vec3::zeros();
        e[k] = 1.0;
        put(k, column(-e, e, zero, zero, g[k]));
        put(7 + k, column(e, zero, zero, zero, g[7 + k]));
    }
    for (k, omega) in rotation_axes(poses[0]).iter().enumerate() {
        put(3 + k, column(zero, zero, omega.cross(&a1), zero, g[3 + k]));
    }
    for (k, omega) in rotation_axes(poses[1]).iter().enumerate() {
        put(
            10 + k,
            column(zero, zero, zero, omega.cross(&a2), g[10 + k]),
        );
    }
    j[3] = *g;
    crate::math::all_finite(&j).then_some(j)
}
