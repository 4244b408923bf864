//! The exact Jacobian of `(x*, α*)` on the active set, by the implicit function theorem: the
//! full system, the reduced one for cones on their boundary, and the square one for vertex
//! contacts.

use super::*;

#[cfg(test)]
thread_local! {
    /// Makes [`exact_jacobian`] skip the reduced system (this thread only), so that a test can
    /// compare the two.
    pub(super) static FULL_SYSTEM_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}
use super::active_set::{eq_g, kkt_matrix, soc_slack};
use crate::solver::dense::{lu_factor_in_place, lu_solve_transposed4};

/// Identities every correct Jacobian satisfies, checked before the active-set one is trusted (a
/// misidentified active set, e.g. a facet whose multiplier and slack are both ~1e-5 at the
/// default tolerance, can leave a nearly singular system that still factors): a common
/// translation moves x* with it and leaves α* alone (`J[:, r₁] + J[:, r₂] = [I₃; 0]`), and the
/// α row equals the Lagrangian gradient. Tolerances are in non-dimensional units (r columns
/// times ℓ, x rows over ℓ), far looser than either computation's error and far tighter than
/// any failure seen.
pub(crate) fn consistent(j: &[[Real; 14]; 4], grad: &[Real; 14], ell: Real) -> bool {
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

/// `−ρ` (active rows and apex cones), `0` (padded components) and `L(λ)ρ` (cones on their
/// boundary). Returns false (leaving `full` alone) when the active set is degenerate: a
/// singular system.
pub(super) fn exact_jacobian<const N: usize>(at: &AtPoint<'_, '_, '_, N>, full: &mut Full) -> bool {
    let set = at.set;
    // First the reduced system (one unknown per cone on its boundary); should it fail, the
    // full one. Each lives on the stack in the smallest storage that holds it (6, 12 or 24 for
    // the reduced system, 12 or 24 for the full one: zeroing and sweeping a 24×24 array for a
    // system of order 6 is wasted work).
    let reduced_order = N + set.eqs[..set.n]
        .iter()
        .filter(|eq| !matches!(eq, Eq::SocBound(_, c) if *c > 0))
        .count();
    #[cfg(test)]
    if FULL_SYSTEM_ONLY.with(|f| f.get()) {
        return exact_jacobian_in::<N, MAX_ACTIVE>(at, full);
    }
    let done = if reduced_order <= TINY_ACTIVE {
        reduced_jacobian::<N, TINY_ACTIVE>(at, full)
    } else if reduced_order <= SMALL_ACTIVE {
        reduced_jacobian::<N, SMALL_ACTIVE>(at, full)
    } else {
        reduced_jacobian::<N, MAX_ACTIVE>(at, full)
    };
    if done {
        return true;
    }
    if N + set.n <= SMALL_ACTIVE {
        exact_jacobian_in::<N, SMALL_ACTIVE>(at, full)
    } else {
        exact_jacobian_in::<N, MAX_ACTIVE>(at, full)
    }
}

/// The active-set Jacobian from the reduced system: a cone on its boundary has
/// `λ = γ J s̄` (complementary boundary rays), so instead of four unknowns `dλ` and four rows of
/// the linearised complementarity it contributes one unknown (`s̄₀ dγ`), the boundary equation
/// `(J ŝ)ᵀ ds̄ = 0` (`ŝ = s̄/s̄₀`, `ds̄ = −G dz − ρ`) and, through `dλ = dγ J s̄ + γ J ds̄`, the
/// curvature term `−γ GᵀJG` of the stationarity rows. Exactly equivalent to [`kkt_matrix`]'s
/// system when the point is on the active set (the full complementarity rows are rank
/// deficient along `J s̄`, and their consistency condition is the boundary equation), at
/// about a quarter of the cost for pairs of curved shapes. False when the system is singular or
/// a cone's slack is not usable (then the full system is tried).
pub(super) fn reduced_jacobian<const N: usize, const M: usize>(
    at: &AtPoint<'_, '_, '_, N>,
    full: &mut Full,
) -> bool {
    let AtPoint {
        ctx,
        problem,
        set,
        p,
        gens,
        e,
        v,
        t,
    } = *at;
    /// One unknown of the reduced system.
    #[derive(Clone, Copy)]
    enum Unknown {
        /// Multiplier of an active orthant row or of an apex-cone component (equation index).
        Row(usize),
        /// Cone `k` on its boundary: `J ŝ`, `γ`.
        Cone(usize, [Real; 4], Real),
    }
    let flat = |eq: &Eq| matches!(eq, Eq::Lp(_) | Eq::SocApex(..));
    let padded = |eq: &Eq| matches!(eq, Eq::SocPad(_));
    let eqs = &set.eqs[..set.n];
    if eqs.iter().all(|eq| flat(eq) || padded(eq)) && eqs.iter().filter(|eq| flat(eq)).count() == N
    {
        return square_jacobian(at, full);
    }
    let mut unknowns = [(Unknown::Row(0), 0usize); M];
    let mut n = 0;
    let mut a = [[0.0; M]; M];
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let unknown = match *eq {
            Eq::Lp(_) | Eq::SocApex(..) => Unknown::Row(qi),
            // The padded component of a 3-dimensional cone at its apex: its row of G is zero,
            // so its equation dλ₃ = 0 is decoupled from the rest and is left out.
            Eq::SocPad(_) => continue,
            Eq::SocBound(k, 0) => {
                let sb = soc_slack(problem, k, &p.z).map(|x| x / t);
                let lam0 = p.lam[qi];
                if !(sb[0] > 0.0 && sb[0].is_finite() && lam0.is_finite()) {
                    return false;
                }
                let sh = sb.map(|x| x / sb[0]);
                Unknown::Cone(k, [sh[0], -sh[1], -sh[2], -sh[3]], lam0 / sb[0])
            }
            Eq::SocBound(..) => continue,
        };
        if N + n >= M {
            return false;
        }
        let col = N + n;
        unknowns[n] = (unknown, set.shape[qi]);
        n += 1;
        match unknown {
            Unknown::Row(_) => {
                let g = eq_g(problem, *eq);
                for q in 0..N {
                    a[q][col] = g[q];
                    a[col][q] = g[q];
                }
                a[col][col] = -DUAL_REGULARISATION;
            }
            Unknown::Cone(k, js, gamma) => {
                let g = &problem.soc[k].g;
                // −γ GᵀJG, with the solver's copy of GᵀJG.
                let gjg = problem.soc[k].gjg();
                for q in 0..N {
                    let w = g[0][q] * js[0] + g[1][q] * js[1] + g[2][q] * js[2] + g[3][q] * js[3];
                    a[q][col] = w;
                    a[col][q] = -w;
                    for q2 in 0..N {
                        a[q][q2] -= gamma * gjg[q][q2];
                    }
                }
            }
        }
    }
    let order = N + n;
    let y = match xalpha_rows(&mut a, order) {
        Some(y) => y,
        None => return false,
    };
    let table = RhoTable::new(ctx, gens, e);
    let jac = table.columns(gens, v, &y, |i, pp, acc| {
        for (qn, (unknown, shape)) in unknowns[..n].iter().enumerate() {
            if *shape != i {
                continue;
            }
            let yq = &y[N + qn];
            match *unknown {
                Unknown::Row(qi) => {
                    let bq = -table.rho(eq_g(problem, set.eqs[qi]), i, pp);
                    for r in 0..4 {
                        acc[r] += yq[r] * bq;
                    }
                }
                Unknown::Cone(k, js, gamma) => {
                    let g = &problem.soc[k].g;
                    let rv = table.rho4(g, i, pp);
                    // Boundary row: (Jŝ)ᵀρ; stationarity rows: γ GᵀJρ.
                    let bq = js[0] * rv[0] + js[1] * rv[1] + js[2] * rv[2] + js[3] * rv[3];
                    let jr = [
                        gamma * rv[0],
                        -gamma * rv[1],
                        -gamma * rv[2],
                        -gamma * rv[3],
                    ];
                    for r in 0..4 {
                        acc[r] += yq[r] * bq;
                    }
                    for q in 0..N {
                        let w =
                            g[0][q] * jr[0] + g[1][q] * jr[1] + g[2][q] * jr[2] + g[3][q] * jr[3];
                        if w != 0.0 {
                            for r in 0..4 {
                                acc[r] += y[q][r] * w;
                            }
                        }
                    }
                }
            }
        }
    });
    store_jacobian(jac, ctx.frame.ell, full)
}

