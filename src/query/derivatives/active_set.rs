//! The active set at a solution point: which rows and cones are active ([`identify`]), how
//! far a point is from satisfying its KKT conditions, and the matrix of that system.

use super::*;

/// The slack `h − G z` of cone block `k` (solver coordinates).
#[inline]
pub(super) fn soc_slack<const N: usize>(
    problem: &Problem<'_, N>,
    k: usize,
    z: &[Real; N],
) -> [Real; 4] {
    let b = &problem.soc[k];
    [
        b.h[0] - dotn(&b.g[0], z),
        b.h[1] - dotn(&b.g[1], z),
        b.h[2] - dotn(&b.g[2], z),
        b.h[3] - dotn(&b.g[3], z),
    ]
}

/// The row of `G` an equation's multiplier multiplies.
#[inline]
pub(super) fn eq_g<'p, const N: usize>(problem: &'p Problem<'_, N>, eq: Eq) -> &'p [Real; N] {
    match eq {
        Eq::Lp(j) => &problem.lp[j].g,
        Eq::SocApex(k, c) | Eq::SocBound(k, c) => &problem.soc[k].g[c],
        Eq::SocPad(k) => &problem.soc[k].g[3],
    }
}

/// Whether orthant row `j` is active at `z`: its polished multiplier exceeds its slack (both
/// vanish only at a degenerate row, where either choice is right), unless listed in `flips`.
#[inline]
pub(super) fn lp_active<const N: usize>(
    problem: &Problem<'_, N>,
    j: usize,
    z: &[Real; N],
    flips: &[usize],
) -> bool {
    let row = &problem.lp[j];
    (row.lam_polished > row.h - dotn(&row.g, z)) != flips.contains(&j)
}

/// Writes into `set` the active set at the point `z` (solver coordinates) with the polished
/// multipliers λ̄. An orthant row is active when λ̄ > s (see [`lp_active`]); a cone is inactive
/// when λ̄₀ < 1e-6·s₀, and at its apex when s₀ < 1e-6·λ̄₀. False when the system would exceed
/// [`MAX_ACTIVE`].
pub(super) fn identify<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    z: &[Real; N],
    flips: &[usize],
    set: &mut ActiveSet,
) -> bool {
    set.n = 0;
    for (i, r) in ranges.iter().enumerate() {
        for j in r.lp.clone() {
            if lp_active(problem, j, z, flips) {
                if N + set.n >= MAX_ACTIVE {
                    return false;
                }
                set.push(Eq::Lp(j), i);
            }
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            let (s, l) = (soc_slack(problem, k, z), b.lam_polished);
            if soc_inactive(&s, &l) {
                continue; // dλ = 0
            }
            if N + set.n + 4 > MAX_ACTIVE {
                return false;
            }
            let apex = soc_apex(&s, &l);
            let padded = b.g[3].iter().all(|v| *v == 0.0) && b.h[3] == 0.0;
            for c in 0..4 {
                set.push(
                    if apex {
                        if c == 3 && padded {
                            Eq::SocPad(k)
                        } else {
                            Eq::SocApex(k, c)
                        }
                    } else {
                        Eq::SocBound(k, c)
                    },
                    i,
                );
            }
        }
    }
    true
}

/// How far the polished point `z` is from satisfying the KKT conditions of the active set
/// [`identify`] would choose there, the largest of (relative): the slack of an active row over
/// `1 + max|z|`, the multiplier of an inactive one over the largest multiplier, and for a cone
/// on its boundary `‖s∘λ̄‖∞/(s₀λ̄₀)` (the relative distance of s and λ̄ from complementary
/// boundary rays). The polish makes the multipliers exactly stationary, so that is the whole
/// residual. Cheap: one pass over the rows, no system.
pub(super) fn ambiguity<const N: usize>(problem: &Problem<'_, N>, z: &[Real; N]) -> Real {
    let (mut ds, mut dl, mut rel, mut lam_max): (Real, Real, Real, Real) = (0.0, 0.0, 0.0, 0.0);
    for j in 0..problem.lp.len() {
        let row = &problem.lp[j];
        let (s, l) = (row.h - dotn(&row.g, z), row.lam_polished);
        lam_max = lam_max.max(l.abs());
        if l > s {
            ds = worse(ds, s.abs());
        } else {
            dl = worse(dl, l.abs());
        }
    }
    for k in 0..problem.n_soc {
        let (s, l) = (soc_slack(problem, k, z), problem.soc[k].lam_polished);
        lam_max = lam_max.max(l[0].abs());
        if soc_inactive(&s, &l) {
            dl = worse(dl, max_abs(&l));
        } else if soc_apex(&s, &l) {
            ds = worse(ds, max_abs(&s));
        } else {
            rel = worse(rel, max_abs(&jprod(&s, &l)) / (s[0] * l[0]));
        }
    }
    let s_scale = 1.0 + z.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    worse(worse(ds / s_scale, dl / lam_max), rel)
}

