//! Proximity on support maps: closed forms where the pair has one; else, on pairs with a curved
//! shape, Newton's method on the support function from the ray's direction
//! (`crate::solver::direct`); else a ray cast (MPR) that identifies the contact features and
//! Newton's method on them (the tie solve of `direct`, else the polish's KKT Newton). Each is
//! certified;
//! `Outcome::Fallback` sends the query to the interior-point solver.
//!
//! The frame is the interior-point path's: origin at `r₁`, lengths divided by `ℓ = max(ρ₁, ρ₂)`;
//! the ray is the unit vector `r = (r₂ − r₁)/‖r₂ − r₁‖`, and α* = α'·‖r₂ − r₁‖/ℓ with α' the
//! gauge of the normalised Minkowski difference at `r` (α* is homogeneous of degree one in the
//! offset, so no precision is lost at tiny or huge offsets).

use super::context::{Options, Proximity};
use super::cores::{Core, Cores};
use super::derivatives::rotation_axes;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::closed_form::{rounded_segments, sphere_box, sphere_revolution, RoundedSegment};
use crate::solver::direct::{after_cast, direct};
use crate::solver::ellipsoid_pair::contact;
use crate::solver::ellipsoid_point::sphere_alpha;
use crate::solver::gjk::padded::{padded_cast, PaddedEnd};
use crate::solver::polish::{polish, Polished};
use crate::solver::raycast::{cast, upper_from_point, Cast, CastEnd, Pair, Posed, Stop};
use crate::solver::segment_solid::{rounded_facet_alpha, segment_solid_alpha};
use crate::solver::sensitivity::{contact_is_unique, refine, sensitivity, Solution};
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
/// How far outside the polytope (in its gauge) `facet_first`'s point may fall to rounding.
const FACET_SLACK: Real = 1e-12;
/// The certified bracket is closed to this fraction of the requested tolerance. The
/// interior-point solver's tolerance bounds its duality measure, and its polish lands about
/// three orders of magnitude below it; a bracket is the error bound itself, so it is closed as
/// far below to give the same accuracy for the same setting.
const MARGIN: Real = 1e-3;

/// What the geometric path concluded.
pub(crate) enum Outcome {
    /// The certified bracket excluded the threshold: α* is below it (`true`) or above it;
    /// `alpha` is the bracket's end on that side (world units).
    Decided { below: bool, alpha: Real },
    /// The full answer, with `∂α*/∂(r₂ − r₁)` (the optimal normal `n*/h_K(n*)`, world units).
    Answer(Proximity, Vec3),
    /// The geometric solvers could not certify an answer: run the interior-point solver.
    Fallback,
}

/// The geometric answer in the normalised frame.
struct Answer {
    alpha: Real,
    /// The optimal normal, scaled so that `n·r = 1`.
    normal: Vec3,
    /// Points of shape 1 and 2, relative to their origins (normalised units).
    a: Vec3,
    b: Vec3,
    solver: Solver,
}

/// Proximity by the geometric solvers, stopping early once α* is proven above `threshold.0`
/// (or below it, when `threshold.1`); [`Outcome::Fallback`] when they cannot certify the
/// answer to the requested tolerance. `dist = ‖r₂ − r₁‖ > 0`.
pub(crate) fn proximity(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    dist: Real,
    threshold: Option<(Real, bool)>,
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
    let stop = threshold.map(|(t, stop_below)| Stop {
        value: t / world,
        stop_below,
    });
    let ans = match solve(&pair, &ray, iota, options.tolerance, stop) {
        Ok(Some(ans)) => ans,
        Ok(None) => return Outcome::Fallback,
        Err((below, alpha)) => {
            return Outcome::Decided {
                below,
                alpha: alpha * world,
            }
        }
    };
    // The touching point x* = r₁ + α*·ℓ·a; contact points r₁ + ℓa, r₂ + ℓb.
    let alpha = ans.alpha * world;
    let contact1 = r1 + ans.a * ell;
    let contact2 = r2 + ans.b * ell;
    let point = r1 + ans.a * (alpha * ell);
    let finite = alpha.is_finite()
        && point.iter().all(|v| v.is_finite())
        && contact1.iter().all(|v| v.is_finite())
        && contact2.iter().all(|v| v.is_finite());
    if !finite {
        return Outcome::Fallback;
    }
    // ∂α*/∂d = n/h_K(n) (world): with n·r = 1 and h_K'(n) = 1/α' in the normalised lengths,
    // n·α'/ℓ.
    let dalpha_dd = ans.normal * (ans.alpha * inv);
    Outcome::Answer(
        Proximity {
            alpha,
            point,
            contact1,
            contact2,
            iterations: 0,
            status: SolveStatus::Converged,
            solver: ans.solver,
            derivatives: DerivativeKind::None,
        },
        dalpha_dd,
    )
}

