//! The penetration of two overlapping polytopes of few facets by the separating-axis theorem.
//!
//! For overlapping shapes the depth is `min over unit n of f(n)`, `f(n) = h₁(n) + h₂(−n) − n·d`
//! with `d = r₂ − r₁` (`docs/maths.md` §5): the distance from `d` to the boundary of the
//! Minkowski difference `K`. For two polytopes `K` is a polytope whose facet normals are among
//! the facet normals of shape 1, the negated facet normals of shape 2 and the cross products of
//! an edge direction of each: `f` over that finite set of candidates is exactly the depth (its
//! minimum is the distance from `d` to the nearest facet plane of `K`, and that plane's nearest
//! point lies on the facet), and any candidate with `f < 0` separates the shapes. A box has six
//! facets and three edge directions: 6 + 6 + 2·9 evaluations, each a few dot products, where
//! GJK and EPA take tens of support calls.
//!
//! The witness points come from the winning candidate: for a facet of one shape, the other's
//! support feature (a corner, an edge or a facet) clipped to that facet's prism, its deepest
//! point and that point moved onto the facet by the depth; for two edges, their closest points.
//! Where the witnesses cannot be found within rounding (the contact on a feature's boundary to
//! the last bits, or edges that are nearly parallel deciding the depth), the caller takes EPA.

use crate::math::{Mat3, Real, Vec3};
use crate::shapes::Polytope;
use arrayvec::ArrayVec;

/// Candidate edge cross products shorter than this (their edges parallel to rounding) are left
/// out: they are no facet normal of the difference.
const PARALLEL: Real = 1e-9;
/// An edge cross product shorter than this that wins makes the answer EPA's (its normal is
/// known only to `ε/|c|`).
const ILL_CONDITIONED: Real = 1e-6;
/// Feature and clipping tolerance, relative to the shapes' size.
const TOL: Real = 1e-11;
/// The most points a clipped feature holds.
const MAX_POINTS: usize = 48;
/// Polytopes of at most this many vertices (a box has 8) keep their vertices' values along a
/// direction in a buffer instead of computing them twice.
const FEW_VERTICES: usize = 32;

/// A polytope in world axes.
#[derive(Clone, Copy)]
pub(crate) struct Placed<'a> {
    pub poly: &'a Polytope,
    pub rot: &'a Mat3,
    pub pos: Vec3,
}

impl Placed<'_> {
    fn world(&self, v: &Vec3) -> Vec3 {
        self.pos + self.rot * v
    }
}

/// A polytope's body support function: a centred box's in closed form.
#[derive(Clone, Copy)]
enum Body<'a> {
    Box(Vec3),
    Poly(&'a Polytope),
}

impl<'a> Body<'a> {
    fn of(p: &'a Polytope) -> Body<'a> {
        match p.half_extents() {
            Some(h) => Body::Box(h),
            None => Body::Poly(p),
        }
    }

    #[inline]
    fn h(&self, m: &Vec3) -> Real {
        match self {
            Body::Box(h) => h.x * m.x.abs() + h.y * m.y.abs() + h.z * m.z.abs(),
            Body::Poly(p) => p.support_value(m),
        }
    }
}

/// The overlap of two polytopes: depth `≥ 0`, the unit normal from shape 1 to shape 2 and the
/// witness points (`closest2 − closest1 = −depth·normal`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Overlap {
    pub depth: Real,
    pub normal: Vec3,
    pub closest1: Vec3,
    pub closest2: Vec3,
}

/// Which candidate decided: a facet of shape 1 or 2 (its index), or two edges (the length of
/// their unit directions' cross product).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Axis {
    Face1(usize),
    Face2(usize),
    Edges(Real),
}

