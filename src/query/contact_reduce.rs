//! The choice of a manifold's points among its candidates (`super::contact`): at most the
//! number asked for, the deepest first, then the ones spanning the largest area; and the
//! clipping in the plane orthogonal to the normal that finds the candidates of two features.

use crate::math::{Real, Vec3};
use arrayvec::ArrayVec;
use nalgebra::Vector2;

/// A point in the plane orthogonal to a manifold's normal.
pub(crate) type V2 = Vector2<Real>;

/// The most candidates considered (the clipping buffers' size).
pub(crate) const MAX_CANDIDATES: usize = 64;
const BUF: usize = MAX_CANDIDATES;

/// Chooses at most `cap` of the points: the deepest, the farthest from it, the one spanning the
/// largest triangle with those two, then each time the one farthest from those chosen (each
/// candidate's distance to the chosen ones kept up to date, one pass per pick).
#[inline]
pub(crate) fn reduce(pos: &[Vec3], depth: &[Real], cap: usize, chosen: &mut [usize]) -> usize {
    reduce_in::<BUF>(pos, depth, cap, chosen)
}

/// [`reduce`] with buffers of `B` slots (the first `B` candidates at most): the boxes' closed
/// form has at most 8 candidates, whose 64-slot buffers cost more to clear than to fill.
#[inline]
pub(crate) fn reduce_in<const B: usize>(
    pos: &[Vec3],
    depth: &[Real],
    cap: usize,
    chosen: &mut [usize],
) -> usize {
    let n = pos.len().min(depth.len()).min(B);
    let cap = cap.min(chosen.len());
    if n <= cap {
        for (i, c) in chosen.iter_mut().enumerate().take(n) {
            *c = i;
        }
        return n;
    }
    let mut used = [false; B];
    let deepest = pick(n, &used, |i| depth[i]).unwrap_or(0);
    chosen[0] = deepest;
    used[deepest] = true;
    let p0 = pos[deepest];
    // Each candidate's distance to the nearest chosen point.
    let mut near = [0.0; B];
    for i in 0..n {
        near[i] = (pos[i] - p0).norm();
    }
    let mut k = 1;
    while k < cap {
        let best = if k == 2 {
            let (a, e) = (pos[chosen[0]], pos[chosen[1]] - pos[chosen[0]]);
            pick(n, &used, |i| e.cross(&(pos[i] - a)).norm_squared())
        } else {
            pick(n, &used, |i| near[i])
        };
        let Some(b) = best else { break };
        chosen[k] = b;
        used[b] = true;
        k += 1;
        if k == cap {
            // The last pick: no distance is asked again.
            break;
        }
        let pb = pos[b];
        for i in 0..n {
            near[i] = near[i].min((pos[i] - pb).norm());
        }
    }
    k
}

/// The first unused candidate of the best `score` (each scored once), `None` when all are used.
#[inline]
fn pick<const B: usize>(
    n: usize,
    used: &[bool; B],
    score: impl Fn(usize) -> Real,
) -> Option<usize> {
    let mut best: Option<(usize, Real)> = None;
    for i in 0..n {
        if used[i] {
            continue;
        }
        let s = score(i);
        if best.map_or(true, |(_, b)| s > b) {
            best = Some((i, s));
        }
    }
    best.map(|(i, _)| i)
}

fn cross2(a: &V2, b: &V2) -> Real {
    a.x * b.y - a.y * b.x
}

