//! Convex hull of points, padded by a ball of radius `R ≥ 0`: points within `R` of the hull of
//! the given points (`R = 0`: the hull itself; `R > 0`: what Bullet's collision margin makes of
//! a hull, and a rounded box). The hull is built once (`super::quickhull`) as a polytope, its
//! *core*; a query sees the core's corners, each padded by the ball. Scaled, with the slack
//! `y ∈ R³` (the core point): the cone `[αR; u − y]` and the rows `α o_i − n_i·y ≥ 0`; with
//! `R = 0`, the core's rows on `u` itself.

use super::quickhull::{self, HullError};
use super::support::{ball_normal, PieceEval, Round, SupportMap};
use super::{BodyRow, ConicShape, Polytope, RowPoint, RowSink, Shape};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// The convex hull of a set of points, padded by a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexHull {
    /// The hull as a polytope (a [`Shape`] so that the queries can take it as the core).
    core: Box<Shape>,
    radius: Real,
    /// The points as given.
    points: Vec<[Real; 3]>,
    /// Each corner's index among the points.
    source: Vec<u32>,
    /// Whether another point given is the same as this corner (moving one of the two out moves
    /// the corner, moving it in does not: no derivative).
    shared: Vec<bool>,
}

impl ConvexHull {
    /// Validates `points` (finite, at least four affinely independent, the origin strictly
    /// inside their hull) and `radius` (finite, ≥ 0), and builds the hull.
    pub fn new(points: &[[Real; 3]], radius: Real) -> Result<ConvexHull, Error> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "radius",
                radius,
                "must be finite and non-negative",
            )));
        }
        if points.len() < 4 {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "n",
                points.len() as Real,
                "must be at least 4 (a hull needs four affinely independent points)",
            )));
        }
        let pts: Vec<Vec3> = points.iter().map(|p| Vec3::from(*p)).collect();
        let why = |e: HullError| {
            Error::InvalidShape(match e {
                HullError::NonFinite(i, v) => ErrorDetail::at("points", i, v, "must be finite"),
                HullError::Coincident(n) => ErrorDetail::new(
                    "n",
                    n as Real,
                    "points all coincide (a hull needs four affinely independent points)",
                ),
                HullError::Collinear => ErrorDetail::new(
                    "n",
                    points.len() as Real,
                    "points all lie on one line (a hull needs four affinely independent points)",
                ),
                HullError::Coplanar => ErrorDetail::new(
                    "n",
                    points.len() as Real,
                    "points all lie in one plane (a hull needs four affinely independent \
                     points; a flat shape is a padded polygon)",
                ),
                HullError::Failed(d) => ErrorDetail::new(
                    "points",
                    d,
                    "could not be hulled within rounding (a point was left this far outside)",
                ),
            })
        };
        let mesh = quickhull::hull(&pts).map_err(why)?;
        let source = mesh.source.clone();
        let shared = shared_corners(points, &source);
        let tol = quickhull::tolerance(&pts);
        // Each corner divided first: a sum of coordinates near the largest double overflows.
        let corners = mesh.vertices.len() as Real;
        let centroid = mesh.vertices.iter().map(|v| v / corners).sum::<Vec3>();
        let poly = Polytope::from_mesh(mesh, tol).map_err(|least| {
            Error::InvalidShape(ErrorDetail::with_point(
                "points",
                least,
                "must surround the origin strictly (the value is the nearest facet's signed \
                 distance from it): shift them by minus the centroid of their hull's corners",
                [centroid.x, centroid.y, centroid.z],
            ))
        })?;
        let core = Shape::polytope_shape(poly)?;
        Ok(ConvexHull {
            core: Box::new(core),
            radius,
            points: points.to_vec(),
            source,
            shared,
        })
    }

    /// The points as given (row-major, body frame).
    pub fn points(&self) -> &[[Real; 3]] {
        &self.points
    }

    /// The padding radius `R` (0: the hull itself).
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The hull's corners (a subset of the points; body frame).
    pub fn corners(&self) -> &[Vec3] {
        self.poly().vertices()
    }

    /// The hull as a polytope shape (unpadded).
    pub(crate) fn core(&self) -> &Shape {
        &self.core
    }

    pub(crate) fn poly(&self) -> &Polytope {
        self.core
            .as_polytope()
            .expect("a hull's core is a polytope by construction")
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        self.core.bounding_radius() + self.radius
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        self.core.inscribed_radius() + self.radius
    }
}