/// The active-set Jacobian when exactly `N` rows are active and none of them is curved (a
/// vertex of one polytope on a facet of the other, crossing edges, a cone's apex on a facet,
/// ...): the active rows alone
/// fix the solution, `G_A dz = −ρ`, so `dz = −G_A⁻¹ρ` needs only the `N×N` factor of `G_A` and
/// no multipliers. False when `G_A` is singular (the general system is then tried).
pub(super) fn square_jacobian<const N: usize>(
    at: &AtPoint<'_, '_, '_, N>,
    full: &mut Full,
) -> bool {
    let AtPoint {
        ctx,
        problem,
        set,
        gens,
        e,
        ..
    } = *at;
    // The N flat rows (padded apex components, whose rows of G are zero, left out).
    let mut rows = [0usize; N];
    let mut n = 0;
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        if !matches!(eq, Eq::SocPad(_)) && n < N {
            rows[n] = qi;
            n += 1;
        }
    }
    let mut a = [[0.0; N]; N];
    for (row, &qi) in a.iter_mut().zip(&rows) {
        *row = *eq_g(problem, set.eqs[qi]);
    }
    let y = match xalpha_rows(&mut a, N) {
        Some(y) => y,
        None => return false,
    };
    let table = RhoTable::new(ctx, gens, e);
    let mut jac = [[0.0; 14]; 4];
    for (q, &qi) in rows.iter().enumerate() {
        let i = set.shape[qi];
        let g = eq_g(problem, set.eqs[qi]);
        for pp in 0..7 {
            if table.skip(i, pp) {
                continue;
            }
            let minus_rho = -table.rho(g, i, pp);
            for r in 0..4 {
                jac[r][7 * i + pp] += y[q][r] * minus_rho;
            }
        }
    }
    store_jacobian(jac, ctx.frame.ell, full)
}

