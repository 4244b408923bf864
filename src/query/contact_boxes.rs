//! The contact manifold of two boxes in closed form, the pair rigid-body scenes meet most (a
//! stack, a pyramid, a wall): the separating axes (`crate::solver::sat`) give the depth and
//! the normal; when a facet's axis wins, the other box's face most opposed to the normal is
//! clipped to that facet's rectangle in the facet's own frame (four axis-aligned edges), each
//! clipped point with its depth below the facet. The same manifold as the general path (the
//! signed distance, then the faces facing each other clipped in the plane orthogonal to the
//! normal, which for a facet's axis is the facet's plane), without its generality.
//!
//! Answers boxes that overlap, touch, or are apart by less than the margin across a facet (a
//! clipped point as far from the facet as the facet's axis separates the boxes: that is their
//! distance), and boxes apart along an axis by more than the margin (no contact). Overlapping
//! boxes whose least axis is an edge pair (boxes nearly face to face and slightly turned, as in
//! a settling stack or pyramid) get the signed distance the general path computes for them (the
//! separating axes' edge witnesses, `crate::solver::sat::box_edges`) without computing the
//! axes a second time, and the general path's points computed in the reference box's frame
//! (`edge_pair`). Apart boxes whose nearest points are not across a facet are the general
//! path's.

use super::context::DistancePath;
use super::context::SignedDistance;
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::Shape;
use crate::solver::sat::{self, two_boxes, Axis, Placed};
use crate::solver::SolveStatus;
use arrayvec::ArrayVec;

/// Clipped points: an incident quadrilateral clipped by four edges has at most 8.
pub(crate) const MAX: usize = 8;
/// The incident box's face is used when its normal is within about 72 degrees of the
/// reference facet's (as the general path's `COS_FACET`).
const COS_FACET: Real = 0.3;
/// Relative tolerance (of the boxes' size) on the depth of the points kept, as the general
/// path's.
const SEP_TOL: Real = 1e-9;

/// A closed-form manifold: the signed distance and the candidate points (world positions
/// midway between the surfaces, and their depths), in the form `super::contact::finish` reads.
pub(crate) struct Boxes {
    pub sd: SignedDistance,
    pub pos: ArrayVec<Vec3, MAX>,
    pub depth: ArrayVec<Real, MAX>,
}

impl Boxes {
    /// No points yet (filled by [`boxes`]).
    pub(crate) fn new() -> Boxes {
        apart(0.0)
    }
}

/// What [`boxes`] found.
pub(crate) enum End {
    /// The closed-form manifold (written to `boxes`' `out`: the points are not moved between
    /// the layers, which cost 125 instructions a pyramid call in copies).
    Closed,
    /// Overlapping boxes whose least axis is an edge pair: the signed distance the general path
    /// computes for them (its points are the general path's to find).
    Edges(SignedDistance),
    /// The general path answers.
    General,
}

