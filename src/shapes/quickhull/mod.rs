//! The convex hull of a set of points in 3-D (quickhull), as a polytope with merged planar
//! facets: the hull's corners, each facet's outward unit normal, offset and corner loop, and the
//! two graphs the support map and the gauge climb on (corners joined by an edge, facets sharing
//! an edge).
//!
//! Quickhull (Barber, Dobkin, Huhdanpaa 1996; the half-edge form of Gregorius 2014) grows a
//! tetrahedron of four extreme points: each face keeps the points above it, the farthest of
//! them is added by replacing the faces it sees with a cone from it to their horizon, until no
//! point lies above a face. A point counts as above a face only when it is farther than a
//! rounding tolerance `tol` (a small multiple of the unit roundoff times the points' extent), so
//! duplicate, interior and coplanar points never become corners of new faces, and no face is
//! built from a point that rounding could put on either side. Faces that end up coplanar (every
//! vertex of one within `tol` of the other's plane: the two triangles of a box's side) are
//! merged into one facet, and vertices that are then not corners (in the middle of a facet or of
//! a straight edge) are dropped.
//!
//! Expected time O(n log n); 10 000 points on a sphere take a few milliseconds.

mod facets;

use crate::math::{Real, Vec3};

/// Why no hull: what the caller's points lack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum HullError {
    /// Coordinate `index` (row-major) is not finite.
    NonFinite(usize, Real),
    /// All points coincide (within rounding): the value is how many were given.
    Coincident(usize),
    /// All points lie on a line (within rounding).
    Collinear,
    /// All points lie in a plane (within rounding): fewer than four affinely independent.
    Coplanar,
    /// A step of the construction lost track of the surface (a bug or an input at the edge of
    /// what rounding allows); the value is how far outside the result a point was left.
    Failed(Real),
}

/// A compressed list of lists: the items of list `k` are `items[first[k]..first[k + 1]]`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Lists {
    pub first: Vec<u32>,
    pub items: Vec<u32>,
}

impl Lists {
    /// List `k`.
    #[inline]
    pub(crate) fn get(&self, k: usize) -> &[u32] {
        &self.items[self.first[k] as usize..self.first[k + 1] as usize]
    }

    /// Lists from `(list, item)` pairs, each list's items sorted and deduplicated (a counting
    /// sort by list, then each short list sorted).
    pub(crate) fn from_pairs(count: usize, pairs: &[(u32, u32)]) -> Lists {
        let mut first = vec![0u32; count + 1];
        for &(k, _) in pairs {
            first[k as usize + 1] += 1;
        }
        for k in 0..count {
            first[k + 1] += first[k];
        }
        let mut at = first.clone();
        let mut items = vec![0u32; pairs.len()];
        for &(k, v) in pairs {
            items[at[k as usize] as usize] = v;
            at[k as usize] += 1;
        }
        // Sort and deduplicate each list, moving it down over the duplicates removed before.
        let mut write = 0usize;
        for k in 0..count {
            let (a, b) = (first[k] as usize, first[k + 1] as usize);
            if items[a..b].windows(2).any(|w| w[0] >= w[1]) {
                items[a..b].sort_unstable();
            }
            first[k] = write as u32;
            for r in a..b {
                if r == a || items[r] != items[r - 1] {
                    items[write] = items[r];
                    write += 1;
                }
            }
        }
        first[count] = write as u32;
        items.truncate(write);
        Lists { first, items }
    }
}

/// A convex polytope from its points: corners, facets and their graphs.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Mesh {
    /// The corners.
    pub vertices: Vec<Vec3>,
    /// Each corner's index among the points given.
    pub source: Vec<u32>,
    /// Each facet's outward unit normal.
    pub normals: Vec<Vec3>,
    /// Each facet's offset: `normal·x ≤ offset` holds for every corner, with equality (to
    /// rounding) on the facet's own.
    pub offsets: Vec<Real>,
    /// Each facet's corners, counter-clockwise seen from outside.
    pub loops: Lists,
    /// Each corner's neighbours along the hull's edges.
    pub vertex_graph: Lists,
    /// Each facet's neighbours across the hull's edges.
    pub facet_graph: Lists,
    /// Each corner's facets.
    pub incident: Lists,
}