/// `∂α*/∂(r₁, q₁, r₂, q₂)` from the geometric solution by the envelope theorem
/// (`../shared/ALGORITHMS.md` §4): with `ñ = n*/h_K(n*)`, `∂α*/∂r₂ = ñ = −∂α*/∂r₁`; a change of
/// `qᵢ` moves shape i's support function at `n*` through its support point `bᵢ*` (body frame),
/// `∂h₁(n)/∂q₁ₖ = n·(∂R₁/∂q₁ₖ) b₁*` and `∂h₂(−n)/∂q₂ₖ = −n·(∂R₂/∂q₂ₖ) b₂*`, and
/// `∂α*/∂h_K = −α*/h_K`. Exact wherever the optimal normal and support points are unique. A
/// sphere's support function does not depend on its attitude: its columns are exactly zero.
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
    // n·(∂Qᵢ/∂qᵢₖ)bᵢ = ωᵢₖ·(wᵢ × n).
    let alpha = prox.alpha;
    if shapes[0].kind() != ShapeKind::Sphere {
        let t = (prox.contact1 - pose1.position()).cross(dalpha_dd) * -alpha;
        for (k, w) in rotation_axes(pose1).iter().enumerate() {
            g[3 + k] = w.dot(&t);
        }
    }
    if shapes[1].kind() != ShapeKind::Sphere {
        let t = (prox.contact2 - pose2.position()).cross(dalpha_dd) * alpha;
        for (k, w) in rotation_axes(pose2).iter().enumerate() {
            g[10 + k] = w.dot(&t);
        }
    }
    g
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
    let strict = |s: &Shape| matches!(s.kind(), ShapeKind::Sphere | ShapeKind::Ellipsoid);
    if strict(shapes[0]) || strict(shapes[1]) {
        return true;
    }
    let (pair, sol, _) = normalised(prox, dalpha_dd, shapes, poses);
    contact_is_unique(&pair, &sol)
}

/// `∂(x*, α*)/∂(r₁, q₁, r₂, q₂)` (4×14, rows x₁, x₂, x₃, α) from the geometric solution, by
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
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> Option<[[Real; 14]; 4]> {
    let (pair, sol, s) = normalised(prox, dalpha_dd, shapes, poses);
    let (ell, inv) = (1.0 / pair.one.inv_scale, pair.one.inv_scale);
    let axes = [rotation_axes(poses[0]), rotation_axes(poses[1])];
    let sens = sensitivity(&pair, &sol, &axes)?;
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
    let round = shapes.map(|s| s.kind() == ShapeKind::Sphere);
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
    j.iter().flatten().all(|v| v.is_finite()).then_some(j)
}

/// The answer (`Ok(None)`: fall back), or `Err((below, bound))` when the bracket decided the
/// threshold first.
type Solved = Result<Option<Answer>, (bool, Real)>;

/// `Err((below, bound))` when the cast's bracket decided the threshold: the bracket's end on
/// that side.
fn decided(c: &Cast) -> Result<(), (bool, Real)> {
    match c.end {
        CastEnd::Decided(below) => Err((below, if below { c.alpha_hi } else { c.alpha_lo })),
        _ => Ok(()),
    }
}

impl Answer {
    /// A Newton answer (the direct solve, the tie solve or the polish), certified.
    fn polished(p: Polished) -> Self {
        Answer {
            alpha: p.alpha_lo,
            normal: p.normal,
            a: p.a,
            b: p.b,
            solver: Solver::Polish,
        }
    }
}

/// Whether Newton's method on the support function goes first: with a sphere or an ellipsoid
/// (strictly convex, so the optimum is mostly on a smooth patch of K), with a capsule (its
/// side is a single tie), or between cylinders and cones. A cylinder or cone against a polytope
/// or padded polygon, or two of those, meets mostly on an edge or face of K where the support
/// alternates between many pieces, or a vertex against a rim where the Hessian is singular:
/// the ray cast identifies those faster (measured: direct first costs 1.1–2.5× there).
fn direct_first(pair: &Pair<'_, Shape>) -> bool {
    use ShapeKind::*;
    let kinds = [pair.one.shape.kind(), pair.two.shape.kind()];
    let round = |k: &ShapeKind| matches!(k, Sphere | Ellipsoid);
    let faceted = |k: &ShapeKind| matches!(k, Polytope | Polygon);
    kinds.iter().any(round) || kinds.contains(&Capsule) || !kinds.iter().any(faceted)
}

