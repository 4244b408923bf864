//! The gradient of α* from the Lagrangian (envelope theorem): per shape,
//! `∂α/∂rᵢ = vᵢ/ℓ` and `∂α/∂q_k = −eᵢᵀ M_k vᵢ`, with `eᵢ = (x* − rᵢ)/ℓ` and `vᵢ = Σ λ a` over the
//! shape's rows (see the module docs of `derivatives`).

use super::active_set::eq_g;
use super::*;

/// `eᵢ` and `vᵢ` of both shapes: at the polished point with the polished multipliers of all
/// rows (`e`, `v`: what the smoothed Jacobian uses), and at the point reported (`er`, `vr`: the
/// refined point with the multipliers of its active set when there is one, else `e`, `v`).
pub(super) struct Lagrangian {
    pub(super) e: [Vec3; 2],
    pub(super) v: [Vec3; 2],
    pub(super) er: [Vec3; 2],
    pub(super) vr: [Vec3; 2],
}

/// [`Lagrangian`] of a solved problem (`z` its primal solution, `delta` the normalised offset,
/// `t` the solver's scale: solver = t · physical).
pub(super) fn lagrangian<const N: usize>(
    problem: &Problem<'_, N>,
    z: &[Real; N],
    refined: &Option<(ActiveSet, Point<N>)>,
    ranges: &[Rows; 2],
    delta: Vec3,
    t: Real,
) -> Lagrangian {
    // eᵢ and vᵢ = Σ λ̄ a over shape i's rows, with the polished multipliers λ̄ (all rows).
    let xi = Vec3::new(z[0], z[1], z[2]) / t;
    let e = [xi, xi - delta / t];
    let mut v = [Vec3::zeros(); 2];
    for (i, r) in ranges.iter().enumerate() {
        for row in &problem.lp[r.lp.clone()] {
            v[i] += gx(&row.g) * row.lam_polished;
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            for (gr, l) in b.g.iter().zip(b.lam_polished.iter()) {
                v[i] += gx(gr) * *l;
            }
        }
    }
    // At a refined point: its own eᵢ, and vᵢ over the active set only (the other multipliers
    // are zero there).
    let (er, vr) = match refined {
        Some((set, p)) => {
            let xi = Vec3::new(p.z[0], p.z[1], p.z[2]) / t;
            let mut vr = [Vec3::zeros(); 2];
            for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
                vr[set.shape[qi]] += gx(eq_g(problem, *eq)) * p.lam[qi];
            }
            ([xi, xi - delta / t], vr)
        }
        None => (e, v),
    };
    Lagrangian { e, v, er, vr }
}

/// ∂α*/∂(r₁, q₁, r₂, q₂) at the point reported, from the rotation axes `ω_k` of both poses
/// (zero for a shape that ignores its attitude).
pub(super) fn gradient(l: &Lagrangian, axes: &[[Vec3; 4]; 2], ell: Real) -> [Real; 14] {
    let mut grad = [0.0; 14];
    for i in 0..2 {
        let base = 7 * i;
        for j in 0..3 {
            grad[base + j] = l.vr[i][j] / ell;
        }
        // −eᵢ·(M_k vᵢ) = −ω_k·(vᵢ × eᵢ).
        let ve = l.vr[i].cross(&l.er[i]);
        for k in 0..4 {
            grad[base + 3 + k] = -axes[i][k].dot(&ve);
        }
    }
    grad
}
