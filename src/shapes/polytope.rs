//! Polytope: `A b ≤ b`, every `b_i > 0` (origin strictly inside), bounded. Scaled: the rows
//! `α b_i − a_i·u ≥ 0`.

use super::climb::Climb;
use super::quickhull::{self, HullError, Lists, Mesh};
use super::support::{argmax_dot, nearest_normal, PieceEval, Round, SupportMap};
use super::{check_halfspaces, BodyRow, ConicShape, RowSink};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

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

/// What a polytope built from a convex hull (of its points, or of its polar points) knows of
/// its facets.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Faces {
    /// Each facet's corners (indices into the vertices), counter-clockwise seen from outside.
    loops: Lists,
    /// The polar polytope's corners `n_i/o_i`, one per facet.
    polar: Vec<Vec3>,
    /// The climb on the facet graph (two facets joined when they share an edge) that finds the
    /// largest `polar_i·p`, the gauge of `p`; for polytopes of [`GAUGE_CLIMB_MIN`] facets or
    /// more.
    gauge: Option<Climb>,
}

impl Polytope {
    /// Validates `A` (m×3, rows non-zero, finite) and `b` (m, positive, finite), m ≤
    /// [`super::MAX_FACETS`], and that the set is bounded; finds its vertices.
    pub fn new(a: &[[Real; 3]], b: &[Real]) -> Result<Polytope, Error> {
        check_halfspaces("A", "b", a, b, super::MAX_FACETS)?;
        if a.len() <= ENUMERATE_MAX {
            Polytope::enumerated(a, b)
        } else {
            Polytope::polar(a, b)
        }
    }

    /// The polytope whose facets are the hull `mesh` of points (the corners), as
    /// [`super::Shape::convex_hull`] builds it: `Err(offset)` with the least facet offset when
    /// the origin is not strictly inside.
    pub(crate) fn from_mesh(mesh: Mesh, tol: Real) -> Result<Polytope, Real> {
        let least = mesh.offsets.iter().cloned().fold(Real::INFINITY, Real::min);
        if !(least > tol) {
            return Err(least);
        }
        let a: Vec<[Real; 3]> = mesh.normals.iter().map(|n| [n.x, n.y, n.z]).collect();
        let faces = Faces::new(mesh.loops, &mesh.normals, &mesh.offsets, &mesh.facet_graph);
        Ok(Polytope::finish(
            a,
            mesh.offsets.clone(),
            mesh.vertices,
            mesh.normals,
            mesh.offsets,
            mesh.vertex_graph,
            Some(faces),
        ))
    }

    /// Many planes: the vertices are the polar polytope's facets. The polar polytope
    /// `{ y : x·y ≤ 1 for all x in P }` is the hull of the points `q_i = a_i/b_i`; its facet
    /// `n·y ≤ o` is the vertex `n/o` of P, its corner `q_i` the facet `i` of P (rows that are not
    /// corners are redundant), and P is bounded exactly when the origin is strictly inside it.
    fn polar(a: &[[Real; 3]], b: &[Real]) -> Result<Polytope, Error> {
        let m = a.len();
        let unbounded = || {
            Error::InvalidShape(ErrorDetail::new(
                "A",
                m as Real,
                "rows must describe a bounded polytope (found a direction d with A d ≤ 0)",
            ))
        };
        let q: Vec<Vec3> = a
            .iter()
            .zip(b)
            .map(|(r, bi)| Vec3::from(*r) / *bi)
            .collect();
        let tol = quickhull::tolerance(&q);
        let mesh = quickhull::hull(&q).map_err(|e| match e {
            HullError::Failed(_) | HullError::NonFinite(..) => {
                Error::InvalidShape(ErrorDetail::new(
                    "A",
                    m as Real,
                    "rows too close to degenerate for their vertices to be found",
                ))
            }
            _ => unbounded(),
        })?;
        if !mesh.offsets.iter().all(|&o| o > tol) {
            return Err(unbounded());
        }
        // P's vertices, one per polar facet; P's facets, one per polar corner.
        let vertices: Vec<Vec3> = mesh
            .normals
            .iter()
            .zip(&mesh.offsets)
            .map(|(n, o)| n / *o)
            .collect();
        let rows: Vec<usize> = mesh.source.iter().map(|&k| k as usize).collect();
        let normals: Vec<Vec3> = rows.iter().map(|&i| Vec3::from(a[i]).normalize()).collect();
        let offsets: Vec<Real> = rows
            .iter()
            .map(|&i| b[i] / Vec3::from(a[i]).norm())
            .collect();
        // Facet k's corners: the polar facets through polar corner k, in order round its normal.
        let mut loops = Lists {
            first: vec![0],
            items: Vec::new(),
        };
        for (k, nk) in normals.iter().enumerate() {
            let mut ring: Vec<u32> = mesh.incident.get(k).to_vec();
            let c = ring.iter().map(|&g| vertices[g as usize]).sum::<Vec3>() / ring.len() as Real;
            let u = (vertices[ring[0] as usize] - c)
                .try_normalize(0.0)
                .unwrap_or(Vec3::x());
            let v = nk.cross(&u);
            let angle = |g: &u32| {
                let d = vertices[*g as usize] - c;
                d.dot(&v).atan2(d.dot(&u))
            };
            ring.sort_by(|x, y| angle(x).total_cmp(&angle(y)));
            loops.items.extend(ring);
            loops.first.push(loops.items.len() as u32);
        }
        let faces = Faces::new(loops, &normals, &offsets, &mesh.vertex_graph);
        Ok(Polytope::finish(
            a.to_vec(),
            b.to_vec(),
            vertices,
            normals,
            offsets,
            mesh.facet_graph,
            Some(faces),
        ))
    }