/// One triangle of the growing hull.
#[derive(Clone, Debug)]
struct Face {
    /// Counter-clockwise seen from outside.
    v: [u32; 3],
    /// `adj[i]`: the face across the edge `v[i] → v[i + 1]`.
    adj: [u32; 3],
    normal: Vec3,
    offset: Real,
    /// The first of the points above this face (farther than `tol`), not yet in the hull:
    /// a list linked through `Builder::next`, `NONE` when empty.
    head: u32,
    /// The farthest of them and its distance.
    far: (Real, u32),
    alive: bool,
    /// The step at which this face was last found visible.
    seen: u32,
}

const NONE: u32 = u32::MAX;

/// The plane through `a, b, c` (counter-clockwise seen from outside): unit normal and offset,
/// taken at the centroid. `None` for a degenerate triangle.
fn plane(a: &Vec3, b: &Vec3, c: &Vec3) -> Option<(Vec3, Real)> {
    // The cross product of the two edges from the vertex opposite the longest edge: the
    // better conditioned of the three.
    let (ab, bc, ca) = (b - a, c - b, a - c);
    let (lab, lbc, lca) = (ab.norm_squared(), bc.norm_squared(), ca.norm_squared());
    let n = if lab >= lbc && lab >= lca {
        (c - a).cross(&(c - b)) // opposite ab: c
    } else if lbc >= lca {
        ab.cross(&(c - a)) // opposite bc: a
    } else {
        bc.cross(&(a - b)) // opposite ca: b
    };
    let n = n.try_normalize(0.0)?;
    Some((n, n.dot(&((a + b + c) / 3.0))))
}

struct Builder<'a> {
    pts: &'a [Vec3],
    tol: Real,
    faces: Vec<Face>,
    /// The conflict lists' links: the point after each point in its face's list.
    next: Vec<u32>,
    step: u32,
    /// Points dropped by a step that could not use them (checked at the end).
    dropped: Vec<u32>,
    /// The depth-first search's stack (kept between steps).
    stack: Vec<(u32, u8, u8)>,
}

