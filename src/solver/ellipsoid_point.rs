//! An ellipsoid's point nearest a given point, and α* of a sphere and an ellipsoid, both by
//! Eberly's secular equation (*Distance from a point to an ellipse, an ellipsoid, or a
//! hyperellipsoid*), certified by Lagrangian duality.
//!
//! In the principal frame (semi-axes `e` descending, `A = diag(1/eᵢ²)`) the point of the
//! ellipsoid's boundary nearest `y` is `xᵢ = eᵢ²yᵢ/(t + eᵢ²)` at the root `t` of
//! `F(t) = Σ (eᵢyᵢ/(t + eᵢ²))² − 1` with `I + tA ⪰ 0` (`t ≥ −e₃²`): `t > 0` outside, `t ≤ 0`
//! inside. On that range F decreases and is convex, so Newton's method from a point where
//! `F ≥ 0` climbs to the root monotonically.

use crate::math::{Real, Vec3};

/// Newton steps at most.
const MAX_STEPS: usize = 200;

/// The nearest boundary point of an ellipsoid, certified.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nearest {
    /// The boundary point (principal frame).
    pub x: Vec3,
    /// Its distance from the given point.
    pub dist: Real,
    /// The given point lies inside.
    pub inside: bool,
}

/// The point of the boundary of the ellipsoid with semi-axes `e` (descending) nearest `y`
/// (principal frame), certified to `1e-12·e₁`; `None` with `y` inside and in the plane of the
/// two longer axes (where the nearest point may be one of two), or when the bracket does not
/// close.
///
/// Newton starts from the largest of `tᵢ = −eᵢ² + eᵢ|yᵢ|` (each term of F is 1 at its own
/// `tᵢ`, so `F ≥ 0` there), and not below 0 outside (`F(0) > 0`). The certificate: every
/// `t` with `I + tA ⪰ 0` gives the lower bound `q(t) = Σ yᵢ² t aᵢ/(1 + t aᵢ) − t` on the
/// squared distance (the minimum over x of `‖x − y‖² + t(xᵀAx − 1)`: weak duality), and `x`
/// pushed radially onto the boundary gives an upper bound. Measured: from `t₃` alone a point
/// 1e-13 off the plane of the longer axes needed more Newton steps than the loop allowed, and
/// the depth came out 7e-10 too deep.
pub(crate) fn nearest(y: &Vec3, e: &Vec3) -> Option<Nearest> {
    let z = y.abs();
    let inside = z.component_div(e).norm_squared() <= 1.0;
    if inside && !(z.z > 0.0) {
        return None;
    }
    let e2 = e.component_mul(e);
    let ez = e.component_mul(&z);
    let f = |t: Real| (0..3).map(|i| (ez[i] / (t + e2[i])).powi(2)).sum::<Real>() - 1.0;
    let df = |t: Real| {
        -2.0 * (0..3)
            .map(|i| ez[i].powi(2) / (t + e2[i]).powi(3))
            .sum::<Real>()
    };
    let floor = if inside { -e2.z + ez.z } else { 0.0 };
    let mut t = (0..3).map(|i| -e2[i] + ez[i]).fold(floor, Real::max);
    for _ in 0..MAX_STEPS {
        let ft = f(t);
        if !(ft > 0.0) {
            break;
        }
        let next = t - ft / df(t);
        if !(next > t) {
            break;
        }
        t = next;
    }
    let x = Vec3::from_fn(|i, _| e2[i] * y[i] / (t + e2[i]));
    let dist = (x - y).norm();
    // The bracket [√q(t), ‖x' − y‖], x' = x / √(xᵀAx) on the boundary.
    let q = (0..3).map(|i| z[i] * z[i] * t / (t + e2[i])).sum::<Real>() - t;
    let on = x / x.component_div(e).norm();
    let upper = (on - y).norm();
    let lower = q.max(0.0).sqrt();
    let closed = upper - lower <= 1e-12 * e.x && (dist - lower).abs() <= 1e-12 * e.x;
    (closed && dist.is_finite() && x.iter().all(|v| v.is_finite())).then_some(Nearest {
        x,
        dist,
        inside,
    })
}

