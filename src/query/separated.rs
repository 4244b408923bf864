//! The exact distance of separated shapes by GJK on their support maps
//! (`crate::solver::gjk`), tried before the interior-point distance program: a certified
//! answer is returned as it is; touching, overlapping or uncertified pairs go to the
//! interior-point path unchanged.
//!
//! The gradient comes from the envelope theorem on `d* = max over unit n of
//! n·(r₂ − r₁) − h₁(R₁ᵀn) − h₂(−R₂ᵀn)`: `∂d*/∂r₂ = n* = −∂d*/∂r₁`,
//! `∂d*/∂q₁ₖ = −n*·(∂R₁/∂q₁ₖ) β₁` and `∂d*/∂q₂ₖ = n*·(∂R₂/∂q₂ₖ) β₂`, with `βᵢ` the witness
//! point of shape i in its body frame (the same expression as the interior-point path's
//! Lagrangian form at its optimum). A sphere's columns are exactly zero.

use super::context::{Distance, DistancePath};
use super::cores::Cores;
use super::dispatch::{route, Stage};
use crate::math::{finite_array, rotation_derivatives, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::closed_form::{closest_segment_points, sphere_solid, RoundedSegment};
use crate::solver::gjk::{self, GjkEnd, Route, Separation};
use crate::solver::raycast::{Pair, Posed, Vertex};
use crate::solver::segment_solid::{segment_solid, SegmentSolid};
use crate::solver::SolveStatus;

/// GJK iterations before the polish (curved pairs hand over earlier, polytopes end exactly).
const BUDGET: u32 = 64;
/// The bracket is closed to this fraction of the options' tolerance (in units of ℓ), as the
/// geometric proximity path does, but not below a few roundings.
pub(super) const MARGIN: Real = 1e-3;
pub(super) const TOL_FLOOR: Real = 1e-14;
/// How far (relative gauge) outside its shape a point projected onto a face may lie and
/// still count as on it (rounding); it is pulled in before use.
const FACE_SLACK: Real = 1e-12;

/// What GJK settled about a pair.
pub(crate) enum Settled {
    /// The distance and gradient; the flag says the distance was proven above the cutoff (the
    /// distance is then infinite).
    Apart(Distance, [Real; 14], bool),
    /// Overlap certified (the origin strictly inside a tetrahedron of support points of the
    /// shapes or their cores), with a point common to both shapes (world).
    Overlapping(Vec3),
    /// Neither: the interior-point path or the proximity must answer.
    Unsettled,
}

/// What the distance's GJK leaves for the signed distance (`super::signed`) when it does not
/// prove the shapes apart.
// Written once per query through an out-parameter, never moved in a loop: the size is fine.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy)]
pub(crate) enum Start {
    /// GJK's tetrahedron on a certified overlap ([`GjkEnd::Inside`]): support vertices whose
    /// `w` hold `d` strictly inside, a start for EPA. They are of the cores when `cored` (a
    /// padded polygon's plane polygon where [`Cores::flat`], else those of [`Cores::of`]),
    /// else of the shapes.
    Tet { cored: bool, tet: [Vertex; 4] },
    /// The cores (as for `Tet`) certified apart, but not by more than their radii and the
    /// tolerance: their GJK answer (the cores' distance and witnesses, not padded), from which
    /// the signed distance is the distance less the radii.
    CoresApart(Separation),
}

/// The distance and gradient by GJK, or a certified overlap, or neither (`cutoff` in world
/// units; `ell` is the larger bounding radius); where GJK certified an overlap, its
/// tetrahedron is written to `start`, and where it found the cores apart by less than their
/// radii (an overlap certified too when by less than the radii to rounding) or within the
/// tolerance of them, the cores' answer.
#[allow(clippy::too_many_arguments)]
pub(crate) fn separated(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    tolerance: Real,
    ell: Real,
    gradient: bool,
    cutoff: Option<Real>,
    mut start: Option<&mut Option<Start>>,
) -> Settled {
    let inv = 1.0 / ell;
    let pair = Pair::new([shape1, shape2], [pose1.rotation(), pose2.rotation()], inv);
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let d = (r2 - r1) * inv;
    let stages = route(shape1, shape2).distance;
    let polyhedral = stages.has(Stage::ExactGjk);
    let tol = (tolerance * MARGIN).max(TOL_FLOOR);
    let cutoff = cutoff.map(|c| c * inv);
    // GJK's tetrahedron, when asked for.
    let mut tet = start.is_some().then(|| [Vertex::default(); 4]);
    // A certified overlap: the common point `a` (normalised, relative to r₁) in world units.
    let overlap = |a: Vec3, cored: bool, tet: Option<[Vertex; 4]>, start: Option<&mut _>| {
        if let (Some(out), Some(tet)) = (start, tet) {
            *out = Some(Start::Tet { cored, tet });
        }
        Settled::Overlapping(r1 + a * ell)
    };
    let beyond = || {
        let far = Distance {
            distance: Real::INFINITY,
            closest1: Vec3::zeros(),
            closest2: Vec3::zeros(),
            normal: Vec3::zeros(),
            iterations: 0,
            status: SolveStatus::Converged,
            path: DistancePath::Gjk,
        };
        Settled::Apart(far, [0.0; 14], true)
    };
    // Newton's method on the sphere of normals first where the witnesses are mostly on smooth
    // pieces (not against a cutoff, which GJK decides early), after a face contact.
    let newton = || {
        (cutoff.is_none() && stages.has(Stage::Newton))
            .then(|| gjk::direct::distance(&pair, &d, tol))
            .flatten()
    };
    let closed = if stages.has(Stage::ClosedForm) {
        match closed_form(&pair, &d, tol) {
            Ok(s) => s,
            Err(w) => return overlap(w, false, None, None),
        }
    } else {
        None
    };
    let faces = || {
        (cutoff.is_none() && stages.has(Stage::FlatFaces))
            .then(|| face_contact(&pair, &d, tol))
            .flatten()
    };
    let s = if let Some(s) = closed.or_else(faces).or_else(newton) {
        s
    } else {
        // Spheres and capsules by their cores first; where those do not certify a positive
        // gap (touching within the tolerance, or closer), the shapes themselves.
        let cores = if stages.has(Stage::CoredGjk) {
            cored(&pair, &d, tol, cutoff, tet.as_mut())
        } else {
            Ok(None)
        };
        match cores {
            Ok(Some(GjkEnd::Separated(s))) => s,
            Ok(Some(GjkEnd::Beyond)) => return beyond(),
            Ok(Some(GjkEnd::Inside { a })) => return overlap(a, true, tet, start),
            _ => {
                if let Err(close) = cores {
                    if let Some(out) = start.as_deref_mut() {
                        *out = Some(Start::CoresApart(close.separation));
                    }
                    if let Some(w) = close.common {
                        return Settled::Overlapping(r1 + w * ell);
                    }
                }
                match gjk::distance(&pair, &d, tol, BUDGET, polyhedral, cutoff, tet.as_mut()) {
                    GjkEnd::Separated(s) => s,
                    GjkEnd::Beyond => return beyond(),
                    GjkEnd::Inside { a } => return overlap(a, false, tet, start),
                    _ => return Settled::Unsettled,
                }
            }
        }
    };
    let Some(result) = in_world(&s, [&r1, &r2], ell) else {
        return Settled::Unsettled;
    };
    let grad = if gradient {
        let (c1, c2) = (&result.closest1, &result.closest2);
        witness_gradient(&result.normal, c1, c2, [shape1, shape2], [pose1, pose2])
    } else {
        [0.0; 14]
    };
    Settled::Apart(result, grad, false)
}

/// The normalised separation `s` in world units (origins `r`, length scale `ℓ = ell`), or
/// `None` unless the distance is positive and the witnesses finite. Shared by [`separated`] and
/// the C ABI's closed-form lane (`super::closed_lane`), which must give the same numbers.
#[inline(always)]
pub(super) fn in_world(s: &Separation, r: [&Vec3; 2], ell: Real) -> Option<Distance> {
    let dist = s.distance * ell;
    let closest1 = r[0] + s.a * ell;
    let closest2 = r[1] + s.b * ell;
    // Every number finite in one test (`finite_array`; the chained iterator it replaces was
    // not inlined, ~110 instructions of a sphere–sphere distance).
    let (c1, c2) = (&closest1, &closest2);
    let finite = dist > 0.0 && finite_array(&[dist, c1.x, c1.y, c1.z, c2.x, c2.y, c2.z]);
    finite.then_some(Distance {
        distance: dist,
        closest1,
        closest2,
        normal: s.normal,
        iterations: 0,
        status: SolveStatus::Converged,
        path: match s.route {
            Route::Gjk => DistancePath::Gjk,
            Route::Polish => DistancePath::GjkPolish,
            Route::ClosedForm => DistancePath::ClosedForm,
        },
    })
}

/// `∂d/∂(r₁, q₁, r₂, q₂)` of `d = max over unit n of n·(r₂ − r₁) − h₁(n) − h₂(−n)` (the
/// distance, or the signed distance) by the envelope theorem at the optimal normal `n` and
/// the witness points: `∂d/∂r₂ = n = −∂d/∂r₁`, `∂d/∂q₁ₖ = −n·(∂R₁/∂q₁ₖ)β₁` and
/// `∂d/∂q₂ₖ = n·(∂R₂/∂q₂ₖ)β₂` with `βᵢ` the witness in body axes. Exact where the normal and the
/// witness points are unique; a sphere's rotation columns are exactly zero.
pub(crate) fn witness_gradient(
    n: &Vec3,
    closest1: &Vec3,
    closest2: &Vec3,
    shapes: [&Shape; 2],
    poses: [&Pose; 2],
) -> [Real; 14] {
    let mut grad = [0.0; 14];
    for j in 0..3 {
        grad[j] = -n[j];
        grad[7 + j] = n[j];
    }
    let beta1 = poses[0]
        .rotation()
        .tr_mul(&(closest1 - poses[0].position()));
    let beta2 = poses[1]
        .rotation()
        .tr_mul(&(closest2 - poses[1].position()));
    let d1 = rotation_derivatives(poses[0].quaternion());
    let d2 = rotation_derivatives(poses[1].quaternion());
    let round = shapes.map(|sh| sh.solver_kind() == ShapeKind::Sphere);
    for k in 0..4 {
        if !round[0] {
            grad[3 + k] = -n.dot(&(d1[k] * beta1));
        }
        if !round[1] {
            grad[10 + k] = n.dot(&(d2[k] * beta2));
        }
    }
    grad
}

/// Sphere and capsule pairs (the closest points of their segments), a sphere with a
/// centred box or a cylinder (the point of those closest to its centre), and a capsule with a
/// centred box, a cylinder or a cone (the segment's closest points), certified; `Err(w)`
/// for pairs found overlapping: sphere and capsule pairs whose segments are no farther apart
/// than the radii summed (`w`, dividing the segments' closest points in the ratio of the
/// radii, lies in both), a sphere overlapping a solid of `sphere_solid`'s (`w` its centre or
/// the solid's closest point) and a capsule whose segment is nearer a solid than its radius (`w`
/// the solid's closest point), `w` relative to shape 1's origin.
pub(super) fn closed_form(
    pair: &Pair<'_, Shape>,
    d: &Vec3,
    tol: Real,
) -> Result<Option<Separation>, Vec3> {
    // Sphere and capsule pairs first: neither `sphere_solid` nor `segment_solid` takes a
    // sphere or capsule as the solid, and asking them cost a sphere pair ~140 instructions.
    let rounded = |p: &Posed<'_, Shape>| p.shape.rounded_segment().is_some();
    if !(rounded(&pair.one) && rounded(&pair.two)) {
        if let Some(s) = sphere_and_solid(pair, d, tol)? {
            return Ok(Some(s));
        }
        if let Some(hit) = segment_solid(pair, d) {
            return capsule_and_solid(pair, d, tol, &hit);
        }
        return Ok(None);
    }
    let seg = RoundedSegment::of;
    let (Some(one), Some(two)) = (seg(&pair.one), seg(&pair.two)) else {
        return Ok(None);
    };
    let (x1, x2) = closest_segment_points(&one, d, &two);
    let diff = x2 - x1;
    let len = diff.norm();
    let pad = one.radius + two.radius;
    if len <= pad {
        return Err(x1 + diff * (one.radius / pad));
    }
    if !(len > pad) {
        return Ok(None);
    }
    let n = diff / len;
    let a = x1 + n * one.radius;
    let b = x2 - d - n * two.radius;
    // The certificate of `gjk::certify_candidate` with the segments' support functions in
    // closed form, `h(n) = |n·u|·h + R` (axis u, half-length h, radius R): the slab gap at n
    // below, the witnesses' distance above.
    let h = |s: &RoundedSegment| n.dot(&s.axis).abs() * s.half + s.radius;
    let lower = n.dot(d) - h(&one) - h(&two);
    let upper = (d + b - a).norm();
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    Ok(
        (lower > floor && upper - lower <= tol.max(floor)).then_some(Separation {
            distance: upper,
            normal: n,
            a,
            b,
            route: Route::ClosedForm,
        }),
    )
}

/// A capsule against a centred box, a cylinder or a cone from the segment's closest points
/// (`crate::solver::segment_solid`): the segment farther from the solid than the radius, the
/// distance certified as the sphere–solid one is; nearer (beyond rounding), `Err` with the
/// solid's closest point, which lies within the radius of the segment, so in both shapes.
fn capsule_and_solid(
    pair: &Pair<'_, Shape>,
    d: &Vec3,
    tol: Real,
    hit: &SegmentSolid,
) -> Result<Option<Separation>, Vec3> {
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let (n, r) = (hit.normal, hit.radius);
    if hit.distance < r - floor {
        return Err(if hit.capsule_first { d + hit.b } else { hit.a });
    }
    if !(hit.distance > r) {
        return Ok(None);
    }
    let (a, b) = if hit.capsule_first {
        (hit.a + n * r, hit.b)
    } else {
        (hit.a, hit.b - n * r)
    };
    Ok(gjk::certify_candidate(pair, d, tol, &n, a, b))
}

/// A sphere (either side) against a centred box or a cylinder: the solid's point closest to the
/// sphere's centre, in the solid's body frame; `Ok(None)` when the pair is not one of these
/// or is within rounding of touching. Overlapping beyond rounding (`sd < 0`), `Err` with a
/// point of both (relative to shape 1's origin): the sphere's centre where it lies in the solid,
/// else the solid's closest point, within the radius of the centre.
fn sphere_and_solid(
    pair: &Pair<'_, Shape>,
    d: &Vec3,
    tol: Real,
) -> Result<Option<Separation>, Vec3> {
    let Some(ss) = sphere_solid(pair, d) else {
        return Ok(None);
    };
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    if ss.sd < -floor {
        // `sphere_solid` takes the ball from shape 2 when it is one.
        let ball = |p: &Posed<'_, Shape>| match p.shape.rounded_segment() {
            Some((0.0, radius)) => Some(radius * p.inv_scale),
            _ => None,
        };
        let (centre, on_solid, rho) = match (ball(&pair.two), ball(&pair.one)) {
            (Some(rho), _) => (*d, ss.a, rho),
            (None, Some(rho)) => (Vec3::zeros(), d + ss.b, rho),
            (None, None) => return Ok(None),
        };
        let gap = (on_solid - centre).norm();
        // The closest point of a solid the centre lies outside of is within ρ of it (sd < 0);
        // a centre inside the solid is `ρ + depth` from its pushed-out point.
        return Err(if gap < rho - floor { on_solid } else { centre });
    }
    if !(ss.sd > 0.0) {
        return Ok(None);
    }
    // A box's or cylinder's certificate with the support functions in closed form (as the
    // segments' below): the same bounds as `gjk::certify_candidate`'s support calls, without
    // them (instructions per `dcol_distance`, sphere–box 1 850 → 1 489, sphere–cylinder
    // 1 717 → 1 428).
    if let Some(lower) = ss.lower {
        let upper = (d + ss.b - ss.a).norm();
        if lower > floor && upper - lower <= tol.max(floor) {
            return Ok(Some(Separation {
                distance: upper,
                normal: ss.normal,
                a: ss.a,
                b: ss.b,
                route: Route::ClosedForm,
            }));
        }
    }
    Ok(gjk::certify_candidate(pair, d, tol, &ss.normal, ss.a, ss.b))
}

