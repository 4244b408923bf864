//! Derivatives of the proximity solution with respect to both poses.
//!
//! In solver coordinates (lengths over ℓ, a fixed origin), shape i's rows are
//! `s = f_u·Qᵢᵀ(ξ − cᵢ) + f_α α + f_w·w` with `cᵢ = (rᵢ − o)/ℓ`, so with `a = Qᵢ f_u` (= −the
//! row's x-part of `G`) and `eᵢ = ξ − cᵢ = (x* − rᵢ)/ℓ`:
//! - `∂(Gz − h)/∂rᵢ = −a/ℓ` as a row of `G` would give, and `∂(Gz − h)/∂q_k = −(M_k a)·eᵢ` with
//!   `M_k = (∂Q/∂q_k) Qᵀ` (through the quaternion normalisation);
//! - the gradient of α is `λᵀ ∂(Gz − h)/∂θ` (envelope theorem on the Lagrangian), which per shape
//!   collapses to `∂α/∂rᵢ = vᵢ/ℓ` and `∂α/∂q_k = −eᵢᵀ M_k vᵢ` with `vᵢ = Σ λ a` over its rows;
//! - the Jacobian of `(x*, α*)` solves the implicit-function system
//!   `Gᵀ W⁻² G dz = −dGᵀλ − Gᵀ W⁻² (dG z − dh)` with the solver's final scaling and factor.
//!
//! The solver works with the offset stretched by `t = κℓ/‖r₂ − r₁‖`; its primal iterate is `t`
//! times the physical one, its multipliers are the physical ones, and its normal matrix is the
//! physical one over `t`, which the formulas below account for.

use super::proximity::{query, Context, Full, Options, Proximity, Want};
use crate::error::Error;
use crate::math::{rotation_derivatives, Mat3, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape};
use crate::solver::{Outcome, Problem};

/// Row ranges of one shape inside the stacked problem.
struct Rows {
    lp: std::ops::Range<usize>,
    soc: Option<usize>,
}

fn row_ranges(s1: &Shape, s2: &Shape) -> [Rows; 2] {
    let m1 = s1.lp_count();
    let m2 = s2.lp_count();
    let k1 = s1.soc_count();
    [
        Rows {
            lp: 0..m1,
            soc: (k1 == 1).then_some(0),
        },
        Rows {
            lp: m1..m1 + m2,
            soc: (s2.soc_count() == 1).then_some(k1),
        },
    ]
}

#[inline]
fn gx<const N: usize>(g: &[Real; N]) -> Vec3 {
    Vec3::new(-g[0], -g[1], -g[2])
}

/// `M_k = (∂Q/∂q_k) Qᵀ` for k = 0..3.
fn rotation_generators(pose: &Pose) -> [Mat3; 4] {
    let d = rotation_derivatives(pose.quaternion());
    let qt = pose.rotation().transpose();
    [d[0] * qt, d[1] * qt, d[2] * qt, d[3] * qt]
}

/// Fills `full.gradient` (and `full.jacobian` when asked) from a solved problem.
pub(crate) fn compute<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    want: Want,
    full: &mut Full,
) {
    let frame = &ctx.frame;
    let ell = frame.ell;
    let t = 1.0 / frame.point_factor() * ell; // κℓ/dist: solver = t · physical (ξ, α, w)
    let z = &outcome.z;
    let xi = Vec3::new(z[0], z[1], z[2]) / t;
    let e = [xi, xi - frame.delta / t];
    let gens = [
        rotation_generators(ctx.pose1),
        rotation_generators(ctx.pose2),
    ];
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    // vᵢ = Σ λ a over shape i's rows.
    let mut v = [Vec3::zeros(); 2];
    for (i, r) in ranges.iter().enumerate() {
        for row in &problem.lp[r.lp.clone()] {
            v[i] += gx(&row.g) * row.lam;
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            for (gr, l) in b.g.iter().zip(b.lam.iter()) {
                v[i] += gx(gr) * *l;
            }
        }
    }
    let mut grad = [0.0; 14];
    for i in 0..2 {
        let base = 7 * i;
        for j in 0..3 {
            grad[base + j] = v[i][j] / ell;
        }
        for k in 0..4 {
            grad[base + 3 + k] = -e[i].dot(&(gens[i][k] * v[i]));
        }
    }
    full.gradient = grad;
    if want < Want::Jacobian {
        return;
    }
    let kkt = match problem.normal_at_iterate() {
        Some(k) => k,
        None => {
            full.prox.status = crate::solver::SolveStatus::NumericalFailure;
            return;
        }
    };
    // One right-hand side per pose parameter: rhs = −dGᵀλ/t − Gᵀ W'⁻² ρ, where ρ = dG z − dh
    // is nonzero only on the moved shape's rows.
    for col in 0..14 {
        let i = col / 7;
        let p = col % 7;
        let r = &ranges[i];
        let mut rhs = [0.0; N];
        // ρ for one row with x-part g: position column j → −a_j/ℓ with a = −g_x, i.e. g_x[j]…
        let rho = |g: &[Real; N]| -> Real {
            let a = gx(g);
            if p < 3 {
                -a[p] / ell
            } else {
                -(gens[i][p - 3] * a).dot(&e[i])
            }
        };
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
            let w = b.scaling().apply_inv_sq(&rv);
            for (gr, wr) in b.g.iter().zip(w.iter()) {
                for j in 0..N {
                    rhs[j] -= gr[j] * wr;
                }
            }
        }
        kkt.solve(&mut rhs);
        for j in 0..3 {
            full.jacobian[j][col] = rhs[j] * ell;
        }
        full.jacobian[3][col] = rhs[3];
    }
}

/// Derivatives at exactly coincident origins, where α* = 0 is not differentiable (α* is the
/// gauge of S₁ − S₂ at r₂ − r₁, homogeneous of degree one): zero is a valid subgradient of α*
/// and the rotation derivatives are exactly zero; the x rows of the Jacobian are left zero.
pub(crate) fn coincident(
    _shape1: &Shape,
    _pose1: &Pose,
    _shape2: &Shape,
    _pose2: &Pose,
    _options: &Options,
    _want: Want,
    full: &mut Full,
) -> Result<(), Error> {
    full.gradient = [0.0; 14];
    full.jacobian = [[0.0; 14]; 4];
    Ok(())
}

/// ∂α*/∂(r₁, q₁, r₂, q₂): 14 numbers, `q` as given (through the normalisation), from the
/// Lagrangian at the primal-dual solution. Costs little beyond [`super::proximity`].
///
/// ```
/// use dcol::{gradient, Options, Pose, Shape};
/// let a = Shape::sphere(1.0).unwrap();
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([4.0, 0.0, 0.0]).unwrap();
/// let (prox, g) = gradient(&a, &pa, &a, &pb, &Options::default()).unwrap();
/// // α = ‖r₂ − r₁‖/2, so ∂α/∂r₂ = (1/2, 0, 0) and ∂α/∂r₁ = −(1/2, 0, 0).
/// assert!((prox.alpha - 2.0).abs() < 1e-9);
/// assert!((g[7] - 0.5).abs() < 1e-8 && (g[0] + 0.5).abs() < 1e-8);
/// ```
pub fn gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [Real; 14]), Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Gradient)?;
    Ok((f.prox, f.gradient))
}

/// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂): 4×14, rows (x₁, x₂, x₃, α), by the implicit function theorem
/// on the KKT conditions, reusing the solver's final scaling and factorisation.
pub fn jacobian(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [[Real; 14]; 4]), Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
    Ok((f.prox, f.jacobian))
}
