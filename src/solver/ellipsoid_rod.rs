//! α* of an ellipsoid and a rod (a capsule or a cylinder) by Newton's method on the support
//! function in one or two variables, with the rod's side as a linear constraint.
//!
//! With the ellipsoid at the origin (`h_E(n) = √(nᵀΣn)`, Σ its inverse shape matrix in world
//! axes) and the rod (unit axis `a`, half-length `l`, radius `R`) along the unit ray `r`,
//! `1/α' = min { F(n) : n·r = 1 }` with `F(n) = √(nᵀΣn) + R‖Pn‖ + l|a·n|` (`docs/maths.md`
//! §1), where `P = I` for a capsule (the segment padded by a ball) and `P = I − aaᵀ` for a
//! cylinder (padded by a disc across the axis). The kink of F is the plane `a·n = 0`, the
//! rod's side, where `Pn = n` for both:
//!
//! - **The side.** On the line `a·n = 0`, `n·r = 1` (`n = n₀ + s u`, `u ∥ r × a`, `n₀ ⊥ u`),
//!   F is `f(s) = √(A + 2Bs + Cs²) + R√(N₀ + s²)`: strictly convex, its minimiser between the
//!   two terms' minimisers `−B/C` and 0. Newton's method safeguarded by that bracket. There
//!   the gradient `g = Σn/h_E + R n/‖n‖` lies in the span of `r` and `a`, and `g + c a = μ r`
//!   gives the subgradient's weight `c`: the optimum when `|c| ≤ l` (a KKT point of a convex
//!   problem), the rod's point `−c a − R n̂`.
//! - **An end.** Otherwise the optimum is off the side, on the end `σ = sign(c)` (a ball, or a
//!   cylinder's rim: `F = h_E + R‖Pn‖ + σ l a·n`, smooth and strictly convex on the plane away
//!   from the axis): Newton's method in the plane's two coordinates from the side's optimum,
//!   with a backtracking line search on F; the answer needs `σ a·n ≥ 0` at its end. A
//!   cylinder's cap face (`Pn = 0`) is not this solver's: it gives up there.
//!
//! Each step costs a few dozen flops (no support call, no piece bookkeeping); the caller
//! certifies the answer with the shapes' own support functions and points
//! (`crate::query::shortcuts`).

use super::direct::plane_basis;
use crate::math::{Mat3, Real, Vec3};

/// Newton steps at most, in each of the two solves.
const MAX_STEPS: usize = 40;
/// Halvings of an end solve's step before it gives up.
const MAX_HALVINGS: u32 = 30;
/// `1 − (r·a)²` below this: the ray runs along the axis, and the side is not tried (the
/// contact is at the end facing the ellipsoid, or the end solve says otherwise).
const PARALLEL: Real = 1e-12;

/// The touching configuration: the normal from the ellipsoid to the capsule (any length,
/// `n·r > 0`), the ellipsoid's point and the capsule's (normalised units, relative to their
/// origins).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Touch {
    pub normal: Vec3,
    pub on_ellipsoid: Vec3,
    pub on_capsule: Vec3,
}

/// The ellipsoid `Σ` (world axes, normalised units) at the origin and the rod of unit axis
/// `axis`, half-length `half` and radius `radius` along the unit ray `r` (a cylinder when
/// `disc`, else a capsule): the optimal normal and touching points (see the module's
/// description), or `None` when an iteration breaks down. `converged`: a Newton step at most
/// this (relative to ‖n‖) is the last.
pub(crate) fn touch(
    sigma: &Mat3,
    axis: &Vec3,
    half: Real,
    radius: Real,
    r: &Vec3,
    converged: Real,
    disc: bool,
) -> Option<Touch> {
    let ra = r.dot(axis);
    let den = 1.0 - ra * ra;
    // The start of the end solve and the end's sign.
    let (start, sign) = if den > PARALLEL {
        let n0 = (r - axis * ra) / den;
        let u = r.cross(axis) / den.sqrt();
        let (sn0, su) = (sigma * n0, sigma * u);
        let (a, b, c) = (n0.dot(&sn0), u.dot(&sn0), u.dot(&su));
        let n0n = n0.norm_squared();
        let s = side_minimum(a, b, c, n0n, radius, converged)?;
        let n = n0 + u * s;
        let sn = sn0 + su * s;
        let he = (a + s * (2.0 * b + s * c)).sqrt();
        let nn = (n0n + s * s).sqrt();
        let g = sn / he + n * (radius / nn);
        // g + w a = μ r with g in the span of r and a: its weight w.
        let w = (ra * g.dot(r) - g.dot(axis)) / den;
        if !w.is_finite() {
            return None;
        }
        if w.abs() <= half {
            return Some(Touch {
                normal: n,
                on_ellipsoid: sn / he,
                on_capsule: -(axis * w) - n * (radius / nn),
            });
        }
        (n, w.signum())
    } else if disc {
        return None;
    } else {
        (*r, if ra >= 0.0 { 1.0 } else { -1.0 })
    };
    if disc && cap_is_optimal(sigma, axis, half * sign, radius, r) {
        return None;
    }
    let n = end_minimum(sigma, axis, half * sign, radius, r, start, converged, disc)?;
    if !(sign * axis.dot(&n) >= 0.0) {
        return None;
    }
    let sn = sigma * n;
    let he = n.dot(&sn).sqrt();
    let pn = if disc { n - axis * axis.dot(&n) } else { n };
    let pnn = pn.norm();
    if !(pnn > 0.0) {
        return None;
    }
    Some(Touch {
        normal: n,
        on_ellipsoid: sn / he,
        on_capsule: -(axis * (half * sign)) - pn * (radius / pnn),
    })
}

