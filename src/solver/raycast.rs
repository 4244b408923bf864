//! α* as a ray cast on support maps (Minkowski portal refinement, MPR).
//!
//! α* is the gauge of `K = K₁ ⊕ (−K₂)` at `d = r₂ − r₁` (`docs/maths.md` §1): the ray
//! from K's interior point 0 along `d` leaves K at `d/α*`. Portal refinement keeps a triangle of
//! support points of K (a *portal*) through which the ray passes, and replaces one vertex at a
//! time by the support point in the portal's normal direction. Every step certifies a bracket:
//!
//! - the ray meets the portal's plane at a point of K (a convex combination of points of K), so
//!   `α* ≤ α_hi = (n·r)/(n·v₁)`;
//! - for any direction `n`, `α* ≥ α_lo = (n·r)/h_K(n)` (a separating plane).
//!
//! Polytope pairs end exactly (the portal lands in a facet of K); curved pairs converge fast to
//! a few digits and are then finished by the feature polish (`super::polish`).
//!
//! Everything here is in the *normalised* frame of the caller: lengths divided by ℓ, the ray
//! direction `r` a unit vector; α' here is the gauge of the normalised K at `r`.

use crate::math::{Mat3, Real, Vec3};
use crate::shapes::SupportMap;

/// A posed shape in the normalised world frame: `R` (world from body) and `1/ℓ`.
#[derive(Clone, Copy)]
pub(crate) struct Posed<'a, S: SupportMap> {
    pub shape: &'a S,
    pub rot: &'a Mat3,
    pub inv_scale: Real,
}

impl<S: SupportMap> Posed<'_, S> {
    /// A support point (normalised world frame, relative to the shape's origin) in world
    /// direction `n`, and its piece.
    #[inline]
    pub fn support(&self, n: &Vec3) -> (Vec3, u32) {
        let (p, id) = self.shape.support_world(self.rot, n);
        (p * self.inv_scale, id)
    }

    /// [`SupportMap::gauge`] of a point given in the normalised world frame (relative to the
    /// shape's origin).
    #[inline]
    pub fn shape_gauge(&self, p: &Vec3) -> Real {
        self.shape.gauge(&(self.rot.tr_mul(p) / self.inv_scale))
    }
}

/// A support point of K with the two shapes' points it came from.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Vertex {
    /// `a − b`, a point of K.
    pub w: Vec3,
    /// The point of shape 1 (relative to its origin).
    pub a: Vec3,
    /// The point of shape 2 (relative to its origin).
    pub b: Vec3,
    /// Pieces of shape 1 and shape 2.
    pub id: [u32; 2],
}

/// Two posed shapes: the Minkowski difference `K = K₁ ⊕ (−K₂)`.
#[derive(Clone, Copy)]
pub(crate) struct Pair<'a, S: SupportMap> {
    pub one: Posed<'a, S>,
    pub two: Posed<'a, S>,
}

impl<'a, S: SupportMap> Pair<'a, S> {
    /// Two shapes at their attitudes (world from body), lengths scaled by `inv_scale`.
    pub fn new(shapes: [&'a S; 2], rots: [&'a Mat3; 2], inv_scale: Real) -> Self {
        Pair {
            one: Posed {
                shape: shapes[0],
                rot: rots[0],
                inv_scale,
            },
            two: Posed {
                shape: shapes[1],
                rot: rots[1],
                inv_scale,
            },
        }
    }

    /// The support point of K in direction `n`.
    #[inline]
    pub fn support(&self, n: &Vec3) -> Vertex {
        let (a, i1) = self.one.support(n);
        let (b, i2) = self.two.support(&-n);
        Vertex {
            w: a - b,
            a,
            b,
            id: [i1, i2],
        }
    }

    /// Shape `i` (0 or 1) and the sign its support map sees the world normal with: `+n` for
    /// shape 1, `−n` for shape 2 (K = K₁ ⊕ (−K₂)).
    #[inline]
    pub fn side(&self, i: usize) -> (&Posed<'_, S>, Real) {
        if i == 0 {
            (&self.one, 1.0)
        } else {
            (&self.two, -1.0)
        }
    }

    /// `h_K(n) = h₁(n) + h₂(−n)`.
    #[cfg(test)]
    pub fn h(&self, n: &Vec3) -> Real {
        self.support(n).w.dot(n)
    }
}

