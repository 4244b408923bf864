//! The contact features of a geometric solution: the pieces of each shape that tie at its
//! normal (a vertex, an edge's two ends, a face's triangle, a smooth patch), or a flat disc
//! facing it, identified from the support functions' values; and whether they pin x*.
//!
//! `super::sensitivity` solves the features' KKT system; `crate::query::warm` keeps them from
//! one query to the next.

use super::raycast::{Pair, Posed};
use crate::math::{Real, Vec3};
use crate::shapes::{SupportMap, ROUND_EPS};

/// The geometric solution, normalised: the ray `r` (unit), `n` with `n·r = 1`, `μ = 1/α'`,
/// the points `a` (shape 1) and `b` (shape 2) relative to their origins.
pub(crate) struct Solution {
    pub r: Vec3,
    pub normal: Vec3,
    pub mu: Real,
    pub a: Vec3,
    pub b: Vec3,
}

/// Pieces per shape in a feature (a triangle of a face), or a disc's three unknowns.
pub(crate) const MAX_SIDE: usize = 3;
/// At most this many pieces may tie at the optimal normal (a face's vertices).
const MAX_TIED: usize = 16;
/// A piece ties when its value is within this (normalised length) of the support function.
const TIE_TOL: Real = 1e-10;
/// Tied support points closer than this (normalised length) are one point.
const POINT_TOL: Real = 1e-9;
/// A disc faces the normal when the cosine of their angle is at least this.
const DISC_COS: Real = 1.0 - 1e-13;
/// Two segments closer to parallel than this (sine of their angle) do not pin x*.
pub(crate) const PARALLEL_SIN: Real = 1e-6;

/// One shape's contact feature.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Feature {
    /// Pieces and their multipliers (1, 2 or 3 of them).
    Pieces {
        ids: [u32; MAX_SIDE],
        lam: [Real; MAX_SIDE],
        count: usize,
    },
    /// A flat disc: body centre, radius, the point's coordinates along `e_y, e_z`.
    Disc {
        centre: Vec3,
        radius: Real,
        s: [Real; 2],
    },
}

impl Feature {
    pub(crate) fn unknowns(&self) -> usize {
        match self {
            Feature::Pieces { count, .. } => *count,
            Feature::Disc { .. } => 3,
        }
    }
}

/// The pieces tied at a normal: their ids and body support points (shape units).
struct Tied {
    ids: [u32; MAX_TIED],
    pts: [Vec3; MAX_TIED],
    count: usize,
}

impl Tied {
    const EMPTY: Tied = Tied {
        ids: [0; MAX_TIED],
        pts: [Vec3::new(0.0, 0.0, 0.0); MAX_TIED],
        count: 0,
    };
}

/// A shape's disc facing `n`, or the affine dimension of its tied pieces' support points (held
/// in a [`Tied`] beside it) and the direction of their segment (world) when that dimension is
/// one.
#[derive(Debug)]
enum Found {
    Disc(Feature),
    Tied(usize, Vec3),
}

/// A shape's disc facing the body direction `m`, as [`find`] takes it.
#[inline]
fn disc<S: SupportMap>(posed: &Posed<'_, S>, m: &Vec3) -> Option<Found> {
    let (centre, radius) = posed.shape.disc(m, DISC_COS)?;
    let s = [0.0; 2];
    Some(Found::Disc(Feature::Disc { centre, radius, s }))
}

/// What [`find`] decides about one shape's support set, without its pieces, where the shape
/// knows the set in closed form ([`SupportMap::support_set`]) or a disc faces `n`; `None`:
/// search the pieces.
fn quick<S: SupportMap>(posed: &Posed<'_, S>, sign: Real, n: &Vec3) -> Option<Found> {
    let m = posed.rot.tr_mul(n) * sign;
    if let Some(found) = disc(posed, &m) {
        return Some(found);
    }
    let unit = 1.0 / posed.inv_scale;
    let tie = TIE_TOL * unit * m.norm();
    // A direction that is not finite ties nothing in the search (no contact is unique there);
    // the closed forms' comparisons would say otherwise.
    if !tie.is_finite() {
        return None;
    }
    let (dim, e) = posed.shape.support_set(&m, tie, POINT_TOL * unit)?;
    Some(Found::Tied(dim, posed.rot * e))
}

