//! A primal-dual interior-point method for small cone programs over the nonnegative orthant and
//! second-order cones, written for DCOL's problems: `N` variables (a compile-time constant, so
//! every loop has a fixed bound), at most [`MAX_SOC`] second-order cones of dimension ≤ 4, and
//! any number of orthant rows held in a caller-provided slice, so the solver never allocates.
//!
//! The problem is `minimise cᵀz subject to s = h − G z ∈ K`. The method is that of CVXOPT's
//! `conelp` without equality constraints: Nesterov–Todd scaling, a Mehrotra
//! predictor-corrector, the normal equations `Gᵀ W⁻² G dz = r` factored as a dense `L D Lᵀ`,
//! one pass of iterative refinement of the corrector, and a final Newton polish (tried early,
//! at a relative gap of 1e-6, on problems without cones). Each iteration passes over the blocks
//! four times (five once refinement starts): once for the residuals, scalings, normal matrix
//! and the predictor's right-hand side, once for the predictor's `ds`, `dλ`, twice for the
//! corrector. It knows nothing of shapes.

pub mod cones;
pub mod kkt;
mod polish;
mod settings;
mod step;

pub use settings::{Settings, DEFAULT_MAX_ITERATIONS, DEFAULT_TOLERANCE};

use super::SolveStatus;
use crate::math::Real;
use cones::{jdot, jprod, jsolve, SocScaling, SocVec, SOC_MAX_DIM};
use kkt::{Lu, Normal, PivotFloor};

const D: usize = SOC_MAX_DIM;

/// Relative duality gap below which the final Newton polish is tried before the tolerance is
/// reached (see `Problem::solve_until`), in problems with orthant rows only. With a
/// second-order cone the interior iterate's point is only `O(√μ)` accurate, and a trial polish
/// (about half an iteration's work) failed often enough (ellipsoids, capsules) to cost more
/// than it saved.
const EARLY_POLISH_GAP: Real = 1e-6;

/// The early polish is kept only if it passes the convergence test with the tolerance times
/// this factor: at the tolerance itself the polished answer would be only as accurate as asked,
/// where the converged iterate's polish is usually accurate to rounding.
const EARLY_POLISH_MARGIN: Real = 1e-3;

/// Refinement runs once the duality gap (relative) is below this.
const REFINE_BELOW_GAP: Real = 1e-7;
/// A central-path point (`Problem::solve_central`) is reached when every block's
/// complementarity is within this relative deviation of the target.
const CENTRED: Real = 1e-10;

/// A Newton direction solved with a factor that kept weak pivots is used only if it satisfies
/// the dual equation `Gᵀdλ = −r_d` to this fraction of `max(‖r_d‖∞, dual residual limit)`.
const WEAK_PIVOT_DUAL_ERROR: Real = 0.1;

/// The most variables a problem may have (the largest `N` the crate instantiates).
pub const MAX_VARS: usize = 12;
/// The most second-order cone blocks a problem may have.
pub const MAX_SOC: usize = 3;

/// One nonnegative-orthant row `s = h − gᵀz ≥ 0` and its iterate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LpRow<const N: usize> {
    /// Row of `G`.
    pub g: [Real; N],
    /// Entry of `h`.
    pub h: Real,
    /// Primal slack.
    pub s: Real,
    /// Dual variable.
    pub lam: Real,
    /// Dual variable after the final Newton polish (equal to `lam` when it was not applied).
    pub lam_polished: Real,
    ds: Real,
    dlam: Real,
    rp: Real,
    /// `λ/s`, `1/s` and `1/λ` at the current iterate (set with the scalings), so that an
    /// iteration divides twice per row rather than a dozen times.
    d: Real,
    inv_s: Real,
    inv_lam: Real,
}

impl<const N: usize> LpRow<N> {
    /// An all-zero row.
    pub const ZERO: Self = LpRow {
        g: [0.0; N],
        h: 0.0,
        s: 0.0,
        lam: 0.0,
        lam_polished: 0.0,
        ds: 0.0,
        dlam: 0.0,
        rp: 0.0,
        d: 0.0,
        inv_s: 0.0,
        inv_lam: 0.0,
    };
}

