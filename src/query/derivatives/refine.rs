//! The solution point refined on its active set by Newton's method, for points next to an
//! active-set change (see [`refine_solution`]).

use super::active_set::{ambiguity, eq_g, kkt_matrix, lp_active, residual, soc_slack};
use super::*;
use crate::solver::dense::{lu_factor_in_place, lu_solve_one};

/// The solution point near an active-set change. The polished point of a converged solve
/// satisfies the KKT conditions of its active set to rounding, except next to an active-set
/// change (a weakly active row whose slack and multiplier are both O(√μ), as at a contact
/// next to a cone's rim): there one Newton polish leaves it O(√μ) off (up to 1e-6 ℓ in x* at
/// the default tolerance), and [`refine`] (Newton's method on the KKT system of the identified
/// active set, with sign checks) finds the exact point. One pass over the rows decides
/// ([`ambiguity`]); the refinement itself runs rarely (12 of 7 201 queries in the benchmark's
/// sweep). `NONE` when not needed, not possible (no accepted polish) or not converged.
pub(crate) fn refine_solution<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
) -> Refined<N> {
    if outcome.status != SolveStatus::Converged
        || !problem.polished
        || ambiguity(problem, &outcome.z) <= AMBIGUOUS
    {
        return Refined::NONE;
    }
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    Refined(refine(problem, &ranges, &outcome.z, solver_scale(ctx)))
}

/// One Newton step on the KKT conditions of `set` from `p`; `None` when the system is singular
/// or the step not finite.
pub(super) fn newton_step<const N: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    t: Real,
) -> Option<Point<N>> {
    let mut a = [[0.0; MAX_ACTIVE]; MAX_ACTIVE];
    kkt_matrix(problem, set, p, t, &mut a);
    let order = N + set.n;
    let mut rhs = [0.0; MAX_ACTIVE];
    for q in 0..N {
        rhs[q] = -problem.c[q];
    }
    let mut sl = [0.0; 4];
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let g = eq_g(problem, *eq);
        for q in 0..N {
            rhs[q] -= g[q] * p.lam[qi];
        }
        rhs[N + qi] = match *eq {
            Eq::Lp(j) => (problem.lp[j].h - dotn(g, &p.z)) / t,
            Eq::SocApex(k, c) => (problem.soc[k].h[c] - dotn(g, &p.z)) / t,
            Eq::SocPad(_) => -p.lam[qi],
            Eq::SocBound(k, c) => {
                if c == 0 {
                    let s = soc_slack(problem, k, &p.z).map(|v| v / t);
                    let l = [0, 1, 2, 3].map(|r| p.lam[qi + r]);
                    sl = jprod(&s, &l);
                }
                -sl[c]
            }
        };
    }
    let perm = lu_factor_in_place(&mut a, order)?;
    lu_solve_one(&a, &perm, order, &mut rhs);
    if !rhs[..order].iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut next = *p;
    for q in 0..N {
        next.z[q] += t * rhs[q];
    }
    for qi in 0..set.n {
        next.lam[qi] += rhs[N + qi];
    }
    Some(next)
}

/// Refines the polished point `z0` by Newton's method on the KKT conditions of its active set,
/// for use when the polish left it short of them (see [`AMBIGUOUS`]). Near an active-set change
/// the interior iterate's slack and multiplier of the row that changes are both O(√μ), and a
/// single Newton step on the complementarity `s λ = 0` from there only halves them; on the
/// right active set the KKT conditions are smooth equations and Newton's method converges
/// quadratically. The result is accepted only if it converges to [`CONVERGED`], stays within
/// [`REFINE_MAX_STEP`] of the polished point and satisfies the sign conditions (λ ≥ 0 on active
/// rows, s ≥ 0 on inactive ones, both in their cones). When an orthant row's sign condition
/// fails, its classification is flipped and the refinement restarted (at most [`MAX_FLIPS`]
/// times). `None` when no active set passes: the caller then keeps the polished point.
pub(super) fn refine<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    z0: &[Real; N],
    t: Real,
) -> Option<(ActiveSet, Point<N>)> {
    let scales = Scales {
        s: 1.0 + z0.iter().fold(0.0, |m: Real, v| m.max(v.abs())),
        lam: problem
            .lp
            .iter()
            .map(|r| r.lam_polished.abs())
            .chain(
                problem.soc[..problem.n_soc]
                    .iter()
                    .map(|b| b.lam_polished[0].abs()),
            )
            .fold(0.0, Real::max),
    };
    let mut flips = [0usize; MAX_FLIPS];
    let mut n_flips = 0;
    loop {
        let mut set = ActiveSet::EMPTY;
        if !identify(problem, ranges, z0, &flips[..n_flips], &mut set) {
            return None;
        }
        let start = Point::polished(problem, &set, z0);
        let mut p = start;
        let mut steps = 0;
        while !(residual(problem, &set, &p, &scales) <= CONVERGED) {
            if steps == MAX_NEWTON_STEPS {
                return None;
            }
            p = newton_step(problem, &set, &p, t)?;
            steps += 1;
        }
        for q in 0..N {
            if !((p.z[q] - z0[q]).abs() <= REFINE_MAX_STEP * scales.s) {
                return None;
            }
        }
        for qi in 0..set.n {
            if !((p.lam[qi] - start.lam[qi]).abs() <= REFINE_MAX_STEP * scales.lam) {
                return None;
            }
        }
        // The worst violated sign condition of an orthant row, if any.
        let mut flip = None;
        let mut worst = SIGN_TOLERANCE;
        for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
            if let Eq::Lp(j) = *eq {
                let v = -p.lam[qi] / scales.lam;
                if !(v <= worst) {
                    worst = v;
                    flip = Some(j);
                }
            }
        }
        for (j, row) in problem.lp.iter().enumerate() {
            if !lp_active(problem, j, z0, &flips[..n_flips]) {
                let v = -(row.h - dotn(&row.g, &p.z)) / scales.s;
                if !(v <= worst) {
                    worst = v;
                    flip = Some(j);
                }
            }
        }
        // Cones: both s and λ in the cone (on the boundary, complementarity already holds).
        for k in 0..problem.n_soc {
            let s = soc_slack(problem, k, &p.z);
            let first = set.eqs[..set.n]
                .iter()
                .position(|eq| matches!(eq, Eq::SocApex(kk, _) | Eq::SocBound(kk, _) if *kk == k));
            let l = match first {
                Some(f) => [0, 1, 2, 3].map(|r| p.lam[f + r]),
                None => [0.0; 4],
            };
            let gap = |u: &[Real; 4]| u[0] - (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]).sqrt();
            if !(gap(&s) >= -SIGN_TOLERANCE * scales.s && gap(&l) >= -SIGN_TOLERANCE * scales.lam) {
                return None;
            }
        }
        match flip {
            None => return Some((set, p)),
            Some(j) if n_flips < MAX_FLIPS => {
                flips[n_flips] = j;
                n_flips += 1;
            }
            Some(_) => return None,
        }
    }
}