/// Sphere and capsule pairs, a sphere with a centred box, a cylinder or a cone, in closed form.
fn closed_form(pair: &Pair<'_, Shape>, ray: &Vec3) -> Option<Answer> {
    let seg = RoundedSegment::of;
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
    let (one, two) = (seg(&pair.one)?, seg(&pair.two)?);
    let hit = rounded_segments(ray, &one, &two)?;
    Some(Answer {
        alpha: hit.alpha,
        normal: hit.normal / hit.normal.dot(ray),
        a: one.axis * hit.s + hit.normal * one.radius,
        b: two.axis * hit.t - hit.normal * two.radius,
        solver: Solver::ClosedForm,
    })
}

/// A capsule and a centred box, a cylinder or a cone: Newton's method on 1/α with the
/// segment's closest points (`crate::solver::segment_solid`); a capsule and a polytope
/// touching on a facet: the facets' slabs. Certified as a polish answer is (the
/// support functions at the normal below, the touching points' difference above).
fn capsule_and_solid(pair: &Pair<'_, Shape>, ray: &Vec3, iota: Real, tol: Real) -> Option<Answer> {
    let hit = segment_solid_alpha(pair, ray).or_else(|| rounded_facet_alpha(pair, ray))?;
    certified(pair, ray, iota, tol, &hit.normal, hit.a, hit.b)
}

/// A candidate α\* found outside the solvers, certified as a polish answer is: the unit normal
/// `n` from shape 1 to shape 2 gives the lower bound `n·r / h_K(n)` (one support call), the
/// touching points `a ∈ K₁`, `b ∈ K₂` the upper bound from `a − b ∈ K`; the answer when the
/// bracket closes to `tol` (relative).
fn certified(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    n: &Vec3,
    a: Vec3,
    b: Vec3,
) -> Option<Answer> {
    let nr = n.dot(ray);
    if !(nr > 0.0) {
        return None;
    }
    let lo = nr / pair.support(n).w.dot(n);
    let hi = upper_from_point(&(a - b), ray, iota);
    (lo.is_finite() && hi - lo <= tol * lo).then_some(Answer {
        alpha: lo,
        normal: n / nr,
        a,
        b,
        solver: Solver::ClosedForm,
    })
}

/// A sphere and an ellipsoid, either order: the secular equation of the sphere's centre on the
/// ray (`crate::solver::ellipsoid_point::sphere_alpha`), certified as a polish answer is.
fn sphere_and_ellipsoid(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
) -> Option<Answer> {
    let ball = |posed: &Posed<'_, Shape>| match posed.shape.rounded_segment() {
        Some((0.0, radius)) => Some(radius),
        _ => None,
    };
    // The ellipsoid, the sphere's radius, the ray from the ellipsoid to the sphere, and whether
    // the ellipsoid is shape 1.
    let (solid, rho, dir, first) = match (ball(&pair.one), ball(&pair.two)) {
        (None, Some(rho)) => (&pair.one, rho, *ray, true),
        (Some(rho), None) => (&pair.two, rho, -ray, false),
        _ => return None,
    };
    let (axes, semi) = solid.shape.ellipsoid_principal()?;
    let s = solid.inv_scale;
    let c = axes.tr_mul(&solid.rot.tr_mul(&dir)) / s;
    let (beta, x) = sphere_alpha(&c, semi, rho)?;
    let gap = c * beta - x;
    let len = gap.norm();
    if !(len > 0.0) {
        return None;
    }
    // From the ellipsoid to the sphere, world axes; the touching points, normalised.
    let m = solid.rot * (axes * (gap / len));
    let on_solid = solid.rot * (axes * x) * s;
    let on_sphere = -m * (rho * s);
    let (n, a, b) = if first {
        (m, on_solid, on_sphere)
    } else {
        (-m, on_sphere, on_solid)
    };
    certified(pair, ray, iota, tol, &n, a, b)
}