impl<const N: usize> Default for LpRow<N> {
    fn default() -> Self {
        Self::ZERO
    }
}

/// One second-order cone block `s = h − G z ∈ Q₄` (a 3-dimensional cone has a zero last row)
/// and its iterate.
#[derive(Clone, Copy, Debug)]
pub struct SocBlock<const N: usize> {
    /// Rows of `G`.
    pub g: [[Real; N]; D],
    /// `h`.
    pub h: SocVec,
    /// Primal slack.
    pub s: SocVec,
    /// Dual variable.
    pub lam: SocVec,
    /// Dual variable after the final Newton polish (equal to `lam` when it was not applied).
    pub lam_polished: SocVec,
    ds: SocVec,
    dlam: SocVec,
    rp: SocVec,
    sc: SocScaling,
    /// `Gᵀ J G`, constant during a solve.
    gjg: [[Real; N]; N],
}

impl<const N: usize> SocBlock<N> {
    /// An empty block.
    pub const EMPTY: Self = SocBlock {
        g: [[0.0; N]; D],
        h: [0.0; D],
        s: [0.0; D],
        lam: [0.0; D],
        lam_polished: [0.0; D],
        ds: [0.0; D],
        dlam: [0.0; D],
        rp: [0.0; D],
        sc: SocScaling::ZERO,
        gjg: [[0.0; N]; N],
    };

    /// The scaling computed at the last iterate (valid after a solve).
    pub fn scaling(&self) -> &SocScaling {
        &self.sc
    }

    /// `Gᵀ J G` with `J = diag(1, −1, −1, −1)` (valid after a solve; it depends on `g` only).
    pub fn gjg(&self) -> &[[Real; N]; N] {
        &self.gjg
    }
}

/// A cone program `min cᵀz s.t. h − G z ∈ K` with its iterate.
#[derive(Debug)]
pub struct Problem<'a, const N: usize> {
    /// Objective.
    pub c: [Real; N],
    /// Orthant rows (caller-provided storage).
    pub lp: &'a mut [LpRow<N>],
    /// Second-order cone blocks (first `n_soc` used).
    pub soc: [SocBlock<N>; MAX_SOC],
    /// Number of second-order cone blocks.
    pub n_soc: usize,
    /// LU factor of `GᵀDG`, `D = L(s)⁻¹L(λ)`, at the final iterate (set by the polish, also
    /// when its step is then refused).
    pub aho: Option<Lu<N>>,
    /// Whether the final polish was accepted: the returned point and `lam_polished` are the
    /// polished ones (when false, `lam_polished` equals `lam`).
    pub polished: bool,
}

/// A question "is the optimal value below `value`?" for [`Problem::solve_until`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Threshold {
    /// The threshold on the optimal value.
    pub value: Real,
    /// `‖z*‖₁ ≤ z_bound_abs + z_bound_rel · (optimal value)`, for the certified lower bound.
    pub z_bound_abs: Real,
    /// See `z_bound_abs`.
    pub z_bound_rel: Real,
    /// Stop also when the value is proven below the threshold.
    pub stop_below: bool,
}

/// What a solve returns besides the iterate left in the problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<const N: usize> {
    /// How it ended.
    pub status: SolveStatus,
    /// Newton steps taken.
    pub iterations: u32,
    /// The primal variables (after the polish, when it was accepted).
    pub z: [Real; N],
    /// `cᵀz`.
    pub primal_objective: Real,
    /// `−hᵀλ`.
    pub dual_objective: Real,
    /// With [`Problem::solve_until`]: `Some(true)` when the optimal value was proven below the
    /// threshold, `Some(false)` when proven above it, `None` when the solve ran to its end.
    pub decided: Option<bool>,
}

/// What one pass over the blocks at an iterate finds (see `Problem::evaluate`).
struct Evaluation<const N: usize> {
    /// Dual residual `c + Gᵀλ`.
    rd: [Real; N],
    /// `‖G z + s − h‖∞`.
    pres: Real,
    /// `sᵀλ`.
    gap: Real,
    /// `−hᵀλ`.
    dobj: Real,
    /// Largest multiplier (a cone's first component).
    lam_max: Real,
    /// Whether every slack and multiplier is strictly inside its cone.
    interior: bool,
    /// `Gᵀ W⁻² G`, not yet factored.
    normal: Normal<N>,
    /// Right-hand side of the predictor's normal equations, `−r_d − Gᵀ W⁻² (r_p − s)`.
    rhs: [Real; N],
}

