//! Derivatives of the proximity solution with respect to both poses.
//!
//! In solver coordinates (lengths over ℓ, a fixed origin), shape i's rows are
//! `s = f_u·Qᵢᵀ(ξ − cᵢ) + f_α α + f_w·w` with `cᵢ = (rᵢ − o)/ℓ`, so with `a = Qᵢ f_u` (= −the
//! row's x-part of `G`) and `eᵢ = ξ − cᵢ = (x* − rᵢ)/ℓ`:
//! - `∂(Gz − h)/∂rᵢ = a/ℓ` (only `h = −a·cᵢ` moves), and `∂(Gz − h)/∂q_k = −(M_k a)·eᵢ` with
//!   `M_k = (∂Q/∂q_k) Qᵀ` (through the quaternion normalisation);
//! - the gradient of α is `λᵀ ∂(Gz − h)/∂θ` (envelope theorem on the Lagrangian), which per shape
//!   collapses to `∂α/∂rᵢ = vᵢ/ℓ` and `∂α/∂q_k = −eᵢᵀ M_k vᵢ` with `vᵢ = Σ λ a` over its rows;
//! - the Jacobian of `(x*, α*)` solves the implicit-function system of the KKT conditions with
//!   the complementarity linearised as `λ∘ds + s∘dλ = 0` (so `dλ = −D ds`, `D = L(s)⁻¹L(λ)` at
//!   the final iterate): `GᵀDG dz = −dGᵀλ − GᵀD (dG z − dh)`, reusing the LU factor of `GᵀDG`
//!   that the solver's final Newton polish already computed. (The NT-scaled form `Gᵀ W⁻² G`
//!   loses the tangential information in rounding once μ is small.)
//!
//! The solver works with the offset stretched by `t = κℓ/‖r₂ − r₁‖`; its primal iterate is `t`
//! times the physical one, its multipliers are the physical ones, and its normal matrix is the
//! `D` is invariant (L(ts)⁻¹L(λ) = L(s)⁻¹L(λ)/t … times t in GᵀDG on the physical scale), so
//! the physical system is the solver's `GᵀD'G dz = −dGᵀλ/t − GᵀD'ρ` with `D' = D/t`.
//!
//! The files: this one holds what they share (the active-set types, the rotation generators,
//! the row layout) and [`compute`], which asks `gradient.rs` for the gradient from the
//! Lagrangian (envelope theorem) and picks the Jacobian's route; `active_set.rs` identifies the active set and
//! forms its KKT system; `refine.rs` refines the solution point on it near an active-set
//! change; `jacobian.rs` solves the implicit-function systems on it; `smoothed.rs` is the
//! barrier-smoothed fallback; `crate::solver::dense` holds the small dense factorisations they use. The public
//! derivative queries built on these are in `query/differentiate.rs`.

use super::context::{Context, Full, Want};
use crate::error::Error;
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape, ShapeKind};
use crate::solver::cones::jprod;
use crate::solver::{DerivativeKind, Outcome, Problem, SolveStatus};

mod active_set;
mod gradient;
mod jacobian;
mod refine;
mod shape;
mod smoothed;
#[cfg(test)]
mod tests;

use active_set::identify;
pub(crate) use jacobian::consistent;
use jacobian::exact_jacobian;
pub(crate) use refine::refine_solution;
pub(crate) use shape::shape_gradient;
use smoothed::smoothed_jacobian;

/// Below this largest quaternion component (below 1e-150), derivatives with respect to q (which scale like
/// 1/‖q‖) may overflow a double.
const TINY_QUATERNION: Real = 1e-150;

/// When derivatives came out non-finite because a quaternion is so small that they overflow
/// (they scale like 1/‖q‖), the answer is a clear InvalidPose naming that quaternion instead
/// of a NaN or an infinity.
pub(crate) fn check_representable(
    derivatives_finite: bool,
    pose1: &Pose,
    pose2: &Pose,
) -> Result<(), Error> {
    if derivatives_finite {
        return Ok(());
    }
    for pose in [pose1, pose2] {
        let m = pose
            .quaternion()
            .iter()
            .fold(0.0, |a: Real, v| a.max(v.abs()));
        if m < TINY_QUATERNION {
            return Err(Error::InvalidPose(crate::error::ErrorDetail::new(
                "quaternion",
                m,
                "is so small that derivatives with respect to it (which scale like 1/|q|) \
                 overflow a double",
            )));
        }
    }
    Ok(())
}

