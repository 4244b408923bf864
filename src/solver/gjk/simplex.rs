//! The sub-simplex step of GJK: the point of a simplex (1 to 4 points) nearest the origin,
//! by the Voronoi-region tests of Ericson's *Real-Time Collision Detection* (§5.1), and the
//! smallest face of the simplex that holds it.

use super::Pt;
use crate::math::{Real, Vec3};

/// Replaces the simplex (its first `k` points) by the smallest sub-simplex whose hull holds
/// the point nearest the origin, with that point's barycentric weights; `None` when the
/// origin lies inside the tetrahedron.
pub(super) fn reduce(s: &mut [Pt; 4], w: &mut [Real; 4], k: usize) -> Option<usize> {
    let (mask, wk) = nearest(s, k)?;
    Some(keep(s, w, k, mask, &wk))
}

/// The point of the simplex `s[..k]` nearest the origin, `s` unchanged: the points of the
/// smallest sub-simplex that holds it (a bit mask over `s[..k]`) and its weights (zero off the
/// mask); `None` when the origin lies inside the tetrahedron. [`keep`] then makes that
/// sub-simplex the simplex: a GJK step that makes no progress leaves `s` as it was without a
/// copy of it (the copies of the simplex were ~3 % of a padded polygon's proximity).
pub(super) fn nearest(s: &[Pt; 4], k: usize) -> Option<(u8, [Real; 4])> {
    let mut wk = [0.0; 4];
    let mask = match k {
        1 => {
            wk[0] = 1.0;
            1
        }
        2 => {
            let (m, t) = segment(&s[0].c, &s[1].c);
            wk[..2].copy_from_slice(&t);
            m
        }
        3 => {
            let (m, t) = triangle(&s[0].c, &s[1].c, &s[2].c);
            wk[..3].copy_from_slice(&t);
            m
        }
        _ => {
            let (m, t) = tetrahedron(&[s[0].c, s[1].c, s[2].c, s[3].c])?;
            wk = t;
            m
        }
    };
    Some((mask, wk))
}

/// `Σ wkᵢ cᵢ` over the points of `mask` in `s[..k]`, in their order: the nearest point
/// [`nearest`] found, bit for bit as it is after [`keep`] (the same sum in the same order).
pub(super) fn masked_point(s: &[Pt; 4], k: usize, mask: u8, wk: &[Real; 4]) -> Vec3 {
    let mut v = Vec3::zeros();
    for (i, (p, wi)) in s[..k].iter().zip(wk).enumerate() {
        if mask & (1 << i) != 0 {
            v += p.c * *wi;
        }
    }
    v
}

/// Keeps the points of `mask` in `s[..k]`, in their order, with their weights `wk`: the
/// number kept.
pub(super) fn keep(
    s: &mut [Pt; 4],
    w: &mut [Real; 4],
    k: usize,
    mask: u8,
    wk: &[Real; 4],
) -> usize {
    let mut n = 0;
    for i in 0..k {
        if mask & (1 << i) != 0 {
            s[n] = s[i];
            w[n] = wk[i];
            n += 1;
        }
    }
    n
}

/// The point of segment `ab` nearest the origin: the vertices used (bit mask) and weights.
fn segment(a: &Vec3, b: &Vec3) -> (u8, [Real; 2]) {
    let ab = b - a;
    let t = -a.dot(&ab);
    if t <= 0.0 {
        return (0b01, [1.0, 0.0]);
    }
    let dd = ab.norm_squared();
    if t >= dd {
        return (0b10, [0.0, 1.0]);
    }
    let t = t / dd;
    (0b11, [1.0 - t, t])
}

/// The point of triangle `abc` nearest the origin (Ericson's Voronoi-region tests).
pub(super) fn triangle(a: &Vec3, b: &Vec3, c: &Vec3) -> (u8, [Real; 3]) {
    let ab = b - a;
    let ac = c - a;
    let d1 = -ab.dot(a);
    let d2 = -ac.dot(a);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (0b001, [1.0, 0.0, 0.0]);
    }
    let d3 = -ab.dot(b);
    let d4 = -ac.dot(b);
    if d3 >= 0.0 && d4 <= d3 {
        return (0b010, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return (0b011, [1.0 - t, t, 0.0]);
    }
    let d5 = -ab.dot(c);
    let d6 = -ac.dot(c);
    if d6 >= 0.0 && d5 <= d6 {
        return (0b100, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return (0b101, [1.0 - t, 0.0, t]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (0b110, [0.0, 1.0 - t, t]);
    }
    let sum = va + vb + vc;
    if !(sum > 0.0) {
        // Degenerate (collinear) triangle: the best of its edges.
        let cands = [(0usize, 1usize), (0, 2), (1, 2)];
        let p = [*a, *b, *c];
        let mut best = (0b001, [1.0, 0.0, 0.0]);
        let mut best_d = Real::INFINITY;
        for (i, j) in cands {
            let (m, t) = segment(&p[i], &p[j]);
            let q = p[i] * t[0] + p[j] * t[1];
            if q.norm_squared() < best_d {
                best_d = q.norm_squared();
                let mut wt = [0.0; 3];
                wt[i] = t[0];
                wt[j] = t[1];
                let mm =
                    (if m & 1 != 0 { 1 << i } else { 0 }) | (if m & 2 != 0 { 1 << j } else { 0 });
                best = (mm, wt);
            }
        }
        return best;
    }
    let v = vb / sum;
    let w = vc / sum;
    (0b111, [1.0 - v - w, v, w])
}

/// The point of tetrahedron `p` nearest the origin, `None` when the origin is inside it.
fn tetrahedron(p: &[Vec3; 4]) -> Option<(u8, [Real; 4])> {
    const FACES: [[usize; 4]; 4] = [[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 1, 2], [1, 3, 2, 0]];
    let mut best: Option<(u8, [Real; 4])> = None;
    let mut best_d = Real::INFINITY;
    for [i, j, l, o] in FACES {
        let n = (p[j] - p[i]).cross(&(p[l] - p[i]));
        let side_origin = -p[i].dot(&n);
        let side_other = (p[o] - p[i]).dot(&n);
        let flat = side_other.abs() <= 1e-12 * n.norm() * (p[o] - p[i]).norm();
        if side_origin * side_other < 0.0 || flat {
            let (m, t) = triangle(&p[i], &p[j], &p[l]);
            let q = p[i] * t[0] + p[j] * t[1] + p[l] * t[2];
            let dq = q.norm_squared();
            if dq < best_d {
                best_d = dq;
                let mut wt = [0.0; 4];
                let mut mm = 0u8;
                for (bit, idx) in [i, j, l].into_iter().enumerate() {
                    if m & (1 << bit) != 0 {
                        mm |= 1 << idx;
                        wt[idx] = t[bit];
                    }
                }
                best = Some((mm, wt));
            }
        }
    }
    best
}
