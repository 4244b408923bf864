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

use super::proximity::{query, Context, Full, Options, Proximity, Want};
use crate::error::Error;
use crate::math::{Mat3, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape, ShapeKind};
use crate::solver::cones::jprod;
use crate::solver::{Outcome, Problem, SolveStatus};

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

/// The axes `ω_k` of [`rotation_generators`] (`M_k u = ω_k × u`).
pub(crate) fn rotation_axes(pose: &Pose) -> [Vec3; 4] {
    let q = pose.quaternion();
    // ‖q‖ without overflow or underflow: scale by the largest component first.
    let c = q.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    let u = q.map(|x| x / c);
    let n = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + u[3] * u[3]).sqrt();
    let (w, v) = (u[0] / n, Vec3::new(u[1] / n, u[2] / n, u[3] / n));
    let k = 2.0 / n / c;
    let axis = |j: usize| {
        let mut e = Vec3::zeros();
        e[j] = 1.0;
        (e * w + v.cross(&e)) * k
    };
    [-v * k, axis(0), axis(1), axis(2)]
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

/// The solution point near an active-set change. The polished point of a converged solve
/// satisfies the KKT conditions of its active set to rounding, except next to an active-set
/// change (a weakly active row whose slack and multiplier are both O(√μ), as at a contact
/// next to a cone's rim): there one Newton polish leaves it O(√μ) off (up to 1e-6 ℓ in x* at
/// the default tolerance), and [`refine`] (Newton's method on the KKT system of the identified
/// active set, with sign checks) finds the exact point. One pass over the rows decides
/// ([`ambiguity`]); the refinement itself runs rarely (12 of 7 201 queries in the benchmark's
/// sweep). `NONE` when not needed, not possible (no accepted polish) or not converged.
pub(crate) fn refine_solution<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
) -> Refined<N> {
    if outcome.status != SolveStatus::Converged
        || !problem.polished
        || ambiguity(problem, &outcome.z) <= AMBIGUOUS
    {
        return Refined::NONE;
    }
    let ranges = row_ranges(ctx.shape1, ctx.shape2);
    Refined(refine(problem, &ranges, &outcome.z, solver_scale(ctx)))
}

/// Fills `full.gradient` (and `full.jacobian` when asked) from a solved problem.
///
/// Both are taken on the active set identified at the polished point ([`identify`]), or, when
/// [`refine_solution`] refined that point (near an active-set change: a weakly active row
/// whose slack the polish has not closed, or an inactive one whose multiplier it has not
/// zeroed), at the refined point `refined` on its active set: the point `proximity` reports.
/// Without an accepted polish only the barrier-smoothed Jacobian is available.
pub(crate) fn compute<const N: usize>(
    ctx: &Context<'_>,
    problem: &Problem<'_, N>,
    outcome: &Outcome<N>,
    refined: &Refined<N>,
    want: Want,
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
    // eᵢ and vᵢ = Σ λ̄ a over shape i's rows, with the polished multipliers λ̄ (all rows).
    let z = &outcome.z;
    let xi = Vec3::new(z[0], z[1], z[2]) / t;
    let e = [xi, xi - frame.delta / t];
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
    let (er, vr) = match &refined {
        Some((set, p)) => {
            let xi = Vec3::new(p.z[0], p.z[1], p.z[2]) / t;
            let mut vr = [Vec3::zeros(); 2];
            for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
                vr[set.shape[qi]] += gx(eq_g(problem, *eq)) * p.lam[qi];
            }
            ([xi, xi - frame.delta / t], vr)
        }
        _ => (e, v),
    };
    let mut grad = [0.0; 14];
    for i in 0..2 {
        let base = 7 * i;
        for j in 0..3 {
            grad[base + j] = vr[i][j] / ell;
        }
        // −eᵢ·(M_k vᵢ) = −ω_k·(vᵢ × eᵢ).
        let ve = vr[i].cross(&er[i]);
        for k in 0..4 {
            grad[base + 3 + k] = -axes[i][k].dot(&ve);
        }
    }
    full.gradient = grad;
    if want < Want::Jacobian {
        return;
    }
    // The generators as matrices, for the Jacobian (written in place: `[_; 2].map` would copy
    // the 576-byte result several times).
    let skew = |o: &Vec3| Mat3::new(0.0, -o.z, o.y, o.z, 0.0, -o.x, -o.y, o.x, 0.0);
    let mut gens = [[Mat3::zeros(); 4]; 2];
    for (g, a) in gens.iter_mut().zip(&axes) {
        for (gk, ak) in g.iter_mut().zip(a) {
            *gk = skew(ak);
        }
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
        smoothed_jacobian(problem, &ranges, &gens, &e, &v, t, ell, full);
    }
}

/// Whether a shape is unchanged by every rotation about its origin (a sphere), so that nothing
/// depends on its quaternion.
#[inline]
fn attitude_free(shape: &Shape) -> bool {
    shape.kind() == ShapeKind::Sphere
}