/// How a ray cast ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum CastEnd {
    /// The bracket closed to the requested relative width.
    Closed,
    /// The support point in the portal's direction lies on the portal's plane to rounding: the
    /// bracket is as closed as double precision allows.
    Flat,
    /// The iteration budget ran out.
    Budget,
    /// The support point along the ray itself lies on the ray: it is the exit point, and the
    /// ray's direction the optimal normal (two spheres, a vertex or face straight ahead).
    Exact,
    /// A degenerate portal (no usable normal): the bracket is whatever was reached.
    Degenerate,
    /// The bracket excludes the threshold: α' is proven below it (`true`) or above it.
    Decided(bool),
}

/// Stop as soon as the bracket excludes `value` (α' in the cast's units): when it lies above,
/// or, with `stop_below`, below.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stop {
    pub value: Real,
    pub stop_below: bool,
}

/// The result of a ray cast: a certified bracket on α', the last portal and where the ray
/// meets it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cast {
    pub alpha_lo: Real,
    pub alpha_hi: Real,
    /// The direction that gave `alpha_lo` (unit).
    pub normal: Vec3,
    pub portal: [Vertex; 3],
    /// Barycentric coordinates of the ray's point on the portal's plane.
    pub bary: [Real; 3],
    /// Support-map calls of K made.
    pub supports: u32,
    pub end: CastEnd,
}

impl Cast {
    /// The point of shape 1 and the point of shape 2 (relative to their origins) that the
    /// portal point combines.
    pub fn points(&self) -> (Vec3, Vec3) {
        let mut a = Vec3::zeros();
        let mut b = Vec3::zeros();
        for j in 0..3 {
            a += self.portal[j].a * self.bary[j];
            b += self.portal[j].b * self.bary[j];
        }
        (a, b)
    }
}

/// How far outside its portal (relative barycentric weight) the ray point may fall to rounding
/// before the portal counts as having lost the ray.
const BARY_SLACK: Real = 1e-13;

#[inline]
fn det(a: &Vec3, b: &Vec3, c: &Vec3) -> Real {
    a.cross(b).dot(c)
}

