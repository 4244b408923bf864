//! Derivatives of the proximity solution with respect to both poses.
//!
//! In solver coordinates (lengths over ℓ, a fixed origin), shape i's rows are
//! `s = f_u·Qᵢᵀ(ξ − cᵢ) + f_α α + f_w·w` with `cᵢ = (rᵢ − o)/ℓ`, so with `a = Qᵢ f_u` (= −the
//! row's x-part of `G`) and `eᵢ = ξ − cᵢ = (x* − rᵢ)/ℓ`:
//! - `∂(Gz − h)/∂rᵢ = a/ℓ` (only `h = −a·cᵢ` moves), and `∂(Gz − h)/∂q_k = −(M_k a)·eᵢ` with
//!   `M_k = (∂Q/∂q_k) Qᵀ` (through the quaternion normalisation);
//! - the gradient of α is `λᵀ ∂(Gz − h)/∂θ` (envelope theorem on the Lagrangian), which per shape
//!   collapses to `∂α/∂rᵢ = vᵢ/ℓ` and `∂α/∂q_k = −eᵢᵀ M_k vᵢ` with `vᵢ = Σ λ a` over its rows;
//! - the Jacobian of `(x*, α*)` solves the implicit-function system of the KKT conditions with
//!   the complementarity linearised as `λ∘ds + s∘dλ = 0` (so `dλ = −D ds`, `D = L(s)⁻¹L(λ)` at
//!   the final iterate): `GᵀDG dz = −dGᵀλ − GᵀD (dG z − dh)`, reusing the LU factor of `GᵀDG`
//!   that the solver's final Newton polish already computed. (The NT-scaled form `Gᵀ W⁻² G`
//!   loses the tangential information in rounding once μ is small.)
//!
//! The solver works with the offset stretched by `t = κℓ/‖r₂ − r₁‖`; its primal iterate is `t`
//! times the physical one, its multipliers are the physical ones, and its normal matrix is the
//! `D` is invariant (L(ts)⁻¹L(λ) = L(s)⁻¹L(λ)/t … times t in GᵀDG on the physical scale), so
//! the physical system is the solver's `GᵀD'G dz = −dGᵀλ/t − GᵀD'ρ` with `D' = D/t`.

use super::proximity::{query, Context, Full, Options, Proximity, Want};
use crate::error::Error;
use crate::math::{rotation_derivatives, Mat3, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape};
use crate::solver::{Outcome, Problem};

/// Below this largest quaternion component (below 1e-150), derivatives with respect to q (which scale like
/// 1/‖q‖) may overflow a double.
const TINY_QUATERNION: Real = 1e-150;

/// When derivatives came out non-finite because a quaternion is so small that they overflow
/// (they scale like 1/‖q‖), the answer is a clear InvalidPose naming that quaternion instead
/// of a NaN or an infinity.
pub(crate) fn check_representable(
    derivatives_finite: bool,
    pose1: &Pose,
    pose2: &Pose,
) -> Result<(), Error> {
    if derivatives_finite {
        return Ok(());
    }
    for pose in [pose1, pose2] {
        let m = pose
            .quaternion()
            .iter()
            .fold(0.0, |a: Real, v| a.max(v.abs()));
        if m < TINY_QUATERNION {
            return Err(Error::InvalidPose(crate::error::ErrorDetail::new(
                "quaternion",
                m,
                "is so small that derivatives with respect to it (which scale like 1/|q|) \
                 overflow a double",
            )));
        }
    }
    Ok(())
}

/// Row ranges of one shape inside the stacked problem.
pub(crate) struct Rows {
    pub lp: std::ops::Range<usize>,
    pub soc: Option<usize>,
}

pub(crate) fn row_ranges(s1: &Shape, s2: &Shape) -> [Rows; 2] {
    let m1 = s1.lp_count();
    let m2 = s2.lp_count();
    let k1 = s1.soc_count();
    [
        Rows {
            lp: 0..m1,
            soc: (k1 == 1).then_some(0),
        },
        Rows {
            lp: m1..m1 + m2,
            soc: (s2.soc_count() == 1).then_some(k1),
        },
    ]
}

#[inline]
fn gx<const N: usize>(g: &[Real; N]) -> Vec3 {
    Vec3::new(-g[0], -g[1], -g[2])
}

/// `M_k = (∂Q/∂q_k) Qᵀ` for k = 0..3.
pub(crate) fn rotation_generators(pose: &Pose) -> [Mat3; 4] {
    let d = rotation_derivatives(pose.quaternion());
    let qt = pose.rotation().transpose();
    [d[0] * qt, d[1] * qt, d[2] * qt, d[3] * qt]
}

