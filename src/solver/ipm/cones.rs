//! Cone algebra for the nonnegative orthant and second-order cones of dimension ≤ 4: Jordan
//! products, Nesterov–Todd scaling and the step to the boundary.
//!
//! A second-order cone vector `u = (u₀, u₁)` is stored in `[Real; 4]`; a cone of dimension 3 is
//! stored with a last component that stays exactly zero (its row of `G` and `h` are zero, so
//! the slack, the multiplier and every direction keep it at zero), which lets every loop run
//! over a constant bound. `J = diag(1, −1, −1, −1)`. The NT scaling of `(s, λ)` is `W = η [w₀, w₁ᵀ; w₁, I + w₁w₁ᵀ/(1+w₀)]`
//! with `wᵀJw = 1`, so that `W λ = W⁻¹ s = v`, `W² = η²(2wwᵀ − J)`, `W⁻² = η⁻²(2Jw wᵀJ − J)`.

use crate::math::Real;

/// Dimension of a (padded) second-order cone block.
pub const SOC_MAX_DIM: usize = 4;
const D: usize = SOC_MAX_DIM;

/// A vector of a second-order cone block.
pub type SocVec = [Real; SOC_MAX_DIM];

/// `uᵀ J v`.
#[inline]
pub fn jdot(u: &SocVec, v: &SocVec) -> Real {
    let mut r = u[0] * v[0];
    for i in 1..D {
        r -= u[i] * v[i];
    }
    r
}

/// `uᵀ v`.
#[inline]
pub fn dot(u: &SocVec, v: &SocVec) -> Real {
    let mut r = 0.0;
    for i in 0..D {
        r += u[i] * v[i];
    }
    r
}

/// The Jordan product `u ∘ v = (uᵀv, u₀v₁ + v₀u₁)`.
#[inline]
pub fn jprod(u: &SocVec, v: &SocVec) -> SocVec {
    let mut r = [0.0; SOC_MAX_DIM];
    r[0] = dot(u, v);
    for i in 1..D {
        r[i] = u[0] * v[i] + v[0] * u[i];
    }
    r
}

/// Solves `v ∘ u = r` for `u` (`v` in the interior).
#[inline]
pub fn jsolve(v: &SocVec, r: &SocVec) -> SocVec {
    let det = jdot(v, v);
    let mut vr = 0.0;
    for i in 1..D {
        vr += v[i] * r[i];
    }
    let mut u = [0.0; SOC_MAX_DIM];
    u[0] = (v[0] * r[0] - vr) / det;
    for i in 1..D {
        u[i] = (r[i] - u[0] * v[i]) / v[0];
    }
    u
}

/// Is `u` strictly inside the cone?
#[inline]
pub fn interior(u: &SocVec) -> bool {
    u[0] > 0.0 && jdot(u, u) > 0.0
}

/// What the step to the boundary of one cone needs about the current point `u` (see
/// [`StepBase::rate`]), computed once per iteration and used for every direction.
#[derive(Clone, Copy, Debug, Default)]
pub struct StepBase {
    /// `ū = u/√(uᵀJu)`.
    ub: SocVec,
    /// `1/√(uᵀJu)`.
    inv_n: Real,
    /// `1/(ū₀ + 1)`.
    inv_ub0p1: Real,
}

impl StepBase {
    /// All zero (no point yet).
    pub const ZERO: Self = StepBase {
        ub: [0.0; SOC_MAX_DIM],
        inv_n: 0.0,
        inv_ub0p1: 0.0,
    };

    fn new(ub: SocVec, inv_n: Real) -> Self {
        StepBase {
            ub,
            inv_n,
            inv_ub0p1: 1.0 / (ub[0] + 1.0),
        }
    }

    /// The rate at which `u + t du` approaches the boundary: the largest `t` keeping it in the
    /// closed cone is `1/rate` when the rate is positive, and unbounded otherwise.
    #[inline]
    pub fn rate(&self, du: &SocVec) -> Real {
        let ub = &self.ub;
        let ub_du = jdot(ub, du);
        let rho0 = ub_du * self.inv_n;
        let factor = (ub_du + du[0]) * self.inv_ub0p1;
        let mut r1 = 0.0;
        for i in 1..D {
            let v = du[i] - factor * ub[i];
            r1 += v * v;
        }
        r1.sqrt() * self.inv_n - rho0
    }
}

/// The Nesterov–Todd scaling of one second-order cone block, with the reciprocals an iteration
/// needs computed once.
#[derive(Clone, Copy, Debug, Default)]
pub struct SocScaling {
    /// η = (sᵀJs / λᵀJλ)^{1/4}
    pub eta: Real,
    /// The scaling point w̄ with w̄ᵀJw̄ = 1.
    pub w: SocVec,
    /// The scaled point v = Wλ = W⁻¹s.
    pub v: SocVec,
    /// `1/η`.
    inv_eta: Real,
    /// `1/η²`.
    inv_eta2: Real,
    /// `1/(1 + w̄₀)`.
    inv_1pw0: Real,
    /// `1/(vᵀJv)` and `1/v₀`, for [`SocScaling::vsolve`].
    inv_vdet: Real,
    inv_v0: Real,
    /// Step-to-boundary data of `s` and `λ`.
    pub s_step: StepBase,
    /// See `s_step`.
    pub lam_step: StepBase,
}

