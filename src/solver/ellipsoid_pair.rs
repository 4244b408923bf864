//! α* of two ellipsoids by the Perram–Wertheim contact function (*Statistical mechanics of
//! hard ellipsoids*, J. Comput. Phys. 58, 1985).
//!
//! With `Σᵢ = Aᵢ⁻¹` the inverse shape matrices (ellipsoid i is `(x − rᵢ)ᵀAᵢ(x − rᵢ) ≤ 1`) and
//! `d = r₂ − r₁`, the two ellipsoids scaled by α about their centres touch at
//! `α*² = max over λ ∈ [0, 1] of F(λ) = λ(1 − λ) dᵀG(λ)⁻¹d`, `G = (1 − λ)Σ₁ + λΣ₂`. F is
//! concave; with `u = G⁻¹d` and `sᵢ = uᵀΣᵢu`, `F' = (1 − λ)²s₁ − λ²s₂`, which says that the
//! point `x = r₁ + (1 − λ)Σ₁u = r₂ − λΣ₂u` is on both scaled boundaries at once; the normal
//! there is along `u`. Newton's method on `F' = 0` inside the bracket `[0, 1]` (`F'(0) > 0 >
//! F'(1)`), each step one 3×3 adjugate; the caller certifies the answer with the support
//! functions.

use crate::math::{Mat3, Real, Vec3};

/// Newton steps at most.
const MAX_STEPS: usize = 60;

/// The touching points of two ellipsoids scaled by α* (α* itself is `|d|/|a − b|`; the
/// caller's certificate computes it from the normal).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Contact {
    /// The unit normal at the touching point, from ellipsoid 1 to ellipsoid 2.
    pub normal: Vec3,
    /// The touching points on the unscaled ellipsoids, relative to their centres
    /// (`α*(a − b) = d`).
    pub a: Vec3,
    pub b: Vec3,
}

/// The adjugate of a symmetric matrix and its determinant.
#[inline]
fn adjugate(g: &Mat3) -> (Mat3, Real) {
    let c00 = g[(1, 1)] * g[(2, 2)] - g[(1, 2)] * g[(2, 1)];
    let c01 = g[(1, 2)] * g[(2, 0)] - g[(1, 0)] * g[(2, 2)];
    let c02 = g[(1, 0)] * g[(2, 1)] - g[(1, 1)] * g[(2, 0)];
    let c11 = g[(0, 0)] * g[(2, 2)] - g[(0, 2)] * g[(2, 0)];
    let c12 = g[(0, 1)] * g[(2, 0)] - g[(0, 0)] * g[(2, 1)];
    let c22 = g[(0, 0)] * g[(1, 1)] - g[(0, 1)] * g[(1, 0)];
    let det = g[(0, 0)] * c00 + g[(0, 1)] * c01 + g[(0, 2)] * c02;
    (Mat3::new(c00, c01, c02, c01, c11, c12, c02, c12, c22), det)
}