/// Identities every correct Jacobian satisfies, checked before the active-set one is trusted (a
/// misidentified active set, e.g. a facet whose multiplier and slack are both ~1e-5 at the
/// default tolerance, can leave a nearly singular system that still factors): a common
/// translation moves x* with it and leaves α* alone (`J[:, r₁] + J[:, r₂] = [I₃; 0]`), and the
/// α row equals the Lagrangian gradient. Tolerances are in non-dimensional units (r columns
/// times ℓ, x rows over ℓ), far looser than either computation's error and far tighter than
/// any failure seen.
fn consistent(j: &[[Real; 14]; 4], grad: &[Real; 14], ell: Real) -> bool {
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

/// The slack `h − G z` of cone block `k` (solver coordinates).
#[inline]
fn soc_slack<const N: usize>(problem: &Problem<'_, N>, k: usize, z: &[Real; N]) -> [Real; 4] {
    let b = &problem.soc[k];
    [
        b.h[0] - dotn(&b.g[0], z),
        b.h[1] - dotn(&b.g[1], z),
        b.h[2] - dotn(&b.g[2], z),
        b.h[3] - dotn(&b.g[3], z),
    ]
}

/// The row of `G` an equation's multiplier multiplies.
#[inline]
fn eq_g<'p, const N: usize>(problem: &'p Problem<'_, N>, eq: Eq) -> &'p [Real; N] {
    match eq {
        Eq::Lp(j) => &problem.lp[j].g,
        Eq::SocApex(k, c) | Eq::SocBound(k, c) => &problem.soc[k].g[c],
        Eq::SocPad(k) => &problem.soc[k].g[3],
    }
}

/// Whether orthant row `j` is active at `z`: its polished multiplier exceeds its slack (both
/// vanish only at a degenerate row, where either choice is right), unless listed in `flips`.
#[inline]
fn lp_active<const N: usize>(
    problem: &Problem<'_, N>,
    j: usize,
    z: &[Real; N],
    flips: &[usize],
) -> bool {
    let row = &problem.lp[j];
    (row.lam_polished > row.h - dotn(&row.g, z)) != flips.contains(&j)
}

/// Writes into `set` the active set at the point `z` (solver coordinates) with the polished
/// multipliers λ̄. An orthant row is active when λ̄ > s (see [`lp_active`]); a cone is inactive
/// when λ̄₀ < 1e-6·s₀, and at its apex when s₀ < 1e-6·λ̄₀. False when the system would exceed
/// [`MAX_ACTIVE`].
fn identify<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    z: &[Real; N],
    flips: &[usize],
    set: &mut ActiveSet,
) -> bool {
    set.n = 0;
    for (i, r) in ranges.iter().enumerate() {
        for j in r.lp.clone() {
            if lp_active(problem, j, z, flips) {
                if N + set.n >= MAX_ACTIVE {
                    return false;
                }
                set.push(Eq::Lp(j), i);
            }
        }
        if let Some(k) = r.soc {
            let b = &problem.soc[k];
            let (s, l) = (soc_slack(problem, k, z), b.lam_polished);
            if soc_inactive(&s, &l) {
                continue; // dλ = 0
            }
            if N + set.n + 4 > MAX_ACTIVE {
                return false;
            }
            let apex = soc_apex(&s, &l);
            let padded = b.g[3].iter().all(|v| *v == 0.0) && b.h[3] == 0.0;
            for c in 0..4 {
                set.push(
                    if apex {
                        if c == 3 && padded {
                            Eq::SocPad(k)
                        } else {
                            Eq::SocApex(k, c)
                        }
                    } else {
                        Eq::SocBound(k, c)
                    },
                    i,
                );
            }
        }
    }
    true
}

/// How far the polished point `z` is from satisfying the KKT conditions of the active set
/// [`identify`] would choose there, the largest of (relative): the slack of an active row over
/// `1 + max|z|`, the multiplier of an inactive one over the largest multiplier, and for a cone
/// on its boundary `‖s∘λ̄‖∞/(s₀λ̄₀)` (the relative distance of s and λ̄ from complementary
/// boundary rays). The polish makes the multipliers exactly stationary, so that is the whole
/// residual. Cheap: one pass over the rows, no system.
fn ambiguity<const N: usize>(problem: &Problem<'_, N>, z: &[Real; N]) -> Real {
    let (mut ds, mut dl, mut rel, mut lam_max): (Real, Real, Real, Real) = (0.0, 0.0, 0.0, 0.0);
    for j in 0..problem.lp.len() {
        let row = &problem.lp[j];
        let (s, l) = (row.h - dotn(&row.g, z), row.lam_polished);
        lam_max = lam_max.max(l.abs());
        if l > s {
            ds = worse(ds, s.abs());
        } else {
            dl = worse(dl, l.abs());
        }
    }
    for k in 0..problem.n_soc {
        let (s, l) = (soc_slack(problem, k, z), problem.soc[k].lam_polished);
        lam_max = lam_max.max(l[0].abs());
        if soc_inactive(&s, &l) {
            dl = worse(dl, max_abs(&l));
        } else if soc_apex(&s, &l) {
            ds = worse(ds, max_abs(&s));
        } else {
            rel = worse(rel, max_abs(&jprod(&s, &l)) / (s[0] * l[0]));
        }
    }
    let s_scale = 1.0 + z.iter().fold(0.0, |m: Real, v| m.max(v.abs()));
    worse(worse(ds / s_scale, dl / lam_max), rel)
}