/// The derivatives with respect to the points and the radius (`docs/derivatives.md`,
/// "Derivatives with respect to the shapes"). A point of the hull's boundary is a convex
/// combination `Σ w_k v_k` of the corners of its feature (a corner, an edge, a facet); moving
/// corner `k` by `δ` moves the boundary there by `w_k δ` (the facet's plane through its
/// corners, to first order), so the support function at that point changes by `w_k m·δ`.
/// A facet of three corners has one such combination; a facet of more (coplanar corners) has
/// many, and moving one corner off its plane folds the facet one way or the other: one of them
/// (a triangle of the facet's fan) is used, and the answer is flagged.
impl ConvexHull {
    /// `3n + 1`: the points (row-major), then the radius.
    pub(crate) fn parameter_count(&self) -> usize {
        3 * self.points.len() + 1
    }

    /// Writes the points (row-major) and the radius, as given.
    pub(crate) fn write_parameters(&self, out: &mut [Real]) {
        let n = self.points.len();
        for (i, p) in self.points.iter().enumerate() {
            out[3 * i..3 * i + 3].copy_from_slice(p);
        }
        out[3 * n] = self.radius;
    }

    /// `∂h(m)/∂(points, R)` at the support point `x` (body frame) into `out` (overwritten): `‖m‖` for the radius, and `w_k m` for the point behind each corner `k` of the
    /// core point's feature. False where that is not unique (a facet of more than three
    /// corners, or a corner given twice among the points).
    pub(crate) fn support_gradient(&self, m: &Vec3, x: &Vec3, out: &mut [Real]) -> bool {
        let mn = m.norm();
        out[..3 * self.points.len()].fill(0.0);
        out[3 * self.points.len()] = mn;
        let core = if self.radius > 0.0 && mn > 0.0 {
            x - m * (self.radius / mn)
        } else {
            *x
        };
        let (ids, w, k, mut unique) = self.feature(&core);
        for t in 0..k {
            let s = self.source[ids[t]] as usize;
            for j in 0..3 {
                out[3 * s + j] += w[t] * m[j];
            }
            unique &= !self.shared[ids[t]];
        }
        unique
    }