/// Fills `full.gradient` (and `full.jacobian` when asked) from a solved problem.
pub(crate) fn compute<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    want: Want,
    full: &mut Full,
) {
    let frame = &ctx.frame;
    let ell = frame.ell;
    let t = 1.0 / frame.point_factor() * ell; // κℓ/dist: solver = t · physical (ξ, α, w)
    let z = &outcome.z;
    let xi = Vec3::new(z[0], z[1], z[2]) / t;
    let e = [xi, xi - frame.delta / t];
    let gens = [
        rotation_generators(ctx.pose1),
        rotation_generators(ctx.pose2),
    ];
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    // vᵢ = Σ λ̄ a over shape i's rows, with the polished multipliers λ̄.
    let mut v = [Vec3::zeros(); 2];
    for (i, r) in ranges.iter().enumerate() {
        for row in &problem.lp[r.lp.clone()] {
            v[i] += gx(&row.g) * row.lam_polished;
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            for (gr, l) in b.g.iter().zip(b.lam_polished.iter()) {
                v[i] += gx(gr) * *l;
            }
        }
    }
    let mut grad = [0.0; 14];
    for i in 0..2 {
        let base = 7 * i;
        for j in 0..3 {
            grad[base + j] = v[i][j] / ell;
        }
        for k in 0..4 {
            grad[base + 3 + k] = -e[i].dot(&(gens[i][k] * v[i]));
        }
    }
    full.gradient = grad;
    if want < Want::Jacobian {
        return;
    }
    if !exact_jacobian(ctx, problem, outcome, &ranges, &gens, &e, &v, t, full)
        || !consistent(&full.jacobian, &full.gradient, ell)
    {
        smoothed_jacobian(problem, &ranges, &gens, &e, &v, t, ell, full);
    }
}

/// Identities every correct Jacobian satisfies, checked before the active-set one is trusted (a
/// misidentified active set, e.g. a facet whose multiplier and slack are both ~1e-5 at the
/// default tolerance, can leave a nearly singular system that still factors): a common
/// translation moves x* with it and leaves α* alone (`J[:, r₁] + J[:, r₂] = [I₃; 0]`), and the
/// α row equals the Lagrangian gradient. Tolerances are in non-dimensional units (r columns
/// times ℓ, x rows over ℓ), far looser than either computation's error and far tighter than
/// any failure seen.
fn consistent(j: &[[Real; 14]; 4], grad: &[Real; 14], ell: Real) -> bool {
    const TOL: Real = 1e-5;
    for c in 0..3 {
        for r in 0..3 {
            let want = if r == c { 1.0 } else { 0.0 };
            if !((j[r][c] + j[r][7 + c] - want).abs() <= TOL) {
                return false;
            }
        }
        if !((j[3][c] + j[3][7 + c]).abs() * ell <= TOL) {
            return false;
        }
    }
    for c in 0..14 {
        let k = if c % 7 < 3 { ell } else { 1.0 };
        let (a, b) = (j[3][c] * k, grad[c] * k);
        if !((a - b).abs() <= TOL * b.abs().max(1.0)) {
            return false;
        }
    }
    true
}

/// ρ = ∂(gᵀz − h)/∂θ for one row of shape `i` and pose parameter `p` (0..3 position, 3..7
/// quaternion): `a_p/ℓ` for a position, `−(M_k a)·eᵢ` for a quaternion.
#[inline]
fn rho_of<const N: usize>(g: &[Real; N], p: usize, gen: &[Mat3; 4], e: &Vec3, ell: Real) -> Real {
    let a = gx(g);
    if p < 3 {
        a[p] / ell
    } else {
        -(gen[p - 3] * a).dot(e)
    }
}

/// Largest order of the active-set system.
const MAX_ACTIVE: usize = 24;

/// `−δ` on the diagonal of each equality row's own multiplier: when more constraints are
/// active than the dimension needs (a polytope vertex where four or more facets meet), the
/// multipliers are not unique and the unregularised system is singular although `dz` is
/// unique; the regularisation picks small multipliers and moves `dz` by O(δ).
const DUAL_REGULARISATION: Real = 1e-12;

