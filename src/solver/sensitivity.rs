//! The Jacobian of (x*, α*) from the geometric solution: the implicit function theorem on the
//! KKT system of the contact features the solution identifies.
//!
//! In the normalised frame of [`super::polish`] (lengths over ℓ, `r` the ray), the optimum of
//! `1/α' = min { h₁(n) + h₂(−n) : n·r = 1 }` satisfies, on its contact features,
//!
//! ```text
//!     Σ_k λ_k G_k(n) − μ r = 0            G_k = ∇p_k: a piece's support point (shape 2: −b)
//!     n·r − 1 = 0
//!     Σ_{k ∈ shape i} λ_k − 1 = 0         (i = 1, 2)
//!     p_k(n) − p_{k₀}(n) = 0               (a shape's pieces tie: an edge, a face)
//!     (R e_y)·n = (R e_z)·n = 0            (a flat disc faces n: a cap, a cone's base)
//! ```
//!
//! with a disc's point `c + s_y e_y + s_z e_z` (its two coordinates unknowns). A shape's feature
//! is one piece (a vertex, a smooth patch), the two ends of a segment (a polytope's edge, a
//! capsule's or cylinder's side, a cone's generator), a triangle of a face's vertices, or a disc.
//! x* is unique, and the system square and (generically) regular, when the two features' affine
//! dimensions add up to at most two and two segments are not parallel; otherwise (face against
//! face or edge, parallel edges) there is no exact Jacobian and the caller falls back.
//!
//! A change of the ray `r` or of a shape's attitude (`δR = [ω]×R`) moves the residual by
//! `∂F/∂r` and `∂F/∂ω`: `δG_k = ω×G_k − H_k(ω×n)`, `δp_k = −G_k·(ω×n)`, a disc's point rotates
//! with its shape, and its rows change by `−(R e)·(ω×n)`. The outputs μ and the contact point
//! `a = Σ_{k ∈ shape 1} λ_k G_k` are linear in the solution's change, so one factorisation and
//! one transposed solve with four right-hand sides (the adjoint) give all fourteen columns.

use super::dense::{lu_factor_in_place, lu_solve_one, lu_solve_transposed4};
use super::features::{identify, Feature, MAX_SIDE};
pub(crate) use super::features::{Solution, PARALLEL_SIN};
use super::polish::{eval, Active, WorldPiece};
use super::raycast::Pair;
use crate::math::{Mat3, Real, Vec3};
use crate::shapes::SupportMap;

/// Unknowns: n (3), μ, and up to `MAX_SIDE` per shape.
const DIM: usize = 4 + 2 * MAX_SIDE;
/// Newton steps that refine the solution on its features before it is differentiated.
const NEWTON: usize = 3;
/// A residual this small (normalised) needs no Newton step: the derivatives' own rounding is
/// larger.
const CONVERGED: Real = 1e-13;
/// The largest residual (normalised) accepted at the end.
const MAX_RESIDUAL: Real = 1e-9;

/// The derivatives of `μ` and of `a` with respect to the ray (a free vector, at `r`) and to each
/// attitude's four rotation axes (`axes[i][k]`, `δRᵢ = [ω]× Rᵢ`).
pub(crate) struct Sensitivity {
    /// `∂μ/∂r`.
    pub dmu_dr: Vec3,
    /// `∂a/∂r`, column j the derivative along `e_j`.
    pub da_dr: Mat3,
    /// `∂μ/∂θ`, columns shape 1's four axes then shape 2's.
    pub dmu_dtheta: [Real; 8],
    /// `∂a/∂θ`.
    pub da_dtheta: [Vec3; 8],
    /// The refined solution's `μ` and `a`.
    pub mu: Real,
    pub a: Vec3,
}

/// One shape's feature, evaluated at `n`.
struct Side {
    feature: Feature,
    /// Pieces evaluated (or the disc's point as `grad`, zero Hessian), world normalised.
    pieces: [WorldPiece; MAX_SIDE],
    /// The disc's tangents `R e_y`, `R e_z` (world), scaled by `sign/ℓ`.
    tangents: [Vec3; 2],
    /// The disc's plain tangents (for its rows).
    axes: [Vec3; 2],
    /// First unknown of this side.
    col: usize,
}

fn zero_piece() -> WorldPiece {
    WorldPiece {
        value: 0.0,
        grad: Vec3::zeros(),
        hess: Mat3::zeros(),
    }
}

