//! The distance from a capsule's segment to a solid whose point nearest a given point is a
//! closed form: a box centred at its origin, a cylinder, a cone.
//!
//! With `p(t) = c + t·u` (`|t| ≤ h`) the segment and `q(p)` the solid's point nearest `p`,
//! `f(t) = ‖p(t) − q(p(t))‖` is convex (the distance to a convex set, along a line), so
//! `φ = f²/2` is convex and differentiable with the non-decreasing derivative
//! `φ'(t) = u·(p(t) − q(p(t)))` (the gradient of half the squared distance is `p − q`). The
//! segment's closest parameter is an end where `φ'` does not change sign on the segment, and
//! otherwise the root of `φ'`, found by regula falsi with the Illinois rule inside a bracket
//! that always holds it (on a box `φ'` is piecewise linear and the root comes exactly once its
//! piece is found; on the curved pieces the convergence is superlinear).
//!
//! The answer is not trusted as it stands: the callers certify it with support functions
//! (GJK's lower bound at the normal, the upper bound the witnesses' distance), as for every
//! other closed form.

use super::closed_form::{closest_on_box, closest_on_cylinder};
use super::raycast::{Pair, Posed};
use crate::math::{Real, Vec3};
use crate::shapes::{Shape, ShapeKind};

/// Regula falsi steps at most (a step costs one nearest-point evaluation, 10–20 ns).
const MAX_STEPS: usize = 60;
/// Newton steps on 1/α at most.
const MAX_NEWTON: usize = 40;

/// The closest points of a capsule's segment and a solid, in the pair's normalised frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SegmentSolid {
    /// The distance between the segment and the solid (not less the capsule's radius).
    pub distance: Real,
    /// The unit normal from shape 1 to shape 2 (`closest2 − closest1 = distance·normal`).
    pub normal: Vec3,
    /// Shape 1's and shape 2's closest points relative to their origins (the segment's point
    /// for the capsule: not moved by its radius).
    pub a: Vec3,
    pub b: Vec3,
    /// The capsule's radius (normalised) and whether the capsule is shape 1.
    pub radius: Real,
    pub capsule_first: bool,
}

/// The solid's point nearest a point of its body frame (its own units).
enum Nearest {
    Box(Vec3),
    Cylinder(Real, Real),
    /// A cone's meridian section: each edge's start `(axial, radial)`, direction and inverse
    /// squared length.
    Section([Edge; 3]),
}

/// An edge of a meridian section.
#[derive(Clone, Copy)]
struct Edge {
    start: (Real, Real),
    dir: (Real, Real),
    inv_len2: Real,
}

impl Nearest {
    fn of(shape: &Shape) -> Option<Nearest> {
        if let Some(h) = shape.centred_box() {
            return Some(Nearest::Box(h));
        }
        match shape.solver_kind() {
            ShapeKind::Cylinder => {
                let (r, h) = shape.cylinder_dims()?;
                Some(Nearest::Cylinder(r, h))
            }
            ShapeKind::Cone => {
                let (v, m) = shape.revolution_section()?;
                if m != 3 {
                    return None;
                }
                let edge = |i: usize| {
                    let (c, n) = (v[i], v[(i + 1) % 3]);
                    let dir = (n.0 - c.0, n.1 - c.1);
                    Edge {
                        start: c,
                        dir,
                        inv_len2: 1.0 / (dir.0 * dir.0 + dir.1 * dir.1),
                    }
                };
                Some(Nearest::Section([edge(0), edge(1), edge(2)]))
            }
            _ => None,
        }
    }

    fn point(&self, p: &Vec3) -> Vec3 {
        match self {
            Nearest::Box(h) => closest_on_box(p, h),
            Nearest::Cylinder(r, h) => closest_on_cylinder(p, *r, *h),
            Nearest::Section(edges) => on_section(p, edges),
        }
    }
}