/// The exact (non-smoothed) Jacobian on the identified active set at the polished solution:
/// unknowns `[dz, dλ of active orthant rows, dλ of active cones]`, equations `Gᵀdλ = −dGᵀλ̄`,
/// `gᵀdz = −ρ` for active rows (and cones whose slack is at the apex), and
/// `−L(λ̄)G dz + L(s̄)dλ = L(λ̄)ρ` for cones active on their boundary. Returns false (leaving
/// `full` alone) when the active set is degenerate: a singular or oversized system.
#[allow(clippy::too_many_arguments)]
fn exact_jacobian<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    ranges: &[Rows; 2],
    gens: &[[Mat3; 4]; 2],
    e: &[Vec3; 2],
    v: &[Vec3; 2],
    t: Real,
    full: &mut Full,
) -> bool {
    if problem.aho.is_none() {
        return false; // the polish was not accepted: no reliable solution point
    }
    let ell = ctx.frame.ell;
    let z = &outcome.z;
    // Physical z̄ = z/t; slacks s̄ = h − G z̄ scale the same way, multipliers do not.
    let mut a = [[0.0; MAX_ACTIVE]; MAX_ACTIVE];
    let mut order = N;
    // Columns for multipliers: (shape index, row kind) recorded to build right-hand sides.
    #[derive(Clone, Copy)]
    enum Eq {
        Lp(usize),              // active orthant row: g dz = −ρ
        SocApex(usize, usize),  // cone k, component r: g_r dz = −ρ_r
        SocPad(usize),          // padded component of cone k at the apex: dλ₃ = 0
        SocBound(usize, usize), // cone k, component r of −L(λ̄)G dz + L(s̄)dλ = L(λ̄)ρ
    }
    let mut eqs = [Eq::Lp(0); MAX_ACTIVE];
    let mut n_eq = 0usize;
    let mut shape_of_eq = [0usize; MAX_ACTIVE];
    for (i, r) in ranges.iter().enumerate() {
        for j in r.lp.clone() {
            let row = &problem.lp[j];
            if row.lam > row.s {
                if order >= MAX_ACTIVE {
                    return false;
                }
                // column `order` = dλ_j; stationarity gets g_j in that column
                for q in 0..N {
                    a[q][order] = row.g[q];
                }
                eqs[n_eq] = Eq::Lp(j);
                shape_of_eq[n_eq] = i;
                n_eq += 1;
                order += 1;
            }
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            if b.lam[0] < 1e-6 * b.s[0] {
                continue; // inactive cone: dλ = 0
            }
            if order + 4 > MAX_ACTIVE {
                return false;
            }
            let apex = b.s[0] < 1e-6 * b.lam[0];
            let padded = b.g[3].iter().all(|v| *v == 0.0) && b.h[3] == 0.0;
            for c in 0..4 {
                for q in 0..N {
                    a[q][order + c] = b.g[c][q];
                }
                eqs[n_eq] = if apex {
                    if c == 3 && padded {
                        Eq::SocPad(k)
                    } else {
                        Eq::SocApex(k, c)
                    }
                } else {
                    Eq::SocBound(k, c)
                };
                shape_of_eq[n_eq] = i;
                n_eq += 1;
            }
            order += 4;
        }
    }
    debug_assert_eq!(order, N + n_eq);
    // Rows N.. of the matrix: one per equation in `eqs`. Multiplier columns start at N in the
    // same order as the equations.
    let mut lam_col = N;
    let mut soc_first_col = [0usize; crate::solver::MAX_SOC];
    for (qi, eq) in eqs[..n_eq].iter().enumerate() {
        let row_idx = N + qi;
        match *eq {
            Eq::Lp(j) => {
                for q in 0..N {
                    a[row_idx][q] = problem.lp[j].g[q];
                }
                a[row_idx][lam_col] = -DUAL_REGULARISATION;
                lam_col += 1;
            }
            Eq::SocApex(k, c) => {
                if c == 0 {
                    soc_first_col[k] = lam_col;
                }
                for q in 0..N {
                    a[row_idx][q] = problem.soc[k].g[c][q];
                }
                a[row_idx][lam_col] = -DUAL_REGULARISATION;
                lam_col += 1;
            }
            Eq::SocPad(k) => {
                a[row_idx][soc_first_col[k] + 3] = 1.0;
                lam_col += 1;
            }
            Eq::SocBound(k, c) => {
                if c == 0 {
                    soc_first_col[k] = lam_col;
                }
                let b = &problem.soc[k];
                // s̄ = (h − G z)/t on the physical scale (the polished point, on the boundary).
                let gz = [0, 1, 2, 3].map(|r| {
                    let mut acc = 0.0;
                    for q in 0..N {
                        acc += b.g[r][q] * z[q];
                    }
                    (b.h[r] - acc) / t
                });
                let l = b.lam_polished;
                // L(λ̄) row c and L(s̄) row c.
                let lrow = |u: &[Real; 4], c: usize| -> [Real; 4] {
                    if c == 0 {
                        *u
                    } else {
                        let mut r = [0.0; 4];
                        r[0] = u[c];
                        r[c] = u[0];
                        r
                    }
                };
                let ll = lrow(&l, c);
                let ls = lrow(&gz, c);
                for q in 0..N {
                    let mut acc = 0.0;
                    for r in 0..4 {
                        acc += ll[r] * b.g[r][q];
                    }
                    a[row_idx][q] = -acc;
                }
                let first = soc_first_col[k];
                a[row_idx][first..first + 4].copy_from_slice(&ls);
                lam_col += 1;
            }
        }
    }
    let perm = match lu_factor_in_place(&mut a, order) {
        Some(p) => p,
        None => return false,
    };
    // All 14 right-hand sides at once: b[row][col].
    let mut b = [[0.0; 14]; MAX_ACTIVE];
    for col in 0..14 {
        let i = col / 7;
        let p = col % 7;
        let mut rv = [0.0; 4];
        if p >= 3 {
            let dgl = -(gens[i][p - 3] * v[i]);
            for j in 0..3 {
                b[j][col] = -dgl[j];
            }
        }
        for (qi, eq) in eqs[..n_eq].iter().enumerate() {
            if shape_of_eq[qi] != i {
                continue;
            }
            b[N + qi][col] = match *eq {
                Eq::Lp(j) => -rho_of(&problem.lp[j].g, p, &gens[i], &e[i], ell),
                Eq::SocApex(k, c) => -rho_of(&problem.soc[k].g[c], p, &gens[i], &e[i], ell),
                Eq::SocPad(_) => 0.0,
                Eq::SocBound(k, c) => {
                    let bk = &problem.soc[k];
                    if c == 0 {
                        // ρ of the whole cone, computed once per column (components follow).
                        rv = [0, 1, 2, 3].map(|r| rho_of(&bk.g[r], p, &gens[i], &e[i], ell));
                    }
                    let l = bk.lam_polished;
                    if c == 0 {
                        l[0] * rv[0] + l[1] * rv[1] + l[2] * rv[2] + l[3] * rv[3]
                    } else {
                        l[c] * rv[0] + l[0] * rv[c]
                    }
                }
            };
        }
    }
    lu_solve_multi(&a, &perm, order, &mut b);
    let mut finite = true;
    for row in &b[..order] {
        for v in row {
            finite &= v.is_finite();
        }
    }
    if !finite {
        return false;
    }
    let mut jac = [[0.0; 14]; 4];
    for col in 0..14 {
        for j in 0..3 {
            jac[j][col] = b[j][col] * ell;
        }
        jac[3][col] = b[3][col];
    }
    full.jacobian = jac;
    true
}