/// `Some(Ok(overlap))` for overlapping polytopes, `Some(Err(()))` when a candidate separates
/// them, `None` when the answer is not this method's (too many edge directions, or witnesses
/// that rounding hides): the caller takes the general path. `scale` is the shapes' size.
pub(crate) fn overlap(a: &Placed<'_>, b: &Placed<'_>, scale: Real) -> Option<Result<Overlap, ()>> {
    let (da, db) = (a.poly.edge_directions()?, b.poly.edge_directions()?);
    // In shape 1's body frame: shape 2 turned by C = R₁ᵀR₂ at t = R₁ᵀ(r₂ − r₁), and
    // f(n) = h₁(n) + h₂(−Cᵀn) − n·t with the body support functions.
    let c = a.rot.tr_mul(b.rot);
    let t = a.rot.tr_mul(&(b.pos - a.pos));
    let (ha, hb) = (Body::of(a.poly), Body::of(b.poly));
    if let (Body::Box(ea), Body::Box(eb)) = (ha, hb) {
        let (v, n, axis) = match two_boxes(&ea, &eb, &c, &t, 0.0) {
            Ok(best) => best,
            Err(_) => return Some(Err(())),
        };
        // The facets' indices in the boxes' own lists.
        let axis = match axis {
            Axis::Face1(k) => {
                let want = Vec3::ith(k % 3, if k < 3 { 1.0 } else { -1.0 });
                Axis::Face1(a.poly.facets().0.iter().position(|m| *m == want)?)
            }
            Axis::Face2(k) => {
                let want = Vec3::ith(k % 3, if k < 3 { 1.0 } else { -1.0 });
                Axis::Face2(b.poly.facets().0.iter().position(|m| *m == want)?)
            }
            e => e,
        };
        return witnesses(a, b, v, a.rot * n, axis, scale);
    }
    let mut best = (Real::INFINITY, Vec3::zeros(), Axis::Face1(0));
    let mut keep = |v: Real, n: Vec3, axis: Axis| {
        if v < best.0 {
            best = (v, n, axis);
        }
        v < 0.0
    };
    let (na, oa) = a.poly.facets();
    for (i, (n, o)) in na.iter().zip(oa).enumerate() {
        if keep(o + hb.h(&-c.tr_mul(n)) - n.dot(&t), *n, Axis::Face1(i)) {
            return Some(Err(()));
        }
    }
    let (nb, ob) = b.poly.facets();
    for (j, (m, o)) in nb.iter().zip(ob).enumerate() {
        let n = -(c * m);
        if keep(ha.h(&n) + o - n.dot(&t), n, Axis::Face2(j)) {
            return Some(Err(()));
        }
    }
    for ea in da {
        for eb in db {
            let n = ea.cross(&(c * eb));
            let len = n.norm();
            if !(len > PARALLEL) {
                continue;
            }
            let n = n / len;
            let m = c.tr_mul(&n);
            let nt = n.dot(&t);
            // Both signs: f(n) and f(−n).
            let (hap, han) = (ha.h(&n), ha.h(&-n));
            let (hbp, hbn) = (hb.h(&m), hb.h(&-m));
            if keep(hap + hbn - nt, n, Axis::Edges(len))
                || keep(han + hbp + nt, -n, Axis::Edges(len))
            {
                return Some(Err(()));
            }
        }
    }
    witnesses(a, b, best.0, a.rot * best.1, best.2, scale)
}

