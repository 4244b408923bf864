//! The maximiser of `m·p` over the vertices `p` of a convex polytope by hill climbing on its
//! vertex graph from a start looked up in a cube map of directions: for a linear objective on a
//! convex polytope a vertex with no better neighbour is a maximiser, so the climb ends at the
//! support vertex, in a step or two from a start that maximises a nearby direction, where the
//! plain search costs a dot product per vertex.
//!
//! Used for a polytope's support map (its corners, joined by its edges) and for its gauge (the
//! polar polytope's corners `n_i/o_i`, one per facet, joined when the facets share an edge).

use super::quickhull::Lists;
use crate::math::{Real, Vec3};

/// Cells per cube face side for small polytopes (6·N² start vertices).
const N_MIN: usize = 6;
/// Cells per cube face side at most (6·N² = 6 144 starts).
const N_MAX: usize = 32;

/// The vertex graph and the cube map of start vertices.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Climb {
    /// Cells per cube face side.
    n: usize,
    /// For each cell of the cube map (face `2·axis + (negative)`, then the two other
    /// coordinates' cells), the vertex maximising the cell's centre direction.
    start: Vec<u32>,
    /// Each vertex's neighbours.
    graph: Lists,
}

impl Climb {
    /// The graph from each vertex's incident facets (two vertices sharing two facets share an
    /// edge); `None` when a check climb from every cell's start to each vertex's own direction
    /// (the sum of its facets' normals) does not reach that vertex's value: the search answers
    /// then. For the polytopes of a few facets built from their planes.
    pub(crate) fn new(vertices: &[Vec3], incident: &[Vec<u16>], normals: &[Vec3]) -> Option<Climb> {
        let nv = vertices.len();
        if incident.len() != nv {
            return None;
        }
        let mut pairs = Vec::new();
        for (i, fi) in incident.iter().enumerate() {
            for (j, fj) in incident.iter().enumerate() {
                let shared = fi.iter().filter(|f| fj.contains(f)).count();
                if i != j && shared >= 2 {
                    pairs.push((i as u32, j as u32));
                }
            }
        }
        let graph = Lists::from_pairs(nv, &pairs);
        let start = (0..6 * N_MIN * N_MIN)
            .map(|c| super::support::argmax_dot(vertices, &centre(N_MIN, c)).0 as u32)
            .collect();
        let climb = Climb {
            n: N_MIN,
            start,
            graph,
        };
        for (j, fj) in incident.iter().enumerate() {
            let m = fj
                .iter()
                .fold(Vec3::zeros(), |s, &f| s + normals[f as usize]);
            let want = vertices[j].dot(&m);
            let tol = 1e-12 * (vertices[j].norm() * m.norm()).max(Real::MIN_POSITIVE);
            for c in 0..6 * N_MIN * N_MIN {
                let k = climb.from(vertices, climb.start[c] as usize, &m);
                if vertices[k].dot(&m) < want - tol {
                    return None;
                }
            }
        }
        Some(climb)
    }

    /// The climb on a convex polytope's own graph (a hull's: exact, so no check), with a cube
    /// map of about one cell per four points (between 6·6² and 6·32² cells), each cell's start
    /// found by climbing from the previous cell's.
    pub(crate) fn from_graph(points: &[Vec3], graph: Lists) -> Climb {
        let n = (((points.len() / 24) as Real).sqrt().ceil() as usize).clamp(N_MIN, N_MAX);
        let mut climb = Climb {
            n,
            start: Vec::with_capacity(6 * n * n),
            graph,
        };
        let mut k = super::support::argmax_dot(points, &centre(n, 0)).0;
        for c in 0..6 * n * n {
            // A new face of the cube: start from the search (the previous cell is far away).
            if c % (n * n) == 0 {
                k = super::support::argmax_dot(points, &centre(n, c)).0;
            }
            k = climb.from(points, k, &centre(n, c));
            climb.start.push(k as u32);
        }
        climb
    }

    /// The support vertex's index in direction `m`.
    #[inline]
    pub(crate) fn support(&self, points: &[Vec3], m: &Vec3) -> usize {
        self.from(points, self.start[cell(self.n, m)] as usize, m)
    }

    /// Each vertex's neighbours.
    pub(crate) fn graph(&self) -> &Lists {
        &self.graph
    }

    /// Steepest ascent from vertex `k`.
    #[inline]
    pub(crate) fn from(&self, points: &[Vec3], mut k: usize, m: &Vec3) -> usize {
        let mut h = points[k].dot(m);
        loop {
            let mut next = k;
            for &j in self.graph.get(k) {
                let hj = points[j as usize].dot(m);
                if hj > h {
                    (h, next) = (hj, j as usize);
                }
            }
            if next == k {
                return k;
            }
            k = next;
        }
    }
}

/// The cube map cell of direction `m` (cell 0 for a zero or NaN direction), `n` cells a side.
#[inline]
fn cell(n: usize, m: &Vec3) -> usize {
    let a = m.abs();
    let axis = if a.x >= a.y && a.x >= a.z {
        0
    } else if a.y >= a.z {
        1
    } else {
        2
    };
    let big = a[axis];
    if !(big > 0.0) {
        return 0;
    }
    let (u, v) = (m[(axis + 1) % 3] / big, m[(axis + 2) % 3] / big);
    let bin = |t: Real| (((t + 1.0) * 0.5 * n as Real) as usize).min(n - 1);
    let face = 2 * axis + usize::from(m[axis] < 0.0);
    (face * n + bin(u)) * n + bin(v)
}

/// The centre direction of cell `c`, `n` cells a side.
fn centre(n: usize, c: usize) -> Vec3 {
    let (face, rest) = (c / (n * n), c % (n * n));
    let (i, j) = (rest / n, rest % n);
    let t = |k: usize| (k as Real + 0.5) / n as Real * 2.0 - 1.0;
    let axis = face / 2;
    let sign = if face % 2 == 1 { -1.0 } else { 1.0 };
    let mut m = Vec3::zeros();
    m[axis] = sign;
    m[(axis + 1) % 3] = t(i);
    m[(axis + 2) % 3] = t(j);
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_and_centres_agree() {
        for n in [N_MIN, 11, N_MAX] {
            for c in 0..6 * n * n {
                assert_eq!(cell(n, &centre(n, c)), c);
            }
            assert_eq!(cell(n, &Vec3::new(Real::NAN, 0.0, 0.0)), 0);
            assert_eq!(cell(n, &Vec3::zeros()), 0);
        }
    }

    #[test]
    fn the_climb_on_a_hulls_graph_finds_the_searchs_maximum() {
        let mut x: u64 = 0x2545_F491_4F6C_DD1D;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
        };
        for n in [10, 100, 5000] {
            let pts: Vec<Vec3> = (0..n)
                .map(|_| Vec3::new(next(), 0.5 * next(), 2.0 * next()))
                .collect();
            let mesh = super::super::quickhull::hull(&pts).unwrap();
            let climb = Climb::from_graph(&mesh.vertices, mesh.vertex_graph.clone());
            for _ in 0..3000 {
                let m = Vec3::new(next(), next(), next());
                let k = climb.support(&mesh.vertices, &m);
                let (_, h) = super::super::support::argmax_dot(&mesh.vertices, &m);
                assert_eq!(mesh.vertices[k].dot(&m), h);
            }
        }
    }
}