/// Two ellipsoids: the Perram–Wertheim contact function
/// (`crate::solver::ellipsoid_pair::contact`), certified as a polish answer is.
fn two_ellipsoids(pair: &Pair<'_, Shape>, ray: &Vec3, iota: Real, tol: Real) -> Option<Answer> {
    // Σᵢ = Rᵢ P⁻¹ Rᵢᵀ in the normalised lengths (a length scaled by s scales Σ by s²).
    let sigma = |posed: &Posed<'_, Shape>| {
        let inv = posed.shape.ellipsoid_inverse()?;
        let s = posed.inv_scale;
        Some(posed.rot * inv * posed.rot.transpose() * (s * s))
    };
    let (s1, s2) = (sigma(&pair.one)?, sigma(&pair.two)?);
    let c = contact(&s1, &s2, ray)?;
    certified(pair, ray, iota, tol, &c.normal, c.a, c.b)
}

/// An ellipsoid and a polytope (a box among them), either order, as a sphere and a polytope:
/// α* does not change when one linear map is applied to the whole scene (both shapes scale
/// about their origins, and the map commutes with that), and `T = U Rᵀ/s` (`P = UᵀU`) maps the
/// ellipsoid onto the unit ball. The polytope seen through T has the support map
/// `T·supp(Tᵀm)`, which is its own support map turned by the (not orthogonal) matrix `T R`, so
/// the padded cast runs on a point padded by 1 against it, along the ray `T r`. Its answer
/// comes back through T (the normal by `Tᵀ`, the points by `T⁻¹`) and is certified on the
/// shapes themselves. `None` for other pairs, or when that does not certify.
fn ellipsoid_and_polytope(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    stop: Option<Stop>,
) -> Option<Solved> {
    let polytope = |posed: &Posed<'_, Shape>| posed.shape.kind() == ShapeKind::Polytope;
    let (ell, poly, first) = if polytope(&pair.two) {
        (&pair.one, &pair.two, true)
    } else if polytope(&pair.one) {
        (&pair.two, &pair.one, false)
    } else {
        return None;
    };
    let u = ell.shape.ellipsoid_cholesky()?;
    let t = u * ell.rot.transpose() / ell.inv_scale;
    let t_inv = t.try_inverse()?;
    let turn = t * poly.rot;
    let point = Core::Segment(0.0);
    let identity = crate::math::Mat3::identity();
    let ball = Posed {
        shape: &point,
        rot: &identity,
        inv_scale: 1.0,
    };
    let seen = Posed {
        shape: &Core::Whole(poly.shape),
        rot: &turn,
        inv_scale: poly.inv_scale,
    };
    let cores = if first {
        Pair {
            one: ball,
            two: seen,
        }
    } else {
        Pair {
            one: seen,
            two: ball,
        }
    };
    let tr = t * ray;
    let len = tr.norm();
    // α' for the ray `r` is `len` times α' for the unit ray `Tr/len`.
    let stop = stop.map(|s| Stop {
        value: s.value / len,
        ..s
    });
    let hit = match padded_cast(&cores, &(tr / len), 1.0, tol, stop) {
        PaddedEnd::Hit(h) => h,
        PaddedEnd::Decided(below, alpha) => return Some(Err((below, alpha * len))),
        PaddedEnd::Failed => return None,
    };
    // The ball's witness moves out by its radius along the normal (from shape 1 to shape 2).
    let (a, b) = if first {
        (hit.a + hit.normal, hit.b)
    } else {
        (hit.a, hit.b - hit.normal)
    };
    let n = (t.transpose() * hit.normal).try_normalize(0.0)?;
    let ans = certified(pair, ray, iota, tol, &n, t_inv * a, t_inv * b)?;
    Some(Ok(Some(Answer {
        solver: Solver::RayCast,
        ..ans
    })))
}

