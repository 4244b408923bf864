//! α* of a padded pair (a sphere, capsule or padded polygon against a polytope, a box or
//! another of those) on its polyhedral cores: GJK from a point of the ray, then the exact
//! value on the feature it found.
//!
//! With `Q = C₁ ⊕ (−C₂)` the cores' Minkowski difference (a sphere's core is its centre, a
//! capsule's its segment, a padded polygon's its plane polygon) and `ρ` the radii summed, `K = Q ⊕ B(ρ)` and α* is the least α with
//! `dist(r, αQ) ≤ αρ`, i.e. `dist(x, Q) = ρ` at `x = r/α*`. Each round runs GJK from `x = r/α`
//! to the point `q` of Q nearest it (warm-started from the previous round's simplex; on
//! polyhedral cores GJK ends exactly) and certifies, in normalised units:
//!
//! - **Lower bound**: for any unit `n` with `n·r > 0`, `α* ≥ n·r/(h_Q(n) + ρ)` (the gauge of K
//!   is the maximum of that over n); GJK's own support calls give it at `n = (x − q)/‖x − q‖`.
//! - **Upper bound**: for any `q ∈ Q` the ball `q + B(ρ)` lies in K, so α* is at most the least
//!   α with `‖r − αq‖ = αρ` (the ray's exit from that ball).
//!
//! The next α is the exact value on the simplex GJK ended on (a vertex, an edge's line or a
//! face's plane of Q, padded by ρ): on the right feature both bounds then meet to rounding,
//! so a pair typically ends after one GJK run and one support call. Elsewhere a Newton step
//! on `t ↦ dist(t r, Q) − ρ` (convex in `t = 1/α`) takes its place.
//!
//! A closed bracket alone does not make the point right: the ball bound pins α to second
//! order in the point, so a GJK run that stalled on rounding a little off the contact feature
//! (a simplex weight of 1e-4, say) still closes the bracket to 1e-12 with a point 1e-6 off.
//! An answer is accepted only when GJK's last support point lies no farther than rounding
//! beyond its point along its normal (the normal supports Q there) and the point was found at
//! the α reported; otherwise the simplex and each of its faces are solved exactly and
//! certified in turn (`settle_faces`).

use super::simplex::{keep, masked_point, nearest, reduce};
use super::Pt;
use crate::math::{Real, Vec3};
use crate::shapes::SupportMap;
use crate::solver::raycast::{Pair, Stop, Vertex};

/// Rounds (GJK runs at a new point of the ray).
const ROUNDS: u32 = 8;
/// GJK iterations per round.
const GJK_BUDGET: u32 = 40;
/// A normal supports Q at a point when no support point lies farther beyond it than this
/// (normalised units, relative to `1 + ‖q‖`): the rounding of the products.
const GAP_TOL: Real = 1e-13;
/// The relative bracket below which the simplex's features are certified one by one.
const NARROW: Real = 1e-6;

/// A certified answer on the cores (normalised units).
#[derive(Clone, Copy, Debug)]
pub(crate) struct PaddedHit {
    /// The upper bound, the value reported: the exit from the ball about `a − b`.
    pub alpha: Real,
    /// The unit normal from Q towards the ray's point at `alpha` (from shape 1 to shape 2).
    pub normal: Vec3,
    /// The cores' witnesses (relative to their origins): `a − b ∈ Q` is the point of Q
    /// nearest `r/alpha`.
    pub a: Vec3,
    pub b: Vec3,
}

/// How the padded cast ended.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PaddedEnd {
    Hit(PaddedHit),
    /// The bracket excluded the threshold: α' below it (`true`) or above it, with the
    /// bracket's end on that side and the unit normal whose support bound gave the lower end
    /// (a separating direction of the scaled shapes when above).
    Decided(bool, Real, Vec3),
    /// No certificate (a degenerate simplex, or the rounds ran out).
    Failed,
}

