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
use super::polish::{Active, WorldPiece};
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

impl Side {
    /// A side with feature `feature`, unknowns from column `col`, not yet evaluated.
    fn new(feature: Feature, col: usize) -> Side {
        Side {
            feature,
            pieces: [zero_piece(), zero_piece(), zero_piece()],
            tangents: [Vec3::zeros(); 2],
            axes: [Vec3::zeros(); 2],
            col,
        }
    }
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
    side: &mut Side,
) -> Option<()> {
    let (posed, sign) = pair.side(shape);
    side.feature = feature;
    match feature {
        Feature::Pieces { ids, count, .. } => {
            for k in 0..count {
                side.pieces[k] = eval_piece(pair, Active { shape, id: ids[k] }, n)?;
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
            side.pieces[0].hess = Mat3::zeros();
            side.tangents = [ey * scale, ez * scale];
            side.axes = [ey, ez];
        }
    }
    Some(())
}

/// `polish::eval` for the feature solve: a piece whose Hessian is exactly zero (a polytope's vertex, a
/// segment's end) skips its rotation into the world frame (two 3×3 products, ~100 instructions a
/// piece): zeros, as the rotated zero matrix is (up to the sign of a zero).
#[inline]
fn eval_piece<S: SupportMap>(pair: &Pair<'_, S>, act: Active, n: &Vec3) -> Option<WorldPiece> {
    let (posed, sign) = pair.side(act.shape);
    let m = posed.rot.tr_mul(n) * sign;
    let e = posed.shape.piece(act.id, &m)?;
    let s = posed.inv_scale;
    // The same expression as `eval`'s where the Hessian is not zero: the same numbers.
    let hess = if e.hess == Mat3::zeros() {
        Mat3::zeros()
    } else {
        posed.rot * e.hess * posed.rot.transpose() * s
    };
    Some(WorldPiece {
        value: e.value * s,
        grad: posed.rot * e.grad * (s * sign),
        hess,
    })
}

/// The residual `F` at the unknowns `z` into `res`; its largest entry.
fn residual(sides: &[Side; 2], r: &Vec3, z: &[Real; DIM], res: &mut [Real; DIM]) -> Real {
    let dim = 4 + sides[0].feature.unknowns() + sides[1].feature.unknowns();
    res.fill(0.0);
    let n = Vec3::new(z[0], z[1], z[2]);
    let mut stat = -r * z[3];
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
                    if k > 0 {
                        res[c + k] = p.value - side.pieces[0].value;
                    }
                }
                res[c] = sum;
            }
            Feature::Disc { .. } => {
                let l = z[c];
                stat += side.pieces[0].grad * l;
                res[c] = l - 1.0;
                for t in 0..2 {
                    res[c + 1 + t] = side.axes[t].dot(&n);
                }
            }
        }
    }
    res[..3].copy_from_slice(stat.as_slice());
    res[..dim].iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

/// The Jacobian of the residual at the unknowns `z` (the full system, for Newton's steps).
fn assemble(sides: &[Side; 2], r: &Vec3, z: &[Real; DIM], jac: &mut [[Real; DIM]; DIM]) {
    for row in jac.iter_mut() {
        row.fill(0.0);
    }
    for i in 0..3 {
        jac[i][3] = -r[i];
        jac[3][i] = r[i];
    }
    for side in sides {
        let c = side.col;
        match side.feature {
            Feature::Pieces { count, .. } => {
                for k in 0..count {
                    let (p, l) = (&side.pieces[k], z[c + k]);
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
                    }
                }
            }
            Feature::Disc { .. } => {
                let l = z[c];
                for i in 0..3 {
                    jac[i][c] = side.pieces[0].grad[i];
                    jac[i][c + 1] = l * side.tangents[0][i];
                    jac[i][c + 2] = l * side.tangents[1][i];
                }
                jac[c][c] = 1.0;
                for t in 0..2 {
                    for j in 0..3 {
                        jac[c + 1 + t][j] = side.axes[t][j];
                    }
                }
            }
        }
    }
}

/// Writes the unknowns `z` back into the features (multipliers, disc coordinates).
fn store(feature: &mut Feature, z: &[Real], col: usize) {
    match feature {
        Feature::Pieces { lam, count, .. } => lam[..*count].copy_from_slice(&z[col..col + *count]),
        Feature::Disc { s, .. } => *s = [z[col + 1], z[col + 2]],
    }
}

