//! The signed distance: `sd = max over unit n of n·(r₂ − r₁) − h₁(n) − h₂(−n)`, the Euclidean
//! distance of separated shapes and minus the penetration depth (the minimum translation
//! distance) of overlapping ones.
//!
//! Separated pairs take the distance query's GJK path (`super::separated`), so their answer is
//! the distance query's, bit for bit. Pairs whose inscribed balls overlap, and pairs GJK finds
//! overlapping, take EPA with a Newton polish and a certificate (`crate::solver::gjk::epa`). A
//! separated pair GJK could not certify goes to the distance query's fallback.

use super::context::{DistancePath, Options, SignedDistance};
use super::cores::Cores;
use super::derivatives::check_representable;
use super::dispatch::{route, Stage};
use super::distance::{distance, MAX_OFFSET_RATIO};
use super::separated::{witness_gradient, Start};
use crate::error::{Error, ErrorDetail};
use crate::math::Vec3;
use crate::math::{robust_norm, Pose, Real};
use crate::shapes::{Shape, ShapeKind};
use crate::solver::closed_form::{closest_segment_points, sphere_solid, RoundedSegment};
use crate::solver::gjk::{self as gjk, penetration, EpaEnd, GjkEnd, Penetration, Polish, Route};
use crate::solver::raycast::{Pair, Vertex};
use crate::solver::sat;
use crate::solver::segment_solid::segment_solid;
use crate::solver::SolveStatus;

/// The bracket is closed to this fraction of the options' tolerance (units of ℓ).
const MARGIN: Real = 0.1;
const TOL_FLOOR: Real = 1e-13;
/// GJK iterations on the cores of a sphere or capsule (as the distance query's).
const GJK_BUDGET: u32 = 64;
/// Support calls of K in EPA. On curved pairs the polytope must be refined round the optimum
/// until its faces there lie within the tolerance of K's boundary: 120 left 187 of 11 200
/// random overlapping pairs (1.7 %) open, 250 leaves 7, at the same median time. Beyond the
/// first 250 (on the stack) EPA goes on in a per-thread heap polytope: of 10⁶ random
/// overlapping pairs 256 needed more than 250 calls, none more than 2 110
/// (`tests/overlap_sweep.rs`, docs/failure-modes.md).
const BUDGET: u32 = 4000;

