//! From quickhull's triangles to the polytope's facets: coplanar neighbours merged into one
//! facet (checked planar and bounded by one loop, else left as triangles), the vertices that are
//! then not corners dropped, and the graphs built (see [`Mesh`]). Linear in the number of
//! triangles but for the sorting of each facet's few boundary edges.

use super::{HullError, Lists, Mesh, Tri};
use crate::math::{Real, Vec3};

fn find(parent: &mut [u32], mut k: u32) -> u32 {
    while parent[k as usize] != k {
        let p = parent[k as usize];
        parent[k as usize] = parent[p as usize];
        k = p;
    }
    k
}

/// Whether every vertex of `b` lies within `tol` of `a`'s plane, and the two face the same way.
fn coplanar(pts: &[Vec3], a: &Tri, b: &Tri, tol: Real) -> bool {
    a.normal.dot(&b.normal) > 0.0
        && b.v
            .iter()
            .all(|&k| (a.normal.dot(&pts[k as usize]) - a.offset).abs() <= tol)
}

/// The sum of the triangles' edge cross products: twice their area times their normal.
fn area_normal(pts: &[Vec3], tris: &[Tri], members: &[u32]) -> Vec3 {
    members.iter().fold(Vec3::zeros(), |s, &t| {
        let [a, b, c] = tris[t as usize].v.map(|k| pts[k as usize]);
        s + (b - a).cross(&(c - a))
    })
}

/// Appends group `g`'s boundary loop (counter-clockwise) to `out`; `false` when the boundary is
/// not one cycle (it touches itself, or is broken).
fn boundary(
    tris: &[Tri],
    group: &[u32],
    members: &[u32],
    g: u32,
    edges: &mut Vec<(u32, u32)>,
    out: &mut Vec<u32>,
) -> bool {
    if let [t] = members {
        out.extend_from_slice(&tris[*t as usize].v);
        return true;
    }
    edges.clear();
    for &t in members {
        let tri = &tris[t as usize];
        for i in 0..3 {
            if group[tri.adj[i] as usize] != g {
                edges.push((tri.v[i], tri.v[(i + 1) % 3]));
            }
        }
    }
    edges.sort_unstable();
    if edges.is_empty() || edges.windows(2).any(|w| w[0].0 == w[1].0) {
        return false; // a vertex where the boundary touches itself
    }
    let start = out.len();
    let mut k = 0;
    for _ in 0..edges.len() {
        out.push(edges[k].0);
        match edges.binary_search_by_key(&edges[k].1, |e| e.0) {
            Ok(next) => k = next,
            Err(_) => break,
        }
    }
    if out.len() - start == edges.len() && k == 0 {
        true
    } else {
        out.truncate(start);
        false
    }
}

