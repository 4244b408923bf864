//! Contact manifolds: up to a few contact points with one normal, for rigid-body engines.
//!
//! Built on the signed distance. Its normal `n` (from shape 1 to shape 2) picks, on each shape,
//! the *feature* facing the other: a flat face (a polytope facet, a cylinder's cap or a cone's
//! base as a regular polygon, a padded polygon's top or bottom), a segment (the support points
//! of two pieces, e.g. a cylinder or capsule on its side) or a single point (spheres,
//! ellipsoids, rims, corners). Two faces are clipped against each other in the plane
//! orthogonal to `n` (Sutherland–Hodgman, the incident face against the reference face, the
//! face better aligned with `n`); a segment is clipped against a face (Cyrus–Beck); each clipped
//! point is lifted along `n` onto both features, so that its two surface points differ by a
//! multiple of `n`. Points separated by more than the margin are dropped and the rest reduced
//! to the requested number (the deepest first, then the ones spanning the largest area).
//!
//! Against a half-space, the other shape's feature facing the plane is not clipped: each of its
//! points within the margin is a contact (a box resting on a floor gives its four corners).

use super::contact_boxes::{Boxes, End};
use super::contact_halfspace::{box_on_halfspace, BoxOnPlane};
use super::contact_reduce::{clip_polygon, clip_segment, reduce, segments, V2};
use super::contact_sphere::SphereAnswer;
use super::context::{Options, SignedDistance};
use super::halfspace::HalfspacePair;
use super::signed::{finite, not_representable, signed_distance_after};
use crate::error::{Error, ErrorDetail};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind, SupportMap};
use crate::solver::SolveStatus;
use arrayvec::ArrayVec;

/// The most contacts a manifold holds.
pub const MAX_CONTACTS: usize = 16;

/// The most points a feature (a face polygon) holds; larger facets keep a subset.
const MAX_FACE: usize = 32;
/// Clipping output: at most one new point per reference edge.
const BUF: usize = 2 * MAX_FACE;
const _: () = assert!(BUF <= super::contact_reduce::MAX_CANDIDATES);
/// Points of the regular polygon standing for a disc (a cylinder's cap, a cone's base).
const DISC_POINTS: usize = 12;
/// A curved shape's flat face (a disc, a padded polygon's side) is used when its normal is
/// within about 25 degrees of the contact normal.
const COS_CURVED: Real = 0.9;
/// A polytope's facet is used when its normal is within about 72 degrees of the normal.
const COS_FACET: Real = 0.3;
/// Relative tolerance (of the bounding radius) for vertices on a facet.
const FACET_TOL: Real = 1e-9;
/// Relative tolerance (of the length scale) on the separation test.
const SEP_TOL: Real = 1e-9;

/// One contact point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Contact {
    /// World point midway between the two surfaces.
    pub position: Vec3,
    /// Unit normal from shape 1 to shape 2 (the manifold's normal).
    pub normal: Vec3,
    /// Penetration depth at this point: `> 0` overlapping, `< 0` separated (within the margin);
    /// the surface points are `position ± depth/2 · normal` (shape 1: `+`, shape 2: `−`).
    pub depth: Real,
}

/// A contact manifold: up to [`MAX_CONTACTS`] points sharing one normal.
#[derive(Clone, Debug)]
pub struct Manifold {
    /// Unit normal from shape 1 to shape 2: the signed distance's normal.
    pub normal: Vec3,
    /// The signed distance the manifold was built from.
    pub signed_distance: Real,
    /// The signed distance's status (`Converged` unless its bracket did not close).
    pub status: SolveStatus,
    /// Iterations of the signed distance.
    pub iterations: u32,
    // No zeroed buffer: a manifold holds only the points written (16 zeroed contacts cost 70
    // instructions a call).
    contacts: ArrayVec<Contact, MAX_CONTACTS>,
}

impl Manifold {
    /// A manifold without points (filled by `manifold`).
    pub(crate) fn empty() -> Manifold {
        Manifold {
            normal: Vec3::zeros(),
            signed_distance: Real::INFINITY,
            status: SolveStatus::Converged,
            iterations: 0,
            contacts: ArrayVec::new(),
        }
    }

    /// The contact points (empty when the signed distance exceeds the margin).
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }
    /// The number of contact points.
    pub fn len(&self) -> usize {
        self.contacts.len()
    }
    /// No contact point.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }
}