/// What the step length and Mehrotra's centring need about a direction, gathered while it is
/// formed.
#[derive(Clone, Copy, Debug, Default)]
struct StepStats {
    /// The largest rate at which a block approaches its cone boundary (step to it: `1/rate`).
    rate: Real,
    /// `sᵀdλ + λᵀds`.
    s1: Real,
    /// `dsᵀdλ`.
    s2: Real,
}

impl StepStats {
    #[inline(always)]
    fn lp<const N: usize>(&mut self, row: &LpRow<N>) {
        self.rate = fmax(
            fmax(self.rate, -row.ds * row.inv_s),
            -row.dlam * row.inv_lam,
        );
        self.s1 += row.s * row.dlam + row.lam * row.ds;
        self.s2 += row.ds * row.dlam;
    }

    #[inline(always)]
    fn soc<const N: usize>(&mut self, b: &SocBlock<N>) {
        self.rate = fmax(
            fmax(self.rate, b.sc.s_step.rate(&b.ds)),
            b.sc.lam_step.rate(&b.dlam),
        );
        for i in 0..D {
            self.s1 += b.s[i] * b.dlam[i] + b.lam[i] * b.ds[i];
            self.s2 += b.ds[i] * b.dlam[i];
        }
    }

    /// Largest step in (0, ∞] keeping `s` and `λ` in the cones.
    fn max_step(&self) -> Real {
        if self.rate > 0.0 {
            1.0 / self.rate
        } else {
            Real::INFINITY
        }
    }
}

/// `max(a, b)` that keeps `a` when `b` is NaN, as one comparison (`f64::max` also handles a
/// NaN `a`, at a few more instructions in the hottest loops).
#[inline(always)]
fn fmax(a: Real, b: Real) -> Real {
    if b > a {
        b
    } else {
        a
    }
}

#[inline(always)]
fn dotn<const N: usize>(a: &[Real; N], b: &[Real; N]) -> Real {
    let mut r = 0.0;
    for i in 0..N {
        r += a[i] * b[i];
    }
    r
}

/// `G u` for a cone block's rows.
#[inline(always)]
fn gmul<const N: usize>(g: &[[Real; N]; D], z: &[Real; N]) -> SocVec {
    [
        dotn(&g[0], z),
        dotn(&g[1], z),
        dotn(&g[2], z),
        dotn(&g[3], z),
    ]
}

/// `acc += Gᵀ u` for a cone block's rows.
#[inline(always)]
fn gtmul_add<const N: usize>(acc: &mut [Real; N], g: &[[Real; N]; D], u: &SocVec, k: Real) {
    for (r, gr) in g.iter().enumerate() {
        let ur = k * u[r];
        for i in 0..N {
            acc[i] += gr[i] * ur;
        }
    }
}

impl<'a, const N: usize> Problem<'a, N> {
    /// An empty problem with storage for its orthant rows.
    pub fn new(lp: &'a mut [LpRow<N>]) -> Self {
        Problem {
            c: [0.0; N],
            lp,
            soc: [SocBlock::EMPTY; MAX_SOC],
            n_soc: 0,
            aho: None,
            polished: false,
        }
    }

    /// Largest |h| entry over all blocks.
    fn h_max(&self) -> Real {
        self.lp
            .iter()
            .map(|r| r.h.abs())
            .chain(
                self.soc[..self.n_soc]
                    .iter()
                    .flat_map(|b| b.h.iter().map(|v| v.abs())),
            )
            .fold(0.0, Real::max)
    }

