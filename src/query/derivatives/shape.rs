//! The derivatives of the interior-point answer with respect to the shapes' parameters θ
//! (`docs/derivatives.md`, "Derivatives with respect to the shapes").
//!
//! The program's rows `s = h − Gz` depend on θ through the shapes' body rows
//! (`crate::shapes::Shape::row_gradient`); the normalisation (`inv_scale`, the offset `Δ`) is
//! held fixed, which changes nothing at the optimum (α* = α'·dist/(κℓ) for any ℓ and κ).
//!
//! - **At the optimum** (the polished or refined point, multipliers `λ`), the envelope theorem
//!   on the Lagrangian `α' + λᵀ(Gz − h)` gives `∂α'/∂θ = λᵀ∂(Gz − h)/∂θ = −Σ_j λ_j ∂s_j/∂θ`
//!   with every row at the solution point `(u, α', w)`.
//! - **On the central path** (smoothing `μ`: `Gᵀλ = c`, `s∘λ = μe`), the linearised equations
//!   `GᵀDG dz = −dGᵀλ − GᵀDρ` (`ρ = ∂(Gz − h)/∂θ`, `D = L(s)⁻¹L(λ)`) are solved once, by the
//!   adjoint `(GᵀDG)ᵀ y = e_α`: `dα' = Σ_j [λ_j ∂s_j/∂θ|_Y + ω_j ∂s_j/∂θ|_Z]` with `Y` the point
//!   `(Qᵀy_ξ, y_α, y_w)` (no offset: a direction), `Z` the solution point and `ω = DᵀGy` (per
//!   orthant row `λ/s·g·y`; per cone `L(λ)L(s)⁻¹Gy`). The smoothed answer also depends on θ
//!   through the normalisation: substituting `x = Lη, α' = La` with `L = κℓ = ρ₁ + ρ₂` shows it is
//!   `dist·a(μ/L)` (`a` the central-path value of the program with a unit offset), so
//!   `dα/dθ = (dist/L)·(dα'/dθ − (μ/L)(∂α'/∂μ) ∂L/∂θ)`, with `∂α'/∂μ = −(Gy)·s⁻¹` from the same
//!   adjoint (`s∘dλ + λ∘ds = e`) and `∂L/∂θ` the bounding radius's derivative
//!   (`crate::shapes::Shape::radius_gradient`).

use super::*;
use crate::query::context::ShapeSink;
use crate::shapes::RowPoint;
use crate::solver::cones::jsolve;
use crate::solver::kkt::Lu;