/// The point of a cone (its counter-clockwise meridian section `edges`) nearest `p` (body
/// frame): `p` inside (on the left of every edge, in its meridian half-plane), else the nearest
/// point of the section's edges. What `closest_on_section` gives, without the depth of an
/// inside point (a square root per edge), with the edges' lengths computed once.
fn on_section(p: &Vec3, edges: &[Edge; 3]) -> Vec3 {
    let radial = (p.y * p.y + p.z * p.z).sqrt();
    let (pa, pr) = (p.x, radial);
    let mut inside = true;
    let (mut best, mut closest) = (Real::INFINITY, (pa, pr));
    for e in edges {
        let (da, dr) = (pa - e.start.0, pr - e.start.1);
        inside &= e.dir.0 * dr - e.dir.1 * da >= 0.0;
        let t = ((da * e.dir.0 + dr * e.dir.1) * e.inv_len2).clamp(0.0, 1.0);
        let (qa, qr) = (e.start.0 + t * e.dir.0, e.start.1 + t * e.dir.1);
        let dist2 = (pa - qa) * (pa - qa) + (pr - qr) * (pr - qr);
        if dist2 < best {
            (best, closest) = (dist2, (qa, qr));
        }
    }
    if inside {
        return *p;
    }
    let (uy, uz) = if radial > 0.0 {
        (p.y / radial, p.z / radial)
    } else {
        (1.0, 0.0)
    };
    Vec3::new(closest.0, uy * closest.1, uz * closest.1)
}

/// A capsule and a solid with a nearest point in closed form, in the solid's body frame and
/// units: what the distance and α* share.
struct Setup<'p, 'a> {
    solid: &'p Posed<'a, Shape>,
    nearest: Nearest,
    capsule_first: bool,
    /// `±v` (normalised world axes): `v` from shape 1 to shape 2, turned to point from the
    /// solid to the capsule.
    toward: Vec3,
    /// The same in the solid's body frame and units.
    e: Vec3,
    /// The capsule's axis and half-length (body frame, solid's units).
    u: Vec3,
    h: Real,
    /// The capsule's radius (normalised).
    radius: Real,
}

impl<'p, 'a> Setup<'p, 'a> {
    /// `None` unless one shape is a capsule of positive length and the other a centred box,
    /// a cylinder or a cone.
    fn of(pair: &'p Pair<'a, Shape>, v: &Vec3) -> Option<Self> {
        let capsule = |posed: &Posed<'_, Shape>| match posed.shape.rounded_segment() {
            Some((half, radius)) if half > 0.0 => Some((half, radius)),
            _ => None,
        };
        let (seg, solid, toward, capsule_first) = if capsule(&pair.one).is_some() {
            (&pair.one, &pair.two, -v, true)
        } else {
            (&pair.two, &pair.one, *v, false)
        };
        let (half, radius) = capsule(seg)?;
        let nearest = Nearest::of(solid.shape)?;
        let s = solid.inv_scale;
        Some(Setup {
            solid,
            nearest,
            capsule_first,
            toward,
            e: solid.rot.tr_mul(&toward) / s,
            u: solid.rot.tr_mul(&seg.rot.column(0).into_owned()),
            h: half * seg.inv_scale / s,
            radius: radius * seg.inv_scale,
        })
    }
}

/// A capsule (of positive length) against a centred box, a cylinder or a cone, either order:
/// the segment's closest points to the solid; `None` for other pairs, or when the segment is
/// within `1e-9` of the solid (touching or crossing it: the normal is not defined to the
/// working precision there).
pub(crate) fn segment_solid(pair: &Pair<'_, Shape>, d: &Vec3) -> Option<SegmentSolid> {
    let Setup {
        solid,
        nearest,
        capsule_first,
        toward: centre,
        e: c,
        u,
        h,
        radius,
        ..
    } = Setup::of(pair, d)?;
    let s = solid.inv_scale;
    let t = closest_param(&nearest, &c, &u, h, None);
    let p = c + u * t;
    let q = nearest.point(&p);
    let gap = p - q;
    let len = gap.norm();
    if !(len > 1e-9) || !len.is_finite() {
        return None;
    }
    // Back to the pair's frame: from the solid to the segment, world axes, normalised units.
    let n = solid.rot * (gap / len);
    let on_solid = solid.rot * q * s;
    let on_segment = solid.rot * p * s - centre;
    let (normal, a, b) = if capsule_first {
        (-n, on_segment, on_solid)
    } else {
        (n, on_solid, on_segment)
    };
    Some(SegmentSolid {
        distance: len * s,
        normal,
        a,
        b,
        radius,
        capsule_first,
    })
}