    fn degree(&self) -> Real {
        (self.lp.len() + self.n_soc) as Real
    }
    /// `GᵀDG` with `D = L(s)⁻¹L(λ)` at the current iterate (`None` if not finite).
    pub fn aho_matrix(&self) -> Option<[[Real; N]; N]> {
        let mut m = [[0.0; N]; N];
        for row in self.lp.iter() {
            let d = row.lam / row.s;
            for i in 0..N {
                let gi = row.g[i] * d;
                if gi == 0.0 {
                    continue;
                }
                for j in 0..N {
                    m[i][j] += gi * row.g[j];
                }
            }
        }
        for k in 0..self.n_soc {
            let b = &self.soc[k];
            for j in 0..N {
                let col = [b.g[0][j], b.g[1][j], b.g[2][j], b.g[3][j]];
                let dc = self.soc_d(k, &col);
                for (r, gr) in b.g.iter().enumerate() {
                    for i in 0..N {
                        m[i][j] += gr[i] * dc[r];
                    }
                }
            }
        }
        m.iter().flatten().all(|v| v.is_finite()).then_some(m)
    }

    /// `D u = L(s)⁻¹(λ∘u)` for cone block `k` at the final iterate: the linearised
    /// complementarity `λ∘ds + s∘dλ = 0` gives `dλ = −D ds`.
    pub fn soc_d(&self, k: usize, u: &SocVec) -> SocVec {
        let b = &self.soc[k];
        jsolve(&b.s, &jprod(&b.lam, u))
    }
    /// Runs the interior-point method from the primal point `z0`, with the dual started at
    /// `mu0 · s⁻¹` (perfectly centred). The final iterate stays in the problem's blocks.
    pub fn solve(&mut self, z0: &[Real; N], mu0: Real, settings: &Settings) -> Outcome<N> {
        self.solve_until(z0, mu0, settings, None)
    }

    /// [`Problem::solve`], stopping as soon as certified bounds decide whether the optimal value
    /// is below `threshold.value`. The upper bound is the primal objective of a primal-feasible
    /// iterate; the lower bound is `−hᵀλ − B‖r_d‖∞` where `B` bounds `‖z*‖₁` (the caller's
    /// `z_bound_abs + z_bound_rel · cᵀz`). Without `stop_below` only a proof that the value is
    /// above the threshold stops the solve (for a caller that needs the full answer below it).
    pub fn solve_until(
        &mut self,
        z0: &[Real; N],
        mu0: Real,
        settings: &Settings,
        threshold: Option<Threshold>,
    ) -> Outcome<N> {
        self.aho = None;
        self.polished = false;
        let outcome = self.iterate(z0, mu0, settings, threshold, None);
        // Without an accepted polish the multipliers of the last iterate stand for the polished
        // ones (derivatives of an unconverged solve are then those of its last iterate).
        if !self.polished {
            for row in self.lp.iter_mut() {
                row.lam_polished = row.lam;
            }
            for b in self.soc[..self.n_soc].iter_mut() {
                b.lam_polished = b.lam;
            }
        }
        outcome
    }

    /// The point of the central path at barrier parameter `mu`: `s∘λ = μe` for every block
    /// (`sλ = μ` for an orthant row) with the primal and dual equations satisfied to the
    /// tolerance. The interior-point iterations run until the duality measure comes within a
    /// factor of two of `mu` (or below it), then pure centring steps (Newton on the target
    /// `μe`, no predictor) converge to the point. No polish: the final iterate, its slacks and
    /// multipliers, stay in the blocks (`lam_polished` = `lam`) for the derivatives of the
    /// central-path point. `mu` must be positive and finite.
    pub fn solve_central(
        &mut self,
        z0: &[Real; N],
        mu0: Real,
        settings: &Settings,
        mu: Real,
    ) -> Outcome<N> {
        self.aho = None;
        self.polished = false;
        let outcome = self.iterate(z0, mu0, settings, None, Some(mu));
        for row in self.lp.iter_mut() {
            row.lam_polished = row.lam;
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            b.lam_polished = b.lam;
        }
        outcome
    }

    /// The largest deviation from the central path at `mu`, relative: `|sλ/μ − 1|` for an
    /// orthant row, `‖s∘λ − μe‖∞/μ` for a cone.
    fn centrality(&self, mu: Real) -> Real {
        let mut worst: Real = 0.0;
        for row in self.lp.iter() {
            worst = fmax(worst, (row.s * row.lam / mu - 1.0).abs());
        }
        for b in self.soc[..self.n_soc].iter() {
            let mut p = jprod(&b.s, &b.lam);
            p[0] -= mu;
            for v in p.iter() {
                worst = fmax(worst, v.abs() / mu);
            }
        }
        worst
    }