/// Whether the cylinder's cap face at the end `l` (signed half-length) holds the optimum:
/// there `Pn = 0`, so `n = a/(r·a)` on the plane `n·r = 1`, and F's subdifferential there is
/// `g + {R v : v ⊥ a, ‖v‖ ≤ 1}` with `g = Σn/h_E(n) + l a` (the end's term, smooth where
/// `a·n` has the end's sign), so n is the minimiser exactly when some μ has `μr − g ⊥ a` and
/// `‖μr − g‖ ≤ R`: `μ = g·a/(r·a)`. The rim's Newton solve would walk towards the axis (where
/// its Hessian's `R/‖Pn‖` grows without bound) and give up after many halvings: an ellipsoid
/// on a cylinder's cap cost 4.5–6 µs before this test, 0.3–0.5 µs without the stage (review).
fn cap_is_optimal(sigma: &Mat3, axis: &Vec3, l: Real, radius: Real, r: &Vec3) -> bool {
    let ra = r.dot(axis);
    // The cap at this end faces the ray only when a·n = 1/(r·a) has the end's sign.
    if !(ra * l > 0.0) {
        return false;
    }
    let n = axis / ra;
    let sn = sigma * n;
    let he = n.dot(&sn).sqrt();
    let g = sn / he + axis * l;
    let mu = g.dot(axis) / ra;
    (r * mu - g).norm() <= radius
}

/// The minimiser of `f(s) = √(a + 2bs + cs²) + R√(n₀ + s²)` (`c > 0`, `n₀ > 0`): Newton's
/// method on `f'`, kept in the bracket between the two terms' minimisers `−b/c` and 0 (each
/// term is convex, so `f' < 0` left of both and `> 0` right of both), bisecting where a step
/// leaves it.
fn side_minimum(
    a: Real,
    b: Real,
    c: Real,
    n0: Real,
    radius: Real,
    converged: Real,
) -> Option<Real> {
    if !(c > 0.0 && n0 > 0.0) {
        return None;
    }
    let s1 = -b / c;
    let (mut lo, mut hi) = if s1 < 0.0 { (s1, 0.0) } else { (0.0, s1) };
    // The start: the terms' minimisers weighted by their curvatures there.
    let k1 = (a - b * s1).max(0.0).sqrt();
    let w1 = c / k1.max(1e-300);
    let w2 = radius / n0.sqrt();
    let mut s = if w1.is_finite() {
        (w1 * s1) / (w1 + w2)
    } else {
        s1
    };
    for _ in 0..MAX_STEPS {
        let q = a + s * (2.0 * b + s * c);
        let he = q.sqrt();
        let nn2 = n0 + s * s;
        let nn = nn2.sqrt();
        let lin = b + c * s;
        let d1 = lin / he + radius * s / nn;
        let d2 = (c - lin * lin / q) / he + radius * n0 / (nn2 * nn);
        if !(d1.is_finite() && d2 > 0.0) {
            return None;
        }
        if d1 < 0.0 {
            lo = lo.max(s);
        } else if d1 > 0.0 {
            hi = hi.min(s);
        } else {
            return Some(s);
        }
        let step = -d1 / d2;
        let next = s + step;
        if step.abs() <= converged * nn && next >= lo && next <= hi {
            return Some(next);
        }
        s = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo <= Real::EPSILON * nn {
            return Some(s);
        }
    }
    None
}