/// The feature of one shape at the world normal `n` (`sign`: how its support map sees `n`); its
/// tied pieces go to `t`.
fn find<S: SupportMap>(posed: &Posed<'_, S>, sign: Real, n: &Vec3, t: &mut Tied) -> Option<Found> {
    let m = posed.rot.tr_mul(n) * sign;
    let unit = 1.0 / posed.inv_scale;
    if let Some(found) = disc(posed, &m) {
        return Some(found);
    }
    // Shapes made of (padded) vertices: the support value and the ties in one pass over the
    // vertices, without the support map's own search (`vertex_ties`); others, or a pass that
    // overflows its room, search as below.
    let tol = TIE_TOL * unit * m.norm();
    if !vertex_ties(posed.shape, &m, tol, t) {
        let (p, _) = posed.shape.support(&m);
        let h = p.dot(&m);
        if posed.shape.piece_count() == 1 {
            // One smooth piece (a sphere, an ellipsoid): it is the support function, so it
            // ties, and its point alone has affine dimension zero.
            if !h.is_finite() {
                return None;
            }
            t.ids[0] = 0;
            t.pts[0] = p;
            t.count = 1;
            return Some(Found::Tied(0, Vec3::zeros()));
        }
        tied_pieces(posed.shape, &m, h - tol, t, true)?;
    }
    if t.count == 0 {
        return None;
    }
    // Affine dimension: the point farthest from the first, then the one farthest from their line.
    let tol = POINT_TOL * unit;
    let p0 = t.pts[0];
    let far = (0..t.count).max_by(|&i, &j| {
        (t.pts[i] - p0)
            .norm_squared()
            .total_cmp(&(t.pts[j] - p0).norm_squared())
    })?;
    let span = t.pts[far] - p0;
    if !(span.norm() > tol) {
        return Some(Found::Tied(0, Vec3::zeros()));
    }
    let e = span.normalize();
    let off = (0..t.count).fold(0.0, |m: Real, i| {
        let v = t.pts[i] - p0;
        m.max((v - e * v.dot(&e)).norm())
    });
    let dim = if off > tol { 2 } else { 1 };
    Some(Found::Tied(dim, posed.rot * e))
}

/// Collects into `t` the pieces of `shape` whose value at `m` is at least `floor`; `None` when a
/// piece cannot be evaluated or more than [`MAX_TIED`] tie. With `vertices`, a polytope's
/// pieces are taken as the dot products of its vertices (the same values and points).
fn tied_pieces<S: SupportMap>(
    shape: &S,
    m: &Vec3,
    floor: Real,
    t: &mut Tied,
    vertices: bool,
) -> Option<()> {
    t.count = 0;
    if let Some(points) = shape.vertex_pieces().filter(|_| vertices) {
        // Piece `id` is `v·m` with gradient `v` (what `piece` gives, without forming its zero
        // Hessian).
        for (id, v) in points.iter().enumerate() {
            if v.dot(m) >= floor {
                if t.count == MAX_TIED {
                    return None;
                }
                t.ids[t.count] = id as u32;
                t.pts[t.count] = *v;
                t.count += 1;
            }
        }
        return Some(());
    }
    if let Some((points, r)) = shape.ball_pieces().filter(|_| vertices) {
        // Piece `id` is `v·m + r‖m‖` with gradient `v + r m/‖m‖`: what `piece` gives
        // (`Round::Ball`, the same operations), the norm taken once.
        let n = m.norm();
        if !(n > ROUND_EPS) {
            return None;
        }
        let (rn, ur) = (r * n, (m / n) * r);
        for (id, v) in points.iter().enumerate() {
            if rn + v.dot(m) >= floor {
                if t.count == MAX_TIED {
                    return None;
                }
                t.ids[t.count] = id as u32;
                t.pts[t.count] = ur + v;
                t.count += 1;
            }
        }
        return Some(());
    }
    for id in 0..shape.piece_count() {
        let (value, point) = shape.piece_point(id, m)?;
        if value >= floor {
            if t.count == MAX_TIED {
                return None;
            }
            t.ids[t.count] = id;
            t.pts[t.count] = point;
            t.count += 1;
        }
    }
    Some(())
}