impl Builder<'_> {
    fn dist(&self, f: usize, p: u32) -> Real {
        let face = &self.faces[f];
        face.normal.dot(&self.pts[p as usize]) - face.offset
    }

    fn add_face(&mut self, v: [u32; 3]) -> Option<u32> {
        let [a, b, c] = v.map(|k| self.pts[k as usize]);
        let (normal, offset) = plane(&a, &b, &c)?;
        self.faces.push(Face {
            v,
            adj: [NONE; 3],
            normal,
            offset,
            head: NONE,
            far: (Real::NEG_INFINITY, NONE),
            alive: true,
            seen: 0,
        });
        Some(self.faces.len() as u32 - 1)
    }

    /// Gives point `p` to the face of `faces` it is farthest above, if any is farther than
    /// `tol`.
    #[inline]
    fn assign(&mut self, p: u32, faces: std::ops::Range<u32>) {
        let q = self.pts[p as usize];
        let mut best = (self.tol, NONE);
        for f in faces {
            let face = &self.faces[f as usize];
            let d = face.normal.dot(&q) - face.offset;
            if d > best.0 {
                best = (d, f);
            }
        }
        if best.1 != NONE {
            let face = &mut self.faces[best.1 as usize];
            self.next[p as usize] = face.head;
            face.head = p;
            if best.0 > face.far.0 {
                face.far = (best.0, p);
            }
        }
    }

    /// Takes `p` out of face `f`'s list (and its farthest point, found again).
    fn remove(&mut self, f: u32, p: u32) {
        let mut k = self.faces[f as usize].head;
        let mut kept = NONE;
        let mut far = (Real::NEG_INFINITY, NONE);
        while k != NONE {
            let after = self.next[k as usize];
            if k != p {
                self.next[k as usize] = kept;
                kept = k;
                let d = self.dist(f as usize, k);
                if d > far.0 {
                    far = (d, k);
                }
            }
            k = after;
        }
        let face = &mut self.faces[f as usize];
        face.head = kept;
        face.far = far;
    }

    /// The faces `eye` sees, from `start` (which it sees), and their horizon: the edges
    /// `(a, b, face beyond)` in counter-clockwise order round the visible region.
    fn horizon(&mut self, start: u32, eye: u32, visible: &mut Vec<u32>, edges: &mut Vec<[u32; 3]>) {
        self.step += 1;
        let step = self.step;
        visible.clear();
        edges.clear();
        self.faces[start as usize].seen = step;
        visible.push(start);
        // Depth first, each face's edges in order from the one it was entered by: the horizon
        // comes out as a cycle when the visible region is a disc.
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        stack.push((start, 0, 3));
        while let Some(top) = stack.last_mut() {
            let (f, from, left) = *top;
            if left == 0 {
                stack.pop();
                continue;
            }
            top.1 = (from + 1) % 3;
            top.2 = left - 1;
            let i = from as usize;
            let g = self.faces[f as usize].adj[i];
            if self.faces[g as usize].seen == step {
                continue;
            }
            if self.dist(g as usize, eye) > self.tol {
                self.faces[g as usize].seen = step;
                visible.push(g);
                let back = self.faces[g as usize]
                    .adj
                    .iter()
                    .position(|&h| h == f)
                    .unwrap_or(0);
                stack.push((g, ((back + 1) % 3) as u8, 2));
            } else {
                let face = &self.faces[f as usize];
                edges.push([face.v[i], face.v[(i + 1) % 3], g]);
            }
        }
        self.stack = stack;
    }

    /// Adds the farthest point above face `f`; queues the new faces with points above them.
    fn expand(
        &mut self,
        f: u32,
        visible: &mut Vec<u32>,
        edges: &mut Vec<[u32; 3]>,
        work: &mut std::collections::VecDeque<u32>,
    ) {
        let eye = self.faces[f as usize].far.1;
        self.horizon(f, eye, visible, edges);
        let cycle = !edges.is_empty()
            && (0..edges.len()).all(|k| edges[k][1] == edges[(k + 1) % edges.len()][0]);
        // The cone from the eye to the horizon.
        let first = self.faces.len() as u32;
        let k = edges.len() as u32;
        let mut made = cycle;
        if cycle {
            for (j, e) in edges.iter().enumerate() {
                let Some(nf) = self.add_face([e[0], e[1], eye]) else {
                    made = false;
                    break;
                };
                let j = j as u32;
                self.faces[nf as usize].adj = [e[2], first + (j + 1) % k, first + (j + k - 1) % k];
            }
        }
        if !made {
            // The visible region is not a disc (rounding at a pinched vertex), or the eye lies
            // on the line of a horizon edge: leave the point out (checked at the end: it is
            // within rounding of the hull).
            self.faces.truncate(first as usize);
            self.remove(f, eye);
            self.dropped.push(eye);
            if self.faces[f as usize].head != NONE {
                work.push_back(f);
            }
            return;
        }
        // The faces beyond the horizon now border the cone across their edge b → a.
        for (j, e) in edges.iter().enumerate() {
            let g = e[2] as usize;
            for s in 0..3 {
                if self.faces[g].v[s] == e[1] && self.faces[g].v[(s + 1) % 3] == e[0] {
                    self.faces[g].adj[s] = first + j as u32;
                }
            }
        }
        // The visible faces' points go to the new faces (or inside).
        for &v in visible.iter() {
            self.faces[v as usize].alive = false;
            let mut p = std::mem::replace(&mut self.faces[v as usize].head, NONE);
            while p != NONE {
                let after = self.next[p as usize];
                if p != eye {
                    self.assign(p, first..first + k);
                }
                p = after;
            }
        }
        work.extend((first..first + k).filter(|&g| self.faces[g as usize].head != NONE));
    }
}

/// The rounding tolerance for points of this extent: a point nearer a plane than this is on it.
pub(crate) fn tolerance(pts: &[Vec3]) -> Real {
    let mut m = Vec3::zeros();
    for p in pts {
        m = m.sup(&p.abs());
    }
    // 64ε is a power of two: the same number as 64ε·(m.x + m.y + m.z), without the sum's
    // overflow for coordinates near the largest double.
    let k = 64.0 * Real::EPSILON;
    k * m.x + k * m.y + k * m.z
}

