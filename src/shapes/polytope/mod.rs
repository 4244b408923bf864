//! Polytope: `A b ≤ b`, every `b_i > 0` (origin strictly inside), bounded. Scaled: the rows
//! `α b_i − a_i·u ≥ 0`.

mod build;
mod gradient;

use super::climb::Climb;
use super::quickhull::Lists;
use super::support::{argmax_dot, PieceEval, Round, SupportMap};
use super::{BodyRow, ConicShape, RowSink};
use crate::math::{Real, Vec3};

pub(crate) use build::add_vertex;

/// Polytopes with this many vertices or more find their support vertex by hill climbing
/// (`super::climb`) rather than a dot product per vertex. Measured (proximity, 200 poses,
/// random facets): against the same polytope 1 192 -> 942 ns at 20 facets (36 vertices),
/// 2 885 -> 1 212 at 100, 4 236 -> 1 302 at 256; against a sphere 621 -> 651 at 20 facets,
/// 1 101 -> 641 at 256; on benches/proximity's 12-facet polytope (20 vertices) the search
/// stays ahead for spheres, capsules and ellipsoids (by 5-9 %).
const CLIMB_MIN: usize = 24;

/// Polytopes given by more planes than this find their vertices as the polar polytope's
/// facets (the convex hull of the points `a_i/b_i`, O(m log m)) rather than by trying every
/// triple of planes (O(m³) triples, each checked against every plane).
const ENUMERATE_MAX: usize = 64;

/// Polytopes with this many facets or more find their gauge (and the facet facing a
/// direction) by climbing the facet graph rather than by a dot product per facet.
const GAUGE_CLIMB_MIN: usize = 24;

/// A bounded convex polytope in halfspace form.
#[derive(Clone, Debug, PartialEq)]
pub struct Polytope {
    a: Vec<[Real; 3]>,
    b: Vec<Real>,
    /// The vertices, deduplicated (the support map is the best of them).
    vertices: Vec<Vec3>,
    /// The facets' outward unit normals.
    normals: Vec<Vec3>,
    /// The facets' offsets along their unit normals, `b_i/|a_i|`.
    offsets: Vec<Real>,
    /// Half extents when the polytope is a box centred at its origin and aligned with its axes.
    half_extents: Option<Vec3>,
    /// A box's support vertex for each sign pattern of the direction (−, 0, + per axis, base
    /// 3): the first vertex of the list whose coordinates have the signs of the non-zero
    /// components, which is the first maximiser `argmax_dot` returns.
    box_support: Option<[u8; 27]>,
    /// The vertex graph and start table of the support map's hill climb (`super::climb`), for
    /// polytopes with [`CLIMB_MIN`] vertices or more.
    climb: Option<Climb>,
    /// The facets' corner loops and the polar climb, for polytopes built from a hull.
    faces: Option<Box<Faces>>,
    bounding_radius: Real,
    inscribed_radius: Real,
}

/// Polytopes with at most this many facets and edge directions give the separating-axis
/// penetration (`crate::solver::sat`) their edge directions: a box has 6 and 3 (two boxes: 30
/// candidate normals), a 12-facet polytope about 15 directions (a pair: 474 candidates, more
/// than EPA costs).
const SAT_FACETS: usize = 16;
const SAT_DIRECTIONS: usize = 8;

/// What a polytope knows of its facets beyond their planes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Faces {
    /// Each facet's corners (indices into the vertices), counter-clockwise seen from outside
    /// (a redundant plane's list is empty).
    loops: Lists,
    /// The directions of the edges (unit, body frame, one of each pair of opposite ones) when
    /// there are at most [`SAT_DIRECTIONS`] of them and [`SAT_FACETS`] facets.
    edge_directions: Option<Vec<Vec3>>,
    /// Whether some plane bounds no facet (a redundant row: its loop has fewer than three
    /// corners).
    redundant: bool,
    /// The polar polytope's corners `n_i/o_i`, one per facet.
    polar: Vec<Vec3>,
    /// The climb on the facet graph (two facets joined when they share an edge) that finds the
    /// largest `polar_i·p`, the gauge of `p`; for polytopes of [`GAUGE_CLIMB_MIN`] facets or
    /// more.
    gauge: Option<Climb>,
}