/// The pieces of a shape made of vertices ([`SupportMap::vertex_pieces`]) or of padded
/// vertices ([`SupportMap::ball_pieces`]) within `tol` of the largest piece value at `m`, into
/// `t` in the order of their ids: what [`tied_pieces`] gives with the floor `h − tol`, `h` the
/// support value, in one pass (the support map's search, a hull's climb included, and a
/// second pass over the vertices saved). The support value is the largest piece value here:
/// for vertices that is the support point's value, the same number; for padded vertices it
/// differs from `p·m` of the support point by rounding only. The pass keeps the pieces within
/// `tol` of the largest value so far, dropping those left behind when it rises. `false` (with
/// `t` holding garbage) for other shapes, a padded shape at a vanishing direction, or more
/// than `MAX_TIED` pieces within `tol` of the value so far: the caller searches.
fn vertex_ties<S: SupportMap>(shape: &S, m: &Vec3, tol: Real, t: &mut Tied) -> bool {
    let (points, pad) = if let Some(points) = shape.vertex_pieces() {
        (points, None)
    } else if let Some((points, r)) = shape.ball_pieces() {
        (points, Some(r))
    } else {
        return false;
    };
    // A padded vertex: value `r‖m‖ + v·m`, point `v + r m/‖m‖` (as `tied_pieces`).
    let (rn, ur) = match pad {
        Some(r) => {
            let n = m.norm();
            if !(n > ROUND_EPS) {
                return false;
            }
            (r * n, (m / n) * r)
        }
        None => (0.0, Vec3::zeros()),
    };
    let mut vals = [0.0; MAX_TIED];
    let mut best = Real::NEG_INFINITY;
    t.count = 0;
    for (id, v) in points.iter().enumerate() {
        let d = if pad.is_some() {
            rn + v.dot(m)
        } else {
            v.dot(m)
        };
        if !(d >= best - tol) {
            continue;
        }
        if d > best {
            best = d;
            let floor = best - tol;
            let mut k = 0;
            for i in 0..t.count {
                if vals[i] >= floor {
                    vals[k] = vals[i];
                    t.ids[k] = t.ids[i];
                    t.pts[k] = t.pts[i];
                    k += 1;
                }
            }
            t.count = k;
        }
        if t.count == MAX_TIED {
            return false;
        }
        vals[t.count] = d;
        t.ids[t.count] = id as u32;
        t.pts[t.count] = if pad.is_some() { ur + v } else { *v };
        t.count += 1;
    }
    true
}

