//! EPA's polytope: support points of K, the triangles of its closed surface with their
//! neighbours, and the insertion of a point (the faces it sees replaced by the cone from
//! their horizon). Its arrays live on the stack or in a per-thread heap buffer
//! (`super::slots`).

use super::slots::{Capped, Slots};
use crate::math::{Real, Vec3};
use crate::solver::raycast::Vertex;
use arrayvec::ArrayVec;

/// Vertices and faces of the polytope on the stack (a closed triangulated sphere has
/// `F = 2V − 4`): room for 250 support calls (about 55 kB of stack, not initialised: see
/// [`Poly`]).
pub(super) const MAX_V: usize = 256;
const MAX_F: usize = 2 * MAX_V;
/// The heap polytope's room: 4 000 support calls.
const HEAP_V: usize = 4096;
const HEAP_F: usize = 2 * HEAP_V;
/// Horizon edges of one insertion.
const MAX_HORIZON: usize = 48;
/// Faces one insertion may see (the horizon search is quadratic in them, not in all faces).
const MAX_VISIBLE: usize = 2 * MAX_HORIZON;

/// A triangle of the polytope's surface.
#[derive(Clone, Copy, Debug)]
pub(super) struct Face {
    /// Its vertices, counter-clockwise seen from outside.
    pub(super) v: [u16; 3],
    /// The unit normal of their plane, outward.
    pub(super) n: Vec3,
    /// The least `n·(w − d)` over its vertices.
    pub(super) rho: Real,
    /// The face across each edge `(v[e], v[e + 1])`.
    adj: [u16; 3],
    /// The index of that edge in the face across it (its twin, `(v[e + 1], v[e])` there).
    twin: [u8; 3],
    /// Visit stamp of an insertion's search (`Poly::stamp` the current one).
    mark: u32,
    pub(super) alive: bool,
}

/// Where a polytope keeps its arrays.
pub(super) trait Store {
    type V: Slots<Vertex>;
    type F: Slots<Face>;
    type K: Slots<Real>;
    type R: Slots<u16>;
}

/// On the stack: `ArrayVec`s, of which a call initialises only the slots it fills
/// (zero-filling fixed arrays of this size cost about 0.7 µs a call).
pub(super) struct OnStack;
impl Store for OnStack {
    type V = ArrayVec<Vertex, MAX_V>;
    type F = ArrayVec<Face, MAX_F>;
    type K = ArrayVec<Real, MAX_F>;
    type R = ArrayVec<u16, MAX_F>;
}

/// In a per-thread heap buffer of [`HEAP_V`] vertices (about 0.9 MB).
pub(super) struct OnHeap;
impl Store for OnHeap {
    type V = Capped<Vertex>;
    type F = Capped<Face>;
    type K = Capped<Real>;
    type R = Capped<u16>;
}

/// The polytope.
pub(super) struct Poly<S: Store> {
    /// The offset whose depth it bounds.
    pub(super) d: Vec3,
    pub(super) verts: S::V,
    /// Face slots, the dead ones listed in `free`.
    pub(super) faces: S::F,
    /// `ρ_f` of each live face slot, `+∞` for a dead one: what the search for the closest
    /// face scans.
    pub(super) keys: S::K,
    free: S::R,
    /// The current visit stamp.
    stamp: u32,
}

/// Why [`Poly::insert`] added nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Refused {
    /// No room for the vertex, its faces or its horizon.
    Full,
    /// The point sees no face, or the result would hold a degenerate face or a horizon that
    /// is not one loop.
    Degenerate,
}

impl Poly<OnStack> {
    pub(super) fn new(d: &Vec3) -> Self {
        Poly {
            d: *d,
            verts: ArrayVec::new(),
            faces: ArrayVec::new(),
            keys: ArrayVec::new(),
            free: ArrayVec::new(),
            stamp: 0,
        }
    }
}

impl Poly<OnHeap> {
    pub(super) fn heap() -> Self {
        Poly {
            d: Vec3::zeros(),
            verts: Capped::with_capacity(HEAP_V),
            faces: Capped::with_capacity(HEAP_F),
            keys: Capped::with_capacity(HEAP_F),
            free: Capped::with_capacity(HEAP_F),
            stamp: 0,
        }
    }

    /// Becomes a copy of `other` (which fits: the heap's arrays are the larger).
    pub(super) fn copy_from<T: Store>(&mut self, other: &Poly<T>) {
        self.d = other.d;
        self.stamp = other.stamp;
        self.verts.clear_slots();
        self.faces.clear_slots();
        self.keys.clear_slots();
        self.free.clear_slots();
        for v in other.verts.iter() {
            self.verts.push_slot(*v);
        }
        for (f, k) in other.faces.iter().zip(other.keys.iter()) {
            self.faces.push_slot(*f);
            self.keys.push_slot(*k);
        }
        for k in other.free.iter() {
            self.free.push_slot(*k);
        }
    }
}