/// Two centred boxes of half extents `ea`, `eb` in shape 1's frame, shape 2 turned by `c` at
/// `t`: the least `f` over the 15 axes (the 3 + 3 face axes, signed towards shape 2, and the 9
/// edge cross products), its unit normal (shape 1's frame) and axis (`Face1(k)`/`Face2(k)`:
/// the body normal `±e_{k mod 3}`, `k < 3` positive); `Err(gap)` as soon as an axis
/// separates the boxes by `gap > beyond` (a lower bound on their distance). The least `f` is
/// negative for boxes apart by less than `beyond` along every axis.
pub(crate) fn two_boxes(
    ea: &Vec3,
    eb: &Vec3,
    c: &Mat3,
    t: &Vec3,
    beyond: Real,
) -> Result<(Real, Vec3, Axis), Real> {
    let abs = c.abs();
    let mut best = (Real::INFINITY, Vec3::zeros(), Axis::Face1(0));
    let mut keep = |v: Real, n: Vec3, axis: Axis| {
        if v < best.0 {
            best = (v, n, axis);
        }
        v < -beyond
    };
    for k in 0..3 {
        let rb = eb.x * abs[(k, 0)] + eb.y * abs[(k, 1)] + eb.z * abs[(k, 2)];
        let s = if t[k] < 0.0 { -1.0 } else { 1.0 };
        let v = ea[k] + rb - t[k].abs();
        if keep(
            v,
            Vec3::ith(k, s),
            Axis::Face1(k + if s < 0.0 { 3 } else { 0 }),
        ) {
            return Err(-v);
        }
    }
    for j in 0..3 {
        let col = c.column(j).into_owned();
        let ra = ea.x * abs[(0, j)] + ea.y * abs[(1, j)] + ea.z * abs[(2, j)];
        let tj = col.dot(t);
        let s = if tj < 0.0 { -1.0 } else { 1.0 };
        // Shape 2's facet facing shape 1 has the body normal −s·e_j.
        let v = ra + eb[j] - tj.abs();
        if keep(v, col * s, Axis::Face2(j + if s > 0.0 { 3 } else { 0 })) {
            return Err(-v);
        }
    }
    // The nine edge axes l = e_i × c_j, written out: l_i = 0, l_{i+1} = −c_{i+2,j},
    // l_{i+2} = c_{i+1,j}. The terms of l_i are exact zeros (every number here is finite but
    // `t`), so |l|, Cᵀl, the radii and l·t are the full products' to the last bit (a zero's sign
    // aside); `0·t_i` is still added to l·t, so a non-finite `t` gives what it gave.
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (a, b) = (-c[(i2, j)], c[(i1, j)]);
            let len = (a * a + b * b).sqrt();
            if !(len > PARALLEL) {
                continue;
            }
            let m = Vec3::new(
                c[(i1, 0)] * a + c[(i2, 0)] * b,
                c[(i1, 1)] * a + c[(i2, 1)] * b,
                c[(i1, 2)] * a + c[(i2, 2)] * b,
            );
            let ra = ea[i1] * a.abs() + ea[i2] * b.abs();
            let rb = eb.x * m.x.abs() + eb.y * m.y.abs() + eb.z * m.z.abs();
            let lt = (a * t[i1] + b * t[i2]) + 0.0 * t[i];
            let s = if lt < 0.0 { -1.0 } else { 1.0 };
            let v = (ra + rb - lt.abs()) / len;
            if keep(v, edge_axis(i, a, b) * (s / len), Axis::Edges(len)) {
                return Err(-v);
            }
        }
    }
    Ok(best)
}

/// The vector of components `l_i = 0`, `l_{i+1} = a`, `l_{i+2} = b` (indices mod 3).
#[inline(always)]
fn edge_axis(i: usize, a: Real, b: Real) -> Vec3 {
    match i {
        0 => Vec3::new(0.0, a, b),
        1 => Vec3::new(b, 0.0, a),
        _ => Vec3::new(a, b, 0.0),
    }
}

/// The overlap of two centred boxes whose least axis (`two_boxes`, every axis overlapping) is
/// the cross product of two edges of length `len`, its depth `depth` and world normal `n`: the
/// witnesses [`overlap`] finds for it (the same numbers), or `None` where it leaves the pair to
/// the general path.
pub(crate) fn box_edges(
    a: &Placed<'_>,
    b: &Placed<'_>,
    depth: Real,
    n: Vec3,
    len: Real,
    scale: Real,
) -> Option<Overlap> {
    witnesses(a, b, depth, n, Axis::Edges(len), scale)?.ok()
}

/// The witness points of the winning candidate (`n` world, from shape 1 to shape 2).
fn witnesses(
    a: &Placed<'_>,
    b: &Placed<'_>,
    depth: Real,
    n: Vec3,
    axis: Axis,
    scale: Real,
) -> Option<Result<Overlap, ()>> {
    let best = (depth, n, axis);
    let (depth, n, axis) = best;
    if !depth.is_finite() {
        return None;
    }
    let tol = TOL * scale;
    let (p1, p2) = match axis {
        Axis::Face1(i) => {
            let p2 = deepest_in_prism(b, &-n, a, i, &n, tol)?;
            (p2 + n * depth, p2)
        }
        Axis::Face2(j) => {
            let p1 = deepest_in_prism(a, &n, b, j, &-n, tol)?;
            (p1, p1 - n * depth)
        }
        Axis::Edges(len) => {
            if len < ILL_CONDITIONED {
                return None;
            }
            let p1 = edge_witness(a, b, &n, tol)?;
            (p1, p1 - n * depth)
        }
    };
    Some(Ok(Overlap {
        depth,
        normal: n,
        closest1: p1,
        closest2: p2,
    }))
}