    /// The parts every construction shares: radii, the box's table, the climb.
    fn finish(
        a: Vec<[Real; 3]>,
        b: Vec<Real>,
        vertices: Vec<Vec3>,
        normals: Vec<Vec3>,
        offsets: Vec<Real>,
        graph: Lists,
        faces: Option<Faces>,
    ) -> Polytope {
        let rho = vertices
            .iter()
            .map(crate::math::robust_norm)
            .fold(0.0, Real::max);
        let iota = offsets.iter().cloned().fold(Real::INFINITY, Real::min);
        let half_extents = centred_box(&normals, &offsets);
        let box_support = half_extents.and_then(|_| box_support(&vertices));
        let climb = (box_support.is_none() && vertices.len() >= CLIMB_MIN)
            .then(|| Climb::from_graph(&vertices, graph));
        Polytope {
            a,
            b,
            vertices,
            normals,
            offsets,
            half_extents,
            box_support,
            climb,
            faces: faces.map(Box::new),
            bounding_radius: rho.max(iota),
            inscribed_radius: iota,
        }
    }

    /// Few planes: every triple of planes whose intersection satisfies all of them is a vertex.
    fn enumerated(a: &[[Real; 3]], b: &[Real]) -> Result<Polytope, Error> {
        let rows: Vec<Vec3> = a.iter().map(|r| Vec3::from(*r)).collect();
        // Scale-free copies: unit normals n_i and offsets b_i/|a_i|.
        let norms: Vec<Real> = rows.iter().map(|r| r.norm()).collect();
        let n: Vec<Vec3> = rows.iter().zip(&norms).map(|(r, k)| r / *k).collect();
        let off: Vec<Real> = b.iter().zip(&norms).map(|(v, k)| v / k).collect();
        let m = n.len();
        // Bounded ⇔ no d ≠ 0 with n_i·d ≤ 0 ∀i. If one exists, an extreme ray of that cone
        // lies on two independent facet planes (or A has rank < 3).
        let unbounded = || {
            Error::InvalidShape(ErrorDetail::new(
                "A",
                m as Real,
                "rows must describe a bounded polytope (found a direction d with A d ≤ 0)",
            ))
        };
        let mut rank3 = false;
        'outer: for i in 0..m {
            for j in (i + 1)..m {
                let c = n[i].cross(&n[j]);
                if c.norm() < 1e-12 {
                    continue;
                }
                for k in (j + 1)..m {
                    if c.dot(&n[k]).abs() > 1e-12 {
                        rank3 = true;
                        break 'outer;
                    }
                }
            }
        }
        if !rank3 {
            return Err(unbounded());
        }
        for i in 0..m {
            for j in (i + 1)..m {
                let c = n[i].cross(&n[j]);
                let cn = c.norm();
                if cn < 1e-12 {
                    continue;
                }
                let d = c / cn;
                for sign in [1.0, -1.0] {
                    if n.iter().all(|nk| sign * nk.dot(&d) <= 1e-12) {
                        return Err(unbounded());
                    }
                }
            }
        }
        let min_off = off.iter().cloned().fold(Real::INFINITY, Real::min);
        // Vertices: intersections of three planes that satisfy all constraints.
        let mut rho: Real = 0.0;
        let mut vertices: Vec<Vec3> = Vec::new();
        // The facets through each vertex (of every triple that gave it).
        let mut incident: Vec<Vec<u16>> = Vec::new();
        for i in 0..m {
            for j in (i + 1)..m {
                let cij = n[i].cross(&n[j]);
                if cij.norm() < 1e-12 {
                    continue;
                }
                for k in (j + 1)..m {
                    let det = cij.dot(&n[k]);
                    if det.abs() < 1e-12 {
                        continue;
                    }
                    // Cramer: v = (off_i (n_j×n_k) + off_j (n_k×n_i) + off_k (n_i×n_j)) / det
                    let v =
                        (n[j].cross(&n[k]) * off[i] + n[k].cross(&n[i]) * off[j] + cij * off[k])
                            / det;
                    let vn = crate::math::robust_norm(&v);
                    let feasible = n
                        .iter()
                        .zip(&off)
                        .all(|(nl, ol)| nl.dot(&v) <= ol + 1e-9 * ol.max(vn));
                    if feasible {
                        rho = rho.max(vn);
                        let at = add_vertex(&mut vertices, v, min_off);
                        if at == incident.len() {
                            incident.push(Vec::new());
                        }
                        for f in [i, j, k] {
                            if !incident[at].contains(&(f as u16)) {
                                incident[at].push(f as u16);
                            }
                        }
                    }
                }
            }
        }
        let iota = off.iter().cloned().fold(Real::INFINITY, Real::min);
        if !(rho.is_finite() && rho > 0.0) {
            return Err(unbounded());
        }
        let half_extents = centred_box(&n, &off);
        let box_support = half_extents.and_then(|_| box_support(&vertices));
        let climb = (box_support.is_none() && vertices.len() >= CLIMB_MIN)
            .then(|| Climb::new(&vertices, &incident, &n))
            .flatten();
        Ok(Polytope {
            a: a.to_vec(),
            b: b.to_vec(),
            vertices,
            half_extents,
            box_support,
            climb,
            faces: None,
            normals: n,
            offsets: off,
            bounding_radius: rho.max(iota),
            inscribed_radius: iota,
        })
    }

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

    /// The index of the facet whose polar corner `n_i/o_i` is largest along `p` (its gauge is
    /// that value), by the climb when there is one.
    fn gauge_facet(&self, p: &Vec3) -> Option<usize> {
        let faces = self.faces.as_deref()?;
        let climb = faces.gauge.as_ref()?;
        Some(climb.support(&faces.polar, p))
    }
}