/// A cone whose polished multiplier is negligible against its slack: inactive.
#[inline]
fn soc_inactive(s: &[Real; 4], l: &[Real; 4]) -> bool {
    l[0] < 1e-6 * s[0]
}

/// An active cone whose slack is negligible against its multiplier: at its apex.
#[inline]
fn soc_apex(s: &[Real; 4], l: &[Real; 4]) -> bool {
    s[0] < 1e-6 * l[0]
}

/// The matrix of the active-set KKT system at `p`, on the physical scale (`dz` physical, so
/// slacks `s̄ = (h − G z)/t`): rows `0..N` stationarity `Gᵀdλ`, then one row per equation of
/// `set` (see [`enum@Eq`]); unknowns `[dz, dλ of each equation]`. It is the Jacobian of the KKT
/// residual, used both for Newton's method ([`refine`]) and the implicit function theorem.
fn kkt_matrix<const N: usize, const M: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    t: Real,
    a: &mut [[Real; M]; M],
) {
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let col = N + qi;
        let g = eq_g(problem, *eq);
        for q in 0..N {
            a[q][col] = g[q];
        }
        let row = &mut a[col];
        match *eq {
            Eq::Lp(_) | Eq::SocApex(..) => {
                row[..N].copy_from_slice(g);
                row[col] = -DUAL_REGULARISATION;
            }
            Eq::SocPad(_) => row[col] = 1.0,
            Eq::SocBound(k, c) => {
                let b = &problem.soc[k];
                let s = soc_slack(problem, k, &p.z).map(|v| v / t);
                let first = col - c;
                let l = [0, 1, 2, 3].map(|r| p.lam[qi - c + r]);
                // L(λ) row c and L(s̄) row c.
                let lrow = |u: &[Real; 4]| -> [Real; 4] {
                    if c == 0 {
                        *u
                    } else {
                        let mut r = [0.0; 4];
                        r[0] = u[c];
                        r[c] = u[0];
                        r
                    }
                };
                let ll = lrow(&l);
                let ls = lrow(&s);
                for q in 0..N {
                    let mut acc = 0.0;
                    for r in 0..4 {
                        acc += ll[r] * b.g[r][q];
                    }
                    row[q] = -acc;
                }
                row[first..first + 4].copy_from_slice(&ls);
            }
        }
    }
}

/// The largest relative violation of the active set's KKT conditions at `p`: stationarity
/// `‖c + Σ g λ‖∞` (c = e_α), active rows' and apex cones' slacks over the slack scale, padded
/// multipliers over the multiplier scale, and `‖s∘λ‖∞/(s₀λ₀)` for cones on their boundary.
fn residual<const N: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    scales: &Scales,
) -> Real {
    let mut rd = problem.c;
    let mut worst: Real = 0.0;
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let g = eq_g(problem, *eq);
        for q in 0..N {
            rd[q] += g[q] * p.lam[qi];
        }
        let r = match *eq {
            Eq::Lp(j) => (problem.lp[j].h - dotn(g, &p.z)).abs() / scales.s,
            Eq::SocApex(k, c) => (problem.soc[k].h[c] - dotn(g, &p.z)).abs() / scales.s,
            Eq::SocPad(_) => p.lam[qi].abs() / scales.lam,
            Eq::SocBound(k, 0) => {
                let s = soc_slack(problem, k, &p.z);
                let l = [0, 1, 2, 3].map(|r| p.lam[qi + r]);
                max_abs(&jprod(&s, &l)) / (s[0] * l[0])
            }
            Eq::SocBound(..) => 0.0,
        };
        worst = worse(worst, r);
    }
    for v in rd {
        worst = worse(worst, v.abs());
    }
    worst
}

/// One Newton step on the KKT conditions of `set` from `p`; `None` when the system is singular
/// or the step not finite.
fn newton_step<const N: usize>(
    problem: &Problem<'_, N>,
    set: &ActiveSet,
    p: &Point<N>,
    t: Real,
) -> Option<Point<N>> {
    let mut a = [[0.0; MAX_ACTIVE]; MAX_ACTIVE];
    kkt_matrix(problem, set, p, t, &mut a);
    let order = N + set.n;
    let mut rhs = [0.0; MAX_ACTIVE];
    for q in 0..N {
        rhs[q] = -problem.c[q];
    }
    let mut sl = [0.0; 4];
    for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
        let g = eq_g(problem, *eq);
        for q in 0..N {
            rhs[q] -= g[q] * p.lam[qi];
        }
        rhs[N + qi] = match *eq {
            Eq::Lp(j) => (problem.lp[j].h - dotn(g, &p.z)) / t,
            Eq::SocApex(k, c) => (problem.soc[k].h[c] - dotn(g, &p.z)) / t,
            Eq::SocPad(_) => -p.lam[qi],
            Eq::SocBound(k, c) => {
                if c == 0 {
                    let s = soc_slack(problem, k, &p.z).map(|v| v / t);
                    let l = [0, 1, 2, 3].map(|r| p.lam[qi + r]);
                    sl = jprod(&s, &l);
                }
                -sl[c]
            }
        };
    }
    let perm = lu_factor_in_place(&mut a, order)?;
    lu_solve_one(&a, &perm, order, &mut rhs);
    if !rhs[..order].iter().all(|v| v.is_finite()) {
        return None;
    }
    let mut next = *p;
    for q in 0..N {
        next.z[q] += t * rhs[q];
    }
    for qi in 0..set.n {
        next.lam[qi] += rhs[N + qi];
    }
    Some(next)
}