/// The contact manifold of two posed shapes: the points where their signed distance is at most
/// `margin`, at most `max_points` of them (and at most [`MAX_CONTACTS`]), with the signed
/// distance's normal. Curved contacts give one point; face-to-face and segment-to-face contacts
/// give the corners of the clipped overlap. Allocates as [`crate::signed_distance`] does (at
/// most once per thread).
///
/// ```
/// use dcol::{contact_manifold, Options, Pose, Shape};
/// let b = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
/// let p1 = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let p2 = Pose::from_position([0.0, 0.0, 0.99]).unwrap();
/// let m = contact_manifold(&b, &p1, &b, &p2, 0.0, 4, &Options::default()).unwrap();
/// assert_eq!(m.len(), 4);
/// assert!(m.contacts().iter().all(|c| (c.depth - 0.01).abs() < 1e-9));
/// ```
#[inline]
pub fn contact_manifold(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    margin: Real,
    max_points: usize,
    options: &Options,
) -> Result<Manifold, Error> {
    check_margin(margin)?;
    options.validate()?;
    let mut out = Manifold::empty();
    manifold(
        shape1, pose1, shape2, pose2, margin, max_points, options, true, &mut out,
    )?;
    Ok(out)
}

/// `InvalidOptions` unless `margin` is finite and nonnegative.
fn check_margin(margin: Real) -> Result<(), Error> {
    if margin.is_finite() && margin >= 0.0 {
        return Ok(());
    }
    Err(Error::InvalidOptions(ErrorDetail::new(
        "margin",
        margin,
        "must be finite and nonnegative",
    )))
}

/// [`contact_manifold`]; with `exact_distance` false, a manifold without points may carry a
/// lower bound above the margin as its signed distance (a separating axis decided, without the
/// distance), for callers that read only the points (the C function). Its numbers are finite:
/// an answer beyond the largest double (shapes within their size of it) is `InvalidPose`.
/// `options` must be validated (`Options::validate`; the C function's are, when read).
#[allow(clippy::too_many_arguments)]
pub(crate) fn manifold(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    margin: Real,
    max_points: usize,
    options: &Options,
    exact_distance: bool,
    out: &mut Manifold,
) -> Result<(), Error> {
    check_margin(margin)?;
    let cap = max_points.min(MAX_CONTACTS);
    // A sphere touching or overlapping another shape: the signed distance's closed form, to
    // the last bit, without its preamble (`super::contact_sphere`); one point, the witnesses'
    // midpoint, as below. Pairs apart take the signed distance (its distance query's status
    // is the C function's too).
    let mut closed_apart = false;
    match super::contact_sphere::sphere_pair(shape1, pose1, shape2, pose2) {
        Some(SphereAnswer::Touching(sd)) => {
            if sd.distance > margin || cap == 0 {
                return finish(&sd, (&[], &[]), 0, out, (pose1, pose2));
            }
            let p = midpoint(&sd.closest1, &sd.closest2);
            return finish(&sd, (&[p], &[-sd.distance]), cap, out, (pose1, pose2));
        }
        Some(SphereAnswer::Apart) => closed_apart = true,
        None => {}
    }
    // Two boxes: the closed form (`super::contact_boxes`), or the signed distance of an
    // edge-pair overlap (the separating axes' answer, which `signed_distance` would compute
    // again).
    let mut known = None;
    if let (Some(h1), Some(h2)) = (shape1.centred_box(), shape2.centred_box()) {
        let ell = shape1.bounding_radius().max(shape2.bounding_radius());
        let mut b = Boxes::new();
        let end = super::contact_boxes::boxes(
            shape1, &h1, pose1, shape2, &h2, pose2, margin, ell, &mut b,
        );
        match end {
            // Boxes apart (by more than the margin, or less) take the distance query's answer
            // in Rust's manifold, whose signed distance is that query's to the last bit; the
            // C function reads only the points.
            End::Closed if (b.sd.distance <= 0.0 && !b.pos.is_empty()) || !exact_distance => {
                return finish(&b.sd, (&b.pos, &b.depth), cap, out, (pose1, pose2));
            }
            // As `signed_distance` checks its answers.
            End::Edges(sd) if !finite(&sd) => {
                return Err(not_representable(pose1.position(), pose2.position()));
            }
            End::Edges(sd) => known = Some(sd),
            _ => {}
        }
    }
    // A strictly convex shape (a sphere, an ellipsoid) touches at one point: the witness pair.
    let strict = |s: &Shape| matches!(s.kind(), ShapeKind::Sphere | ShapeKind::Ellipsoid);
    if known.is_none() {
        if let Some(pair) = super::halfspace::split(shape1, pose1, shape2, pose2)? {
            if let Some(b) = box_on_plane(&pair, margin) {
                let mut pts = Points::new();
                for (p, d) in b.pos.iter().zip(&b.depth).take(b.count) {
                    pts.push(*p, *d);
                }
                return finish(&b.sd, pts.slices(), cap, out, (pose1, pose2));
            }
            if let Some(()) = on_halfspace_alone(&pair, strict(pair.other), margin, cap, out)? {
                return Ok(());
            }
        }
    }
    let sd = match known {
        Some(sd) => sd,
        // `options` validated by the caller.
        None => signed_distance_after(shape1, pose1, shape2, pose2, options, closed_apart)?,
    };
    if sd.distance > margin || cap == 0 {
        return finish(&sd, (&[], &[]), 0, out, (pose1, pose2));
    }
    let mut pts = Points::new();
    if strict(shape1) || strict(shape2) {
        pts.push_witness(&sd);
        return finish(&sd, pts.slices(), cap, out, (pose1, pose2));
    }
    let ell = match super::halfspace::split(shape1, pose1, shape2, pose2)? {
        Some(pair) => {
            let ell = pair.ell();
            on_halfspace(&pair, &sd, margin, ell, &mut pts);
            ell
        }
        None => {
            let ell = shape1.bounding_radius().max(shape2.bounding_radius());
            build(shape1, pose1, shape2, pose2, &sd, margin, ell, &mut pts);
            ell
        }
    };
    // The deepest point is the signed distance's witness pair: when the clipped features miss
    // it (a capsule or padded polygon tilted against a face, whose surface line is not where
    // it is deepest), it is added, so that the manifold's largest depth is always −sd.
    let deepest = pts.depth.iter().fold(Real::NEG_INFINITY, |m, d| m.max(*d));
    if !(deepest >= -sd.distance - SEP_TOL * ell) {
        pts.push_witness(&sd);
    }
    finish(&sd, pts.slices(), cap, out, (pose1, pose2))
}