/// Two centred boxes `shape1`, `shape2` of half extents `h1`, `h2` at `pose1`, `pose2`: their
/// manifold within `margin` (in `out`), the signed distance of an edge-pair overlap, or the
/// general path (`scale`: the boxes' size; `out` is then partly written, to be ignored).
#[allow(clippy::too_many_arguments)]
pub(crate) fn boxes(
    shape1: &Shape,
    h1: &Vec3,
    pose1: &Pose,
    shape2: &Shape,
    h2: &Vec3,
    pose2: &Pose,
    margin: Real,
    scale: Real,
    out: &mut Boxes,
) -> End {
    out.pos.clear();
    out.depth.clear();
    let (r1, r2) = (pose1.rotation(), pose2.rotation());
    let c = r1.tr_mul(r2);
    let t = r1.tr_mul(&(pose2.position() - pose1.position()));
    let (depth, n, axis) = match two_boxes(h1, h2, &c, &t, margin) {
        Ok(best) => best,
        // Separated along an axis by more than the margin: no contact at all.
        Err(gap) => {
            out.sd = apart(gap).sd;
            return End::Closed;
        }
    };
    // The reference facet's box, frame and facet, and the incident box in that frame.
    let (k, s, first) = match axis {
        Axis::Face1(k) => (k % 3, if k < 3 { 1.0 } else { -1.0 }, true),
        Axis::Face2(k) => (k % 3, if k < 3 { 1.0 } else { -1.0 }, false),
        Axis::Edges(len) => {
            let end = edges(shape1, pose1, shape2, pose2, (depth, n, len), scale);
            if let End::Edges(sd) = &end {
                let pair = ((h1, pose1), (h2, pose2), (&c, &t));
                if edge_pair(pair, &n, sd, margin, scale, out) {
                    out.sd = *sd;
                    return End::Closed;
                }
            }
            return end;
        }
    };
    let (href, hinc, pref, cinc, tinc) = if first {
        (h1, h2, pose1, c, t)
    } else {
        (h2, h1, pose2, c.transpose(), -c.tr_mul(&t))
    };
    let (mut pts, plane) = clip_to_facet(href, hinc, &cinc, &tinc, k, s);
    // Each candidate's depth below the facet; those at least `−margin` deep are kept, in
    // place (`pts` holds at most MAX points).
    let mut depths = [0.0; MAX];
    let mut kept = 0;
    for a in 0..pts.len.min(MAX) {
        let p = pts.pts[a];
        let d = plane - s * p[k];
        if d >= -margin {
            pts.pts[kept] = p;
            depths[kept] = d;
            kept += 1;
        }
    }
    let inc = &pts.pts[..kept];
    let depths = &depths[..kept];
    // The deepest clipped point is the overlap's depth (the facet's axis won: the nearest
    // facet of the difference, whose nearest point lies on it). Apart by less than the margin
    // (`depth < 0`), the axis's gap is a lower bound on the distance, and the distance when a
    // clipped point is that far and no farther. To rounding, else the general path decides.
    let deepest = depths.iter().fold(Real::NEG_INFINITY, |m, d| m.max(*d));
    if !((deepest - depth).abs() <= 1e-9 * scale) {
        return End::General;
    }
    // World: the reference facet's outward normal, from shape 1 to shape 2 when the facet is
    // shape 1's.
    let rot = pref.rotation();
    let facet = rot.column(k) * s;
    let normal = if first { facet } else { -facet };
    let world = |p: &Vec3| pref.position() + rot * p;
    let (pos, dep) = (&mut out.pos, &mut out.depth);
    // The last point as deep as `deepest` gives the witnesses.
    let mut at = 0;
    for (i, (p, d)) in inc.iter().zip(depths).enumerate() {
        // `p` on the incident box's face; its foot on the reference facet's plane is `p + d·e`.
        pos.push(world(&(p + Vec3::ith(k, s) * (0.5 * d))));
        dep.push(*d);
        if *d == deepest {
            at = i;
        }
    }
    // `kept ≥ 1` here (else `deepest` is −∞ and the general path answered).
    let (p, d) = (inc[at], depths[at]);
    let (w_inc, w_ref) = (world(&p), world(&(p + Vec3::ith(k, s) * d)));
    let (closest1, closest2) = if first {
        (w_ref, w_inc)
    } else {
        (w_inc, w_ref)
    };
    if !((closest2 - closest1 + normal * depth).norm() <= 1e-9 * scale) {
        return End::General;
    }
    out.sd = SignedDistance {
        distance: -depth,
        normal,
        closest1,
        closest2: closest1 - normal * depth,
        iterations: 0,
        status: SolveStatus::Converged,
        path: DistancePath::SeparatingAxes,
    };
    End::Closed
}

/// Overlapping boxes (`depth ≥ 0`: every axis overlaps) whose least axis is the edge pair of
/// cross-product length `len` and unit normal `n` (shape 1's frame): the signed distance of the
/// general path (`super::signed`'s separating axes: `two_boxes` without a margin finds the same
/// least axis when every axis overlaps, then the edges' witnesses), or [`End::General`] where
/// that path does not answer by the separating axes (boxes apart by less than the margin, ill
/// conditioned or unwitnessed edges).
fn edges(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    (depth, n, len): (Real, Vec3, Real),
    scale: Real,
) -> End {
    let (Some(p1), Some(p2)) = (shape1.as_polytope(), shape2.as_polytope()) else {
        return End::General;
    };
    if !(depth >= 0.0) {
        return End::General;
    }
    let a = Placed {
        poly: p1,
        rot: pose1.rotation(),
        pos: *pose1.position(),
    };
    let b = Placed {
        poly: p2,
        rot: pose2.rotation(),
        pos: *pose2.position(),
    };
    let Some(o) = sat::box_edges(&a, &b, depth, pose1.rotation() * n, len, scale) else {
        return End::General;
    };
    // As `super::signed`'s separating axes write it (no padding).
    let (pad1, pad2) = (0.0, 0.0);
    let n = o.normal;
    End::Edges(SignedDistance {
        distance: -(o.depth + pad1 + pad2),
        normal: n,
        closest1: o.closest1 + n * pad1,
        closest2: o.closest2 - n * pad2,
        iterations: 0,
        status: SolveStatus::Converged,
        path: DistancePath::SeparatingAxes,
    })
}

