//! Proximity on support maps: closed forms where the pair has one, and the pair-specific
//! answers of `super::shortcuts`; else, on pairs with a curved shape, Newton's method on the
//! support function from the ray's direction (`crate::solver::direct`); else a ray cast (MPR)
//! that identifies the contact features and Newton's method on them (the tie solve of
//! `direct`, else the polish's KKT Newton). Each is certified; `Outcome::Fallback` sends the
//! query to the interior-point solver.
//!
//! The frame is the interior-point path's: origin at `r₁`, lengths divided by `ℓ = max(ρ₁, ρ₂)`;
//! the ray is the unit vector `r = (r₂ − r₁)/‖r₂ − r₁‖`, and α* = α'·‖r₂ − r₁‖/ℓ with α' the
//! gauge of the normalised Minkowski difference at `r` (α* is homogeneous of degree one in the
//! offset, so no precision is lost at tiny or huge offsets).

use super::ball_jacobian::ball_jacobian;
use super::capsule_jacobian::capsule_jacobian;
use super::context::{Options, Proximity, ShapeSink};
use super::cores::Cores;
use super::derivatives::{rotation_axes, rotation_dots};
use super::dispatch::{route, Stage, Stages};
use super::ellipsoid_jacobian::ellipsoid_jacobian;
use super::face_jacobian::face_jacobian;
use super::polytope_jacobian::polytope_jacobian;
use super::segment_jacobian::segment_jacobian;
use super::shortcuts::{
    capsule_and_solid, ellipsoid_and_polytope, ellipsoid_and_rod, flat_first, sphere_and_ellipsoid,
    two_ellipsoids, Answer, Solved,
};
use super::sphere_jacobian::sphere_jacobian;
use super::warm::{Cache, Kind};
use crate::math::{finite_array, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::closed_form::{rounded_segments, sphere_box, sphere_revolution, RoundedSegment};
use crate::solver::direct::{after_cast, direct};
use crate::solver::features::contact_is_unique;
use crate::solver::gjk::padded::{padded_cast, PaddedEnd};
use crate::solver::polish::polish;
use crate::solver::raycast::{cast, upper_from_point, Cast, CastEnd, Pair, Posed, Stop};
use crate::solver::sensitivity::{refine, sensitivity, Solution, PARALLEL_SIN};
use crate::solver::{DerivativeKind, SolveStatus, Solver};

/// Portal refinements before the polish takes over.
const CAST_BUDGET: u32 = 40;
/// Relative bracket at which a curved pair's cast hands over to the polish (1e-3: 10 % faster
/// than 1e-5 over all pairs, the same accuracy since the Jacobian and the uniqueness test come
/// from the identified features; 1e-2 gains nothing more).
const HANDOVER: Real = 1e-3;
/// Portal refinements allowed after a failed polish, before the interior-point fallback.
const CAST_RESCUE: u32 = 200;
/// The narrowest relative bracket asked of the geometric solvers (a few roundings of the bounds).
const TOL_FLOOR: Real = 1e-14;
/// The certified bracket is closed to this fraction of the requested tolerance. The
/// interior-point solver's tolerance bounds its duality measure, and its polish lands about
/// three orders of magnitude below it; a bracket is the error bound itself, so it is closed as
/// far below to give the same accuracy for the same setting.
const MARGIN: Real = 1e-3;

/// What the geometric path concluded.
pub(crate) enum Outcome {
    /// The certified bracket excluded the threshold: α* is below it (`true`) or above it;
    /// `alpha` is the bracket's end on that side (world units); `normal` (world, any length)
    /// the direction whose support bound gave the lower end: one that separates the shapes
    /// scaled by the threshold when not `below`.
    Decided {
        below: bool,
        alpha: Real,
        normal: Vec3,
    },
    /// The full answer, with `∂α*/∂(r₂ − r₁)` (the optimal normal `n*/h_K(n*)`, world units).
    Answer(Proximity, Vec3),
    /// The geometric solvers could not certify an answer: run the interior-point solver.
    Fallback,
}

/// Proximity by the geometric solvers, stopping early once α* is proven above `threshold.0`
/// (or below it, when `threshold.1`); [`Outcome::Fallback`] when they cannot certify the
/// answer to the requested tolerance. `dist = ‖r₂ − r₁‖ > 0`. With `warm`, the pair's cache
/// (`super::warm`) is tried first and keeps the answer.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn proximity(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    dist: Real,
    threshold: Option<(Real, bool)>,
    warm: Option<&mut Cache>,
) -> Outcome {
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let ray = (r2 - r1) / dist;
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    let inv = 1.0 / ell;
    let iota = (shape1.inscribed_radius() + shape2.inscribed_radius()) * inv;
    let pair = Pair::new([shape1, shape2], [pose1.rotation(), pose2.rotation()], inv);
    // α* = α'·dist/ℓ.
    let world = dist * inv;
    let stages = route(shape1, shape2).proximity;
    // The cache keeps answers only between polytopes (`super::warm`): other pairs neither try
    // nor keep one.
    let mut warm = warm.filter(|_| stages.has(Stage::Warm));
    let stop = threshold.map(|(t, stop_below)| Stop {
        value: t / world,
        stop_below,
    });
    let solved = solve(
        stages,
        &pair,
        [pose1, pose2],
        &ray,
        iota,
        options.tolerance,
        stop,
        warm.as_deref_mut(),
    );
    if let Some(cache) = warm {
        match &solved {
            Ok(Some(_)) => cache.keep_poses(Kind::Proximity, [shape1, shape2], ell, [pose1, pose2]),
            _ => cache.forget(Kind::Proximity),
        }
    }
    let ans = match solved {
        Ok(Some(ans)) => ans,
        Ok(None) => return Outcome::Fallback,
        Err((below, alpha, normal)) => {
            return Outcome::Decided {
                below,
                alpha: alpha * world,
                normal,
            }
        }
    };
    match in_world(&ans, [&r1, &r2], ell, world) {
        Some(prox) => {
            // ∂α*/∂d = n/h_K(n) (world): with n·r = 1 and h_K'(n) = 1/α' in the normalised
            // lengths, n·α'/ℓ.
            let dalpha_dd = ans.normal * (ans.alpha * inv);
            Outcome::Answer(prox, dalpha_dd)
        }
        None => Outcome::Fallback,
    }
}

