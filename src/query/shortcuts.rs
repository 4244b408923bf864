//! Pair-specific answers the geometric path tries before its general solvers (Newton on the
//! support function, the ray cast and its polish): a capsule against a box, cylinder or cone
//! (`crate::solver::segment_solid`), a sphere and an ellipsoid (`crate::solver::ellipsoid_point`),
//! two ellipsoids (`crate::solver::ellipsoid_pair`), an ellipsoid against a capsule or cylinder
//! (`crate::solver::ellipsoid_rod`), an ellipsoid against a polytope (seen
//! through the map that makes the ellipsoid a ball), and a polytope's facet or a cylinder's or
//! cone's cap as the contact face. Each candidate is certified on the shapes themselves, as a
//! polish answer is: the support functions at its normal below, its touching points above.

use super::cores::Core;
use crate::math::{Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::ellipsoid_pair::contact;
use crate::solver::ellipsoid_point::sphere_alpha;
use crate::solver::ellipsoid_rod::touch;
use crate::solver::gjk::padded::{padded_cast, PaddedEnd};
use crate::solver::polish::Polished;
use crate::solver::raycast::{upper_from_point, Pair, Posed, Stop};
use crate::solver::segment_solid::{rounded_facet_alpha, segment_solid_alpha};
use crate::solver::Solver;

/// How far outside its shape (in its gauge) `flat_first`'s point may fall to rounding.
const FACE_SLACK: Real = 1e-12;

/// The geometric answer in the normalised frame.
pub(super) struct Answer {
    pub alpha: Real,
    /// The optimal normal, scaled so that `n·r = 1`.
    pub normal: Vec3,
    /// Points of shape 1 and 2, relative to their origins (normalised units).
    pub a: Vec3,
    pub b: Vec3,
    pub solver: Solver,
}

impl Answer {
    /// A Newton answer (the direct solve, the tie solve or the polish), certified.
    pub(super) fn polished(p: Polished) -> Self {
        Answer {
            alpha: p.alpha_lo,
            normal: p.normal,
            a: p.a,
            b: p.b,
            solver: Solver::Polish,
        }
    }
}

/// The answer (`Ok(None)`: fall back), or `Err((below, bound, normal))` when the bracket
/// decided the threshold first: `normal` (world orientation, any length) is the direction whose
/// support bound gave the bracket's lower end, a separating direction when not `below`.
pub(super) type Solved = Result<Option<Answer>, (bool, Real, Vec3)>;

/// A capsule and a centred box, a cylinder or a cone: Newton's method on 1/α with the
/// segment's closest points (`crate::solver::segment_solid`); a capsule and a polytope
/// touching on a facet: the facets' slabs. Certified as a polish answer is (the
/// support functions at the normal below, the touching points' difference above).
pub(super) fn capsule_and_solid(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
) -> Option<Answer> {
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
pub(super) fn sphere_and_ellipsoid(
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
pub(super) fn two_ellipsoids(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
) -> Option<Answer> {
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

/// An ellipsoid and a capsule or cylinder, either order: Newton's method on the support
/// function along the side, else on the end (ball or rim) the side's weight points to
/// (`crate::solver::ellipsoid_rod::touch`), certified as a polish answer is.
pub(super) fn ellipsoid_and_rod(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
) -> Option<Answer> {
    // A capsule's (half-length, radius, false) or a cylinder's (.., true).
    let rod = |posed: &Posed<'_, Shape>| match posed.shape.rounded_segment() {
        Some((half, radius)) if half > 0.0 => Some((half, radius, false)),
        _ => posed
            .shape
            .cylinder_dims()
            .map(|(radius, half)| (half, radius, true)),
    };
    // The ellipsoid, the rod, its dimensions, the ray from the ellipsoid to the rod, and
    // whether the ellipsoid is shape 1.
    let (ell, cap, (half, radius, disc), dir, first) = match (rod(&pair.one), rod(&pair.two)) {
        (None, Some(c)) => (&pair.one, &pair.two, c, *ray, true),
        (Some(c), None) => (&pair.two, &pair.one, c, -ray, false),
        _ => return None,
    };
    // Σ = R P⁻¹ Rᵀ in the normalised lengths (a length scaled by s scales Σ by s²).
    let inv = ell.shape.ellipsoid_inverse()?;
    let s = ell.inv_scale;
    let sigma = ell.rot * inv * ell.rot.transpose() * (s * s);
    let axis = cap.rot.column(0).into_owned();
    let c = cap.inv_scale;
    // A step of √tol/10 leaves the iterate within about its square.
    let converged = (0.1 * tol.sqrt()).clamp(1e-8, 1e-3);
    let t = touch(&sigma, &axis, half * c, radius * c, &dir, converged, disc)?;
    let (n, a, b) = if first {
        (t.normal, t.on_ellipsoid, t.on_capsule)
    } else {
        (-t.normal, t.on_capsule, t.on_ellipsoid)
    };
    certified(pair, ray, iota, tol, &n, a, b)
}

/// An ellipsoid and a polytope (a box among them), either order, as a sphere and a polytope:
/// α* does not change when one linear map is applied to the whole scene (both shapes scale
/// about their origins, and the map commutes with that), and `T = U Rᵀ/s` (`P = UᵀU`) maps the
/// ellipsoid onto the unit ball. The polytope seen through T has the support map
/// `T·supp(Tᵀm)`, which is its own support map turned by the (not orthogonal) matrix `T R`, so
/// the padded cast runs on a point padded by 1 against it, along the ray `T r`. Its answer
/// comes back through T (the normal by `Tᵀ`, the points by `T⁻¹`) and is certified on the
/// shapes themselves. `None` for other pairs, or when that does not certify.
pub(super) fn ellipsoid_and_polytope(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    stop: Option<Stop>,
) -> Option<Solved> {
    let polytope = |posed: &Posed<'_, Shape>| posed.shape.solver_kind() == ShapeKind::Polytope;
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
        PaddedEnd::Decided(below, alpha, m) => {
            // A plane of normal m in the mapped space is one of normal Tᵀm in the shapes'.
            return Some(Err((below, alpha * len, t.transpose() * m)));
        }
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

/// A flat face of one shape as the contact: a polytope's facet against a cylinder or cone, or
/// a cylinder's cap or a cone's base against a polytope, cylinder, cone or ellipsoid. Every
/// such face's outward normal n gives the lower bound `n·r/h_K(n)`, `h_K(n)` the face's offset
/// plus the other shape's support function (from its meridian section when it is a cylinder
/// or cone, else one support call), and if the optimum is at a face's normal it is the best of
/// them. Then the other shape's support point there and the point of the face's shape that puts
/// their difference on the ray touch, and the bracket closes, exactly when that point lies in
/// the shape (one gauge). Tried on the pairs `super::dispatch` lists it for; `None` when the
/// contact is not on a face.
pub(super) fn flat_first(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
) -> Option<Answer> {
    use ShapeKind::*;
    let kinds = [pair.one.shape.solver_kind(), pair.two.shape.solver_kind()];
    let revolution = |k: ShapeKind| matches!(k, Cylinder | Cone);
    // Each shape's best bound: its value and K's normal (from shape 1 to shape 2, world).
    let mut best = [(0.0, Vec3::zeros()); 2];
    for side in 0..2 {
        let (posed, sign) = pair.side(side);
        let (other, other_sign) = pair.side(1 - side);
        match kinds[side] {
            Polytope if revolution(kinds[1 - side]) => {
                let (normals, offsets) = posed.shape.facets()?;
                let (section, count) = other.shape.revolution_section()?;
                // In the polytope's frame, once: the ray and the other shape's axis (its
                // support function at a unit normal m is the best of the section's vertices at
                // the axial part a·m and the radial part √(1 − (a·m)²): two dot products and a
                // square root a facet).
                let ray_body = posed.rot.tr_mul(ray) * sign;
                let axis_body =
                    posed.rot.tr_mul(&other.rot.column(0).into_owned()) * (sign * other_sign);
                let value = |mx: Real| {
                    let mp = (1.0 - mx * mx).max(0.0).sqrt();
                    section[..count]
                        .iter()
                        .fold(Real::NEG_INFINITY, |h, v| h.max(v.0 * mx + v.1 * mp))
                        * other.inv_scale
                };
                for (normal, offset) in normals.iter().zip(offsets) {
                    let nr = normal.dot(&ray_body);
                    if !(nr > 0.0) {
                        continue;
                    }
                    let lo = nr / (offset * posed.inv_scale + value(normal.dot(&axis_body)));
                    if lo > best[side].0 {
                        best[side] = (lo, posed.rot * normal * sign);
                    }
                }
            }
            Cylinder | Cone => {
                // The caps: the section's edges across the axis, at axial coordinate a (normal
                // sign(a)·x, offset |a|).
                let (section, count) = posed.shape.revolution_section()?;
                for k in 0..count {
                    let (v, w) = (section[k], section[(k + 1) % count]);
                    if v.0 != w.0 || v.1 != -w.1 || v.1 == 0.0 {
                        continue;
                    }
                    let n = posed.rot.column(0) * (v.0.signum() * sign);
                    let nr = n.dot(ray);
                    if !(nr > 0.0) {
                        continue;
                    }
                    let seen = n * other_sign;
                    let h = v.0.abs() * posed.inv_scale + other.support(&seen).0.dot(&seen);
                    let lo = nr / h;
                    if lo > best[side].0 {
                        best[side] = (lo, n);
                    }
                }
            }
            _ => {}
        }
    }
    // The better bound first; the other too when they tie (face against face, where either
    // face's own support point may miss the other face).
    let first = usize::from(best[1].0 > best[0].0);
    let tie = best[1 - first].0 >= best[first].0 * (1.0 - 1e-12);
    [first, 1 - first]
        .into_iter()
        .take(if tie { 2 } else { 1 })
        .find_map(|side| {
            let (lo, n) = best[side];
            on_face(
                pair,
                ray,
                iota,
                tol,
                side,
                lo,
                &n,
                revolution(kinds[1 - side]),
            )
        })
}

/// `flat_first`'s candidate: shape `side`'s face with K's normal `n` and bound `lo`, certified
/// when the point of that shape that puts its difference with the other's support point on the
/// ray lies in the shape. `revolution`: the other shape is a cylinder or cone (its cap's centre
/// is tried when its rim point misses).
#[allow(clippy::too_many_arguments)]
fn on_face(
    pair: &Pair<'_, Shape>,
    ray: &Vec3,
    iota: Real,
    tol: Real,
    side: usize,
    lo: Real,
    n: &Vec3,
    revolution: bool,
) -> Option<Answer> {
    if !(lo > 0.0 && lo.is_finite()) {
        return None;
    }
    let (posed, _) = pair.side(side);
    let (other, other_sign) = pair.side(1 - side);
    let seen = n * other_sign;
    let target = ray / lo;
    let own_at = |p: &Vec3| if side == 0 { target + p } else { p - target };
    let mut p = other.support(&seen).0;
    let mut own = own_at(&p);
    let mut g = posed.shape_gauge(&own);
    // Face against face (a can on a can, a cone's base on a cap): the other's support point is
    // one of its face's rim points, which need not face the first face; its face's centre is
    // tried too.
    if !(g <= 1.0 + FACE_SLACK) && revolution {
        let axis = other.rot.column(0).into_owned();
        if axis.dot(&seen).abs() >= 1.0 - 1e-12 {
            p = axis * axis.dot(&p);
            own = own_at(&p);
            g = posed.shape_gauge(&own);
        }
    }
    if !(g <= 1.0 + FACE_SLACK) {
        return None;
    }
    // Rounding can leave the point a hair outside the face: pulled in, it lies in the shape.
    let own = if g > 1.0 { own / g } else { own };
    let (a, b) = if side == 0 { (own, p) } else { (p, own) };
    certified(pair, ray, iota, tol, n, a, b)
}