/// The points of `s` whose value along `m` is within `tol` of its largest (world): the first
/// `out.len()` of them written, their number (at most `out.len()`) returned.
fn support_feature(s: &Placed<'_>, m: &Vec3, tol: Real, out: &mut [Vec3]) -> usize {
    let mb = s.rot.tr_mul(m);
    match <&[Vec3; 8]>::try_from(s.poly.vertices()) {
        Ok(v8) => support_eight(s, v8, &mb, tol, out),
        Err(_) => support_listed(s, &mb, tol, out),
    }
}

/// [`support_feature`] of a polytope of eight vertices `v8` (a box: the pyramid's and the
/// stack's edge pairs; `mb` the direction in its body frame): the same values and choice as
/// [`support_listed`], in fixed-size loops the compiler unrolls (no buffer to fill, no bounds
/// to check; unit test `eight_vertices_are_the_listed_path`).
#[inline]
fn support_eight(s: &Placed<'_>, v8: &[Vec3; 8], mb: &Vec3, tol: Real, out: &mut [Vec3]) -> usize {
    let dots: [Real; 8] = std::array::from_fn(|i| v8[i].dot(mb));
    let top = dots.iter().fold(Real::NEG_INFINITY, |t, d| t.max(*d));
    let mut k = 0;
    for (v, d) in v8.iter().zip(&dots) {
        if *d >= top - tol && k < out.len() {
            out[k] = s.world(v);
            k += 1;
        }
    }
    k
}

/// [`support_feature`] for any polytope (`mb`: the direction in its body frame).
fn support_listed(s: &Placed<'_>, mb: &Vec3, tol: Real, out: &mut [Vec3]) -> usize {
    let mb = *mb;
    let verts = s.poly.vertices();
    if verts.len() <= FEW_VERTICES {
        // Each vertex's value once (the same numbers the two passes below compute twice).
        let mut dots: ArrayVec<Real, FEW_VERTICES> = ArrayVec::new();
        let mut top = Real::NEG_INFINITY;
        for v in verts {
            let d = v.dot(&mb);
            top = top.max(d);
            dots.push(d);
        }
        let mut k = 0;
        for (v, d) in verts.iter().zip(&dots) {
            if *d >= top - tol && k < out.len() {
                out[k] = s.world(v);
                k += 1;
            }
        }
        return k;
    }
    let top = verts
        .iter()
        .map(|v| v.dot(&mb))
        .fold(Real::NEG_INFINITY, Real::max);
    let mut k = 0;
    for v in verts {
        if v.dot(&mb) >= top - tol && k < out.len() {
            out[k] = s.world(v);
            k += 1;
        }
    }
    k
}

/// The support feature of `s` in direction `m` (its points deepest below facet `face` of `f`,
/// whose outward world normal is `n`), clipped to that facet's prism: its deepest point (the
/// one farthest along `m`), or `None` when nothing of it lies in the prism.
fn deepest_in_prism(
    s: &Placed<'_>,
    m: &Vec3,
    f: &Placed<'_>,
    face: usize,
    n: &Vec3,
    tol: Real,
) -> Option<Vec3> {
    let mut pts = [Vec3::zeros(); MAX_POINTS];
    let mut k = support_feature(s, m, tol, &mut pts);
    // A face of three points or more: in order round its centroid (for clipping as a polygon).
    if k >= 3 {
        order(&mut pts[..k], m);
    }
    let corners = f.poly.facet_loop(face).filter(|l| l.len() >= 3)?;
    let mut buf = [Vec3::zeros(); MAX_POINTS];
    for (e, &c) in corners.iter().enumerate() {
        let q = f.world(&f.poly.vertices()[c as usize]);
        let q_next = f.world(&f.poly.vertices()[corners[(e + 1) % corners.len()] as usize]);
        let side = (q_next - q).cross(n);
        k = clip(&pts[..k], &side, side.dot(&q) + tol * side.norm(), &mut buf);
        pts[..k].copy_from_slice(&buf[..k]);
        if k == 0 {
            return None;
        }
    }
    pts[..k]
        .iter()
        .copied()
        .max_by(|x, y| x.dot(m).total_cmp(&y.dot(m)))
}

