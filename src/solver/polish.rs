//! Newton polish of a ray cast on the contact features it identified, with a certificate.
//!
//! By duality (`docs/maths.md` §1), `1/α' = min { h_K(n) : n·r = 1 }` with
//! `h_K(n) = h₁(n) + h₂(−n)`, and every shape's support function is the maximum of a few
//! smooth pieces (`crate::shapes::SupportMap`). Once the cast has identified which pieces are
//! active (a vertex, an edge's two vertices, a rim, a smooth patch, ...), the optimum solves the
//! smooth KKT system of the epigraph problem
//!
//! ```text
//!     Σ_k λ_k ∇p_k(n) = μ r          (the primal point u − v on the ray: μ = 1/α')
//!     n·r = 1
//!     Σ_{k ∈ shape i} λ_k = 1        (i = 1, 2)
//!     p_k(n) = p_{k₀(i)}(n)          (the active pieces of a shape tie)
//! ```
//!
//! in `(n, μ, λ)`, which Newton's method solves to full precision in a few steps. A flat face
//! (polytope facet, disc, padded polygon side) fixes `n` outright and is tried first.
//!
//! Both routes end in the certificate of §1: `α_lo = 1/h_K(n)` from the full support maps, and
//! `α_hi` from a point of K (a convex combination of the pieces' support points, which lie in
//! the shapes) on or next to the ray. An answer is returned only when the bracket is closed.

use super::dense::{lu_factor_in_place, lu_solve_one};
use super::raycast::{upper_from_point, Cast, Pair};
use crate::math::{Mat3, Real, Vec3};
use crate::shapes::SupportMap;

/// At most this many active pieces per shape.
pub(crate) const MAX_PIECES: usize = 3;
/// Unknowns: n (3), μ, and up to 2·MAX_PIECES multipliers.
pub(crate) const MAX_DIM: usize = 4 + 2 * MAX_PIECES;
/// Newton steps per active set.
const MAX_NEWTON: usize = 10;
/// A full Newton step of this relative size ends the iteration: convergence is quadratic, so
/// the iterate it leads to is within about its square (rounding); the certificate checks.
const CONVERGED_STEP: Real = 1e-8;
/// How far (relative gauge) outside its shape a snapped face point may lie and still count as
/// on the face: rounding in forming it, not a contact beyond the face's rim.
const SNAP_SLACK: Real = 1e-12;

/// A polished answer in the normalised frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Polished {
    pub alpha_lo: Real,
    /// The optimal normal (scaled so that `n·r = 1`).
    pub normal: Vec3,
    /// The point of shape 1 and of shape 2 (relative to their origins, normalised units).
    pub a: Vec3,
    pub b: Vec3,
}

/// One active piece: which shape (0 or 1) and which piece.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Active {
    pub shape: usize,
    pub id: u32,
}

/// A piece evaluated in the normalised world frame as a function of the world normal `n`:
/// shape 1's `p(R₁ᵀn)/ℓ`, shape 2's `p(−R₂ᵀn)/ℓ`.
pub(crate) struct WorldPiece {
    pub value: Real,
    /// Gradient in n: shape 1's point `a`, or minus shape 2's point `−b`.
    pub grad: Vec3,
    pub hess: Mat3,
}

pub(crate) fn eval<S: SupportMap>(pair: &Pair<'_, S>, act: Active, n: &Vec3) -> Option<WorldPiece> {
    let (posed, sign) = pair.side(act.shape);
    let m = posed.rot.tr_mul(n) * sign;
    let e = posed.shape.piece(act.id, &m)?;
    let s = posed.inv_scale;
    Some(WorldPiece {
        value: e.value * s,
        grad: posed.rot * e.grad * (s * sign),
        hess: posed.rot * e.hess * posed.rot.transpose() * s,
    })
}