/// No contact: the boxes are apart by `gap` (more than the margin) along an axis.
fn apart(gap: Real) -> Boxes {
    Boxes {
        sd: SignedDistance {
            distance: gap,
            normal: Vec3::zeros(),
            closest1: Vec3::zeros(),
            closest2: Vec3::zeros(),
            iterations: 0,
            status: SolveStatus::Converged,
            path: DistancePath::SeparatingAxes,
        },
        pos: ArrayVec::new(),
        depth: ArrayVec::new(),
    }
}

/// In the reference box's frame: the incident box (half extents `hinc`, axes the columns of
/// `c`, centre `t`)'s face most opposed to the reference facet `s·e_k`, clipped to the facet's
/// rectangle (or its corner, when no face is within about 72 degrees), points on the incident
/// face; and the facet's plane `s·x_k = href_k` (`href_k`). A point's depth below the facet is
/// `href_k − s·p_k`.
fn clip_to_facet(
    href: &Vec3,
    hinc: &Vec3,
    c: &Mat3,
    t: &Vec3,
    k: usize,
    s: Real,
) -> (Polygon, Real) {
    // The incident face: the axis j most aligned with the facet's normal, on the side facing it.
    let j = (0..3)
        .max_by(|&a, &b| c[(k, a)].abs().total_cmp(&c[(k, b)].abs()))
        .unwrap_or(0);
    let sign = if c[(k, j)] * s > 0.0 { -1.0 } else { 1.0 };
    let plane = href[k];
    let mut poly = Polygon::new();
    if c[(k, j)].abs() < COS_FACET {
        // No face of the incident box within about 72 degrees of the normal: its corner (the
        // general path's feature too).
        let corner = (0..3).fold(*t, |p, a| {
            let side = if c[(k, a)] * s > 0.0 { -1.0 } else { 1.0 };
            p + c.column(a) * (side * hinc[a])
        });
        poly.pts[0] = corner;
        poly.len = 1;
        return (poly, plane);
    }
    let centre = t + c.column(j) * (sign * hinc[j]);
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    let (u, v) = (c.column(j1) * hinc[j1], c.column(j2) * hinc[j2]);
    poly.quad([
        centre + u + v,
        centre - u + v,
        centre - u - v,
        centre + u - v,
    ]);
    clip_rect(&mut poly, href, k);
    (poly, plane)
}

/// A polygon of at most [`MAX`] points in fixed storage (the clipping's buffers: no capacity
/// test per point as an `ArrayVec`'s push, no copy between buffers at the end).
#[derive(Clone, Copy)]
struct Polygon {
    pts: [Vec3; MAX],
    len: usize,
}

impl Polygon {
    fn new() -> Polygon {
        Polygon {
            pts: [Vec3::zeros(); MAX],
            len: 0,
        }
    }

    /// The quadrilateral `q` (in order).
    #[inline(always)]
    fn quad(&mut self, q: [Vec3; 4]) {
        self.pts[..4].copy_from_slice(&q);
        self.len = 4;
    }

    fn points(&self) -> &[Vec3] {
        &self.pts[..self.len.min(MAX)]
    }
}

/// Clips the polygon `poly` (in a box's frame), in place, to `|p_i| ≤ href_i` for the two axes
/// `i ≠ k` (two buffers taking turns), emptied when nothing is left. Each edge `(p, q)` in
/// order, `p`'s value carried over from the edge before (no indexing, one evaluation per point).
/// A side with every point within it (a pass that would copy them in order) is skipped.
#[inline(always)]
fn clip_rect(poly: &mut Polygon, href: &Vec3, k: usize) {
    let mut tmp = Polygon::new();
    let (mut cur, mut next) = (poly, &mut tmp);
    let mut turns = 0;
    for i in [(k + 1) % 3, (k + 2) % 3] {
        let h = href[i];
        for side in [1.0, -1.0] {
            let f = |p: &Vec3| side * p[i] - h;
            let n = cur.len.min(MAX);
            if n == 0 {
                return;
            }
            let first = cur.pts[0];
            if cur.pts[..n].iter().all(|p| f(p) <= 0.0) {
                continue;
            }
            let mut m = 0;
            let (mut p, mut fp) = (first, f(&first));
            for a in 1..=n {
                let q = if a < n { cur.pts[a] } else { first };
                let fq = f(&q);
                if fp <= 0.0 && m < MAX {
                    next.pts[m] = p;
                    m += 1;
                }
                if ((fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0)) && m < MAX {
                    next.pts[m] = p + (q - p) * (fp / (fp - fq));
                    m += 1;
                }
                (p, fp) = (q, fq);
            }
            if m == 0 {
                // Nothing left (in `poly` either way).
                cur.len = 0;
                next.len = 0;
                return;
            }
            next.len = m;
            std::mem::swap(&mut cur, &mut next);
            turns += 1;
        }
    }
    if turns % 2 == 1 {
        // The result is in `tmp`: back to `poly`.
        let n = cur.len.min(MAX);
        next.pts[..n].copy_from_slice(&cur.pts[..n]);
        next.len = n;
    }
}