/// A shape against a half-space from one support point of the shape (the half-space's closed
/// form: [`HalfspacePair::signed_distance_of_one_support`], the signed distance's value and
/// normal to the last bit) and the shape's feature facing the plane: the manifold the general
/// path gives (`Some`), without the tied support points' centroid, which the general path needs
/// only for witnesses that are not a point of the feature (then `None`: the general path
/// answers, as it does when a witness is not a finite number).
fn on_halfspace_alone(
    pair: &HalfspacePair<'_>,
    strict: bool,
    margin: Real,
    cap: usize,
    out: &mut Manifold,
) -> Result<Option<()>, Error> {
    let sd = pair.signed_distance_of_one_support()?;
    let poses = (pair.pose_h, pair.pose_b);
    let poses = if pair.hs_first {
        poses
    } else {
        (poses.1, poses.0)
    };
    if !finite(&sd) {
        return Ok(None);
    }
    let mut pts = Points::new();
    if sd.distance > margin || cap == 0 {
        return finish(&sd, pts.slices(), 0, out, poses).map(Some);
    }
    if strict {
        // One support point, the only one (a ball's or an ellipsoid's): the general path's
        // witness.
        pts.push_witness(&sd);
        return finish(&sd, pts.slices(), cap, out, poses).map(Some);
    }
    let ell = pair.ell();
    on_halfspace(pair, &sd, margin, ell, &mut pts);
    let deepest = pts.depth.iter().fold(Real::NEG_INFINITY, |m, d| m.max(*d));
    if !(deepest >= -sd.distance - SEP_TOL * ell) {
        return Ok(None);
    }
    finish(&sd, pts.slices(), cap, out, poses).map(Some)
}

/// A centred box on a half-space in closed form (`super::contact_halfspace`, the same numbers
/// as [`on_halfspace_alone`]); `None` for other shapes and where the general path answers.
fn box_on_plane(pair: &HalfspacePair<'_>, margin: Real) -> Option<BoxOnPlane> {
    let poly = box_polytope(pair.other)?;
    let half = poly.half_extents()?;
    let b = box_on_halfspace(pair, poly, &half, margin)?;
    finite(&b.sd).then_some(b)
}