/// The signed area's sign of a polygon: `1` counter-clockwise, `-1` clockwise.
fn orientation(poly: &[V2]) -> Real {
    let mut a = 0.0;
    for i in 0..poly.len() {
        let j = (i + 1) % poly.len();
        a += cross2(&poly[i], &poly[j]);
    }
    if a >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// Sutherland–Hodgman: clips the polygon `poly` against the convex polygon `reference`, in
/// place (two buffers taking turns: moving a whole buffer per edge cost more than the clipping).
pub(crate) fn clip_polygon<const N: usize>(reference: &[V2], poly: &mut ArrayVec<V2, N>) {
    let s = orientation(reference);
    let mut tmp: ArrayVec<V2, N> = ArrayVec::new();
    let (mut cur, mut next) = (poly, &mut tmp);
    let mut turned = false;
    for e in 0..reference.len() {
        let a = reference[e];
        let d = reference[if e + 1 == reference.len() { 0 } else { e + 1 }] - a;
        let side = |p: &V2| s * cross2(&d, &(p - a));
        next.clear();
        let len = cur.len();
        for i in 0..len {
            let p = cur[i];
            let c = cur[if i + 1 == len { 0 } else { i + 1 }];
            let (sp, sc) = (side(&p), side(&c));
            if sp >= 0.0 {
                let _ = next.try_push(p);
            }
            if (sp >= 0.0) != (sc >= 0.0) {
                let t = sp / (sp - sc);
                let _ = next.try_push(p + (c - p) * t);
            }
        }
        std::mem::swap(&mut cur, &mut next);
        turned = !turned;
        if cur.is_empty() {
            break;
        }
    }
    if turned {
        // The result is in `tmp` (`cur`); `next` is the caller's buffer.
        next.clear();
        next.extend(cur.iter().copied());
    }
}

/// Cyrus–Beck: clips the segment `seg` against the convex polygon `reference`, into `out`.
pub(crate) fn clip_segment<const N: usize>(
    reference: &[V2],
    seg: &[V2; 2],
    out: &mut ArrayVec<V2, N>,
) {
    let s = orientation(reference);
    let (p, d) = (seg[0], seg[1] - seg[0]);
    let (mut lo, mut hi) = (0.0, 1.0);
    for e in 0..reference.len() {
        let a = reference[e];
        let ed = reference[(e + 1) % reference.len()] - a;
        // inside: s·cross(ed, x − a) ≥ 0, linear in t: f0 + t·f1.
        let f0 = s * cross2(&ed, &(p - a));
        let f1 = s * cross2(&ed, &d);
        if f1 == 0.0 {
            if f0 < 0.0 {
                return;
            }
        } else {
            let t = -f0 / f1;
            if f1 > 0.0 {
                lo = Real::max(lo, t);
            } else {
                hi = Real::min(hi, t);
            }
        }
    }
    if lo > hi {
        return;
    }
    out.push(p + d * lo);
    if hi > lo {
        out.push(p + d * hi);
    }
}

/// Two segments in the plane: their overlap if parallel, else their crossing point, into
/// `out`.
pub(crate) fn segments<const N: usize>(
    a: &[V2; 2],
    b: &[V2; 2],
    tol: Real,
    out: &mut ArrayVec<V2, N>,
) {
    let (da, db) = (a[1] - a[0], b[1] - b[0]);
    let (la, lb) = (da.norm(), db.norm());
    if !(la > 0.0 && lb > 0.0) {
        return;
    }
    let c = cross2(&da, &db);
    if c.abs() <= 1e-6 * la * lb {
        // Parallel: unless the lines coincide (to rounding) the normal does not join them and
        // the witness point answers; else the overlap of b with a, as parameters along a.
        if cross2(&da, &(b[0] - a[0])).abs() > tol * la {
            return;
        }
        let ta = |p: &V2| (p - a[0]).dot(&da) / (la * la);
        let (t0, t1) = (ta(&b[0]), ta(&b[1]));
        let lo = t0.min(t1).max(0.0);
        let hi = t0.max(t1).min(1.0);
        if lo > hi {
            return;
        }
        out.push(a[0] + da * lo);
        if hi > lo {
            out.push(a[0] + da * hi);
        }
        return;
    }
    let w = b[0] - a[0];
    let s = cross2(&w, &db) / c;
    let t = cross2(&w, &da) / c;
    if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
        out.push(a[0] + da * s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::query::test_support::lcg;

    /// The choice written plainly (a pass over all candidates per pick, each scored from
    /// scratch): the distance to the nearest chosen point as the minimum over the chosen ones.
    fn plain(pos: &[Vec3], depth: &[Real], cap: usize) -> Vec<usize> {
        let n = pos.len();
        if n <= cap {
            return (0..n).collect();
        }
        let best = |chosen: &Vec<usize>, score: &dyn Fn(usize) -> Real| {
            let mut b: Option<(usize, Real)> = None;
            for i in (0..n).filter(|i| !chosen.contains(i)) {
                let s = score(i);
                if b.map_or(true, |(_, v)| s > v) {
                    b = Some((i, s));
                }
            }
            b.map(|(i, _)| i)
        };
        let mut chosen = vec![best(&vec![], &|i| depth[i]).unwrap()];
        while chosen.len() < cap {
            let c = chosen.clone();
            let next = if c.len() == 2 {
                let (a, e) = (pos[c[0]], pos[c[1]] - pos[c[0]]);
                best(&c, &|i| e.cross(&(pos[i] - a)).norm_squared())
            } else {
                best(&c, &|i| {
                    c.iter()
                        .map(|&j| (pos[i] - pos[j]).norm())
                        .fold(Real::INFINITY, Real::min)
                })
            };
            match next {
                Some(b) => chosen.push(b),
                None => break,
            }
        }
        chosen
    }

    /// `reduce` chooses what the plain definition chooses, in the same order: random clouds,
    /// regular polygons (ties of distance and depth), repeated points, 1 to 16 of 2 to 64.
    #[test]
    fn reduce_is_the_plain_choice() {
        let mut rnd = lcg(5);
        let mut reduced = 0;
        for t in 0..3000 {
            let n = 2 + t % 63;
            let (pos, depth): (Vec<Vec3>, Vec<Real>) = match t % 3 {
                0 => (0..n)
                    .map(|_| (Vec3::new(rnd(), rnd(), 0.1 * rnd()), rnd()))
                    .unzip(),
                1 => (0..n)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as Real / n as Real;
                        (Vec3::new(a.cos(), a.sin(), 0.0), 0.01)
                    })
                    .unzip(),
                _ => (0..n)
                    .map(|i| {
                        (
                            Vec3::new((i % 4) as Real, (i % 3) as Real, 0.0),
                            (i % 2) as Real,
                        )
                    })
                    .unzip(),
            };
            let cap = 1 + t % 16;
            let mut chosen = [0usize; 16];
            let k = reduce(&pos, &depth, cap, &mut chosen);
            assert_eq!(chosen[..k].to_vec(), plain(&pos, &depth, cap), "case {t}");
            reduced += usize::from(n > cap);
        }
        assert!(reduced > 2000, "{reduced}");
    }

    /// `reduce_in::<8>` (the boxes' lane, at most 8 candidates) chooses what the plain
    /// definition chooses, in the same order: 3 000 clouds of 1 to 8 points (random, on a
    /// regular polygon, repeated), capacities 1 to 8.
    #[test]
    fn eight_slots_are_the_plain_choice() {
        let mut rnd = lcg(11);
        let mut reduced = 0;
        for t in 0..3000 {
            let n = 1 + t % 8;
            let (pos, depth): (Vec<Vec3>, Vec<Real>) = match t % 3 {
                0 => (0..n)
                    .map(|_| (Vec3::new(rnd(), rnd(), 0.1 * rnd()), rnd()))
                    .unzip(),
                1 => (0..n)
                    .map(|i| {
                        let a = std::f64::consts::TAU * i as Real / n as Real;
                        (Vec3::new(a.cos(), a.sin(), 0.0), 0.01)
                    })
                    .unzip(),
                _ => (0..n)
                    .map(|i| (Vec3::new((i % 2) as Real, 0.0, 0.0), (i % 2) as Real))
                    .unzip(),
            };
            let cap = 1 + (t / 8) % 8;
            let mut chosen = [0usize; 16];
            let k = reduce_in::<8>(&pos, &depth, cap, &mut chosen);
            assert_eq!(chosen[..k].to_vec(), plain(&pos, &depth, cap), "case {t}");
            reduced += usize::from(n > cap);
        }
        assert!(reduced > 1000, "{reduced}");
    }
}