/// Groups (dense numbers) of the triangles: coplanar neighbours joined, unless `alone[t]`.
fn groups(pts: &[Vec3], tol: Real, tris: &[Tri], alone: &[bool]) -> (Vec<u32>, usize) {
    let nt = tris.len();
    let mut parent: Vec<u32> = (0..nt as u32).collect();
    for (t, tri) in tris.iter().enumerate() {
        for &u in &tri.adj {
            let u = u as usize;
            if u > t
                && !alone[t]
                && !alone[u]
                && coplanar(pts, tri, &tris[u], tol)
                && coplanar(pts, &tris[u], tri, tol)
            {
                let (a, b) = (find(&mut parent, t as u32), find(&mut parent, u as u32));
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
    }
    let mut group = vec![0u32; nt];
    let mut index = vec![u32::MAX; nt];
    let mut count = 0usize;
    for t in 0..nt {
        let r = find(&mut parent, t as u32) as usize;
        if index[r] == u32::MAX {
            index[r] = count as u32;
            count += 1;
        }
        group[t] = index[r];
    }
    (group, count)
}

/// The facets of the hull whose triangles are `tris` (adjacency closed, outward normals).
pub(crate) fn merge(pts: &[Vec3], tol: Real, tris: &[Tri]) -> Result<Mesh, HullError> {
    let nt = tris.len();
    if nt < 4 || tris.iter().any(|t| t.adj.iter().any(|&a| a as usize >= nt)) {
        return Err(HullError::Failed(Real::INFINITY));
    }
    // Groups of coplanar neighbours, each checked planar (a chain of nearly coplanar triangles
    // may bend) and bounded by one loop; the triangles of a group that is not go back to being
    // facets of their own, once.
    let mut alone = vec![false; nt];
    let mut edges = Vec::new();
    let (group, count, members, loops) = loop {
        let (group, count) = groups(pts, 2.0 * tol, tris, &alone);
        let pairs: Vec<(u32, u32)> = (0..nt as u32).map(|t| (group[t as usize], t)).collect();
        let members = Lists::from_pairs(count, &pairs);
        let mut loops = Lists {
            first: Vec::with_capacity(count + 1),
            items: Vec::with_capacity(3 * nt),
        };
        let mut bad = Vec::new();
        for g in 0..count {
            let m = members.get(g);
            loops.first.push(loops.items.len() as u32);
            let planar = m.len() < 2 || {
                let n = area_normal(pts, tris, m)
                    .try_normalize(0.0)
                    .unwrap_or_default();
                let (lo, hi) = m
                    .iter()
                    .flat_map(|&t| tris[t as usize].v)
                    .map(|k| n.dot(&pts[k as usize]))
                    .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), v| {
                        (l.min(v), h.max(v))
                    });
                n != Vec3::zeros() && hi - lo <= 4.0 * tol
            };
            if !(planar && boundary(tris, &group, m, g as u32, &mut edges, &mut loops.items)) {
                bad.push(g);
            }
        }
        loops.first.push(loops.items.len() as u32);
        if bad.is_empty() {
            break (group, count, members, loops);
        }
        if alone.iter().any(|&a| a) {
            return Err(HullError::Failed(Real::INFINITY));
        }
        for g in bad {
            for &t in members.get(g) {
                alone[t as usize] = true;
            }
        }
    };
    // Corners: vertices on three facets or more (the others lie inside a facet or a straight
    // edge). A loop left with fewer than three keeps all its vertices.
    let np = pts.len();
    // Up to three distinct facets seen at each vertex (and whether it is on the hull at all).
    let mut seen = vec![[u32::MAX; 3]; np];
    for (t, tri) in tris.iter().enumerate() {
        for &v in &tri.v {
            let s = &mut seen[v as usize];
            if let Some(slot) = s.iter().position(|&g| g == u32::MAX || g == group[t]) {
                s[slot] = group[t];
            }
        }
    }
    let on_hull = |v: usize| seen[v][0] != u32::MAX;
    let mut corner: Vec<bool> = (0..np).map(|v| seen[v][2] != u32::MAX).collect();
    for g in 0..count {
        let l = loops.get(g);
        if l.iter().filter(|&&v| corner[v as usize]).count() < 3 {
            for &v in l {
                corner[v as usize] = true;
            }
        }
    }
    let mut vindex = vec![u32::MAX; np];
    let mut vertices = Vec::new();
    let mut source = Vec::new();
    for (v, &is) in corner.iter().enumerate() {
        if is && on_hull(v) {
            vindex[v] = vertices.len() as u32;
            vertices.push(pts[v]);
            source.push(v as u32);
        }
    }
    let mut corners = Lists {
        first: Vec::with_capacity(count + 1),
        items: Vec::with_capacity(loops.items.len()),
    };
    for g in 0..count {
        corners.first.push(corners.items.len() as u32);
        corners.items.extend(
            loops
                .get(g)
                .iter()
                .filter(|&&v| corner[v as usize])
                .map(|&v| vindex[v as usize]),
        );
    }
    corners.first.push(corners.items.len() as u32);
    // Planes: the area-weighted normal; the offset the largest of the corners'.
    let mut normals = Vec::with_capacity(count);
    let mut offsets = Vec::with_capacity(count);
    for g in 0..count {
        let n = area_normal(pts, tris, members.get(g))
            .try_normalize(0.0)
            .ok_or(HullError::Failed(Real::INFINITY))?;
        let off = corners
            .get(g)
            .iter()
            .map(|&v| n.dot(&vertices[v as usize]))
            .fold(Real::NEG_INFINITY, Real::max);
        normals.push(n);
        offsets.push(off);
    }
    // Graphs.
    let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(2 * corners.items.len());
    for g in 0..count {
        let l = corners.get(g);
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
    let vertex_graph = Lists::from_pairs(vertices.len(), &pairs);
    pairs.clear();
    for (t, tri) in tris.iter().enumerate() {
        for &u in &tri.adj {
            if group[u as usize] != group[t] {
                pairs.push((group[t], group[u as usize]));
            }
        }
    }
    let facet_graph = Lists::from_pairs(count, &pairs);
    pairs.clear();
    for g in 0..count {
        for &v in corners.get(g) {
            pairs.push((v, g as u32));
        }
    }
    let incident = Lists::from_pairs(vertices.len(), &pairs);
    let mut mesh = Mesh {
        vertices,
        source,
        normals,
        offsets,
        loops: corners,
        vertex_graph,
        facet_graph,
        incident,
    };
    // Every corner below every facet's plane: the offsets as the support values found by
    // climbing the vertex graph from the facet's first corner (the merged planes may tilt a
    // neighbour's corner above them by rounding).
    for g in 0..count {
        let start = mesh.loops.get(g)[0] as usize;
        let n = mesh.normals[g];
        let h = climb(&mesh.vertices, &mesh.vertex_graph, start, &n);
        mesh.offsets[g] = mesh.offsets[g].max(h);
    }
    Ok(mesh)
}

/// Steepest ascent of `m·x` on the vertex graph from `k`: the support value in direction `m`.
pub(crate) fn climb(vertices: &[Vec3], graph: &Lists, mut k: usize, m: &Vec3) -> Real {
    let mut h = vertices[k].dot(m);
    loop {
        let mut next = k;
        for &j in graph.get(k) {
            let hj = vertices[j as usize].dot(m);
            if hj > h {
                (h, next) = (hj, j as usize);
            }
        }
        if next == k {
            return h;
        }
        k = next;
    }
}
