//! A primal-dual interior-point method for small cone programs over the nonnegative orthant and
//! second-order cones, written for DCOL's problems: at most [`MAX_VARS`] variables and
//! [`MAX_SOC`] second-order cones of dimension ≤ 4, any number of orthant rows (held in a
//! caller-provided slice, so the solver itself never allocates).
//!
//! The problem is `minimise cᵀz subject to s = h − G z ∈ K`. The method is the standard one of
//! CVXOPT's `conelp` without equality constraints: Nesterov–Todd scaling, a Mehrotra
//! predictor-corrector, and the normal equations `Gᵀ W⁻² G dz = r` factored by a dense Cholesky
//! of order n. It knows nothing of shapes.

pub mod cones;
pub mod kkt;
mod settings;
mod status;

pub use settings::{Settings, DEFAULT_MAX_ITERATIONS, DEFAULT_TOLERANCE};
pub use status::SolveStatus;

use crate::math::Real;
use cones::{jdot, jprod, jsolve, soc_step, SocScaling, SocVec, SOC_MAX_DIM};
use kkt::Normal;

/// The most variables a problem may have.
pub const MAX_VARS: usize = 12;
/// The most second-order cone blocks a problem may have.
pub const MAX_SOC: usize = 3;

/// One nonnegative-orthant row `s = h − gᵀz ≥ 0` and its iterate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LpRow {
    /// Row of `G`.
    pub g: [Real; MAX_VARS],
    /// Entry of `h`.
    pub h: Real,
    /// Primal slack.
    pub s: Real,
    /// Dual variable.
    pub lam: Real,
    ds: Real,
    dlam: Real,
    rc: Real,
    rp: Real,
}

impl LpRow {
    /// An all-zero row.
    pub const ZERO: LpRow = LpRow {
        g: [0.0; MAX_VARS],
        h: 0.0,
        s: 0.0,
        lam: 0.0,
        ds: 0.0,
        dlam: 0.0,
        rc: 0.0,
        rp: 0.0,
    };
}

impl Default for LpRow {
    fn default() -> Self {
        LpRow::ZERO
    }
}

/// One second-order cone block `s = h − G z ∈ Q_d` and its iterate.
#[derive(Clone, Copy, Debug)]
pub struct SocBlock {
    /// Dimension `d` (3 or 4).
    pub dim: usize,
    /// Rows of `G`.
    pub g: [[Real; MAX_VARS]; SOC_MAX_DIM],
    /// `h`.
    pub h: SocVec,
    /// Primal slack.
    pub s: SocVec,
    /// Dual variable.
    pub lam: SocVec,
    ds: SocVec,
    dlam: SocVec,
    rc: SocVec,
    rp: SocVec,
    sc: SocScaling,
}

impl SocBlock {
    /// An empty block.
    pub const EMPTY: SocBlock = SocBlock {
        dim: 0,
        g: [[0.0; MAX_VARS]; SOC_MAX_DIM],
        h: [0.0; SOC_MAX_DIM],
        s: [0.0; SOC_MAX_DIM],
        lam: [0.0; SOC_MAX_DIM],
        ds: [0.0; SOC_MAX_DIM],
        dlam: [0.0; SOC_MAX_DIM],
        rc: [0.0; SOC_MAX_DIM],
        rp: [0.0; SOC_MAX_DIM],
        sc: SocScaling {
            eta: 0.0,
            w: [0.0; SOC_MAX_DIM],
            v: [0.0; SOC_MAX_DIM],
        },
    };

    /// The scaling computed at the last iterate (valid after a solve).
    pub fn scaling(&self) -> &SocScaling {
        &self.sc
    }
}

/// A cone program `min cᵀz s.t. h − G z ∈ K` with its iterate.
#[derive(Debug)]
pub struct Problem<'a> {
    /// Number of variables.
    pub n: usize,
    /// Objective.
    pub c: [Real; MAX_VARS],
    /// Orthant rows (caller-provided storage).
    pub lp: &'a mut [LpRow],
    /// Second-order cone blocks (first `n_soc` used).
    pub soc: [SocBlock; MAX_SOC],
    /// Number of second-order cone blocks.
    pub n_soc: usize,
}

