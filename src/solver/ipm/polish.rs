//! The final Newton polish of a converged iterate, and its convergence test.

use super::cones::{jprod, jsolve, SocVec};
use super::kkt::Lu;
use super::{dotn, fmax, gmul, gtmul_add, Outcome, Problem, D, MAX_SOC};
use crate::math::Real;

/// Largest change of a multiplier, relative to the largest multiplier, that the final polish
/// may make (an interior iterate's multipliers are O(√μ) off on curved contacts).
const POLISH_DUAL_CHANGE: Real = 1e-3;

/// Largest step (relative to `1 + max|z|`) the final polish may take.
const POLISH_MAX_STEP: Real = 1e-2;

/// How far outside a cone (relative to the problem's size) the polished point may lie.
const POLISH_CONE_SLACK: Real = 1e-8;

impl<const N: usize> Problem<'_, N> {
    /// One full Newton step (σ = 0, step length 1, cones ignored) on the primal variables from
    /// the converged iterate, with the complementarity `s∘λ = 0` linearised directly (AHO form)
    /// rather than in the NT-scaled space: `λ∘ds + s∘dλ = −s∘λ`. Eliminating `ds = −r_p − G dz`
    /// and `dλ = −λ + D(r_p + G dz)` with `D = L(s)⁻¹L(λ)` leaves `GᵀDG dz = −c − GᵀD r_p`.
    /// Where the active set is regular this moves the primal point from O(√μ) to O(μ) of the
    /// solution (an interior-point iterate on a curved contact is only O(√μ) accurate). The step
    /// is kept only if it is finite and keeps the objective inside the duality bracket.
    /// The multipliers of the same step, `λ + dλ`, go to `lam_polished`, and the factor of
    /// `GᵀDG` to `aho` for the implicit-function derivatives. Returns whether the step was
    /// kept.
    pub(super) fn polish(&mut self, outcome: &mut Outcome<N>, objective_tolerance: Real) -> bool {
        // Nothing of an earlier attempt (the early polish) may survive this one.
        self.aho = None;
        self.polished = false;
        for row in self.lp.iter_mut() {
            row.lam_polished = row.lam;
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            b.lam_polished = b.lam;
        }
        let m = match self.aho_matrix() {
            Some(m) => m,
            None => return false,
        };
        // rhs = −c − Gᵀ D r_p
        let mut rhs = [0.0; N];
        for i in 0..N {
            rhs[i] = -self.c[i];
        }
        for row in self.lp.iter() {
            let k = row.lam / row.s * row.rp;
            for i in 0..N {
                rhs[i] -= row.g[i] * k;
            }
        }
        for k in 0..self.n_soc {
            let drp = self.soc_d(k, &self.soc[k].rp);
            gtmul_add(&mut rhs, &self.soc[k].g, &drp, -1.0);
        }
        let lu = match Lu::factor(m) {
            Some(lu) => lu,
            None => return false,
        };
        self.aho = Some(lu);
        let dz = lu.solve(&rhs);
        if !dz.iter().all(|v| v.is_finite()) {
            return false;
        }
        // The optimal value lies in [dual objective, primal objective] (up to the residuals), so
        // a step that leaves that bracket by more than the tolerance is not trusted; nor is one
        // that is large or leaves the cones: at a degenerate solution (non-unique optimal point)
        // the Newton system is singular and its step can move along the optimal face by any
        // amount, or off it.
        let zmax = outcome.z.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        let step = dz.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
        if !(step <= POLISH_MAX_STEP * (1.0 + zmax)) {
            return false;
        }
        let mut znew = outcome.z;
        for i in 0..N {
            znew[i] += dz[i];
        }
        let hmax = self.h_max();
        let slack = POLISH_CONE_SLACK * (1.0 + hmax + zmax);
        for row in self.lp.iter() {
            if !(row.h - dotn(&row.g, &znew) >= -slack) {
                return false;
            }
        }
        for b in self.soc[..self.n_soc].iter() {
            let gz = gmul(&b.g, &znew);
            let sv = [
                b.h[0] - gz[0],
                b.h[1] - gz[1],
                b.h[2] - gz[2],
                b.h[3] - gz[3],
            ];
            let nrm = (sv[1] * sv[1] + sv[2] * sv[2] + sv[3] * sv[3]).sqrt();
            if !(sv[0] - nrm >= -slack) {
                return false;
            }
        }
        let dobj = dotn(&self.c, &dz);
        let polished = outcome.primal_objective + dobj;
        let lo = outcome.dual_objective.min(outcome.primal_objective) - objective_tolerance;
        let hi = outcome.primal_objective + objective_tolerance;
        if !(polished >= lo && polished <= hi) {
            return false;
        }
        // λ + dλ = D(r_p + G dz), checked finite before anything is written.
        let mut ok = true;
        for row in self.lp.iter() {
            ok &= (row.lam / row.s * (row.rp + dotn(&row.g, &dz))).is_finite();
        }
        let mut soc_l = [[0.0; D]; MAX_SOC];
        for (k, b) in self.soc[..self.n_soc].iter().enumerate() {
            let gdz = gmul(&b.g, &dz);
            let u = [
                b.rp[0] + gdz[0],
                b.rp[1] + gdz[1],
                b.rp[2] + gdz[2],
                b.rp[3] + gdz[3],
            ];
            soc_l[k] = jsolve(&b.s, &jprod(&b.lam, &u));
            ok &= soc_l[k].iter().all(|v| v.is_finite());
        }
        // Keep the polished multipliers only where the step is a small correction that stays
        // in the dual cone: at a degenerate solution (e.g. parallel faces) the Newton system is
        // singular and its multipliers are meaningless, while the interior ones are fine.
        let lam_max = self
            .lp
            .iter()
            .map(|r| r.lam.abs())
            .chain(self.soc[..self.n_soc].iter().map(|b| b.lam[0].abs()))
            .fold(0.0, Real::max);
        let slack = POLISH_DUAL_CHANGE * lam_max;
        for row in self.lp.iter() {
            let lp = row.lam / row.s * (row.rp + dotn(&row.g, &dz));
            ok &= lp >= -slack && (lp - row.lam).abs() <= slack;
        }
        for (k, b) in self.soc[..self.n_soc].iter().enumerate() {
            let l = &soc_l[k];
            let nrm = (l[1] * l[1] + l[2] * l[2] + l[3] * l[3]).sqrt();
            ok &= l[0] - nrm >= -slack;
            for i in 0..D {
                ok &= (l[i] - b.lam[i]).abs() <= slack;
            }
        }
        if !ok {
            return false;
        }
        for row in self.lp.iter_mut() {
            row.lam_polished = row.lam / row.s * (row.rp + dotn(&row.g, &dz));
        }
        for (k, b) in self.soc[..self.n_soc].iter_mut().enumerate() {
            b.lam_polished = soc_l[k];
        }
        for i in 0..N {
            outcome.z[i] += dz[i];
        }
        outcome.primal_objective += dobj;
        self.polished = true;
        true
    }

    /// Whether the polished point `z` with the polished multipliers passes the convergence
    /// test: `s = h − G z` and `λ` in their cones to within `gap_limit`, `|sᵀλ| ≤ gap_limit`,
    /// `|cᵀz + hᵀλ| ≤ gap_limit` and `‖c + Gᵀλ‖∞ ≤ dres_limit`.
    pub(super) fn polished_converged(
        &self,
        z: &[Real; N],
        gap_limit: Real,
        dres_limit: Real,
    ) -> bool {
        let mut rd = self.c;
        let mut gap = 0.0;
        let mut dobj = 0.0;
        // Both points must be feasible to the same accuracy for the gap to bound the error.
        let mut infeasible: Real = 0.0;
        for row in self.lp.iter() {
            let l = row.lam_polished;
            for i in 0..N {
                rd[i] += row.g[i] * l;
            }
            let s = row.h - dotn(&row.g, z);
            infeasible = fmax(fmax(infeasible, -s), -l);
            gap += s * l;
            dobj -= row.h * l;
        }
        for b in self.soc[..self.n_soc].iter() {
            let l = &b.lam_polished;
            gtmul_add(&mut rd, &b.g, l, 1.0);
            let gz = gmul(&b.g, z);
            let mut sv = [0.0; D];
            for r in 0..D {
                sv[r] = b.h[r] - gz[r];
                gap += sv[r] * l[r];
                dobj -= b.h[r] * l[r];
            }
            let outside = |u: &SocVec| (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]).sqrt() - u[0];
            infeasible = fmax(fmax(infeasible, outside(&sv)), outside(l));
        }
        let dres = rd.iter().fold(0.0, |m: Real, v| fmax(m, v.abs()));
        infeasible <= gap_limit
            && gap.abs() <= gap_limit
            && (dotn(&self.c, z) - dobj).abs() <= gap_limit
            && dres <= dres_limit
    }
}