/// The feature of a shape from its tied pieces and its contact point `q` (body, shape units).
fn feature(found: Found, t: &Tied, q: &Vec3) -> Option<Feature> {
    let mut ids = [0; MAX_SIDE];
    let mut lam = [0.0; MAX_SIDE];
    match found {
        Found::Disc(Feature::Disc { centre, radius, .. }) => Some(Feature::Disc {
            centre,
            radius,
            s: [q.y - centre.y, q.z - centre.z],
        }),
        Found::Disc(f) => Some(f),
        Found::Tied(0, _) => {
            ids[0] = t.ids[0];
            lam[0] = 1.0;
            Some(Feature::Pieces { ids, lam, count: 1 })
        }
        Found::Tied(1, _) => {
            // The segment's two ends, and where q lies between them.
            let p0 = t.pts[0];
            let far = (0..t.count).max_by(|&i, &j| {
                (t.pts[i] - p0)
                    .norm_squared()
                    .total_cmp(&(t.pts[j] - p0).norm_squared())
            })?;
            let e = t.pts[far] - p0;
            let along = |i: usize| (t.pts[i] - p0).dot(&e);
            let lo = (0..t.count).min_by(|&i, &j| along(i).total_cmp(&along(j)))?;
            let hi = (0..t.count).max_by(|&i, &j| along(i).total_cmp(&along(j)))?;
            let seg = t.pts[hi] - t.pts[lo];
            let u = (q - t.pts[lo]).dot(&seg) / seg.norm_squared();
            ids[0] = t.ids[lo];
            ids[1] = t.ids[hi];
            lam[0] = 1.0 - u;
            lam[1] = u;
            Some(Feature::Pieces { ids, lam, count: 2 })
        }
        Found::Tied(_, _) => {
            // The triangle of tied points whose barycentric coordinates of q are the most
            // balanced (q inside it: all of them non-negative).
            let mut best = (Real::NEG_INFINITY, [0usize; 3], [0.0; 3]);
            for i in 0..t.count {
                for j in i + 1..t.count {
                    for k in j + 1..t.count {
                        let Some(w) = barycentric(&t.pts[i], &t.pts[j], &t.pts[k], q) else {
                            continue;
                        };
                        let worst = w[0].min(w[1]).min(w[2]);
                        if worst > best.0 {
                            best = (worst, [i, j, k], w);
                        }
                    }
                }
            }
            if best.0 == Real::NEG_INFINITY {
                return None;
            }
            for c in 0..3 {
                ids[c] = t.ids[best.1[c]];
                lam[c] = best.2[c];
            }
            Some(Feature::Pieces { ids, lam, count: 3 })
        }
    }
}

/// Barycentric coordinates of `q` projected onto the plane of triangle `(a, b, c)`.
fn barycentric(a: &Vec3, b: &Vec3, c: &Vec3, q: &Vec3) -> Option<[Real; 3]> {
    let (u, v, w) = (b - a, c - a, q - a);
    let (uu, uv, vv) = (u.dot(&u), u.dot(&v), v.dot(&v));
    let (wu, wv) = (w.dot(&u), w.dot(&v));
    let det = uu * vv - uv * uv;
    if !(det > 1e-12 * uu * vv) {
        return None;
    }
    let y = (wu * vv - wv * uv) / det;
    let z = (wv * uu - wu * uv) / det;
    Some([1.0 - y - z, y, z])
}

/// Both shapes' tied pieces (or discs) at the solution's normal, when their affine dimensions
/// leave x* unique: they add up to at most two, and two segments are not parallel.
fn features<S: SupportMap>(
    pair: &Pair<'_, S>,
    sol: &Solution,
    tied: &mut [Tied; 2],
) -> Option<[Found; 2]> {
    let [t0, t1] = tied;
    let found = [
        find(&pair.one, 1.0, &sol.normal, t0)?,
        find(&pair.two, -1.0, &sol.normal, t1)?,
    ];
    pins(found)
}

/// The two features when their affine dimensions add up to at most two and two segments are
/// not parallel (x* unique).
fn pins(found: [Found; 2]) -> Option<[Found; 2]> {
    let dims = found.each_ref().map(|f| match f {
        Found::Disc(_) => 2,
        Found::Tied(d, _) => *d,
    });
    if dims[0] + dims[1] > 2 {
        return None;
    }
    if let (Found::Tied(1, e0), Found::Tied(1, e1)) = (&found[0], &found[1]) {
        if !(e0.cross(e1).norm() > PARALLEL_SIN) {
            return None;
        }
    }
    Some(found)
}