impl Faces {
    fn new(loops: Lists, normals: &[Vec3], offsets: &[Real], facet_graph: &Lists) -> Faces {
        let polar: Vec<Vec3> = normals.iter().zip(offsets).map(|(n, o)| n / *o).collect();
        let gauge = (normals.len() >= GAUGE_CLIMB_MIN)
            .then(|| Climb::from_graph(&polar, facet_graph.clone()));
        Faces {
            loops,
            polar,
            gauge,
        }
    }
}

/// The half extents when the six unit normals are exactly `±e_x, ±e_y, ±e_z` and opposite
/// facets are equally far from the origin (a box centred at its origin).
fn centred_box(normals: &[Vec3], offsets: &[Real]) -> Option<Vec3> {
    if normals.len() != 6 {
        return None;
    }
    let mut plus = [None; 3];
    let mut minus = [None; 3];
    for (nrm, off) in normals.iter().zip(offsets) {
        let axis = (0..3).find(|&j| nrm[j].abs() == 1.0)?;
        if (0..3).any(|j| j != axis && nrm[j] != 0.0) {
            return None;
        }
        let slot = if nrm[axis] > 0.0 {
            &mut plus
        } else {
            &mut minus
        };
        if slot[axis].replace(*off).is_some() {
            return None;
        }
    }
    let mut h = Vec3::zeros();
    for j in 0..3 {
        let (p, m) = (plus[j]?, minus[j]?);
        if p != m {
            return None;
        }
        h[j] = p;
    }
    Some(h)
}

/// Adds `v` unless a vertex within rounding of it is already there (several facets through one
/// vertex give it once per triple of facets). `scale` is the smallest facet offset: two
/// vertices closer than 1e-9 of it are one, however far from the origin (relative to `‖v‖`
/// alone, the two faces of a box 1e10 times wider than thick merged into one).
pub(crate) fn add_vertex(vertices: &mut Vec<Vec3>, v: Vec3, scale: Real) -> usize {
    let tol = 1e-9 * v.norm().min(scale).max(Real::MIN_POSITIVE);
    match vertices.iter().position(|w| (w - v).norm() <= tol) {
        Some(k) => k,
        None => {
            vertices.push(v);
            vertices.len() - 1
        }
    }
}

/// The table of `Polytope::box_support` for a centred box's eight vertices; `None` if they are
/// not one vertex per octant.
fn box_support(vertices: &[Vec3]) -> Option<[u8; 27]> {
    if vertices.len() != 8 {
        return None;
    }
    let mut table = [0u8; 27];
    for (p, entry) in table.iter_mut().enumerate() {
        let signs = [p / 9, (p / 3) % 3, p % 3].map(|d| d as i32 - 1);
        let k = vertices.iter().position(|v| {
            (0..3).all(|i| signs[i] == 0 || (v[i] > 0.0) == (signs[i] > 0) && v[i] != 0.0)
        })?;
        *entry = k as u8;
    }
    Some(table)
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
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        Round::Flat.eval(self.vertices.get(id as usize)?, m)
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        let Some(mut k) = self.gauge_facet(m) else {
            return nearest_normal(&self.normals, m, cos_min);
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
        let n = m.norm();
        (n > 0.0 && c >= cos_min * n).then(|| self.normals[k])
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