/// α' of the padded pair whose cores are `pair`, for the unit ray `r` and the radii summed
/// `rho > 0`, closing the bracket to `rel_tol·α'`; stops early on `stop` as the ray cast does.
/// The cores must be polyhedral (polytopes, plane polygons, segments, points) with the origin
/// in Q (a plane polygon holds it in its relative interior; ρ > 0 puts it inside K).
pub(crate) fn padded_cast<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    rho: Real,
    rel_tol: Real,
    stop: Option<Stop>,
) -> PaddedEnd {
    let first = pair.support(r);
    let den = r.dot(&first.w) + rho;
    if !(den > 0.0) {
        return PaddedEnd::Failed;
    }
    let mut lo = 1.0 / den;
    // The normal of `lo`'s bound.
    let mut lo_n = *r;
    let mut hi = Real::INFINITY;
    let mut best = PaddedHit {
        alpha: Real::INFINITY,
        normal: *r,
        a: first.a,
        b: first.b,
    };
    // A threshold is decided as soon as the bounds allow: GJK's support bounds from below, the
    // ball about any point of Q it passes from above (the support point along r first).
    let decide = |lo: Real, hi: Real, lo_n: Vec3| {
        let s = stop?;
        if lo > s.value {
            Some(PaddedEnd::Decided(false, lo, lo_n))
        } else if s.stop_below && hi < s.value {
            Some(PaddedEnd::Decided(true, hi, lo_n))
        } else {
            None
        }
    };
    if stop.is_some() {
        let up = ball_exit(r, &first.w, rho);
        if let Some(end) = decide(lo, up, lo_n) {
            return end;
        }
    }
    let mut alpha = lo;
    let mut simplex = [Pt::default(); 4];
    let mut wts = [0.0; 4];
    simplex[0].v = first;
    let mut k = 1;
    for _ in 0..ROUNDS {
        let x = r / alpha;
        for p in simplex[..k].iter_mut() {
            p.c = x - p.v.w;
        }
        let Some(nk) = reduce(&mut simplex, &mut wts, k) else {
            return PaddedEnd::Failed;
        };
        k = nk;
        let mut v = combine(&simplex[..k], &wts[..k]);
        // How far GJK's last support point lies beyond its nearest point along the normal.
        let mut gap = Real::INFINITY;
        for _ in 0..GJK_BUDGET {
            let vv = v.norm_squared();
            if !(vv > 0.0) {
                return PaddedEnd::Failed;
            }
            let n = v / vv.sqrt();
            let vtx = pair.support(&n);
            let (nr, den) = (n.dot(r), n.dot(&vtx.w) + rho);
            if nr > 0.0 && den > 0.0 && nr / den > lo {
                (lo, lo_n) = (nr / den, n);
            }
            let c = x - vtx.w;
            gap = n.dot(&(v - c));
            // The new point adds nothing beyond v's plane (to rounding): v is the nearest.
            if vv - v.dot(&c) <= 1e-14 * vv {
                break;
            }
            // The new point goes in slot k, past the simplex: the simplex changes only once
            // the step is known to make progress (no copy to restore).
            simplex[k] = Pt { c, v: vtx };
            let Some((mask, wk)) = nearest(&simplex, k + 1) else {
                return PaddedEnd::Failed;
            };
            let nv = masked_point(&simplex, k + 1, mask, &wk);
            if !(nv.norm_squared() < vv) {
                // Rounding: GJK stalls here, its point possibly off the contact feature.
                break;
            }
            k = keep(&mut simplex, &mut wts, k + 1, mask, &wk);
            v = nv;
            gap = Real::INFINITY;
            if stop.is_some() {
                let q = x - v;
                let up = ball_exit(r, &q, rho);
                if let Some(end) = decide(lo, up, lo_n) {
                    return end;
                }
            }
        }
        let mut pts = [Vertex::default(); 3];
        for (p, s) in pts.iter_mut().zip(&simplex[..k]) {
            *p = s.v;
        }
        let pts = &pts[..k];
        // GJK's nearest point q = x − v of Q bounds α' from above.
        let q = point(pts, &wts[..k]);
        let up = ball_exit(r, &q.w, rho);
        let this = (r / up - q.w).try_normalize(0.0).map(|normal| PaddedHit {
            alpha: up,
            normal,
            a: q.a,
            b: q.b,
        });
        if up < hi {
            hi = up;
            best = this.unwrap_or(best);
        }
        if let Some(end) = decide(lo, hi, lo_n) {
            return end;
        }
        // Closed, GJK's normal supporting Q at its point, and the point found from the ray's
        // point at the value reported: exact. (The bracket pins α' to second order in the
        // point, so a closed bracket alone does not make the point right.)
        let closed = hi - lo <= rel_tol * lo;
        let exact = gap <= GAP_TOL * (1.0 + q.w.norm());
        if closed && exact && (up - alpha).abs() <= 16.0 * Real::EPSILON * alpha {
            // This round's point (an earlier one may have given the same bound to rounding).
            if let Some(h) = this {
                return PaddedEnd::Hit(h);
            }
        }
        // The simplex's feature solved exactly gives the next point of the ray; near the end
        // (or where GJK stalled) it and its faces are certified in turn.
        let next = settle(pts, r, rho, &v)
            .map(|f| f.alpha)
            .filter(|a| *a > lo && *a < hi);
        if hi - lo <= NARROW * lo {
            if let Some(h) = settle_faces(pair, pts, r, rho, &v, (&mut lo, &mut hi), &mut lo_n) {
                best = h;
                if hi - lo <= rel_tol * lo {
                    return PaddedEnd::Hit(best);
                }
            }
        }
        let next = next.or_else(|| {
            // A Newton step on t ↦ dist(t r, Q) − ρ, convex in t = 1/α.
            let dist = v.norm();
            let t = 1.0 / alpha - (dist - rho) / (v.dot(r) / dist);
            let a = 1.0 / t;
            (t > 0.0 && a > lo && a < hi).then_some(a)
        });
        alpha = match next {
            Some(a) => a,
            None if hi.is_finite() => 0.5 * (lo + hi),
            // No upper bound yet (the ray misses the ball about every point GJK found) and no
            // step: the point of the ray on GJK's last support plane, still outside K (α* ≥
            // lo), where the next round's GJK starts (this was the ray cast's fallback on 9 %
            // of separated polygon–polygon calls, ~10k instructions each).
            None if lo > alpha => lo,
            None => return PaddedEnd::Failed,
        };
    }
    PaddedEnd::Failed
}