/// LU with partial pivoting, in place, of the leading `n×n` block of `a`; returns the pivot
/// row chosen at each step (LAPACK's `ipiv`), or `None` when a pivot is below 1e-14 of the
/// largest entry (a degenerate active set).
fn lu_factor_in_place(
    a: &mut [[Real; MAX_ACTIVE]; MAX_ACTIVE],
    n: usize,
) -> Option<[usize; MAX_ACTIVE]> {
    let mut ipiv = [0usize; MAX_ACTIVE];
    let mut big: Real = 0.0;
    for i in 0..n {
        for j in 0..n {
            big = big.max(a[i][j].abs());
        }
    }
    if !(big > 0.0) || !big.is_finite() {
        return None;
    }
    for k in 0..n {
        let mut p = k;
        for i in (k + 1)..n {
            if a[i][k].abs() > a[p][k].abs() {
                p = i;
            }
        }
        let piv = a[p][k];
        if !(piv.abs() > 1e-14 * big) {
            return None;
        }
        a.swap(k, p);
        ipiv[k] = p;
        let pivot_row = a[k];
        for i in (k + 1)..n {
            let f = a[i][k] / piv;
            a[i][k] = f;
            if f == 0.0 {
                continue;
            }
            for j in (k + 1)..n {
                a[i][j] -= f * pivot_row[j];
            }
        }
    }
    Some(ipiv)
}