/// Row ranges of one shape inside the stacked problem.
pub(crate) struct Rows {
    pub lp: std::ops::Range<usize>,
    pub soc: Option<usize>,
}

pub(crate) fn row_ranges(s1: &Shape, s2: &Shape) -> [Rows; 2] {
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

/// `M_k = (∂Q/∂q_k) Qᵀ` for k = 0..3, through the normalisation `Q = R(q/‖q‖)`. Each is the
/// cross-product matrix `[ω_k]×` of `ω_k = (2/‖q‖)(w ẽ_k − ẽ₀ v + v × ẽ_k)` with `(w, v)` the
/// unit quaternion and `(ẽ₀, ẽ_k)` the k-th unit vector of R⁴ (its component along q does not
/// rotate, so the projection of the normalisation drops out). Closed form, a few dozen flops.
pub(crate) fn rotation_generators(pose: &Pose) -> [Mat3; 4] {
    rotation_axes(pose).map(|o| Mat3::new(0.0, -o.z, o.y, o.z, 0.0, -o.x, -o.y, o.x, 0.0))
}

/// The axes `ω_k` of [`rotation_generators`] (`M_k u = ω_k × u`): with the raw quaternion
/// `(w, v)` of squared norm `n²`, `ω_k = (2/n²)(w ẽ_k − ẽ₀ v + v × ẽ_k)` (the unit quaternion's
/// form with `(2/‖q‖)` and `q/‖q‖` multiplied out: one division, no square root).
#[inline]
pub(crate) fn rotation_axes(pose: &Pose) -> [Vec3; 4] {
    let (k, [w, x, y, z]) = axes_scale(pose);
    [
        Vec3::new(-x * k, -y * k, -z * k),
        Vec3::new(w * k, z * k, -y * k),
        Vec3::new(-z * k, w * k, x * k),
        Vec3::new(y * k, -x * k, w * k),
    ]
}

/// `[ω_k·t]` for the four axes of [`rotation_axes`], without forming them:
/// `ω₀·t = −k v·t`, `ω_j·t = k (w t + t × v)_j` (`(v × ẽ_j)·t = ẽ_j·(t × v)`), `k = 2/n²`.
#[inline]
pub(crate) fn rotation_dots(pose: &Pose, t: &Vec3) -> [Real; 4] {
    let (k, [w, x, y, z]) = axes_scale(pose);
    let v = Vec3::new(x, y, z);
    let kt = t * k;
    let a = kt * w + kt.cross(&v);
    [-v.dot(&kt), a.x, a.y, a.z]
}

/// `(2/n², q)` for the pose's quaternion `q` of squared norm `n²` in [1e-150, 1e150] (any
/// quaternion a caller normalises, and far beyond), else the same for `q/c` with `c` its largest
/// component and `2/n²` divided by `c` (the axes are homogeneous of degree −1 in q), so that no
/// square overflows or underflows.
#[inline(always)]
fn axes_scale(pose: &Pose) -> (Real, [Real; 4]) {
    let q = pose.quaternion();
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    if (1e-150..=1e150).contains(&n2) {
        return (2.0 / n2, q);
    }
    scaled_axes_scale(q)
}

#[cold]
#[inline(never)]
fn scaled_axes_scale(q: [Real; 4]) -> (Real, [Real; 4]) {
    let c = q.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    let u = q.map(|x| x / c);
    let n2 = u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + u[3] * u[3];
    (2.0 / n2 / c, u)
}

/// `κℓ/dist`: solver coordinates are this times physical ones (ξ, α, slacks).
fn solver_scale(ctx: &Context<'_>) -> Real {
    1.0 / ctx.frame.point_factor() * ctx.frame.ell
}

/// The solution point refined on its active set (see [`refine_solution`]), when it was.
pub(crate) struct Refined<const N: usize>(Option<(ActiveSet, Point<N>)>);

impl<const N: usize> Refined<N> {
    /// Not refined.
    pub(crate) const NONE: Self = Refined(None);

    /// The refined primal point (solver coordinates), if there is one.
    pub(crate) fn z(&self) -> Option<&[Real; N]> {
        self.0.as_ref().map(|(_, p)| &p.z)
    }
}

/// Fills `full.gradient` (and `full.jacobian` when asked) from a solved problem.
///
/// Both are taken on the active set identified at the polished point ([`identify`]), or, when
/// [`refine_solution`] refined that point (near an active-set change: a weakly active row
/// whose slack the polish has not closed, or an inactive one whose multiplier it has not
/// zeroed), at the refined point `refined` on its active set: the point `proximity` reports.
/// Without an accepted polish only the barrier-smoothed Jacobian is available. With `central`
/// the problem holds a point of the central path (`Problem::solve_central`): both derivatives
/// are that point's, the gradient the Jacobian's α row.
pub(crate) fn compute<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    refined: &Refined<N>,
    want: Want,
    central: bool,
    full: &mut Full,
) {
    let frame = &ctx.frame;
    let ell = frame.ell;
    // κℓ/dist: solver = t · physical (ξ, α, w).
    let t = solver_scale(ctx);
    // A sphere's set does not depend on its attitude, so every derivative with respect to its
    // quaternion is exactly zero: zero generators make every route give exact zeros, and the
    // Jacobian skips those columns.
    let mut axes = [[Vec3::zeros(); 4]; 2];
    for (a, (shape, pose)) in axes
        .iter_mut()
        .zip([(ctx.shape1, ctx.pose1), (ctx.shape2, ctx.pose2)])
    {
        if !attitude_free(shape) {
            *a = rotation_axes(pose);
        }
    }
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    // The polish was accepted (else there is no reliable solution point, only the
    // barrier-smoothed Jacobian); near an active-set change, the refined point.
    let polished = problem.polished;
    let refined = &refined.0;
    let lag = gradient::lagrangian(problem, &outcome.z, refined, &ranges, frame.delta, t);
    full.gradient = gradient::gradient(&lag, &axes, ell);
    let gradient::Lagrangian { e, v, er, vr } = lag;
    // The kind of the derivatives is the Jacobian's: exact where the active set pins x*, so the
    // Jacobian is formed for a gradient query too (then cleared), to tell.
    let gradient = full.gradient;
    // The generators as matrices, for the Jacobian (written in place: `[_; 2].map` would copy
    // the 576-byte result several times).
    let skew = |o: &Vec3| Mat3::new(0.0, -o.z, o.y, o.z, 0.0, -o.x, -o.y, o.x, 0.0);
    let mut gens = [[Mat3::zeros(); 4]; 2];
    for (g, a) in gens.iter_mut().zip(&axes) {
        for (gk, ak) in g.iter_mut().zip(a) {
            *gk = skew(ak);
        }
    }
    if central {
        smoothed_jacobian(problem, &ranges, &gens, &e, &v, t, ell, full);
        homogeneous_in_offset(full, ctx);
        full.gradient = full.jacobian[3];
        if want < Want::Jacobian {
            full.jacobian = [[0.0; 14]; 4];
        }
        full.prox.derivatives = DerivativeKind::Smoothed;
        return;
    }
    let exact = match &refined {
        Some((set, p)) => exact_jacobian(
            &AtPoint {
                ctx,
                problem,
                set,
                p,
                gens: &gens,
                e: &er,
                v: &vr,
                t,
            },
            full,
        ),
        None if polished => {
            let mut set = ActiveSet::EMPTY;
            identify(problem, &ranges, &outcome.z, &[], &mut set) && {
                let p = Point::polished(problem, &set, &outcome.z);
                let at = AtPoint {
                    ctx,
                    problem,
                    set: &set,
                    p: &p,
                    gens: &gens,
                    e: &er,
                    v: &vr,
                    t,
                };
                exact_jacobian(&at, full)
            }
        }
        None => false,
    };
    if !exact || !consistent(&full.jacobian, &full.gradient, ell) {
        if want == Want::Jacobian {
            smoothed_jacobian(problem, &ranges, &gens, &e, &v, t, ell, full);
        }
        full.prox.derivatives = DerivativeKind::Smoothed;
    } else {
        full.prox.derivatives = DerivativeKind::Exact;
    }
    if want < Want::Jacobian {
        full.jacobian = [[0.0; 14]; 4];
        full.gradient = gradient;
    }
}