/// Orders points of a planar face counter-clockwise about `axis`.
fn order(pts: &mut [Vec3], axis: &Vec3) {
    let c = pts.iter().sum::<Vec3>() / pts.len() as Real;
    let u = (pts[0] - c).try_normalize(0.0).unwrap_or_else(Vec3::x);
    let v = axis.cross(&u);
    pts.sort_by(|x, y| {
        let (dx, dy) = (x - c, y - c);
        dx.dot(&v)
            .atan2(dx.dot(&u))
            .total_cmp(&dy.dot(&v).atan2(dy.dot(&u)))
    });
}

/// Keeps the part of the polygon (or segment, or point) `pts` where `side·x ≤ limit`
/// (Sutherland–Hodgman), into `out`; the number of points.
fn clip(pts: &[Vec3], side: &Vec3, limit: Real, out: &mut [Vec3; MAX_POINTS]) -> usize {
    let k = pts.len();
    let mut n = 0;
    let mut push = |p: Vec3| {
        if n < MAX_POINTS {
            out[n] = p;
            n += 1;
        }
    };
    if k == 1 {
        if side.dot(&pts[0]) <= limit {
            push(pts[0]);
        }
        return n;
    }
    let edges = if k == 2 { 1 } else { k };
    for i in 0..edges {
        let (p, q) = (pts[i], pts[(i + 1) % k]);
        let (sp, sq) = (side.dot(&p) - limit, side.dot(&q) - limit);
        if sp <= 0.0 {
            push(p);
        }
        if (sp < 0.0 && sq > 0.0) || (sp > 0.0 && sq < 0.0) {
            push(p + (q - p) * (sp / (sp - sq)));
        }
        if k == 2 && sq <= 0.0 {
            push(q);
        }
    }
    n
}