/// Casts the unit ray `r` against K; stops when `α_hi − α_lo ≤ rel_tol·α_lo` or after
/// `max_iter` refinements. K must contain the ball of radius `iota` about the origin (the two
/// inscribed balls' radii summed).
pub(crate) fn cast<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    iota: Real,
    rel_tol: Real,
    max_iter: u32,
    stop: Option<Stop>,
) -> Cast {
    let decided = |lo: Real, hi: Real| {
        let s = stop?;
        if lo > s.value {
            Some(false)
        } else if s.stop_below && hi < s.value {
            Some(true)
        } else {
            None
        }
    };
    let mut supports = 1;
    let v1 = pair.support(r);
    let h1 = v1.w.dot(r);
    let mut out = Cast {
        alpha_lo: 1.0 / h1,
        alpha_hi: Real::INFINITY,
        normal: *r,
        portal: [v1; 3],
        bary: [1.0, 0.0, 0.0],
        supports,
        end: CastEnd::Degenerate,
    };
    // The support point along the ray itself may already lie on it (two spheres, a vertex
    // straight ahead): then it is the exit point.
    let off = v1.w.cross(r);
    if off.norm() <= 1e-15 * v1.w.norm() {
        out.alpha_hi = 1.0 / h1;
        out.end = CastEnd::Exact;
        return out;
    }
    if let Some(below) = decided(out.alpha_lo, out.alpha_hi) {
        out.end = CastEnd::Decided(below);
        return out;
    }
    // Portal discovery (XenoCollide with the interior point 0 and the target at infinity
    // along r): find v1, v2, v3 with r inside the cone they span from 0.
    let mut p1 = v1;
    let mut p2 = pair.support(&off);
    supports += 1;
    let mut n = p1.w.cross(&p2.w);
    if n.dot(r) < 0.0 {
        std::mem::swap(&mut p1, &mut p2);
        n = -n;
    }
    let mut p3;
    let mut found = false;
    let mut guard = 0;
    loop {
        p3 = pair.support(&n);
        supports += 1;
        if det(&p1.w, r, &p3.w) < 0.0 {
            p2 = p3;
            n = p1.w.cross(&p2.w);
        } else if det(r, &p2.w, &p3.w) < 0.0 {
            p1 = p3;
            n = p1.w.cross(&p2.w);
        } else {
            found = true;
            break;
        }
        guard += 1;
        if guard > 64 || !(n.norm_squared() > 0.0) {
            break;
        }
    }
    if !found {
        out.supports = supports;
        return out;
    }
    let mut portal = [p1, p2, p3];
    let mut best_lo = out.alpha_lo;
    let mut best_n = *r;
    // The upper bound is certified from the best portal only when the plane's estimate
    // `nr/off` says the bracket may have closed (and once more at the end): the convex
    // combination's bound costs a square root and four divisions, and polytope pairs end
    // flat without needing it on the way.
    let mut best_plane = Real::INFINITY;
    let mut best_dets = [1.0, 0.0, 0.0];
    let mut certified_plane = Real::NAN;
    for it in 0..=max_iter {
        let [q1, q2, q3] = portal;
        let nn = (q2.w - q1.w).cross(&(q3.w - q1.w));
        let len = nn.norm();
        if !(len > 0.0) {
            out.end = CastEnd::Degenerate;
            break;
        }
        let n = nn * (1.0 / len);
        let nr = n.dot(r);
        let off = n.dot(&q1.w);
        if !(nr > 0.0 && off > 0.0) {
            out.end = CastEnd::Degenerate;
            break;
        }
        // Barycentric coordinates (unnormalised) of the ray point t·r on the portal's plane,
        // t = off/nr. On a portal shrunk to a sliver the plane's normal carries rounding, and
        // its point need not lie in K (seen: α = nr/off below α* by 5e-11 relative on a curved
        // pair cast to 1e-15); so the bound is taken from the convex combination of the
        // vertices with these weights, which lies in K whatever their rounding, corrected for
        // its distance from the ray (`bound`).
        let t = off / nr;
        let p = r * t;
        let d1 = det(&(q2.w - p), &(q3.w - p), &n);
        let d2 = det(&(q3.w - p), &(q1.w - p), &n);
        let d3 = det(&(q1.w - p), &(q2.w - p), &n);
        if !([d1, d2, d3]
            .iter()
            .all(|b| *b >= -BARY_SLACK * (d1 + d2 + d3).abs()))
        {
            // The portal lost the ray (rounding in the choice of sub-triangle).
            out.end = CastEnd::Degenerate;
            break;
        }
        let plane = 1.0 / t;
        if plane < best_plane {
            best_plane = plane;
            best_dets = [d1, d2, d3];
            out.portal = portal;
        }
        if it == max_iter {
            out.end = CastEnd::Budget;
            break;
        }
        let v4 = pair.support(&n);
        supports += 1;
        let h = v4.w.dot(&n);
        let lo = nr / h;
        if lo > best_lo {
            best_lo = lo;
            best_n = n;
        }
        // The bracket with the best portal's certified bound, when the estimate says it may
        // have closed or decided (once per new best portal).
        let may_close = best_plane - best_lo <= rel_tol * best_lo;
        let may_decide = stop.is_some_and(|s| s.stop_below && best_plane < s.value);
        if (may_close || may_decide) && certified_plane != best_plane {
            certified_plane = best_plane;
            (out.alpha_hi, out.bary) = bound(&out.portal, best_dets, r, iota);
        }
        if out.alpha_hi - best_lo <= rel_tol * best_lo {
            out.end = CastEnd::Closed;
            break;
        }
        if let Some(below) = decided(best_lo, out.alpha_hi) {
            out.end = CastEnd::Decided(below);
            break;
        }
        // The new support point adds nothing beyond the portal's plane (to rounding): the
        // portal lies in a face of K.
        if h - off <= 4.0 * Real::EPSILON * h {
            out.end = CastEnd::Flat;
            break;
        }
        // Keep the sub-triangle of (v1, v2, v3, v4) through which the ray passes.
        let q = v4.w.cross(r);
        if q.dot(&q1.w) >= 0.0 {
            if q.dot(&q3.w) <= 0.0 {
                portal[1] = v4;
            } else {
                portal[0] = v4;
            }
        } else if q.dot(&q2.w) >= 0.0 {
            portal[2] = v4;
        } else {
            portal[0] = v4;
        }
    }
    if best_plane.is_finite() && certified_plane != best_plane {
        (out.alpha_hi, out.bary) = bound(&out.portal, best_dets, r, iota);
    }
    out.alpha_lo = best_lo;
    out.normal = best_n;
    out.supports = supports;
    out
}