/// Two boxes' half extents and poses, and shape 2's attitude and centre in shape 1's frame.
type BoxPair<'a> = (
    (&'a Vec3, &'a Pose),
    (&'a Vec3, &'a Pose),
    (&'a Mat3, &'a Vec3),
);

/// The box pair `((h1, pose1), (h2, pose2), (c, t))` (shape 2's attitude and centre in shape
/// 1's frame), overlapping with an edge pair as its least axis, of unit normal `n` (shape 1's
/// frame) and signed distance `sd` (`edges`' answer, witnesses finite): the points the general
/// path finds for it, in closed form (the face of each box facing the other along `n`, the
/// incident one clipped to the reference one in the plane orthogonal to `n`, each point lifted
/// along `n` onto both faces). Computed in the reference box's frame: the incident face moved
/// along `n` onto the reference facet's plane (an affine image of the plane orthogonal to `n`,
/// so the same clipping), clipped to its rectangle, and lifted along `n` onto the incident
/// face; written to `out`'s points). False (the general path answers) when a face is more
/// than about 72 degrees from `n` or no point is as deep as `sd` (the general path then adds
/// the witness).
fn edge_pair(
    pair: BoxPair<'_>,
    n: &Vec3,
    sd: &SignedDistance,
    margin: Real,
    scale: Real,
    out: &mut Boxes,
) -> bool {
    edge_points(pair, n, sd, margin, scale, out).is_some()
}