/// The translation columns of a central-path point's Jacobian. The smoothed answer is the
/// central-path point of the *normalised* program, whose offset has the fixed length κ: it
/// depends on the direction `u` of `r₂ − r₁` and the attitudes only, and is scaled back by
/// `‖r₂ − r₁‖`, so α and `x − r₁` are homogeneous of degree one in the offset (as the exact ones
/// are). The implicit-function system is right for moves across `u` (they leave the length
/// unchanged to first order); along `u` homogeneity gives the derivative exactly:
/// `∂o/∂r₂ = (∂o/∂r₂)(I − uuᵀ) + (o/‖r₂ − r₁‖) uᵀ` for `o = α, x − r₁`, then
/// `∂α/∂r₁ = −∂α/∂r₂` and `∂x/∂r₁ = I − ∂x/∂r₂`.
fn homogeneous_in_offset(full: &mut Full, ctx: &Context<'_>) {
    let frame = &ctx.frame;
    let u = frame.delta / frame.kappa;
    let rel = full.prox.point - ctx.pose1.position();
    for row in 0..4 {
        let o = if row < 3 { rel[row] } else { full.prox.alpha };
        let j = &mut full.jacobian[row];
        let d = Vec3::new(j[7], j[8], j[9]);
        let d = d - u * d.dot(&u) + u * (o / frame.dist);
        for c in 0..3 {
            j[7 + c] = d[c];
            let identity = if c == row { 1.0 } else { 0.0 };
            j[c] = identity - d[c];
        }
    }
}