/// Fills `out` with the manifold of the candidate points `(pos, depth)` for the signed distance `sd`:
/// at most `cap` of them (`reduce`); `InvalidPose` (naming the poses' largest coordinate) when
/// one of its numbers is not finite.
fn finish(
    sd: &SignedDistance,
    (pos, depth): (&[Vec3], &[Real]),
    cap: usize,
    out: &mut Manifold,
    (pose1, pose2): (&Pose, &Pose),
) -> Result<(), Error> {
    out.normal = sd.normal;
    out.signed_distance = sd.distance;
    out.status = sd.status;
    out.iterations = sd.iterations;
    out.contacts.clear();
    // Points of shapes within their size of the largest double can pass it.
    // `v · 0` is 0 for a finite `v` and NaN otherwise: one sum tests every number (summed as
    // the points are written: any order gives 0 or NaN alike).
    let zero = |v: &Vec3| v.x * 0.0 + v.y * 0.0 + v.z * 0.0;
    let mut sum = out.signed_distance * 0.0 + zero(&out.normal);
    let n = pos.len().min(depth.len());
    if cap > 0 && n <= cap.min(MAX_CONTACTS) {
        // Nothing to reduce (`reduce` would choose them all, in order).
        for (p, d) in pos.iter().zip(depth) {
            sum = sum + d * 0.0 + zero(p);
            out.contacts.push(Contact {
                position: *p,
                normal: sd.normal,
                depth: *d,
            });
        }
    } else if cap > 0 {
        let mut chosen = [0usize; MAX_CONTACTS];
        let k = reduce(pos, depth, cap, &mut chosen);
        for &i in &chosen[..k] {
            sum = sum + depth[i] * 0.0 + zero(&pos[i]);
            out.contacts.push(Contact {
                position: pos[i],
                normal: sd.normal,
                depth: depth[i],
            });
        }
    }
    let finite = sum == 0.0;
    if !finite {
        return Err(not_representable(pose1.position(), pose2.position()));
    }
    Ok(())
}

/// Candidate contacts (no zeroed buffers: a query fills only what it uses).
struct Points {
    pos: ArrayVec<Vec3, BUF>,
    depth: ArrayVec<Real, BUF>,
}

impl Points {
    fn new() -> Self {
        Points {
            pos: ArrayVec::new(),
            depth: ArrayVec::new(),
        }
    }
    fn slices(&self) -> (&[Vec3], &[Real]) {
        (&self.pos, &self.depth)
    }
    fn push(&mut self, pos: Vec3, depth: Real) {
        if !self.pos.is_full() {
            self.pos.push(pos);
            self.depth.push(depth);
        }
    }
    fn push_witness(&mut self, sd: &SignedDistance) {
        self.push(midpoint(&sd.closest1, &sd.closest2), -sd.distance);
    }
}

/// The point midway between `a` and `b`, without forming `a + b` (which overflows for points
/// near the largest double: a padded polygon and a capsule at x = −1e308 got a contact at −inf).
fn midpoint(a: &Vec3, b: &Vec3) -> Vec3 {
    a + (b - a) * 0.5
}

/// A feature in world coordinates: 1 point, a segment (2) or a convex face polygon (≥ 3, in
/// order) with its outward unit normal.
struct Feature {
    pts: ArrayVec<Vec3, MAX_FACE>,
    face: Vec3,
}

impl Feature {
    #[inline]
    fn empty() -> Self {
        Feature {
            pts: ArrayVec::new(),
            face: Vec3::zeros(),
        }
    }
    fn k(&self) -> usize {
        self.pts.len()
    }
    fn push(&mut self, p: Vec3) {
        let _ = self.pts.try_push(p);
    }
}