/// The signed distance of two posed shapes, the unit normal from shape 1 to shape 2 and the
/// witness points (`closest2 − closest1 = distance·normal`).
///
/// For separated shapes this is [`crate::distance`] (the same numbers). For overlapping ones
/// the distance is minus the penetration depth: moving shape 2 by `depth·normal` separates
/// them. The answer is certified by a bracket closed to a tenth of the tolerance (times the
/// larger bounding radius); when it does not close, the status says so and the fields hold the
/// best answer found (a lower bound on the signed distance). Does not allocate, except once
/// per thread: the first overlap on a thread whose certificate needs more than 250 support
/// points reserves EPA's heap polytope (about 0.9 MB), which the thread's later queries reuse.
///
/// ```
/// use dcol::{signed_distance, Options, Pose, Shape};
/// let s = Shape::sphere(1.0).unwrap();
/// let a = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let b = Pose::from_position([1.5, 0.0, 0.0]).unwrap();
/// let sd = signed_distance(&s, &a, &s, &b, &Options::default()).unwrap();
/// assert!((sd.distance + 0.5).abs() < 1e-9);
/// assert!((sd.normal.x - 1.0).abs() < 1e-9);
/// ```
pub fn signed_distance(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<SignedDistance, Error> {
    options.validate()?;
    signed_distance_validated(shape1, pose1, shape2, pose2, options)
}

/// [`signed_distance`] with `options` already validated (the contact manifold validates them
/// once for its closed forms and this).
pub(crate) fn signed_distance_validated(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<SignedDistance, Error> {
    signed_distance_after(shape1, pose1, shape2, pose2, options, false)
}

/// [`signed_distance_validated`], told whether the pair's closed form (`closed_forms`) was
/// computed already and found the shapes apart (`super::contact_sphere`): the early closed form
/// is then skipped, which would find the same and be dropped. The same answer, bit for bit.
pub(crate) fn signed_distance_after(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    closed_apart: bool,
) -> Result<SignedDistance, Error> {
    // Every answer is checked at its return: the witnesses `r + ℓa` (a half-space's: the other's
    // projection onto the plane) pass the largest double when the shapes sit within their size
    // of it. (A wrapper around the whole function cost 50 instructions a query, moving the
    // result twice.)
    let checked = |sd: SignedDistance| {
        if finite(&sd) {
            Ok(sd)
        } else {
            Err(not_representable(pose1.position(), pose2.position()))
        }
    };
    if let Some(pair) = super::halfspace::split(shape1, pose1, shape2, pose2)? {
        return pair.signed_distance().and_then(checked);
    }
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let offset = r2 - r1;
    let len = robust_norm(&offset);
    if !len.is_finite() {
        return Err(Error::InvalidPose(ErrorDetail::new(
            "position",
            Real::INFINITY,
            "the distance between the two origins overflows a double",
        )));
    }
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    if !(len / ell <= MAX_OFFSET_RATIO) {
        return Err(Error::InvalidPose(ErrorDetail::new(
            "position",
            len / ell,
            "puts the shapes more than 1e100 times their size apart, beyond what the distance \
             program can represent in double precision",
        )));
    }
    let from_distance = |d: super::context::Distance| SignedDistance {
        distance: d.distance,
        normal: d.normal,
        closest1: d.closest1,
        closest2: d.closest2,
        iterations: d.iterations,
        status: d.status,
        path: d.path,
    };
    let inscribed = len < shape1.inscribed_radius() + shape2.inscribed_radius();
    let stages = route(shape1, shape2).signed;
    // Two polytopes of few facets (boxes, small hulls; padded hulls by their hulls): the
    // separating axes decide, and answer an overlap exactly.
    if stages.has(Stage::SeparatingAxes) {
        if let Some(sd) = separating_axes(shape1, pose1, shape2, pose2, ell) {
            return checked(sd);
        }
    }
    // GJK's tetrahedron where it certified an overlap: EPA's start (polyhedral pairs), and
    // the overlap of the cores settled.
    let mut start = None;
    // A curved pair (an ellipsoid, cylinder or cone) whose slab along the offset does not
    // separate it is mostly overlapping: the distance query's Newton and GJK would only find
    // that out (about a microsecond on deep overlaps), so such a pair goes to EPA at once,
    // which hands a separated pair back to the distance query.
    let rounded = stages.has(Stage::Probe);
    let inv = 1.0 / ell;
    let pair = Pair::new([shape1, shape2], [pose1.rotation(), pose2.rotation()], inv);
    let d = offset * inv;
    let probe_overlaps = || {
        let u = offset / len;
        u.dot(&d) - u.dot(&pair.support(&u).w) <= 0.0
    };
    let probed = !inscribed && rounded && probe_overlaps();
    let tol = (options.tolerance * MARGIN).max(TOL_FLOOR);
    // A sphere or capsule pair with a closed form (two rounded segments, a sphere against a
    // centred box, cylinder, cone, ellipsoid or a polytope about its centre, a capsule against
    // a centred box, cylinder or cone whose segment stays outside it) that finds the
    // shapes touching or overlapping: its answer, which the general path reaches after the
    // distance query's try anyway (separated pairs keep the distance query's answer). A sphere
    // resting on a box no longer runs GJK to learn that it overlaps (5 600 instructions a
    // contact call in ODE, 1 900 after).
    let closed = stages.has(Stage::ClosedForm);
    let early = if !(inscribed || probed || closed_apart) && closed {
        closed_forms(&pair, &d)
            .or_else(|| {
                capsule_and_solid(&pair, &d, tol).map(|p| (p, Some(DistancePath::ClosedForm)))
            })
            .filter(|(p, _)| p.sd <= 0.0)
    } else {
        None
    };
    if !(inscribed || probed || early.is_some()) {
        if let super::separated::Settled::Apart(d, _, _) = super::separated::separated(
            shape1,
            pose1,
            shape2,
            pose2,
            options.tolerance,
            ell,
            false,
            None,
            Some(&mut start),
        ) {
            return checked(from_distance(d));
        }
    }
    let curved = stages.has(Stage::Epa);
    let polish = epa_polish(curved, shape1, shape2);
    // The path, where it is not told by the penetration's own record.
    let late = || closed.then(|| closed_forms(&pair, &d)).flatten();
    let (end, path) = match early.or_else(late) {
        Some((p, path)) => (EpaEnd::Closed(p), path),
        None => match closed.then(|| capsule_and_solid(&pair, &d, tol)).flatten() {
            Some(p) => (EpaEnd::Closed(p), Some(DistancePath::ClosedForm)),
            None => match stages
                .has(Stage::CoredEpa)
                .then(|| cored(&pair, &d, tol, start))
                .flatten()
            {
                Some((end, path)) => (end, path),
                None => {
                    let tet = match start {
                        Some(Start::Tet { cored: false, tet }) if !curved => Some(tet),
                        _ => None,
                    };
                    (
                        penetration(&pair, &d, tol, BUDGET, polish, tet.as_ref(), true),
                        None,
                    )
                }
            },
        },
    };
    let (p, status) = match end {
        EpaEnd::Closed(p) => (p, SolveStatus::Converged),
        // A K too thin for EPA (relative thickness near rounding) can stop it far from the
        // optimum: the slab through its plane may be the better lower bound.
        EpaEnd::Open(p) => {
            let s = slab(&pair, &d);
            (if s.sd > p.sd { s } else { p }, SolveStatus::MaxIterations)
        }
        EpaEnd::Separated => {
            return distance(shape1, pose1, shape2, pose2, options)
                .map(from_distance)
                .and_then(checked);
        }
        EpaEnd::Failed => {
            // A pair sent here by the probe without the distance query's try: a separated one
            // is the distance query's answer.
            if probed {
                let d = distance(shape1, pose1, shape2, pose2, options)?;
                if d.distance > 0.0 {
                    return checked(from_distance(d));
                }
            }
            // K flatter than a double resolves (relative thickness below 1e-14: shapes of
            // aspect ratio near the constructors' 1e12 limit, thin the same way): the best
            // slab of a few directions, its support points, and the status says so.
            (slab(&pair, &d), SolveStatus::NumericalFailure)
        }
    };
    // Touching: within rounding of 0.
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let sd = if p.sd.abs() <= floor { 0.0 } else { p.sd };
    // A separated pair the probe sent past the distance query (its closed forms and cores
    // answer separated pairs too): the distance query's answer, bit for bit, as for every
    // separated pair.
    if probed && sd > 0.0 {
        return distance(shape1, pose1, shape2, pose2, options)
            .map(from_distance)
            .and_then(checked);
    }
    let out = SignedDistance {
        distance: sd * ell,
        normal: p.normal,
        closest1: r1 + p.a * ell,
        closest2: r2 + p.b * ell,
        iterations: p.supports,
        status,
        path: if let Some(path) = path {
            path
        } else if p.supports == 0 {
            DistancePath::Segments
        } else if p.polished {
            DistancePath::EpaPolish
        } else {
            DistancePath::Epa
        },
    };
    checked(out)
}

/// The error of an answer a double cannot hold (shapes placed within their size of the largest
/// double, so that a witness or contact point, x* or α* would pass it): `InvalidPose` naming the
/// origins' largest coordinate.
pub(crate) fn not_representable(r1: &Vec3, r2: &Vec3) -> Error {
    let far = r1
        .iter()
        .chain(r2.iter())
        .fold(0.0 as Real, |m, v| m.max(v.abs()));
    Error::InvalidPose(ErrorDetail::new(
        "position",
        far,
        "puts the answer beyond the largest double (a point, distance or alpha* of it would \
         overflow): keep positions and offsets well inside 1e308",
    ))
}

/// Whether every number of a signed distance is finite.
pub(crate) fn finite(sd: &SignedDistance) -> bool {
    // `v · 0` is 0 for a finite `v` and NaN otherwise: one sum tests all ten numbers without
    // branches (the chained iterators it replaces cost 200 instructions a contact call).
    let zero = |v: &Vec3| v.x * 0.0 + v.y * 0.0 + v.z * 0.0;
    sd.distance * 0.0 + zero(&sd.normal) + zero(&sd.closest1) + zero(&sd.closest2) == 0.0
}

/// [`signed_distance`] and its gradient with respect to (r₁, q₁, r₂, q₂): 14 numbers, the
/// quaternion columns with respect to the four numbers given (through the normalisation), by
/// the envelope theorem at the normal and the witness points (`∂sd/∂r₂ = normal = −∂sd/∂r₁`).
/// Exact where the normal and the witness points are unique; flat against flat (a face or an
/// edge on a face) the rotation columns depend on the witness points returned. A gradient that
/// overflows (a quaternion so small that derivatives with respect to it are not representable)
/// is an error or a `NumericalFailure` with zeros.
///
/// ```
/// use dcol::{signed_distance_gradient, Options, Pose, Shape};
/// let s = Shape::sphere(1.0).unwrap();
/// let a = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let b = Pose::from_position([1.5, 0.0, 0.0]).unwrap();
/// let (sd, g) = signed_distance_gradient(&s, &a, &s, &b, &Options::default()).unwrap();
/// assert!((sd.distance + 0.5).abs() < 1e-9);
/// assert!((g[7] - 1.0).abs() < 1e-9 && (g[0] + 1.0).abs() < 1e-9);
/// ```
pub fn signed_distance_gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(SignedDistance, [Real; 14]), Error> {
    let mut sd = signed_distance(shape1, pose1, shape2, pose2, options)?;
    let g = witness_gradient(
        &sd.normal,
        &sd.closest1,
        &sd.closest2,
        [shape1, shape2],
        [pose1, pose2],
    );
    let finite = g.iter().all(|v| v.is_finite());
    check_representable(finite, pose1, pose2)?;
    if !finite {
        sd.status = SolveStatus::NumericalFailure;
        return Ok((sd, [0.0; 14]));
    }
    Ok((sd, g))
}

/// Sphere and capsule pairs whose core segments do not meet: `sd = ‖x₂ − x₁‖ − R₁ − R₂` at the
/// closest points of the segments (exact; K is the segments' difference padded by R₁ + R₂).
fn segments(pair: &Pair<'_, Shape>, d: &Vec3) -> Option<Penetration> {
    let seg = RoundedSegment::of;
    let (one, two) = (seg(&pair.one)?, seg(&pair.two)?);
    let (x1, x2) = closest_segment_points(&one, d, &two);
    let diff = x2 - x1;
    let len = diff.norm();
    // The normal's direction carries rounding ε/len.
    if !(len > 1e-6) {
        return meeting_segments(&one, &two, x1, x2, d);
    }
    let n = diff / len;
    Some(Penetration {
        sd: len - one.radius - two.radius,
        upper: len - one.radius - two.radius,
        normal: n,
        a: x1 + n * one.radius,
        b: x2 - d - n * two.radius,
        polished: false,
        supports: 0,
    })
}

/// Sphere and capsule pairs whose core segments meet, or pass within 1e-12 (of ℓ) of each other
/// (two spheres at the same centre, a sphere centred on a capsule's segment, crossing capsules):
/// the cores' difference is flat (a point, a segment or a parallelogram), so K's depth at the
/// origin is `R₁ + R₂` less the cores' distance, along any normal of that flat set; `sd = n·diff
/// − R₁ − R₂` with such an `n` is exact to the cores' distance. (The general path's EPA found no
/// start there and ran out of iterations.) `None` between 1e-12 and 1e-6, where the general path
/// answers, and for capsules within 1e-6 rad of parallel but not parallel, whose plane is not
/// known well enough.
fn meeting_segments(
    one: &RoundedSegment,
    two: &RoundedSegment,
    x1: Vec3,
    x2: Vec3,
    d: &Vec3,
) -> Option<Penetration> {
    let diff = x2 - x1;
    if !(diff.norm() <= 1e-12) {
        return None;
    }
    // A unit vector perpendicular to the unit `a`: `a` crossed with the axis it is least along.
    let across = |a: &Vec3| {
        let k = a.iamin();
        a.cross(&Vec3::ith(k, 1.0)).normalize()
    };
    let n = match (one.half > 0.0, two.half > 0.0) {
        (true, true) => {
            let m = one.axis.cross(&two.axis);
            let s = m.norm();
            if s > 1e-6 {
                m / s
            } else if s <= 1e-12 {
                across(&one.axis)
            } else {
                return None;
            }
        }
        (true, false) => across(&one.axis),
        (false, true) => across(&two.axis),
        (false, false) => Vec3::x(),
    };
    let n = if n.dot(&diff) < 0.0 { -n } else { n };
    let sd = n.dot(&diff) - one.radius - two.radius;
    Some(Penetration {
        sd,
        upper: sd + diff.norm(),
        normal: n,
        a: x1 + n * one.radius,
        b: x2 - d - n * two.radius,
        polished: false,
        supports: 0,
    })
}

/// A sphere, capsule, padded polygon or ellipsoid against another shape through the cores
/// (`super::cores`, [`Cores::rolling`]: an ellipsoid's core is the ellipsoid less a ball that
/// rolls freely inside it): when the cores are apart, `sd = ‖cores‖ − R₁ − R₂` at their
/// closest points (GJK, certified); when they overlap, the cores' penetration minus the radii
/// (EPA on the cores: a point, segment or plane polygon against a polytope has no curvature to
/// refine, and a shrunk ellipsoid's difference with the other core bends less about the
/// depth's optimum than the shapes' own, so fewer faces certify it: two ellipsoids 241 M ->
/// 26 M instructions over 2 000 mostly overlapping poses). K is the cores' difference padded
/// by `R₁ + R₂`, so both are exact.
/// A gap proven positive with a polygon's core goes to the distance query (as before the
/// polygon was cored, so that separated answers stay the distance's). `None` when no shape is padded,
/// when GJK on the cores neither certifies a gap nor finds them overlapping, or when EPA on
/// them fails (a flat difference: parallel polygons, a point or a segment in a polygon's
/// plane). With the answer, its path when GJK gave it.
fn cored(
    pair: &Pair<'_, Shape>,
    d: &Vec3,
    tol: Real,
    start: Option<Start>,
) -> Option<(EpaEnd, Option<DistancePath>)> {
    let cores = Cores::rolling(pair)?;
    let pad = cores.pad();
    let polyhedral = cores.polyhedral();
    let padded = |p: Penetration| {
        let (a, b) = cores.padded(&p.normal, p.a, p.b);
        Penetration {
            sd: p.sd - pad,
            upper: p.upper - pad,
            a,
            b,
            ..p
        }
    };
    let posed = cores.posed(pair);
    // Newton's method on the sphere of normals first where the other shape is an ellipsoid
    // (smooth pieces: a point or a segment against it). Measured (200 overlapping poses, the
    // old and new code back to back): ellipsoid–capsule with the cores apart 3.6 -> 1.2 µs; against a cylinder or a
    // cone (flat caps and rims) it fails more often than not and costs more than it saves.
    let smooth = [&pair.one, &pair.two]
        .iter()
        .any(|s| s.shape.solver_kind() == ShapeKind::Ellipsoid);
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    // The cores' EPA; polyhedral cores start from GJK's tetrahedron where there is one (on
    // curved pieces, measured, GJK's thin tetrahedron starts EPA no better than four fresh
    // support calls in the directions of a regular one).
    let polish = epa_polish(!polyhedral, pair.one.shape, pair.two.shape);
    let epa =
        |tet: Option<&[Vertex; 4]>| match penetration(&posed, d, tol, BUDGET, polish, tet, false) {
            EpaEnd::Closed(p) => Some((EpaEnd::Closed(padded(p)), None)),
            EpaEnd::Open(p) => Some((EpaEnd::Open(padded(p)), None)),
            EpaEnd::Separated | EpaEnd::Failed => None,
        };
    // GJK on these cores (those of `Cores::of`: no polygon) certified their overlap already,
    // or found them apart by less than the radii (and the tolerance).
    let mut tet = [Vertex::default(); 4];
    let end = match start.filter(|_| !cores.flat()) {
        // The distance query's cores (`Cores::of`) are these but for a shrunk ellipsoid, which
        // it takes whole: its overlap or separation is theirs only without one.
        Some(Start::Tet { cored: true, tet }) if !cores.shrunk() => {
            return epa(Some(&tet).filter(|_| polyhedral))
        }
        Some(Start::CoresApart(s)) if !cores.shrunk() => GjkEnd::Separated(s),
        _ => match smooth
            .then(|| gjk::direct::distance(&posed, d, tol))
            .flatten()
        {
            Some(s) => GjkEnd::Separated(s),
            None => gjk::distance(&posed, d, tol, GJK_BUDGET, polyhedral, None, Some(&mut tet)),
        },
    };
    match end {
        // Shapes proven apart (the bracket [upper − tol, upper] above the radii) with a
        // polygon's plane polygon: the distance query answers, as it did before polygons were
        // cored (its GJK path did not certify them, or it would have been taken before).
        // Within the tolerance of touching the cores' answer stands: its normal is theirs
        // (the distance query has none at 0).
        GjkEnd::Separated(s) if cores.flat() && s.distance - tol.max(floor) - pad > floor => {
            Some((EpaEnd::Separated, None))
        }
        // The cores apart: their distance less the radii, where the witnesses meet the
        // identity `d + b − a = distance·n` to the tolerance (Newton on the sphere certifies
        // the distance to `tol` but its normal only to about `√tol` where a core is sharply
        // curved: a shrunk ellipsoid near its most curved point against a rim, 1.6e-8 ℓ
        // measured); otherwise EPA on the shapes answers.
        GjkEnd::Separated(s) if (d + s.b - s.a - s.normal * s.distance).norm() > tol => None,
        GjkEnd::Separated(s) => {
            let p = padded(Penetration {
                sd: s.distance,
                upper: s.distance,
                normal: s.normal,
                a: s.a,
                b: s.b,
                polished: false,
                supports: 1,
            });
            let path = match s.route {
                Route::Polish => DistancePath::GjkPolish,
                _ => DistancePath::Gjk,
            };
            Some((EpaEnd::Closed(p), Some(path)))
        }
        GjkEnd::Overlap => epa(None),
        GjkEnd::Inside { .. } => epa(Some(&tet).filter(|_| polyhedral)),
        _ => None,
    }
}

/// How EPA polishes: not at all on polytopes (`curved` false), at the hand-over on curved
/// pieces, and also on a bracket that closes early where an ellipsoid takes part.
fn epa_polish(curved: bool, shape1: &Shape, shape2: &Shape) -> Polish {
    let smooth = |s: &Shape| s.solver_kind() == ShapeKind::Ellipsoid;
    match (curved, smooth(shape1) || smooth(shape2)) {
        (false, _) => Polish::Never,
        (true, false) => Polish::HandOver,
        (true, true) => Polish::Smooth,
    }
}

/// The closed forms tried first on a pair that is not known apart: two rounded segments
/// (spheres and capsules; the path told by the answer), else a sphere against a solid
/// (`DistancePath::ClosedForm`).
fn closed_forms(pair: &Pair<'_, Shape>, d: &Vec3) -> Option<(Penetration, Option<DistancePath>)> {
    match segments(pair, d) {
        Some(p) => Some((p, None)),
        None => sphere_and_solid(pair, d).map(|p| (p, Some(DistancePath::ClosedForm))),
    }
}

/// A sphere (either side) against a centred box or a cylinder, in closed form
/// (`crate::solver::closed_form::sphere_solid`).
fn sphere_and_solid(pair: &Pair<'_, Shape>, d: &Vec3) -> Option<Penetration> {
    let ss = sphere_solid(pair, d)?;
    Some(Penetration {
        sd: ss.sd,
        upper: ss.sd,
        normal: ss.normal,
        a: ss.a,
        b: ss.b,
        polished: false,
        supports: 0,
    })
}

/// A capsule against a centred box, a cylinder or a cone whose segment does not meet the solid
/// and is nearer it than the radius (or within rounding of it): `sd = dist(segment, solid) − R`
/// from the segment's closest points (`crate::solver::segment_solid`), the segment's distance
/// certified on the cores to `tol`. K is the cores' difference padded by R, so this is exact.
/// Separated pairs are left to the distance query.
fn capsule_and_solid(pair: &Pair<'_, Shape>, d: &Vec3, tol: Real) -> Option<Penetration> {
    let hit = segment_solid(pair, d)?;
    let cores = Cores::of(pair)?;
    let s = gjk::certify_candidate(&cores.posed(pair), d, tol, &hit.normal, hit.a, hit.b)?;
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let sd = s.distance - cores.pad();
    if sd > floor {
        return None;
    }
    let (a, b) = cores.padded(&s.normal, s.a, s.b);
    Some(Penetration {
        sd,
        upper: sd,
        normal: s.normal,
        a,
        b,
        polished: false,
        supports: 2,
    })
}

/// The separating-axis penetration (`crate::solver::sat`) of two overlapping polytopes of few
/// facets, or of padded hulls whose hulls overlap (the padding adds its radius to the depth and
/// moves the witnesses along the normal); `None` when the shapes are not such polytopes, are
/// separated, or the witnesses are the general path's to find.
fn separating_axes(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    ell: Real,
) -> Option<SignedDistance> {
    fn core(s: &Shape) -> Option<(&crate::shapes::Polytope, Real)> {
        match s.padded_core() {
            Some((c, r)) => Some((c.as_polytope()?, r)),
            None => Some((s.as_polytope()?, 0.0)),
        }
    }
    fn placed<'a>(poly: &'a crate::shapes::Polytope, pose: &'a Pose) -> sat::Placed<'a> {
        sat::Placed {
            poly,
            rot: pose.rotation(),
            pos: *pose.position(),
        }
    }
    let ((c1, pad1), (c2, pad2)) = (core(shape1)?, core(shape2)?);
    let o = sat::overlap(&placed(c1, pose1), &placed(c2, pose2), ell)?.ok()?;
    let n = o.normal;
    Some(SignedDistance {
        distance: -(o.depth + pad1 + pad2),
        normal: n,
        closest1: o.closest1 + n * pad1,
        closest2: o.closest2 - n * pad2,
        iterations: 0,
        status: SolveStatus::Converged,
        path: DistancePath::SeparatingAxes,
    })
}

/// The best lower bound `L(n) = n·d − h_K(n)` over the directions across K's long axis (the
/// line through its two support points along `(1, 1, 1)`: 36 angles, then a bisection about the
/// best), the axes, the offset, and their opposites, with the support points there as
/// witnesses: an answer for a K too thin for EPA (a needle or a sheet, from shapes of aspect
/// ratio near the constructors' limit), each witness on its shape's support plane (the identity
/// `d + b − a = L·n` does not hold).
fn slab(pair: &Pair<'_, Shape>, d: &Vec3) -> Penetration {
    let u = Vec3::new(1.0, 1.0, 1.0) / (3.0 as Real).sqrt();
    let (v0, v1) = (pair.support(&u), pair.support(&-u));
    let e = (v1.w - v0.w).try_normalize(0.0).unwrap_or(u);
    let o = if e.x.abs() < 0.6 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let m = (o - e * e.dot(&o)).normalize();
    let k = e.cross(&m);
    let mut supports = 2;
    let mut best: Option<(Real, Vec3, Vertex)> = None;
    let mut try_n = |n: Vec3, best: &mut Option<(Real, Vec3, Vertex)>| {
        let v = pair.support(&n);
        supports += 1;
        let lo = n.dot(&(d - v.w));
        if best.as_ref().map_or(true, |b| lo > b.0) {
            *best = Some((lo, n, v));
        }
        lo
    };
    let across = |t: Real| m * t.cos() + k * t.sin();
    let step = std::f64::consts::TAU / 36.0;
    let mut top = (Real::NEG_INFINITY, 0.0);
    for i in 0..36 {
        let t = i as Real * step;
        let lo = try_n(across(t), &mut best);
        if lo > top.0 {
            top = (lo, t);
        }
    }
    // Bisection of the angle about the best sample.
    let (mut t, mut h) = (top.1, step);
    for _ in 0..30 {
        h *= 0.5;
        let (a, b) = (
            try_n(across(t - h), &mut best),
            try_n(across(t + h), &mut best),
        );
        if a > top.0 && a >= b {
            (top.0, t) = (a, t - h);
        } else if b > top.0 {
            (top.0, t) = (b, t + h);
        }
    }
    let along = d.try_normalize(0.0).unwrap_or(Vec3::x());
    for n in [Vec3::x(), Vec3::y(), Vec3::z(), along] {
        try_n(n, &mut best);
        try_n(-n, &mut best);
    }
    let (sd, normal, v) = best.expect("directions tried");
    Penetration {
        sd,
        upper: 0.0,
        normal,
        a: v.a,
        b: v.b,
        polished: false,
        supports,
    }
}