    /// The corners (indices into [`ConvexHull::corners`]) and weights whose combination is the
    /// core point `y` (on the core's boundary), their number, and whether they are the only
    /// ones: a corner where three or more facets are active (within 1e-8 of the core's
    /// bounding radius), an edge where two are, a facet's triangle where one is.
    fn feature(&self, y: &Vec3) -> ([usize; 3], [Real; 3], usize, bool) {
        let poly = self.poly();
        let (normals, offsets) = poly.facets();
        let tol = 1e-8 * self.core.bounding_radius();
        let mut active = [0usize; 3];
        let mut count = 0;
        for (f, (n, o)) in normals.iter().zip(offsets).enumerate() {
            if n.dot(y) >= o - tol {
                if count < 3 {
                    active[count] = f;
                }
                count += 1;
            }
        }
        let corners = self.corners();
        let nearest = |ids: &mut dyn Iterator<Item = usize>| {
            ids.min_by(|&a, &b| {
                (corners[a] - y)
                    .norm_squared()
                    .total_cmp(&(corners[b] - y).norm_squared())
            })
        };
        let loop_of = |f: usize| poly.facet_loop(f).unwrap_or(&[]);
        match count {
            1 => {
                let l = loop_of(active[0]);
                if l.len() < 3 {
                    return self.vertex(nearest(&mut (0..corners.len())), false);
                }
                let (tri, w) = fan_triangle(corners, l, y);
                (tri, w, 3, l.len() == 3)
            }
            2 => {
                let (la, lb) = (loop_of(active[0]), loop_of(active[1]));
                let mut common = la.iter().filter(|c| lb.contains(c)).map(|&c| c as usize);
                match (common.next(), common.next()) {
                    (Some(a), Some(b)) => {
                        let e = corners[b] - corners[a];
                        let t = ((y - corners[a]).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
                        ([a, b, 0], [1.0 - t, t, 0.0], 2, true)
                    }
                    _ => self.vertex(nearest(&mut (0..corners.len())), false),
                }
            }
            0 => self.vertex(nearest(&mut (0..corners.len())), false),
            _ => {
                let l = loop_of(active[0]);
                let k = nearest(&mut l.iter().map(|&c| c as usize));
                let close = k.is_some_and(|k| (corners[k] - y).norm() <= 1e3 * tol);
                self.vertex(k, close)
            }
        }
    }

    /// One corner with weight one (`None`: none at all).
    fn vertex(&self, k: Option<usize>, unique: bool) -> ([usize; 3], [Real; 3], usize, bool) {
        match k {
            Some(k) => ([k, 0, 0], [1.0, 0.0, 0.0], 1, unique),
            None => ([0; 3], [0.0; 3], 0, false),
        }
    }

    /// The rows' derivatives at `p` (`shapes/parameters.rs`): the cone's `αR·inv_scale`, and
    /// facet `f`'s row `α o_f·inv_scale − n_f·y` (`y` the core point: `u` unpadded, the slack
    /// `w` padded) as a function of the corners through its plane. For the triangle `(A, B, C)`
    /// of the facet (`N = (B − A)×(C − A)`) the row moves with corner `A` by
    /// `inv_scale·w̃_A n_f`, `w̃_A = (α (B×C) + y'×(B − C))·N/‖N‖²` (`y' = y/inv_scale`): `α`
    /// times the barycentric weight of `y'/α`, linear in the point. A facet of more corners
    /// takes the triangle of its fan that holds `at` (the solution's core point, body frame);
    /// false when such a facet, or a corner given twice, carries weight. `central`: the points
    /// are those of the central path's adjoint, not `−λ` times the solution point.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        at: &Vec3,
        central: bool,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) -> bool {
        let n = self.points.len();
        let padded = self.radius > 0.0;
        if padded {
            out[3 * n] += inv_scale * p(0).a;
        }
        let poly = self.poly();
        let (normals, _) = poly.facets();
        let corners = self.corners();
        let biggest = (0..normals.len()).fold(0.0, |b: Real, f| b.max(p(4 + f).a.abs()));
        let mut unique = true;
        // Unpadded, the radius's derivative (growing it from 0) is that of a cone whose
        // multiplier balances the facets': `−inv_scale·‖Σ_f p_f.α n_f‖` at the optimum (where
        // every `p_f` is `−λ_f` times the solution point). The central path has none: padding a
        // hull adds a cone to the program, whose barrier moves the central point by O(μ) at once.
        if !padded && !central {
            let v: Vec3 = normals
                .iter()
                .enumerate()
                .map(|(f, n)| n * p(4 + f).a)
                .sum();
            out[3 * n] -= inv_scale * v.norm();
        }
        for (f, nf) in normals.iter().enumerate() {
            let q = p(4 + f);
            let y = if padded { q.w } else { q.u };
            let l = poly.facet_loop(f).unwrap_or(&[]);
            if l.len() < 3 {
                continue;
            }
            let (tri, _) = fan_triangle(corners, l, at);
            let significant = q.a.abs() > 1e-6 * biggest;
            if l.len() > 3 && significant {
                unique = false;
            }
            let [a, b, c] = tri.map(|k| corners[k]);
            let big_n = (b - a).cross(&(c - a));
            let nn = big_n.norm_squared();
            if !(nn > 0.0) {
                continue;
            }
            for (k, (u, v)) in [(b, c), (c, a), (a, b)].into_iter().enumerate() {
                let wt = (u.cross(&v) * (inv_scale * q.a) + y.cross(&(u - v))).dot(&big_n) / nn;
                let s = self.source[tri[k]] as usize;
                for j in 0..3 {
                    out[3 * s + j] += wt * nf[j];
                }
                if significant && wt != 0.0 && self.shared[tri[k]] {
                    unique = false;
                }
            }
        }
        unique
    }