/// The hull of `pts` (finite; any number, duplicates allowed).
///
/// Points whose largest coordinate lies outside `[2⁻¹⁰⁰, 2¹⁰⁰)` are hulled at unit size (scaled by
/// a power of two, which is exact) and the corners and offsets scaled back: the construction's
/// products of coordinates would underflow or overflow there. Inside that range nothing is
/// rescaled, so the hull is bit for bit what it was.
pub(crate) fn hull(pts: &[Vec3]) -> Result<Mesh, HullError> {
    let mut largest: Real = 0.0;
    for (i, p) in pts.iter().enumerate() {
        for j in 0..3 {
            if !p[j].is_finite() {
                return Err(HullError::NonFinite(3 * i + j, p[j]));
            }
            largest = largest.max(p[j].abs());
        }
    }
    let Some((f, e)) = unit_factor(largest) else {
        return hull_finite(pts);
    };
    let scaled: Vec<Vec3> = pts.iter().map(|p| p * f).collect();
    let back = (2.0 as Real).powi(e);
    let mut mesh = hull_finite(&scaled).map_err(|e| match e {
        HullError::Failed(d) => HullError::Failed(d * back),
        e => e,
    })?;
    for (v, &k) in mesh.vertices.iter_mut().zip(&mesh.source) {
        *v = pts[k as usize];
    }
    for o in &mut mesh.offsets {
        *o *= back;
    }
    Ok(mesh)
}

/// The power of two `2⁻ᵉ` with `largest` in `[2ᵉ, 2ᵉ⁺¹)`, and `e`, when `largest` lies outside
/// `[2⁻¹⁰⁰, 2¹⁰⁰)`; `None` inside that range (or for 0 or a subnormal, whose hull fails as
/// coincident points anyway). Multiplying by it is exact.
fn unit_factor(largest: Real) -> Option<(Real, i32)> {
    let e = ((largest.to_bits() >> 52) & 0x7ff) as i32 - 1023;
    if (-100..100).contains(&e) || largest < Real::MIN_POSITIVE {
        return None;
    }
    Some(((2.0 as Real).powi(-e), e))
}

/// [`hull`] of finite points at the size given.
fn hull_finite(pts: &[Vec3]) -> Result<Mesh, HullError> {
    let tol = tolerance(pts);
    let simplex = initial_simplex(pts, tol)?;
    let mut b = Builder {
        pts,
        tol,
        faces: Vec::with_capacity(2 * pts.len() + 8),
        next: vec![NONE; pts.len()],
        step: 0,
        dropped: Vec::new(),
        stack: Vec::new(),
    };
    let [p0, p1, p2, p3] = simplex;
    // p3 lies below the plane (p0, p1, p2) seen counter-clockwise: orient every face outward.
    let tris = [[p0, p1, p2], [p0, p3, p1], [p1, p3, p2], [p2, p3, p0]];
    for t in tris {
        b.add_face(t).ok_or(HullError::Coplanar)?;
    }
    // Adjacency of the tetrahedron: the face sharing each directed edge reversed.
    for f in 0..4 {
        for i in 0..3 {
            let (a, c) = (b.faces[f].v[i], b.faces[f].v[(i + 1) % 3]);
            b.faces[f].adj[i] = (0..4)
                .find(|&g| {
                    g != f && (0..3).any(|j| b.faces[g].v[j] == c && b.faces[g].v[(j + 1) % 3] == a)
                })
                .map_or(NONE, |g| g as u32);
        }
    }
    for p in 0..pts.len() as u32 {
        if !simplex.contains(&p) {
            b.assign(p, 0..4);
        }
    }
    // Faces in the order they were made (the oldest, largest first: balanced splits).
    let mut work: std::collections::VecDeque<u32> = (0..4)
        .filter(|&f| b.faces[f as usize].head != NONE)
        .collect();
    let (mut visible, mut edges) = (Vec::new(), Vec::new());
    while let Some(f) = work.pop_front() {
        let face = &b.faces[f as usize];
        if face.alive && face.head != NONE {
            b.expand(f, &mut visible, &mut edges, &mut work);
        }
    }
    let alive: Vec<usize> = (0..b.faces.len()).filter(|&f| b.faces[f].alive).collect();
    // Points left out by a step: inside to the tolerance, or the construction failed.
    for &p in &b.dropped {
        let q = pts[p as usize];
        let out = alive
            .iter()
            .map(|&f| b.faces[f].normal.dot(&q) - b.faces[f].offset)
            .fold(Real::NEG_INFINITY, Real::max);
        if out > 1e3 * tol {
            return Err(HullError::Failed(out));
        }
    }
    facets::merge(pts, tol, &b.faces_view(&alive))
}