/// Whether a shape is unchanged by every rotation about its origin (a sphere), so that nothing
/// depends on its quaternion.
#[inline]
fn attitude_free(shape: &Shape) -> bool {
    shape.solver_kind() == ShapeKind::Sphere
}

/// ρ = ∂(gᵀz − h)/∂θ for one row of shape `i` and pose parameter `p` (0..3 position, 3..7
/// quaternion): `a_p/ℓ` for a position, `−(M_k a)·eᵢ` for a quaternion.
#[inline]
fn rho_of<const N: usize>(g: &[Real; N], p: usize, gen: &[Mat3; 4], e: &Vec3, ell: Real) -> Real {
    let a = gx(g);
    if p < 3 {
        a[p] / ell
    } else {
        -(gen[p - 3] * a).dot(e)
    }
}

/// Largest order of the active-set system.
const MAX_ACTIVE: usize = 24;

/// The smaller storage size for the active-set system (see [`exact_jacobian`]).
const SMALL_ACTIVE: usize = 12;

/// The smallest storage size, for the reduced systems of pairs of curved shapes (order
/// `4 + 2`: two cones on their boundary).
const TINY_ACTIVE: usize = 6;

/// Storage sizes up to this are factored whole, padded (see [`xalpha_rows`]).
const PADDED_ACTIVE: usize = 6;

/// `−δ` on the diagonal of each equality row's own multiplier: when more constraints are
/// active than the dimension needs (a polytope vertex where four or more facets meet), the
/// multipliers are not unique and the unregularised system is singular although `dz` is
/// unique; the regularisation picks small multipliers and moves `dz` by O(δ).
const DUAL_REGULARISATION: Real = 1e-12;

/// How far (relative, see [`identify`]) the polished point may be from satisfying the KKT
/// conditions of its active set before it is refined. After a regular polish the residual is
/// at rounding level (≤ 1e-13); next to an active-set change it is 1e-7..1e-5 at the default
/// tolerance, and a residual r moves the derivatives by a few r.
const AMBIGUOUS: Real = 1e-9;

/// KKT residual (relative, see [`residual`]) at which the refinement stops.
const CONVERGED: Real = 1e-12;

/// Newton steps the refinement may take per active set (it converges quadratically: 1e-6 →
/// 1e-12 → rounding).
const MAX_NEWTON_STEPS: usize = 4;

/// Rows whose classification the refinement may flip when the refined point violates their
/// sign condition (λ ≥ 0 when active, s ≥ 0 when inactive).
const MAX_FLIPS: usize = 2;

/// Sign violations (relative to the scale of s or λ) below this are rounding.
const SIGN_TOLERANCE: Real = 1e-10;

/// Largest move of z (relative to 1 + max|z|) or of a multiplier (relative to the largest)
/// the refinement may make: it corrects an O(√μ) error, it does not find another solution.
const REFINE_MAX_STEP: Real = 1e-3;

/// One equation of the active-set system; its own multiplier is the unknown of the same index.
#[derive(Clone, Copy, Debug)]
enum Eq {
    /// Active orthant row j: `g_j dz = …`.
    Lp(usize),
    /// Cone k with its slack at the apex, component r: `g_r dz = …`.
    SocApex(usize, usize),
    /// The padded (identically zero) component of cone k at the apex: `dλ₃ = …`.
    SocPad(usize),
    /// Cone k active on its boundary, component r of the linearised complementarity
    /// `−L(λ)G dz + L(s)dλ = …`.
    SocBound(usize, usize),
}