impl SocScaling {
    /// All zero (no iterate yet).
    pub const ZERO: Self = SocScaling {
        eta: 0.0,
        w: [0.0; SOC_MAX_DIM],
        v: [0.0; SOC_MAX_DIM],
        inv_eta: 0.0,
        inv_eta2: 0.0,
        inv_1pw0: 0.0,
        inv_vdet: 0.0,
        inv_v0: 0.0,
        s_step: StepBase::ZERO,
        lam_step: StepBase::ZERO,
    };

    /// Computes the scaling of interior `s`, `lam`; `None` if either is not interior.
    pub fn new(s: &SocVec, lam: &SocVec) -> Option<SocScaling> {
        let sn2 = jdot(s, s);
        let ln2 = jdot(lam, lam);
        if !(sn2 > 0.0 && ln2 > 0.0 && s[0] > 0.0 && lam[0] > 0.0) {
            return None;
        }
        let sn = sn2.sqrt();
        let ln = ln2.sqrt();
        let (isn, iln) = (1.0 / sn, 1.0 / ln);
        let mut sb = [0.0; SOC_MAX_DIM];
        let mut lb = [0.0; SOC_MAX_DIM];
        for i in 0..D {
            sb[i] = s[i] * isn;
            lb[i] = lam[i] * iln;
        }
        let gamma = ((1.0 + dot(&sb, &lb)) * 0.5).sqrt();
        let i2g = 0.5 / gamma;
        let mut w = [0.0; SOC_MAX_DIM];
        w[0] = (sb[0] + lb[0]) * i2g;
        for i in 1..D {
            w[i] = (sb[i] - lb[i]) * i2g;
        }
        let eta = (sn * iln).sqrt();
        let inv_eta = 1.0 / eta;
        let mut sc = SocScaling {
            eta,
            w,
            v: [0.0; SOC_MAX_DIM],
            inv_eta,
            inv_eta2: inv_eta * inv_eta,
            inv_1pw0: 1.0 / (1.0 + w[0]),
            // v = W λ = η‖λ‖ W̄ λ̄ with det W̄ = 1 and (W̄ λ̄)₀ = γ, so vᵀJv = ‖s‖‖λ‖ and
            // v₀ = η ‖λ‖ γ: both reciprocals without a division on the critical path (and
            // vᵀJv without the cancellation of forming it from v near the boundary).
            inv_vdet: isn * iln,
            inv_v0: inv_eta * iln * 2.0 * i2g,
            s_step: StepBase::new(sb, isn),
            lam_step: StepBase::new(lb, iln),
        };
        sc.v = sc.apply(lam);
        if !sc.v.iter().all(|x| x.is_finite()) || !interior(&sc.v) {
            return None;
        }
        Some(sc)
    }

    /// `W u`.
    #[inline]
    pub fn apply(&self, u: &SocVec) -> SocVec {
        self.apply_signed(u, 1.0, self.eta)
    }

    /// `W⁻¹ u`.
    #[inline]
    pub fn apply_inv(&self, u: &SocVec) -> SocVec {
        self.apply_signed(u, -1.0, self.inv_eta)
    }

    #[inline]
    fn apply_signed(&self, u: &SocVec, sign: Real, k: Real) -> SocVec {
        let w = &self.w;
        let mut w1u1 = 0.0;
        for i in 1..D {
            w1u1 += w[i] * u[i];
        }
        let mut r = [0.0; SOC_MAX_DIM];
        r[0] = k * (w[0] * u[0] + sign * w1u1);
        let c = sign * u[0] + w1u1 * self.inv_1pw0;
        for i in 1..D {
            r[i] = k * (u[i] + c * w[i]);
        }
        r
    }

    /// `W² u = η²(2w(wᵀu) − Ju)`.
    #[inline]
    pub fn apply_sq(&self, u: &SocVec) -> SocVec {
        let e2 = self.eta * self.eta;
        let wu = dot(&self.w, u);
        let mut r = [0.0; SOC_MAX_DIM];
        r[0] = e2 * (2.0 * self.w[0] * wu - u[0]);
        for i in 1..D {
            r[i] = e2 * (2.0 * self.w[i] * wu + u[i]);
        }
        r
    }

