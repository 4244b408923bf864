//! The polish of GJK: Newton on the optimality conditions of
//! `max over unit n of n·d − h₁(n) − h₂(−n)` with the pieces GJK's simplex identified,
//!
//! ```text
//!     Σ_k λ_k ∇p_k(n) + μ n = d      (the witnesses' difference d + b − a = μ n, μ = d*)
//!     ‖n‖² = 1
//!     Σ_{k ∈ shape i} λ_k = 1        (i = 1, 2)
//!     p_k(n) = p_{k₀(i)}(n)          (the active pieces of a shape tie)
//! ```
//!
//! (`super::super::polish` solves the same system for the ray cast, with `n·r = 1` in place of
//! the unit norm), each solution ending in the certificate.

use super::Cert;
use crate::math::{Mat3, Real, Vec3};
use crate::shapes::SupportMap;
use crate::solver::dense::lu_solve_one;
use crate::solver::polish::{
    assemble_kkt, drop_piece, eval, normalise_multipliers, solve_dense, Active, DampedNewton,
    Stationarity, MAX_DIM, MAX_PIECES,
};
use crate::solver::raycast::Pair;

/// Newton steps per active set.
const MAX_NEWTON: usize = 12;
/// A full Newton step this small (normalised units) ends the iteration: convergence is
/// quadratic, so the iterate it leads to is within about its square; the certificate checks.
const CONVERGED_STEP: Real = 1e-6;
/// The step at which a second run ends, when the first one's certificate did not close.
const FINAL_STEP: Real = 1e-13;

/// Newton on the optimality conditions of `max n·d − h₁(n) − h₂(−n)` over unit `n` with the
/// pieces active in the simplex, then the certificate at the solution.
pub(super) fn polish<S: SupportMap>(
    pair: &Pair<'_, S>,
    pts: &[super::Pt],
    w: &[Real],
    n0: Vec3,
    mu0: Real,
    (tol, floor): (Real, Real),
    cert: &mut Cert,
) {
    let mut act = [Active { shape: 0, id: 0 }; 2 * MAX_PIECES];
    let mut lam = [0.0; 2 * MAX_PIECES];
    let mut p = 0;
    for (pt, wt) in pts.iter().zip(w) {
        for shape in 0..2 {
            let id = pt.v.id[shape];
            match act[..p].iter().position(|a| a.shape == shape && a.id == id) {
                Some(k) => lam[k] += wt.max(0.0),
                None if p < act.len() => {
                    act[p] = Active { shape, id };
                    lam[p] = wt.max(0.0);
                    p += 1;
                }
                None => return,
            }
        }
    }
    let mu0 = mu0.max(0.0);
    let run = |act: &[Active], lam: &[Real], cert: &mut Cert| -> Option<(usize, Real)> {
        let mut l = [0.0; 2 * MAX_PIECES];
        l[..act.len()].copy_from_slice(lam);
        normalise_multipliers(act, &mut l[..act.len()]);
        let (mut n, mut mu) = (n0, mu0);
        let na = act.len();
        if !newton(
            pair,
            &cert.d,
            act,
            &mut n,
            &mut mu,
            &mut l[..na],
            CONVERGED_STEP,
        ) {
            return None;
        }
        let (kmin, lmin) = (0..act.len()).fold((0, Real::INFINITY), |acc, k| {
            if l[k] < acc.1 {
                (k, l[k])
            } else {
                acc
            }
        });
        if lmin >= -1e-12 {
            certify(pair, act, &n, &l[..na], cert);
            // Where the pieces curve sharply (a rim seen almost along its axis) the iterate
            // after a step of CONVERGED_STEP may still be short of the tolerance: go on to
            // rounding.
            if !cert.closed(tol, floor)
                && newton(
                    pair,
                    &cert.d,
                    act,
                    &mut n,
                    &mut mu,
                    &mut l[..na],
                    FINAL_STEP,
                )
            {
                certify(pair, act, &n, &l[..na], cert);
            }
        }
        Some((kmin, lmin))
    };
    let (act0, lam0, p0) = (act, lam, p);
    // The active set, dropping a piece whose multiplier turns negative (or, when the system
    // is singular, the one with the least weight in the simplex).
    for _attempt in 0..4 {
        match run(&act[..p], &lam[..p], cert) {
            Some((_, lmin)) if lmin >= -1e-12 => break,
            Some((kmin, _)) => {
                if !drop_piece(&mut act, &mut lam, &mut p, kmin) {
                    break;
                }
            }
            None => {
                let Some(k) = (0..p)
                    .filter(|&k| act[..p].iter().filter(|a| a.shape == act[k].shape).count() > 1)
                    .min_by(|&i, &j| lam[i].total_cmp(&lam[j]))
                else {
                    break;
                };
                if !drop_piece(&mut act, &mut lam, &mut p, k) {
                    break;
                }
            }
        }
    }
    if cert.closed(tol, floor) {
        return;
    }
    // Every smaller subset with a piece of each shape, largest first: where the optimum is
    // not unique (parallel edges or segments) the full set is singular and the drop order
    // above may miss the subset that holds a solution.
    for size in (2..p0).rev() {
        for mask in 1u32..(1 << p0) {
            if mask.count_ones() as usize != size {
                continue;
            }
            let mut sub = [Active { shape: 0, id: 0 }; 2 * MAX_PIECES];
            let mut sl = [0.0; 2 * MAX_PIECES];
            let mut q = 0;
            for k in 0..p0 {
                if mask & (1 << k) != 0 {
                    sub[q] = act0[k];
                    sl[q] = lam0[k];
                    q += 1;
                }
            }
            if !(sub[..q].iter().any(|a| a.shape == 0) && sub[..q].iter().any(|a| a.shape == 1)) {
                continue;
            }
            run(&sub[..q], &sl[..q], cert);
            if cert.closed(tol, floor) {
                return;
            }
        }
    }
}