/// [`eval`]'s gradient alone (the piece's support point in world axes, normalised units), the
/// same numbers without forming the Hessian.
#[inline]
pub(crate) fn point<S: SupportMap>(pair: &Pair<'_, S>, act: Active, n: &Vec3) -> Option<Vec3> {
    let (posed, sign) = pair.side(act.shape);
    let m = posed.rot.tr_mul(n) * sign;
    let (_, g) = posed.shape.piece_point(act.id, &m)?;
    Some(posed.rot * g * (posed.inv_scale * sign))
}

/// The cosine of the largest angle between a cast's normal and a flat face's that the polish
/// tries snapping to.
pub(crate) const SNAP_COS: Real = 1.0 - 1e-3;

/// Tries a flat face of either shape whose normal makes an angle with `normal` of cosine at
/// least `cos_min`: its normal is the exact optimum's if the ray meets K's face there, which the
/// certificate checks.
pub(crate) fn snap_to_face<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    normal: &Vec3,
    cos_min: Real,
    iota: Real,
    rel_tol: Real,
) -> Option<Polished> {
    for shape in 0..2 {
        let (posed, sign) = pair.side(shape);
        let m = posed.rot.tr_mul(normal) * sign;
        let Some(f) = posed.shape.flat_face(&m, cos_min) else {
            continue;
        };
        let n = posed.rot * f * sign;
        let nr = n.dot(r);
        if !(nr > 0.0) {
            continue;
        }
        let v = pair.support(&n);
        let h = v.w.dot(&n);
        let lo = nr / h;
        // The other shape's support point is taken as it is; this shape's point is then the
        // one that puts u − v on the ray, r/α' = u − v. It lies in this shape's face plane; the
        // certificate needs it inside the shape, i.e. inside the face.
        let target = r * (1.0 / lo);
        let (a, b) = if shape == 0 {
            (target + v.b, v.b)
        } else {
            (v.a, v.a - target)
        };
        // Inside the face (to rounding), u − v lies on the ray and in K: the bracket closes
        // exactly, and the face's normal is the optimal one. Outside it, the face's normal is
        // only near the optimum (a contact by the face's rim): α would pass the certificate to
        // second order, but the normal (and with it the gradient) would not; the Newton polish
        // takes those.
        let own = if shape == 0 { a } else { b };
        let g = posed.shape_gauge(&own);
        if !(g <= 1.0 + SNAP_SLACK) {
            continue;
        }
        // Rounding can leave the point a hair outside the face's plane: pull it in (p/g lies
        // in the shape) so that the upper bound stays rigorous.
        let (a, b) = match (g > 1.0, shape) {
            (false, _) => (a, b),
            (true, 0) => (a / g, b),
            (true, _) => (a, b / g),
        };
        let hi = upper_from_point(&(a - b), r, iota);
        if hi - lo <= rel_tol * lo {
            return Some(Polished {
                alpha_lo: lo,
                normal: n / nr,
                a,
                b,
            });
        }
    }
    None
}