/// One final triangle: its corners, its neighbours and its plane.
pub(crate) struct Tri {
    pub v: [u32; 3],
    pub adj: [u32; 3],
    pub normal: Vec3,
    pub offset: Real,
}

impl Builder<'_> {
    /// The live faces, renumbered `0..`, with their adjacency in the new numbers.
    fn faces_view(&self, alive: &[usize]) -> Vec<Tri> {
        let mut index = vec![NONE; self.faces.len()];
        for (k, &f) in alive.iter().enumerate() {
            index[f] = k as u32;
        }
        alive
            .iter()
            .map(|&f| {
                let face = &self.faces[f];
                Tri {
                    v: face.v,
                    adj: face.adj.map(|g| index[g as usize]),
                    normal: face.normal,
                    offset: face.offset,
                }
            })
            .collect()
    }
}

/// Four affinely independent points among `pts`: the farthest pair of the axis extremes, the
/// point farthest from their line, the point farthest from the plane of those three, ordered so
/// that the fourth lies below the plane of the first three (counter-clockwise seen from above).
fn initial_simplex(pts: &[Vec3], tol: Real) -> Result<[u32; 4], HullError> {
    if pts.is_empty() {
        return Err(HullError::Coincident(0));
    }
    let mut ext = [0usize; 6];
    for (k, p) in pts.iter().enumerate() {
        for j in 0..3 {
            if p[j] < pts[ext[2 * j]][j] {
                ext[2 * j] = k;
            }
            if p[j] > pts[ext[2 * j + 1]][j] {
                ext[2 * j + 1] = k;
            }
        }
    }
    let mut best = (0.0, 0, 0);
    for i in 0..6 {
        for j in (i + 1)..6 {
            let d = (pts[ext[i]] - pts[ext[j]]).norm_squared();
            if d > best.0 {
                best = (d, ext[i], ext[j]);
            }
        }
    }
    let (a, b) = (best.1, best.2);
    if !(best.0.sqrt() > tol) {
        return Err(HullError::Coincident(pts.len()));
    }
    let dir = (pts[b] - pts[a]).normalize();
    let mut far: (Real, usize) = (0.0, 0);
    for (k, p) in pts.iter().enumerate() {
        let r = p - pts[a];
        let d = (r - dir * r.dot(&dir)).norm_squared();
        if d > far.0 {
            far = (d, k);
        }
    }
    let c = far.1;
    if !(far.0.sqrt() > tol) {
        return Err(HullError::Collinear);
    }
    let (n, off) = plane(&pts[a], &pts[b], &pts[c]).ok_or(HullError::Collinear)?;
    let mut far: (Real, usize) = (0.0, 0);
    for (k, p) in pts.iter().enumerate() {
        let d = n.dot(p) - off;
        if d.abs() > far.0.abs() {
            far = (d, k);
        }
    }
    let d = far.1;
    if !(far.0.abs() > tol) {
        return Err(HullError::Coplanar);
    }
    let ids = [a, b, c, d].map(|k| k as u32);
    Ok(if far.0 > 0.0 {
        [ids[1], ids[0], ids[2], ids[3]]
    } else {
        ids
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rng(seed: u64) -> impl FnMut() -> Real {
        let mut x = seed;
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
        }
    }

    /// Euler's formula, closed loops, every facet's corners on its plane, every corner and
    /// every input point below every plane (to the tolerance).
    fn check(mesh: &Mesh, pts: &[Vec3]) {
        let tol = tolerance(pts);
        let (v, f) = (mesh.vertices.len(), mesh.normals.len());
        let e: usize = (0..f).map(|g| mesh.loops.get(g).len()).sum::<usize>() / 2;
        assert_eq!(v + f, e + 2, "Euler: V {v} F {f} E {e}");
        assert_eq!(mesh.vertex_graph.items.len(), 2 * e);
        for g in 0..f {
            let (n, o) = (mesh.normals[g], mesh.offsets[g]);
            assert!((n.norm() - 1.0).abs() < 1e-14);
            for &k in mesh.loops.get(g) {
                let d = n.dot(&mesh.vertices[k as usize]) - o;
                assert!(d <= 0.0 && d > -8.0 * tol, "corner off its facet by {d}");
            }
            for p in pts {
                assert!(n.dot(p) - o <= 4.0 * tol, "a point above a facet");
            }
        }
        // Each corner is one of the points.
        for c in &mesh.vertices {
            assert!(pts.iter().any(|p| p == c));
        }
    }

    #[test]
    fn a_cube_with_duplicate_interior_and_coplanar_points_has_eight_corners_and_six_quads() {
        let mut pts = Vec::new();
        for i in 0..5 {
            for j in 0..5 {
                for k in 0..5 {
                    pts.push(Vec3::new(i as Real, j as Real, k as Real) * 0.5 - Vec3::repeat(1.0));
                }
            }
        }
        pts.extend(pts.clone()); // every point twice
        let m = hull(&pts).unwrap();
        check(&m, &pts);
        assert_eq!(m.vertices.len(), 8);
        assert_eq!(m.normals.len(), 6);
        for g in 0..6 {
            assert_eq!(m.loops.get(g).len(), 4);
            assert_eq!(m.offsets[g], 1.0);
            assert_eq!(m.facet_graph.get(g).len(), 4);
        }
        for k in 0..8 {
            assert_eq!(m.vertex_graph.get(k).len(), 3);
            assert_eq!(m.incident.get(k).len(), 3);
        }
    }

    #[test]
    fn points_on_a_sphere_are_all_corners() {
        let mut r = rng(7);
        let pts: Vec<Vec3> = (0..3000)
            .map(|_| loop {
                let p = Vec3::new(r(), r(), r());
                if p.norm() > 0.1 && p.norm() <= 1.0 {
                    break p.normalize() * 2.5;
                }
            })
            .collect();
        let m = hull(&pts).unwrap();
        check(&m, &pts);
        assert_eq!(m.vertices.len(), 3000);
        assert_eq!(m.normals.len(), 2 * 3000 - 4);
    }

    #[test]
    fn random_clouds_at_many_scales() {
        let mut r = rng(11);
        for (n, scale) in [(4, 1.0), (5, 1e-3), (50, 1e3), (500, 1.0), (2000, 1e-6)] {
            for _ in 0..5 {
                let pts: Vec<Vec3> = (0..n)
                    .map(|_| Vec3::new(r(), 0.3 * r(), r()) * scale)
                    .collect();
                match hull(&pts) {
                    Ok(m) => check(&m, &pts),
                    Err(e) => panic!("{n} points at {scale}: {e:?}"),
                }
            }
        }
    }

    #[test]
    fn flat_and_degenerate_inputs_say_why() {
        let p = |x: Real, y: Real, z: Real| Vec3::new(x, y, z);
        assert_eq!(hull(&[]), Err(HullError::Coincident(0)));
        assert_eq!(hull(&[p(1.0, 2.0, 3.0); 5]), Err(HullError::Coincident(5)));
        let line: Vec<Vec3> = (0..6).map(|i| p(i as Real, 2.0 * i as Real, 1.0)).collect();
        assert_eq!(hull(&line), Err(HullError::Collinear));
        let flat: Vec<Vec3> = (0..30)
            .map(|i| p((i % 5) as Real, (i / 5) as Real, 0.5))
            .collect();
        assert_eq!(hull(&flat), Err(HullError::Coplanar));
        assert!(matches!(
            hull(&[p(0.0, 0.0, 0.0), p(1.0, Real::NAN, 0.0)]),
            Err(HullError::NonFinite(4, v)) if v.is_nan()
        ));
    }
}
