//! Small dense LU factorisations with partial pivoting, in place, for the active-set and
//! feature systems of the derivatives.

use crate::math::Real;

/// LU with partial pivoting, in place, of the leading `n×n` block of `a`; returns the pivot
/// row chosen at each step (LAPACK's `ipiv`), or `None` when a pivot is below 1e-14 of the
/// largest entry (a degenerate active set).
#[inline(always)]
pub(crate) fn lu_factor_in_place<const M: usize>(
    a: &mut [[Real; M]; M],
    n: usize,
) -> Option<[usize; M]> {
    let n = n.min(M);
    let mut ipiv = [0usize; M];
    // The largest |entry| (a NaN is passed over here and refused as a pivot below).
    let mut big: Real = 0.0;
    for row in a[..n].iter() {
        for v in row[..n].iter() {
            let x = v.abs();
            if x > big {
                big = x;
            }
        }
    }
    if !(big > 0.0) || !big.is_finite() {
        return None;
    }
    let floor = 1e-14 * big;
    for k in 0..n {
        let (mut p, mut pmax) = (k, a[k][k].abs());
        for (i, row) in a[..n].iter().enumerate().skip(k + 1) {
            let x = row[k].abs();
            if x > pmax {
                p = i;
                pmax = x;
            }
        }
        if !(pmax > floor) {
            return None;
        }
        // Whole rows: the entries beyond the order are zero in both.
        a.swap(p, k);
        ipiv[k] = p;
        let pivot_row = a[k];
        let inv = 1.0 / pivot_row[k];
        for row in a[k + 1..n].iter_mut() {
            let f = row[k] * inv;
            row[k] = f;
            if f == 0.0 {
                continue;
            }
            for (x, pv) in row[k + 1..n].iter_mut().zip(&pivot_row[k + 1..n]) {
                *x -= f * pv;
            }
        }
    }
    Some(ipiv)
}

/// Solves `A x = b` in place with the factor from [`lu_factor_in_place`].
pub(crate) fn lu_solve_one<const M: usize>(
    a: &[[Real; M]; M],
    ipiv: &[usize; M],
    n: usize,
    b: &mut [Real; M],
) {
    for k in 0..n {
        b.swap(k, ipiv[k]);
    }
    for i in 0..n {
        let mut acc = b[i];
        for k in 0..i {
            acc -= a[i][k] * b[k];
        }
        b[i] = acc;
    }
    for i in (0..n).rev() {
        let mut acc = b[i];
        for k in (i + 1)..n {
            acc -= a[i][k] * b[k];
        }
        b[i] = acc / a[i][i];
    }
}

/// Solves `Aᵀ Y = B` in place for four right-hand sides (the columns of `b`, stored row by
/// row) with the factor from [`lu_factor_in_place`]: `PA = LU`, so `Aᵀ = UᵀLᵀP`, a forward
/// solve with `Uᵀ` and a backward one with the unit `Lᵀ` (both sweeping rows of the factor),
/// then `Pᵀ`.
#[inline(always)]
pub(crate) fn lu_solve_transposed4<const M: usize>(
    a: &[[Real; M]; M],
    ipiv: &[usize; M],
    n: usize,
    b: &mut [[Real; 4]; M],
) {
    let n = n.min(M);
    for k in 0..n {
        let inv = 1.0 / a[k][k];
        let wk = b[k].map(|x| x * inv);
        b[k] = wk;
        for (bi, u) in b[k + 1..n].iter_mut().zip(&a[k][k + 1..n]) {
            for c in 0..4 {
                bi[c] -= u * wk[c];
            }
        }
    }
    for k in (0..n).rev() {
        let vk = b[k];
        for (bi, l) in b[..k].iter_mut().zip(&a[k][..k]) {
            for c in 0..4 {
                bi[c] -= l * vk[c];
            }
        }
    }
    for k in (0..n).rev() {
        b.swap(k, ipiv[k]);
    }
}