fn evaluate<S: SupportMap>(
    pair: &Pair<'_, S>,
    shape: usize,
    feature: Feature,
    n: &Vec3,
    col: usize,
) -> Option<Side> {
    let (posed, sign) = pair.side(shape);
    let mut side = Side {
        feature,
        pieces: [zero_piece(), zero_piece(), zero_piece()],
        tangents: [Vec3::zeros(); 2],
        axes: [Vec3::zeros(); 2],
        col,
    };
    match feature {
        Feature::Pieces { ids, count, .. } => {
            for k in 0..count {
                side.pieces[k] = eval(pair, Active { shape, id: ids[k] }, n)?;
            }
        }
        Feature::Disc { centre, s, .. } => {
            let (ey, ez) = (
                posed.rot.column(1).into_owned(),
                posed.rot.column(2).into_owned(),
            );
            let scale = sign * posed.inv_scale;
            let body = centre + Vec3::new(0.0, s[0], s[1]);
            side.pieces[0].grad = posed.rot * body * scale;
            side.pieces[0].value = n.dot(&side.pieces[0].grad);
            side.tangents = [ey * scale, ez * scale];
            side.axes = [ey, ez];
        }
    }
    Some(side)
}

/// The residual `F` and its Jacobian at the unknowns `z`; the residual's largest entry.
fn assemble(
    sides: &[Side; 2],
    r: &Vec3,
    z: &[Real; DIM],
    jac: &mut [[Real; DIM]; DIM],
    res: &mut [Real; DIM],
) -> Real {
    let dim = 4 + sides[0].feature.unknowns() + sides[1].feature.unknowns();
    for row in jac.iter_mut() {
        row.fill(0.0);
    }
    res.fill(0.0);
    let n = Vec3::new(z[0], z[1], z[2]);
    let mu = z[3];
    let mut stat = -r * mu;
    for i in 0..3 {
        jac[i][3] = -r[i];
        jac[3][i] = r[i];
    }
    res[3] = n.dot(r) - 1.0;
    for side in sides {
        let c = side.col;
        match side.feature {
            Feature::Pieces { count, .. } => {
                let mut sum = -1.0;
                for k in 0..count {
                    let (p, l) = (&side.pieces[k], z[c + k]);
                    stat += p.grad * l;
                    sum += l;
                    for i in 0..3 {
                        jac[i][c + k] = p.grad[i];
                        for j in 0..3 {
                            jac[i][j] += l * p.hess[(i, j)];
                        }
                    }
                    jac[c][c + k] = 1.0;
                    if k > 0 {
                        let g = p.grad - side.pieces[0].grad;
                        for j in 0..3 {
                            jac[c + k][j] = g[j];
                        }
                        res[c + k] = p.value - side.pieces[0].value;
                    }
                }
                res[c] = sum;
            }
            Feature::Disc { .. } => {
                let l = z[c];
                stat += side.pieces[0].grad * l;
                for i in 0..3 {
                    jac[i][c] = side.pieces[0].grad[i];
                    jac[i][c + 1] = l * side.tangents[0][i];
                    jac[i][c + 2] = l * side.tangents[1][i];
                }
                jac[c][c] = 1.0;
                res[c] = l - 1.0;
                for t in 0..2 {
                    for j in 0..3 {
                        jac[c + 1 + t][j] = side.axes[t][j];
                    }
                    res[c + 1 + t] = side.axes[t].dot(&n);
                }
            }
        }
    }
    res[..3].copy_from_slice(stat.as_slice());
    res[..dim].iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

/// Writes the unknowns `z` back into the features (multipliers, disc coordinates).
fn store(feature: &mut Feature, z: &[Real], col: usize) {
    match feature {
        Feature::Pieces { lam, count, .. } => lam[..*count].copy_from_slice(&z[col..col + *count]),
        Feature::Disc { s, .. } => *s = [z[col + 1], z[col + 2]],
    }
}

/// The features' system solved at the geometric solution: the features, their evaluation, the
/// unknowns and the factorised Jacobian there.
struct Solved {
    sides: [Side; 2],
    ipiv: [usize; DIM],
    dim: usize,
    z: [Real; DIM],
}

/// Identifies both shapes' features at `sol` and solves their system by Newton's method from it;
/// `None` where x* is not unique, the features cannot be identified, their system is singular,
/// or the solution leaves the features (a negative multiplier, a point off its disc).
fn solve_features<S: SupportMap>(
    pair: &Pair<'_, S>,
    sol: &Solution,
    lu: &mut [[Real; DIM]; DIM],
) -> Option<Solved> {
    let feats = identify(pair, sol)?;
    newton(pair, &sol.r, feats, &sol.normal, sol.mu, lu)
}

/// Newton's method on the system of the features `feats` from the normal `normal` (`n·r = 1`)
/// and `mu`, at most [`NEWTON`] steps; `None` as for [`solve_features`].
fn newton<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    mut feats: [Feature; 2],
    normal: &Vec3,
    mu: Real,
    lu: &mut [[Real; DIM]; DIM],
) -> Option<Solved> {
    let r = *r;
    let cols = [4, 4 + feats[0].unknowns()];
    let dim = cols[1] + feats[1].unknowns();
    let mut z = [0.0; DIM];
    z[..3].copy_from_slice(normal.as_slice());
    z[3] = mu;
    for (f, &c) in feats.iter().zip(&cols) {
        match f {
            Feature::Pieces { lam, count, .. } => z[c..c + count].copy_from_slice(&lam[..*count]),
            Feature::Disc { s, .. } => {
                z[c] = 1.0;
                z[c + 1] = s[0];
                z[c + 2] = s[1];
            }
        }
    }
    let mut res = [0.0; DIM];
    let mut step = 0;
    let (sides, ipiv) = loop {
        let n = Vec3::new(z[0], z[1], z[2]);
        let sides = [
            evaluate(pair, 0, feats[0], &n, cols[0])?,
            evaluate(pair, 1, feats[1], &n, cols[1])?,
        ];
        let worst = assemble(&sides, &r, &z, lu, &mut res);
        if !worst.is_finite() {
            return None;
        }
        let ipiv = lu_factor_in_place(lu, dim)?;
        if worst <= CONVERGED || step == NEWTON {
            if !(worst <= MAX_RESIDUAL) {
                return None;
            }
            break (sides, ipiv);
        }
        lu_solve_one(lu, &ipiv, dim, &mut res);
        for i in 0..dim {
            z[i] -= res[i];
        }
        for (f, &c) in feats.iter_mut().zip(&cols) {
            store(f, &z, c);
        }
        step += 1;
    };
    // The features must hold at the refined point: multipliers non-negative, a disc's point on
    // the disc.
    for f in &feats {
        match f {
            Feature::Pieces { lam, count, .. } => {
                if lam[..*count].iter().any(|l| !(*l >= -1e-9)) {
                    return None;
                }
            }
            Feature::Disc { radius, s, .. } => {
                if !(s[0].hypot(s[1]) <= radius * (1.0 + 1e-9)) {
                    return None;
                }
            }
        }
    }
    Some(Solved {
        sides,
        ipiv,
        dim,
        z,
    })
}

