//! A polytope's construction: from its planes (every triple of planes for a few, the polar
//! hull for many), or from the hull of its points; the parts every construction shares.

use super::{
    Climb, Faces, Polytope, CLIMB_MIN, ENUMERATE_MAX, GAUGE_CLIMB_MIN, SAT_DIRECTIONS, SAT_FACETS,
};
use crate::error::{Error, ErrorDetail};
use crate::math::{robust_norm, Real, Vec3};
use crate::shapes::check_halfspaces;
use crate::shapes::quickhull::{self, HullError, Lists, Mesh};

impl Polytope {
    /// Validates `A` (m×3, rows non-zero, finite) and `b` (m, positive, finite), m ≤
    /// [`crate::shapes::MAX_FACETS`], and that the set is bounded; finds its vertices.
    pub fn new(a: &[[Real; 3]], b: &[Real]) -> Result<Polytope, Error> {
        check_halfspaces("A", "b", a, b, crate::shapes::MAX_FACETS)?;
        if a.len() <= ENUMERATE_MAX {
            Polytope::enumerated(a, b)
        } else {
            Polytope::polar(a, b)
        }
    }

    /// The polytope whose facets are the hull `mesh` of points (the corners), as
    /// [`crate::shapes::Shape::convex_hull`] builds it: `Err(offset)` with the least facet offset when
    /// the origin is not strictly inside.
    pub(crate) fn from_mesh(mesh: Mesh, tol: Real) -> Result<Polytope, Real> {
        let least = mesh.offsets.iter().cloned().fold(Real::INFINITY, Real::min);
        if !(least > tol) {
            return Err(least);
        }
        let a: Vec<[Real; 3]> = mesh.normals.iter().map(|n| [n.x, n.y, n.z]).collect();
        let faces = Faces::new(
            mesh.loops,
            &mesh.vertices,
            &mesh.normals,
            &mesh.offsets,
            Some(&mesh.facet_graph),
        );
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
        let faces = Faces::new(
            loops,
            &vertices,
            &normals,
            &offsets,
            Some(&mesh.vertex_graph),
        );
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
        let loops = facet_loops(&vertices, &incident, &n);
        let faces = Faces::new(loops, &vertices, &n, &off, None);
        Ok(Polytope {
            a: a.to_vec(),
            b: b.to_vec(),
            vertices,
            half_extents,
            box_support,
            climb,
            faces: Some(Box::new(faces)),
            normals: n,
            offsets: off,
            bounding_radius: rho.max(iota),
            inscribed_radius: iota,
        })
    }
}

impl Faces {
    /// The facets' data from their corner loops; the gauge's climb when the facet graph is
    /// given (the hulls' and the polar construction's, whose facets are all irredundant).
    fn new(
        loops: Lists,
        vertices: &[Vec3],
        normals: &[Vec3],
        offsets: &[Real],
        facet_graph: Option<&Lists>,
    ) -> Faces {
        let polar: Vec<Vec3> = normals.iter().zip(offsets).map(|(n, o)| n / *o).collect();
        let gauge = facet_graph
            .filter(|_| normals.len() >= GAUGE_CLIMB_MIN)
            .map(|g| Climb::from_graph(&polar, g.clone()));
        let edge_directions = (normals.len() <= SAT_FACETS)
            .then(|| edge_directions(&loops, vertices))
            .flatten();
        let redundant = (0..normals.len()).any(|k| loops.get(k).len() < 3);
        Faces {
            loops,
            edge_directions,
            redundant,
            polar,
            gauge,
        }
    }
}

/// The distinct edge directions of the facets' loops (unit; the largest component positive),
/// `None` past [`SAT_DIRECTIONS`].
fn edge_directions(loops: &Lists, vertices: &[Vec3]) -> Option<Vec<Vec3>> {
    let mut dirs: Vec<Vec3> = Vec::new();
    for k in 0..loops.first.len().saturating_sub(1) {
        let l = loops.get(k);
        for i in 0..l.len() {
            let e = vertices[l[(i + 1) % l.len()] as usize] - vertices[l[i] as usize];
            let Some(mut u) = e.try_normalize(0.0) else {
                continue;
            };
            let big = (0..3)
                .max_by(|&x, &y| u[x].abs().total_cmp(&u[y].abs()))
                .unwrap_or(0);
            if u[big] < 0.0 {
                u = -u;
            }
            if dirs.iter().all(|d| d.cross(&u).norm() > 1e-9) {
                if dirs.len() == SAT_DIRECTIONS {
                    return None;
                }
                dirs.push(u);
            }
        }
    }
    Some(dirs)
}

/// Each facet's vertices (from the facets through each vertex), counter-clockwise about its
/// outward normal.
fn facet_loops(vertices: &[Vec3], incident: &[Vec<u16>], normals: &[Vec3]) -> Lists {
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (v, fs) in incident.iter().enumerate() {
        for &f in fs {
            pairs.push((f as u32, v as u32));
        }
    }
    let mut lists = Lists::from_pairs(normals.len(), &pairs);
    for (k, n) in normals.iter().enumerate() {
        let (a, b) = (lists.first[k] as usize, lists.first[k + 1] as usize);
        let ring = &mut lists.items[a..b];
        if ring.len() < 3 {
            continue;
        }
        let c = ring.iter().map(|&v| vertices[v as usize]).sum::<Vec3>() / ring.len() as Real;
        let u = (vertices[ring[0] as usize] - c)
            .try_normalize(0.0)
            .unwrap_or_else(Vec3::x);
        let w = n.cross(&u);
        let angle = |v: &u32| {
            let d = vertices[*v as usize] - c;
            d.dot(&w).atan2(d.dot(&u))
        };
        ring.sort_by(|x, y| angle(x).total_cmp(&angle(y)));
    }
    lists
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
/// alone, the two faces of a box 1e10 times wider than thick merged into one). Lengths by
/// `robust_norm`: a plain norm's squares underflow for shapes below ~1e-154, and every vertex
/// of a box of 1e-170 then merged into one.
pub(crate) fn add_vertex(vertices: &mut Vec<Vec3>, v: Vec3, scale: Real) -> usize {
    let tol = 1e-9 * robust_norm(&v).min(scale).max(Real::MIN_POSITIVE);
    match vertices.iter().position(|w| robust_norm(&(w - v)) <= tol) {
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