/// The normalised answer `ans` in world units (origins `r`, length scale `ℓ = ell`, α* = α'·
/// `world`), or `None` when a number is not finite (the caller falls back). Shared by
/// [`proximity`] and the C ABI's closed-form lane (`super::closed_lane`), which must give the
/// same numbers.
#[inline(always)]
pub(super) fn in_world(ans: &Answer, r: [&Vec3; 2], ell: Real, world: Real) -> Option<Proximity> {
    // The touching point x* = r₁ + α*·ℓ·a; contact points r₁ + ℓa, r₂ + ℓb.
    let alpha = ans.alpha * world;
    let contact1 = r[0] + ans.a * ell;
    let contact2 = r[1] + ans.b * ell;
    let point = r[0] + ans.a * (alpha * ell);
    // Every number finite, in one test (`crate::math::finite_array`).
    let numbers = [
        alpha, point.x, point.y, point.z, contact1.x, contact1.y, contact1.z, contact2.x,
        contact2.y, contact2.z,
    ];
    finite_array(&numbers).then_some(Proximity {
        alpha,
        point,
        contact1,
        contact2,
        iterations: 0,
        status: SolveStatus::Converged,
        solver: ans.solver,
        derivatives: DerivativeKind::None,
    })
}

/// `∂α*/∂(r₁, q₁, r₂, q₂)` from the geometric solution by the envelope theorem
/// (`docs/maths.md` §4): with `ñ = n*/h_K(n*)`, `∂α*/∂r₂ = ñ = −∂α*/∂r₁`; a change of
/// `qᵢ` moves shape i's support function at `n*` through its support point `bᵢ*` (body frame),
/// `∂h₁(n)/∂q₁ₖ = n·(∂R₁/∂q₁ₖ) b₁*` and `∂h₂(−n)/∂q₂ₖ = −n·(∂R₂/∂q₂ₖ) b₂*`, and
/// `∂α*/∂h_K = −α*/h_K`. Exact wherever the optimal normal and support points are unique. A
/// sphere's support function does not depend on its attitude: its columns are exactly zero.
#[inline(always)]
pub(crate) fn gradient(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    pose1: &Pose,
    pose2: &Pose,
) -> [Real; 14] {
    let mut g = [0.0; 14];
    for j in 0..3 {
        g[j] = -dalpha_dd[j];
        g[7 + j] = dalpha_dd[j];
    }
    // ∂Qᵢ/∂qᵢₖ bᵢ = ωᵢₖ × wᵢ with wᵢ = Qᵢbᵢ the support point relative to rᵢ (world), so
    // n·(∂Qᵢ/∂qᵢₖ)bᵢ = ωᵢₖ·(wᵢ × n): the four dots without forming the axes
    // ([`rotation_dots`]).
    let alpha = prox.alpha;
    if shapes[0].solver_kind() != ShapeKind::Sphere {
        let t = (prox.contact1 - pose1.position()).cross(dalpha_dd) * -alpha;
        g[3..7].copy_from_slice(&rotation_dots(pose1, &t));
    }
    if shapes[1].solver_kind() != ShapeKind::Sphere {
        let t = (prox.contact2 - pose2.position()).cross(dalpha_dd) * alpha;
        g[10..14].copy_from_slice(&rotation_dots(pose2, &t));
    }
    g
}