/// The segment's parameter `t ∈ [−h, h]` of its point nearest the solid, for the segment
/// `c + t·u` in the solid's body frame: an end where `φ'` keeps its sign, else its root by
/// regula falsi with the Illinois rule (the end kept twice in a row has its value halved, so
/// that neither end stalls). `near`, a guess `(t₀, w)`: the root is sought first within `w`
/// of `t₀` (the bracket widened fourfold until `φ'` changes sign), which saves the first
/// steps' search over the whole segment when the guess is good.
#[inline(always)]
fn closest_param(
    nearest: &Nearest,
    c: &Vec3,
    u: &Vec3,
    h: Real,
    near: Option<(Real, Real)>,
) -> Real {
    let slope = |t: Real| {
        let p = c + u * t;
        u.dot(&(p - nearest.point(&p)))
    };
    // The rounding of `u·(p − q)` (|u| = 1, p and q within about |c| + h of the origin): a
    // value this small is a root to working precision, and halving the bracket further only
    // follows the rounding's signs (it took 30 bisections to pin the last bits of a root already
    // found).
    let noise = 16.0 * Real::EPSILON * (c.x.abs() + c.y.abs() + c.z.abs() + h);
    let (lo, hi, glo, ghi);
    match near {
        Some((t0, w)) if t0.abs() < h && w > 0.0 => {
            let g0 = slope(t0);
            if g0.abs() <= noise {
                return t0;
            }
            // Walk from t₀ toward the root until φ' changes sign (or the segment ends).
            let dir = if g0 < 0.0 { 1.0 } else { -1.0 };
            let (mut from, mut gfrom, mut step) = (t0, g0, w);
            loop {
                let to = (from + dir * step).clamp(-h, h);
                let gto = slope(to);
                if gto == 0.0 || (gto > 0.0) == (g0 < 0.0) {
                    (lo, glo, hi, ghi) = if dir > 0.0 {
                        (from, gfrom, to, gto)
                    } else {
                        (to, gto, from, gfrom)
                    };
                    break;
                }
                if to.abs() >= h {
                    return to;
                }
                (from, gfrom, step) = (to, gto, 4.0 * step);
            }
        }
        _ => {
            (lo, hi) = (-h, h);
            (glo, ghi) = (slope(lo), slope(hi));
            if glo >= 0.0 {
                return lo;
            }
            if ghi <= 0.0 {
                return hi;
            }
        }
    }
    if glo == 0.0 {
        return lo;
    }
    if ghi == 0.0 {
        return hi;
    }
    // Anderson–Björck: `b` is the latest point and `a` the other end of the bracket; when the
    // sign repeats, `a`'s value is scaled by `1 − g(c)/g(b)` (halved if that is not positive)
    // so that the retained end does not stall. Safeguarded: a bracket not halved within three
    // steps gets a bisection (with φ' nearly constant on a long stretch, 1.0e-3 against
    // 1.025e-3, the scaling shrank the far end's value a thousandfold and the points
    // alternated between the ends for 60 steps, ending far from the root).
    let (mut a, mut fa, mut b, mut fb) = (lo, glo, hi, ghi);
    let mut t = b;
    let (mut mark, mut since) = ((a - b).abs(), 0);
    for _ in 0..MAX_STEPS {
        let (l, r) = if a < b { (a, b) } else { (b, a) };
        t = (a * fb - b * fa) / (fb - fa);
        if since >= 3 || !(t > l && t < r) {
            t = 0.5 * (l + r);
        }
        let g = slope(t);
        if g.abs() <= noise {
            break;
        }
        if (g < 0.0) != (fb < 0.0) {
            (a, fa) = (b, fb);
        } else {
            let m = 1.0 - g / fb;
            fa *= if m > 0.0 { m } else { 0.5 };
        }
        (b, fb) = (t, g);
        let width = (a - b).abs();
        if width <= 4.0 * Real::EPSILON * h.max(1.0) {
            break;
        }
        if width <= 0.5 * mark {
            (mark, since) = (width, 0);
        } else {
            since += 1;
        }
    }
    t
}