/// Solves `A X = B` in place for all 14 columns of `b` with the factor from
/// [`lu_factor_in_place`] (row operations on 14-wide rows).
fn lu_solve_multi(
    a: &[[Real; MAX_ACTIVE]; MAX_ACTIVE],
    ipiv: &[usize; MAX_ACTIVE],
    n: usize,
    b: &mut [[Real; 14]; MAX_ACTIVE],
) {
    for k in 0..n {
        b.swap(k, ipiv[k]);
    }
    for i in 0..n {
        let (done, rest) = b.split_at_mut(i);
        let bi = &mut rest[0];
        for (k, bk) in done.iter().enumerate() {
            let l = a[i][k];
            if l == 0.0 {
                continue;
            }
            for c in 0..14 {
                bi[c] -= l * bk[c];
            }
        }
    }
    for i in (0..n).rev() {
        let (head, tail) = b.split_at_mut(i + 1);
        let bi = &mut head[i];
        for (k, bk) in tail.iter().enumerate().take(n - i - 1) {
            let u = a[i][i + 1 + k];
            if u == 0.0 {
                continue;
            }
            for c in 0..14 {
                bi[c] -= u * bk[c];
            }
        }
        let inv = 1.0 / a[i][i];
        for v in bi.iter_mut() {
            *v *= inv;
        }
    }
}

/// The barrier-smoothed Jacobian: the implicit-function system at the final interior iterate,
/// `GᵀDG dz = −dGᵀλ − GᵀDρ` with `D = L(s)⁻¹L(λ)` (the LU of `GᵀDG` from the polish), used when
/// the active set is degenerate. It is the derivative of the central-path point, which smooths
/// the kinks of α* at edges and corners and approaches the exact one as the tolerance shrinks.
#[allow(clippy::too_many_arguments)]
fn smoothed_jacobian<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    gens: &[[Mat3; 4]; 2],
    e: &[Vec3; 2],
    v: &[Vec3; 2],
    t: Real,
    ell: Real,
    full: &mut Full,
) {
    let lu = match problem.aho {
        Some(lu) => lu,
        None => match aho_at_iterate(problem) {
            Some(lu) => lu,
            None => {
                full.prox.status = crate::solver::SolveStatus::NumericalFailure;
                return;
            }
        },
    };
    for col in 0..14 {
        let i = col / 7;
        let p = col % 7;
        let r = &ranges[i];
        let mut rhs = [0.0; N];
        let rho = |g: &[Real; N]| rho_of(g, p, &gens[i], &e[i], ell);
        if p >= 3 {
            // dG only touches the x-columns: x-part of G = −a, d(−a)/dq_k = −M_k a, so
            // dGᵀλ = −M_k vᵢ in the x-columns.
            let dgl = -(gens[i][p - 3] * v[i]);
            for j in 0..3 {
                rhs[j] -= dgl[j] / t;
            }
        }
        for row in &problem.lp[r.lp.clone()] {
            let w = row.lam / row.s * rho(&row.g);
            for j in 0..N {
                rhs[j] -= row.g[j] * w;
            }
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            let rv = [rho(&b.g[0]), rho(&b.g[1]), rho(&b.g[2]), rho(&b.g[3])];
            let w = problem.soc_d(k, &rv);
            for (gr, wr) in b.g.iter().zip(w.iter()) {
                for j in 0..N {
                    rhs[j] -= gr[j] * wr;
                }
            }
        }
        let x = lu.solve(&rhs);
        for j in 0..3 {
            full.jacobian[j][col] = x[j] * ell;
        }
        full.jacobian[3][col] = x[3];
    }
}

/// The LU of `GᵀDG` at the current iterate when the polish did not store one.
fn aho_at_iterate<const N: usize>(problem: &Problem<'_, N>) -> Option<crate::solver::kkt::Lu<N>> {
    problem
        .aho_matrix()
        .and_then(crate::solver::kkt::Lu::factor)
}

/// Derivatives at exactly coincident origins, where α* = 0 is not differentiable (α* is the
/// gauge of S₁ − S₂ at r₂ − r₁, homogeneous of degree one): zero is a valid subgradient of α*
/// and the rotation derivatives are exactly zero; the x rows of the Jacobian are left zero.
pub(crate) fn coincident(full: &mut Full) {
    full.gradient = [0.0; 14];
    full.jacobian = [[0.0; 14]; 4];
}

