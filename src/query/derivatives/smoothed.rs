//! The barrier-smoothed Jacobian, used when the active set is degenerate.

use super::*;

/// The barrier-smoothed Jacobian: the implicit-function system at the final interior iterate,
/// `GᵀDG dz = −dGᵀλ − GᵀDρ` with `D = L(s)⁻¹L(λ)` (the LU of `GᵀDG` from the polish), used when
/// the active set is degenerate. It is the derivative of the central-path point, which smooths
/// the kinks of α* at edges and corners and approaches the exact one as the tolerance shrinks.
#[allow(clippy::too_many_arguments)]
pub(super) fn smoothed_jacobian<const N: usize>(
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
pub(super) fn aho_at_iterate<const N: usize>(
    problem: &Problem<'_, N>,
) -> Option<crate::solver::kkt::Lu<N>> {
    problem
        .aho_matrix()
        .and_then(crate::solver::kkt::Lu::factor)
}