/// Whether the contact points of the geometric solution are unique (see [`features`]), from
/// its normal `n` alone (`Solution::normal`: the other fields are not needed, and not formed
/// by the gradient's caller).
pub(crate) fn contact_is_unique<S: SupportMap>(pair: &Pair<'_, S>, n: &Vec3) -> bool {
    // Boxes, capsules and cylinders answer in closed form (a search of their pieces costs
    // about 500 instructions a shape), each shape on its own: a box against a hull searches
    // the hull's pieces only. Only the dimensions and directions are needed here, so one
    // buffer of tied pieces serves both searches.
    let (q0, q1) = (quick(&pair.one, 1.0, n), quick(&pair.two, -1.0, n));
    let (f0, f1) = match (q0, q1) {
        (Some(f0), Some(f1)) => (f0, f1),
        (q0, q1) => {
            let mut t = Tied::EMPTY;
            let f0 = match q0 {
                Some(f) => f,
                None => match find(&pair.one, 1.0, n, &mut t) {
                    Some(f) => f,
                    None => return false,
                },
            };
            let f1 = match q1 {
                Some(f) => f,
                None => match find(&pair.two, -1.0, n, &mut t) {
                    Some(f) => f,
                    None => return false,
                },
            };
            (f0, f1)
        }
    };
    pins([f0, f1]).is_some()
}

/// Both shapes' features at the solution `sol` (normal, points): `None` where x* is not unique
/// ([`features`]) or a feature cannot be described (its point outside every triangle of a
/// face's tied points).
pub(crate) fn identify<S: SupportMap>(pair: &Pair<'_, S>, sol: &Solution) -> Option<[Feature; 2]> {
    let mut tied = [Tied::EMPTY, Tied::EMPTY];
    let [f0, f1] = features(pair, sol, &mut tied)?;
    let body = |posed: &Posed<'_, S>, p: &Vec3| posed.rot.tr_mul(p) / posed.inv_scale;
    Some([
        feature(f0, &tied[0], &body(&pair.one, &sol.a))?,
        feature(f1, &tied[1], &body(&pair.two, &sol.b))?,
    ])
}

#[cfg(test)]
mod tests {
    use super::{tied_pieces, vertex_ties, Tied};
    use crate::math::{Real, Vec3};
    use crate::shapes::{Shape, SupportMap};