    /// The interior-point iterations of [`Problem::solve_until`] and, with `center`, of
    /// [`Problem::solve_central`].
    fn iterate(
        &mut self,
        z0: &[Real; N],
        mu0: Real,
        settings: &Settings,
        threshold: Option<Threshold>,
        center: Option<Real>,
    ) -> Outcome<N> {
        let mut z = *z0;
        // Initial slacks; the largest violation of strict interiority (negative when z0 is
        // strictly feasible) decides whether they must be pushed inside.
        let mut shift = Real::NEG_INFINITY;
        for row in self.lp.iter_mut() {
            row.s = row.h - dotn(&row.g, &z);
            shift = shift.max(-row.s);
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let gz = gmul(&b.g, &z);
            for i in 0..D {
                b.s[i] = b.h[i] - gz[i];
            }
            let nrm = (b.s[1] * b.s[1] + b.s[2] * b.s[2] + b.s[3] * b.s[3]).sqrt();
            shift = shift.max(nrm - b.s[0]);
            // Gᵀ J G (constant during the solve).
            let mut gjg = [[0.0; N]; N];
            for (r, gr) in b.g.iter().enumerate() {
                let sign = if r == 0 { 1.0 } else { -1.0 };
                for i in 0..N {
                    let gi = sign * gr[i];
                    if gi == 0.0 {
                        continue;
                    }
                    for j in 0..N {
                        gjg[i][j] += gi * gr[j];
                    }
                }
            }
            b.gjg = gjg;
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
            let sn2 = jdot(&b.s, &b.s);
            b.lam = [
                mu0 * b.s[0] / sn2,
                -mu0 * b.s[1] / sn2,
                -mu0 * b.s[2] / sn2,
                -mu0 * b.s[3] / sn2,
            ];
        }
        let hmax = self.h_max();
        let cmax = self.c.iter().map(|v| v.abs()).fold(0.0, Real::max);
        // Largest |G| entry: with the largest |λ| (|z|) it sets the size of the terms whose
        // rounding the dual (primal) residual cannot beat, so the residual tests are relative.
        let gmax = self
            .lp
            .iter()
            .flat_map(|r| r.g.iter())
            .chain(
                self.soc[..self.n_soc]
                    .iter()
                    .flat_map(|b| b.g.iter().flatten()),
            )
            .fold(0.0, |m: Real, v| m.max(v.abs()));
        let tol = settings.tolerance;
        let mut outcome = Outcome {
            status: SolveStatus::MaxIterations,
            iterations: 0,
            z,
            primal_objective: Real::NAN,
            dual_objective: Real::NAN,
            decided: None,
        };
        let mut iter = 0u32;
        // When the polish is refused (a degenerate optimum: parallel faces, a non-unique x*),
        // the objective is only as accurate as the duality gap, so one more interior-point
        // iteration is taken (it shrinks the gap about a hundredfold); `saved` keeps the
        // converged answer in case that iteration cannot be completed.
        let mut saved: Option<Outcome<N>> = None;
        // The step taken along the directions held in the blocks, applied by `evaluate`.
        let mut step: Option<Real> = None;
        // The early polish is tried at most once (where it fails, it fails again until the
        // iterate is converged), and only without cones (see `EARLY_POLISH_GAP`).
        let mut early_pending = self.n_soc == 0 && center.is_none();
        // With `center`: whether the centring steps have begun.
        let mut centring = false;
        loop {
            // Residuals, scalings and the normal matrix; then convergence.
            let ev = match step {
                Some(t) => self.evaluate::<true>(&z, t),
                None => self.evaluate::<false>(&z, 0.0),
            };
            let (rd, pres, gap, dobj) = (ev.rd, ev.pres, ev.gap, ev.dobj);
            let pobj = dotn(&self.c, &z);
            let dres = rd.iter().map(|v| v.abs()).fold(0.0, Real::max);
            outcome.z = z;
            outcome.iterations = iter;
            outcome.primal_objective = pobj;
            outcome.dual_objective = dobj;
            let scale = pobj.abs().max(1.0);
            let zmax = z.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
            let pres_limit = tol * (1.0 + hmax + gmax * zmax);
            let dres_limit = tol * (1.0 + cmax + gmax * ev.lam_max);
            if let Some(th) = threshold {
                let primal_feasible = pres <= pres_limit;
                if th.stop_below && primal_feasible && pobj < th.value {
                    outcome.decided = Some(true);
                    return outcome;
                }
                let zb = th.z_bound_abs + th.z_bound_rel * pobj.abs();
                if primal_feasible && dobj - zb * dres > th.value {
                    outcome.decided = Some(false);
                    return outcome;
                }
            }
            if let Some(mu) = center {
                if !ev.interior {
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
                centring |= gap <= 2.0 * mu * self.degree();
                if centring
                    && self.centrality(mu) <= CENTRED
                    && pres <= pres_limit
                    && dres <= dres_limit
                {
                    outcome.status = SolveStatus::Converged;
                    return outcome;
                }
                if iter >= settings.max_iterations {
                    outcome.status = SolveStatus::MaxIterations;
                    return outcome;
                }
            }
            let converged = center.is_none()
                && gap <= tol * scale
                && (pobj - dobj).abs() <= tol * scale
                && pres <= pres_limit
                && dres <= dres_limit;
            // Close to the optimum the final Newton polish alone usually reaches the tolerance
            // (it converges quadratically where the interior iterate converges linearly), so it
            // is tried early and its point kept when it passes the same test.
            if !converged
                && early_pending
                && saved.is_none()
                && ev.interior
                && gap <= EARLY_POLISH_GAP * scale
                && pres <= pres_limit
            {
                early_pending = false;
                let mut trial = outcome;
                if self.polish(&mut trial, tol * scale)
                    && self.polished_converged(
                        &trial.z,
                        EARLY_POLISH_MARGIN * tol * scale,
                        EARLY_POLISH_MARGIN * dres_limit,
                    )
                {
                    trial.status = SolveStatus::Converged;
                    return trial;
                }
                // Refused: the iterate moves on, so nothing of this attempt may describe it.
                self.aho = None;
                self.polished = false;
            }
            // The scalings are current (for derivatives) whatever happens next.
            if converged || saved.is_some() {
                outcome.status = SolveStatus::Converged;
                if !ev.interior {
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
                if self.polish(&mut outcome, tol * scale)
                    || saved.is_some()
                    || iter >= settings.max_iterations
                {
                    return outcome;
                }
                saved = Some(outcome);
            } else {
                if iter >= settings.max_iterations {
                    outcome.status = SolveStatus::MaxIterations;
                    return outcome;
                }
                if !ev.interior {
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
            }
            // The normal matrix is factored keeping every pivot above its own rounding level
            // (weakly curved directions stay resolved); if that kept a pivot the conservative
            // floor would have raised and the direction then misses the dual equation (the
            // pivot was rounding noise: a direction that is singular at the solution), the
            // direction is recomputed with the conservative floor.
            let mut kkt = ev.normal;
            if !kkt.factor(PivotFloor::Own) {
                if let Some(done) = saved {
                    return done;
                }
                outcome.status = SolveStatus::NumericalFailure;
                return outcome;
            }
            // Rounding in the normal equations only matters once the scaling is extreme.
            let refine = gap < REFINE_BELOW_GAP * scale;
            let direction = |p: &mut Self, kkt: &Normal<N>| match center {
                Some(mu) if centring => p.centring(kkt, &ev, refine, mu),
                _ => p.predictor_corrector(kkt, &ev, refine),
            };
            let (mut dz, mut stats) = direction(self, &kkt);
            if kkt.has_weak_pivot()
                && !(self.dual_equation_error(&rd) <= WEAK_PIVOT_DUAL_ERROR * dres.max(dres_limit))
            {
                kkt = ev.normal;
                if !kkt.factor(PivotFloor::Largest) {
                    if let Some(done) = saved {
                        return done;
                    }
                    outcome.status = SolveStatus::NumericalFailure;
                    return outcome;
                }
                (dz, stats) = direction(self, &kkt);
            }
            let t = (0.99 * stats.max_step()).min(1.0);
            if !(t > 0.0) || !dz.iter().all(|v| v.is_finite()) {
                if let Some(done) = saved {
                    return done;
                }
                outcome.status = SolveStatus::NumericalFailure;
                return outcome;
            }
            for i in 0..N {
                z[i] += t * dz[i];
            }
            step = Some(t);
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
        let mut rows = [LpRow::<2>::ZERO; 2];
        rows[0].g[0] = -1.0;
        rows[0].h = -1.0;
        rows[1].g[1] = -1.0;
        rows[1].h = -2.0;
        let mut p = Problem::new(&mut rows);
        p.c[0] = 1.0;
        p.c[1] = 1.0;
        let z0 = [5.0, 5.0];
        let out = p.solve(&z0, 1.0, &Settings::default());
        assert_eq!(out.status, SolveStatus::Converged);
        assert!((out.z[0] - 1.0).abs() < 1e-9 && (out.z[1] - 2.0).abs() < 1e-9);
        assert!((out.primal_objective - 3.0).abs() < 1e-9);
    }

    /// An orthant-only problem ends on the early polish: the answer is the vertex to rounding
    /// while the interior iterate's own gap is still above the tolerance.
    #[test]
    fn lp_ends_on_early_polish() {
        // min x₀ + 2x₁ + 3x₂ s.t. x ≥ (1, −2, 0.5), x₀ + x₁ + x₂ ≤ 10.
        let mut rows = [LpRow::<3>::ZERO; 4];
        for (i, lo) in [1.0, -2.0, 0.5].into_iter().enumerate() {
            // s = x_i − lo = h − g·x
            rows[i].g[i] = -1.0;
            rows[i].h = -lo;
        }
        rows[3].g = [1.0, 1.0, 1.0];
        rows[3].h = 10.0;
        let mut p = Problem::new(&mut rows);
        p.c = [1.0, 2.0, 3.0];
        let settings = Settings::default();
        let out = p.solve(&[3.0, 3.0, 3.0], 1.0, &settings);
        assert_eq!(out.status, SolveStatus::Converged);
        let expect = [1.0, -2.0, 0.5];
        for i in 0..3 {
            assert!((out.z[i] - expect[i]).abs() < 1e-14, "{out:?}");
        }
        assert!((out.primal_objective - (1.0 - 4.0 + 1.5)).abs() < 1e-14);
        let gap: Real = p.lp.iter().map(|r| r.s * r.lam).sum();
        assert!(
            gap > settings.tolerance && gap <= EARLY_POLISH_GAP * 10.0,
            "gap {gap}"
        );
        // The polished multipliers certify the vertex: λ = c on the three active rows.
        for i in 0..3 {
            assert!((p.lp[i].lam_polished - p.c[i]).abs() < 1e-12);
        }
        assert!(p.lp[3].lam_polished.abs() < 1e-12);
    }

    /// min t s.t. ‖(x − a)‖ ≤ t with x₀ ≤ −1 → distance from a = (1, 0) to the halfplane = 2.
    #[test]
    fn tiny_socp() {
        let mut rows = [LpRow::<3>::ZERO; 1];
        // s = −1 − x₀ ≥ 0  → h = −1, g = (1, 0, 0)
        rows[0].g[0] = 1.0;
        rows[0].h = -1.0;
        let mut p = Problem::new(&mut rows);
        p.c[2] = 1.0;
        // [t; x − a] ∈ Q₃ → s = h − Gz with s₀ = t, s₁ = x₀ − 1, s₂ = x₁
        let mut b = SocBlock::EMPTY;
        b.g[0][2] = -1.0;
        b.g[1][0] = -1.0;
        b.h[1] = -1.0;
        b.g[2][1] = -1.0;
        p.soc[0] = b;
        p.n_soc = 1;
        let z0 = [-2.0, 0.0, 10.0];
        let out = p.solve(&z0, 1.0, &Settings::default());
        assert_eq!(out.status, SolveStatus::Converged);
        assert!((out.primal_objective - 2.0).abs() < 1e-9, "{out:?}");
        assert!((out.z[0] + 1.0).abs() < 1e-6 && out.z[1].abs() < 1e-6);
    }
}