/// α* of the ellipsoids with inverse shape matrices `s1`, `s2` (symmetric positive definite,
/// the frame of `d`) whose centres are `d` apart (`d ≠ 0`); `None` when the iteration breaks
/// down (a singular `G` to rounding, a non-finite value).
pub(crate) fn contact(s1: &Mat3, s2: &Mat3, d: &Vec3) -> Option<Contact> {
    // The start: exact for two spheres (Σᵢ = ρᵢ²I gives λ = ρ₁/(ρ₁ + ρ₂)), with ρᵢ the
    // support functions along d.
    let rho1 = d.dot(&(s1 * d)).sqrt();
    let rho2 = d.dot(&(s2 * d)).sqrt();
    let mut lam = rho1 / (rho1 + rho2);
    if !(lam > 0.0 && lam < 1.0) {
        return None;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let ds = s2 - s1;
    let mut last = None;
    for _ in 0..MAX_STEPS {
        let g = s1 * (1.0 - lam) + s2 * lam;
        let (adj, det) = adjugate(&g);
        if !(det > 0.0 && det.is_finite()) {
            return None;
        }
        let u = adj * d / det;
        let (v1, v2) = (s1 * u, s2 * u);
        let (q1, q2) = (u.dot(&v1), u.dot(&v2));
        let f = (1.0 - lam) * (1.0 - lam) * q1 - lam * lam * q2;
        last = Some((lam, u, v1, v2));
        // Below the rounding of its two terms F' has no sign left to follow.
        let noise = 16.0 * Real::EPSILON * ((1.0 - lam) * (1.0 - lam) * q1 + lam * lam * q2);
        if f.abs() <= noise {
            break;
        }
        if f > 0.0 {
            lo = lam;
        } else if f < 0.0 {
            hi = lam;
        } else {
            break;
        }
        // u' = −G⁻¹(Σ₂ − Σ₁)u, sᵢ' = 2 vᵢ·u'.
        let du = -(adj * (ds * u)) / det;
        let slope = -2.0 * (1.0 - lam) * q1 + 2.0 * (1.0 - lam) * (1.0 - lam) * v1.dot(&du)
            - 2.0 * lam * q2
            - 2.0 * lam * lam * v2.dot(&du);
        let mut next = lam - f / slope;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        let done = (next - lam).abs() <= 4.0 * Real::EPSILON || hi - lo <= 4.0 * Real::EPSILON;
        lam = next;
        if done {
            break;
        }
    }
    let (lam, u, v1, v2) = last?;
    let alpha = (lam * (1.0 - lam) * d.dot(&u)).sqrt();
    let len = u.norm();
    let answer = Contact {
        normal: u / len,
        a: v1 * ((1.0 - lam) / alpha),
        b: -v2 * (lam / alpha),
    };
    let finite = alpha > 0.0
        && alpha.is_finite()
        && [answer.normal, answer.a, answer.b]
            .iter()
            .all(|v| v.iter().all(|x| x.is_finite()));
    finite.then_some(answer)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// α* from the touching points.
    fn alpha(c: &Contact, d: &Vec3) -> Real {
        d.norm() / (c.a - c.b).norm()
    }

    /// Two spheres: α* = |d|/(ρ₁ + ρ₂), touching where the centres' segment divides in the
    /// ratio of the radii.
    #[test]
    fn two_spheres() {
        let d = Vec3::new(1.0, 2.0, -2.0);
        let c = contact(&(Mat3::identity() * 4.0), &(Mat3::identity() * 0.25), &d).unwrap();
        assert!((alpha(&c, &d) - 3.0 / 2.5).abs() <= 1e-15 * 1.2, "{c:?}");
        assert!((c.normal - d / 3.0).norm() <= 1e-15, "{c:?}");
        assert!((c.a - d / 3.0 * 2.0).norm() <= 1e-15, "{c:?}");
        assert!((c.b + d / 3.0 * 0.5).norm() <= 1e-15, "{c:?}");
    }

    /// Two axis-aligned ellipsoids along a common axis: α* = d/(e₁ + e₂) with eᵢ the semi-axes
    /// along it.
    #[test]
    fn aligned_ellipsoids() {
        let s1 = Mat3::from_diagonal(&Vec3::new(0.25, 1.0, 9.0));
        let s2 = Mat3::from_diagonal(&Vec3::new(4.0, 0.01, 1.0));
        let d = Vec3::new(0.0, 3.3, 0.0);
        let c = contact(&s1, &s2, &d).unwrap();
        assert!((alpha(&c, &d) - 3.3 / 1.1).abs() <= 1e-15 * 3.0, "{c:?}");
        assert!((c.a - Vec3::new(0.0, 1.0, 0.0)).norm() <= 1e-15, "{c:?}");
        assert!((c.b - Vec3::new(0.0, -0.1, 0.0)).norm() <= 1e-15, "{c:?}");
    }

    /// A general pair: the touching points lie on the unscaled boundaries, `α(a − b) = d`,
    /// and the normals there are opposite and along `normal`.
    #[test]
    fn general_pair_touches() {
        let m1 = Mat3::new(1.0, 0.3, -0.2, 0.1, 0.7, 0.4, -0.3, 0.2, 0.5);
        let m2 = Mat3::new(0.4, -0.1, 0.0, 0.2, 1.2, 0.3, 0.1, -0.5, 0.6);
        let (s1, s2) = (m1 * m1.transpose(), m2 * m2.transpose());
        let (a1, a2) = (s1.try_inverse().unwrap(), s2.try_inverse().unwrap());
        let d = Vec3::new(0.3, -1.1, 0.8);
        let c = contact(&s1, &s2, &d).unwrap();
        assert!((c.a.dot(&(a1 * c.a)) - 1.0).abs() <= 1e-13, "{c:?}");
        assert!((c.b.dot(&(a2 * c.b)) - 1.0).abs() <= 1e-13, "{c:?}");
        assert!(((c.a - c.b) * alpha(&c, &d) - d).norm() <= 1e-13, "{c:?}");
        let (n1, n2) = ((a1 * c.a).normalize(), (a2 * c.b).normalize());
        assert!(
            (n1 - c.normal).norm() <= 1e-12 && (n2 + c.normal).norm() <= 1e-12,
            "{c:?}"
        );
    }
}