/// The feature of `shape` at `pose` facing the world direction `dir` (unit); `window` is how
/// far below the support value a piece's support point may lie to count.
fn feature(shape: &Shape, pose: &Pose, dir: &Vec3, window: Real, f: &mut Feature) {
    let rot = pose.rotation();
    let r = pose.position();
    let m = rot.transpose() * dir;
    let world = |b: &Vec3| r + rot * b;
    f.pts.clear();
    f.face = Vec3::zeros();
    let Some(poly) = box_polytope(shape) else {
        return feature_general(shape, pose, dir, window, f);
    };
    {
        // A centred box (six facets, no gauge climb): the general path's facet (the last best
        // aligned normal, as `Polytope::facet_index` picks it) and corner loop, without its
        // dispatch and searches; the same points to the last bit.
        let verts = poly.vertices();
        let (k, best) = poly.scan_facet(&m);
        let len = m.norm();
        if len > 0.0 && best >= COS_FACET * len {
            if let Some(corners) = poly.facet_loop(k) {
                for &c in corners.iter().take(MAX_FACE) {
                    f.push(world(&verts[c as usize]));
                }
                f.face = rot * poly.facets().0[k];
                if f.k() >= 3 {
                    return;
                }
                f.pts.clear();
            }
        }
        f.push(world(&shape.support(&m).0));
    }
}

/// [`feature`] for every shape (a box's facet found by its general search).
fn feature_general(shape: &Shape, pose: &Pose, dir: &Vec3, window: Real, f: &mut Feature) {
    let rot = pose.rotation();
    let r = pose.position();
    let m = rot.transpose() * dir;
    let world = |b: &Vec3| r + rot * b;
    f.pts.clear();
    f.face = Vec3::zeros();
    // Flat faces.
    if let Some((verts, pad)) = shape.flat_vertices() {
        let cos_min = if pad > 0.0 { COS_CURVED } else { COS_FACET };
        if let Some(nrm) = shape.flat_face(&m, cos_min) {
            // A polygon's face is all of it; a hull knows its facets' corners (taken evenly
            // when there are more than the feature holds); other polytopes' are the vertices
            // on the facet's plane.
            let planar = shape.kind() == crate::shapes::ShapeKind::Polygon;
            // A facet's corner loop is in order already (counter-clockwise seen from outside).
            let mut ordered = false;
            if let Some(corners) = shape.facet_corners(&nrm).filter(|_| !planar) {
                let step = corners.len().div_ceil(MAX_FACE).max(1);
                for &k in corners.iter().step_by(step) {
                    f.push(world(&(verts[k as usize] + nrm * pad)));
                }
                ordered = true;
            } else {
                let top = verts
                    .iter()
                    .map(|v| v.dot(&nrm))
                    .fold(Real::NEG_INFINITY, Real::max);
                let tol = FACET_TOL * shape.bounding_radius();
                for v in verts {
                    if planar || v.dot(&nrm) >= top - tol {
                        f.push(world(&(v + nrm * pad)));
                    }
                }
            }
            f.face = rot * nrm;
            if f.k() >= 3 {
                if !ordered {
                    order(f);
                }
                return;
            }
            f.pts.clear();
        }
    } else if let Some((centre, radius)) = shape.disc(&m, COS_CURVED) {
        // A regular polygon with a vertex at the rim's support point, each vertex the last
        // turned by 2π/DISC_POINTS.
        let myz = m.y.hypot(m.z);
        let (mut c, mut s) = if myz > 0.0 {
            (m.y / myz, m.z / myz)
        } else {
            (1.0, 0.0)
        };
        let (sn, cs) = (std::f64::consts::TAU / DISC_POINTS as Real).sin_cos();
        for _ in 0..DISC_POINTS {
            f.push(world(&(centre + Vec3::new(0.0, radius * c, radius * s))));
            (c, s) = (c * cs - s * sn, s * cs + c * sn);
        }
        f.face = rot * Vec3::new(centre.x.signum(), 0.0, 0.0);
        return;
    }
    if shape.flat_vertices().is_some_and(|(_, pad)| pad == 0.0) {
        // A polytope without a facet facing m: its corner.
        f.push(world(&shape.support(&m).0));
        return;
    }
    // Pieces: the support point, and the piece point farthest from it within the window.
    let (s, _) = shape.support(&m);
    let h = s.dot(&m);
    f.push(world(&s));
    let mut far: Option<(Real, Vec3)> = None;
    for id in 0..shape.piece_count() {
        let Some(e) = shape.piece(id, &m) else {
            continue;
        };
        if e.value >= h - window {
            let d = (e.grad - s).norm();
            if d > 1e-9 * shape.bounding_radius() && far.map_or(true, |(best, _)| d > best) {
                far = Some((d, e.grad));
            }
        }
    }
    if let Some((_, p)) = far {
        match ball_radius(shape) {
            // Two balls (a capsule's ends, a padded polygon's corners): the surface line
            // along them, at the direction orthogonal to their centres' segment.
            Some(rad) => {
                let mn = m.normalize();
                let (c0, c1) = (s - mn * rad, p - mn * rad);
                let e = (c1 - c0).normalize();
                let w = (mn - e * mn.dot(&e)).try_normalize(0.0).unwrap_or(mn);
                f.pts[0] = world(&(c0 + w * rad));
                f.push(world(&(c1 + w * rad)));
            }
            None => f.push(world(&p)),
        }
    }
}