impl<S: Store> Poly<S> {
    fn face(&self, v: [u16; 3]) -> Option<Face> {
        let w = v.map(|i| self.verts[i as usize].w);
        let c = (w[1] - w[0]).cross(&(w[2] - w[0]));
        let len = c.norm();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let n = c / len;
        let rho = w
            .iter()
            .map(|wi| n.dot(&(wi - self.d)))
            .fold(Real::INFINITY, Real::min);
        Some(Face {
            v,
            n,
            rho,
            adj: [0; 3],
            twin: [0; 3],
            mark: 0,
            alive: true,
        })
    }

    /// The face of least `ρ_f` (the first of them).
    pub(super) fn closest(&self) -> usize {
        // The least key in four lanes (`r < m` as a select: the compiler's vector minimum),
        // then its first slot: the same face as a scan keeping the first strict minimum (NaN
        // keys, which the polytope never holds, lose either way), for about half the work.
        let keys: &[Real] = &self.keys;
        let mut lanes = [Real::INFINITY; 4];
        let mut chunks = keys.chunks_exact(4);
        for c in &mut chunks {
            for (m, &r) in lanes.iter_mut().zip(c) {
                *m = if r < *m { r } else { *m };
            }
        }
        for &r in chunks.remainder() {
            lanes[0] = if r < lanes[0] { r } else { lanes[0] };
        }
        let least = lanes
            .iter()
            .fold(Real::INFINITY, |m, &r| if r < m { r } else { m });
        let mut best = if least < Real::INFINITY {
            keys.iter().position(|&r| r == least).unwrap_or(usize::MAX)
        } else {
            usize::MAX
        };
        if best == usize::MAX {
            // No finite key: the first live face.
            best = self
                .faces
                .iter()
                .position(|f| f.alive)
                .unwrap_or(usize::MAX);
        }
        best
    }

    /// Sets every face's neighbours by matching twin edges (the starting tetrahedron).
    fn link_all(&mut self) -> bool {
        let nf = self.faces.len();
        for k in 0..nf {
            for e in 0..3 {
                let (i, j) = (self.faces[k].v[e], self.faces[k].v[(e + 1) % 3]);
                let twin = (0..nf).find_map(|m| {
                    let u = self.faces[m].v;
                    (0..3)
                        .find(|&t| u[t] == j && u[(t + 1) % 3] == i)
                        .map(|t| (m, t))
                });
                match twin {
                    Some((m, t)) => {
                        self.faces[k].adj[e] = m as u16;
                        self.faces[k].twin[e] = t as u8;
                    }
                    None => return false,
                }
            }
        }
        true
    }