/// α* of a capsule and a centred box, cylinder or cone, as a candidate (normalised units, the
/// ray `r` unit, from shape 1 to shape 2): with the shapes scaled by α about their origins,
/// or equivalently the capsule's segment moved to `β·e` from the solid's origin (β = 1/α, `e`
/// the ray in the solid's frame), `G(β) = dist(segment, solid) − R` is convex in β (the
/// distance is jointly convex in the segment's offset and parameter, and the least over the
/// parameter keeps that), negative at 0 and positive beyond the bounding balls, so Newton's
/// method from there, with `G'(β) = n·e` (`n` the unit normal from the solid to the segment at
/// its closest points, by the envelope theorem), falls monotonically to its root 1/α*. The
/// closest points there give the unit normal from shape 1 to shape 2 and the touching points
/// `a` and `b` (relative to their origins), which the caller certifies.
pub(crate) fn segment_solid_alpha(pair: &Pair<'_, Shape>, r: &Vec3) -> Option<AlphaHit> {
    let Setup {
        solid,
        nearest,
        capsule_first,
        e,
        u,
        h,
        radius,
        ..
    } = Setup::of(pair, r)?;
    let s = solid.inv_scale;
    let rad = radius / s;
    // Newton starts where G ≥ 0: at `h_K(r)` (`βr ∈ K` needs `β ≤ h_K(r)`), one support call;
    // past the bounding balls (about the origins) if that is not finite.
    let hk = pair.support(r).w.dot(r);
    let reach = (h + rad + solid.shape.bounding_radius()) / e.norm();
    let mut beta = if hk > 0.0 && hk.is_finite() {
        hk.min(reach)
    } else {
        reach
    };
    let mut closest = (Vec3::zeros(), Vec3::zeros(), 0.0);
    // The closest parameter moves less at every step as Newton converges: each search starts
    // at the last one's root, within the last move (a hundredth of the segment at first).
    let mut near: Option<(Real, Real)> = None;
    for _ in 0..MAX_NEWTON {
        let c = e * beta;
        let t = closest_param(&nearest, &c, &u, h, near);
        near = Some(match near {
            Some((t0, _)) => (t, (t - t0).abs().max(1e-9 * h)),
            None => (t, 1e-2 * h),
        });
        let p = c + u * t;
        let q = nearest.point(&p);
        let dist = (p - q).norm();
        if !(dist > 0.0 && dist.is_finite()) {
            return None;
        }
        let n = (p - q) / dist;
        let g = dist - rad;
        let slope = n.dot(&e);
        if !(slope > 0.0) {
            return None;
        }
        closest = (p - c, q, beta);
        let next = beta - g / slope;
        let done = (beta - next).abs() <= 4.0 * Real::EPSILON * beta;
        beta = next;
        if done {
            break;
        }
    }
    // The touching points at the last evaluation (their normal from the solid to the segment).
    let (on_segment, q, _) = closest;
    let gap = (e * closest.2 + on_segment) - q;
    let n = solid.rot * (gap / gap.norm());
    let on_solid = solid.rot * q * s;
    let on_capsule = solid.rot * on_segment * s - n * (rad * s);
    let (normal, a, b) = if capsule_first {
        (-n, on_capsule, on_solid)
    } else {
        (n, on_solid, on_capsule)
    };
    (normal.iter().all(|v| v.is_finite()) && beta.is_finite()).then_some(AlphaHit { normal, a, b })
}