/// [`exact_jacobian`] with storage for a system of order ≤ `M`.
pub(super) fn exact_jacobian_in<const N: usize, const M: usize>(
    at: &AtPoint<'_, '_, '_, N>,
    full: &mut Full,
) -> bool {
    let AtPoint {
        ctx,
        problem,
        set,
        p,
        gens,
        e,
        v,
        t,
    } = *at;
    let order = N + set.n;
    let mut a = [[0.0; M]; M];
    kkt_matrix(problem, set, p, t, &mut a);
    let y = match xalpha_rows(&mut a, order) {
        Some(y) => y,
        None => return false,
    };
    let table = RhoTable::new(ctx, gens, e);
    let jac = table.columns(gens, v, &y, |i, pp, acc| {
        let mut rv = [0.0; 4];
        for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
            if set.shape[qi] != i {
                continue;
            }
            let bq = match *eq {
                Eq::Lp(j) => -table.rho(&problem.lp[j].g, i, pp),
                Eq::SocApex(k, c) => -table.rho(&problem.soc[k].g[c], i, pp),
                Eq::SocPad(_) => 0.0,
                Eq::SocBound(k, c) => {
                    if c == 0 {
                        // ρ of the whole cone, computed once per column (components follow).
                        rv = table.rho4(&problem.soc[k].g, i, pp);
                    }
                    let l = &p.lam[qi - c..qi - c + 4];
                    if c == 0 {
                        l[0] * rv[0] + l[1] * rv[1] + l[2] * rv[2] + l[3] * rv[3]
                    } else {
                        l[c] * rv[0] + l[0] * rv[c]
                    }
                }
            };
            if bq != 0.0 {
                let yq = &y[N + qi];
                for r in 0..4 {
                    acc[r] += yq[r] * bq;
                }
            }
        }
    });
    store_jacobian(jac, ctx.frame.ell, full)
}