impl Polytope {
    /// The facet normals `A` (rows, as given).
    pub fn a(&self) -> &[[Real; 3]] {
        &self.a
    }

    /// The offsets `b`.
    pub fn b(&self) -> &[Real] {
        &self.b
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        self.bounding_radius
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        self.inscribed_radius
    }

    /// The vertices (deduplicated).
    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The facets' outward unit normals and their offsets (`n_i·x ≤ o_i`).
    pub(crate) fn facets(&self) -> (&[Vec3], &[Real]) {
        (&self.normals, &self.offsets)
    }

    /// Half extents when this is a box centred at its origin and aligned with its axes.
    pub(crate) fn half_extents(&self) -> Option<Vec3> {
        self.half_extents
    }

    /// The corners (indices into [`Polytope::vertices`]) of the facet whose outward unit
    /// normal is `normal` (one of [`Polytope::facets`]'), counter-clockwise seen from outside,
    /// when the polytope knows its facets' loops (built from a hull).
    pub(crate) fn facet_corners(&self, normal: &Vec3) -> Option<&[u32]> {
        let faces = self.faces.as_deref()?;
        let k = self.normals.iter().position(|n| n == normal)?;
        Some(faces.loops.get(k))
    }

    /// The corners of facet `k` (as [`Polytope::facet_corners`]).
    pub(crate) fn facet_loop(&self, k: usize) -> Option<&[u32]> {
        let faces = self.faces.as_deref()?;
        (k < faces.loops.first.len().saturating_sub(1)).then(|| faces.loops.get(k))
    }

    /// The unit edge directions (body frame, one per pair of opposite ones) of a polytope of
    /// few facets and edge directions (a box: its three axes), for the separating-axis
    /// penetration.
    pub(crate) fn edge_directions(&self) -> Option<&[Vec3]> {
        self.faces.as_deref()?.edge_directions.as_deref()
    }

    /// The facet whose outward unit normal is best aligned with `m` by a scan of every facet
    /// (the last on a tie, as [`Polytope::facet_index`] picks it; for a box's six facets, its
    /// choice without its search) and that normal's dot product with `m`.
    pub(crate) fn scan_facet(&self, m: &Vec3) -> (usize, Real) {
        let mut k = 0;
        let mut best = self.normals[0].dot(m);
        for (i, nrm) in self.normals.iter().enumerate().skip(1) {
            let c = nrm.dot(m);
            if c.total_cmp(&best) != std::cmp::Ordering::Less {
                (k, best) = (i, c);
            }
        }
        (k, best)
    }

    /// The index of the facet whose outward unit normal is closest to `m`, when its cosine
    /// with `m` is at least `cos_min` ([`SupportMap::flat_face`]).
    pub(crate) fn facet_index(&self, m: &Vec3, cos_min: Real) -> Option<usize> {
        let n = m.norm();
        let Some(mut k) = self.gauge_facet(m) else {
            // Planes that bound no facet (redundant rows) are no face.
            let real = |i: &usize| {
                self.faces
                    .as_deref()
                    .map_or(true, |f| !f.redundant || f.loops.get(*i).len() >= 3)
            };
            let best = (0..self.normals.len())
                .filter(real)
                .map(|i| (self.normals[i].dot(m), i))
                .max_by(|a, b| a.0.total_cmp(&b.0));
            return best
                .filter(|(c, _)| n > 0.0 && *c >= cos_min * n)
                .map(|(_, i)| i);
        };
        // From the facet whose polar corner is best along m, the best aligned normal by
        // steepest ascent on the facet graph.
        let graph = self.faces.as_deref()?.gauge.as_ref()?.graph();
        let mut c = self.normals[k].dot(m);
        loop {
            let mut next = k;
            for &j in graph.get(k) {
                let cj = self.normals[j as usize].dot(m);
                if cj > c {
                    (c, next) = (cj, j as usize);
                }
            }
            if next == k {
                break;
            }
            k = next;
        }
        (n > 0.0 && c >= cos_min * n).then_some(k)
    }