/// Each shape's four rotation axes ([`rotation_axes`]), zero for a sphere (its rotation
/// columns are exactly zero and are not formed): computed once for the Jacobian of one call.
#[inline]
pub(crate) fn pair_axes(shapes: [&Shape; 2], poses: [&Pose; 2]) -> [[Vec3; 4]; 2] {
    let axes_of = |i: usize| {
        if shapes[i].solver_kind() == ShapeKind::Sphere {
            [Vec3::zeros(); 4]
        } else {
            rotation_axes(poses[i])
        }
    };
    [axes_of(0), axes_of(1)]
}

/// `factor · ∂hᵢ(mᵢ)/∂θᵢ` into each wanted buffer of `sink`, for the support functions at the
/// world normal `n` (shape 1 at `m₁ = R₁ᵀn`, shape 2 at `m₂ = −R₂ᵀn`) and the support points
/// `contacts` (world): the envelope theorem's shape derivatives (`docs/maths.md` §4). With
/// `n = ñ = n*/h_K(n*)` and `factor = −α*` they are `∂α*/∂θᵢ` (α* = n·d/h_K(n) at its
/// maximiser); with the unit normal of a distance or signed distance and `factor = −1`, its
/// `∂d/∂θᵢ`. False when a shape's derivative is not unique there (one element of the
/// generalised gradient was written).
pub(crate) fn support_gradients(
    n: &Vec3,
    contacts: [&Vec3; 2],
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    factor: Real,
    sink: &mut ShapeSink<'_>,
) -> bool {
    // An answer a double cannot hold (α* = +inf, a witness beyond ±1.8e308) has no
    // derivatives: the buffers stay untouched (`written` false) and the caller reports it.
    let inputs = n.iter().chain(contacts[0].iter()).chain(contacts[1].iter());
    if !factor.is_finite() || !inputs.into_iter().all(|v| v.is_finite()) {
        return true;
    }
    let mut unique = true;
    for i in 0..2 {
        let Some(out) = sink.d[i].as_deref_mut() else {
            continue;
        };
        let rot = poses[i].rotation();
        let sign = if i == 0 { 1.0 } else { -1.0 };
        let m = rot.tr_mul(n) * sign;
        // Only faceted kinds and the cone tell their features apart by the support point.
        let x = if shapes[i].support_point_matters() {
            rot.tr_mul(&(contacts[i] - poses[i].position()))
        } else {
            Vec3::zeros()
        };
        unique &= shapes[i].support_gradient(&m, &x, out);
        sink.scale(i, shapes[i].parameter_count(), factor);
    }
    sink.written = true;
    unique
}

/// The geometric answer in the solvers' normalised frame (lengths over ℓ, the unit ray), and
/// `s = ‖r₂ − r₁‖/ℓ`.
fn normalised<'a>(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    shapes: [&'a Shape; 2],
    poses: [&'a Pose; 2],
) -> (Pair<'a, Shape>, Solution, Real) {
    let (r1, r2) = (*poses[0].position(), *poses[1].position());
    let dist = (r2 - r1).norm();
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let inv = 1.0 / ell;
    let s = dist * inv;
    let alpha_n = prox.alpha / s;
    let pair = Pair::new(
        [shapes[0], shapes[1]],
        [poses[0].rotation(), poses[1].rotation()],
        inv,
    );
    let sol = Solution {
        r: (r2 - r1) / dist,
        // ∂α*/∂d = n·α'/ℓ with n·r = 1.
        normal: dalpha_dd * (ell / alpha_n),
        mu: 1.0 / alpha_n,
        a: (prox.contact1 - r1) * inv,
        b: (prox.contact2 - r2) * inv,
    };
    (pair, sol, s)
}

