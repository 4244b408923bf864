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
/// (principal frame), certified to `1e-12·e₁`; `None` when the bracket does not close.
///
/// Newton starts from the largest of `tᵢ = −eᵢ² + eᵢ|yᵢ|` (each term of F is 1 at its own
/// `tᵢ`, so `F ≥ 0` there), and not below 0 outside (`F(0) > 0`). The certificate: every
/// `t` with `I + tA ⪰ 0` gives the lower bound `q(t) = Σ yᵢ² t aᵢ/(1 + t aᵢ) − t` on the
/// squared distance (the minimum over x of `‖x − y‖² + t(xᵀAx − 1)`: weak duality), and `x`
/// pushed radially onto the boundary gives an upper bound. Measured: from `t₃` alone a point
/// 1e-13 off the plane of the longer axes needed more Newton steps than the loop allowed, and
/// the depth came out 7e-10 too deep.
///
/// Inside, the root lies just above `−e₃²`, and `t + eᵢ²` computed from t loses the digits of
/// a point near the centre (`t + e₃² ≈ e₃|y₃|`: a point 1e-5 from the centre of a unit
/// ellipsoid kept 11 digits of its nearest point, and the bracket did not close). Inside, the
/// unknown is therefore `s = t + e₃²`, with `t + eᵢ² = s + gᵢ`, `gᵢ = (eᵢ − e₃)(eᵢ + e₃)`.
/// A point inside on the plane of the two longer axes (`y₃ = 0`, as a centred sphere is) has
/// its nearest points off that plane when `F` has no root above `s = 0`: then `s = 0`,
/// `xᵢ = eᵢ²yᵢ/gᵢ` (i = 1, 2) and `x₃ = e₃√(1 − Σ (xᵢ/eᵢ)²)`, one of the two (or, on the axis
/// of a spheroid, of the circle of) nearest points, and the bracket closes at `t = −e₃²`.
pub(crate) fn nearest(y: &Vec3, e: &Vec3) -> Option<Nearest> {
    let z = y.abs();
    let inside = z.component_div(e).norm_squared() <= 1.0;
    let e2 = e.component_mul(e);
    let ez = e.component_mul(&z);
    // The shift of the unknown (`s = t + c`) and `gᵢ = eᵢ² − c`.
    let (c, g) = if inside {
        (e2.z, Vec3::from_fn(|i, _| (e[i] - e.z) * (e[i] + e.z)))
    } else {
        (0.0, e2)
    };
    // The terms of F, nonnegative; zero where `yᵢ = 0` also at `s + gᵢ = 0` (`max` takes the
    // number over the NaN of 0/0, without a branch).
    let term = |i: usize, s: Real| (ez[i] / (s + g[i])).max(0.0);
    let f = |s: Real| (0..3).map(|i| term(i, s).powi(2)).sum::<Real>() - 1.0;
    let df = |s: Real| {
        -2.0 * (0..3)
            .map(|i| term(i, s).powi(2) / (s + g[i]))
            .sum::<Real>()
    };
    // `xᵢ = eᵢ²yᵢ/(s + gᵢ)`, 0 where `yᵢ = 0`.
    let point = |s: Real| {
        Vec3::from_fn(|i, _| {
            let x = e2[i] * y[i] / (s + g[i]);
            if x.is_nan() {
                0.0
            } else {
                x
            }
        })
    };
    // `q = t(Σ yᵢ²/(t + eᵢ²) − 1)`, `t = s − c` (a term is 0 where `yᵢ = 0`, as above).
    let dual = |s: Real| {
        let sum = (0..3)
            .map(|i| (z[i] * z[i] / (s + g[i])).max(0.0))
            .sum::<Real>();
        (s - c) * (sum - 1.0)
    };
    let (x, q) = if inside && z.z == 0.0 && f(0.0) <= 0.0 {
        // Off the plane: `s = 0`, x₃ from the boundary equation.
        let mut x = point(0.0);
        let rest = 1.0 - (x.x / e.x).powi(2) - (x.y / e.y).powi(2);
        x.z = e.z * rest.max(0.0).sqrt();
        (x, dual(0.0))
    } else {
        let floor = if inside { ez.z } else { 0.0 };
        let mut s = (0..3).map(|i| ez[i] - g[i]).fold(floor, Real::max);
        for _ in 0..MAX_STEPS {
            let fs = f(s);
            if !(fs > 0.0) {
                break;
            }
            let next = s - fs / df(s);
            if !(next > s) {
                break;
            }
            s = next;
        }
        (point(s), dual(s))
    };
    let dist = (x - y).norm();
    // The bracket [√q, ‖x' − y‖], x' = x / √(xᵀAx) on the boundary.
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

    /// Points inside near the centre (they used to lose their digits in `t + e₃²`, and the
    /// bracket did not close) and on the plane of the two longer axes (they used to be left to
    /// the general solvers): the depth from `q(−e₃²) = e₃²(1 − Σ yᵢ²/(eᵢ² − e₃²))`, exact on
    /// that plane, and near the centre the short semi-axis less the offset along it (to its
    /// square, with the optimality condition to rounding).
    #[test]
    fn nearest_points_inside_near_the_centre_and_on_the_long_axes_plane() {
        let e = Vec3::new(0.9534, 0.5782, 0.5583);
        let y = Vec3::new(5.7e-7, 9.4e-6, 4.3e-6);
        let n = nearest(&y, &e).expect("closed near the centre");
        assert!(n.inside && (n.dist - (e.z - y.z)).abs() < 1e-8, "{n:?}");
        // On the boundary, and `y − x` along the normal `A x` there (the optimality condition).
        let normal = n.x.component_div(&e.component_mul(&e)).normalize();
        assert!((n.x.component_div(&e).norm_squared() - 1.0).abs() < 1e-14);
        assert!(((n.x - y) / n.dist).cross(&normal).norm() < 1e-12, "{n:?}");
        // On the plane of the longer axes: two nearest points, off it.
        for (e, y) in [
            (Vec3::new(2.0, 1.0, 0.5), Vec3::new(0.1, 0.05, 0.0)),
            (Vec3::new(2.0, 1.0, 0.5), Vec3::new(0.0, 0.0, 0.0)),
            // A spheroid's axis: a circle of nearest points.
            (Vec3::new(2.0, 0.5, 0.5), Vec3::new(0.3, 0.0, 0.0)),
        ] {
            let n = nearest(&y, &e).expect("closed on the plane");
            let term = |i: usize| {
                if y[i] == 0.0 {
                    0.0
                } else {
                    y[i] * y[i] / (e[i] * e[i] - e.z * e.z)
                }
            };
            let want = e.z * (1.0 - term(0) - term(1)).sqrt();
            let on = (n.x.component_div(&e).norm_squared() - 1.0).abs();
            assert!(
                n.inside && (n.dist - want).abs() < 1e-14 && on < 1e-14 && n.x.z > 0.0,
                "{y:?}: {n:?} vs {want}"
            );
        }
    }
}