/// The point `Σ λ_k G_k` of one side's feature (shape 2's is `−b`).
fn side_point(side: &Side, z: &[Real; DIM]) -> Vec3 {
    let c = side.col;
    match side.feature {
        Feature::Pieces { count, .. } => {
            (0..count).fold(Vec3::zeros(), |acc, k| acc + side.pieces[k].grad * z[c + k])
        }
        Feature::Disc { .. } => side.pieces[0].grad * z[c],
    }
}

/// The geometric solution refined on its contact features: the normal (`n·r = 1`), `μ`, and
/// the points `a` and `b`; `None` as for [`sensitivity`]. The caller certifies it.
pub(crate) fn refine<S: SupportMap>(pair: &Pair<'_, S>, sol: &Solution) -> Option<Solution> {
    let mut lu = [[0.0; DIM]; DIM];
    let s = solve_features(pair, sol, &mut lu)?;
    Some(Solution {
        r: sol.r,
        normal: Vec3::new(s.z[0], s.z[1], s.z[2]),
        mu: s.z[3],
        a: side_point(&s.sides[0], &s.z),
        b: -side_point(&s.sides[1], &s.z),
    })
}

/// The sensitivities of the geometric solution `sol`, or `None` where x* is not unique, the
/// features cannot be identified, or their system is singular (the caller falls back).
///
/// `round[i]`: shape i ignores its attitude (a sphere); its rotation columns are left zero
/// instead of being computed (they are exactly zero).
pub(crate) fn sensitivity<S: SupportMap>(
    pair: &Pair<'_, S>,
    sol: &Solution,
    axes: &[[Vec3; 4]; 2],
    round: [bool; 2],
) -> Option<Sensitivity> {
    let mut lu = [[0.0; DIM]; DIM];
    let s = solve_features(pair, sol, &mut lu)?;
    Some(adjoint(&s.sides, &lu, &s.ipiv, s.dim, &s.z, axes, round))
}