/// α* of a capsule and a polytope when the ray leaves K through a facet of the
/// polytope pushed out by the rounded shape (a face contact), as a candidate: K lies in the slab
/// `n_k·y ≤ o_k + h|n_k·u| + ρ` of every facet, so the ray's least exit from those slabs bounds
/// 1/α* above, and it is 1/α* exactly when the touching point it gives (the segment's end
/// toward the facet, less ρ along its normal) lies in the polytope. `None` for other pairs or
/// when the exit is through an edge or a vertex (GJK on the cores answers those).
pub(crate) fn rounded_facet_alpha(pair: &Pair<'_, Shape>, r: &Vec3) -> Option<AlphaHit> {
    let (round, poly, dir, round_first) = match (
        pair.one.shape.rounded_segment(),
        pair.two.shape.rounded_segment(),
    ) {
        (Some(_), None) => (&pair.one, &pair.two, -r, true),
        (None, Some(_)) => (&pair.two, &pair.one, *r, false),
        _ => return None,
    };
    let (half, radius) = round.shape.rounded_segment()?;
    // A sphere meets a polytope of its size on an edge or a vertex more often than on a facet
    // (measured: 30 % facets, and the miss cost more than the hits saved); a capsule's
    // padded cast costs enough more that the same share pays (polytope–capsule 631 -> 581 ns).
    if !(half > 0.0) {
        return None;
    }
    let (normals, offsets) = poly.shape.facets()?;
    let s = poly.inv_scale;
    let e = poly.rot.tr_mul(&dir) / s;
    let u = poly.rot.tr_mul(&round.rot.column(0).into_owned());
    let k = round.inv_scale / s;
    let (h, rho) = (half * k, radius * k);
    let (mut beta, mut best) = (Real::INFINITY, usize::MAX);
    for (j, (n, o)) in normals.iter().zip(offsets).enumerate() {
        let c = n.dot(&e);
        if c > 0.0 {
            let b = (o + h * n.dot(&u).abs() + rho) / c;
            if b < beta {
                (beta, best) = (b, j);
            }
        }
    }
    let n = normals.get(best)?;
    let nu = n.dot(&u);
    let t = if nu > 0.0 {
        -h
    } else if nu < 0.0 {
        h
    } else {
        0.0
    };
    let on_round = u * t - n * rho;
    let p = e * beta + on_round;
    let slack = 1e-12 * offsets.iter().fold(0.0, |m: Real, o| m.max(o.abs()));
    if !normals
        .iter()
        .zip(offsets)
        .all(|(m, o)| m.dot(&p) <= o + slack)
    {
        return None;
    }
    let m = poly.rot * n;
    let on_poly = poly.rot * p * s;
    let on_round = poly.rot * on_round * s;
    let (normal, a, b) = if round_first {
        (-m, on_round, on_poly)
    } else {
        (m, on_poly, on_round)
    };
    (beta.is_finite() && normal.iter().all(|v| v.is_finite())).then_some(AlphaHit { normal, a, b })
}

/// The candidate of [`segment_solid_alpha`]: the unit normal from shape 1 to shape 2 and the
/// touching points of the unscaled shapes (normalised, relative to their origins).
#[derive(Clone, Copy, Debug)]
pub(crate) struct AlphaHit {
    pub normal: Vec3,
    pub a: Vec3,
    pub b: Vec3,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Pose;