    /// The vertices tied with vertex `k` for the support in direction `m` (value within `tol`
    /// of `k`'s, the best): their sum and count, found on the vertex graph (a polytope's tied
    /// vertices are a face of it, connected by its edges); `None` for a polytope without a
    /// graph (a few vertices: scan them) or a face of more than 64 vertices.
    pub(crate) fn tied(&self, k: usize, m: &Vec3, tol: Real) -> Option<(Vec3, usize)> {
        let graph = self.climb.as_ref()?.graph();
        let h = self.vertices[k].dot(m);
        // A facet facing m whose corners all tie: the support set is that facet.
        if let (Some(f), Some(faces)) = (self.facet_index(m, 0.0), self.faces.as_deref()) {
            let l = faces.loops.get(f);
            if l.len() >= 3
                && l.contains(&(k as u32))
                && l.iter()
                    .all(|&v| self.vertices[v as usize].dot(m) >= h - tol)
            {
                let sum = l.iter().map(|&v| self.vertices[v as usize]).sum();
                return Some((sum, l.len()));
            }
        }
        let mut seen: arrayvec::ArrayVec<u32, 64> = arrayvec::ArrayVec::new();
        seen.push(k as u32);
        let mut at = 0;
        while at < seen.len() {
            let v = seen[at] as usize;
            at += 1;
            for &j in graph.get(v) {
                if self.vertices[j as usize].dot(m) >= h - tol && !seen.contains(&j) {
                    seen.try_push(j).ok()?;
                }
            }
        }
        let sum = seen.iter().map(|&v| self.vertices[v as usize]).sum();
        Some((sum, seen.len()))
    }

    /// The support function `max over the vertices of m·v`.
    #[inline]
    pub(crate) fn support_value(&self, m: &Vec3) -> Real {
        self.support(m).0.dot(m)
    }

    /// The index of the facet whose polar corner `n_i/o_i` is largest along `p` (its gauge is
    /// that value), by the climb when there is one.
    fn gauge_facet(&self, p: &Vec3) -> Option<usize> {
        let faces = self.faces.as_deref()?;
        let climb = faces.gauge.as_ref()?;
        Some(climb.support(&faces.polar, p))
    }
}

impl SupportMap for Polytope {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        // A centred box: by the signs of the direction (three comparisons and a table, where
        // the search costs a dot product per vertex).
        if let Some(t) = &self.box_support {
            let s = |v: Real| usize::from(v >= 0.0) + usize::from(v > 0.0);
            let k = t[s(m.x) * 9 + s(m.y) * 3 + s(m.z)] as usize;
            return (self.vertices[k], k as u32);
        }
        if let Some(c) = &self.climb {
            let k = c.support(&self.vertices, m);
            return (self.vertices[k], k as u32);
        }
        let (k, _) = argmax_dot(&self.vertices, m);
        (self.vertices[k], k as u32)
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        Round::Flat.eval(self.vertices.get(id as usize)?, m)
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        Some(self.normals[self.facet_index(m, cos_min)?])
    }
    fn gauge(&self, p: &Vec3) -> Real {
        if let Some(k) = self.gauge_facet(p) {
            return self
                .faces
                .as_deref()
                .map_or(0.0, |f| f.polar[k].dot(p).max(0.0));
        }
        self.a.iter().zip(&self.b).fold(0.0, |g: Real, (a, b)| {
            g.max((a[0] * p.x + a[1] * p.y + a[2] * p.z) / b)
        })
    }
    fn piece_count(&self) -> u32 {
        self.vertices.len() as u32
    }
    fn vertex_pieces(&self) -> Option<&[Vec3]> {
        Some(&self.vertices)
    }
    fn support_set(&self, m: &Vec3, tie: Real, point: Real) -> Option<(usize, Vec3)> {
        // A centred box: the vertex flipped along axis i is 2hᵢ|mᵢ| below the support value,
        // so the tied vertices span the axes where that is within `tie`.
        let h = self.half_extents.filter(|_| self.box_support.is_some())?;
        let mut set = (0, Vec3::zeros());
        for i in 0..3 {
            let edge = 2.0 * h[i];
            if edge * m[i].abs() <= tie && edge > point {
                set.0 += 1;
                set.1[i] = 1.0;
            }
        }
        Some(set)
    }
}