    /// `∂ρ/∂(points, R)` of the bounding radius (the farthest corner's distance plus `R`):
    /// the support function's derivative along that corner's direction.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) -> bool {
        let Some(v) = self
            .corners()
            .iter()
            .max_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()))
        else {
            return false;
        };
        let dir = v.normalize();
        self.support_gradient(&dir, &(v + dir * self.radius), out)
    }
}

/// The triangle `(l₀, l_i, l_{i+1})` of a facet's fan (corner loop `l`) that holds the
/// projection of `y` (the one that comes closest, if rounding leaves none), and the
/// barycentric weights of that projection.
fn fan_triangle(corners: &[Vec3], l: &[u32], y: &Vec3) -> ([usize; 3], [Real; 3]) {
    let mut best = ([0usize; 3], [0.0; 3], Real::NEG_INFINITY);
    for i in 1..l.len() - 1 {
        let tri = [l[0] as usize, l[i] as usize, l[i + 1] as usize];
        let w = barycentric(&corners[tri[0]], &corners[tri[1]], &corners[tri[2]], y);
        let least = w[0].min(w[1]).min(w[2]);
        if least > best.2 {
            best = (tri, w, least);
        }
        if least >= -1e-12 {
            break;
        }
    }
    (best.0, best.1)
}

/// The barycentric weights in the triangle `(a, b, c)` of the projection of `y` onto its plane.
fn barycentric(a: &Vec3, b: &Vec3, c: &Vec3, y: &Vec3) -> [Real; 3] {
    let n = (b - a).cross(&(c - a));
    let nn = n.norm_squared();
    if !(nn > 0.0) {
        return [1.0, 0.0, 0.0];
    }
    let w = |p: &Vec3, q: &Vec3| (p - y).cross(&(q - y)).dot(&n) / nn;
    [w(b, c), w(c, a), w(a, b)]
}

/// For each corner (`source`: its index among `points`), whether another of the points has the
/// same coordinates (`==`, so −0 and +0 are the same).
///
/// The points are sorted by a hash of their coordinates' bits (one integer comparison each:
/// the full lexicographic sort was a quarter of a 10 000-point hull's build), and each run of
/// equal hashes, where equal points lie, by the coordinates themselves.
fn shared_corners(points: &[[Real; 3]], source: &[u32]) -> Vec<bool> {
    let bits = |p: &[Real; 3]| p.map(|x| (x + 0.0).to_bits());
    let mut order: Vec<(u64, u32)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let [a, b, c] = bits(p);
            let mut h = a.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            h = (h ^ b).wrapping_mul(0xC2B2_AE3D_27D4_EB4F);
            h = (h ^ c).wrapping_mul(0x1656_67B1_9E37_79F9);
            (h ^ (h >> 29), i as u32)
        })
        .collect();
    order.sort_unstable();
    let key = |i: u32| points[i as usize].map(|x| x + 0.0);
    let mut repeated = vec![false; points.len()];
    let mut run: Vec<u32> = Vec::new();
    let mut start = 0;
    while start < order.len() {
        let end = start + order[start..].partition_point(|e| e.0 == order[start].0);
        if end - start > 1 {
            run.clear();
            run.extend(order[start..end].iter().map(|e| e.1));
            run.sort_unstable_by(|&a, &b| {
                let (p, q) = (key(a), key(b));
                p[0].total_cmp(&q[0])
                    .then(p[1].total_cmp(&q[1]))
                    .then(p[2].total_cmp(&q[2]))
            });
            for w in run.windows(2) {
                if key(w[0]) == key(w[1]) {
                    repeated[w[0] as usize] = true;
                    repeated[w[1] as usize] = true;
                }
            }
        }
        start = end;
    }
    source.iter().map(|&s| repeated[s as usize]).collect()
}