/// The closest points of shape 1's supporting edge at `n` and shape 2's at `−n`: shape 1's
/// point, when both features are edges and the points lie on them.
fn edge_witness(a: &Placed<'_>, b: &Placed<'_>, n: &Vec3, tol: Real) -> Option<Vec3> {
    // Three slots tell an edge (two points) from a face (more): no zeroed 48-point buffers.
    let mut ea = [Vec3::zeros(); 3];
    let mut eb = [Vec3::zeros(); 3];
    if support_feature(a, n, tol, &mut ea) != 2 || support_feature(b, &-n, tol, &mut eb) != 2 {
        return None;
    }
    let (p, u) = (ea[0], ea[1] - ea[0]);
    let (q, v) = (eb[0], eb[1] - eb[0]);
    let w = p - q;
    let (uu, uv, vv, uw, vw) = (u.dot(&u), u.dot(&v), v.dot(&v), u.dot(&w), v.dot(&w));
    let den = uu * vv - uv * uv;
    if !(den > 0.0) {
        return None;
    }
    let s = (uv * vw - vv * uw) / den;
    let t = (uu * vw - uv * uw) / den;
    let slack = tol / (uu.sqrt().min(vv.sqrt()));
    if !((-slack..=1.0 + slack).contains(&s) && (-slack..=1.0 + slack).contains(&t)) {
        return None;
    }
    Some(p + u * s.clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lcg;
    use crate::math::Pose;
    use crate::shapes::Shape;

    /// `two_boxes` as it was written before the edge axes were written out (the cross product,
    /// its norm and Cᵀl in full): the reference for `two_boxes`.
    fn two_boxes_full(
        ea: &Vec3,
        eb: &Vec3,
        c: &Mat3,
        t: &Vec3,
        beyond: Real,
    ) -> Result<(Real, Vec3, Axis), Real> {
        let abs = c.abs();
        let mut best = (Real::INFINITY, Vec3::zeros(), Axis::Face1(0));
        let mut keep = |v: Real, n: Vec3, axis: Axis| {
            if v < best.0 {
                best = (v, n, axis);
            }
            v < -beyond
        };
        for k in 0..3 {
            let rb = eb.x * abs[(k, 0)] + eb.y * abs[(k, 1)] + eb.z * abs[(k, 2)];
            let s = if t[k] < 0.0 { -1.0 } else { 1.0 };
            let v = ea[k] + rb - t[k].abs();
            let axis = Axis::Face1(k + if s < 0.0 { 3 } else { 0 });
            if keep(v, Vec3::ith(k, s), axis) {
                return Err(-v);
            }
        }
        for j in 0..3 {
            let col = c.column(j).into_owned();
            let ra = ea.x * abs[(0, j)] + ea.y * abs[(1, j)] + ea.z * abs[(2, j)];
            let tj = col.dot(t);
            let s = if tj < 0.0 { -1.0 } else { 1.0 };
            let v = ra + eb[j] - tj.abs();
            if keep(v, col * s, Axis::Face2(j + if s > 0.0 { 3 } else { 0 })) {
                return Err(-v);
            }
        }
        for i in 0..3 {
            for j in 0..3 {
                let l = Vec3::ith(i, 1.0).cross(&c.column(j));
                let len = l.norm();
                if !(len > PARALLEL) {
                    continue;
                }
                let m = c.tr_mul(&l);
                let ra = ea.x * l.x.abs() + ea.y * l.y.abs() + ea.z * l.z.abs();
                let rb = eb.x * m.x.abs() + eb.y * m.y.abs() + eb.z * m.z.abs();
                let lt = l.dot(t);
                let s = if lt < 0.0 { -1.0 } else { 1.0 };
                let v = (ra + rb - lt.abs()) / len;
                if keep(v, l * (s / len), Axis::Edges(len)) {
                    return Err(-v);
                }
            }
        }
        Ok(best)
    }

    /// `two_boxes` gives the full products' answers to the last bit (a zero's sign aside: the
    /// normals compared with `==`): 60 000 box pairs at random attitudes, quarter turns (exact
    /// zeros in C), tilts of 1e-3 to 1e-12 rad from a quarter turn (nearly parallel edges),
    /// overlapping, touching and apart, margins 0 and 0.05; a few with a non-finite centre.
    #[test]
    fn edge_axes_are_the_full_products() {
        let mut r = lcg(0xb0b0);
        let (mut faces, mut edges, mut apart) = (0, 0, 0);
        for case in 0..60_000 {
            let e = |r: &mut dyn FnMut() -> Real| {
                Vec3::new(0.1 + r().abs(), 0.1 + r().abs(), 0.1 + r().abs())
            };
            let (ea, eb) = (e(&mut r), e(&mut r));
            let quarter = |r: &mut dyn FnMut() -> Real| {
                let h = 0.5_f64.sqrt();
                let q = [
                    [1.0, 0.0, 0.0, 0.0],
                    [h, h, 0.0, 0.0],
                    [h, 0.0, h, 0.0],
                    [0.5, 0.5, 0.5, 0.5],
                ];
                q[(r().abs() * 4.0) as usize % 4]
            };
            let q = match case % 4 {
                0 => [r(), r(), r(), r()],
                1 => quarter(&mut r),
                _ => {
                    let [w, x, y, z] = quarter(&mut r);
                    let tilt = [1e-3, 1e-6, 1e-9, 1e-12][case / 4 % 4] * r();
                    let (a, b) = (tilt * r(), tilt * r());
                    [w - a * x, x + a * w + b * z, y + b * w, z - b * x]
                }
            };
            let c = *Pose::new([0.0; 3], q).unwrap().rotation();
            let reach = (ea + eb).norm();
            let mut t = Vec3::new(r(), r(), r()) * reach * [0.5, 1.0, 1.5][case % 3];
            if case % 1000 == 7 {
                t[case % 3] = [Real::INFINITY, Real::NAN][case / 1000 % 2];
            }
            let beyond = [0.0, 0.05][case % 2];
            let (a, b) = (
                two_boxes(&ea, &eb, &c, &t, beyond),
                two_boxes_full(&ea, &eb, &c, &t, beyond),
            );
            match (a, b) {
                (Ok((va, na, xa)), Ok((vb, nb, xb))) => {
                    assert_eq!(va.to_bits(), vb.to_bits(), "case {case}");
                    assert_eq!(na, nb, "case {case}");
                    match (xa, xb) {
                        (Axis::Face1(p), Axis::Face1(q)) | (Axis::Face2(p), Axis::Face2(q)) => {
                            assert_eq!(p, q, "case {case}");
                            faces += 1;
                        }
                        (Axis::Edges(p), Axis::Edges(q)) => {
                            assert_eq!(p.to_bits(), q.to_bits(), "case {case}");
                            edges += 1;
                        }
                        _ => panic!("case {case}: {xa:?} {xb:?}"),
                    }
                }
                (Err(ga), Err(gb)) => {
                    assert_eq!(ga.to_bits(), gb.to_bits(), "case {case}");
                    apart += 1;
                }
                _ => panic!("case {case}"),
            }
        }
        assert!(
            faces > 5_000 && edges > 2_000 && apart > 5_000,
            "{faces} {edges} {apart}"
        );
    }

    /// The support feature of an eight-vertex polytope (`support_eight`) is the listed path's,
    /// to the last bit: random boxes (and random hulls of eight points) at random attitudes, along
    /// random directions and along the body axes and face diagonals (where 2 and 4 vertices
    /// tie), tolerances 0 to 1e-3, outputs of 3 and 48 slots.
    #[test]
    fn eight_vertices_are_the_listed_path() {
        let mut r = lcg(0x5a7e1);
        let (mut cases, mut sizes) = (0, [0usize; 9]);
        for i in 0..6000 {
            let shape = if i % 4 == 3 {
                let pts: Vec<[Real; 3]> = (0..8)
                    .map(|k| {
                        let s = |b: usize| if k >> b & 1 == 1 { 1.0 } else { -1.0 };
                        [s(0) + 0.3 * r(), s(1) + 0.3 * r(), s(2) + 0.3 * r()]
                    })
                    .collect();
                Shape::convex_hull(&pts, 0.0).unwrap()
            } else {
                Shape::cuboid(0.6 + 0.5 * r(), 0.6 + 0.5 * r(), 0.6 + 0.5 * r()).unwrap()
            };
            let poly = shape.as_polytope().unwrap();
            if poly.vertices().len() != 8 {
                continue;
            }
            let pose = Pose::new([r(), r(), r()], [r(), r(), r(), r()]).unwrap();
            let rot = pose.rotation();
            let body = match i % 3 {
                0 => Vec3::new(r(), r(), r()),
                1 => Vec3::ith(i % 7 % 3, if r() < 0.0 { -1.0 } else { 1.0 }),
                _ => {
                    let (a, b) = (i % 3, (i + 1) % 3);
                    (Vec3::ith(a, 1.0) + Vec3::ith(b, r().signum())) * 0.5_f64.sqrt()
                }
            };
            let m = rot * body;
            let tol = [0.0, 1e-12, 1e-9, 1e-3][i % 4];
            let placed = Placed {
                poly,
                rot,
                pos: *pose.position(),
            };
            for slots in [3, 48] {
                let (mut a, mut b) = ([Vec3::zeros(); 48], [Vec3::zeros(); 48]);
                let ka = support_feature(&placed, &m, tol, &mut a[..slots]);
                let kb = support_listed(&placed, &rot.tr_mul(&m), tol, &mut b[..slots]);
                assert_eq!(ka, kb, "case {i}");
                for (p, q) in a[..ka].iter().zip(&b[..kb]) {
                    let bits = |v: &Vec3| v.map(Real::to_bits);
                    assert_eq!(bits(p), bits(q), "case {i}");
                }
                sizes[ka] += 1;
            }
            cases += 1;
        }
        assert!(cases > 5000, "{cases}");
        // Vertices, edges and faces all met.
        assert!(
            sizes[1] > 1000 && sizes[2] > 1000 && sizes[3] > 500,
            "{sizes:?}"
        );
    }
}