/// Refines the polished point `z0` by Newton's method on the KKT conditions of its active set,
/// for use when the polish left it short of them (see [`AMBIGUOUS`]). Near an active-set change
/// the interior iterate's slack and multiplier of the row that changes are both O(√μ), and a
/// single Newton step on the complementarity `s λ = 0` from there only halves them; on the
/// right active set the KKT conditions are smooth equations and Newton's method converges
/// quadratically. The result is accepted only if it converges to [`CONVERGED`], stays within
/// [`REFINE_MAX_STEP`] of the polished point and satisfies the sign conditions (λ ≥ 0 on active
/// rows, s ≥ 0 on inactive ones, both in their cones). When an orthant row's sign condition
/// fails, its classification is flipped and the refinement restarted (at most [`MAX_FLIPS`]
/// times). `None` when no active set passes: the caller then keeps the polished point.
fn refine<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    z0: &[Real; N],
    t: Real,
) -> Option<(ActiveSet, Point<N>)> {
    let scales = Scales {
        s: 1.0 + z0.iter().fold(0.0, |m: Real, v| m.max(v.abs())),
        lam: problem
            .lp
            .iter()
            .map(|r| r.lam_polished.abs())
            .chain(
                problem.soc[..problem.n_soc]
                    .iter()
                    .map(|b| b.lam_polished[0].abs()),
            )
            .fold(0.0, Real::max),
    };
    let mut flips = [0usize; MAX_FLIPS];
    let mut n_flips = 0;
    loop {
        let mut set = ActiveSet::EMPTY;
        if !identify(problem, ranges, z0, &flips[..n_flips], &mut set) {
            return None;
        }
        let start = Point::polished(problem, &set, z0);
        let mut p = start;
        let mut steps = 0;
        while !(residual(problem, &set, &p, &scales) <= CONVERGED) {
            if steps == MAX_NEWTON_STEPS {
                return None;
            }
            p = newton_step(problem, &set, &p, t)?;
            steps += 1;
        }
        for q in 0..N {
            if !((p.z[q] - z0[q]).abs() <= REFINE_MAX_STEP * scales.s) {
                return None;
            }
        }
        for qi in 0..set.n {
            if !((p.lam[qi] - start.lam[qi]).abs() <= REFINE_MAX_STEP * scales.lam) {
                return None;
            }
        }
        // The worst violated sign condition of an orthant row, if any.
        let mut flip = None;
        let mut worst = SIGN_TOLERANCE;
        for (qi, eq) in set.eqs[..set.n].iter().enumerate() {
            if let Eq::Lp(j) = *eq {
                let v = -p.lam[qi] / scales.lam;
                if !(v <= worst) {
                    worst = v;
                    flip = Some(j);
                }
            }
        }
        for (j, row) in problem.lp.iter().enumerate() {
            if !lp_active(problem, j, z0, &flips[..n_flips]) {
                let v = -(row.h - dotn(&row.g, &p.z)) / scales.s;
                if !(v <= worst) {
                    worst = v;
                    flip = Some(j);
                }
            }
        }
        // Cones: both s and λ in the cone (on the boundary, complementarity already holds).
        for k in 0..problem.n_soc {
            let s = soc_slack(problem, k, &p.z);
            let first = set.eqs[..set.n]
                .iter()
                .position(|eq| matches!(eq, Eq::SocApex(kk, _) | Eq::SocBound(kk, _) if *kk == k));
            let l = match first {
                Some(f) => [0, 1, 2, 3].map(|r| p.lam[f + r]),
                None => [0.0; 4],
            };
            let gap = |u: &[Real; 4]| u[0] - (u[1] * u[1] + u[2] * u[2] + u[3] * u[3]).sqrt();
            if !(gap(&s) >= -SIGN_TOLERANCE * scales.s && gap(&l) >= -SIGN_TOLERANCE * scales.lam) {
                return None;
            }
        }
        match flip {
            None => return Some((set, p)),
            Some(j) if n_flips < MAX_FLIPS => {
                flips[n_flips] = j;
                n_flips += 1;
            }
            Some(_) => return None,
        }
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

/// `−ρ` (active rows and apex cones), `0` (padded components) and `L(λ)ρ` (cones on their
/// boundary). Returns false (leaving `full` alone) when the active set is degenerate: a
/// singular system.
fn exact_jacobian<const N: usize>(at: &AtPoint<'_, '_, '_, N>, full: &mut Full) -> bool {
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
    if tests::FULL_SYSTEM_ONLY.with(|f| f.get()) {
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
fn reduced_jacobian<const N: usize, const M: usize>(
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
fn square_jacobian<const N: usize>(at: &AtPoint<'_, '_, '_, N>, full: &mut Full) -> bool {
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
fn exact_jacobian_in<const N: usize, const M: usize>(
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
fn xalpha_rows<const M: usize>(a: &mut [[Real; M]; M], order: usize) -> Option<[[Real; 4]; M]> {
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

/// `ρ = ∂(gᵀz − h)/∂θ` of any row for each pose parameter, with what all rows share
/// precomputed: `M_kᵀ eᵢ` for the quaternion columns (`−(M_k a)·eᵢ = −a·(M_kᵀ eᵢ)`), `1/ℓ` for
/// the position ones, and which shapes ignore their attitude (their columns stay zero).
struct RhoTable {
    u: [[Vec3; 4]; 2],
    inv_ell: Real,
    fixed: [bool; 2],
}

impl RhoTable {
    fn new(ctx: &Context<'_>, gens: &[[Mat3; 4]; 2], e: &[Vec3; 2]) -> Self {
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
    fn skip(&self, i: usize, pp: usize) -> bool {
        pp >= 3 && self.fixed[i]
    }

    /// ρ of row `g` of shape `i` for its parameter `pp` (0..3 position, 3..7 quaternion).
    #[inline]
    fn rho<const N: usize>(&self, g: &[Real; N], i: usize, pp: usize) -> Real {
        if pp < 3 {
            -g[pp] * self.inv_ell
        } else {
            -gx(g).dot(&self.u[i][pp - 3])
        }
    }

    /// ρ of the four rows of a cone block.
    #[inline]
    fn rho4<const N: usize>(&self, g: &[[Real; N]; 4], i: usize, pp: usize) -> [Real; 4] {
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
    fn columns<const M: usize>(
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
fn store_jacobian(mut jac: [[Real; 14]; 4], ell: Real, full: &mut Full) -> bool {
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

/// LU with partial pivoting, in place, of the leading `n×n` block of `a`; returns the pivot
/// row chosen at each step (LAPACK's `ipiv`), or `None` when a pivot is below 1e-14 of the
/// largest entry (a degenerate active set).
#[inline(always)]
fn lu_factor_in_place<const M: usize>(a: &mut [[Real; M]; M], n: usize) -> Option<[usize; M]> {
    let n = n.min(M);
    let mut ipiv = [0usize; M];
    // The largest |entry| (a NaN is passed over here and refused as a pivot below).
    let mut big: Real = 0.0;
    for row in a[..n].iter() {
        for v in row[..n].iter() {
            let x = v.abs();
            if x > big {
                big = x;
            }
        }
    }
    if !(big > 0.0) || !big.is_finite() {
        return None;
    }
    let floor = 1e-14 * big;
    for k in 0..n {
        let (mut p, mut pmax) = (k, a[k][k].abs());
        for (i, row) in a[..n].iter().enumerate().skip(k + 1) {
            let x = row[k].abs();
            if x > pmax {
                p = i;
                pmax = x;
            }
        }
        if !(pmax > floor) {
            return None;
        }
        // Whole rows: the entries beyond the order are zero in both.
        a.swap(p, k);
        ipiv[k] = p;
        let pivot_row = a[k];
        let inv = 1.0 / pivot_row[k];
        for row in a[k + 1..n].iter_mut() {
            let f = row[k] * inv;
            row[k] = f;
            if f == 0.0 {
                continue;
            }
            for (x, pv) in row[k + 1..n].iter_mut().zip(&pivot_row[k + 1..n]) {
                *x -= f * pv;
            }
        }
    }
    Some(ipiv)
}

/// Solves `A x = b` in place with the factor from [`lu_factor_in_place`].
fn lu_solve_one<const M: usize>(
    a: &[[Real; M]; M],
    ipiv: &[usize; M],
    n: usize,
    b: &mut [Real; M],
) {
    for k in 0..n {
        b.swap(k, ipiv[k]);
    }
    for i in 0..n {
        let mut acc = b[i];
        for k in 0..i {
            acc -= a[i][k] * b[k];
        }
        b[i] = acc;
    }
    for i in (0..n).rev() {
        let mut acc = b[i];
        for k in (i + 1)..n {
            acc -= a[i][k] * b[k];
        }
        b[i] = acc / a[i][i];
    }
}

/// Solves `Aᵀ Y = B` in place for four right-hand sides (the columns of `b`, stored row by
/// row) with the factor from [`lu_factor_in_place`]: `PA = LU`, so `Aᵀ = UᵀLᵀP`, a forward
/// solve with `Uᵀ` and a backward one with the unit `Lᵀ` (both sweeping rows of the factor),
/// then `Pᵀ`.
#[inline(always)]
fn lu_solve_transposed4<const M: usize>(
    a: &[[Real; M]; M],
    ipiv: &[usize; M],
    n: usize,
    b: &mut [[Real; 4]; M],
) {
    let n = n.min(M);
    for k in 0..n {
        let inv = 1.0 / a[k][k];
        let wk = b[k].map(|x| x * inv);
        b[k] = wk;
        for (bi, u) in b[k + 1..n].iter_mut().zip(&a[k][k + 1..n]) {
            for c in 0..4 {
                bi[c] -= u * wk[c];
            }
        }
    }
    for k in (0..n).rev() {
        let vk = b[k];
        for (bi, l) in b[..k].iter_mut().zip(&a[k][..k]) {
            for c in 0..4 {
                bi[c] -= l * vk[c];
            }
        }
    }
    for k in (0..n).rev() {
        b.swap(k, ipiv[k]);
    }
}

/// The barrier-smoothed Jacobian: the implicit-function system at the final interior iterate,
/// `GᵀDG dz = −dGᵀλ − GᵀDρ` with `D = L(s)⁻¹L(λ)` (the LU of `GᵀDG` from the polish), used when
/// the active set is degenerate. It is the derivative of the central-path point, which smooths
/// the kinks of α* at edges and corners and approaches the exact one as the tolerance shrinks.
#[allow(clippy::too_many_arguments)]
fn smoothed_jacobian<const N: usize>(
    problem: &Problem<'_, N>,
    ranges: &[Rows; 2],
    gens: &[[Mat3; 4]; 2],
    e: &[Vec3; 2],
    v: &[Vec3; 2],
    t: Real,
    ell: Real,
    full: &mut Full,
) {
    let lu = match problem.aho {
        Some(lu) => lu,
        None => match aho_at_iterate(problem) {
            Some(lu) => lu,
            None => {
                full.prox.status = crate::solver::SolveStatus::NumericalFailure;
                return;
            }
        },
    };
    for col in 0..14 {
        let i = col / 7;
        let p = col % 7;
        let r = &ranges[i];
        let mut rhs = [0.0; N];
        let rho = |g: &[Real; N]| rho_of(g, p, &gens[i], &e[i], ell);
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
            let w = problem.soc_d(k, &rv);
            for (gr, wr) in b.g.iter().zip(w.iter()) {
                for j in 0..N {
                    rhs[j] -= gr[j] * wr;
                }
            }
        }
        let x = lu.solve(&rhs);
        for j in 0..3 {
            full.jacobian[j][col] = x[j] * ell;
        }
        full.jacobian[3][col] = x[3];
    }
}

/// The LU of `GᵀDG` at the current iterate when the polish did not store one.
fn aho_at_iterate<const N: usize>(problem: &Problem<'_, N>) -> Option<crate::solver::kkt::Lu<N>> {
    problem
        .aho_matrix()
        .and_then(crate::solver::kkt::Lu::factor)
}

/// Derivatives at exactly coincident origins, where α* = 0 is not differentiable (α* is the
/// gauge of S₁ − S₂ at r₂ − r₁, homogeneous of degree one): zero is a valid subgradient of α*
/// and the rotation derivatives are exactly zero; the x rows of the Jacobian are left zero.
pub(crate) fn coincident(full: &mut Full) {
    full.gradient = [0.0; 14];
    full.jacobian = [[0.0; 14]; 4];
}

/// ∂α*/∂(r₁, q₁, r₂, q₂): 14 numbers, `q` as given (through the normalisation), from the
/// Lagrangian at the primal-dual solution. Costs little beyond [`super::proximity()`].
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

/// Everything differentiable about a proximity query, in one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivatives {
    /// The proximity result.
    pub proximity: Proximity,
    /// ∂α*/∂(r₁, q₁, r₂, q₂).
    pub dalpha: [Real; 14],
    /// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂), rows (x₁, x₂, x₃, α).
    pub jacobian: [[Real; 14]; 4],
    /// ∂p₁/∂(r₁, q₁, r₂, q₂) (3×14) for `p₁ = r₁ + (x* − r₁)/α*`; zero when α* = 0.
    pub dcontact1: [[Real; 14]; 3],
    /// ∂p₂/∂(r₁, q₁, r₂, q₂) (3×14); zero when α* = 0.
    pub dcontact2: [[Real; 14]; 3],
}

/// The Jacobian of (x*, α*) and, by the chain rule, of both contact points:
/// `∂pᵢ = ∂rᵢ + (∂x* − ∂rᵢ)/α* − (x* − rᵢ) ∂α*/α*²`.
pub fn derivatives(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Derivatives, Error> {
    let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
    let p = f.prox;
    let mut d = Derivatives {
        proximity: p,
        dalpha: f.gradient,
        jacobian: f.jacobian,
        dcontact1: [[0.0; 14]; 3],
        dcontact2: [[0.0; 14]; 3],
    };
    if p.alpha > 0.0 {
        let inv = 1.0 / p.alpha;
        let r = [*pose1.position(), *pose2.position()];
        for (i, out) in [&mut d.dcontact1, &mut d.dcontact2].into_iter().enumerate() {
            let rel = p.point - r[i];
            for row in 0..3 {
                for col in 0..14 {
                    let dr = if col == 7 * i + row { 1.0 } else { 0.0 };
                    out[row][col] = dr + (f.jacobian[row][col] - dr) * inv
                        - rel[row] * f.jacobian[3][col] * inv * inv;
                }
            }
        }
    }
    Ok(d)
}

/// Maps 14 quaternion-parameter columns to 12 MRP-parameter columns (`J_q · ∂q/∂p` per pose).
fn to_mrp_columns(row: &[Real; 14], mrp: [[Real; 3]; 2]) -> [Real; 12] {
    let mut out = [0.0; 12];
    for i in 0..2 {
        let dq = crate::math::mrp_quaternion_jacobian(mrp[i]);
        for j in 0..3 {
            out[6 * i + j] = row[7 * i + j];
        }
        for c in 0..3 {
            out[6 * i + 3 + c] = (0..4).map(|k| row[7 * i + 3 + k] * dq[k][c]).sum();
        }
    }
    out
}

/// ∂α*/∂(r₁, p₁, r₂, p₂) for attitudes given as modified Rodrigues parameters (12 numbers).
pub fn gradient_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [Real; 12]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, g) = gradient(shape1, &pose1, shape2, &pose2, options)?;
    Ok((p, to_mrp_columns(&g, [mrp1, mrp2])))
}

/// ∂(x*, α*)/∂(r₁, p₁, r₂, p₂), 4×12, for attitudes given as modified Rodrigues parameters.
pub fn jacobian_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [[Real; 12]; 4]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, j) = jacobian(shape1, &pose1, shape2, &pose2, options)?;
    let mut out = [[0.0; 12]; 4];
    for r in 0..4 {
        out[r] = to_mrp_columns(&j[r], [mrp1, mrp2]);
    }
    Ok((p, out))
}

#[cfg(test)]
mod tests {
    use crate::{jacobian, Options, Pose, Shape};
    use std::cell::Cell;

    thread_local! {
        /// Makes [`super::exact_jacobian`] skip the reduced system (this thread only).
        pub(super) static FULL_SYSTEM_ONLY: Cell<bool> = const { Cell::new(false) };
    }

    /// The reduced system (one unknown per cone on its boundary) and the full one (four
    /// multiplier components and the linearised complementarity) are two derivations of the
    /// same Jacobian: they must agree wherever both apply. Fixed-seed random poses over pairs
    /// of every kind with a cone block (sphere, ellipsoid, capsule, cylinder, cone, polygon)
    /// and with facets.
    #[test]
    fn reduced_and_full_active_set_systems_agree() {
        let shapes = [
            Shape::sphere(0.7).unwrap(),
            Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 2.0, 0.1], [0.0, 0.1, 0.5]]).unwrap(),
            Shape::capsule(0.3, 1.2).unwrap(),
            Shape::cylinder(0.4, 0.9).unwrap(),
            Shape::cone(1.1, 0.5).unwrap(),
            Shape::polygon(
                &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
                &[0.6; 4],
                0.1,
            )
            .unwrap(),
            Shape::cuboid(0.5, 0.4, 0.3).unwrap(),
        ];
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut compared, mut worst) = (0, 0.0f64);
        for a in &shapes {
            for b in &shapes {
                for _ in 0..20 {
                    let mut pose = || {
                        let r = [2.0 * next(), 2.0 * next(), 2.0 * next()];
                        let q = [next(), next(), next(), next()];
                        Pose::new(r, q).unwrap()
                    };
                    let (pa, pb) = (pose(), pose());
                    let opts = Options::default();
                    let (p, reduced) = jacobian(a, &pa, b, &pb, &opts).unwrap();
                    FULL_SYSTEM_ONLY.with(|f| f.set(true));
                    let (_, full) = jacobian(a, &pa, b, &pb, &opts).unwrap();
                    FULL_SYSTEM_ONLY.with(|f| f.set(false));
                    if !p.status.is_converged() || p.alpha == 0.0 {
                        continue;
                    }
                    let scale = full.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
                    for (rr, fr) in reduced.iter().zip(full.iter()) {
                        for (x, y) in rr.iter().zip(fr.iter()) {
                            worst = worst.max((x - y).abs() / scale);
                        }
                    }
                    compared += 1;
                }
            }
        }
        assert!(compared > 900, "only {compared} converged cases");
        assert!(
            worst <= 1e-8,
            "reduced and full Jacobians differ by {worst:e}"
        );
    }

    /// The closed-form generators against `(∂Q/∂q_k) Qᵀ` from the entry-wise derivatives of
    /// the rotation matrix (`math::rotation_derivatives`), over quaternions of norms 1e-100 to
    /// 1e100.
    #[test]
    fn rotation_generators_match_matrix_derivatives() {
        let mut worst = 0.0f64;
        for (i, scale) in [1e-100, 1e-3, 1.0, 7.5, 1e100].into_iter().enumerate() {
            for j in 0..20 {
                let t = (i * 20 + j) as f64;
                let q = [
                    (t * 0.37).sin(),
                    (t * 1.1).cos(),
                    (t * 0.73).sin() - 0.2,
                    (t * 2.3).cos(),
                ]
                .map(|x| x * scale);
                let pose = Pose::new([0.0; 3], q).unwrap();
                let d = crate::math::rotation_derivatives(q);
                let rt = pose.rotation().transpose();
                let m = super::rotation_generators(&pose);
                for k in 0..4 {
                    let want = d[k] * rt * scale;
                    let got = m[k] * scale;
                    worst = worst.max((want - got).abs().max());
                }
            }
        }
        assert!(worst <= 1e-14, "generators differ by {worst:e} (times |q|)");
    }

    /// A sphere's quaternion columns are exactly zero (its set ignores its attitude), and every
    /// other column equals the generic computation for the same ball written as an ellipsoid
    /// (`P = I/R²`), whose quaternion columns come out at rounding level.
    #[test]
    fn sphere_attitude_columns_are_exactly_zero() {
        let r = 0.6;
        let ball = Shape::sphere(r).unwrap();
        let same = Shape::ellipsoid([
            [1.0 / (r * r), 0.0, 0.0],
            [0.0, 1.0 / (r * r), 0.0],
            [0.0, 0.0, 1.0 / (r * r)],
        ])
        .unwrap();
        let others = [
            Shape::cuboid(0.5, 0.4, 0.3).unwrap(),
            Shape::cone(1.1, 0.5).unwrap(),
            Shape::capsule(0.3, 1.2).unwrap(),
            Shape::sphere(0.4).unwrap(),
        ];
        let pa = Pose::new([0.1, -0.2, 0.3], [0.9, 0.1, -0.3, 0.2]).unwrap();
        let pb = Pose::new([1.4, 0.5, -0.6], [0.4, -0.5, 0.2, 0.7]).unwrap();
        let opts = Options::default();
        for other in &others {
            let (_, j) = jacobian(&ball, &pa, other, &pb, &opts).unwrap();
            let (_, g) = crate::gradient(&ball, &pa, other, &pb, &opts).unwrap();
            let (_, je) = jacobian(&same, &pa, other, &pb, &opts).unwrap();
            for c in 3..7 {
                assert_eq!(g[c], 0.0);
                for row in &j {
                    assert_eq!(row[c], 0.0);
                }
                for row in &je {
                    assert!(row[c].abs() <= 1e-9, "ellipsoid q column {c}: {}", row[c]);
                }
            }
            for (jr, er) in j.iter().zip(je.iter()) {
                for c in (0..3).chain(7..14) {
                    assert!(
                        (jr[c] - er[c]).abs() <= 1e-8 * (1.0 + er[c].abs()),
                        "column {c}: sphere {} vs ellipsoid {}",
                        jr[c],
                        er[c]
                    );
                }
            }
        }
    }

    /// The padded whole-matrix factorisation of the smallest storage gives what the general
    /// one gives for the same system in larger storage (orders below and at the storage size,
    /// pivoting exercised by a small leading entry), and both report a singular system.
    #[test]
    fn padded_small_system_matches_general_factorisation() {
        use super::{xalpha_rows, TINY_ACTIVE};
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for order in 4..=TINY_ACTIVE {
            for trial in 0..20 {
                let mut small = [[0.0; TINY_ACTIVE]; TINY_ACTIVE];
                let mut large = [[0.0; 12]; 12];
                for i in 0..order {
                    for j in 0..order {
                        let v = next() * if trial % 2 == 0 { 1e-3 } else { 1e3 };
                        small[i][j] = v;
                        large[i][j] = v;
                    }
                }
                small[0][0] *= 1e-6;
                large[0][0] *= 1e-6;
                let ys = xalpha_rows(&mut small, order).expect("regular");
                let yl = xalpha_rows(&mut large, order).expect("regular");
                for q in 0..order {
                    for r in 0..4 {
                        let (a, b) = (ys[q][r], yl[q][r]);
                        assert!(
                            (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                            "order {order} trial {trial} Y[{q}][{r}]: {a} vs {b}"
                        );
                    }
                }
                for y in &ys[order..] {
                    assert_eq!(*y, [0.0; 4]);
                }
                // A repeated row makes both singular.
                let mut small_singular = [[0.0; TINY_ACTIVE]; TINY_ACTIVE];
                let mut large_singular = [[0.0; 12]; 12];
                for i in 0..order {
                    for j in 0..order {
                        let v = next();
                        small_singular[i][j] = v;
                        large_singular[i][j] = v;
                    }
                }
                for j in 0..order {
                    small_singular[order - 1][j] = small_singular[0][j];
                    large_singular[order - 1][j] = large_singular[0][j];
                }
                assert!(xalpha_rows(&mut small_singular, order).is_none());
                assert!(xalpha_rows(&mut large_singular, order).is_none());
            }
        }
    }
}