    /// The closest parameter from a guess, good or bad, gives the distance of the search over
    /// the whole segment (to rounding): segments in random places about a box, a cylinder and
    /// a cone, with guesses anywhere on the segment and bracket widths from 1e-9 to the whole.
    #[test]
    fn a_guessed_start_finds_the_whole_searchs_distance() {
        let mut seed = 0x5EED_u64;
        let mut unit = move || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as Real / (1u64 << 53) as Real
        };
        let solids = [
            Shape::cuboid(0.5, 0.3, 0.2).unwrap(),
            Shape::cylinder(0.4, 1.2).unwrap(),
            Shape::cone(1.0, 0.5).unwrap(),
        ];
        let mut compared = 0;
        for solid in &solids {
            let nearest = Nearest::of(solid).unwrap();
            for _ in 0..400 {
                let mut v = || Vec3::new(unit() - 0.5, unit() - 0.5, unit() - 0.5);
                let c = v() * 4.0;
                let u = v().normalize();
                let h = 0.05 + 2.0 * unit();
                let dist = |t: Real| {
                    let p = c + u * t;
                    (p - nearest.point(&p)).norm()
                };
                let best = dist(closest_param(&nearest, &c, &u, h, None));
                for _ in 0..4 {
                    let t0 = (2.0 * unit() - 1.0) * h;
                    let w = h * 10f64.powf(-9.0 * unit());
                    let t = closest_param(&nearest, &c, &u, h, Some((t0, w)));
                    assert!(t.abs() <= h, "t {t} outside [-{h}, {h}]");
                    let d = dist(t);
                    assert!(
                        (d - best).abs() <= 1e-12 * (1.0 + best),
                        "from {t0} within {w}: {d} against {best}"
                    );
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 4800);
    }

    /// A segment over a cylinder's cap, nearly parallel to it: `φ'` is about 1.02e-3 along the
    /// part over the disc and steep beyond its rim. Unsafeguarded, Anderson–Björck alternated
    /// between the ends for its 60 steps and returned t = 1.8, 4e-4 above the distance at the
    /// root t = 1.2986 (found here by a golden-section search on the convex distance).
    #[test]
    fn a_nearly_flat_stretch_still_finds_the_root() {
        let solid = Shape::cylinder(0.4, 1.2).unwrap();
        let nearest = Nearest::of(&solid).unwrap();
        let c = Vec3::new(-1.7867362748129159, 0.6612081634128928, -1.4933097222235223);
        let u = Vec3::new(
            -0.0008623235762419492,
            -0.538909570207317,
            0.8423631826813269,
        );
        let h = 1.849404623656236;
        let dist = |t: Real| {
            let p = c + u * t;
            (p - nearest.point(&p)).norm()
        };
        let (mut lo, mut hi) = (-h, h);
        for _ in 0..200 {
            let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if dist(m1) < dist(m2) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        let t = closest_param(&nearest, &c, &u, h, None);
        assert!((t - lo).abs() < 1e-7, "t {t} against {lo}");
        assert!(
            dist(t) <= dist(lo) + 1e-15,
            "{} against {}",
            dist(t),
            dist(lo)
        );
    }

    fn pair<'a>(
        one: &'a Shape,
        p1: &'a Pose,
        two: &'a Shape,
        p2: &'a Pose,
    ) -> (Pair<'a, Shape>, Vec3) {
        let pair = Pair::new([one, two], [p1.rotation(), p2.rotation()], 1.0);
        (pair, p2.position() - p1.position())
    }

    #[test]
    fn a_capsule_over_a_box_face_edge_and_a_cylinder_rim() {
        // A capsule along x, 2 long, 1.5 above a unit cube's top face: the whole segment is
        // closest (the parameter is any; the distance is exact).
        let capsule = Shape::capsule(0.1, 2.0).unwrap();
        let cube = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
        let id = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
        let up = Pose::from_position([0.0, 0.0, 2.0]).unwrap();
        let (p, d) = pair(&cube, &id, &capsule, &up);
        let hit = segment_solid(&p, &d).unwrap();
        assert!((hit.distance - 1.5).abs() < 1e-15, "{hit:?}");
        assert!((hit.normal - Vec3::z()).norm() < 1e-15);
        assert!(!hit.capsule_first && (hit.radius - 0.1).abs() < 1e-15);
        // Tilted in the x-z plane by 45° over the edge x = 0.5, z = 0.5, its centre at
        // (1.5, 0, 1.5): the segment's point nearest the edge is its foot on the line through
        // the edge's direction... the closest pair is the edge's point (0.5, 0, 0.5) and the
        // segment's point there along (1, 0, 1)/√2 at distance √2·1 = 1.414...
        let q = [
            (std::f64::consts::FRAC_PI_8).cos(),
            0.0,
            (std::f64::consts::FRAC_PI_8).sin(),
            0.0,
        ];
        let tilted = Pose::new([1.5, 0.0, 1.5], q).unwrap();
        let (p, d) = pair(&capsule, &tilted, &cube, &id);
        let hit = segment_solid(&p, &d).unwrap();
        // The segment runs along (cos 45°, 0, −sin 45°) through (1.5, 0, 1.5): its points
        // (1.5 + s/√2, 0, 1.5 − s/√2) keep x + z = 3, and the cube's nearest to that line is
        // its corner edge (0.5, y, 0.5): distance (3 − 1)/√2 = √2.
        assert!((hit.distance - 2f64.sqrt()).abs() < 1e-14, "{hit:?}");
        let n = Vec3::new(-1.0, 0.0, -1.0).normalize();
        assert!((hit.normal - n).norm() < 1e-14 && hit.capsule_first);
        // A cylinder of radius 0.5 and half-length 1 about x; a capsule along y whose segment
        // passes 1 beyond the rim's plane x = 1 at height z = 0: the nearest point is on the
        // cap's disc, (1, y, 0) for the segment's point (2, y, 0) with |y| <= 0.5.
        let cyl = Shape::cylinder(0.5, 2.0).unwrap();
        let q = [
            (std::f64::consts::FRAC_PI_4).cos(),
            0.0,
            0.0,
            (std::f64::consts::FRAC_PI_4).sin(),
        ];
        let side = Pose::new([2.0, 0.0, 0.0], q).unwrap();
        let (p, d) = pair(&cyl, &id, &capsule, &side);
        let hit = segment_solid(&p, &d).unwrap();
        assert!((hit.distance - 1.0).abs() < 1e-15, "{hit:?}");
        assert!((hit.normal - Vec3::x()).norm() < 1e-15);
        // The same capsule raised to z = 1.5 and moved to x = 1.5: nearest the rim point
        // (1, 0, 0.5) from (1.5, 0, 1.5): distance √(0.25 + 1).
        let rim = Pose::new([1.5, 0.0, 1.5], q).unwrap();
        let (p, d) = pair(&cyl, &id, &capsule, &rim);
        let hit = segment_solid(&p, &d).unwrap();
        assert!((hit.distance - 1.25f64.sqrt()).abs() < 1e-14, "{hit:?}");
        assert!((hit.b + d - hit.a - hit.normal * hit.distance).norm() < 1e-14);
    }

    #[test]
    fn the_cone_section_agrees_with_the_closed_form_module() {
        let cone = Shape::cone(1.3, 0.4).unwrap();
        let Some(Nearest::Section(edges)) = Nearest::of(&cone) else {
            panic!("a cone has a section");
        };
        let (v, m) = cone.revolution_section().unwrap();
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as Real / (1u64 << 53) as Real * 4.0 - 2.0
        };
        for _ in 0..2000 {
            let p = Vec3::new(next(), next(), next());
            let want = super::super::closed_form::closest_on_section(&p, &v[..m]).0;
            assert!((on_section(&p, &edges) - want).norm() < 1e-15, "{p:?}");
        }
    }