/// The features' system solved at the geometric solution: the unknowns there (and, for the
/// tests' full system, the features evaluated); the factorised reduced system ([`Reduced`])
/// goes to the caller's.
struct Solved {
    #[cfg(test)]
    sides: [Side; 2],
    z: [Real; DIM],
}

/// Identifies both shapes' features at `sol` and solves their system by Newton's method from it;
/// `None` where x* is not unique, the features cannot be identified, their system is singular,
/// or the solution leaves the features (a negative multiplier, a point off its disc).
fn solve_features<S: SupportMap>(
    pair: &Pair<'_, S>,
    sol: &Solution,
    reduced: &mut Reduced,
) -> Option<Solved> {
    let feats = identify(pair, sol)?;
    newton(pair, &sol.r, feats, &sol.normal, sol.mu, reduced)
}

/// Newton's method on the system of the features `feats` from the normal `normal` (`n·r = 1`)
/// and `mu`, at most [`NEWTON`] steps; `None` as for [`solve_features`]. The full system is
/// formed and factorised only for a step: at a converged point the reduced one decides.
fn newton<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    mut feats: [Feature; 2],
    normal: &Vec3,
    mu: Real,
    reduced: &mut Reduced,
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
    let mut sides = [Side::new(feats[0], cols[0]), Side::new(feats[1], cols[1])];
    loop {
        let n = Vec3::new(z[0], z[1], z[2]);
        for (i, side) in sides.iter_mut().enumerate() {
            evaluate(pair, i, feats[i], &n, side)?;
        }
        let worst = residual(&sides, &r, &z, &mut res);
        if !worst.is_finite() {
            return None;
        }
        if worst <= CONVERGED || step == NEWTON {
            if !(worst <= MAX_RESIDUAL) {
                return None;
            }
            break;
        }
        let mut lu = [[0.0; DIM]; DIM];
        assemble(&sides, &r, &z, &mut lu);
        let ipiv = lu_factor_in_place(&mut lu, dim)?;
        lu_solve_one(&lu, &ipiv, dim, &mut res);
        for i in 0..dim {
            z[i] -= res[i];
        }
        for (f, &c) in feats.iter_mut().zip(&cols) {
            store(f, &z, c);
        }
        step += 1;
    }
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
    reduced.build(&sides, &r, &z)?;
    Some(Solved {
        #[cfg(test)]
        sides,
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

/// The weighted Hessian `Σ λ_k H_k` of one side's feature (a disc's is zero).
fn side_hessian(side: &Side, z: &[Real; DIM]) -> Mat3 {
    let c = side.col;
    match side.feature {
        Feature::Pieces { count, .. } => {
            (0..count).fold(Mat3::zeros(), |acc, k| acc + side.pieces[k].hess * z[c + k])
        }
        Feature::Disc { .. } => Mat3::zeros(),
    }
}

/// The geometric solution refined on its contact features: the normal (`n·r = 1`), `μ`, and
/// the points `a` and `b`; `None` as for [`sensitivity`]. The caller certifies it.
pub(crate) fn refine<S: SupportMap>(pair: &Pair<'_, S>, sol: &Solution) -> Option<Solution> {
    let mut reduced = Reduced::EMPTY;
    let s = solve_features(pair, sol, &mut reduced)?;
    Some(Solution {
        r: sol.r,
        normal: Vec3::new(s.z[0], s.z[1], s.z[2]),
        mu: s.z[3],
        a: reduced.point[0],
        b: -reduced.point[1],
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
    let mut reduced = Reduced::EMPTY;
    let _s = solve_features(pair, sol, &mut reduced)?;
    #[cfg(test)]
    if dense_reference::DENSE.with(|d| d.get()) {
        return dense_reference::adjoint(&_s.sides, &sol.r, &_s.z, axes, round);
    }
    Some(reduced.adjoint(axes, round))
}

/// Order of the reduced system: n, μ and at most two coordinates along the features.
const RED: usize = 6;

/// The features' system with the multipliers' sums eliminated, factorised.
///
/// The linearised system in (δn, δμ, δλ, δs) has the rows `Σ_k δλ_k = 0` (a side of pieces) and
/// `δλ = 0` (a disc's multiplier) for every right-hand side the derivatives need, so
/// `δλ₀ = −Σ_{k≥1} δλ_k` and a disc's δλ drop out exactly: the unknowns left are δn, δμ and one
/// coordinate `t_x` per feature direction, a segment's or triangle's edge `G_k − G₀` (`k ≥ 1`)
/// or a disc's tangent, at most two in all (x* unique). The system is
///
/// ```text
///     [ H   −r  C ] [δn]   [f]
///     [ rᵀ   0  0 ] [δμ] = [g₀]      H = Σ_k λ_k H_k (both sides), C the directions' columns
///     [ Rᵀ   0  0 ] [t ]   [g ]      (a disc's: λ·tangent), R their rows (a disc's: its axes)
/// ```
///
/// of order at most six (the full one's is up to ten), factorised once. The outputs μ and
/// `a = Σ_{k ∈ shape 1} λ_k G_k` change by `δμ` and `δa = H₁δn + C₁t` (`H₁`, `C₁` shape 1's
/// part), so one transposed solve with four right-hand sides gives their adjoint `Y`, and each
/// parameter's column is `−Yᵀ ∂F/∂p`. Those are structured: a translation of the ray changes
/// only the stationarity rows (by `−μ e_j`) and the ray row (by `n_j`); a rotation `ω` of shape
/// i changes the stationarity rows by `ω × a_i − H_i(ω × n)` and shape i's direction rows by
/// `−R_x·(ω × n)`, so its effect on each output is `ω·q` with one vector
/// `q = n × (H_i y + Σ_x y_x R_x) − a_i × y` per output and shape (`y` the output's adjoint on
/// the stationarity rows).
struct Reduced {
    lu: [[Real; RED]; RED],
    ipiv: [usize; RED],
    /// The system's order (4 + the directions).
    order: usize,
    /// Each direction's column `C_x`, row `R_x` and side.
    cols: [Vec3; 2],
    rows: [Vec3; 2],
    side_of: [usize; 2],
    /// Each side's point `Σ λ_k G_k` and weighted Hessian `Σ λ_k H_k`.
    point: [Vec3; 2],
    hess: [Mat3; 2],
    /// The normal (`n·r = 1`) and μ.
    n: Vec3,
    mu: Real,
}

impl Reduced {
    /// Not built yet.
    const EMPTY: Reduced = Reduced {
        lu: [[0.0; RED]; RED],
        ipiv: [0; RED],
        order: 0,
        cols: [Vec3::new(0.0, 0.0, 0.0); 2],
        rows: [Vec3::new(0.0, 0.0, 0.0); 2],
        side_of: [0; 2],
        point: [Vec3::new(0.0, 0.0, 0.0); 2],
        hess: [Mat3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0); 2],
        n: Vec3::new(0.0, 0.0, 0.0),
        mu: 0.0,
    };

    /// Builds the reduced system of `sides` at the unknowns `z` and factorises it; `None` where
    /// it is singular (a pivot below 1e-14 of its largest entry).
    fn build(&mut self, sides: &[Side; 2], r: &Vec3, z: &[Real; DIM]) -> Option<()> {
        let (cols, rows, side_of) = (&mut self.cols, &mut self.rows, &mut self.side_of);
        let mut extra = 0;
        for (i, side) in sides.iter().enumerate() {
            match side.feature {
                Feature::Pieces { count, .. } => {
                    for k in 1..count {
                        if extra == 2 {
                            return None;
                        }
                        let e = side.pieces[k].grad - side.pieces[0].grad;
                        (cols[extra], rows[extra], side_of[extra]) = (e, e, i);
                        extra += 1;
                    }
                }
                Feature::Disc { .. } => {
                    let l = z[side.col];
                    for t in 0..2 {
                        if extra == 2 {
                            return None;
                        }
                        cols[extra] = side.tangents[t] * l;
                        rows[extra] = side.axes[t];
                        side_of[extra] = i;
                        extra += 1;
                    }
                }
            }
        }
        self.point = [side_point(&sides[0], z), side_point(&sides[1], z)];
        self.hess = [side_hessian(&sides[0], z), side_hessian(&sides[1], z)];
        let h = self.hess[0] + self.hess[1];
        #[cfg(test)]
        dense_reference::LARGEST_HESSIAN.with(|c| c.set(h.amax()));
        let order = 4 + extra;
        let lu = &mut self.lu;
        for row in lu.iter_mut() {
            row.fill(0.0);
        }
        for i in 0..3 {
            for j in 0..3 {
                lu[i][j] = h[(i, j)];
            }
            lu[i][3] = -r[i];
            lu[3][i] = r[i];
            for x in 0..extra {
                lu[i][4 + x] = self.cols[x][i];
                lu[4 + x][i] = self.rows[x][i];
            }
        }
        // The order as a constant in each arm: the inlined factorisation's loops are unrolled
        // for it (the same operations in the same order as with a variable order).
        self.ipiv = match order {
            4 => lu_factor_in_place(lu, 4),
            5 => lu_factor_in_place(lu, 5),
            _ => lu_factor_in_place(lu, RED),
        }?;
        self.order = order;
        self.n = Vec3::new(z[0], z[1], z[2]);
        self.mu = z[3];
        Some(())
    }

    /// The outputs' sensitivities (see [`Reduced`]).
    fn adjoint(&self, axes: &[[Vec3; 4]; 2], round: [bool; 2]) -> Sensitivity {
        // The order as a constant in each arm: the inlined loops over the directions and the
        // solve are unrolled for it (the same operations in the same order).
        match self.order {
            4 => self.adjoint_of_order(axes, round, 4),
            5 => self.adjoint_of_order(axes, round, 5),
            _ => self.adjoint_of_order(axes, round, RED),
        }
    }

    /// [`Reduced::adjoint`] for the system's order `order`.
    #[inline(always)]
    fn adjoint_of_order(
        &self,
        axes: &[[Vec3; 4]; 2],
        round: [bool; 2],
        order: usize,
    ) -> Sensitivity {
        let (n, mu) = (self.n, self.mu);
        let extra = order - 4;
        // Right-hand sides: e_μ and the rows of δa = H₁δn + C₁t.
        let mut y = [[0.0; 4]; RED];
        y[3][0] = 1.0;
        for j in 0..3 {
            for i in 0..3 {
                y[j][1 + i] = self.hess[0][(i, j)];
            }
        }
        for x in 0..extra {
            if self.side_of[x] == 0 {
                // Shape 1's column: its edge, or a disc's scaled tangent (C₁).
                let c = self.cols[x];
                for i in 0..3 {
                    y[4 + x][1 + i] = c[i];
                }
            }
        }
        lu_solve_transposed4(&self.lu, &self.ipiv, order, &mut y);
        // Translations of the ray: ∂F/∂r_j is −μ on stationarity row j and n_j on the ray row.
        let mut dmu_dr = Vec3::zeros();
        let mut da_dr = Mat3::zeros();
        for j in 0..3 {
            let o = |k: usize| mu * y[j][k] - n[j] * y[3][k];
            dmu_dr[j] = o(0);
            for i in 0..3 {
                da_dr[(i, j)] = o(1 + i);
            }
        }
        let mut dmu_dtheta = [0.0; 8];
        let mut da_dtheta = [Vec3::zeros(); 8];
        for i in 0..2 {
            if round[i] {
                continue;
            }
            // Each output's change along a rotation axis ω of shape i is ω·q.
            let a = self.point[i];
            let mut q = [Vec3::zeros(); 4];
            for (o, qo) in q.iter_mut().enumerate() {
                let ys = Vec3::new(y[0][o], y[1][o], y[2][o]);
                let mut v = self.hess[i] * ys;
                for x in 0..extra {
                    if self.side_of[x] == i {
                        v += self.rows[x] * y[4 + x][o];
                    }
                }
                *qo = n.cross(&v) - a.cross(&ys);
            }
            for k in 0..4 {
                let w = axes[i][k];
                dmu_dtheta[4 * i + k] = w.dot(&q[0]);
                let mut da = Vec3::new(w.dot(&q[1]), w.dot(&q[2]), w.dot(&q[3]));
                if i == 0 {
                    // Shape 1's point moves with its shape: ω × a − H₁(ω × n).
                    da += w.cross(&a) - self.hess[0] * w.cross(&n);
                }
                da_dtheta[4 * i + k] = da;
            }
        }
        Sensitivity {
            dmu_dr,
            da_dr,
            dmu_dtheta,
            da_dtheta,
            mu,
            a: self.point[0],
        }
    }
}

#[cfg(test)]
#[path = "sensitivity_dense.rs"]
pub(crate) mod dense_reference;