/// A polytope (a box among them) against a cylinder or cone, either order, when the contact
/// is on one of the polytope's facets: every facet's normal n gives the lower bound
/// `n·r/h_K(n)`, `h_K(n)` its offset plus one support call of the other shape, and if the
/// optimum is at a facet's normal it is the best of them. Then the other shape's support point
/// there and the point of the polytope that puts their difference on the ray touch, and the
/// bracket closes, exactly when that point lies in the polytope (one gauge). `None` for other
/// pairs or when the contact is not on a facet.
#[inline(never)]
fn facet_first(pair: &Pair<'_, Shape>, ray: &Vec3, iota: Real, tol: Real) -> Option<Answer> {
    let curved = |posed: &Posed<'_, Shape>| {
        matches!(posed.shape.kind(), ShapeKind::Cylinder | ShapeKind::Cone)
    };
    let polytope = |posed: &Posed<'_, Shape>| posed.shape.kind() == ShapeKind::Polytope;
    let side = if polytope(&pair.one) && curved(&pair.two) {
        0
    } else if polytope(&pair.two) && curved(&pair.one) {
        1
    } else {
        return None;
    };
    let (posed, sign) = pair.side(side);
    let (other, other_sign) = pair.side(1 - side);
    let (normals, offsets) = posed.shape.facets()?;
    // The other shape's support function from its meridian section: at a unit world normal m
    // with axial part mₓ = a·m and radial part √(1 − mₓ²), the best of the section's vertices
    // (three products and a square root where a support point costs two turns).
    let (section, count) = other.shape.revolution_section()?;
    // In the polytope's frame, once: the ray and the other shape's axis (its support function
    // at a unit normal m is the best of the section's vertices at the axial part a·m and the
    // radial part √(1 − (a·m)²): two dot products and a square root a facet).
    let ray_body = posed.rot.tr_mul(ray) * sign;
    let axis_body = posed.rot.tr_mul(&other.rot.column(0).into_owned()) * (sign * other_sign);
    let value = |mx: Real| {
        let mp = (1.0 - mx * mx).max(0.0).sqrt();
        section[..count]
            .iter()
            .fold(Real::NEG_INFINITY, |h, v| h.max(v.0 * mx + v.1 * mp))
            * other.inv_scale
    };
    // The best bound: its value and the facet.
    let mut best = (0.0, 0);
    for (k, (normal, offset)) in normals.iter().zip(offsets).enumerate() {
        let nr = normal.dot(&ray_body);
        if !(nr > 0.0) {
            continue;
        }
        let lo = nr / (offset * posed.inv_scale + value(normal.dot(&axis_body)));
        if lo > best.0 {
            best = (lo, k);
        }
    }
    let (lo, k) = best;
    if !(lo > 0.0 && lo.is_finite()) {
        return None;
    }
    // K's normal (from shape 1 to shape 2), world.
    let n = posed.rot * normals[k] * sign;
    let p = other.support(&(n * other_sign)).0;
    let target = ray / lo;
    let own = if side == 0 { target + p } else { p - target };
    let g = posed.shape_gauge(&own);
    if !(g <= 1.0 + FACET_SLACK) {
        return None;
    }
    // Rounding can leave the point a hair outside the facet: pulled in, it lies in the shape.
    let own = if g > 1.0 { own / g } else { own };
    let (a, b) = if side == 0 { (own, p) } else { (p, own) };
    certified(pair, ray, iota, tol, &n, a, b)
}

fn solve(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tolerance: Real,
    stop: Option<Stop>,
) -> Solved {
    if let Some(ans) = closed_form(pair, ray) {
        return Ok(Some(ans));
    }
    // No bracket can be certified much below the rounding of the bounds themselves.
    let tol = (tolerance * MARGIN).max(TOL_FLOOR);
    if let Some(ans) = capsule_and_solid(pair, ray, iota, tol)
        .or_else(|| sphere_and_ellipsoid(pair, ray, iota, tol))
        .or_else(|| two_ellipsoids(pair, ray, iota, tol))
    {
        return Ok(Some(ans));
    }
    if let Some(solved) = ellipsoid_and_polytope(pair, ray, iota, tol, stop) {
        return solved;
    }
    // Spheres, capsules and padded polygons against polytopes and each other: GJK on the
    // cores, exact on polyhedral features.
    if let Some(cores) = Cores::with_polygons(pair).filter(Cores::polyhedral) {
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
            PaddedEnd::Decided(below, alpha) => return Err((below, alpha)),
            PaddedEnd::Failed => {}
        }
    }
    if let Some(ans) = facet_first(pair, ray, iota, tol) {
        return Ok(Some(ans));
    }
    // Two polytopes: the cast ends exactly, in a facet of K, within a few refinements; curved
    // pairs hand over to the polish once the bracket is narrow enough to identify the pieces.
    let polyhedral = [pair.one.shape, pair.two.shape]
        .iter()
        .all(|s| s.kind() == ShapeKind::Polytope);
    let cast_tol = if polyhedral { tol } else { tol.max(HANDOVER) };
    let newton_first = direct_first(pair);
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