/// `∂α*/∂θᵢ` of the interior-point answer for each shape whose buffer `sink` holds, at the
/// point `proximity` reports (the refined one when there is one); with `central`, the
/// central-path point's. False when a shape's derivative is not unique there (a hull's facet
/// of more than three corners carries weight); a smoothed answer whose adjoint cannot be
/// solved writes zeros and returns false.
pub(crate) fn shape_gradient<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    refined: &Refined<N>,
    central: Option<Real>,
    sink: &mut ShapeSink<'_>,
) -> bool {
    let shapes = [ctx.shape1, ctx.shape2];
    sink.zero(shapes);
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    let places = [&ctx.place1, &ctx.place2];
    let inv = ctx.inv_scale;
    let factor = ctx.frame.alpha_factor();
    // Shape i's point (u, α, w) for a vector v of the problem's variables: the solution point
    // (`offset`: u = Qᵀ(ξ − c)), or a direction (no offset).
    let point_of = |i: usize, v: &[Real; N], offset: bool| {
        let pl = places[i];
        let xi = Vec3::new(v[0], v[1], v[2]);
        let c = if offset { pl.center } else { Vec3::zeros() };
        let mut w = Vec3::zeros();
        for k in 0..pl.slacks.min(3) {
            w[k] = v[pl.slack_col + k];
        }
        RowPoint {
            u: pl.rotation.tr_mul(&(xi - c)),
            a: v[3],
            w,
        }
    };
    let scaled = |p: &RowPoint, k: Real| RowPoint {
        u: p.u * k,
        a: p.a * k,
        w: p.w * k,
    };
    let sum = |p: &RowPoint, q: &RowPoint| RowPoint {
        u: p.u + q.u,
        a: p.a + q.a,
        w: p.w + q.w,
    };
    let mut unique = true;
    let Some(mu) = central else {
        // The optimum: −λ_j at the solution point.
        let z = refined.z().unwrap_or(&outcome.z);
        let lam = |i: usize, j: usize| multiplier(problem, refined, &ranges[i], j);
        for i in 0..2 {
            let Some(out) = sink.d[i].as_deref_mut() else {
                continue;
            };
            let at = point_of(i, z, true);
            unique &= shapes[i].row_gradient(inv, &at, false, |j| scaled(&at, -lam(i, j)), out);
            sink.scale(i, shapes[i].parameter_count(), factor);
        }
        return unique;
    };
    // The central path: the adjoint y of the α column.
    let Some(y) = adjoint(problem) else {
        return false;
    };
    let z = &outcome.z;
    // ∂α'/∂μ = −(Gy)·s⁻¹ over every block.
    let mut dmu = 0.0;
    for row in problem.lp.iter() {
        dmu -= dotn(&row.g, &y) / row.s;
    }
    for b in problem.soc[..problem.n_soc].iter() {
        let gy = [0, 1, 2, 3].map(|c| dotn(&b.g[c], &y));
        let sinv = jsolve(&b.s, &[1.0, 0.0, 0.0, 0.0]);
        dmu -= (0..4).map(|c| gy[c] * sinv[c]).sum::<Real>();
    }
    let big_l = ctx.frame.kappa * ctx.frame.ell;
    let through_radius = -(mu / big_l) * dmu;
    for i in 0..2 {
        let Some(out) = sink.d[i].as_deref_mut() else {
            continue;
        };
        let count = shapes[i].parameter_count();
        // The normalisation's part first (the buffer holds ∂ρᵢ/∂θᵢ), then the rows'.
        unique &= shapes[i].radius_gradient(out);
        for v in out[..count].iter_mut() {
            *v *= through_radius;
        }
        let (at, dir) = (point_of(i, z, true), point_of(i, &y, false));
        let r = &ranges[i];
        // ω of shape i's cone, once.
        let omega_soc = r.soc.map(|k| {
            let b = &problem.soc[k];
            let gy = [0, 1, 2, 3].map(|c| dotn(&b.g[c], &y));
            jprod(&b.lam, &jsolve(&b.s, &gy))
        });
        let point = |j: usize| {
            let (lam, omega) = if j < 4 {
                match (r.soc, omega_soc) {
                    (Some(k), Some(om)) => (problem.soc[k].lam[j], om[j]),
                    _ => (0.0, 0.0),
                }
            } else {
                let row = &problem.lp[r.lp.start + j - 4];
                (row.lam, row.lam / row.s * dotn(&row.g, &y))
            };
            sum(&scaled(&dir, lam), &scaled(&at, omega))
        };
        unique &= shapes[i].row_gradient(inv, &at, true, point, out);
        sink.scale(i, count, factor);
    }
    unique
}

/// The multiplier of shape row `j` (the cone's components 0..4, orthant row `k` as `4 + k`)
/// of a shape with rows `r`: the refined point's (zero off its active set) when there is one,
/// else the polished one.
fn multiplier<const N: usize>(
    problem: &Problem<'_, N>,
    refined: &Refined<N>,
    r: &Rows,
    j: usize,
) -> Real {
    let lp = (j >= 4).then(|| r.lp.start + j - 4);
    match &refined.0 {
        Some((set, p)) => {
            for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
                let hit = match *eq {
                    Eq::Lp(row) => Some(row) == lp,
                    Eq::SocApex(k, c) | Eq::SocBound(k, c) => r.soc == Some(k) && c == j,
                    Eq::SocPad(k) => r.soc == Some(k) && j == 3,
                };
                if hit {
                    return p.lam[qi];
                }
            }
            0.0
        }
        None => match lp {
            Some(row) => problem.lp[row].lam_polished,
            None => r.soc.map_or(0.0, |k| problem.soc[k].lam_polished[j]),
        },
    }
}

/// `y` with `(GᵀDG)ᵀ y = e_α` at the final iterate (`D = L(s)⁻¹L(λ)`); `None` when that matrix
/// is singular or not finite.
fn adjoint<const N: usize>(problem: &Problem<'_, N>) -> Option<[Real; N]> {
    let m = problem.aho_matrix()?;
    let mut t = [[0.0; N]; N];
    for i in 0..N {
        for j in 0..N {
            t[i][j] = m[j][i];
        }
    }
    let mut e = [0.0; N];
    e[3] = 1.0;
    let y = Lu::factor(t)?.solve(&e);
    y.iter().all(|v| v.is_finite()).then_some(y)
}