/// The polytope of `shape` when it is a centred box with six facets whose corner loops it knows
/// (every box `Shape::cuboid` makes).
fn box_polytope(shape: &Shape) -> Option<&crate::shapes::Polytope> {
    let poly = shape.as_polytope()?;
    poly.half_extents()?;
    (poly.facets().0.len() == 6 && poly.facet_loop(0).is_some()).then_some(poly)
}

/// The radius of the balls a capsule or padded polygon is made of.
fn ball_radius(shape: &Shape) -> Option<Real> {
    match shape.rounded_segment() {
        Some((half, rad)) if half > 0.0 => Some(rad),
        Some(_) => None,
        None => shape
            .flat_vertices()
            .and_then(|(_, pad)| (pad > 0.0).then_some(pad)),
    }
}

/// Orders a face's points counter-clockwise about its normal.
fn order(f: &mut Feature) {
    let k = f.k();
    // The centroid, from the first point (a sum of far points can overflow).
    let p0 = f.pts[0];
    let c = p0 + f.pts[..k].iter().map(|p| p - p0).sum::<Vec3>() / k as Real;
    let (u, v) = basis(&f.face);
    let mut key = [0.0; MAX_FACE];
    for i in 0..k {
        let d = f.pts[i] - c;
        key[i] = d.dot(&v).atan2(d.dot(&u));
    }
    for i in 1..k {
        let mut j = i;
        while j > 0 && key[j - 1] > key[j] {
            key.swap(j - 1, j);
            f.pts.swap(j - 1, j);
            j -= 1;
        }
    }
}