/// The outputs' sensitivities by one transposed solve with four right-hand sides.
#[allow(clippy::too_many_arguments)]
fn adjoint(
    sides: &[Side; 2],
    lu: &[[Real; DIM]; DIM],
    ipiv: &[usize; DIM],
    dim: usize,
    z: &[Real; DIM],
    axes: &[[Vec3; 4]; 2],
    round: [bool; 2],
) -> Sensitivity {
    let n = Vec3::new(z[0], z[1], z[2]);
    let mu = z[3];
    // Right-hand sides: e_μ and the rows of ∂a/∂z (a from shape 1's feature).
    let mut y = [[0.0; 4]; DIM];
    y[3][0] = 1.0;
    let s0 = &sides[0];
    let c = s0.col;
    let mut a = Vec3::zeros();
    match s0.feature {
        Feature::Pieces { count, .. } => {
            for k in 0..count {
                let (p, l) = (&s0.pieces[k], z[c + k]);
                a += p.grad * l;
                for i in 0..3 {
                    y[c + k][1 + i] = p.grad[i];
                    for j in 0..3 {
                        y[j][1 + i] += l * p.hess[(i, j)];
                    }
                }
            }
        }
        Feature::Disc { .. } => {
            let l = z[c];
            a = s0.pieces[0].grad * l;
            for i in 0..3 {
                y[c][1 + i] = s0.pieces[0].grad[i];
                y[c + 1][1 + i] = l * s0.tangents[0][i];
                y[c + 2][1 + i] = l * s0.tangents[1][i];
            }
        }
    }
    lu_solve_transposed4(lu, ipiv, dim, &mut y);
    // d(output) = −Yᵀ ∂F/∂p (+ the explicit change of a).
    let apply = |df: &[Real; DIM]| {
        let mut out = [0.0; 4];
        for (row, d) in y[..dim].iter().zip(&df[..dim]) {
            for o in 0..4 {
                out[o] -= row[o] * d;
            }
        }
        out
    };
    let mut dmu_dr = Vec3::zeros();
    let mut da_dr = Mat3::zeros();
    for j in 0..3 {
        let mut df = [0.0; DIM];
        df[j] = -mu;
        df[3] = n[j];
        let o = apply(&df);
        dmu_dr[j] = o[0];
        for i in 0..3 {
            da_dr[(i, j)] = o[1 + i];
        }
    }
    let mut dmu_dtheta = [0.0; 8];
    let mut da_dtheta = [Vec3::zeros(); 8];
    for (i, side) in sides.iter().enumerate() {
        if round[i] {
            continue;
        }
        for k in 0..4 {
            let w = axes[i][k];
            let wn = w.cross(&n);
            let mut df = [0.0; DIM];
            let mut explicit = Vec3::zeros();
            let c = side.col;
            match side.feature {
                Feature::Pieces { count, .. } => {
                    for q in 0..count {
                        let p = &side.pieces[q];
                        let dg = w.cross(&p.grad) - p.hess * wn;
                        explicit += dg * z[c + q];
                        if q > 0 {
                            df[c + q] = -(p.grad - side.pieces[0].grad).dot(&wn);
                        }
                    }
                }
                Feature::Disc { .. } => {
                    explicit = w.cross(&side.pieces[0].grad) * z[c];
                    df[c + 1] = -side.axes[0].dot(&wn);
                    df[c + 2] = -side.axes[1].dot(&wn);
                }
            }
            df[..3].copy_from_slice(explicit.as_slice());
            let o = apply(&df);
            dmu_dtheta[4 * i + k] = o[0];
            let own = if i == 0 { explicit } else { Vec3::zeros() };
            da_dtheta[4 * i + k] = Vec3::new(o[1], o[2], o[3]) + own;
        }
    }
    Sensitivity {
        dmu_dr,
        da_dr,
        dmu_dtheta,
        da_dtheta,
        mu,
        a,
    }
}
