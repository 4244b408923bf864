//! The Jacobian of (x*, α*) between two polytopes in closed form, where their contact is a
//! facet of K: a vertex of one against a face of the other, or an edge of each (not parallel).
//!
//! With shape i at `(rᵢ, Rᵢ)` and `d = r₂ − r₁`, the scaled shapes touch where the scaled
//! vertex (or edge) meets the plane of the scaled face (or of the other edge): with `m` that
//! plane's normal (the face's `Rⱼ m_b`, or `e₁ × e₂` for edges `eᵢ = Rᵢ(p₁ − p₀)`) and `u₁, u₂`
//! a body point of each feature in world axes (`Rᵢ pᵢ`),
//!
//! ```text
//!     m·(r₁ + α u₁ − r₂ − α u₂) = 0   ⇒   α* = N/D,  N = m·d,  D = m·(u₁ − u₂)
//! ```
//!
//! (independent of `m`'s length and sign). Its derivatives: `∂α/∂r₂ = m/D = −∂α/∂r₁`, and along
//! a quaternion component, `δα = (δN − α δD)/D` with `δN = δm·d`, `δD = δm·(u₁ − u₂) + m·(δu₁ −
//! δu₂)`, `δuᵢ = (∂Rᵢ/∂qᵢₖ) pᵢ`. The touching point is the vertex scaled, `x* = r₁ + α u₁`
//! (vertex of shape 1) or `r₂ + α u₂` (vertex of shape 2); for two edges
//! `x* = r₁ + α(u₁ + s e₁)`, where the lines `u₁ + s e₁` and `u₂ + t e₂ + d/α` meet:
//! `c + s e₁ − t e₂ = 0` with `c = u₁ − u₂ − d/α`, so `s = −(c × e₂)·m/|m|²` and
//! `δs = −((δc + s δe₁ − t δe₂) × e₂)·m/|m|²`.

use crate::math::{rotation_derivatives, Pose, Real, Vec3};
use crate::shapes::{Shape, SupportMap};
use crate::solver::features::{identify, Feature};
use crate::solver::raycast::Pair;
use crate::solver::sensitivity::Solution;