/// Calls `f` with each flat face of `shape` (body frame: outward unit normal, offset `h(n)`):
/// a polytope's facets (those of [`Shape::facets`]), a cylinder's caps, a cone's base, a padded
/// polygon's two sides (offset its radius); `false` for a shape without.
fn for_faces(shape: &Shape, mut f: impl FnMut(Vec3, Real)) -> bool {
    if let Some((normals, offsets)) = shape.facets() {
        for (n, o) in normals.iter().zip(offsets) {
            f(*n, *o);
        }
        return true;
    }
    if let Some((v, m)) = shape.revolution_section() {
        // The section's second vertex is the base's (cone) or the +x cap's (cylinder) rim.
        f(Vec3::x(), v[1].0);
        if m == 4 {
            f(-Vec3::x(), v[1].0);
        }
        return true;
    }
    if shape.solver_kind() == ShapeKind::Polygon {
        if let Some((_, radius)) = shape.flat_vertices() {
            f(Vec3::z(), radius);
            f(-Vec3::z(), radius);
            return true;
        }
    }
    false
}

/// A face contact: the flat face of either shape (`for_faces`) whose slab gap
/// `g = n·d − h₁(n) − h₂(−n)` at its outward normal is the largest, with the other shape's
/// support point there and that point's projection onto the face's plane (inside the face's
/// shape, by its gauge) as the witnesses, certified as GJK's candidates are
/// (`gjk::certify_candidate`). One support call of the other shape per face (a face's own
/// support is its offset). Tried where `super::dispatch` lists it: on the pairs with a flat
/// face that try Newton's method first, where a face contact (more than two support pieces
/// tied) stalls it and costs a GJK run after it; `None` where the optimum is not on a face
/// (the projection falls outside it, or the bracket does not close).
fn face_contact(pair: &Pair<'_, Shape>, d: &Vec3, tol: Real) -> Option<Separation> {
    // (g, n, the other shape's support point, whether the face is shape 1's)
    let mut best: Option<(Real, Vec3, Vec3, bool)> = None;
    for first in [true, false] {
        let (own, other) = if first {
            (&pair.one, &pair.two)
        } else {
            (&pair.two, &pair.one)
        };
        let s = own.inv_scale;
        // The other shape's points lie within this of its origin: `out·p ≤ reach`.
        let reach = other.shape.bounding_radius() * other.inv_scale;
        for_faces(own.shape, |f, off| {
            // n from shape 1 to shape 2: the face's outward normal on shape 1, its opposite on
            // shape 2; the other shape's support at −(outward normal) either way.
            let out = own.rot * f;
            let lin = if first { out.dot(d) } else { -out.dot(d) } - off * s;
            // The gap is at most `lin + reach`: a face that cannot give a positive gap larger
            // than the best so far needs no support call (the choice is the same).
            if !(lin + reach > best.map_or(0.0, |(gb, ..)| gb.max(0.0))) {
                return;
            }
            let p = other.support(&-out).0;
            let (n, g) = if first {
                (out, out.dot(d) - off * s + out.dot(&p))
            } else {
                (-out, -out.dot(d) + out.dot(&p) - off * s)
            };
            if best.map_or(true, |(gb, ..)| g > gb) {
                best = Some((g, n, p, first));
            }
        });
    }
    let (g, n, p, first) = best?;
    if !(g > 0.0) {
        return None;
    }
    // The other shape's point moved by g along the normal onto the face's plane.
    let (a, b) = if first {
        (d + p - n * g, p)
    } else {
        (p, p + n * g - d)
    };
    // On the face to rounding: pulled into its shape (the upper bound needs points of the
    // shapes).
    let own = if first { &pair.one } else { &pair.two };
    let gauge = own.shape_gauge(if first { &a } else { &b });
    if !(gauge <= 1.0 + FACE_SLACK) {
        return None;
    }
    let (a, b) = match (gauge > 1.0, first) {
        (false, _) => (a, b),
        (true, true) => (a / gauge, b),
        (true, false) => (a, b / gauge),
    };
    gjk::certify_candidate(pair, d, tol, &n, a, b).map(|s| Separation {
        route: Route::Gjk,
        ..s
    })
}

