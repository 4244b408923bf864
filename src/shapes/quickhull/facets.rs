//! From quickhull's triangles to the polytope's facets: coplanar neighbours merged into one
//! facet (checked planar and bounded by one loop, else left as triangles), the vertices that are
//! then not corners dropped, and the graphs built (see [`Mesh`]).

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

/// The boundary loop of each group: `None` for a group whose boundary is not one cycle.
fn loops(tris: &[Tri], group: &[u32], count: usize) -> Vec<Option<Vec<u32>>> {
    // Boundary half-edges (group, from, to), sorted by group then start.
    let mut edges: Vec<(u32, u32, u32)> = Vec::new();
    for (t, tri) in tris.iter().enumerate() {
        for i in 0..3 {
            if group[tri.adj[i] as usize] != group[t] {
                edges.push((group[t], tri.v[i], tri.v[(i + 1) % 3]));
            }
        }
    }
    edges.sort_unstable();
    let mut out = vec![None; count];
    let mut at = 0;
    while at < edges.len() {
        let g = edges[at].0;
        let end = at + edges[at..].iter().take_while(|e| e.0 == g).count();
        let mine = &edges[at..end];
        at = end;
        if mine.windows(2).any(|w| w[0].1 == w[1].1) {
            continue; // a vertex where the boundary touches itself
        }
        let mut cycle = Vec::with_capacity(mine.len());
        let mut k = 0;
        for _ in 0..mine.len() {
            cycle.push(mine[k].1);
            match mine.binary_search_by_key(&mine[k].2, |e| e.1) {
                Ok(next) => k = next,
                Err(_) => break,
            }
        }
        if cycle.len() == mine.len() && k == 0 {
            out[g as usize] = Some(cycle);
        }
    }
    out
}