/// ∂α*/∂(r₁, q₁, r₂, q₂): 14 numbers, `q` as given (through the normalisation), from the
/// Lagrangian at the primal-dual solution. Costs little beyond [`super::proximity`].
///
/// ```
/// use dcol::{gradient, Options, Pose, Shape};
/// let a = Shape::sphere(1.0).unwrap();
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([4.0, 0.0, 0.0]).unwrap();
/// let (prox, g) = gradient(&a, &pa, &a, &pb, &Options::default()).unwrap();
/// // α = ‖r₂ − r₁‖/2, so ∂α/∂r₂ = (1/2, 0, 0) and ∂α/∂r₁ = −(1/2, 0, 0).
/// assert!((prox.alpha - 2.0).abs() < 1e-9);
/// assert!((g[7] - 0.5).abs() < 1e-8 && (g[0] + 0.5).abs() < 1e-8);
/// ```
pub fn gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [Real; 14]), Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Gradient)?;
    Ok((f.prox, f.gradient))
}

/// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂): 4×14, rows (x₁, x₂, x₃, α), by the implicit function theorem
/// on the KKT conditions, reusing the solver's final scaling and factorisation.
pub fn jacobian(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [[Real; 14]; 4]), Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
    Ok((f.prox, f.jacobian))
}

/// Everything differentiable about a proximity query, in one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivatives {
    /// The proximity result.
    pub proximity: Proximity,
    /// ∂α*/∂(r₁, q₁, r₂, q₂).
    pub dalpha: [Real; 14],
    /// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂), rows (x₁, x₂, x₃, α).
    pub jacobian: [[Real; 14]; 4],
    /// ∂p₁/∂(r₁, q₁, r₂, q₂) (3×14) for `p₁ = r₁ + (x* − r₁)/α*`; zero when α* = 0.
    pub dcontact1: [[Real; 14]; 3],
    /// ∂p₂/∂(r₁, q₁, r₂, q₂) (3×14); zero when α* = 0.
    pub dcontact2: [[Real; 14]; 3],
}

/// The Jacobian of (x*, α*) and, by the chain rule, of both contact points:
/// `∂pᵢ = ∂rᵢ + (∂x* − ∂rᵢ)/α* − (x* − rᵢ) ∂α*/α*²`.
pub fn derivatives(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Derivatives, Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
    let p = f.prox;
    let mut d = Derivatives {
        proximity: p,
        dalpha: f.gradient,
        jacobian: f.jacobian,
        dcontact1: [[0.0; 14]; 3],
        dcontact2: [[0.0; 14]; 3],
    };
    if p.alpha > 0.0 {
        let inv = 1.0 / p.alpha;
        let r = [*pose1.position(), *pose2.position()];
        for (i, out) in [&mut d.dcontact1, &mut d.dcontact2].into_iter().enumerate() {
            let rel = p.point - r[i];
            for row in 0..3 {
                for col in 0..14 {
                    let dr = if col == 7 * i + row { 1.0 } else { 0.0 };
                    out[row][col] = dr + (f.jacobian[row][col] - dr) * inv
                        - rel[row] * f.jacobian[3][col] * inv * inv;
                }
            }
        }
    }
    Ok(d)
}

/// Maps 14 quaternion-parameter columns to 12 MRP-parameter columns (`J_q · ∂q/∂p` per pose).
fn to_mrp_columns(row: &[Real; 14], mrp: [[Real; 3]; 2]) -> [Real; 12] {
    let mut out = [0.0; 12];
    for i in 0..2 {
        let dq = crate::math::mrp_quaternion_jacobian(mrp[i]);
        for j in 0..3 {
            out[6 * i + j] = row[7 * i + j];
        }
        for c in 0..3 {
            out[6 * i + 3 + c] = (0..4).map(|k| row[7 * i + 3 + k] * dq[k][c]).sum();
        }
    }
    out
}

/// ∂α*/∂(r₁, p₁, r₂, p₂) for attitudes given as modified Rodrigues parameters (12 numbers).
pub fn gradient_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [Real; 12]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, g) = gradient(shape1, &pose1, shape2, &pose2, options)?;
    Ok((p, to_mrp_columns(&g, [mrp1, mrp2])))
}

/// ∂(x*, α*)/∂(r₁, p₁, r₂, p₂), 4×12, for attitudes given as modified Rodrigues parameters.
pub fn jacobian_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [[Real; 12]; 4]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, j) = jacobian(shape1, &pose1, shape2, &pose2, options)?;
    let mut out = [[0.0; 12]; 4];
    for r in 0..4 {
        out[r] = to_mrp_columns(&j[r], [mrp1, mrp2]);
    }
    Ok((p, out))
}