impl SupportMap for ConvexHull {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let (p, k) = self.poly().support(m);
        if self.radius > 0.0 {
            (p + Round::Ball(self.radius).point(m), k)
        } else {
            (p, k)
        }
    }
    #[inline(always)]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        let v = self.corners().get(id as usize)?;
        if self.radius > 0.0 {
            Round::Ball(self.radius).eval(v, m)
        } else {
            Round::Flat.eval(v, m)
        }
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        // The padded facets keep the core's normals.
        self.poly().flat_face(m, cos_min)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        // The core grown by the factor 1 + R/ρ (ρ its bounding radius) lies in the padded hull:
        // each of its points is within R of the core point it was scaled from.
        let rho = self.core.bounding_radius();
        self.poly().gauge(p) / (1.0 + self.radius / rho)
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        if self.radius > 0.0 {
            ball_normal(self.corners().get(id as usize)?, p)
        } else {
            None
        }
    }
    fn piece_count(&self) -> u32 {
        self.corners().len() as u32
    }
    fn vertex_pieces(&self) -> Option<&[Vec3]> {
        // Unpadded, piece `id` is the corner `id` itself (`Round::Flat`).
        (self.radius == 0.0).then(|| self.corners())
    }
    fn ball_pieces(&self) -> Option<(&[Vec3], Real)> {
        // Padded, piece `id` is the corner `id` padded by the ball (`Round::Ball`).
        (self.radius > 0.0).then(|| (self.corners(), self.radius))
    }
}