    /// Adds `vtx` to the hull: the faces that see it (the connected set found by walking the
    /// neighbours from `hint`, or from the first face that sees it) are replaced by the cone
    /// from their horizon. An error (nothing changed) when it sees no face, or the result would
    /// overflow, hold a degenerate face or a horizon that is not one loop.
    pub(super) fn insert(&mut self, vtx: Vertex, eps: Real, hint: usize) -> Result<(), Refused> {
        if self.verts.room() == 0 {
            return Err(Refused::Full);
        }
        let s = vtx.w;
        let verts = &self.verts;
        let sees = |f: &Face| f.alive && f.n.dot(&(s - verts[f.v[0] as usize].w)) > eps;
        let nf = self.faces.len();
        let seed = if hint < nf && sees(&self.faces[hint]) {
            hint
        } else {
            match (0..nf).find(|&k| sees(&self.faces[k])) {
                Some(k) => k,
                None => return Err(Refused::Degenerate),
            }
        };
        // The visible faces: a walk over neighbours from the seed; each edge of a visible face
        // whose neighbour does not see the point is a horizon edge, with that neighbour and the
        // index of the twin edge in it (in the order of the faces taken off the stack, then of
        // their edges).
        self.stamp = self.stamp.wrapping_add(1);
        let stamp = self.stamp;
        let mut seen = ArrayVec::<u16, MAX_VISIBLE>::new();
        let mut stack = ArrayVec::<u16, MAX_VISIBLE>::new();
        let mut horizon = ArrayVec::<([u16; 2], u16, u8), MAX_HORIZON>::new();
        stack.push(seed as u16);
        self.faces[seed].mark = stamp;
        while let Some(k) = stack.pop() {
            if seen.try_push(k).is_err() {
                return Err(Refused::Full);
            }
            let (v, adj, twin) = {
                let f = &self.faces[k as usize];
                (f.v, f.adj, f.twin)
            };
            for e in 0..3 {
                let m = adj[e] as usize;
                if self.faces[m].mark == stamp {
                    continue;
                }
                if sees(&self.faces[m]) {
                    self.faces[m].mark = stamp;
                    if stack.try_push(m as u16).is_err() {
                        return Err(Refused::Full);
                    }
                } else {
                    let edge = [v[e], v[if e == 2 { 0 } else { e + 1 }]];
                    if horizon.try_push((edge, m as u16, twin[e])).is_err() {
                        return Err(Refused::Full);
                    }
                }
            }
        }
        let nh = horizon.len();
        if self.free.len() + self.faces.room() + seen.len() < nh {
            return Err(Refused::Full);
        }
        // The cone's faces, and for each horizon edge the one that starts where it ends
        // (`next`) and the one that ends where it starts (`prev`): each exactly one, so that
        // every horizon vertex starts and ends exactly one edge.
        // (Exactly one edge starting where each ends, and no edge the successor of two: then
        // `next` is a bijection and `prev` its inverse, which is the same as exactly one
        // successor and one predecessor each, at half the comparisons.)
        let mut next = [0u8; MAX_HORIZON];
        let mut prev = [0u8; MAX_HORIZON];
        let mut taken: u64 = 0;
        for (h, (e, _, _)) in horizon.iter().enumerate() {
            let mut nn = 0;
            for (g, (o, _, _)) in horizon.iter().enumerate() {
                if o[0] == e[1] {
                    next[h] = g as u8;
                    nn += 1;
                }
            }
            let bit = 1u64 << next[h];
            if nn != 1 || taken & bit != 0 {
                return Err(Refused::Degenerate);
            }
            taken |= bit;
            prev[next[h] as usize] = h as u8;
        }
        let new = self.verts.len() as u16;
        self.verts.push_slot(vtx);
        let mut fresh = ArrayVec::<Face, MAX_HORIZON>::new();
        for (e, _, _) in &horizon {
            match self.face([e[0], e[1], new]) {
                Some(face) => fresh.push(face),
                None => {
                    self.verts.pop_slot();
                    return Err(Refused::Degenerate);
                }
            }
        }
        // Commit: free the visible faces, then place the cone's (room checked above).
        for &k in &seen {
            self.faces[k as usize].alive = false;
            self.keys[k as usize] = Real::INFINITY;
            self.free.push_slot(k);
        }
        let mut slot = [0u16; MAX_HORIZON];
        for (s, f) in slot[..nh].iter_mut().zip(&fresh) {
            *s = match self.free.pop_slot() {
                Some(k) => k,
                None => {
                    self.faces.push_slot(*f);
                    self.keys.push_slot(Real::INFINITY);
                    (self.faces.len() - 1) as u16
                }
            };
        }
        // Face h is (e₀, e₁, new): across its edge 0 the horizon's neighbour (at the twin's
        // index), across edge 1 (e₁, new) the next cone face's edge 2 (new, its e₀ = e₁), across
        // edge 2 the previous cone face's edge 1.
        for (h, (_, m, t)) in horizon.iter().enumerate() {
            let mut f = fresh[h];
            f.adj = [*m, slot[next[h] as usize], slot[prev[h] as usize]];
            f.twin = [*t, 2, 1];
            self.faces[slot[h] as usize] = f;
            self.keys[slot[h] as usize] = f.rho;
            let across = &mut self.faces[*m as usize];
            across.adj[*t as usize] = slot[h];
            across.twin[*t as usize] = 0;
        }
        Ok(())
    }
}

/// The polytope of the four vertices `tet`, its faces oriented outward; false when they do
/// not span a tetrahedron (relative volume `least`).
pub(super) fn start_from<T: Store>(poly: &mut Poly<T>, tet: &[Vertex; 4], least: Real) -> bool {
    poly.verts.clear_slots();
    poly.faces.clear_slots();
    poly.keys.clear_slots();
    poly.free.clear_slots();
    for v in tet {
        poly.verts.push_slot(*v);
    }
    let w = tet.map(|v| v.w);
    let vol = (w[1] - w[0]).cross(&(w[2] - w[0])).dot(&(w[3] - w[0]));
    let scale = (w[1] - w[0]).norm() * (w[2] - w[0]).norm() * (w[3] - w[0]).norm();
    if !(vol.abs() > least * scale) {
        return false;
    }
    // With vol > 0, (0,1,2) has 3 on its positive side: orient it the other way.
    let faces: [[u16; 3]; 4] = if vol > 0.0 {
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
    } else {
        [[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]
    };
    for v in faces {
        let Some(f) = poly.face(v) else {
            return false;
        };
        poly.faces.push_slot(f);
        poly.keys.push_slot(f.rho);
    }
    poly.link_all()
}