/// The polish of a cast: a flat face near the cast's normal (or near the normal of a strictly
/// convex piece at its portal point), else Newton on the KKT system of the pieces active in the
/// portal from each of those normals (dropping a piece whose multiplier turns negative), each
/// ending in the certificate.
pub(crate) fn polish<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    cast: &Cast,
    iota: Real,
    rel_tol: Real,
) -> Option<Polished> {
    // Active pieces and their starting multipliers from the portal's barycentric weights.
    let mut act = [Active { shape: 0, id: 0 }; 2 * MAX_PIECES];
    let mut lam = [0.0; 2 * MAX_PIECES];
    let mut p = 0;
    for j in 0..3 {
        for shape in 0..2 {
            let id = cast.portal[j].id[shape];
            let w = cast.bary[j].max(0.0);
            match act[..p].iter().position(|a| a.shape == shape && a.id == id) {
                Some(k) => lam[k] += w,
                None => {
                    act[p] = Active { shape, id };
                    lam[p] = w;
                    p += 1;
                }
            }
        }
    }
    let alpha0 = 0.5 * (cast.alpha_lo + cast.alpha_hi.min(2.0 * cast.alpha_lo));
    // Starting normals: the cast's best one; then, for a shape whose one active piece is
    // strictly convex (a ball or ellipsoid patch), the normal at its portal point, which is
    // the better start where the other shape's piece is a rim seen almost along its axis (its
    // support point then swings round the rim for small changes of n).
    let mut starts = [None; 3];
    starts[0] = Some(cast.normal);
    let (pa, pb) = cast.points();
    for (shape, point) in [(0, pa), (1, pb)] {
        let (posed, sign) = pair.side(shape);
        let mut ids = act[..p].iter().filter(|a| a.shape == shape);
        if let (Some(only), None) = (ids.next(), ids.next()) {
            let body = posed.rot.tr_mul(&point) / posed.inv_scale;
            if let Some(m) = posed.shape.normal_at(only.id, &body) {
                starts[1 + shape] = Some(posed.rot * m * sign);
            }
        }
    }
    // A flat face near any of those normals fixes the normal outright.
    for start in starts.iter().flatten() {
        if let Some(out) = snap_to_face(pair, r, start, SNAP_COS, iota, rel_tol) {
            return Some(out);
        }
    }
    for start in starts.iter().flatten() {
        if !(start.dot(r) > 0.0) {
            continue;
        }
        let n0 = start / start.dot(r);
        if let Some(out) = from_start(pair, r, n0, 1.0 / alpha0, act, lam, p, iota, rel_tol) {
            return Some(out);
        }
    }
    None
}

/// Newton from `n0`, dropping pieces as their multipliers turn negative, then the certificate.
#[allow(clippy::too_many_arguments)]
fn from_start<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    n0: Vec3,
    mu0: Real,
    mut act: [Active; 2 * MAX_PIECES],
    mut lam: [Real; 2 * MAX_PIECES],
    mut p: usize,
    iota: Real,
    rel_tol: Real,
) -> Option<Polished> {
    for _attempt in 0..4 {
        normalise_multipliers(&act[..p], &mut lam[..p]);
        let mut n = n0;
        let mut mu = mu0;
        let mut l = lam;
        let ok = solve_kkt(pair, r, &act[..p], &mut n, &mut mu, &mut l[..p]);
        if ok {
            // A negative multiplier: that piece is not active at the optimum.
            let (kmin, lmin) = (0..p).fold((0, Real::INFINITY), |acc, k| {
                if l[k] < acc.1 {
                    (k, l[k])
                } else {
                    acc
                }
            });
            if lmin >= -1e-12 {
                return certify(pair, r, &act[..p], &n, &l[..p], iota, rel_tol);
            }
            if !drop_piece(&mut act, &mut lam, &mut p, kmin) {
                return None;
            }
        } else {
            // Singular or not converging: drop the piece with the least weight in the portal
            // from a shape that has more than one.
            let k = (0..p)
                .filter(|&k| act[..p].iter().filter(|a| a.shape == act[k].shape).count() > 1)
                .min_by(|&i, &j| lam[i].total_cmp(&lam[j]))?;
            if !drop_piece(&mut act, &mut lam, &mut p, k) {
                return None;
            }
        }
    }
    None
}

/// Removes piece `k` unless it is its shape's last one.
pub(crate) fn drop_piece(act: &mut [Active], lam: &mut [Real], p: &mut usize, k: usize) -> bool {
    let shape = act[k].shape;
    if act[..*p].iter().filter(|a| a.shape == shape).count() <= 1 {
        return false;
    }
    for i in k..*p - 1 {
        act[i] = act[i + 1];
        lam[i] = lam[i + 1];
    }
    *p -= 1;
    true
}