/// Whether the contact points (and with them x* and the gradient's rotation columns) are
/// unique: always when either shape is strictly convex (a sphere, an ellipsoid); otherwise
/// when the contact features allow it (`crate::solver::sensitivity::unique_contact`). Flat
/// against flat, α* has a kink under rotation and the gradient formula's value depends on which
/// contact point it is given.
pub(crate) fn unique_contact(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> bool {
    let strict = |s: &Shape| matches!(s.solver_kind(), ShapeKind::Sphere | ShapeKind::Ellipsoid);
    if strict(shapes[0]) || strict(shapes[1]) {
        return true;
    }
    if !general_only() && capsules_not_parallel(shapes, poses) {
        return true;
    }
    // The normal of [`normalised`]'s solution, the same operations, without its other fields
    // (the test reads the normal only).
    let (r1, r2) = (*poses[0].position(), *poses[1].position());
    let ell = shapes[0].bounding_radius().max(shapes[1].bounding_radius());
    let inv = 1.0 / ell;
    let alpha_n = prox.alpha / ((r2 - r1).norm() * inv);
    let pair = Pair::new(
        [shapes[0], shapes[1]],
        [poses[0].rotation(), poses[1].rotation()],
        inv,
    );
    contact_is_unique(&pair, &(dalpha_dd * (ell / alpha_n)))
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` (4×14, rows x₁, x₂, x₃, α) from the geometric solution and
/// its gradient `g` ([`gradient`]): in closed form for two spheres, for a sphere against a
/// box, a capsule, a cylinder, a cone or an ellipsoid (`super::sphere_jacobian`), for two capsules
/// (`super::capsule_jacobian`), for two ellipsoids (`super::ellipsoid_jacobian`), and for two polytopes
/// touching on a facet of K (`super::polytope_jacobian`), else by
/// the implicit function theorem on its contact features (`crate::solver::sensitivity`);
/// `None` where x* is not unique or the features' system is singular.
///
/// With `s = ‖r₂ − r₁‖/ℓ`, α* = s·α'(r) for the unit ray r, and α' = 1/μ is homogeneous of
/// degree one in the ray, so `∂α*/∂r₂ = ∇α'/ℓ` with `∇α' = −α'²∂μ/∂r`. The touching point is
/// `x* = r₁ + ℓα*a` with the contact point `a` homogeneous of degree zero:
/// `∂x*/∂r₂ = a∇α'ᵀ + α'∂a/∂r`, `∂x*/∂r₁ = I − ∂x*/∂r₂`, and along a rotation axis
/// `∂x*/∂θ = ℓ(a ∂α*/∂θ + α* ∂a/∂θ)`.
pub(crate) fn jacobian(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    g: &[Real; 14],
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> Option<[[Real; 14]; 4]> {
    let mut j = [[0.0; 14]; 4];
    jacobian_into(prox, dalpha_dd, g, shapes, poses, &mut j)?;
    Some(j)
}

/// How [`jacobian_into`] formed the Jacobian.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Formed {
    /// A closed form for spheres, capsules and ellipsoids: its α row is the gradient `g` and its columns
    /// of `r₁` and `r₂` sum to the identity by construction (up to rounding).
    Closed,
    /// The polytopes' closed form or the general feature solve.
    Solved,
}

/// [`jacobian`] written into `j` (every entry; garbage when `None` is returned), saying how
/// it was formed: the closed forms write their columns in place, without the copies of the
/// 4×14 result through `Option`s and returns. The pair's rotation axes ([`pair_axes`]) are
/// formed after the sphere closed forms, which take none (two spheres) or one shape's.
#[inline]
pub(crate) fn jacobian_into(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    g: &[Real; 14],
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    out: &mut [[Real; 14]; 4],
) -> Option<Formed> {
    let kinds = shapes.map(|s| s.solver_kind());
    if !general_only() {
        let sphere = match kinds {
            [ShapeKind::Sphere, ShapeKind::Sphere] => {
                two_spheres_jacobian(prox, dalpha_dd, shapes, out)
            }
            [ShapeKind::Sphere, _] | [_, ShapeKind::Sphere] => {
                sphere_jacobian(prox, g, dalpha_dd, shapes, poses, out)
            }
            _ => None,
        };
        if sphere.is_some() {
            return Some(Formed::Closed);
        }
    }
    let axes = &pair_axes(shapes, poses);
    if !general_only() {
        let closed = match kinds {
            [ShapeKind::Sphere, _] | [_, ShapeKind::Sphere] => None,
            [ShapeKind::Capsule, ShapeKind::Capsule] => {
                capsule_jacobian(prox, g, dalpha_dd, shapes, poses, axes, out)
            }
            [ShapeKind::Ellipsoid, ShapeKind::Ellipsoid] => {
                ellipsoid_jacobian(prox, g, dalpha_dd, shapes, poses, axes, out)
            }
            _ => ball_jacobian(prox, g, dalpha_dd, shapes, poses, axes, out)
                .or_else(|| segment_jacobian(prox, g, dalpha_dd, shapes, poses, axes, out))
                .or_else(|| face_jacobian(prox, g, dalpha_dd, shapes, poses, axes, out)),
        };
        if closed.is_some() {
            return Some(Formed::Closed);
        }
    }
    *out = general_jacobian(prox, dalpha_dd, shapes, poses, axes)?;
    Some(Formed::Solved)
}

/// The polytopes' closed form or the general feature solve (see [`jacobian`]).
fn general_jacobian(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
    axes: &[[Vec3; 4]; 2],
) -> Option<[[Real; 14]; 4]> {
    let (pair, sol, s) = normalised(prox, dalpha_dd, shapes, poses);
    if !general_only() {
        if let Some(j) = polytope_jacobian(&pair, &sol, prox.alpha, shapes, poses) {
            return Some(j);
        }
    }
    let (ell, inv) = (1.0 / pair.one.inv_scale, pair.one.inv_scale);
    let round = shapes.map(|s| s.solver_kind() == ShapeKind::Sphere);
    // A sphere's rotation columns are exactly zero: neither its axes nor its columns are formed.
    let sens = sensitivity(&pair, &sol, axes, round)?;
    let alpha_n = 1.0 / sens.mu;
    let alpha = s * alpha_n;
    let a = sens.a;
    let grad_n = -sens.dmu_dr * (alpha_n * alpha_n);
    let mut j = [[0.0; 14]; 4];
    for c in 0..3 {
        j[3][7 + c] = grad_n[c] * inv;
        j[3][c] = -grad_n[c] * inv;
        for i in 0..3 {
            let dx = a[i] * grad_n[c] + alpha_n * sens.da_dr[(i, c)];
            j[i][7 + c] = dx;
            j[i][c] = if i == c { 1.0 } else { 0.0 } - dx;
        }
    }
    for (t, col) in [3, 4, 5, 6, 10, 11, 12, 13].into_iter().enumerate() {
        if round[t / 4] {
            continue;
        }
        let da = -s * alpha_n * alpha_n * sens.dmu_dtheta[t];
        j[3][col] = da;
        let dx = (a * da + sens.da_dtheta[t] * alpha) * ell;
        for i in 0..3 {
            j[i][col] = dx[i];
        }
    }
    crate::math::all_finite(&j).then_some(j)
}

#[cfg(test)]
thread_local! {
    /// Makes [`jacobian`] and [`unique_contact`] skip their closed forms (this thread only), so
    /// that a test can compare them with the general feature solve.
    pub(crate) static GENERAL_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

#[cfg(test)]
fn general_only() -> bool {
    GENERAL_ONLY.with(|f| f.get())
}

#[cfg(not(test))]
#[inline(always)]
fn general_only() -> bool {
    false
}

/// Two capsules whose axes are far from parallel: each one's contact feature is a cap's point
/// or its side (affine dimension at most one), so x* is unique unless both are sides and
/// parallel, which the general test ([`contact_is_unique`]) rejects below a sine of
/// [`PARALLEL_SIN`] between the world directions of the two sides: the capsules' axes. Twice
/// that margin leaves its decision unchanged by the rounding of its directions; closer to
/// parallel the general test decides. Saves finding both features (every piece evaluated
/// with its Hessian) on every capsule-capsule gradient.
fn capsules_not_parallel(shapes: [&Shape; 2], poses: [&Pose; 2]) -> bool {
    if shapes.iter().any(|s| s.solver_kind() != ShapeKind::Capsule) {
        return false;
    }
    let axis = |p: &Pose| p.rotation().column(0).into_owned();
    axis(poses[0]).cross(&axis(poses[1])).norm() > 2.0 * PARALLEL_SIN
}

/// The Jacobian of two spheres in closed form: α* = d/(R₁ + R₂) and
/// x* = r₁ + R₁/(R₁ + R₂)·(r₂ − r₁), so the x rows are `R₂/(R₁+R₂)·I` (r₁) and `R₁/(R₁+R₂)·I`
/// (r₂), the α row is the gradient `∓ñ` proximity found, and nothing depends on the
/// quaternions. `None` unless both shapes are spheres.
fn two_spheres_jacobian(
    prox: &Proximity,
    dalpha_dd: &Vec3,
    shapes: [&Shape; 2],
    j: &mut [[Real; 14]; 4],
) -> Option<()> {
    if shapes.iter().any(|s| s.solver_kind() != ShapeKind::Sphere) {
        return None;
    }
    let (_, r1) = shapes[0].rounded_segment()?;
    let (_, r2) = shapes[1].rounded_segment()?;
    let (k1, k2) = (r1 / (r1 + r2), r2 / (r1 + r2));
    *j = [[0.0; 14]; 4];
    for c in 0..3 {
        j[c][c] = k2;
        j[c][7 + c] = k1;
        j[3][c] = -dalpha_dd[c];
        j[3][7 + c] = dalpha_dd[c];
    }
    // Every entry is ±one of these five numbers or zero: one sum tests them (a finite sum
    // that overflows only sends the pair to the general solve; the row-by-row check of the 56
    // entries cost ~120 instructions).
    let sum = prox.alpha + k1 + k2 + dalpha_dd.x + dalpha_dd.y + dalpha_dd.z;
    sum.is_finite().then_some(())
}

/// `Err((below, bound, normal))` when the cast's bracket decided the threshold: the bracket's
/// end on that side, and the normal of its lower end.
fn decided(c: &Cast) -> Result<(), (bool, Real, Vec3)> {
    match c.end {
        CastEnd::Decided(below) => {
            Err((below, if below { c.alpha_hi } else { c.alpha_lo }, c.normal))
        }
        _ => Ok(()),
    }
}

/// Sphere and capsule pairs, a sphere with a centred box, a cylinder or a cone, in closed form.
pub(super) fn closed_form(pair: &Pair<'_, Shape>, ray: &Vec3) -> Option<Answer> {
    let seg = RoundedSegment::of;
    // Sphere and capsule pairs first: no sphere–solid form below takes a sphere or a capsule as
    // the solid (asking them cost a sphere pair ~120 instructions).
    if let (Some(one), Some(two)) = (seg(&pair.one), seg(&pair.two)) {
        return segments_answer(ray, &one, &two);
    }
    let ball = |posed: &Posed<'_, Shape>| match posed.shape.rounded_segment() {
        Some((0.0, radius)) => Some(radius * posed.inv_scale),
        _ => None,
    };
    let boxed = |posed: &Posed<'_, Shape>| Some(posed.shape.centred_box()? * posed.inv_scale);
    // A sphere and a cylinder or cone (a solid of revolution): its meridian section.
    let revolved = |posed: &Posed<'_, Shape>| {
        let (mut v, n) = posed.shape.revolution_section()?;
        for x in v.iter_mut() {
            *x = (x.0 * posed.inv_scale, x.1 * posed.inv_scale);
        }
        Some((v, n))
    };
    // A sphere and a centred box, cylinder or cone, in either order: the hit for the offset
    // from the solid to the sphere (`±ray`), its normal from the solid to the sphere.
    for (solid, sphere, first) in [(&pair.one, &pair.two, true), (&pair.two, &pair.one, false)] {
        let Some(rho) = ball(sphere) else {
            continue;
        };
        let q = if first { *ray } else { -ray };
        let hit = if let Some(h) = boxed(solid) {
            sphere_box(&q, solid.rot, &h, rho)
        } else if let Some((v, n)) = revolved(solid) {
            sphere_revolution(&q, solid.rot, &v[..n], rho)
        } else {
            continue;
        }?;
        let (a, b) = if first {
            (hit.box_point, -hit.normal * rho)
        } else {
            (-hit.normal * rho, hit.box_point)
        };
        return Some(Answer {
            alpha: hit.alpha,
            normal: hit.normal / hit.normal.dot(ray),
            a,
            b,
            solver: Solver::ClosedForm,
        });
    }
    None
}

/// The closed form of two rounded segments (spheres and capsules), normalised.
#[inline(always)]
fn segments_answer(ray: &Vec3, one: &RoundedSegment, two: &RoundedSegment) -> Option<Answer> {
    let hit = rounded_segments(ray, one, two)?;
    Some(Answer {
        alpha: hit.alpha,
        normal: hit.normal / hit.normal.dot(ray),
        a: one.axis * hit.s + hit.normal * one.radius,
        b: two.axis * hit.t - hit.normal * two.radius,
        solver: Solver::ClosedForm,
    })
}

/// The geometric answer by the pair's `stages` (`super::dispatch`): a closed form, else the
/// answer on the features `warm` kept from the pair's last answer where that certifies, else
/// the cold solvers (whose answer `warm` then keeps).
#[allow(clippy::too_many_arguments)]
fn solve(
    stages: Stages,
    pair: &Pair<'_, Shape>,
    poses: [&Pose; 2],
    ray: &Vec3,
    iota: Real,
    tolerance: Real,
    stop: Option<Stop>,
    warm: Option<&mut Cache>,
) -> Solved {
    if stages.has(Stage::ClosedForm) {
        if let Some(ans) = closed_form(pair, ray) {
            return Ok(Some(ans));
        }
    }
    // No bracket can be certified much below the rounding of the bounds themselves.
    let tol = (tolerance * MARGIN).max(TOL_FLOOR);
    let Some(cache) = warm else {
        return solve_cold(stages, pair, ray, iota, tol, stop);
    };
    if let Some(ans) = cache.solve(pair, poses, ray, iota, tol) {
        return Ok(Some(ans));
    }
    let solved = solve_cold(stages, pair, ray, iota, tol, stop);
    if let Ok(Some(ans)) = &solved {
        cache.keep_answer(
            Kind::Proximity,
            &ans.normal,
            1.0 / ans.alpha,
            ray,
            &ans.a,
            &ans.b,
        );
    }
    solved
}

/// The cold solvers of `stages`, after the closed forms (`tol`: the bracket to close,
/// relative).
fn solve_cold(
    stages: Stages,
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    stop: Option<Stop>,
) -> Solved {
    // The pair-specific answers (`super::shortcuts`), each where the table lists it (direct
    // calls: through a table of function pointers sphere–ellipsoid took 8 % longer).
    if stages.has(Stage::SegmentSolid) {
        if let Some(ans) = capsule_and_solid(pair, ray, iota, tol) {
            return Ok(Some(ans));
        }
    }
    if stages.has(Stage::SphereEllipsoid) {
        if let Some(ans) = sphere_and_ellipsoid(pair, ray, iota, tol) {
            return Ok(Some(ans));
        }
    }
    if stages.has(Stage::TwoEllipsoids) {
        if let Some(ans) = two_ellipsoids(pair, ray, iota, tol) {
            return Ok(Some(ans));
        }
    }
    if stages.has(Stage::EllipsoidRod) {
        if let Some(ans) = ellipsoid_and_rod(pair, ray, iota, tol) {
            return Ok(Some(ans));
        }
    }
    if stages.has(Stage::EllipsoidPolytope) {
        if let Some(solved) = ellipsoid_and_polytope(pair, ray, iota, tol, stop) {
            return solved;
        }
    }
    // Spheres, capsules and padded polygons against polytopes and each other: GJK on the
    // cores, exact on polyhedral features.
    let cores = || Cores::with_polygons(pair).filter(Cores::polyhedral);
    if let Some(cores) = stages.has(Stage::PaddedCast).then(cores).flatten() {
        match padded_cast(&cores.posed(pair), ray, cores.pad(), tol, stop) {
            PaddedEnd::Hit(h) => {
                let (a, b) = cores.padded(&h.normal, h.a, h.b);
                return Ok(Some(Answer {
                    alpha: h.alpha,
                    normal: h.normal / h.normal.dot(ray),
                    a,
                    b,
                    solver: Solver::RayCast,
                }));
            }
            PaddedEnd::Decided(below, alpha, n) => return Err((below, alpha, n)),
            PaddedEnd::Failed => {}
        }
    }
    if stages.has(Stage::FlatFaces) {
        if let Some(ans) = flat_first(pair, ray, iota, tol) {
            return Ok(Some(ans));
        }
    }
    // Two polytopes: the cast ends exactly, in a facet of K, within a few refinements; curved
    // pairs hand over to the polish once the bracket is narrow enough to identify the pieces.
    let polyhedral = stages.has(Stage::ExactCast);
    let cast_tol = if polyhedral { tol } else { tol.max(HANDOVER) };
    let newton_first = stages.has(Stage::Newton);
    if newton_first {
        // A threshold first gets the cast's early decision (a few support calls); undecided,
        // the query goes on exactly as one without a threshold, so that both give the same
        // answer.
        if let Some(stop) = stop {
            decided(&cast(pair, ray, iota, cast_tol, CAST_BUDGET, Some(stop)))?;
        }
        // Newton's method on the support function alone, where it certifies.
        if let Some(p) = direct(pair, ray, iota, tol) {
            return Ok(Some(Answer::polished(p)));
        }
    }
    let c = cast(
        pair,
        ray,
        iota,
        cast_tol,
        CAST_BUDGET,
        // The threshold's early decision, unless the cast with it ran already above.
        stop.filter(|_| !newton_first),
    );
    decided(&c)?;
    let from_cast = |c: &Cast| {
        let (a, b) = c.points();
        Answer {
            alpha: c.alpha_hi,
            normal: c.normal / c.normal.dot(ray),
            a,
            b,
            solver: Solver::RayCast,
        }
    };
    // A loose tolerance is met by the cast alone; a support point on the ray is exact.
    if c.end == CastEnd::Exact
        || ((tol >= HANDOVER || polyhedral) && matches!(c.end, CastEnd::Closed | CastEnd::Flat))
    {
        return Ok(Some(from_cast(&c)));
    }
    if c.end == CastEnd::Degenerate {
        return Ok(None);
    }
    // Elsewhere a portal pins α' (to second order) but not the normal or the point: a tiny
    // portal on a curved patch also ends "flat" to rounding, with its normal and point only as
    // good as the portal is small. The polish finishes both.
    if let Some(p) =
        after_cast(pair, ray, &c, iota, tol).or_else(|| polish(pair, ray, &c, iota, tol))
    {
        return Ok(Some(Answer::polished(p)));
    }
    if c.end == CastEnd::Flat {
        // A flat face of K the polish cannot describe (a disc against a facet, say).
        let ans = from_cast(&c);
        return Ok(Some(refined(pair, ray, iota, tol, &ans).unwrap_or(ans)));
    }
    // The polish could not certify: refine the portal further. Its bracket pins α' but its
    // point only to about the bracket's square root on a curved patch: the point is then
    // refined on the contact features the portal's normal identifies, where they are unique.
    let c = cast(pair, ray, iota, tol, CAST_RESCUE, None);
    if !(c.alpha_hi - c.alpha_lo <= tol * c.alpha_lo) {
        return Ok(None);
    }
    let ans = from_cast(&c);
    Ok(Some(refined(pair, ray, iota, tol, &ans).unwrap_or(ans)))
}

/// `ans` refined by Newton's method on the contact features at its normal
/// (`crate::solver::sensitivity::refine`), if that solution's bracket closes to `tol`.
fn refined(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    ans: &Answer,
) -> Option<Answer> {
    let sol = Solution {
        r: *ray,
        normal: ans.normal,
        mu: 1.0 / ans.alpha,
        a: ans.a,
        b: ans.b,
    };
    let better = refine(pair, &sol)?;
    let n = better.normal;
    let lo = n.dot(ray) / pair.support(&n).w.dot(&n);
    let hi = upper_from_point(&(better.a - better.b), ray, iota);
    (lo.is_finite() && hi - lo <= tol * lo).then_some(Answer {
        alpha: lo,
        normal: n / n.dot(ray),
        a: better.a,
        b: better.b,
        solver: Solver::Polish,
    })
}
