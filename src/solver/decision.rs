//! "Is α* below t?" without α*: a sphere against a box, a capsule or a cylinder, and two boxes.
//!
//! **A sphere.** Scaled by α about their origins, a sphere of radius ρ centred at `c` and a solid B at `r`
//! touch when `dist(c, r + αRB) = αρ`. In B's frame, with `p = Rᵀ(c − r)`, that is
//! `dist(p/α, B) = ρ`, and `dist(p/α, B)` does not increase with α (B is convex and holds its
//! origin, so `p/α` moves towards B as α grows). Hence α* < t exactly when
//! `dist(p, tB) < tρ` (distance is homogeneous of degree one): a clamp and a comparison of
//! squares, where α* itself takes the root of a quadratic in the closed forms
//! (`super::closed_form`). The two answers can differ only where α* is t to rounding, inside
//! the band that every threshold question leaves to the tolerance.
//!
//! **Two boxes.** K = B₁ ⊕ (−B₂) is a centrally symmetric polytope whose facet normals are
//! among the 15 separating axes (the boxes' 3 + 3 face normals and the 9 cross products of
//! their edges), and for any axis `n`, `|n·d|/(h₁(n) + h₂(n)) ≤ α*` with equality at K's facet
//! normal that d crosses: α* is the largest of the 15 ratios. So α* ≥ t as soon as one ratio
//! reaches t, and α* < t when all 15 stay below it; an edge axis whose cross product is too
//! short to trust (nearly parallel edges) leaves a "below" undecided.

use crate::math::{Mat3, Real, Vec3};

/// The solid the sphere is tested against, in its body frame (axis `e_x` for the capsule and
/// the cylinder, as everywhere in dcol).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Solid {
    /// A box centred at its origin with these half extents.
    Box(Vec3),
    /// The points within `radius` of the segment `[−half, half]·e_x` (a capsule).
    Segment { half: Real, radius: Real },
    /// A cylinder of this radius and half-length.
    Cylinder { radius: Real, half: Real },
}

/// Whether α* < t for a sphere of radius `rho` whose centre lies at `p` in the solid's frame
/// (the solid's origin at 0): `dist(p, t·solid) < t·rho`. `None` when a number on the way is
/// not finite (the caller then asks the general path).
#[inline]
pub(crate) fn sphere_below(p: &Vec3, t: Real, rho: Real, solid: Solid) -> Option<bool> {
    let out = |v: Real, h: Real| (v.abs() - t * h).max(0.0);
    let (gap2, reach) = match solid {
        Solid::Box(h) => {
            let e = Vec3::new(out(p.x, h.x), out(p.y, h.y), out(p.z, h.z));
            (e.norm_squared(), t * rho)
        }
        Solid::Segment { half, radius } => {
            let ex = out(p.x, half);
            (ex * ex + p.y * p.y + p.z * p.z, t * (rho + radius))
        }
        Solid::Cylinder { radius, half } => {
            let ex = out(p.x, half);
            let s2 = p.y * p.y + p.z * p.z;
            let tr = t * radius;
            // The radial excess only where the centre lies outside the scaled radius (its
            // square root is then needed; inside it is zero).
            let er = if s2 > tr * tr { s2.sqrt() - tr } else { 0.0 };
            (ex * ex + er * er, t * rho)
        }
    };
    let reach2 = reach * reach;
    (gap2.is_finite() && reach2.is_finite()).then_some(gap2 < reach2)
}

/// A cross product of two unit edge directions shorter than this (squared length 1e-12) is not
/// trusted as an axis: its direction carries rounding of 1e-16/1e-6 relative, and a decision
/// resting on it would fall outside the tolerance's band. Such pairs are left undecided.
const SHORT: Real = 1e-12;

/// Whether α* < t for two boxes centred at their origins, of half extents `ea` and `eb`, box 2
/// turned by `c = R₁ᵀR₂` at `d = R₁ᵀ(r₂ − r₁)` in box 1's frame: `Some(false)` as soon as an
/// axis gives a ratio ≥ t, `Some(true)` when all 15 are below, `None` when one of them is a
/// short cross product or a number is not finite (the caller asks the general path).
#[inline]
pub(crate) fn boxes_below(ea: &Vec3, eb: &Vec3, c: &Mat3, d: &Vec3, t: Real) -> Option<bool> {
    let abs = c.abs();
    // |n·d| ≥ t (h₁(n) + h₂(n)) for an axis n (not necessarily unit: both sides scale with it).
    let apart = |nd: Real, h: Real| nd.abs() >= t * h;
    for k in 0..3 {
        let rb = eb.x * abs[(k, 0)] + eb.y * abs[(k, 1)] + eb.z * abs[(k, 2)];
        if apart(d[k], ea[k] + rb) {
            return Some(false);
        }
    }
    for j in 0..3 {
        let ra = ea.x * abs[(0, j)] + ea.y * abs[(1, j)] + ea.z * abs[(2, j)];
        if apart(c.column(j).dot(d), ra + eb[j]) {
            return Some(false);
        }
    }
    let mut trusted = true;
    for i in 0..3 {
        for j in 0..3 {
            let l = Vec3::ith(i, 1.0).cross(&c.column(j));
            let m = c.tr_mul(&l);
            let ra = ea.x * l.x.abs() + ea.y * l.y.abs() + ea.z * l.z.abs();
            let rb = eb.x * m.x.abs() + eb.y * m.y.abs() + eb.z * m.z.abs();
            if l.norm_squared() < SHORT {
                trusted = false;
            } else if apart(l.dot(d), ra + rb) {
                return Some(false);
            }
        }
    }
    // NaN anywhere fails every `>=` above and lands here: only finite inputs say "below".
    let finite = d.iter().chain(c.iter()).all(|v| v.is_finite()) && t.is_finite();
    (trusted && finite).then_some(true)
}