impl ConicShape for Polytope {
    fn lp_count(&self) -> usize {
        self.a.len()
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn soc_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        for (a, b) in self.a.iter().zip(&self.b) {
            sink.lp(BodyRow::new([-a[0], -a[1], -a[2]], b * inv_scale, [0.0; 3]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn the_hill_climb_finds_the_searchs_support_value() {
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
        };
        let mut climbed = 0;
        for m in [12, 20, 40, 100, 256] {
            for _ in 0..4 {
                let a: Vec<[Real; 3]> = (0..m)
                    .map(|_| {
                        let v = Vec3::new(next(), next(), next()).normalize();
                        [v.x, v.y, v.z]
                    })
                    .collect();
                let b: Vec<Real> = (0..m).map(|_| 1.0 + 0.3 * next()).collect();
                let Ok(p) = Polytope::new(&a, &b) else {
                    continue;
                };
                climbed += usize::from(p.climb.is_some());
                for _ in 0..2000 {
                    // Directions on a coarse grid now and then: ties between vertices.
                    let mut d = Vec3::new(next(), next(), next());
                    if next() > 0.5 {
                        d = d.map(|v| (v * 2.0).round());
                    }
                    let (v, _) = p.support(&d);
                    let (_, h) = super::super::support::argmax_dot(&p.vertices, &d);
                    assert!(v.dot(&d) >= h - 1e-15 * h.abs().max(1.0), "{d:?}");
                }
            }
        }
        assert!(climbed >= 15, "only {climbed} polytopes climb");
    }

    #[test]
    fn a_box_support_by_signs_is_the_search_s() {
        let b = Polytope::new(
            &[
                [1.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
            ],
            &[0.5, 0.5, 0.3, 0.3, 0.2, 0.2],
        )
        .unwrap();
        assert!(b.box_support.is_some());
        for p in 0..27 {
            let m = Vec3::new(
                (p / 9) as Real - 1.0,
                ((p / 3) % 3) as Real - 1.0,
                (p % 3) as Real - 1.0,
            )
            .component_mul(&Vec3::new(0.3, -1.7, 2.9));
            let (v, k) = b.support(&m);
            let (j, h) = super::super::support::argmax_dot(&b.vertices, &m);
            assert_eq!(v, b.vertices[k as usize]);
            assert_eq!(v.dot(&m), h, "{m:?}: vertex {k} against {j}");
        }
        // Not a box: no table.
        let t = Polytope::new(
            &[
                [1.0, 1.0, 1.0],
                [-1.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, -1.0],
            ],
            &[1.0, 1.0, 1.0, 1.0],
        )
        .unwrap();
        assert!(t.box_support.is_none());
    }

    const BOX_A: [[Real; 3]; 6] = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];

    #[test]
    fn box_radii_and_membership() {
        let p = Polytope::new(&BOX_A, &[1.0, 2.0, 3.0, 1.0, 2.0, 3.0]).unwrap();
        assert!((p.bounding_radius() - 14f64.sqrt()).abs() < 1e-14);
        assert_eq!(p.inscribed_radius(), 1.0);
        assert!(member(&p, [0.9, -1.9, 2.9], 1.0, [0.0; 2]));
        assert!(!member(&p, [1.1, 0.0, 0.0], 1.0, [0.0; 2]));
    }

    #[test]
    fn rejects_unbounded_and_bad_rows() {
        // Missing the -z face: unbounded.
        assert!(Polytope::new(&BOX_A[..5], &[1.0; 5]).is_err());
        // Zero row.
        let mut a = BOX_A;
        a[2] = [0.0; 3];
        assert!(Polytope::new(&a, &[1.0; 6]).is_err());
        // Non-positive offset.
        assert!(Polytope::new(&BOX_A, &[1.0, 1.0, 0.0, 1.0, 1.0, 1.0]).is_err());
        // Mismatched lengths and empty.
        assert!(Polytope::new(&BOX_A, &[1.0; 5]).is_err());
        assert!(Polytope::new(&[], &[]).is_err());
        // Tetrahedron is fine.
        let t = [
            [1.0, 1.0, 1.0],
            [-1.0, -1.0, 1.0],
            [-1.0, 1.0, -1.0],
            [1.0, -1.0, -1.0],
        ];
        assert!(Polytope::new(&t, &[1.0; 4]).is_ok());
    }
}