/// [`edge_pair`], `None` for false.
fn edge_points(
    ((h1, pose1), (h2, pose2), (c, t)): BoxPair<'_>,
    n: &Vec3,
    sd: &SignedDistance,
    margin: Real,
    scale: Real,
    out: &mut Boxes,
) -> Option<()> {
    let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
    if !(sd.distance <= 0.0 && finite(&sd.closest1) && finite(&sd.closest2)) {
        return None;
    }
    let n = *n;
    // Each box's facet facing the other along n, and its alignment |face·n|.
    let k1 = (0..3).max_by(|&a, &b| n[a].abs().total_cmp(&n[b].abs()))?;
    let n2 = -c.tr_mul(&n); // −n in shape 2's frame
    let k2 = (0..3).max_by(|&a, &b| n2[a].abs().total_cmp(&n2[b].abs()))?;
    if n[k1].abs() < COS_FACET || n2[k2].abs() < COS_FACET {
        return None;
    }
    // The reference face is the better aligned one (shape 1's on a tie); in its box's frame,
    // `d` is the contact normal pointing out of it (n for shape 1, −n for shape 2).
    let first = n[k1].abs() >= n2[k2].abs();
    let (href, hinc, pref, cinc, tinc, d, k) = if first {
        (h1, h2, pose1, *c, *t, n, k1)
    } else {
        (h2, h1, pose2, c.transpose(), -c.tr_mul(t), n2, k2)
    };
    let s = d[k].signum();
    // The incident box's face most opposed to d.
    let dinc = cinc.tr_mul(&d);
    let j = (0..3).max_by(|&a, &b| dinc[a].abs().total_cmp(&dinc[b].abs()))?;
    let sign = if dinc[j] > 0.0 { -1.0 } else { 1.0 };
    let face = cinc.column(j) * sign;
    let centre = tinc + face * hinc[j];
    let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
    let (u, v) = (cinc.column(j1) * hinc[j1], cinc.column(j2) * hinc[j2]);
    // Its corners moved along d onto the reference facet's plane x_k = s·href_k.
    let plane = s * href[k];
    let mut poly = Polygon::new();
    poly.quad(
        [
            centre + u + v,
            centre - u + v,
            centre - u - v,
            centre + u - v,
        ]
        .map(|p| p + d * ((plane - p[k]) / d[k])),
    );
    clip_rect(&mut poly, href, k);
    if poly.len == 0 {
        return None;
    }
    let df = d.dot(&face);
    let rot = pref.rotation();
    let world = |p: &Vec3| pref.position() + rot * p;
    let keep = margin + SEP_TOL * scale;
    let (pos, depth) = (&mut out.pos, &mut out.depth);
    let mut deepest = Real::NEG_INFINITY;
    for q in poly.points() {
        // `q` on the reference face, `b` on the incident face's plane along d.
        let b = q + d * ((centre - q).dot(&face) / df);
        let e = (q - b).dot(&d);
        if -e <= keep {
            pos.push(world(&(q + (b - q) * 0.5)));
            depth.push(e);
            deepest = deepest.max(e);
        }
    }
    if !(deepest >= -sd.distance - SEP_TOL * scale) {
        return None;
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::query::test_support::lcg;

    /// The rectangle clipping as it was written before (each edge's two points read by index
    /// and both values computed per edge): the reference for `clip_rect`.
    fn clip_rect_indexed(poly: &mut ArrayVec<Vec3, MAX>, href: &Vec3, k: usize) -> bool {
        let mut tmp: ArrayVec<Vec3, MAX> = ArrayVec::new();
        let (mut cur, mut next) = (poly, &mut tmp);
        for i in [(k + 1) % 3, (k + 2) % 3] {
            for side in [1.0, -1.0] {
                next.clear();
                let n = cur.len();
                for a in 0..n {
                    let (p, q) = (cur[a], cur[if a + 1 == n { 0 } else { a + 1 }]);
                    let (fp, fq) = (side * p[i] - href[i], side * q[i] - href[i]);
                    if fp <= 0.0 {
                        let _ = next.try_push(p);
                    }
                    if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
                        let _ = next.try_push(p + (q - p) * (fp / (fp - fq)));
                    }
                }
                std::mem::swap(&mut cur, &mut next);
                if cur.is_empty() {
                    return false;
                }
            }
        }
        true
    }

    /// `clip_rect` gives the indexed clipping's points, in the same order, to the last bit:
    /// 20 000 random parallelograms (incident faces) against random rectangles, some inside,
    /// some cut on every side, some missing the rectangle, corners on the rectangle's edges.
    #[test]
    fn clip_rect_is_the_indexed_clipping() {
        let mut r = lcg(0xc11b0c5);
        let (mut cut, mut empty, mut sizes) = (0, 0, [0usize; MAX + 1]);
        for case in 0..20_000 {
            let href = Vec3::new(0.2 + r().abs(), 0.2 + r().abs(), 0.2 + r().abs());
            let k = case % 3;
            let spread = [0.3, 1.0, 3.0][case / 3 % 3];
            let centre = Vec3::new(r(), r(), r()) * spread;
            let (u, v) = (Vec3::new(r(), r(), r()), Vec3::new(r(), r(), r()));
            let mut poly: ArrayVec<Vec3, MAX> = ArrayVec::new();
            for p in [
                centre + u + v,
                centre - u + v,
                centre - u - v,
                centre + u - v,
            ] {
                poly.push(p);
            }
            if case % 5 == 0 {
                // A corner exactly on an edge of the rectangle (a value of 0).
                let i = (k + 1) % 3;
                poly[0][i] = href[i];
            }
            let mut reference = poly.clone();
            let mut fixed = Polygon::new();
            fixed.quad([poly[0], poly[1], poly[2], poly[3]]);
            clip_rect(&mut fixed, &href, k);
            let b = clip_rect_indexed(&mut reference, &href, k);
            assert_eq!(fixed.len > 0, b, "case {case}");
            if !b {
                empty += 1;
                continue;
            }
            assert_eq!(fixed.len, reference.len(), "case {case}");
            for (p, q) in fixed.points().iter().zip(&reference) {
                assert_eq!(p.map(Real::to_bits), q.map(Real::to_bits), "case {case}");
            }
            cut += usize::from(fixed.len != 4);
            sizes[fixed.len] += 1;
        }
        assert!(cut > 5_000 && empty > 500, "{cut} {empty} {sizes:?}");
        assert!(sizes[3] > 0 && sizes[5] > 0 && sizes[8] > 0, "{sizes:?}");
    }
}