    #[test]
    fn alpha_of_a_capsule_over_a_cylinder_cap_and_rim_and_a_box_face() {
        use crate::{proximity, Options, Solver};
        let capsule = Shape::capsule(0.25, 2.0).unwrap();
        let cyl = Shape::cylinder(0.5, 2.0).unwrap();
        let id = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
        // The capsule along y (a quarter turn about z).
        let q = [
            (std::f64::consts::FRAC_PI_4).cos(),
            0.0,
            0.0,
            (std::f64::consts::FRAC_PI_4).sin(),
        ];
        let o = Options::default();
        // Over the cap: the scaled cap x = α meets the scaled capsule's side at 2 − α/4.
        let cap = Pose::new([2.0, 0.0, 0.0], q).unwrap();
        let p = proximity(&cyl, &id, &capsule, &cap, &o).unwrap();
        assert_eq!(p.solver, Solver::ClosedForm);
        assert!((p.alpha - 1.6).abs() < 1e-12, "{p:?}");
        // Over the rim: (2 − α)² + (1 − α/2)² = (α/4)², the least root.
        let rim = Pose::new([2.0, 0.0, 1.0], q).unwrap();
        let p = proximity(&capsule, &rim, &cyl, &id, &o).unwrap();
        let want = (5.0 - 1.25f64.sqrt()) / 2.375;
        assert_eq!(p.solver, Solver::ClosedForm);
        assert!((p.alpha - want).abs() < 1e-12, "{} vs {want}", p.alpha);
        // The rim point (α, 0, α/2) of the scaled cylinder is (1, 0, 1/2) on the unscaled one,
        // shape 2's contact point.
        let c = p.contact2;
        let touch = Vec3::new(1.0, 0.0, 0.5);
        assert!((c - touch).norm() < 1e-9, "{c:?}");
        // A box face: 3 − α·0.25 = α·0.5 for a cube of half-side 0.5 under the capsule.
        let cube = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
        let up = Pose::new([0.0, 0.0, 3.0], q).unwrap();
        let p = proximity(&cube, &id, &capsule, &up, &o).unwrap();
        assert_eq!(p.solver, Solver::ClosedForm);
        assert!((p.alpha - 4.0).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn alpha_of_a_capsule_lying_over_an_octahedron_facet() {
        use crate::{proximity, Options, Solver};
        // |x| + |y| + |z| <= 1: facets (±1, ±1, ±1)·x <= 1.
        let mut a = Vec::new();
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                for sz in [-1.0, 1.0] {
                    a.push([sx, sy, sz]);
                }
            }
        }
        let octahedron = Shape::polytope(&a, &[1.0; 8]).unwrap();
        // A capsule of radius 0.2 and length 0.2 whose axis (1, −1, 0)/√2 lies in the planes of
        // the facet with normal n = (1, 1, 1)/√3, its centre at distance 2 along n: the
        // facet's offset α/√3 meets the capsule's side 2 − 0.2α.
        let n = Vec3::new(1.0, 1.0, 1.0) / 3f64.sqrt();
        let c = n * 2.0;
        let capsule = Shape::capsule(0.2, 0.2).unwrap();
        // The quaternion turning x to (1, −1, 0)/√2: a turn of −45° about z.
        let h = -std::f64::consts::FRAC_PI_8;
        let pose = Pose::new([c.x, c.y, c.z], [h.cos(), 0.0, 0.0, h.sin()]).unwrap();
        let id = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
        let want = 2.0 / (0.2 + 1.0 / 3f64.sqrt());
        for (s1, p1, s2, p2) in [
            (&octahedron, &id, &capsule, &pose),
            (&capsule, &pose, &octahedron, &id),
        ] {
            let p = proximity(s1, p1, s2, p2, &Options::default()).unwrap();
            assert_eq!(p.solver, Solver::ClosedForm);
            assert!(
                (p.alpha - want).abs() < 1e-12 * want,
                "{} vs {want}",
                p.alpha
            );
        }
    }

    #[test]
    fn a_segment_through_the_solid_has_no_answer() {
        let capsule = Shape::capsule(0.1, 4.0).unwrap();
        let cone = Shape::cone(1.0, 0.5).unwrap();
        let id = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
        let (p, d) = pair(&cone, &id, &capsule, &id);
        assert!(segment_solid(&p, &d).is_none());
        // Spheres are the sphere–solid closed form's, and two capsules the segments'.
        let ball = Shape::sphere(0.5).unwrap();
        let far = Pose::from_position([3.0, 0.0, 0.0]).unwrap();
        let (p, d) = pair(&ball, &far, &cone, &id);
        assert!(segment_solid(&p, &d).is_none());
        let (p, d) = pair(&capsule, &far, &capsule, &id);
        assert!(segment_solid(&p, &d).is_none());
    }
}
