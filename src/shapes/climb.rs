//! A polytope's support vertex by hill climbing on its vertex graph from a start looked up in a
//! cube map of directions: for a linear objective on a convex polytope a vertex with no better
//! neighbour is a maximiser, so the climb ends at the support vertex, in a step or two from a
//! start that maximises a nearby direction, where the plain search costs a dot product per
//! vertex.

use crate::math::{Real, Vec3};

/// Cells per cube face side (6·N² start vertices).
const N: usize = 6;

/// The vertex graph and the cube map of start vertices.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Climb {
    /// For each cell of the cube map (face `2·axis + (negative)`, then the two other
    /// coordinates' cells), the vertex maximising the cell's centre direction.
    start: Vec<u16>,
    /// Neighbours of vertex k: `adj[first[k]..first[k + 1]]`.
    first: Vec<u32>,
    adj: Vec<u16>,
}

impl Climb {
    /// The graph from each vertex's incident facets (two vertices sharing two facets share an
    /// edge); `None` when a check climb from every cell's start to each vertex's own direction
    /// (the sum of its facets' normals) does not reach that vertex's value: the search answers
    /// then.
    pub(crate) fn new(vertices: &[Vec3], incident: &[Vec<u16>], normals: &[Vec3]) -> Option<Climb> {
        let nv = vertices.len();
        if nv > u16::MAX as usize || incident.len() != nv {
            return None;
        }
        let mut first = Vec::with_capacity(nv + 1);
        let mut adj = Vec::new();
        for (i, fi) in incident.iter().enumerate() {
            first.push(adj.len() as u32);
            for (j, fj) in incident.iter().enumerate() {
                let shared = fi.iter().filter(|f| fj.contains(f)).count();
                if i != j && shared >= 2 {
                    adj.push(j as u16);
                }
            }
        }
        first.push(adj.len() as u32);
        let mut start = vec![0u16; 6 * N * N];
        for (c, s) in start.iter_mut().enumerate() {
            *s = super::support::argmax_dot(vertices, &centre(c)).0 as u16;
        }
        let climb = Climb { start, first, adj };
        for (j, fj) in incident.iter().enumerate() {
            let m = fj
                .iter()
                .fold(Vec3::zeros(), |s, &f| s + normals[f as usize]);
            let want = vertices[j].dot(&m);
            let tol = 1e-12 * (vertices[j].norm() * m.norm()).max(Real::MIN_POSITIVE);
            for c in 0..6 * N * N {
                let k = climb.from(vertices, climb.start[c] as usize, &m);
                if vertices[k].dot(&m) < want - tol {
                    return None;
                }
            }
        }
        Some(climb)
    }

    /// The support vertex's index in direction `m`.
    #[inline]
    pub(crate) fn support(&self, vertices: &[Vec3], m: &Vec3) -> usize {
        self.from(vertices, self.start[cell(m)] as usize, m)
    }

    /// Steepest ascent from vertex `k`.
    #[inline]
    fn from(&self, vertices: &[Vec3], mut k: usize, m: &Vec3) -> usize {
        let mut h = vertices[k].dot(m);
        loop {
            let mut next = k;
            for &j in &self.adj[self.first[k] as usize..self.first[k + 1] as usize] {
                let hj = vertices[j as usize].dot(m);
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

/// The cube map cell of direction `m` (cell 0 for a zero or NaN direction).
#[inline]
fn cell(m: &Vec3) -> usize {
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
    let bin = |t: Real| (((t + 1.0) * 0.5 * N as Real) as usize).min(N - 1);
    let face = 2 * axis + usize::from(m[axis] < 0.0);
    (face * N + bin(u)) * N + bin(v)
}

/// The centre direction of cell `c`.
fn centre(c: usize) -> Vec3 {
    let (face, rest) = (c / (N * N), c % (N * N));
    let (i, j) = (rest / N, rest % N);
    let t = |k: usize| (k as Real + 0.5) / N as Real * 2.0 - 1.0;
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
        for c in 0..6 * N * N {
            assert_eq!(cell(&centre(c)), c);
        }
        assert_eq!(cell(&Vec3::new(Real::NAN, 0.0, 0.0)), 0);
        assert_eq!(cell(&Vec3::zeros()), 0);
    }
}
