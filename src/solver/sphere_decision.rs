//! "Is α* below t?" for a sphere against a box, a capsule or a cylinder, without α*.
//!
//! Scaled by α about their origins, a sphere of radius ρ centred at `c` and a solid B at `r`
//! touch when `dist(c, r + αRB) = αρ`. In B's frame, with `p = Rᵀ(c − r)`, that is
//! `dist(p/α, B) = ρ`, and `dist(p/α, B)` does not increase with α (B is convex and holds its
//! origin, so `p/α` moves towards B as α grows). Hence α* < t exactly when
//! `dist(p, tB) < tρ` (distance is homogeneous of degree one): a clamp and a comparison of
//! squares, where α* itself takes the root of a quadratic in the closed forms
//! (`super::closed_form`). The two answers can differ only where α* is t to rounding, inside
//! the band that every threshold question leaves to the tolerance.

use crate::math::{Real, Vec3};

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