/// The bounds at a Newton solution: the full support maps at `n`, and the primal points
/// `Σ λ_k ∇p_k` of each shape.
fn certify<S: SupportMap>(
    pair: &Pair<'_, S>,
    act: &[Active],
    n: &Vec3,
    lam: &[Real],
    cert: &mut Cert,
) {
    cert.try_normal(pair, n);
    let (mut a, mut b) = (Vec3::zeros(), Vec3::zeros());
    let mut sums = [0.0; 2];
    for (piece, l) in act.iter().zip(lam) {
        let l = l.max(0.0);
        let Some(e) = eval(pair, *piece, n) else {
            return;
        };
        sums[piece.shape] += l;
        if piece.shape == 0 {
            a += e.grad * l;
        } else {
            b -= e.grad * l;
        }
    }
    if sums[0] > 0.0 && sums[1] > 0.0 {
        cert.try_points(a / sums[0], b / sums[1]);
    }
}

/// Damped Newton on `Σ λ_k ∇p_k(n) + μ n = d`, `‖n‖² = 1`, each shape's multipliers summing
/// to one and its active pieces tied; true when a full step converged to rounding.
pub(super) fn newton<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    act: &[Active],
    n: &mut Vec3,
    mu: &mut Real,
    lam: &mut [Real],
    converged: Real,
) -> bool {
    let p = act.len();
    // One piece per shape: both multipliers are 1 (normalised), and only (n, μ) move.
    let dim = if p == 2 { 4 } else { 4 + p };
    let newton = DampedNewton {
        dim,
        multipliers: p,
        converged,
        tiny: 0.0,
        relative: false,
        max_steps: MAX_NEWTON,
    };
    newton.run(
        n,
        mu,
        lam,
        |n, mu, lam, jac, rhs| system(pair, d, act, n, mu, lam, jac, rhs),
        |jac, rhs| match dim {
            4 => solve4(jac, rhs),
            5 => solve_fixed::<5>(jac, rhs),
            6 => solve_fixed::<6>(jac, rhs),
            7 => solve_fixed::<7>(jac, rhs),
            8 => solve_fixed::<8>(jac, rhs),
            9 => solve_fixed::<9>(jac, rhs),
            _ => solve_dense(jac, rhs, dim),
        },
    )
}