/// Factors the leading `order×order` block of `a` and returns `Y = A⁻ᵀ[e₀ e₁ e₂ e₃]` (row q
/// of `Y` holds the four (x, α) components): only those rows of `A⁻¹B` are wanted, so
/// `J = YᵀB` needs four solves with the transposed factor instead of fourteen. `None` when
/// the system is singular.
pub(super) fn xalpha_rows<const M: usize>(
    a: &mut [[Real; M]; M],
    order: usize,
) -> Option<[[Real; 4]; M]> {
    // In the small storage the system is padded to order M with a diagonal block (the largest
    // entry on its diagonal, so that the singularity test's scale is unchanged; a padded row is
    // never a pivot of a real column, and its right-hand side and solution are zero): the
    // factorisation's loops then have compile-time bounds, which for these orders costs less
    // than the padding adds.
    let n = if M <= PADDED_ACTIVE {
        let big = a[..order]
            .iter()
            .flat_map(|row| row[..order].iter())
            .fold(0.0, |m: Real, v| m.max(v.abs()));
        for (i, row) in a.iter_mut().enumerate().skip(order) {
            row[i] = big;
        }
        M
    } else {
        order
    };
    let perm = lu_factor_in_place(a, n)?;
    let mut y = [[0.0; 4]; M];
    for (r, yr) in y.iter_mut().take(4).enumerate() {
        yr[r] = 1.0;
    }
    lu_solve_transposed4(a, &perm, n, &mut y);
    Some(y)
}

impl RhoTable {
    pub(super) fn new(ctx: &Context<'_>, gens: &[[Mat3; 4]; 2], e: &[Vec3; 2]) -> Self {
        let mut u = [[Vec3::zeros(); 4]; 2];
        for i in 0..2 {
            for k in 0..4 {
                u[i][k] = gens[i][k].transpose() * e[i];
            }
        }
        RhoTable {
            u,
            inv_ell: 1.0 / ctx.frame.ell,
            fixed: [attitude_free(ctx.shape1), attitude_free(ctx.shape2)],
        }
    }

    /// Whether column `pp` of shape `i` is identically zero (a sphere's quaternion).
    #[inline]
    pub(super) fn skip(&self, i: usize, pp: usize) -> bool {
        pp >= 3 && self.fixed[i]
    }

    /// ρ of row `g` of shape `i` for its parameter `pp` (0..3 position, 3..7 quaternion).
    #[inline]
    pub(super) fn rho<const N: usize>(&self, g: &[Real; N], i: usize, pp: usize) -> Real {
        if pp < 3 {
            -g[pp] * self.inv_ell
        } else {
            -gx(g).dot(&self.u[i][pp - 3])
        }
    }

    /// ρ of the four rows of a cone block.
    #[inline]
    pub(super) fn rho4<const N: usize>(
        &self,
        g: &[[Real; N]; 4],
        i: usize,
        pp: usize,
    ) -> [Real; 4] {
        [
            self.rho(&g[0], i, pp),
            self.rho(&g[1], i, pp),
            self.rho(&g[2], i, pp),
            self.rho(&g[3], i, pp),
        ]
    }

    /// `J = YᵀB` column by column, for an active-set system whose first rows are the
    /// stationarity rows: their right-hand side `−dGᵀλ` (the x-columns `(M_k vᵢ)`, quaternion
    /// parameters only) is common to every form of the system; `rows(i, pp, acc)` adds the
    /// rest of column `(i, pp)`. Columns that are identically zero are skipped.
    pub(super) fn columns<const M: usize>(
        &self,
        gens: &[[Mat3; 4]; 2],
        v: &[Vec3; 2],
        y: &[[Real; 4]; M],
        mut rows: impl FnMut(usize, usize, &mut [Real; 4]),
    ) -> [[Real; 14]; 4] {
        let mut jac = [[0.0; 14]; 4];
        for col in 0..14 {
            let (i, pp) = (col / 7, col % 7);
            if self.skip(i, pp) {
                continue; // exactly zero (see `compute`)
            }
            let mut acc = [0.0; 4];
            if pp >= 3 {
                let dgl = gens[i][pp - 3] * v[i];
                for r in 0..4 {
                    acc[r] += y[0][r] * dgl[0] + y[1][r] * dgl[1] + y[2][r] * dgl[2];
                }
            }
            rows(i, pp, &mut acc);
            for r in 0..4 {
                jac[r][col] = acc[r];
            }
        }
        jac
    }
}

/// Stores a Jacobian accumulated in non-dimensional units (the x rows are then multiplied by
/// `ℓ`); false, leaving `full` alone, when an entry is not finite.
pub(super) fn store_jacobian(mut jac: [[Real; 14]; 4], ell: Real, full: &mut Full) -> bool {
    for row in jac.iter_mut().take(3) {
        for v in row.iter_mut() {
            *v *= ell;
        }
    }
    if !jac.iter().flatten().all(|v| v.is_finite()) {
        return false;
    }
    full.jacobian = jac;
    true
}