/// Makes each shape's multipliers sum to one (equal shares where they sum to zero).
pub(crate) fn normalise_multipliers(act: &[Active], lam: &mut [Real]) {
    for shape in 0..2 {
        let (mut sum, mut count) = (0.0, 0);
        for (a, l) in act.iter().zip(lam.iter()) {
            if a.shape == shape {
                sum += *l;
                count += 1;
            }
        }
        for (a, l) in act.iter().zip(lam.iter_mut()) {
            if a.shape == shape {
                *l = if sum > 0.0 {
                    *l / sum
                } else {
                    1.0 / count as Real
                };
            }
        }
    }
}

/// Newton's method on the KKT system, damped by halving the step until the residual
/// decreases (a rim seen almost along its axis moves its support point far for a small change
/// of n, and an undamped step can throw the iterate out of the region where the pieces hold);
/// true when the step converged to rounding.
fn solve_kkt<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    act: &[Active],
    n: &mut Vec3,
    mu: &mut Real,
    lam: &mut [Real],
) -> bool {
    let dim = 4 + act.len();
    let newton = DampedNewton {
        dim,
        multipliers: act.len(),
        converged: CONVERGED_STEP,
        tiny: 1e-15,
        relative: true,
        max_steps: MAX_NEWTON,
    };
    newton.run(
        n,
        mu,
        lam,
        |n, mu, lam, jac, rhs| kkt_system(pair, r, act, n, mu, lam, jac, rhs),
        |jac, rhs| solve_dense(jac, rhs, dim),
    )
}

/// The damped Newton iteration that the ray cast's polish and the GJK polish share, on
/// unknowns `(n, μ, λ)`: each full step is halved until the residual's norm decreases (down to
/// 1/1024), and a full step of size at most `converged` ends it (convergence is quadratic, so
/// the iterate it leads to is within about its square).
pub(crate) struct DampedNewton {
    /// Order of the linear systems (`4 + multipliers`, or 4 when the multipliers are fixed).
    pub dim: usize,
    /// Number of multipliers in `λ`.
    pub multipliers: usize,
    /// The full step size that ends the iteration.
    pub converged: Real,
    /// A residual at most this is converged outright.
    pub tiny: Real,
    /// Whether the step size is relative to `‖n‖` and `|μ|` (else absolute).
    pub relative: bool,
    /// Newton steps allowed.
    pub max_steps: usize,
}

impl DampedNewton {
    /// Runs the iteration. `system` writes the negated residual into `rhs` and its Jacobian into
    /// `jac` at `(n, μ, λ)` and returns the residual's norm (`None`: a piece not differentiable
    /// there); `solve` solves `jac · x = rhs` in place (false: singular). True when converged.
    pub fn run(
        &self,
        n: &mut Vec3,
        mu: &mut Real,
        lam: &mut [Real],
        mut system: impl FnMut(
            &Vec3,
            Real,
            &[Real],
            &mut [[Real; MAX_DIM]; MAX_DIM],
            &mut [Real; MAX_DIM],
        ) -> Option<Real>,
        mut solve: impl FnMut(&mut [[Real; MAX_DIM]; MAX_DIM], &mut [Real; MAX_DIM]) -> bool,
    ) -> bool {
        let p = self.multipliers;
        let mut jac = [[0.0; MAX_DIM]; MAX_DIM];
        let mut rhs = [0.0; MAX_DIM];
        let Some(mut scale) = system(n, *mu, lam, &mut jac, &mut rhs) else {
            return false;
        };
        for _ in 0..self.max_steps {
            if scale <= self.tiny {
                return true;
            }
            if !solve(&mut jac, &mut rhs) {
                return false;
            }
            let dn = Vec3::new(rhs[0], rhs[1], rhs[2]);
            let dmu = rhs[3];
            let mut dl = [0.0; 2 * MAX_PIECES];
            if self.dim > 4 {
                dl[..p].copy_from_slice(&rhs[4..4 + p]);
            }
            let (sn, sm) = if self.relative {
                (n.norm(), mu.abs())
            } else {
                (1.0, 1.0)
            };
            let step = dn.norm() / sn
                + dmu.abs() / sm
                + dl[..p].iter().fold(0.0, |m: Real, v| m.max(v.abs()));
            if !step.is_finite() {
                return false;
            }
            let mut t = 1.0;
            let accepted = loop {
                let nt = *n + dn * t;
                let mut lt = [0.0; 2 * MAX_PIECES];
                for k in 0..p {
                    lt[k] = lam[k] + dl[k] * t;
                }
                let mt = *mu + dmu * t;
                if let Some(st) = system(&nt, mt, &lt[..p], &mut jac, &mut rhs) {
                    if st < scale || (t == 1.0 && step <= self.converged) {
                        *n = nt;
                        *mu = mt;
                        lam.copy_from_slice(&lt[..p]);
                        scale = st;
                        break true;
                    }
                }
                t *= 0.5;
                if t < 1.0 / 1024.0 {
                    break false;
                }
            };
            if !accepted {
                return false;
            }
            if t == 1.0 && step <= self.converged {
                return true;
            }
        }
        false
    }
}