/// The minimiser of `F(n) = √(nᵀΣn) + R‖Pn‖ + l·(a·n)` on the plane `n·r = 1` (`l = ±` the
/// half-length: the end whose piece it is; `P` across the axis when `disc`, else the
/// identity), by Newton's method in the plane's two coordinates from `start` (on the plane),
/// with a backtracking line search on F.
#[allow(clippy::too_many_arguments)]
fn end_minimum(
    sigma: &Mat3,
    axis: &Vec3,
    l: Real,
    radius: Real,
    r: &Vec3,
    start: Vec3,
    converged: Real,
    disc: bool,
) -> Option<Vec3> {
    let (t1, t2) = plane_basis(r);
    let (st1, st2) = (sigma * t1, sigma * t2);
    let (s11, s12, s22) = (t1.dot(&st1), t1.dot(&st2), t2.dot(&st2));
    let (ta1, ta2) = (t1.dot(axis), t2.dot(axis));
    let (a1, a2) = (l * ta1, l * ta2);
    // The radius term's projector: the identity (a ball), or across the axis (a rim).
    let k = if disc { 1.0 } else { 0.0 };
    let across = |n: &Vec3| n - axis * (k * axis.dot(n));
    let (p11, p12, p22) = (1.0 - k * ta1 * ta1, -k * ta1 * ta2, 1.0 - k * ta2 * ta2);
    let value =
        |n: &Vec3| (n.dot(&(sigma * n))).sqrt() + radius * across(n).norm() + l * axis.dot(n);
    let mut n = start;
    let mut f = value(&n);
    for _ in 0..MAX_STEPS {
        let sn = sigma * n;
        let he = n.dot(&sn).sqrt();
        let nn = n.norm();
        let pn = across(&n);
        let pnn = pn.norm();
        let (p1, p2) = (t1.dot(&sn), t2.dot(&sn));
        let (q1, q2) = (t1.dot(&pn) / pnn, t2.dot(&pn) / pnn);
        let g1 = p1 / he + radius * q1 + a1;
        let g2 = p2 / he + radius * q2 + a2;
        let (ie, ir) = (1.0 / he, radius / pnn);
        let h11 = (s11 - p1 * p1 * ie * ie) * ie + ir * (p11 - q1 * q1);
        let h12 = (s12 - p1 * p2 * ie * ie) * ie + ir * (p12 - q1 * q2);
        let h22 = (s22 - p2 * p2 * ie * ie) * ie + ir * (p22 - q2 * q2);
        let det = h11 * h22 - h12 * h12;
        if !(h11 > 0.0 && det > 0.0) {
            return None;
        }
        let y1 = -(h22 * g1 - h12 * g2) / det;
        let y2 = -(h11 * g2 - h12 * g1) / det;
        let dn = t1 * y1 + t2 * y2;
        let step = dn.norm() / nn;
        if !step.is_finite() {
            return None;
        }
        if step <= converged {
            return Some(n + dn);
        }
        let slope = g1 * y1 + g2 * y2;
        let mut t = 1.0;
        let mut accepted = false;
        for _ in 0..=MAX_HALVINGS {
            let nt = n + dn * t;
            let ft = value(&nt);
            if ft <= f + 1e-4 * t * slope {
                n = nt;
                f = ft;
                accepted = true;
                break;
            }
            t *= 0.5;
        }
        if !accepted {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `F` at `n` (see the module's description).
    fn value(sigma: &Mat3, axis: &Vec3, half: Real, radius: Real, n: &Vec3, disc: bool) -> Real {
        let pn = if disc { n - axis * axis.dot(n) } else { *n };
        n.dot(&(sigma * n)).sqrt() + radius * pn.norm() + half * axis.dot(n).abs()
    }

    /// The ellipsoid of these tests (Σ = L Lᵀ, not axis-aligned).
    fn test_sigma() -> Mat3 {
        let l = Mat3::new(1.0, 0.0, 0.0, 0.3, 0.8, 0.0, -0.2, 0.4, 0.5);
        l * l.transpose()
    }

    /// A xorshift stream in [−1/2, 1/2).
    fn centred(seed: u64) -> impl FnMut() -> Real {
        let mut state = seed;
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as Real / 9_007_199_254_740_992.0 - 0.5
        }
    }

    /// The least F on a 41 × 41 grid of spacing 1e-3 about `n` in the plane `m·r = n·r`.
    fn grid_minimum(
        sigma: &Mat3,
        axis: &Vec3,
        half: Real,
        radius: Real,
        n: &Vec3,
        r: &Vec3,
        disc: bool,
    ) -> Real {
        let (t1, t2) = plane_basis(r);
        let mut best = Real::INFINITY;
        for i in -20..=20 {
            for j in -20..=20 {
                let m = n + t1 * (i as Real * 1e-3) + t2 * (j as Real * 1e-3);
                best = best.min(value(sigma, axis, half, radius, &m, disc));
            }
        }
        best
    }

    /// The touch against a brute-force minimum of F over the plane (a grid around its
    /// normal): F at the touch's normal is the least, and the touching points lie on the ray at
    /// `1/F` apart, the rod's point on its boundary. Capsules answer every case; cylinders all
    /// but those whose contact is near a cap face (which the flat-face stage answers).
    #[test]
    fn side_and_end_contacts_minimise_the_support_function() {
        let sigma = test_sigma();
        let mut next = centred(0x2545_F491_4F6C_DD1D);
        for disc in [false, true] {
            let (mut sides, mut ends, mut none) = (0, 0, 0);
            for _ in 0..200 {
                let axis = Vec3::new(next(), next(), next()).normalize();
                let r = Vec3::new(next(), next(), next()).normalize();
                let (half, radius) = (0.2 + 2.0 * next().abs(), 0.05 + next().abs());
                let Some(t) = touch(&sigma, &axis, half, radius, &r, 1e-7, disc) else {
                    none += 1;
                    continue;
                };
                let n = t.normal / t.normal.dot(&r);
                let f = value(&sigma, &axis, half, radius, &n, disc);
                // The points: a − b = r·F(n) (on the ray, at 1/α' = F).
                let w = t.on_ellipsoid - t.on_capsule;
                assert!((w - r * f).norm() <= 1e-12 * f, "{w:?} {f}");
                // The rod's point: its axial part within the half-length, its radial part R
                // (a cylinder) or its distance from the segment R (a capsule).
                let along = t.on_capsule.dot(&axis);
                let radial = (t.on_capsule - axis * along).norm();
                let off = (t.on_capsule - axis * along.clamp(-half, half)).norm();
                if disc {
                    assert!(along.abs() <= half * (1.0 + 1e-12));
                    assert!((radial - radius).abs() <= 1e-12, "{radial} vs {radius}");
                } else {
                    assert!((off - radius).abs() <= 1e-12, "{off} vs {radius}");
                }
                // Its segment parameter: less R along the unit normal for a capsule.
                let seg = if disc {
                    along
                } else {
                    (t.on_capsule + t.normal.normalize() * radius).dot(&axis)
                };
                if seg.abs() < half * (1.0 - 1e-9) {
                    sides += 1;
                } else {
                    ends += 1;
                }
                // Brute force over the plane around n.
                let best = grid_minimum(&sigma, &axis, half, radius, &n, &r, disc);
                assert!(f <= best * (1.0 + 1e-14), "{f} > {best}");
            }
            assert!(sides > 20 && ends > 20, "{sides} sides, {ends} ends");
            assert!(
                if disc { none <= 20 } else { none == 0 },
                "{none} not answered"
            );
        }
    }

    /// The cap test against a brute-force minimum of F over the plane: where it says the cap
    /// face holds the optimum, no point of a grid about `a/(r·a)` has a smaller F, and where it
    /// says not, some grid point does (the minimiser is off the axis); both cases occur.
    #[test]
    fn cap_test_matches_brute_force() {
        let sigma = test_sigma();
        let mut next = centred(0x9E37_79B9_7F4A_7C15);
        let (mut caps, mut rims) = (0, 0);
        for _ in 0..400 {
            let axis = Vec3::new(next(), next(), next()).normalize();
            // Rays within about 50° of the axis, either way along it.
            let r = (axis * (2.0 * next().signum()) + Vec3::new(next(), next(), next()) * 3.0)
                .normalize();
            let (half, radius) = (0.2 + 2.0 * next().abs(), 0.05 + 2.0 * next().abs());
            let ra = r.dot(&axis);
            let end = half * ra.signum();
            let n = axis / ra;
            let f = value(&sigma, &axis, half, radius, &n, true);
            let best = grid_minimum(&sigma, &axis, half, radius, &n, &r, true);
            if cap_is_optimal(&sigma, &axis, end, radius, &r) {
                caps += 1;
                assert!(f <= best * (1.0 + 1e-14), "cap: {f} > {best}");
            } else {
                rims += 1;
                assert!(best < f, "not the cap, yet F is least there: {f} vs {best}");
            }
        }
        assert!(caps > 50 && rims > 50, "{caps} caps, {rims} rims");
    }

    /// The ray along the capsule's axis: the end facing the ellipsoid, exactly.
    #[test]
    fn a_ray_along_the_axis_meets_the_near_end() {
        let sigma = Mat3::from_diagonal(&Vec3::new(4.0, 1.0, 0.25));
        let axis = Vec3::x();
        for sign in [1.0, -1.0] {
            let r = Vec3::x() * sign;
            let t = touch(&sigma, &axis, 1.5, 0.5, &r, 1e-7, false).unwrap();
            // α' = 1/(2 + 0.5 + 1.5) along x.
            let f = (t.on_ellipsoid - t.on_capsule).dot(&r);
            assert!((f - 4.0).abs() <= 1e-14, "{f}");
            assert!((t.on_capsule - Vec3::x() * (-1.5 * sign) + r * 0.5).norm() <= 1e-14);
        }
    }
}