/// What a solve returns besides the iterate left in the problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// How it ended.
    pub status: SolveStatus,
    /// Newton steps taken.
    pub iterations: u32,
    /// The primal variables at the last iterate.
    pub z: [Real; MAX_VARS],
    /// `cᵀz`.
    pub primal_objective: Real,
    /// `−hᵀλ`.
    pub dual_objective: Real,
}

#[inline]
fn dotn(a: &[Real; MAX_VARS], b: &[Real; MAX_VARS], n: usize) -> Real {
    let mut r = 0.0;
    for i in 0..n {
        r += a[i] * b[i];
    }
    r
}

impl<'a> Problem<'a> {
    /// An empty problem with `n` variables and storage for its orthant rows.
    pub fn new(n: usize, lp: &'a mut [LpRow]) -> Problem<'a> {
        Problem {
            n,
            c: [0.0; MAX_VARS],
            lp,
            soc: [SocBlock::EMPTY; MAX_SOC],
            n_soc: 0,
        }
    }

    fn degree(&self) -> Real {
        (self.lp.len() + self.n_soc) as Real
    }

    /// Builds the normal matrix `Gᵀ W⁻² G` at the current iterate (scalings must be current)
    /// and factors it. `gjg` holds `Gᵀ J G` per cone block.
    fn normal_matrix(&self, gjg: &[[[Real; MAX_VARS]; MAX_VARS]; MAX_SOC]) -> Option<Normal> {
        let n = self.n;
        let mut h = Normal::zeros(n);
        for row in self.lp.iter() {
            h.add_rank1(row.lam / row.s, &row.g);
        }
        for (k, b) in self.soc[..self.n_soc].iter().enumerate() {
            let e2 = 1.0 / (b.sc.eta * b.sc.eta);
            // a = Gᵀ J w
            let mut a = [0.0; MAX_VARS];
            for (i, gi) in b.g[..b.dim].iter().enumerate() {
                let wi = if i == 0 { b.sc.w[0] } else { -b.sc.w[i] };
                for j in 0..n {
                    a[j] += gi[j] * wi;
                }
            }
            h.add_rank1(2.0 * e2, &a);
            h.add_scaled(-e2, &gjg[k]);
        }
        if h.factor() {
            Some(h)
        } else {
            None
        }
    }

    /// Updates every block's NT scaling; false if an iterate left the cone interior.
    fn update_scalings(&mut self) -> bool {
        for row in self.lp.iter() {
            if !(row.s > 0.0 && row.lam > 0.0) {
                return false;
            }
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            match SocScaling::new(&b.s, &b.lam, b.dim) {
                Some(sc) => b.sc = sc,
                None => return false,
            }
        }
        true
    }

    /// Solves the Newton system for the complementarity target held in each block's `rc`
    /// (in the scaled space), with residuals `rd` and each block's `rp`. Writes `ds`, `dlam`
    /// into the blocks and returns `dz`.
    fn direction(&mut self, kkt: &Normal, rd: &[Real; MAX_VARS]) -> [Real; MAX_VARS] {
        let n = self.n;
        let mut rhs = [0.0; MAX_VARS];
        for i in 0..n {
            rhs[i] = -rd[i];
        }
        // t = rp + W (v \ rc); rhs -= Gᵀ W⁻² t. Keep t in ds, W(v\rc) in dlam temporarily.
        for row in self.lp.iter_mut() {
            let wu = row.rc / row.lam;
            let t = row.rp + wu;
            row.ds = t;
            row.dlam = wu;
            let k = row.lam / row.s * t;
            for i in 0..n {
                rhs[i] -= k * row.g[i];
            }
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let d = b.dim;
            let u = jsolve(&b.sc.v, &b.rc, d);
            let wu = b.sc.apply(&u, d);
            let mut t = [0.0; SOC_MAX_DIM];
            for i in 0..d {
                t[i] = b.rp[i] + wu[i];
            }
            let wt = b.sc.apply_inv_sq(&t, d);
            for (i, gi) in b.g[..d].iter().enumerate() {
                for j in 0..n {
                    rhs[j] -= gi[j] * wt[i];
                }
            }
            b.ds = t;
            b.dlam = wu;
        }
        kkt.solve(&mut rhs);
        let dz = rhs;
        for row in self.lp.iter_mut() {
            // dλ = W⁻²(G dz + t) keeps the dual equation exact; ds from the primal equation
            // (not from W(v\rc) − W²dλ, which amplifies rounding by ‖W²‖ near the boundary),
            // so only the self-correcting complementarity equation absorbs rounding.
            let t = row.ds;
            let gdz = dotn(&row.g, &dz, n);
            row.dlam = row.lam / row.s * (gdz + t);
            row.ds = -row.rp - gdz;
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let d = b.dim;
            let t = b.ds;
            let mut gt = [0.0; SOC_MAX_DIM];
            for i in 0..d {
                let gdz = dotn(&b.g[i], &dz, n);
                gt[i] = gdz + t[i];
                b.ds[i] = -b.rp[i] - gdz;
            }
            b.dlam = b.sc.apply_inv_sq(&gt, d);
        }
        let mut dz = dz;
        self.refine(kkt, rd, &mut dz);
        dz
    }

    /// Iterative refinement of the dual equation `Gᵀdλ = −r_d`: forming `Gᵀ W⁻² G` and
    /// applying `W⁻²` round differently when the scaling is extreme, so the correction
    /// `H δz = e_d`, `δλ = W⁻² G δz`, `δs = −G δz` (which leaves the primal and linearised
    /// complementarity equations unchanged) is applied while it helps.
    fn refine(&mut self, kkt: &Normal, rd: &[Real; MAX_VARS], dz: &mut [Real; MAX_VARS]) {
        let n = self.n;
        let mut prev = Real::INFINITY;
        for _ in 0..3 {
            let mut e = [0.0; MAX_VARS];
            for i in 0..n {
                e[i] = -rd[i];
            }
            for row in self.lp.iter() {
                for i in 0..n {
                    e[i] -= row.g[i] * row.dlam;
                }
            }
            for b in self.soc[..self.n_soc].iter() {
                for (r, gr) in b.g[..b.dim].iter().enumerate() {
                    for i in 0..n {
                        e[i] -= gr[i] * b.dlam[r];
                    }
                }
            }
            let err = e[..n].iter().map(|v| v.abs()).fold(0.0, Real::max);
            let scale = rd[..n].iter().map(|v| v.abs()).fold(1e-300, Real::max);
            if !(err > 1e-15 * scale.max(1e-3)) || !(err < 0.5 * prev) {
                break;
            }
            prev = err;
            kkt.solve(&mut e);
            for i in 0..n {
                dz[i] += e[i];
            }
            for row in self.lp.iter_mut() {
                let gd = dotn(&row.g, &e, n);
                row.dlam += row.lam / row.s * gd;
                row.ds -= gd;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                let d = b.dim;
                let mut gd = [0.0; SOC_MAX_DIM];
                for i in 0..d {
                    gd[i] = dotn(&b.g[i], &e, n);
                    b.ds[i] -= gd[i];
                }
                let dl = b.sc.apply_inv_sq(&gd, d);
                for i in 0..d {
                    b.dlam[i] += dl[i];
                }
            }
        }
    }

    /// Largest step in (0, ∞] keeping `s` and `λ` in the cones.
    fn max_step(&self) -> Real {
        let mut t = Real::INFINITY;
        for row in self.lp.iter() {
            if row.ds < 0.0 {
                t = t.min(-row.s / row.ds);
            }
            if row.dlam < 0.0 {
                t = t.min(-row.lam / row.dlam);
            }
        }
        for b in self.soc[..self.n_soc].iter() {
            t = t.min(soc_step(&b.s, &b.ds, b.dim));
            t = t.min(soc_step(&b.lam, &b.dlam, b.dim));
        }
        t
    }

    /// One full Newton step (σ = 0, step length 1, cones ignored) on the primal variables from
    /// the converged iterate, with the complementarity `s∘λ = 0` linearised directly (AHO form)
    /// rather than in the NT-scaled space: `λ∘ds + s∘dλ = −s∘λ`. Eliminating `ds = −r_p − G dz`
    /// and `dλ = −λ + D(r_p + G dz)` with `D = L(s)⁻¹L(λ)` leaves `GᵀDG dz = −c − GᵀD r_p`.
    /// Where the active set is regular this moves the primal point from O(√μ) to O(μ) of the
    /// solution (an interior-point iterate on a curved contact is only O(√μ) accurate). The step
    /// is kept only if it is finite and changes the objective by no more than the gap tolerance.
    fn polish(&self, outcome: &mut Outcome, objective_tolerance: Real) {
        let n = self.n;
        let mut m = [[0.0; MAX_VARS]; MAX_VARS];
        let mut rhs = [0.0; MAX_VARS];
        for i in 0..n {
            rhs[i] = -self.c[i];
        }
        for row in self.lp.iter() {
            let d = row.lam / row.s;
            for i in 0..n {
                let gi = row.g[i] * d;
                if gi == 0.0 {
                    continue;
                }
                rhs[i] -= gi * row.rp;
                for j in 0..n {
                    m[i][j] += gi * row.g[j];
                }
            }
        }
        for b in self.soc[..self.n_soc].iter() {
            let dim = b.dim;
            // D applied to each column of G, and to r_p.
            let apply_d = |u: &SocVec| jsolve(&b.s, &jprod(&b.lam, u, dim), dim);
            for j in 0..n {
                let mut col = [0.0; SOC_MAX_DIM];
                for r in 0..dim {
                    col[r] = b.g[r][j];
                }
                let dc = apply_d(&col);
                for (r, gr) in b.g[..dim].iter().enumerate() {
                    for i in 0..n {
                        m[i][j] += gr[i] * dc[r];
                    }
                }
            }
            let drp = apply_d(&b.rp);
            for (r, gr) in b.g[..dim].iter().enumerate() {
                for i in 0..n {
                    rhs[i] -= gr[i] * drp[r];
                }
            }
        }
        let dz = match kkt::lu_solve(&mut m, rhs, n) {
            Some(d) => d,
            None => return,
        };
        if !dz[..n].iter().all(|v| v.is_finite()) {
            return;
        }
        let dobj = dotn(&self.c, &dz, n);
        if !(dobj.abs() <= objective_tolerance) {
            return;
        }
        for i in 0..n {
            outcome.z[i] += dz[i];
        }
        outcome.primal_objective += dobj;
    }

    /// Runs the interior-point method from the primal point `z0`, with the dual started at
    /// `mu0 · s⁻¹` (perfectly centred). The final iterate stays in the problem's blocks.
    pub fn solve(&mut self, z0: &[Real; MAX_VARS], mu0: Real, settings: &Settings) -> Outcome {
        let n = self.n;
        let mut z = *z0;
        // Initial slacks, pushed into the interior if needed.
        // Largest violation of strict interiority (negative when z0 is strictly feasible).
        let mut shift = Real::NEG_INFINITY;
        for row in self.lp.iter_mut() {
            row.s = row.h - dotn(&row.g, &z, n);
            shift = shift.max(-row.s);
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            for i in 0..b.dim {
                b.s[i] = b.h[i] - dotn(&b.g[i], &z, n);
            }
            let mut nrm = 0.0;
            for i in 1..b.dim {
                nrm += b.s[i] * b.s[i];
            }
            shift = shift.max(nrm.sqrt() - b.s[0]);
        }
        let mu0 = if mu0 > 0.0 && mu0.is_finite() {
            mu0
        } else {
            1.0
        };
        if shift >= 0.0 {
            let add = shift + 1.0;
            for row in self.lp.iter_mut() {
                row.s += add;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                b.s[0] += add;
            }
        }
        for row in self.lp.iter_mut() {
            row.lam = mu0 / row.s;
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let d = b.dim;
            let sn2 = jdot(&b.s, &b.s, d);
            b.lam[0] = mu0 * b.s[0] / sn2;
            for i in 1..d {
                b.lam[i] = -mu0 * b.s[i] / sn2;
            }
        }
        // Gᵀ J G per cone block (constant).
        let mut gjg = [[[0.0; MAX_VARS]; MAX_VARS]; MAX_SOC];
        for (k, b) in self.soc[..self.n_soc].iter().enumerate() {
            for (r, gr) in b.g[..b.dim].iter().enumerate() {
                let sign = if r == 0 { 1.0 } else { -1.0 };
                for i in 0..n {
                    let gi = sign * gr[i];
                    if gi == 0.0 {
                        continue;
                    }
                    for j in 0..n {
                        gjg[k][i][j] += gi * gr[j];
                    }
                }
            }
        }
        let hmax = self
            .lp
            .iter()
            .map(|r| r.h.abs())
            .chain(
                self.soc[..self.n_soc]
                    .iter()
                    .flat_map(|b| b.h[..b.dim].iter().map(|v| v.abs())),
            )
            .fold(0.0, Real::max);
        let cmax = self.c[..n].iter().map(|v| v.abs()).fold(0.0, Real::max);
        let nu = self.degree();
        let tol = settings.tolerance;
        let mut outcome = Outcome {
            status: SolveStatus::MaxIterations,
            iterations: 0,
            z,
            primal_objective: Real::NAN,
            dual_objective: Real::NAN,
        };
        let mut iter = 0u32;
        loop {
            // Residuals and convergence.
            let mut rd = self.c;
            let mut pres: Real = 0.0;
            let mut gap = 0.0;
            let mut dobj = 0.0;
            for row in self.lp.iter_mut() {
                for i in 0..n {
                    rd[i] += row.g[i] * row.lam;
                }
                row.rp = dotn(&row.g, &z, n) + row.s - row.h;
                pres = pres.max(row.rp.abs());
                gap += row.s * row.lam;
                dobj -= row.h * row.lam;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                for (r, gr) in b.g[..b.dim].iter().enumerate() {
                    for i in 0..n {
                        rd[i] += gr[i] * b.lam[r];
                    }
                    b.rp[r] = dotn(gr, &z, n) + b.s[r] - b.h[r];
                    pres = pres.max(b.rp[r].abs());
                    gap += b.s[r] * b.lam[r];
                    dobj -= b.h[r] * b.lam[r];
                }
            }
            let pobj = dotn(&self.c, &z, n);
            let dres = rd[..n].iter().map(|v| v.abs()).fold(0.0, Real::max);
            outcome.z = z;
            outcome.iterations = iter;
            outcome.primal_objective = pobj;
            outcome.dual_objective = dobj;
            let scale = pobj.abs().max(1.0);
            if gap <= tol * scale
                && (pobj - dobj).abs() <= tol * scale
                && pres <= tol * (1.0 + hmax)
                && dres <= tol * (1.0 + cmax)
            {
                outcome.status = SolveStatus::Converged;
                // Leave the scalings current for derivatives.
                if !self.update_scalings() {
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
                self.polish(&mut outcome, tol * scale);
                return outcome;
            }
            if iter >= settings.max_iterations {
                outcome.status = SolveStatus::MaxIterations;
                self.update_scalings();
                return outcome;
            }
            if !self.update_scalings() {
                outcome.status = SolveStatus::NumericalFailure;
                return outcome;
            }
            let kkt = match self.normal_matrix(&gjg) {
                Some(k) => k,
                None => {
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
            };
            // Predictor: rc = −v∘v.
            for row in self.lp.iter_mut() {
                row.rc = -row.s * row.lam;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                let vv = jprod(&b.sc.v, &b.sc.v, b.dim);
                for i in 0..b.dim {
                    b.rc[i] = -vv[i];
                }
            }
            let _dz_aff = self.direction(&kkt, &rd);
            let t_aff = self.max_step().min(1.0);
            let mu = gap / nu;
            // Gap after the affine step, for σ.
            let mut gap_aff = 0.0;
            for row in self.lp.iter() {
                gap_aff += (row.s + t_aff * row.ds) * (row.lam + t_aff * row.dlam);
            }
            for b in self.soc[..self.n_soc].iter() {
                for i in 0..b.dim {
                    gap_aff += (b.s[i] + t_aff * b.ds[i]) * (b.lam[i] + t_aff * b.dlam[i]);
                }
            }
            let ratio = (gap_aff / gap).clamp(0.0, 1.0);
            let sigma = ratio * ratio * ratio;
            // Corrector: rc = −v∘v − (W⁻¹Δs_a)∘(WΔλ_a) + σμe.
            for row in self.lp.iter_mut() {
                row.rc = -row.s * row.lam - row.ds * row.dlam + sigma * mu;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                let d = b.dim;
                let a = b.sc.apply_inv(&b.ds, d);
                let c = b.sc.apply(&b.dlam, d);
                let corr = jprod(&a, &c, d);
                let vv = jprod(&b.sc.v, &b.sc.v, d);
                for i in 0..d {
                    b.rc[i] = -vv[i] - corr[i];
                }
                b.rc[0] += sigma * mu;
            }
            let dz = self.direction(&kkt, &rd);
            let t = (0.99 * self.max_step()).min(1.0);
            if std::env::var_os("DCOL_TRACE").is_some() {
                eprintln!("it {iter} pobj {pobj:.12e} dobj {dobj:.12e} gap {gap:.2e} pres {pres:.1e} dres {dres:.1e} t_aff {t_aff:.3e} sigma {sigma:.1e} t {t:.4e}");
            }
            if !(t > 0.0) || !dz[..n].iter().all(|v| v.is_finite()) {
                outcome.status = SolveStatus::NumericalFailure;
                return outcome;
            }
            for i in 0..n {
                z[i] += t * dz[i];
            }
            for row in self.lp.iter_mut() {
                row.s += t * row.ds;
                row.lam += t * row.dlam;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                for i in 0..b.dim {
                    b.s[i] += t * b.ds[i];
                    b.lam[i] += t * b.dlam[i];
                }
            }
            iter += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// min x₀ + x₁ s.t. x ≥ (1, 2) (orthant) → optimum 3.
    #[test]
    fn tiny_lp() {
        let mut rows = [LpRow::ZERO; 2];
        rows[0].g[0] = -1.0;
        rows[0].h = -1.0;
        rows[1].g[1] = -1.0;
        rows[1].h = -2.0;
        let mut p = Problem::new(2, &mut rows);
        p.c[0] = 1.0;
        p.c[1] = 1.0;
        let mut z0 = [0.0; MAX_VARS];
        z0[0] = 5.0;
        z0[1] = 5.0;
        let out = p.solve(&z0, 1.0, &Settings::default());
        assert_eq!(out.status, SolveStatus::Converged);
        assert!((out.z[0] - 1.0).abs() < 1e-9 && (out.z[1] - 2.0).abs() < 1e-9);
        assert!((out.primal_objective - 3.0).abs() < 1e-9);
    }

    /// min t s.t. ‖(x − a)‖ ≤ t with x₀ ≤ −1 → distance from a = (1, 0) to the halfplane = 2.
    #[test]
    fn tiny_socp() {
        let mut rows = [LpRow::ZERO; 1];
        // s = −1 − x₀ ≥ 0  → h = −1, g = (1, 0, 0)
        rows[0].g[0] = 1.0;
        rows[0].h = -1.0;
        let mut p = Problem::new(3, &mut rows);
        p.c[2] = 1.0;
        // [t; x − a] ∈ Q₃ → s = h − Gz with s₀ = t, s₁ = x₀ − 1, s₂ = x₁
        let mut b = SocBlock::EMPTY;
        b.dim = 3;
        b.g[0][2] = -1.0;
        b.g[1][0] = -1.0;
        b.h[1] = -1.0;
        b.g[2][1] = -1.0;
        p.soc[0] = b;
        p.n_soc = 1;
        let mut z0 = [0.0; MAX_VARS];
        z0[0] = -2.0;
        z0[2] = 10.0;
        let out = p.solve(&z0, 1.0, &Settings::default());
        assert_eq!(out.status, SolveStatus::Converged);
        assert!((out.primal_objective - 2.0).abs() < 1e-9, "{out:?}");
        assert!((out.z[0] + 1.0).abs() < 1e-6 && out.z[1].abs() < 1e-6);
    }
}
