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
            // The polytope's support below `SCAN_BOTH` vertices (the first vertex of largest
            // `v·m`, its value recomputed), without its dispatch.
            Body::Poly(p) if p.vertices().len() < SCAN_BOTH => {
                let verts = p.vertices();
                let (mut hi, mut top) = (0, Real::NEG_INFINITY);
                for (k, v) in verts.iter().enumerate() {
                    let d = v.dot(m);
                    if d > top {
                        top = d;
                        hi = k;
                    }
                }
                verts[hi].dot(m)
            }
            Body::Poly(p) => p.support_value(m),
        }
    }

    /// `(h(m), h(−m))`, bit for bit: a polytope of fewer than [`SCAN_BOTH`] vertices in one scan
    /// (the first vertex of largest and of least `v·m`: `v·(−m)` is `−(v·m)` exactly, so the
    /// second is the first of largest `v·(−m)`, the vertex `h(−m)` takes), each value computed as
    /// `h` computes it; other shapes by `h` twice.
    #[inline]
    fn h_both(&self, m: &Vec3) -> (Real, Real) {
        match self {
            Body::Poly(p) if p.vertices().len() < SCAN_BOTH => {
                let verts = p.vertices();
                let (mut hi, mut lo) = (0, 0);
                let (mut top, mut bottom) = (Real::NEG_INFINITY, Real::INFINITY);
                for (k, v) in verts.iter().enumerate() {
                    let d = v.dot(m);
                    if d > top {
                        top = d;
                        hi = k;
                    }
                    if d < bottom {
                        bottom = d;
                        lo = k;
                    }
                }
                (verts[hi].dot(m), verts[lo].dot(&-m))
            }
            _ => (self.h(m), self.h(&-m)),
        }
    }
}

/// Below this many vertices a polytope's support is a scan of its vertices (the polytope's
/// climb starts at 24, `shapes::polytope::CLIMB_MIN`), which [`Body::h_both`] does once for
/// both signs. Where a climb answers instead, the scan's value is the largest computed `v·m`,
/// never below the climb's.
const SCAN_BOTH: usize = 24;

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
            let (hap, han) = ha.h_both(&n);
            let (hbp, hbn) = hb.h_both(&m);
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
    let mut keep = |v: Real, n: (Vec3, Axis)| {
        if v < best.0 {
            best = (v, n.0, n.1);
        }
        v < -beyond
    };
    for k in 0..3 {
        let rb = eb.x * abs[(k, 0)] + eb.y * abs[(k, 1)] + eb.z * abs[(k, 2)];
        let s = if t[k] < 0.0 { -1.0 } else { 1.0 };
        let v = ea[k] + rb - t[k].abs();
        if keep(
            v,
            (
                Vec3::ith(k, s),
                Axis::Face1(k + if s < 0.0 { 3 } else { 0 }),
            ),
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
        if keep(v, (col * s, Axis::Face2(j + if s > 0.0 { 3 } else { 0 }))) {
            return Err(-v);
        }
    }
    // The nine edge axes l = e_i × c_j, written out: l_i = 0, l_{i+1} = −c_{i+2,j},
    // l_{i+2} = c_{i+1,j}. The terms of l_i are exact zeros (every number here is finite but
    // `t`), so |l|, Cᵀl, the radii and l·t are the full products' to the last bit (a zero's sign
    // aside); `0·t_i` is still added to l·t, so a non-finite `t` gives what it gave. The
    // component j of m = Cᵀl is `c_{i+1,j}·(−c_{i+2,j}) + c_{i+2,j}·c_{i+1,j}`, an exact zero
    // (the two products are the same number), so its term of the radius is left out: adding
    // `+0` to a non-negative sum leaves it as it is.
    // Written out nine times (indices known at compile time: no index arithmetic or checks).
    macro_rules! edge {
        ($i:literal, $i1:literal, $i2:literal; $j:literal, $lo:literal, $hi:literal) => {
            let (a, b) = (-c[($i2, $j)], c[($i1, $j)]);
            let len = (a * a + b * b).sqrt();
            if len > PARALLEL {
                let m_lo = c[($i1, $lo)] * a + c[($i2, $lo)] * b;
                let m_hi = c[($i1, $hi)] * a + c[($i2, $hi)] * b;
                let ra = ea[$i1] * a.abs() + ea[$i2] * b.abs();
                let rb = eb[$lo] * m_lo.abs() + eb[$hi] * m_hi.abs();
                let lt = (a * t[$i1] + b * t[$i2]) + 0.0 * t[$i];
                let s = if lt < 0.0 { -1.0 } else { 1.0 };
                let v = (ra + rb - lt.abs()) / len;
                if v < best.0 {
                    // Formed only for a new best.
                    best = (v, edge_axis($i, a, b) * (s / len), Axis::Edges(len));
                }
                if v < -beyond {
                    return Err(-v);
                }
            }
        };
    }
    edge!(0, 1, 2; 0, 1, 2);
    edge!(0, 1, 2; 1, 0, 2);
    edge!(0, 1, 2; 2, 0, 1);
    edge!(1, 2, 0; 0, 1, 2);
    edge!(1, 2, 0; 1, 0, 2);
    edge!(1, 2, 0; 2, 0, 1);
    edge!(2, 0, 1; 0, 1, 2);
    edge!(2, 0, 1; 1, 0, 2);
    edge!(2, 0, 1; 2, 0, 1);
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

/// Orders points of a planar face counter-clockwise about `axis` (at most [`MAX_POINTS`]).
fn order(pts: &mut [Vec3], axis: &Vec3) {
    let c = pts.iter().sum::<Vec3>() / pts.len() as Real;
    let u = (pts[0] - c).try_normalize(0.0).unwrap_or_else(Vec3::x);
    let v = axis.cross(&u);
    // Each point's angle once (a comparator computing both angles took two `atan2` per
    // comparison); a stable sort on the same keys gives the same order.
    // (No zeroed buffer: only the points written.)
    let mut keyed: arrayvec::ArrayVec<(Real, Vec3), MAX_POINTS> = arrayvec::ArrayVec::new();
    for p in pts.iter().take(MAX_POINTS) {
        let d = p - c;
        keyed.push((d.dot(&v).atan2(d.dot(&u)), *p));
    }
    keyed.sort_by(|x, y| x.0.total_cmp(&y.0));
    for (p, slot) in pts.iter_mut().zip(&keyed) {
        *p = slot.1;
    }
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
#[path = "sat_tests.rs"]
mod tests;