/// The certified upper bound on α' from a portal and the (unnormalised, possibly slightly
/// negative) barycentric weights of the ray's point on its plane: the convex combination with
/// the weights clamped at 0 is a point of K, and [`upper_from_point`] corrects for its distance
/// from the ray. Also the normalised weights.
fn bound(portal: &[Vertex; 3], dets: [Real; 3], r: &Vec3, iota: Real) -> (Real, [Real; 3]) {
    let d = dets.map(|v| v.max(0.0));
    let inv = 1.0 / (d[0] + d[1] + d[2]);
    let bary = d.map(|v| v * inv);
    let point = portal[0].w * bary[0] + portal[1].w * bary[1] + portal[2].w * bary[2];
    (upper_from_point(&point, r, iota), bary)
}

/// An upper bound on α' from a point `w` of K near the ray `r` (unit): K contains the ball of
/// radius `iota` about 0, so the convex hull of `w` and that ball meets the ray at a distance
/// `(w·r)·ι/(ι + e)` from 0, `e` the distance of `w` from the ray.
pub(crate) fn upper_from_point(w: &Vec3, r: &Vec3, iota: Real) -> Real {
    let along = w.dot(r);
    if !(along > 0.0) {
        return Real::INFINITY;
    }
    let e = (w - r * along).norm();
    (1.0 + e / iota) / along
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pose;
    use crate::shapes::Shape;

    fn pair<'a>(s1: &'a Shape, q1: &'a Mat3, s2: &'a Shape, q2: &'a Mat3) -> Pair<'a, Shape> {
        Pair {
            one: Posed {
                shape: s1,
                rot: q1,
                inv_scale: 1.0,
            },
            two: Posed {
                shape: s2,
                rot: q2,
                inv_scale: 1.0,
            },
        }
    }

    #[test]
    fn two_spheres_and_two_boxes_are_exact() {
        let id = Mat3::identity();
        let a = Shape::sphere(1.0).unwrap();
        let b = Shape::sphere(0.5).unwrap();
        let r = Vec3::new(1.0, 2.0, -0.5).normalize();
        let c = cast(&pair(&a, &id, &b, &id), &r, 0.5, 1e-12, 50, None);
        assert!((c.alpha_lo - 1.0 / 1.5).abs() < 1e-15 && (c.alpha_hi - 1.0 / 1.5).abs() < 1e-15);
        // Box against box, rotated: the exit point of a polytope pair is found exactly.
        let bx = Shape::cuboid(1.0, 0.5, 0.25).unwrap();
        let rot = *Pose::new([0.0; 3], [0.9, 0.1, -0.3, 0.2])
            .unwrap()
            .rotation();
        let c = cast(&pair(&bx, &id, &bx, &rot), &r, 0.25, 1e-14, 60, None);
        assert!(c.alpha_hi - c.alpha_lo <= 1e-14 * c.alpha_lo, "{c:?}");
        // The exit point lies on K's boundary: h_K(n) at the exit normal equals n·(r/α).
        let p = r / c.alpha_hi;
        let h = pair(&bx, &id, &bx, &rot).h(&c.normal);
        assert!((c.normal.dot(&p) - h).abs() < 1e-13);
    }

    #[test]
    fn ellipsoid_pair_brackets_close() {
        let id = Mat3::identity();
        let e = Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 4.0, 0.1], [0.0, 0.1, 9.0]]).unwrap();
        let rot = *Pose::new([0.0; 3], [0.3, 0.5, -0.2, 0.7])
            .unwrap()
            .rotation();
        let r = Vec3::new(0.3, -1.0, 0.4).normalize();
        let c = cast(&pair(&e, &id, &e, &rot), &r, 0.3, 1e-6, 100, None);
        assert_eq!(c.end, CastEnd::Closed, "{c:?}");
        assert!(c.alpha_hi >= c.alpha_lo && c.alpha_hi - c.alpha_lo <= 1e-6 * c.alpha_lo);
    }
}