/// α* of a sphere of radius `rho` and the ellipsoid with semi-axes `e` (descending), the
/// sphere's centre at `β·c` (principal frame, β = 1/α): the largest β with
/// `dist(βc, E) ≤ ρ`, and the ellipsoid's touching point. Candidates only: the caller
/// certifies them.
///
/// With `y = βc` outside and its nearest point at multiplier `t > 0`, `xᵀAx = 1` reads
/// `β²S₁(t) = 1` and `‖y − x‖ = ρ` reads `β²t²S₂(t) = ρ²`, with `S₁ = Σ (eᵢcᵢ/(t + eᵢ²))²` and
/// `S₂ = Σ (cᵢ/(t + eᵢ²))²`; so t is the root of `ψ(t) = t²S₂(t) − ρ²S₁(t)` and
/// `β = 1/√S₁(t)`. As `y − x = tAx` and `1/e₁ ≤ ‖Ax‖ ≤ 1/e₃` on the boundary, the root lies in
/// `[ρe₃, ρe₁]`: Newton's method inside that bracket, bisecting where a step leaves it, from
/// `ρ/‖Ax₀‖` at the ray's exit point `x₀`.
pub(crate) fn sphere_alpha(c: &Vec3, e: &Vec3, rho: Real) -> Option<(Real, Vec3)> {
    let e2 = e.component_mul(e);
    let ec = e.component_mul(c);
    let sums = |t: Real| {
        let (mut s1, mut s2, mut d1, mut d2) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..3 {
            let k = 1.0 / (t + e2[i]);
            let (a, b) = (ec[i] * k, c[i] * k);
            s1 += a * a;
            s2 += b * b;
            d1 -= 2.0 * a * a * k;
            d2 -= 2.0 * b * b * k;
        }
        (s1, s2, d1, d2)
    };
    let psi = |t: Real| {
        let (s1, s2, d1, d2) = sums(t);
        (
            t * t * s2 - rho * rho * s1,
            2.0 * t * s2 + t * t * d2 - rho * rho * d1,
        )
    };
    let (mut lo, mut hi) = (rho * e.z, rho * e.x);
    let exit = c / c.component_div(e).norm();
    let ax = exit.component_div(&e2).norm();
    if !(lo > 0.0 && lo <= hi && hi.is_finite()) {
        return None;
    }
    let mut t = (rho / ax).max(lo).min(hi);
    if !(t.is_finite() && psi(lo).0 <= 0.0 && psi(hi).0 >= 0.0) {
        return None;
    }
    for _ in 0..MAX_STEPS {
        let (v, dv) = psi(t);
        if v == 0.0 {
            break;
        }
        if v < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let mut next = t - v / dv;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let done = (next - t).abs() <= 4.0 * Real::EPSILON * t;
        t = next;
        if done || hi - lo <= 4.0 * Real::EPSILON * hi {
            break;
        }
    }
    let beta = 1.0 / sums(t).0.sqrt();
    let x = Vec3::from_fn(|i, _| e2[i] * beta * c[i] / (t + e2[i]));
    (beta.is_finite() && x.iter().all(|v| v.is_finite())).then_some((beta, x))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_points_of_a_spheroid_and_a_sphere_alpha() {
        let e = Vec3::new(2.0, 1.0, 1.0);
        // On the long axis, outside: the pole.
        let n = nearest(&Vec3::new(3.0, 0.0, 0.0), &e).unwrap();
        assert!(!n.inside && (n.dist - 1.0).abs() < 1e-14 && (n.x.x - 2.0).abs() < 1e-14);
        // On a short axis, outside: the equator.
        let n = nearest(&Vec3::new(0.0, 0.0, 1.5), &e).unwrap();
        assert!((n.dist - 0.5).abs() < 1e-14 && (n.x.z - 1.0).abs() < 1e-14);
        // Inside on the shortest axis: its pole is nearest.
        let n = nearest(&Vec3::new(0.0, 0.0, 0.2), &Vec3::new(2.0, 1.0, 0.5)).unwrap();
        assert!(n.inside && (n.dist - 0.3).abs() < 1e-14, "{n:?}");
        // A sphere of radius 0.5 along the long axis: touches at β·1 = 2 + 0.5.
        let (beta, x) = sphere_alpha(&Vec3::new(1.0, 0.0, 0.0), &e, 0.5).unwrap();
        assert!((beta - 2.5).abs() < 1e-14 && (x - Vec3::new(2.0, 0.0, 0.0)).norm() < 1e-14);
        // Along a short axis: 1 + 0.5.
        let (beta, _) = sphere_alpha(&Vec3::new(0.0, 2.0, 0.0), &e, 0.5).unwrap();
        assert!((beta * 2.0 - 1.5).abs() < 1e-14);
        // Off-axis: the centre βc lies at distance ρ from its nearest point.
        let c = Vec3::new(0.6, -0.3, 0.8);
        let (beta, x) = sphere_alpha(&c, &Vec3::new(1.5, 0.9, 0.4), 0.3).unwrap();
        let n = nearest(&(c * beta), &Vec3::new(1.5, 0.9, 0.4)).unwrap();
        assert!(
            (n.dist - 0.3).abs() < 1e-14 && (n.x - x).norm() < 1e-13,
            "{n:?} {x:?}"
        );
    }
}