impl ConicShape for ConvexHull {
    fn lp_count(&self) -> usize {
        self.poly().lp_count()
    }
    fn slack_count(&self) -> usize {
        if self.radius > 0.0 {
            3
        } else {
            0
        }
    }
    fn soc_count(&self) -> usize {
        usize::from(self.radius > 0.0)
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        if self.radius == 0.0 {
            return self.poly().rows(inv_scale, sink);
        }
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([1.0, 0.0, 0.0], 0.0, [-1.0, 0.0, 0.0]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0, -1.0, 0.0]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0, 0.0, -1.0]),
        ]);
        let (normals, offsets) = self.poly().facets();
        for (n, o) in normals.iter().zip(offsets) {
            sink.lp(BodyRow::new([0.0; 3], o * inv_scale, [-n.x, -n.y, -n.z]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    fn cube(h: Real) -> Vec<[Real; 3]> {
        let mut p = Vec::new();
        for i in 0..8 {
            p.push([0, 1, 2].map(|k| if i >> k & 1 == 1 { h } else { -h }));
        }
        p
    }

    #[test]
    fn a_padded_cube_is_a_rounded_box() {
        let h = ConvexHull::new(&cube(1.0), 0.25).unwrap();
        assert_eq!(h.corners().len(), 8);
        assert_eq!(h.bounding_radius(), 3f64.sqrt() + 0.25);
        assert_eq!(h.inscribed_radius(), 1.25);
        // Support: the corner plus the ball.
        let (s, _) = h.support(&Vec3::new(1.0, 1.0, 1.0));
        assert!((s - Vec3::repeat(1.0 + 0.25 / 3f64.sqrt())).norm() < 1e-15);
        let (s, _) = h.support(&Vec3::new(0.0, 0.0, -2.0));
        assert!((s.z + 1.25).abs() < 1e-15);
        // The conic rows: a point within R of the cube, with its core point as the slack.
        assert!(member(&h, [1.2, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]));
        assert!(member(&h, [1.1, 1.1, 0.0], 1.0, [1.0, 1.0, 0.0]));
        assert!(!member(&h, [1.2, 1.2, 0.0], 1.0, [1.0, 1.0, 0.0]));
        assert!(!member(&h, [1.3, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]));
        // The gauge is an upper bound: p/g lies in the shape.
        for p in [
            Vec3::new(1.24, 0.0, 0.0),
            Vec3::new(1.1, 1.1, 1.1),
            Vec3::new(0.3, -2.0, 0.1),
        ] {
            let g = h.gauge(&p);
            let q = p / g;
            let core = q.map(|v| v.clamp(-1.0, 1.0));
            assert!((q - core).norm() <= 0.25 + 1e-12, "{p:?}");
        }
    }

    #[test]
    fn an_unpadded_hull_is_its_polytope() {
        let h = ConvexHull::new(&cube(0.5), 0.0).unwrap();
        assert_eq!(h.slack_count(), 0);
        assert_eq!(h.lp_count(), 6);
        assert!(member(&h, [0.5, -0.5, 0.4], 1.0, [0.0; 0]));
        assert!(!member(&h, [0.51, 0.0, 0.0], 1.0, [0.0; 0]));
        assert_eq!(h.gauge(&Vec3::new(1.0, 0.25, 0.0)), 2.0);
        assert_eq!(h.core().centred_box(), Some(Vec3::repeat(0.5)));
    }

    #[test]
    fn bad_points_say_why() {
        let msg = |r: Result<ConvexHull, Error>| r.unwrap_err().to_string();
        assert!(msg(ConvexHull::new(&cube(1.0), -0.1)).contains("radius"));
        assert!(msg(ConvexHull::new(&cube(1.0)[..3], 0.0)).contains("at least 4"));
        let mut nan = cube(1.0);
        nan[2][1] = Real::NAN;
        assert!(msg(ConvexHull::new(&nan, 0.0)).contains("points[7]"));
        let flat: Vec<[Real; 3]> = cube(1.0).into_iter().map(|p| [p[0], p[1], 0.0]).collect();
        assert!(msg(ConvexHull::new(&flat, 0.1)).contains("one plane"));
        let shifted: Vec<[Real; 3]> = cube(1.0)
            .into_iter()
            .map(|p| [p[0] + 3.0, p[1], p[2]])
            .collect();
        let m = msg(ConvexHull::new(&shifted, 0.0));
        assert!(
            m.contains("surround the origin") && m.contains("(3, 0, 0)"),
            "{m}"
        );
        // The origin on a facet is not strictly inside.
        let touching: Vec<[Real; 3]> = cube(1.0)
            .into_iter()
            .map(|p| [p[0] + 1.0, p[1], p[2]])
            .collect();
        assert!(msg(ConvexHull::new(&touching, 0.0)).contains("surround the origin"));
    }

    /// The hashed sort finds exactly the corners that another point repeats, as comparing every
    /// pair does: random sets with exact repeats, −0 against +0, and points differing in one
    /// coordinate's last bit.
    #[test]
    fn shared_corners_are_the_repeated_points() {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        for _ in 0..200 {
            let n = 5 + (next() % 60) as usize;
            let mut pts: Vec<[Real; 3]> = Vec::new();
            for _ in 0..n {
                let pick = next() % 4;
                if pick == 0 && !pts.is_empty() {
                    let q = pts[(next() % pts.len() as u64) as usize];
                    pts.push(q);
                } else if pick == 1 && !pts.is_empty() {
                    let mut q = pts[(next() % pts.len() as u64) as usize];
                    let k = (next() % 3) as usize;
                    q[k] = if q[k] == 0.0 {
                        -q[k]
                    } else {
                        Real::from_bits(q[k].to_bits() ^ 1)
                    };
                    pts.push(q);
                } else {
                    let c = |v: u64| [0.0, -0.0, 1.0, -1.0, 0.5][(v % 5) as usize];
                    pts.push([c(next()), c(next()), c(next())]);
                }
            }
            let source: Vec<u32> = (0..n as u32).filter(|_| next() % 2 == 0).collect();
            let brute: Vec<bool> = source
                .iter()
                .map(|&i| (0..n).any(|j| j != i as usize && pts[j] == pts[i as usize]))
                .collect();
            assert_eq!(shared_corners(&pts, &source), brute, "{pts:?}");
        }
    }
}