/// Cores certified apart by no more than their radii and the tolerance.
struct Close {
    /// The cores' GJK answer (not padded).
    separation: Separation,
    /// Where the cores' witnesses are closer than the radii (beyond rounding): a point common
    /// to both shapes (normalised, relative to shape 1's origin), dividing the witnesses in the
    /// ratio of the radii.
    common: Option<Vec3>,
}

/// GJK on the cores when a shape is a sphere or capsule, or a padded polygon against a
/// polytope, polygon, sphere or capsule (`crate::query::cores`): the cores'
/// certified distance minus the radii, the witnesses moved by the radii along the normal.
/// Only a gap certified positive (the cores' bracket above the radii) is an answer;
/// `GjkEnd::Beyond` when the cores' lower bound exceeds the cutoff plus the radii; `None`
/// when neither shape is padded or the cores do not settle it; `Err` when the cores are apart
/// by no more than the radii and the tolerance (touching or overlapping shapes).
fn cored(
    pair: &Pair<'_, Shape>,
    d: &Vec3,
    tol: Real,
    cutoff: Option<Real>,
    tet: Option<&mut [Vertex; 4]>,
) -> Result<Option<GjkEnd>, Close> {
    // A padded polygon by its plane polygon where that makes the cores polyhedral (GJK then
    // ends exactly, as for a sphere or capsule against a polytope); against a curved shape it
    // stays whole (measured on bench_posesets' first pose set, separated: cylinder–polygon
    // 2.1 -> 2.7 µs and cone–polygon 2.3 -> 2.6 µs with the plane polygon).
    let Some(cores) = Cores::with_polygons(pair)
        .filter(Cores::polyhedral)
        .or_else(|| Cores::of(pair))
    else {
        return Ok(None);
    };
    let pad = cores.pad();
    let end = gjk::distance(
        &cores.posed(pair),
        d,
        tol,
        BUDGET,
        cores.polyhedral(),
        cutoff.map(|c| c + pad),
        tet,
    );
    match end {
        GjkEnd::Separated(s) => {
            // The cores' bracket is [upper − tol, upper] (closed to tol).
            let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
            if !(s.distance - tol.max(floor) - pad > floor) {
                // The witnesses `a` (core 1, from r₁) and `d + b` (core 2) are `s.distance`
                // apart: closer than the radii, the point dividing them in the ratio of the
                // radii lies within R₁ of core 1 and within R₂ of core 2, so in both shapes.
                let common = (s.distance < pad - floor).then(|| {
                    let (x1, x2) = (s.a, d + s.b);
                    x1 + (x2 - x1) * (cores.radii[0] / pad)
                });
                return Err(Close {
                    separation: s,
                    common,
                });
            }
            let (a, b) = cores.padded(&s.normal, s.a, s.b);
            Ok(Some(GjkEnd::Separated(Separation {
                distance: s.distance - pad,
                a,
                b,
                ..s
            })))
        }
        GjkEnd::Beyond => Ok(Some(GjkEnd::Beyond)),
        // The cores overlap, so do the shapes (each core lies in its shape).
        inside @ GjkEnd::Inside { .. } => Ok(Some(inside)),
        _ => Ok(None),
    }
}