/// The facets of the hull whose triangles are `tris` (adjacency closed, outward normals).
pub(crate) fn merge(pts: &[Vec3], tol: Real, tris: &[Tri]) -> Result<Mesh, HullError> {
    let nt = tris.len();
    if nt < 4 || tris.iter().any(|t| t.adj.iter().any(|&a| a as usize >= nt)) {
        return Err(HullError::Failed(Real::INFINITY));
    }
    // Groups of coplanar neighbours.
    let mut parent: Vec<u32> = (0..nt as u32).collect();
    for (t, tri) in tris.iter().enumerate() {
        for &u in &tri.adj {
            let u = u as usize;
            if u > t
                && coplanar(pts, tri, &tris[u], 2.0 * tol)
                && coplanar(pts, &tris[u], tri, 2.0 * tol)
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
    // Each group's plane: the area-weighted normal, checked against every vertex of the group
    // (a chain of nearly coplanar triangles may bend): groups that are not planar, or not
    // bounded by one loop, go back to their triangles.
    let normal_of = |members: &mut dyn Iterator<Item = usize>| -> Vec3 {
        members.fold(Vec3::zeros(), |s, t| {
            let [a, b, c] = tris[t].v.map(|k| pts[k as usize]);
            s + (b - a).cross(&(c - a))
        })
    };
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); count];
    for t in 0..nt {
        members[group[t] as usize].push(t);
    }
    let mut bad = vec![false; count];
    for (g, m) in members.iter().enumerate() {
        if m.len() < 2 {
            continue;
        }
        let Some(n) = normal_of(&mut m.iter().copied()).try_normalize(0.0) else {
            bad[g] = true;
            continue;
        };
        let vals: Vec<Real> = m
            .iter()
            .flat_map(|&t| tris[t].v)
            .map(|k| n.dot(&pts[k as usize]))
            .collect();
        let (lo, hi) = vals
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        bad[g] = hi - lo > 4.0 * tol;
    }
    let mut cycles = loops(tris, &group, count);
    if bad.iter().zip(&cycles).any(|(b, c)| *b || c.is_none()) {
        let split: Vec<bool> = bad
            .iter()
            .zip(&cycles)
            .map(|(b, c)| *b || c.is_none())
            .collect();
        let mut next = count as u32;
        for t in 0..nt {
            if split[group[t] as usize] {
                group[t] = next;
                next += 1;
            }
        }
        // Renumber densely.
        let mut index = vec![u32::MAX; next as usize];
        count = 0;
        for g in group.iter_mut() {
            if index[*g as usize] == u32::MAX {
                index[*g as usize] = count as u32;
                count += 1;
            }
            *g = index[*g as usize];
        }
        cycles = loops(tris, &group, count);
        if cycles.iter().any(Option::is_none) {
            return Err(HullError::Failed(Real::INFINITY));
        }
        members = vec![Vec::new(); count];
        for t in 0..nt {
            members[group[t] as usize].push(t);
        }
    }
    let cycles: Vec<Vec<u32>> = cycles.into_iter().map(Option::unwrap_or_default).collect();
    // Corners: vertices on three facets or more (the others lie inside a facet or a straight
    // edge). A loop left with fewer than three keeps all its vertices.
    let np = pts.len();
    let mut on: Vec<(u32, u32)> = Vec::with_capacity(3 * nt);
    for (t, tri) in tris.iter().enumerate() {
        for &v in &tri.v {
            on.push((v, group[t]));
        }
    }
    let facets_of = Lists::from_pairs(np, &mut on);
    let mut corner: Vec<bool> = (0..np).map(|v| facets_of.get(v).len() >= 3).collect();
    for c in &cycles {
        if c.iter().filter(|&&v| corner[v as usize]).count() < 3 {
            for &v in c {
                corner[v as usize] = true;
            }
        }
    }
    let mut vindex = vec![u32::MAX; np];
    let mut vertices = Vec::new();
    let mut source = Vec::new();
    for (v, &is) in corner.iter().enumerate() {
        if is && !facets_of.get(v).is_empty() {
            vindex[v] = vertices.len() as u32;
            vertices.push(pts[v]);
            source.push(v as u32);
        }
    }
    let mut loops_out = Lists {
        first: Vec::with_capacity(count + 1),
        items: Vec::new(),
    };
    for c in &cycles {
        loops_out.first.push(loops_out.items.len() as u32);
        loops_out.items.extend(
            c.iter()
                .filter(|&&v| corner[v as usize])
                .map(|&v| vindex[v as usize]),
        );
    }
    loops_out.first.push(loops_out.items.len() as u32);
    // Planes.
    let mut normals = Vec::with_capacity(count);
    let mut offsets = Vec::with_capacity(count);
    for (g, m) in members.iter().enumerate() {
        let n = normal_of(&mut m.iter().copied())
            .try_normalize(0.0)
            .ok_or(HullError::Failed(Real::INFINITY))?;
        let off = loops_out
            .get(g)
            .iter()
            .map(|&v| n.dot(&vertices[v as usize]))
            .fold(Real::NEG_INFINITY, Real::max);
        normals.push(n);
        offsets.push(off);
    }
    // Graphs.
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for g in 0..count {
        let l = loops_out.get(g);
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            pairs.push((a, b));
            pairs.push((b, a));
        }
    }
    let vertex_graph = Lists::from_pairs(vertices.len(), &mut pairs);
    pairs.clear();
    for (t, tri) in tris.iter().enumerate() {
        for &u in &tri.adj {
            if group[u as usize] != group[t] {
                pairs.push((group[t], group[u as usize]));
            }
        }
    }
    let facet_graph = Lists::from_pairs(count, &mut pairs);
    pairs.clear();
    for g in 0..count {
        for &v in loops_out.get(g) {
            pairs.push((v, g as u32));
        }
    }
    let incident = Lists::from_pairs(vertices.len(), &mut pairs);
    let mut mesh = Mesh {
        vertices,
        source,
        normals,
        offsets,
        loops: loops_out,
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