/// The KKT residual (negated, into `rhs`) and its Jacobian at `(n, μ, λ)`; the
/// residual's 1-norm, or `None` where a piece is not differentiable.
#[allow(clippy::too_many_arguments)]
fn kkt_system<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    act: &[Active],
    n: &Vec3,
    mu: Real,
    lam: &[Real],
    jac: &mut [[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> Option<Real> {
    // Σ λ_k g_k − μ r = 0 and n·r − 1 = 0.
    let form = Stationarity {
        hess: Mat3::zeros(),
        mu_column: -r,
        offset: -r * mu,
        last_row: *r,
        last_residual: n.dot(r) - 1.0,
    };
    assemble_kkt(pair, act, n, lam, &form, jac, rhs)
}

/// How the two polishes' KKT systems differ in their first four rows: rows 0..3 are
/// `Σ λ_k ∇p_k(n) + offset = 0` with Jacobian `Σ λ_k H_k + hess` in n and `mu_column` in μ;
/// row 3 is a normalisation of n with gradient `last_row` and residual `last_residual`.
pub(crate) struct Stationarity {
    pub hess: Mat3,
    pub mu_column: Vec3,
    pub offset: Vec3,
    pub last_row: Vec3,
    pub last_residual: Real,
}

/// The residual (negated, into `rhs`) and Jacobian of a polish's KKT system at `(n, μ, λ)` in
/// the form `form`, with the multiplier and tie rows of [`piece_rows`]; the residual's 1-norm,
/// or `None` where a piece is not differentiable.
pub(crate) fn assemble_kkt<S: SupportMap>(
    pair: &Pair<'_, S>,
    act: &[Active],
    n: &Vec3,
    lam: &[Real],
    form: &Stationarity,
    jac: &mut [[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> Option<Real> {
    let p = act.len();
    let mut value = [0.0; 2 * MAX_PIECES];
    let mut grad = [Vec3::zeros(); 2 * MAX_PIECES];
    let mut hsum = form.hess;
    let mut gsum = Vec3::zeros();
    for k in 0..p {
        let e = eval(pair, act[k], n)?;
        value[k] = e.value;
        grad[k] = e.grad;
        hsum += e.hess * lam[k];
        gsum += e.grad * lam[k];
    }
    let dim = 4 + p;
    for row in jac.iter_mut().take(dim) {
        row[..dim].fill(0.0);
    }
    let ra = gsum + form.offset;
    for i in 0..3 {
        for j in 0..3 {
            jac[i][j] = hsum[(i, j)];
        }
        jac[i][3] = form.mu_column[i];
        for k in 0..p {
            jac[i][4 + k] = grad[k][i];
        }
        rhs[i] = -ra[i];
    }
    for j in 0..3 {
        jac[3][j] = form.last_row[j];
    }
    rhs[3] = -form.last_residual;
    let scale = ra.norm() + rhs[3].abs() + piece_rows(act, lam, &value, &grad, jac, rhs)?;
    scale.is_finite().then_some(scale)
}

/// Rows 4.. of both polishes' KKT systems (this one's and the GJK polish's): each shape's
/// multipliers sum to one (the row of its first piece) and its other pieces tie to the first
/// (`p_k(n) = p_first(n)`). Writes the negated residuals and the rows' Jacobian entries; returns
/// the residuals' 1-norm, or `None` when a shape has no piece.
pub(crate) fn piece_rows(
    act: &[Active],
    lam: &[Real],
    value: &[Real],
    grad: &[Vec3],
    jac: &mut [[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> Option<Real> {
    let first = |shape: usize| act.iter().position(|a| a.shape == shape);
    let firsts = [first(0)?, first(1)?];
    let mut scale = 0.0;
    for k in 0..act.len() {
        let row = 4 + k;
        let shape = act[k].shape;
        let f = firsts[shape];
        if k == f {
            let mut sum = 0.0;
            for (i, a) in act.iter().enumerate() {
                if a.shape == shape {
                    jac[row][4 + i] = 1.0;
                    sum += lam[i];
                }
            }
            rhs[row] = -(sum - 1.0);
        } else {
            let g = grad[k] - grad[f];
            for j in 0..3 {
                jac[row][j] = g[j];
            }
            rhs[row] = -(value[k] - value[f]);
        }
        scale += rhs[row].abs();
    }
    Some(scale)
}

/// The certificate of a Newton solution: the full support maps at `n` for the lower bound, the
/// primal point `Σ λ_k ∇p_k` (a point of K when λ ≥ 0) for the upper bound.
pub(crate) fn certify<S: SupportMap>(
    pair: &Pair<'_, S>,
    r: &Vec3,
    act: &[Active],
    n: &Vec3,
    lam: &[Real],
    iota: Real,
    rel_tol: Real,
) -> Option<Polished> {
    let nr = n.dot(r);
    let v = pair.support(n);
    let lo = nr / v.w.dot(n);
    let mut a = Vec3::zeros();
    let mut b = Vec3::zeros();
    let mut sums = [0.0; 2];
    for (k, piece) in act.iter().enumerate() {
        let l = lam[k].max(0.0);
        let g = point(pair, *piece, n)?;
        sums[piece.shape] += l;
        if piece.shape == 0 {
            a += g * l;
        } else {
            b -= g * l;
        }
    }
    if !(sums[0] > 0.0 && sums[1] > 0.0) {
        return None;
    }
    let (a, b) = (a / sums[0], b / sums[1]);
    let hi = upper_from_point(&(a - b), r, iota);
    (lo.is_finite() && hi - lo <= rel_tol * lo).then_some(Polished {
        alpha_lo: lo,
        normal: n / nr,
        a,
        b,
    })
}

/// Solves `A x = b` in place (the first `dim` rows and columns) by Gaussian elimination with
/// partial pivoting; false when a pivot is negligible.
pub(crate) fn solve_dense(
    a: &mut [[Real; MAX_DIM]; MAX_DIM],
    b: &mut [Real; MAX_DIM],
    dim: usize,
) -> bool {
    let mut amax: Real = 0.0;
    for row in a.iter().take(dim) {
        for v in row.iter().take(dim) {
            amax = amax.max(v.abs());
        }
    }
    let Some(ipiv) = lu_factor_in_place(a, dim) else {
        return false;
    };
    // The pivots chosen are the diagonal of U: each must stand clear of rounding.
    let floor = 1e-13 * amax;
    if !(0..dim).all(|k| a[k][k].abs() > floor) {
        return false;
    }
    lu_solve_one(a, &ipiv, dim, b);
    true
}