    /// A polytope's ties from its vertices' dot products, and a padded hull's or padded
    /// polygon's from its ball pieces with the norm taken once, are those of evaluating every
    /// piece, bit for bit: on 40 000 directions, half of them a facet's normal or the sum of two
    /// (where vertices tie), for a box, a 12-facet polytope, a padded hull and a padded polygon.
    #[test]
    fn vertex_ties_match_the_piece_evaluation() {
        let mut a = Vec::new();
        let mut b = Vec::new();
        for k in 0..12 {
            let t = k as f64 * 0.9;
            let v = Vec3::new(
                t.cos() * (1.0 + 0.1 * k as f64),
                t.sin(),
                (k as f64 - 5.5) * 0.2,
            );
            a.push(v.normalize().into());
            b.push(0.5 + 0.01 * k as f64);
        }
        let corners: Vec<[Real; 3]> = a
            .iter()
            .map(|v: &[Real; 3]| [v[0] * 0.6, v[1] * 0.5, v[2]])
            .collect();
        let c = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.6, 0.8]];
        let shapes = [
            Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
            Shape::polytope(&a, &b).unwrap(),
            // Padded: the ball pieces' search (the norm of `m` taken once).
            Shape::convex_hull(&corners, 0.05).unwrap(),
            Shape::polygon(&c, &[0.4, 0.3, 0.5, 0.35, 0.45], 0.08).unwrap(),
        ];
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut unit = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut fast, mut slow) = (Tied::EMPTY, Tied::EMPTY);
        let mut ties = 0;
        for shape in &shapes {
            let normals: Vec<Vec3> = (0..64)
                .filter_map(|_| {
                    let m = Vec3::new(unit(), unit(), unit());
                    shape.flat_face(&m, -1.0)
                })
                .collect();
            for k in 0..10_000 {
                let m = match k % 4 {
                    0 => normals[k % normals.len()],
                    1 => normals[k % normals.len()] + normals[(k / 7) % normals.len()],
                    _ => Vec3::new(unit(), unit(), unit()),
                };
                let (p, _) = shape.support(&m);
                let floor = p.dot(&m) - 1e-10 * m.norm();
                let a = tied_pieces(shape, &m, floor, &mut fast, true);
                let b = tied_pieces(shape, &m, floor, &mut slow, false);
                assert_eq!(a, b);
                assert_eq!(fast.count, slow.count, "direction {m:?}");
                assert_eq!(fast.ids[..fast.count], slow.ids[..slow.count]);
                assert_eq!(fast.pts[..fast.count], slow.pts[..slow.count]);
                ties += usize::from(fast.count > 1);
            }
        }
        assert!(ties > 5_000, "{ties}");
    }

    /// The one-pass ties of (padded) vertices (`vertex_ties`, what `find` takes) are the
    /// search's (the support point's value less the tolerance as the floor, then every piece),
    /// bit for bit, ids in the same order: on 20 000 directions per shape, half of them a
    /// facet's normal or the sum of two (where vertices tie), for a box, a 12-facet polytope,
    /// an unpadded hull of 60 points (its support map climbs), a padded hull and a padded
    /// polygon, at two scales of the direction (97 276 of the 100 000 take the pass, 35 848 with
    /// ties; the rest tie past its room: a zero direction, sums of opposite normals).
    #[test]
    fn one_pass_vertex_ties_match_the_search() {
        let mut state: u64 = 0x5851_f42d_4c95_7f2d;
        let mut unit = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for k in 0..12 {
            let t = k as f64 * 0.9;
            let v = Vec3::new(t.cos(), t.sin(), (k as f64 - 5.5) * 0.2);
            a.push(v.normalize().into());
            b.push(0.5 + 0.01 * k as f64);
        }
        let cloud: Vec<[Real; 3]> = (0..60)
            .map(|_| {
                let v = Vec3::new(unit(), unit(), unit()).normalize();
                [v.x * 0.5, v.y * 0.4, v.z * 0.3]
            })
            .collect();
        let c = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], [0.6, 0.8]];
        let shapes = [
            Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
            Shape::polytope(&a, &b).unwrap(),
            Shape::convex_hull(&cloud, 0.0).unwrap(),
            Shape::convex_hull(&cloud, 0.05).unwrap(),
            Shape::polygon(&c, &[0.4, 0.3, 0.5, 0.35, 0.45], 0.08).unwrap(),
        ];
        let (mut one, mut two) = (Tied::EMPTY, Tied::EMPTY);
        let (mut ties, mut taken) = (0, 0);
        for shape in &shapes {
            let normals: Vec<Vec3> = (0..64)
                .filter_map(|_| shape.flat_face(&Vec3::new(unit(), unit(), unit()), -1.0))
                .collect();
            for k in 0..20_000 {
                let m = match k % 4 {
                    0 => normals[k % normals.len()],
                    1 => normals[k % normals.len()] + normals[(k / 7) % normals.len()],
                    _ => Vec3::new(unit(), unit(), unit()),
                } * if k % 3 == 0 { 40.0 } else { 1.0 };
                let tol = 1e-10 * m.norm();
                let (p, _) = shape.support(&m);
                let searched = tied_pieces(shape, &m, p.dot(&m) - tol, &mut two, true);
                if !vertex_ties(shape, &m, tol, &mut one) {
                    // Only ties past the room fall back (where the search finds more than
                    // 16, or ties on the way to the largest value overflowed).
                    assert!(searched.is_none() || two.count > 1, "direction {m:?}");
                    continue;
                }
                assert!(searched.is_some(), "direction {m:?}");
                taken += 1;
                assert_eq!(one.count, two.count, "direction {m:?}");
                assert_eq!(one.ids[..one.count], two.ids[..two.count]);
                assert_eq!(one.pts[..one.count], two.pts[..two.count]);
                ties += usize::from(one.count > 1);
            }
        }
        assert!(taken > 95_000 && ties > 20_000, "{taken} {ties}");
    }
}

