//! One interior-point iteration's work on the blocks: the evaluation pass (residuals,
//! scalings, normal matrix), the Mehrotra predictor and corrector directions, and the iterative
//! refinement of the corrector.

use super::cones::{jprod, SocScaling};
use super::kkt::Normal;
use super::{dotn, fmax, gmul, gtmul_add, Evaluation, Problem, StepStats, D};
use crate::math::Real;

impl<const N: usize> Problem<'_, N> {
    /// `‖r_d + Gᵀdλ‖∞` for the direction held in the blocks: how far it misses the dual
    /// equation.
    pub(super) fn dual_equation_error(&self, rd: &[Real; N]) -> Real {
        let mut e = *rd;
        for row in self.lp.iter() {
            for i in 0..N {
                e[i] += row.g[i] * row.dlam;
            }
        }
        for b in self.soc[..self.n_soc].iter() {
            gtmul_add(&mut e, &b.g, &b.dlam, 1.0);
        }
        e.iter().map(|v| v.abs()).fold(0.0, Real::max)
    }

    /// The Mehrotra predictor-corrector direction with the factored normal matrix `kkt` and
    /// the evaluation `ev` of the current iterate: leaves `ds`, `dλ` of the corrector in the
    /// blocks and returns `dz` with the corrector's step statistics.
    pub(super) fn predictor_corrector(
        &mut self,
        kkt: &Normal<N>,
        ev: &Evaluation<N>,
        refine: bool,
    ) -> ([Real; N], StepStats) {
        // Predictor: complementarity target −v∘v.
        let aff = self.predictor(kkt, &ev.rhs);
        let t_aff = aff.max_step().min(1.0);
        let mu = ev.gap / self.degree();
        // Gap after the affine step, Σ (s + t ds)ᵀ(λ + t dλ), for σ.
        let gap_aff = ev.gap + t_aff * (aff.s1 + t_aff * aff.s2);
        let ratio = (gap_aff / ev.gap).clamp(0.0, 1.0);
        let sigma = ratio * ratio * ratio;
        // Corrector: −v∘v − (W⁻¹Δs_a)∘(WΔλ_a) + σμe.
        self.corrector(kkt, ev, refine, sigma * mu)
    }

    /// The centring direction: Newton's step towards `s∘λ = μe` (the corrector with no
    /// predictor terms and target `μ`).
    pub(super) fn centring(
        &mut self,
        kkt: &Normal<N>,
        ev: &Evaluation<N>,
        refine: bool,
        mu: Real,
    ) -> ([Real; N], StepStats) {
        for row in self.lp.iter_mut() {
            row.ds = 0.0;
            row.dlam = 0.0;
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            b.ds = [0.0; D];
            b.dlam = [0.0; D];
        }
        self.corrector(kkt, ev, refine, mu)
    }

    /// The residuals at `z` and the current slacks and multipliers, the scalings (every
    /// block's `λ/s`, reciprocals and NT scaling) and the normal matrix `Gᵀ W⁻² G`, in one pass
    /// over the blocks; first, the previous iteration's step `t` along the directions held in
    /// the blocks is taken when `STEP`.
    pub(super) fn evaluate<const STEP: bool>(&mut self, z: &[Real; N], t: Real) -> Evaluation<N> {
        let mut ev = Evaluation {
            rd: self.c,
            pres: 0.0,
            gap: 0.0,
            dobj: 0.0,
            lam_max: 0.0,
            interior: true,
            normal: Normal::zeros(),
            rhs: [0.0; N],
        };
        // Σ Gᵀ W⁻² t with t = r_p − s (the predictor's right-hand side, less r_d).
        let mut gwt = [0.0; N];
        for row in self.lp.iter_mut() {
            if STEP {
                row.s += t * row.ds;
                row.lam += t * row.dlam;
            }
            ev.lam_max = fmax(ev.lam_max, row.lam.abs());
            for i in 0..N {
                ev.rd[i] += row.g[i] * row.lam;
            }
            row.rp = dotn(&row.g, z) + row.s - row.h;
            ev.pres = fmax(ev.pres, row.rp.abs());
            ev.gap += row.s * row.lam;
            ev.dobj -= row.h * row.lam;
            ev.interior &= row.s > 0.0 && row.lam > 0.0;
            row.inv_s = 1.0 / row.s;
            row.inv_lam = 1.0 / row.lam;
            row.d = row.lam * row.inv_s;
            let t = row.rp - row.s;
            let dt = row.d * t;
            for i in 0..N {
                gwt[i] += dt * row.g[i];
            }
            ev.normal.add_rank1(row.d, &row.g);
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            if STEP {
                for i in 0..D {
                    b.s[i] += t * b.ds[i];
                    b.lam[i] += t * b.dlam[i];
                }
            }
            ev.lam_max = ev.lam_max.max(b.lam[0].abs());
            gtmul_add(&mut ev.rd, &b.g, &b.lam, 1.0);
            let gz = gmul(&b.g, z);
            for r in 0..D {
                b.rp[r] = gz[r] + b.s[r] - b.h[r];
                ev.pres = ev.pres.max(b.rp[r].abs());
                ev.gap += b.s[r] * b.lam[r];
                ev.dobj -= b.h[r] * b.lam[r];
            }
            match SocScaling::new(&b.s, &b.lam) {
                Some(sc) => {
                    b.sc = sc;
                    // W⁻² = η⁻²(2Jw wᵀJ − J): a rank-one term with a = Gᵀ J w, and −η⁻² GᵀJG.
                    let e2 = sc.inv_eta2();
                    let jw = [sc.w[0], -sc.w[1], -sc.w[2], -sc.w[3]];
                    let mut a = [0.0; N];
                    gtmul_add(&mut a, &b.g, &jw, 1.0);
                    ev.normal.add_rank1(2.0 * e2, &a);
                    ev.normal.add_scaled(-e2, &b.gjg);
                    let mut t = [0.0; D];
                    for i in 0..D {
                        t[i] = b.rp[i] - b.s[i];
                    }
                    gtmul_add(&mut gwt, &b.g, &sc.apply_inv_sq(&t), 1.0);
                }
                None => ev.interior = false,
            }
        }
        for i in 0..N {
            ev.rhs[i] = -ev.rd[i] - gwt[i];
        }
        ev
    }

    /// The affine-scaling (predictor) direction, complementarity target `−v∘v`, from the
    /// right-hand side `rhs` that [`Problem::evaluate`] formed. With `t = r_p + W(v \ r_c)`
    /// the Newton system reduces to `H dz = −r_d − Gᵀ W⁻² t`, and for the target `−v∘v`,
    /// `W(v \ (−v∘v)) = −Wv = −s` exactly. Writes `ds`, `dλ` into the blocks and returns the
    /// step statistics.
    pub(super) fn predictor(&mut self, kkt: &Normal<N>, rhs: &[Real; N]) -> StepStats {
        let mut dz = *rhs;
        kkt.solve(&mut dz);
        // dλ = W⁻²(G dz + t) keeps the dual equation exact; ds from the primal equation
        // (not from W(v\rc) − W²dλ, which amplifies rounding by ‖W²‖ near the boundary), so
        // only the self-correcting complementarity equation absorbs rounding.
        let mut stats = StepStats::default();
        for row in self.lp.iter_mut() {
            let gdz = dotn(&row.g, &dz);
            row.dlam = row.d * (gdz + row.rp - row.s);
            row.ds = -row.rp - gdz;
            stats.lp(row);
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let gdz = gmul(&b.g, &dz);
            let mut gt = [0.0; D];
            for i in 0..D {
                gt[i] = gdz[i] + b.rp[i] - b.s[i];
                b.ds[i] = -b.rp[i] - gdz[i];
            }
            b.dlam = b.sc.apply_inv_sq(&gt);
            stats.soc(b);
        }
        stats
    }

    /// The corrector direction, complementarity target `−v∘v − (W⁻¹Δs_a)∘(WΔλ_a) + σμe`, with
    /// the predictor's `ds`, `dλ` still in the blocks. Its right-hand side is the predictor's
    /// plus what the target adds: `−(λ/s)·c·g` for an orthant row with `c = (σμ − ds dλ)/λ`,
    /// and `−Gᵀ W⁻¹ (v \ r)` for a cone with `r` the target's extra part (`W⁻² W = W⁻¹`);
    /// each block keeps its extra part in `ds` for the second pass. Writes `ds`, `dλ` into the
    /// blocks and returns `dz` with the step statistics; with `refine`, one pass of iterative
    /// refinement follows, from the dual residual gathered in the second pass.
    pub(super) fn corrector(
        &mut self,
        kkt: &Normal<N>,
        ev: &Evaluation<N>,
        refine: bool,
        sigma_mu: Real,
    ) -> ([Real; N], StepStats) {
        let mut rhs = ev.rhs;
        for row in self.lp.iter_mut() {
            let extra = (sigma_mu - row.ds * row.dlam) * row.inv_lam;
            row.ds = extra;
            let k = row.d * extra;
            for i in 0..N {
                rhs[i] -= k * row.g[i];
            }
        }
        // Each cone's W⁻¹(v \ r) goes to its `ds` (the predictor's is not needed after this).
        for b in self.soc[..self.n_soc].iter_mut() {
            let a = b.sc.apply_inv(&b.ds);
            let c = b.sc.apply(&b.dlam);
            let mut r = jprod(&a, &c);
            for v in r.iter_mut() {
                *v = -*v;
            }
            r[0] += sigma_mu;
            let u = b.sc.apply_inv(&b.sc.vsolve(&r));
            gtmul_add(&mut rhs, &b.g, &u, -1.0);
            b.ds = u;
        }
        let mut dz = rhs;
        kkt.solve(&mut dz);
        // The dual equation's residual −r_d − Gᵀdλ, for the refinement.
        let mut e = [0.0; N];
        let mut stats = StepStats::default();
        for row in self.lp.iter_mut() {
            let t = row.rp - row.s + row.ds;
            let gdz = dotn(&row.g, &dz);
            row.dlam = row.d * (gdz + t);
            row.ds = -row.rp - gdz;
            stats.lp(row);
            if refine {
                for i in 0..N {
                    e[i] -= row.g[i] * row.dlam;
                }
            }
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let u = b.ds;
            let gdz = gmul(&b.g, &dz);
            let mut gt = [0.0; D];
            for i in 0..D {
                gt[i] = gdz[i] + b.rp[i] - b.s[i];
                b.ds[i] = -b.rp[i] - gdz[i];
            }
            let dl = b.sc.apply_inv_sq(&gt);
            for i in 0..D {
                b.dlam[i] = dl[i] + u[i];
            }
            stats.soc(b);
            if refine {
                gtmul_add(&mut e, &b.g, &b.dlam, -1.0);
            }
        }
        if refine {
            for i in 0..N {
                e[i] -= ev.rd[i];
            }
            self.refine(kkt, &ev.rd, e, &mut dz, &mut stats);
        }
        (dz, stats)
    }

    /// Iterative refinement of the dual equation `Gᵀdλ = −r_d`: forming `Gᵀ W⁻² G` and
    /// applying `W⁻²` round differently when the scaling is extreme, so the correction
    /// `H δz = e_d`, `δλ = W⁻² G δz`, `δs = −G δz` (which leaves the primal and linearised
    /// complementarity equations unchanged) is applied once, from the residual
    /// `e = −r_d − Gᵀdλ` the corrector gathered, unless it is already at rounding level.
    /// `stats` is updated to the corrected direction.
    pub(super) fn refine(
        &mut self,
        kkt: &Normal<N>,
        rd: &[Real; N],
        mut e: [Real; N],
        dz: &mut [Real; N],
        stats: &mut StepStats,
    ) {
        let scale = rd.iter().map(|v| v.abs()).fold(1e-3, Real::max);
        let err = e.iter().map(|v| v.abs()).fold(0.0, Real::max);
        if !(err > 1e-15 * scale) {
            return;
        }
        kkt.solve(&mut e);
        for i in 0..N {
            dz[i] += e[i];
        }
        *stats = StepStats::default();
        for row in self.lp.iter_mut() {
            let gd = dotn(&row.g, &e);
            row.dlam += row.d * gd;
            row.ds -= gd;
            stats.lp(row);
        }
        for b in self.soc[..self.n_soc].iter_mut() {
            let gd = gmul(&b.g, &e);
            let dl = b.sc.apply_inv_sq(&gd);
            for i in 0..D {
                b.ds[i] -= gd[i];
                b.dlam[i] += dl[i];
            }
            stats.soc(b);
        }
    }
}