/// An identified active set: its equations in unknown order, and the shape of each.
#[derive(Clone, Copy, Debug)]
struct ActiveSet {
    eqs: [Eq; MAX_ACTIVE],
    shape: [usize; MAX_ACTIVE],
    n: usize,
}

impl ActiveSet {
    const EMPTY: Self = ActiveSet {
        eqs: [Eq::Lp(0); MAX_ACTIVE],
        shape: [0; MAX_ACTIVE],
        n: 0,
    };

    fn push(&mut self, eq: Eq, shape: usize) {
        self.eqs[self.n] = eq;
        self.shape[self.n] = shape;
        self.n += 1;
    }
}

/// A primal-dual point on an active set: `z` in solver coordinates and the multiplier of each
/// equation of the set (all others zero).
#[derive(Clone, Copy, Debug)]
struct Point<const N: usize> {
    z: [Real; N],
    lam: [Real; MAX_ACTIVE],
}

impl<const N: usize> Point<N> {
    /// The polished point: the solver's `z` and polished multipliers.
    fn polished(problem: &Problem<'_, N>, set: &ActiveSet, z: &[Real; N]) -> Self {
        let mut lam = [0.0; MAX_ACTIVE];
        for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
            lam[qi] = match *eq {
                Eq::Lp(j) => problem.lp[j].lam_polished,
                Eq::SocApex(k, c) | Eq::SocBound(k, c) => problem.soc[k].lam_polished[c],
                Eq::SocPad(k) => problem.soc[k].lam_polished[3],
            };
        }
        Point { z: *z, lam }
    }
}

/// The scales residuals are measured against: `1 + max|z|` for slacks (solver coordinates) and
/// the largest polished multiplier.
#[derive(Clone, Copy, Debug)]
struct Scales {
    s: Real,
    lam: Real,
}

#[inline]
fn dotn<const N: usize>(a: &[Real; N], b: &[Real; N]) -> Real {
    let mut r = 0.0;
    for i in 0..N {
        r += a[i] * b[i];
    }
    r
}

#[inline]
fn max_abs(u: &[Real; 4]) -> Real {
    u.iter().fold(0.0, |m: Real, v| m.max(v.abs()))
}

/// `worst` raised to `x`, with a NaN `x` winning (so that it is never taken for small).
#[inline]
fn worse(worst: Real, x: Real) -> Real {
    if x <= worst {
        worst
    } else {
        x
    }
}

/// The exact (non-smoothed) Jacobian on the active set `set` at the point `p`: the
/// implicit-function system of [`kkt_matrix`] with right-hand sides `−dGᵀλ` (stationarity),
/// What every form of the active-set Jacobian needs: the query, the solved problem, the active
/// set and the point on it, the rotation generators, `eᵢ` and `vᵢ`, and the scale `t` (solver =
/// t · physical).
#[derive(Clone, Copy)]
struct AtPoint<'r, 'q, 'a, const N: usize> {
    ctx: &'r Context<'q>,
    problem: &'r Problem<'a, N>,
    set: &'r ActiveSet,
    p: &'r Point<N>,
    gens: &'r [[Mat3; 4]; 2],
    e: &'r [Vec3; 2],
    v: &'r [Vec3; 2],
    t: Real,
}

/// `ρ = ∂(gᵀz − h)/∂θ` of any row for each pose parameter, with what all rows share
/// precomputed: `M_kᵀ eᵢ` for the quaternion columns (`−(M_k a)·eᵢ = −a·(M_kᵀ eᵢ)`), `1/ℓ` for
/// the position ones, and which shapes ignore their attitude (their columns stay zero).
struct RhoTable {
    u: [[Vec3; 4]; 2],
    inv_ell: Real,
    fixed: [bool; 2],
}

/// Derivatives at exactly coincident origins, where α* = 0 is not differentiable (α* is the
/// gauge of S₁ − S₂ at r₂ − r₁, homogeneous of degree one): zero is a valid subgradient of α*
/// and the rotation derivatives are exactly zero; the x rows of the Jacobian are left zero.
pub(crate) fn coincident(full: &mut Full) {
    full.gradient = [0.0; 14];
    full.jacobian = [[0.0; 14]; 4];
    full.prox.derivatives = DerivativeKind::Subgradient;
}