/// The closed-form support sets (box, capsule, cylinder) decide what the search of the pieces
/// decides, affine dimension and direction, on 60 000 directions per shape: random ones, and
/// ones with components at, near and across the tie threshold (a box's edges and faces, a
/// capsule's or cylinder's side), at two scales.
#[cfg(test)]
mod support_set_tests {
    use super::{find, quick, Found, Tied};
    use crate::math::{Mat3, Real, Vec3};
    use crate::shapes::Shape;
    use crate::solver::raycast::Posed;

    #[test]
    fn closed_form_support_sets_match_the_search() {
        let shapes = [
            Shape::cuboid(0.5, 0.35, 0.25).unwrap(),
            Shape::cuboid(2.0, 1e-3, 0.7).unwrap(),
            Shape::capsule(0.3, 0.8).unwrap(),
            Shape::cylinder(0.4, 0.9).unwrap(),
        ];
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut unit = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut t = Tied::EMPTY;
        let (mut ties, mut quick_answers) = (0, 0);
        for shape in &shapes {
            for inv_scale in [1.0, 0.01] {
                for k in 0..30_000 {
                    let mut m = Vec3::new(unit(), unit(), unit());
                    // Components zeroed, and pushed to a few multiples of the tie tolerance
                    // (1e-10 of the scale), around where pieces start and stop tying.
                    for i in 0..3 {
                        match (k + i * 7) % 5 {
                            0 => m[i] = 0.0,
                            1 => m[i] = unit() * 3e-10 / inv_scale,
                            _ => {}
                        }
                    }
                    if m.norm() == 0.0 {
                        continue;
                    }
                    let n = m.normalize();
                    let rot = Mat3::identity();
                    let posed = Posed {
                        shape,
                        rot: &rot,
                        inv_scale,
                    };
                    let Some(fast) = quick(&posed, 1.0, &n) else {
                        continue;
                    };
                    quick_answers += 1;
                    let slow = find(&posed, 1.0, &n, &mut t);
                    match (fast, slow) {
                        (Found::Disc(_), Some(Found::Disc(_))) => {}
                        (Found::Tied(d0, e0), Some(Found::Tied(d1, e1))) => {
                            assert_eq!(d0, d1, "{shape:?} at {n:?}");
                            if d0 == 1 {
                                assert!(e0.cross(&e1).norm() < 1e-12, "{e0:?} {e1:?}");
                            }
                            ties += usize::from(d0 > 0);
                        }
                        (f, s) => panic!("{shape:?} at {n:?}: {f:?} against {s:?}"),
                    }
                }
            }
        }
        // A direction that is not finite: the search finds no feature, nor does the closed form.
        for shape in &shapes {
            let rot = Mat3::identity();
            let posed = Posed {
                shape,
                rot: &rot,
                inv_scale: 1.0,
            };
            for n in [
                Vec3::new(Real::NAN, 0.0, 1.0),
                Vec3::new(Real::INFINITY, 0.0, 0.0),
            ] {
                assert!(quick(&posed, 1.0, &n).is_none(), "{shape:?} {n:?}");
                assert!(find(&posed, 1.0, &n, &mut t).is_none(), "{shape:?} {n:?}");
            }
        }
        assert!(quick_answers > 200_000, "{quick_answers}");
        assert!(ties > 40_000, "{ties}");
    }
}