/// A cone whose polished multiplier is negligible against its slack: inactive.
#[inline]
pub(super) fn soc_inactive(s: &[Real; 4], l: &[Real; 4]) -> bool {
    l[0] < 1e-6 * s[0]
}

/// An active cone whose slack is negligible against its multiplier: at its apex.
#[inline]
pub(super) fn soc_apex(s: &[Real; 4], l: &[Real; 4]) -> bool {
    s[0] < 1e-6 * l[0]
}

/// The matrix of the active-set KKT system at `p`, on the physical scale (`dz` physical, so
/// slacks `s̄ = (h − G z)/t`): rows `0..N` stationarity `Gᵀdλ`, then one row per equation of
/// `set` (see [`enum@Eq`]); unknowns `[dz, dλ of each equation]`. It is the Jacobian of the KKT
/// residual, used both for Newton's method ([`refine`]) and the implicit function theorem.
pub(super) fn kkt_matrix<const N: usize, const M: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    t: Real,
    a: &mut [[Real; M]; M],
) {
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let col = N + qi;
        let g = eq_g(problem, *eq);
        for q in 0..N {
            a[q][col] = g[q];
        }
        let row = &mut a[col];
        match *eq {
            Eq::Lp(_) | Eq::SocApex(..) => {
                row[..N].copy_from_slice(g);
                row[col] = -DUAL_REGULARISATION;
            }
            Eq::SocPad(_) => row[col] = 1.0,
            Eq::SocBound(k, c) => {
                let b = &problem.soc[k];
                let s = soc_slack(problem, k, &p.z).map(|v| v / t);
                let first = col - c;
                let l = [0, 1, 2, 3].map(|r| p.lam[qi - c + r]);
                // L(λ) row c and L(s̄) row c.
                let lrow = |u: &[Real; 4]| -> [Real; 4] {
                    if c == 0 {
                        *u
                    } else {
                        let mut r = [0.0; 4];
                        r[0] = u[c];
                        r[c] = u[0];
                        r
                    }
                };
                let ll = lrow(&l);
                let ls = lrow(&s);
                for q in 0..N {
                    let mut acc = 0.0;
                    for r in 0..4 {
                        acc += ll[r] * b.g[r][q];
                    }
                    row[q] = -acc;
                }
                row[first..first + 4].copy_from_slice(&ls);
            }
        }
    }
}

/// The largest relative violation of the active set's KKT conditions at `p`: stationarity
/// `‖c + Σ g λ‖∞` (c = e_α), active rows' and apex cones' slacks over the slack scale, padded
/// multipliers over the multiplier scale, and `‖s∘λ‖∞/(s₀λ₀)` for cones on their boundary.
pub(super) fn residual<const N: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    scales: &Scales,
) -> Real {
    let mut rd = problem.c;
    let mut worst: Real = 0.0;
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let g = eq_g(problem, *eq);
        for q in 0..N {
            rd[q] += g[q] * p.lam[qi];
        }
        let r = match *eq {
            Eq::Lp(j) => (problem.lp[j].h - dotn(g, &p.z)).abs() / scales.s,
            Eq::SocApex(k, c) => (problem.soc[k].h[c] - dotn(g, &p.z)).abs() / scales.s,
            Eq::SocPad(_) => p.lam[qi].abs() / scales.lam,
            Eq::SocBound(k, 0) => {
                let s = soc_slack(problem, k, &p.z);
                let l = [0, 1, 2, 3].map(|r| p.lam[qi + r]);
                max_abs(&jprod(&s, &l)) / (s[0] * l[0])
            }
            Eq::SocBound(..) => 0.0,
        };
        worst = worse(worst, r);
    }
    for v in rd {
        worst = worse(worst, v.abs());
    }
    worst
}