/// The simplex `pts` and its faces (edges, vertices) solved exactly and certified in turn,
/// tightening the bracket `(lo, hi)`; the first whose normal supports Q at its point (the
/// contact feature) that lowers `hi`, as the answer.
fn settle_faces<S: SupportMap>(
    pair: &Pair<'_, S>,
    pts: &[Vertex],
    r: &Vec3,
    rho: Real,
    v: &Vec3,
    (lo, hi): (&mut Real, &mut Real),
    lo_n: &mut Vec3,
) -> Option<PaddedHit> {
    const FACES: [&[usize]; 7] = [&[0, 1, 2], &[0, 1], &[1, 2], &[0, 2], &[0], &[1], &[2]];
    for ids in FACES
        .iter()
        .filter(|ids| ids.iter().all(|i| *i < pts.len()))
    {
        let mut sub = [Vertex::default(); 3];
        for (s, i) in sub.iter_mut().zip(ids.iter()) {
            *s = pts[*i];
        }
        let sub = &sub[..ids.len()];
        let Some(f) = settle(sub, r, rho, v) else {
            continue;
        };
        let (l, u, exact) = certify(pair, sub, &f, r, rho);
        if l > *lo {
            (*lo, *lo_n) = (l, f.normal);
        }
        if exact && u <= *hi {
            *hi = u;
            let p = point(sub, &f.weights);
            return Some(PaddedHit {
                alpha: u,
                normal: f.normal,
                a: p.a,
                b: p.b,
            });
        }
    }
    None
}