/// The contact of two polytopes as a facet of K, in world axes (lengths as the shapes').
enum Facet {
    /// Shape `vertex_of`'s vertex `v` (body) against the other's face through body points
    /// `w[0..3]`.
    VertexFace {
        vertex_of: usize,
        v: Vec3,
        w: [Vec3; 3],
    },
    /// Shape 1's edge `p₀p₁` against shape 2's edge `w₀w₁` (body points).
    Edges { p: [Vec3; 2], w: [Vec3; 2] },
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` for two polytopes touching on a facet of K (see the module
/// doc), or `None` for another contact (`pair` and `sol` the normalised geometric solution, as
/// `crate::solver::sensitivity` takes it). `alpha` is α* (world).
pub(crate) fn polytope_jacobian(
    pair: &Pair<'_, Shape>,
    sol: &Solution,
    alpha: Real,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> Option<[[Real; 14]; 4]> {
    let verts = [shapes[0].vertex_pieces()?, shapes[1].vertex_pieces()?];
    let feats = identify(pair, sol)?;
    let mut ids = [[0u32; 3]; 2];
    let mut counts = [0usize; 2];
    for (i, f) in feats.iter().enumerate() {
        let Feature::Pieces { ids: k, count, .. } = f else {
            return None;
        };
        ids[i] = *k;
        counts[i] = *count;
    }
    let at = |i: usize, k: usize| verts[i].get(ids[i][k] as usize).copied();
    let facet = match counts {
        [1, 3] => Facet::VertexFace {
            vertex_of: 0,
            v: at(0, 0)?,
            w: [at(1, 0)?, at(1, 1)?, at(1, 2)?],
        },
        [3, 1] => Facet::VertexFace {
            vertex_of: 1,
            v: at(1, 0)?,
            w: [at(0, 0)?, at(0, 1)?, at(0, 2)?],
        },
        [2, 2] => Facet::Edges {
            p: [at(0, 0)?, at(0, 1)?],
            w: [at(1, 0)?, at(1, 1)?],
        },
        _ => return None,
    };
    let jac = facet_jacobian(&facet, alpha, poses)?;
    crate::math::all_finite(&jac).then_some(jac)
}

fn facet_jacobian(facet: &Facet, alpha: Real, poses: [&Pose; 2]) -> Option<[[Real; 14]; 4]> {
    let rot = [poses[0].rotation(), poses[1].rotation()];
    let drot = [
        rotation_derivatives(poses[0].quaternion()),
        rotation_derivatives(poses[1].quaternion()),
    ];
    let d = poses[1].position() - poses[0].position();
    let mut j = [[0.0; 14]; 4];
    match *facet {
        Facet::VertexFace { vertex_of, v, w } => {
            // Shape `a` has the vertex, shape `b` the face; in the formula shape 1's point is
            // u₁ (the vertex when a = 0, the face's when a = 1).
            let (a, b) = (vertex_of, 1 - vertex_of);
            let mb = (w[1] - w[0]).cross(&(w[2] - w[0]));
            let m = rot[b] * mb;
            let (pv, pw) = (rot[a] * v, rot[b] * w[0]);
            // u₁ − u₂ with u of shape 1 first.
            let sign = if a == 0 { 1.0 } else { -1.0 };
            let gap = (pv - pw) * sign;
            let den = m.dot(&gap);
            if !(den.abs() > 0.0) {
                return None;
            }
            let mut da = [0.0; 14];
            for c in 0..3 {
                da[7 + c] = m[c] / den;
                da[c] = -m[c] / den;
            }
            for k in 0..4 {
                // The vertex's shape: only D changes, through δu of the vertex.
                let dv = drot[a][k] * v;
                da[7 * a + 3 + k] = -alpha * m.dot(&(dv * sign)) / den;
                // The face's shape: m and its point move.
                let dm = drot[b][k] * mb;
                let dw = drot[b][k] * w[0];
                let dn = dm.dot(&d);
                let dd = dm.dot(&gap) - m.dot(&(dw * sign));
                da[7 * b + 3 + k] = (dn - alpha * dd) / den;
            }
            // x* = r_a + α R_a v.
            for (col, &g) in da.iter().enumerate() {
                j[3][col] = g;
                for i in 0..3 {
                    j[i][col] = pv[i] * g;
                }
            }
            for i in 0..3 {
                j[i][7 * a + i] += 1.0;
            }
            for k in 0..4 {
                let dv = drot[a][k] * v * alpha;
                for i in 0..3 {
                    j[i][7 * a + 3 + k] += dv[i];
                }
            }
        }
        Facet::Edges { p, w } => {
            let (eb1, eb2) = (p[1] - p[0], w[1] - w[0]);
            let (e1, e2) = (rot[0] * eb1, rot[1] * eb2);
            let (u1, u2) = (rot[0] * p[0], rot[1] * w[0]);
            let m = e1.cross(&e2);
            let mm = m.norm_squared();
            let den = m.dot(&(u1 - u2));
            if !(mm > 0.0 && den.abs() > 0.0) {
                return None;
            }
            let c = u1 - u2 - d / alpha;
            let s = -c.cross(&e2).dot(&m) / mm;
            let t = (c + e1 * s).dot(&e2) / e2.norm_squared();
            let point = u1 + e1 * s;
            // One column at a time: the changes of d, u₁, u₂, e₁, e₂ it makes.
            let mut column = |col: usize, dd: Vec3, du1: Vec3, du2: Vec3, de1: Vec3, de2: Vec3| {
                let dm = de1.cross(&e2) + e1.cross(&de2);
                let dn = dm.dot(&d) + m.dot(&dd);
                let dden = dm.dot(&(u1 - u2)) + m.dot(&(du1 - du2));
                let dalpha = (dn - alpha * dden) / den;
                let dc = du1 - du2 - dd / alpha + d * (dalpha / (alpha * alpha));
                let ds = -(dc + de1 * s - de2 * t).cross(&e2).dot(&m) / mm;
                let dx = point * dalpha + (du1 + e1 * ds + de1 * s) * alpha;
                j[3][col] = dalpha;
                for i in 0..3 {
                    j[i][col] = dx[i];
                }
            };
            let z = Vec3::zeros();
            for c in 0..3 {
                let mut e = Vec3::zeros();
                e[c] = 1.0;
                // r₂ moves d; r₁ moves d the other way and x* with it.
                column(7 + c, e, z, z, z, z);
                column(c, -e, z, z, z, z);
            }
            for k in 0..4 {
                column(3 + k, z, drot[0][k] * p[0], z, drot[0][k] * eb1, z);
                column(10 + k, z, z, drot[1][k] * w[0], z, drot[1][k] * eb2);
            }
            for i in 0..3 {
                j[i][i] += 1.0;
            }
        }
    }
    Some(j)
}