    /// `W⁻² u = η⁻²(2Jw(wᵀJu) − Ju)`.
    #[inline]
    pub fn apply_inv_sq(&self, u: &SocVec) -> SocVec {
        let e2 = self.inv_eta2;
        let wju = jdot(&self.w, u);
        let mut r = [0.0; SOC_MAX_DIM];
        r[0] = e2 * (2.0 * self.w[0] * wju - u[0]);
        for i in 1..D {
            r[i] = e2 * (-2.0 * self.w[i] * wju + u[i]);
        }
        r
    }

    /// `η⁻²`: `W⁻² = η⁻²(2Jw̄ w̄ᵀJ − J)`.
    #[inline]
    pub fn inv_eta2(&self) -> Real {
        self.inv_eta2
    }

    /// Solves `v ∘ u = r` for `u` ([`jsolve`] with the scaled point, without dividing).
    #[inline]
    pub fn vsolve(&self, r: &SocVec) -> SocVec {
        let v = &self.v;
        let mut vr = 0.0;
        for i in 1..D {
            vr += v[i] * r[i];
        }
        let mut u = [0.0; SOC_MAX_DIM];
        u[0] = (v[0] * r[0] - vr) * self.inv_vdet;
        for i in 1..D {
            u[i] = (r[i] - u[0] * v[i]) * self.inv_v0;
        }
        u
    }
}

/// Largest `t` with `u + t du` in the closed cone (∞ when the whole ray stays inside);
/// `u` must be interior.
#[inline]
pub fn soc_step(u: &SocVec, du: &SocVec) -> Real {
    let inv_n = 1.0 / jdot(u, u).sqrt();
    let mut ub = [0.0; SOC_MAX_DIM];
    for i in 0..D {
        ub[i] = u[i] * inv_n;
    }
    let sigma = StepBase::new(ub, inv_n).rate(du);
    if sigma > 0.0 {
        1.0 / sigma
    } else {
        Real::INFINITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rand_interior(seed: u64, d: usize) -> SocVec {
        let mut x = seed;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let mut u = [0.0; SOC_MAX_DIM];
        let mut n2 = 0.0;
        for i in 1..d {
            u[i] = next();
            n2 += u[i] * u[i];
        }
        u[0] = n2.sqrt() + 0.1 + next().abs();
        u
    }

    #[test]
    fn nt_scaling_identities() {
        for d in [3, 4] {
            for seed in 0..50 {
                let s = rand_interior(seed, d);
                let l = rand_interior(seed + 1000, d);
                let sc = SocScaling::new(&s, &l).unwrap();
                let a = sc.apply(&l);
                let b = sc.apply_inv(&s);
                let c = sc.apply_sq(&l);
                let e = sc.apply_inv_sq(&s);
                let back = sc.apply_inv(&sc.apply(&s));
                for i in 0..D {
                    assert!((a[i] - b[i]).abs() < 1e-12, "Wλ = W⁻¹s");
                    assert!((c[i] - s[i]).abs() < 1e-12, "W²λ = s");
                    assert!((e[i] - l[i]).abs() < 1e-12, "W⁻²s = λ");
                    assert!((back[i] - s[i]).abs() < 1e-12, "W⁻¹W = I");
                }
                assert!((jdot(&sc.w, &sc.w) - 1.0).abs() < 1e-12);
                // The cached solve with v and the cached step rates match the plain ones.
                let r = rand_interior(seed + 2000, d);
                let (u1, u2) = (sc.vsolve(&r), jsolve(&sc.v, &r));
                let du = [-3.0 * r[0], r[1], r[2], r[3]];
                for i in 0..D {
                    assert!((u1[i] - u2[i]).abs() < 1e-12 * (1.0 + u2[i].abs()));
                }
                for (base, u) in [(&sc.s_step, &s), (&sc.lam_step, &l)] {
                    let (a, b) = (1.0 / base.rate(&du), soc_step(u, &du));
                    assert!((a - b).abs() < 1e-12 * b.abs(), "{a} {b}");
                }
            }
        }
    }

    #[test]
    fn jordan_solve_inverts_product() {
        let v = rand_interior(7, 4);
        let u = rand_interior(8, 4);
        let r = jprod(&v, &u);
        let back = jsolve(&v, &r);
        for i in 0..4 {
            assert!((back[i] - u[i]).abs() < 1e-12);
        }
    }

    #[test]
    fn step_to_boundary_matches_bisection() {
        for seed in 0..50 {
            let u = rand_interior(seed, 4);
            let mut du = rand_interior(seed + 99, 4);
            du[0] = -du[0] * 3.0;
            let t = soc_step(&u, &du);
            let at = |t: f64| {
                let mut p = [0.0; 4];
                for i in 0..4 {
                    p[i] = u[i] + t * du[i];
                }
                p[0] - (p[1] * p[1] + p[2] * p[2] + p[3] * p[3]).sqrt()
            };
            assert!(t.is_finite());
            assert!(
                at(t * 0.999) > 0.0 && at(t * 1.001) < 0.0,
                "seed {seed}: t = {t}"
            );
        }
    }
}