/// A feature of Q (1 to 3 of the simplex's points) solved exactly: α on its affine hull padded
/// by ρ, the point of Q it touches there (weights of the points, all ≥ 0) and the unit normal.
struct Settled {
    alpha: Real,
    weights: [Real; 3],
    normal: Vec3,
}

/// The exact α on the affine hull of `pts` (points of Q) padded by ρ, where the touching point
/// lies on the feature itself (weights ≥ −slack, then clamped); `v` orients a face.
fn settle(pts: &[Vertex], r: &Vec3, rho: Real, v: &Vec3) -> Option<Settled> {
    const SLACK: Real = 1e-12;
    let w0 = pts[0].w;
    let (alpha, weights) = match pts.len() {
        1 => (ball_exit(r, &w0, rho), [1.0, 0.0, 0.0]),
        2 => {
            let e = pts[1].w - w0;
            let u = e.try_normalize(0.0)?;
            let rp = r - u * u.dot(r);
            let wp = w0 - u * u.dot(&w0);
            let alpha = ball_exit(&rp, &wp, rho);
            let s = (r / alpha - w0).dot(&e) / e.norm_squared();
            if !((-SLACK..=1.0 + SLACK).contains(&s)) {
                return None;
            }
            let s = s.clamp(0.0, 1.0);
            (alpha, [1.0 - s, s, 0.0])
        }
        _ => {
            let (e1, e2) = (pts[1].w - w0, pts[2].w - w0);
            let m = e1.cross(&e2);
            let m = (m * m.dot(v).signum()).try_normalize(0.0)?;
            let (mr, den) = (m.dot(r), m.dot(&w0) + rho);
            if !(mr > 0.0 && den > 0.0) {
                return None;
            }
            let alpha = mr / den;
            // Barycentric coordinates of the foot of r/α on the face's plane.
            let f = r / alpha - m * rho - w0;
            let (d11, d12, d22) = (e1.dot(&e1), e1.dot(&e2), e2.dot(&e2));
            let (f1, f2) = (f.dot(&e1), f.dot(&e2));
            let det = d11 * d22 - d12 * d12;
            if !(det > 0.0) {
                return None;
            }
            let (b1, b2) = ((d22 * f1 - d12 * f2) / det, (d11 * f2 - d12 * f1) / det);
            let b0 = 1.0 - b1 - b2;
            if !(b0 >= -SLACK && b1 >= -SLACK && b2 >= -SLACK) {
                return None;
            }
            let (b0, b1, b2) = (b0.max(0.0), b1.max(0.0), b2.max(0.0));
            let sum = b0 + b1 + b2;
            (alpha, [b0 / sum, b1 / sum, b2 / sum])
        }
    };
    if !(alpha.is_finite() && alpha > 0.0) {
        return None;
    }
    let q = point(pts, &weights).w;
    let normal = (r / alpha - q).try_normalize(0.0)?;
    Some(Settled {
        alpha,
        weights,
        normal,
    })
}

/// The combination `Σ wᵢ pᵢ` of points of Q with their witnesses.
fn point(pts: &[Vertex], w: &[Real]) -> Vertex {
    let mut out = Vertex::default();
    for (p, wi) in pts.iter().zip(w) {
        out.w += p.w * *wi;
        out.a += p.a * *wi;
        out.b += p.b * *wi;
    }
    out
}

/// The bounds of one settled feature: `(lower, upper)` from its normal (one support call)
/// and its point, and whether the normal supports Q at the point (to rounding): then the
/// feature is the one in contact and its point and normal are exact.
fn certify<S: SupportMap>(
    pair: &Pair<'_, S>,
    pts: &[Vertex],
    f: &Settled,
    r: &Vec3,
    rho: Real,
) -> (Real, Real, bool) {
    let q = point(pts, &f.weights).w;
    let s = pair.support(&f.normal);
    let (nr, den) = (f.normal.dot(r), f.normal.dot(&s.w) + rho);
    let lower = if nr > 0.0 && den > 0.0 { nr / den } else { 0.0 };
    let upper = ball_exit(r, &q, rho);
    let gap = f.normal.dot(&(s.w - q));
    (lower, upper, gap <= GAP_TOL * (1.0 + q.norm()))
}