#[cfg(test)]
mod tests {
    use super::{sphere_below, Solid};
    use crate::math::{lcg, Vec3};

    /// The decision against the distance by brute force: the solid sampled densely (its
    /// nearest point found by a fine search), on random centres and thresholds, away from the
    /// tie; and exact ties by construction on each face, edge and cap.
    #[test]
    fn decisions_match_the_scaled_distance() {
        let mut g = lcg(0x5EED);
        let mut next = move || (g() + 1.0) * 0.5;
        let solids = [
            Solid::Box(Vec3::new(0.6, 0.4, 0.3)),
            Solid::Segment {
                half: 0.4,
                radius: 0.3,
            },
            Solid::Cylinder {
                radius: 0.4,
                half: 0.45,
            },
        ];
        let mut decided = [0usize; 2];
        for solid in solids {
            for _ in 0..20_000 {
                let p = Vec3::new(next() * 4.0 - 2.0, next() * 4.0 - 2.0, next() * 4.0 - 2.0);
                let t = 0.2 + next() * 2.0;
                let rho = 0.05 + next() * 0.6;
                // The exact distance from p to t·solid, written independently per solid.
                let d = match solid {
                    Solid::Box(h) => {
                        let q = Vec3::new(
                            p.x.clamp(-t * h.x, t * h.x),
                            p.y.clamp(-t * h.y, t * h.y),
                            p.z.clamp(-t * h.z, t * h.z),
                        );
                        (p - q).norm()
                    }
                    Solid::Segment { half, radius } => {
                        let q = Vec3::new(p.x.clamp(-t * half, t * half), 0.0, 0.0);
                        ((p - q).norm() - t * radius).max(0.0)
                    }
                    Solid::Cylinder { radius, half } => {
                        let s = (p.y * p.y + p.z * p.z).sqrt();
                        let k = if s > t * radius { t * radius / s } else { 1.0 };
                        let q = Vec3::new(p.x.clamp(-t * half, t * half), p.y * k, p.z * k);
                        (p - q).norm()
                    }
                };
                if (d - t * rho).abs() <= 1e-9 {
                    continue;
                }
                let got = sphere_below(&p, t, rho, solid).unwrap();
                assert_eq!(
                    got,
                    d < t * rho,
                    "{solid:?}, p {p:?}, t {t}, rho {rho}: d {d}"
                );
                decided[usize::from(got)] += 1;
            }
        }
        assert!(decided[0] > 10_000 && decided[1] > 3_000, "{decided:?}");
        // Non-finite numbers on the way: no decision.
        let big = Vec3::new(1e200, 1e200, 0.0);
        assert_eq!(sphere_below(&big, 1.0, 0.5, solids[0]), None);
    }
}

#[cfg(test)]
mod box_tests {
    use super::boxes_below;
    use crate::math::{lcg, rotation_from_quaternion, Vec3};

    /// Two boxes against α* by brute force over directions: α* = max over unit n of
    /// `|n·d|/(h₁(n) + h₂(n))`, maximised by a dense random search refined by local moves
    /// (a lower bound that converges to α*). Where the decision says "apart" the search must
    /// reach t; where it says "below", the search stays below t.
    #[test]
    fn decisions_match_the_gauge() {
        let mut g = lcg(0xB0C5);
        let ea = Vec3::new(0.6, 0.4, 0.3);
        let eb = Vec3::new(0.5, 0.2, 0.35);
        let (mut below, mut apart, mut open) = (0, 0, 0);
        for _ in 0..400 {
            let c = rotation_from_quaternion([g(), g(), g(), g()]);
            let d = Vec3::new(g(), g(), g()) * 1.5;
            let t = 0.5 + (g() + 1.0);
            let ratio = |n: &Vec3| {
                let m = c.tr_mul(n);
                n.dot(&d).abs() / (ea.dot(&n.abs()) + eb.dot(&m.abs()))
            };
            // The search: 4 000 random directions, then shrinking local moves.
            let mut best = (0.0, Vec3::x());
            for _ in 0..4_000 {
                let n = Vec3::new(g(), g(), g());
                if n.norm() > 1e-3 {
                    let n = n.normalize();
                    let r = ratio(&n);
                    if r > best.0 {
                        best = (r, n);
                    }
                }
            }
            let mut step = 0.1;
            while step > 1e-9 {
                let mut moved = false;
                for _ in 0..40 {
                    let n = (best.1 + Vec3::new(g(), g(), g()) * step).normalize();
                    let r = ratio(&n);
                    if r > best.0 {
                        best = (r, n);
                        moved = true;
                    }
                }
                if !moved {
                    step *= 0.5;
                }
            }
            let alpha = best.0;
            if (alpha - t).abs() < 1e-6 * t {
                continue;
            }
            match boxes_below(&ea, &eb, &c, &d, t) {
                Some(true) => {
                    assert!(alpha < t, "said below: search reached {alpha} >= {t}");
                    below += 1;
                }
                Some(false) => {
                    assert!(alpha > t, "said apart: search found only {alpha} < {t}");
                    apart += 1;
                }
                None => open += 1,
            }
        }
        assert!(
            below > 100 && apart > 100 && open < 5,
            "{below} {apart} {open}"
        );
    }
}