/// An orthonormal pair `(u, v)` with `u × v = n`.
fn basis(n: &Vec3) -> (Vec3, Vec3) {
    let a = if n.x.abs() < 0.6 {
        Vec3::x()
    } else if n.y.abs() < 0.6 {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let u = (a - n * n.dot(&a)).normalize();
    (u, n.cross(&u))
}

/// A feature ready to lift plane points onto (along `n`): what the lifting needs of it, computed
/// once per feature instead of once per point (the same numbers).
enum Lifter {
    /// A single point: every plane point lifts to it.
    Point(Vec3),
    /// A segment from `p0` along `e`, whose plane coordinates are `a` and `a + d`
    /// (`dd = ‖d‖²`).
    Segment {
        p0: Vec3,
        e: Vec3,
        a: V2,
        d: V2,
        dd: Real,
    },
    /// A face through `p0` with outward normal `face`, `nf = n·face`.
    Face { p0: Vec3, face: Vec3, nf: Real },
}

impl Lifter {
    /// The lifter of `f` for plane coordinates on `(u, v)` about the origin `o`, along `n`.
    fn new(f: &Feature, o: &Vec3, (u, v): (&Vec3, &Vec3), n: &Vec3) -> Lifter {
        match f.k() {
            1 => Lifter::Point(f.pts[0]),
            2 => {
                let (p0, p1) = (f.pts[0], f.pts[1]);
                let a = V2::new((p0 - o).dot(u), (p0 - o).dot(v));
                let d = V2::new((p1 - p0).dot(u), (p1 - p0).dot(v));
                Lifter::Segment {
                    p0,
                    e: p1 - p0,
                    a,
                    d,
                    dd: d.norm_squared(),
                }
            }
            _ => Lifter::Face {
                p0: f.pts[0],
                face: f.face,
                nf: n.dot(&f.face),
            },
        }
    }

    /// Lifts the plane point `q` (coordinates on `(u, v)` about the origin `o`) along `n` onto
    /// the feature: onto a face's plane, or onto a segment's line.
    #[inline]
    fn lift(&self, q: &V2, o: &Vec3, (u, v): (&Vec3, &Vec3), n: &Vec3) -> Vec3 {
        match self {
            Lifter::Point(p) => *p,
            Lifter::Segment { p0, e, a, d, dd } => {
                let s = if *dd > 0.0 {
                    ((q - a).dot(d) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p0 + e * s
            }
            Lifter::Face { p0, face, nf } => {
                let x = o + u * q.x + v * q.y;
                let t = (p0 - x).dot(face) / nf;
                x + n * t
            }
        }
    }
}

/// Fills `pts` with the clipped, lifted points within the margin.
#[allow(clippy::too_many_arguments)]
fn build(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    sd: &SignedDistance,
    margin: Real,
    ell: Real,
    pts: &mut Points,
) {
    let n = sd.normal;
    let window = (margin - sd.distance).max(0.0) + SEP_TOL * ell;
    let mut f1 = Feature::empty();
    let mut f2 = Feature::empty();
    feature(shape1, pose1, &n, window, &mut f1);
    feature(shape2, pose2, &(-n), window, &mut f2);
    if f1.k() == 1 || f2.k() == 1 {
        return;
    }
    let (u, v) = basis(&n);
    // Plane coordinates about a witness point (world coordinates near the largest double would
    // overflow in the dot products).
    let o = sd.closest1;
    let proj = |p: &Vec3| V2::new((p - o).dot(&u), (p - o).dot(&v));
    let mut q: ArrayVec<V2, BUF> = ArrayVec::new();
    if f1.k() == 2 && f2.k() == 2 {
        segments(
            &[proj(&f1.pts[0]), proj(&f1.pts[1])],
            &[proj(&f2.pts[0]), proj(&f2.pts[1])],
            SEP_TOL * ell,
            &mut q,
        );
    } else {
        // The reference face: a face better aligned with n (a face beats a segment).
        let score = |f: &Feature, s: Real| {
            if f.k() >= 3 {
                (f.face.dot(&n) * s).abs()
            } else {
                -1.0
            }
        };
        let (reference, incident) = if score(&f1, 1.0) >= score(&f2, -1.0) {
            (&f1, &f2)
        } else {
            (&f2, &f1)
        };
        // Filled in place (a collected `ArrayVec` is moved: a copy of its whole buffer).
        let mut r2: ArrayVec<V2, MAX_FACE> = ArrayVec::new();
        for p in &reference.pts {
            r2.push(proj(p));
        }
        if incident.k() == 2 {
            let seg = [proj(&incident.pts[0]), proj(&incident.pts[1])];
            clip_segment(&r2, &seg, &mut q)
        } else {
            q.extend(incident.pts.iter().map(proj));
            clip_polygon(&r2, &mut q)
        }
    }
    let l1 = Lifter::new(&f1, &o, (&u, &v), &n);
    let l2 = Lifter::new(&f2, &o, (&u, &v), &n);
    for qi in &q {
        let a = l1.lift(qi, &o, (&u, &v), &n);
        let b = l2.lift(qi, &o, (&u, &v), &n);
        let depth = (a - b).dot(&n);
        if -depth <= margin + SEP_TOL * ell {
            pts.push(midpoint(&a, &b), depth);
        }
    }
}

/// A shape against a half-space: the other shape's feature facing the plane (a face, a
/// segment or a point), each of its points within the margin of the plane with its depth below
/// the plane; no clipping (the plane has no boundary).
fn on_halfspace(
    pair: &HalfspacePair<'_>,
    sd: &SignedDistance,
    margin: Real,
    ell: Real,
    pts: &mut Points,
) {
    let n = pair.normal;
    let window = (margin - sd.distance).max(0.0) + SEP_TOL * ell;
    let mut f = Feature::empty();
    feature(pair.other, pair.pose_b, &(-n), window, &mut f);
    let origin = pair.pose_h.position();
    for q in &f.pts[..f.k()] {
        // Below the plane `n·x = n·r + depth`, from its origin (`n·q` alone can overflow).
        let depth = pair.depth - n.dot(&(q - origin));
        if -depth <= margin + SEP_TOL * ell {
            // Midway between the point and its projection onto the plane.
            pts.push(q + n * (0.5 * depth), depth);
        }
    }
}

#[cfg(test)]
#[path = "contact_tests.rs"]
mod tests;