/// The least α with `‖d − αc‖ = αρ` (the ray `d`'s exit from the ball of radius ρ about `c`,
/// scaled), or ∞: `1/α = (d·c + √(ρ²‖d‖² − ‖d × c‖²))/‖d‖²`. The discriminant is formed from
/// the cross product (as `closed_form::vertex_root`'s callers form it); written as
/// `(d·c)² − (‖c‖² − ρ²)‖d‖²` its first two terms cancel down to `‖d × c‖² ≤ ρ²‖d‖²` and leave an absolute error
/// of about ε‖c‖²‖d‖²: with a padding of 1e-4 about a core of size 3, α about 1e-11 too low
/// (8e-12 measured, below the exact α at a requested tolerance of 1e-12).
fn ball_exit(d: &Vec3, c: &Vec3, rho: Real) -> Real {
    let d2 = d.norm_squared();
    let disc = rho * rho * d2 - d.cross(c).norm_squared();
    if !(disc >= 0.0) {
        return Real::INFINITY;
    }
    let den = d.dot(c) + disc.sqrt();
    if den > 0.0 {
        d2 / den
    } else {
        Real::INFINITY
    }
}

/// `Σ wᵢ cᵢ`.
fn combine(pts: &[Pt], w: &[Real]) -> Vec3 {
    pts.iter()
        .zip(w)
        .fold(Vec3::zeros(), |acc, (p, wi)| acc + p.c * *wi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Mat3;
    use crate::shapes::Shape;

    /// A unit sphere's centre against a box of half extents (1, 2, 3): the face, edge and
    /// corner values in closed form.
    #[test]
    fn a_point_padded_against_a_box() {
        let bx = Shape::cuboid(1.0, 2.0, 3.0).unwrap();
        let pt = Shape::sphere(1e-300).unwrap();
        let id = Mat3::identity();
        let pair = Pair::new([&bx, &pt], [&id, &id], 1.0);
        let rho = 0.5;
        // Face: α(1 + ρ) = 1 along x.
        let PaddedEnd::Hit(h) = padded_cast(&pair, &Vec3::x(), rho, 1e-14, None) else {
            panic!("no hit");
        };
        assert!((h.alpha - 1.0 / 1.5).abs() < 1e-15, "{h:?}");
        assert!((h.normal - Vec3::x()).norm() < 1e-14);
        // Corner: ‖r − α(1, 2, 3)‖ = αρ with r along (1.3, 2.3, 3.3) (the ray's point lies
        // beyond all three faces' planes).
        let r = Vec3::new(1.3, 2.3, 3.3).normalize();
        let PaddedEnd::Hit(h) = padded_cast(&pair, &r, rho, 1e-14, None) else {
            panic!("no hit");
        };
        let c = Vec3::new(1.0, 2.0, 3.0);
        assert!(
            ((r - c * h.alpha).norm() - h.alpha * rho).abs() < 1e-14,
            "{h:?}"
        );
        assert!((h.a - c).norm() < 1e-14);
        let e = r / h.alpha - c;
        assert!(e.iter().all(|v| *v > 0.0));
        // Edge (x, y): the z part lies inside the face.
        let r = Vec3::new(3.0, 4.0, 0.5).normalize();
        let PaddedEnd::Hit(h) = padded_cast(&pair, &r, rho, 1e-14, None) else {
            panic!("no hit");
        };
        let e = Vec3::new(r.x - h.alpha, r.y - 2.0 * h.alpha, 0.0);
        assert!(e.x > 0.0 && e.y > 0.0 && (e.norm() - h.alpha * rho).abs() < 1e-14);
        // A threshold the first bounds decide.
        let stop = Stop {
            value: 10.0,
            stop_below: true,
        };
        assert!(matches!(
            padded_cast(&pair, &Vec3::x(), rho, 1e-14, Some(stop)),
            PaddedEnd::Decided(true, _, _)
        ));
    }

    /// A point padded by a thin ball against a box, along 2 000 random rays: more casts
    /// certify (with thin padding the ray often misses the ball about GJK's first points,
    /// which left the first round without an upper bound or a step), and every certified one
    /// agrees with α' found by bisection on the exact distance to the box (clamping).
    #[test]
    fn thin_padding_certifies_more_rays() {
        let (hx, hy, hz) = (1.0, 2.0, 3.0);
        let bx = Shape::cuboid(hx, hy, hz).unwrap();
        let pt = Shape::sphere(1e-300).unwrap();
        let id = Mat3::identity();
        let pair = Pair::new([&bx, &pt], [&id, &id], 1.0);
        // The same rays at rel_tol 1e-10, then 1e-12 (where the ball's exit, formed with the
        // cancelling discriminant, came out 8e-12 below the exact α on a face contact at
        // ρ = 1e-4).
        let mut counts = [(0, 0); 2];
        for (tol, (checked, failed)) in [1e-10, 1e-12].into_iter().zip(counts.iter_mut()) {
            let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
            let mut uniform = || {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                (seed >> 11) as Real / (1_u64 << 53) as Real
            };
            for rho in [1e-4, 1e-3, 1e-2, 0.1] {
                for _ in 0..500 {
                    let r = Vec3::new(
                        2.0 * uniform() - 1.0,
                        2.0 * uniform() - 1.0,
                        2.0 * uniform() - 1.0,
                    );
                    let Some(r) = r.try_normalize(1e-3) else {
                        continue;
                    };
                    let PaddedEnd::Hit(h) = padded_cast(&pair, &r, rho, tol, None) else {
                        *failed += 1;
                        continue;
                    };
                    // t* = sup { t : dist(t r, box) <= rho }, and alpha' = 1/t*.
                    let dist = |t: Real| {
                        let p = r * t;
                        let c =
                            Vec3::new(p.x.clamp(-hx, hx), p.y.clamp(-hy, hy), p.z.clamp(-hz, hz));
                        (p - c).norm()
                    };
                    let (mut lo, mut hi) = (0.0, 10.0);
                    for _ in 0..200 {
                        let mid = 0.5 * (lo + hi);
                        if dist(mid) <= rho {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    let truth = 1.0 / lo;
                    // The answer is the bracket's upper end: never below α (beyond the bisection's
                    // own rounding, ~1e-15), at most the tolerance above it.
                    let rel = (h.alpha - truth) / truth;
                    assert!(
                        (-1e-14..=tol * (1.0 + 1e-3)).contains(&rel),
                        "rho {rho}, tol {tol}, r {r:?}: {} against {truth} ({rel:e})",
                        h.alpha
                    );
                    // The witness is a point of the box and the normal points from it to r/alpha.
                    assert!(
                        h.a.x.abs() <= hx + 1e-12
                            && h.a.y.abs() <= hy + 1e-12
                            && h.a.z.abs() <= hz + 1e-12
                    );
                    let e = r / h.alpha - (h.a - h.b);
                    assert!((e.norm() - rho).abs() <= 1e-9, "{e:?}");
                    *checked += 1;
                }
            }
        }
        // Before the dead end went on (`alpha = lo`): 721 of the 2 000 certified; now 937 (the
        // rest end on other exits and go to the ray cast, as before).
        let [(checked, failed), (tight, tight_failed)] = counts;
        assert!(
            checked >= 900 && checked + failed == 2000,
            "{checked} certified, {failed} failed"
        );
        assert!(
            tight >= 900 && tight + tight_failed == 2000,
            "rel_tol 1e-12: {tight} certified, {tight_failed} failed"
        );
    }
}