/// The residual (negated, into `rhs`) and Jacobian of the polish's system; the residual's
/// 1-norm, or `None` where a piece is not differentiable.
#[allow(clippy::too_many_arguments)]
fn system<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    act: &[Active],
    n: &Vec3,
    mu: Real,
    lam: &[Real],
    jac: &mut [[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> Option<Real> {
    // Σ λ_k ∇p_k(n) + μ n − d = 0 and (‖n‖² − 1)/2 = 0.
    let form = Stationarity {
        hess: Mat3::identity() * mu,
        mu_column: *n,
        offset: n * mu - d,
        last_row: *n,
        last_residual: 0.5 * (n.norm_squared() - 1.0),
    };
    assemble_kkt(pair, act, n, lam, &form, jac, rhs)
}

/// [`solve_dense`] for the leading 4×4 block (one piece per shape), by nalgebra's LU with
/// partial pivoting on the stack; false when the solution is not finite or a pivot is
/// negligible against the largest entry.
fn solve4(jac: &[[Real; MAX_DIM]; MAX_DIM], rhs: &mut [Real; MAX_DIM]) -> bool {
    let a = nalgebra::Matrix4::from_fn(|i, j| jac[i][j]);
    let b = nalgebra::Vector4::new(rhs[0], rhs[1], rhs[2], rhs[3]);
    let amax = a.amax();
    let lu = a.lu();
    let u = lu.u();
    if !(0..4).all(|i| u[(i, i)].abs() > 1e-13 * amax) {
        return false;
    }
    let Some(x) = lu.solve(&b) else {
        return false;
    };
    if !x.iter().all(|v| v.is_finite()) {
        return false;
    }
    rhs[..4].copy_from_slice(x.as_slice());
    true
}

/// [`solve_dense`] of order `N` known at compile time: the same pivots, operations and checks
/// (every pivot above 1e-13 of the largest entry), so the same numbers, with fixed loop bounds
/// and the largest entry found by independent per-column maxima (`solve_dense` finds it twice,
/// each time by one chain of dependent comparisons: most of its time at order 8).
fn solve_fixed<const N: usize>(
    jac: &[[Real; MAX_DIM]; MAX_DIM],
    rhs: &mut [Real; MAX_DIM],
) -> bool {
    let mut a = [[0.0; N]; N];
    for (row, src) in a.iter_mut().zip(jac) {
        row.copy_from_slice(&src[..N]);
    }
    // The largest |entry| (a NaN passed over, as there).
    let mut col = [0.0 as Real; N];
    for row in &a {
        for (m, v) in col.iter_mut().zip(row) {
            let x = v.abs();
            if x > *m {
                *m = x;
            }
        }
    }
    let big = col
        .iter()
        .fold(0.0, |m: Real, &x| if x > m { x } else { m });
    if !(big > 0.0) || !big.is_finite() {
        return false;
    }
    let floor = 1e-13 * big;
    let mut ipiv = [0usize; N];
    for k in 0..N {
        let (mut p, mut pmax) = (k, a[k][k].abs());
        for (i, row) in a.iter().enumerate().skip(k + 1) {
            let x = row[k].abs();
            if x > pmax {
                p = i;
                pmax = x;
            }
        }
        if !(pmax > floor) {
            return false;
        }
        a.swap(p, k);
        ipiv[k] = p;
        let pivot_row = a[k];
        let inv = 1.0 / pivot_row[k];
        for row in a[k + 1..].iter_mut() {
            let f = row[k] * inv;
            row[k] = f;
            if f == 0.0 {
                continue;
            }
            for (x, pv) in row[k + 1..].iter_mut().zip(&pivot_row[k + 1..]) {
                *x -= f * pv;
            }
        }
    }
    let mut b = [0.0; N];
    b.copy_from_slice(&rhs[..N]);
    lu_solve_one(&a, &ipiv, N, &mut b);
    rhs[..N].copy_from_slice(&b);
    true
}
