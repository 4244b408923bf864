//! Exact distance between separated shapes by GJK on their support maps, with a certificate
//! (`docs/maths.md` §5), then a Newton polish on the features GJK identified.
//!
//! The frame is the normalised one of the ray cast (`super::raycast`): origin at shape 1's
//! origin, lengths over ℓ, `d = (r₂ − r₁)/ℓ`. GJK finds the point of
//! `C = d + K₂ ⊕ (−K₁)` (the points `y₂ − y₁`) nearest the origin; its norm is the distance.
//! Every step certifies a bracket:
//!
//! - for any unit `n`, `d* ≥ n·d − h₁(n) − h₂(−n)` (the gap of the two slabs along `n`, one
//!   support call of each shape), the *lower* bound;
//! - for any points `a ∈ K₁`, `b ∈ K₂`, `d* ≤ ‖d + b − a‖` (the current convex combinations of
//!   support points), the *upper* bound.
//!
//! An answer is returned only when the lower bound is positive (the shapes are proven
//! separated, so a gap however small is never reported as 0) and the bracket is closed to the
//! requested width. Polytope pairs end exactly within a few steps. On curved pieces GJK
//! converges only linearly, and on a tiny gap the direction of `d + b − a` (a difference of
//! O(1) numbers) carries rounding far above the gap; so once GJK has identified the pieces in
//! contact, the normal is found from their smooth optimality conditions instead (Newton),
//! along with a simplex triangle's own normal and any flat face nearby, and the bracket is
//! certified again.

pub(crate) mod direct;
mod epa;
mod newton;
pub(crate) mod padded;
mod polytope;
mod simplex;
mod slots;

pub(crate) use epa::{penetration, EpaEnd, Penetration, Polish};

use super::raycast::{Pair, Vertex};
use crate::math::{Real, Vec3};
use crate::shapes::SupportMap;
use newton::polish;
use simplex::{keep, masked_point, nearest};

/// Within this relative width (or [`HANDOVER_ABS`]) of the bracket a curved pair's GJK hands
/// over to the polish: the pieces in contact are identified.
const HANDOVER: Real = 1e-6;
const HANDOVER_ABS: Real = 1e-9;
/// The hand-over of the second round (and a thousandth of [`HANDOVER_ABS`]), after a polish
/// that failed to certify.
const HANDOVER_RESCUE: Real = 1e-10;
/// GJK stops on its own only when the bracket is this narrow relative to the distance (as well
/// as within the tolerance), so that tiny gaps come out with a few correct digits.
const REL_STRICT: Real = 1e-3;
/// A flat face within this cosine of the current normal is tried as the normal.
const FACE_COS: Real = 1.0 - 1e-3;
/// How far (relative gauge) outside its shape a point projected onto a face may lie and still
/// count as on the face (rounding); it is pulled in before use.
const SNAP_SLACK: Real = 1e-12;

/// Which route certified the answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Route {
    /// GJK's own bracket (with a simplex or face normal).
    Gjk,
    /// The Newton polish on the features GJK identified.
    Polish,
    /// A closed form (sphere and capsule pairs), certified the same way.
    ClosedForm,
}

/// A certified distance, normalised units.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Separation {
    /// `‖d + b − a‖`, the upper bound: the distance between the witness points.
    pub distance: Real,
    /// The unit normal from shape 1 to shape 2 that gave `lower`.
    pub normal: Vec3,
    /// Witness of shape 1 (relative to its origin) and of shape 2 (relative to its origin).
    pub a: Vec3,
    pub b: Vec3,
    pub route: Route,
}

/// How GJK ended.
#[derive(Clone, Copy, Debug)]
pub(crate) enum GjkEnd {
    Separated(Separation),
    /// The origin lies in (or on) the simplex, or the bracket pins the distance at 0: touching
    /// or overlapping.
    Overlap,
    /// The origin lies strictly inside a tetrahedron of support points: overlap certified,
    /// with a point common to both shapes: `a`, shape 1's witness (relative to its origin;
    /// shape 2's is `a − d`, to rounding). [`distance`] hands over the tetrahedron.
    Inside {
        a: Vec3,
    },
    /// No certificate within the budget.
    Uncertified,
    /// The lower bound exceeded the cutoff.
    Beyond,
}

/// A point of `C` with the support points it came from.
#[derive(Clone, Copy, Debug, Default)]
struct Pt {
    c: Vec3,
    v: Vertex,
}

/// The best bounds seen.
struct Cert {
    lower: Real,
    normal: Vec3,
    upper: Real,
    a: Vec3,
    b: Vec3,
    d: Vec3,
}

impl Cert {
    /// Evaluates the lower bound at the direction of `n` (any length); returns the support
    /// vertex there.
    fn try_normal<S: SupportMap>(&mut self, pair: &Pair<'_, S>, n: &Vec3) -> Option<Vertex> {
        let len = n.norm();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        let n = n / len;
        let v = pair.support(&n);
        let lo = n.dot(&self.d) - n.dot(&v.w);
        if lo > self.lower {
            self.lower = lo;
            self.normal = n;
        }
        Some(v)
    }

    /// Evaluates the upper bound from points `a ∈ K₁`, `b ∈ K₂`.
    fn try_points(&mut self, a: Vec3, b: Vec3) {
        let up = (self.d + b - a).norm();
        if up < self.upper {
            self.upper = up;
            self.a = a;
            self.b = b;
        }
    }

    /// The better bounds of the two.
    fn merge(&mut self, other: &Cert) {
        if other.lower > self.lower {
            self.lower = other.lower;
            self.normal = other.normal;
        }
        if other.upper < self.upper {
            self.upper = other.upper;
            self.a = other.a;
            self.b = other.b;
        }
    }

    fn width(&self) -> Real {
        self.upper - self.lower
    }

    /// Separation proven (the lower bound above its rounding) and the bracket closed.
    fn closed(&self, tol: Real, floor: Real) -> bool {
        self.lower > floor && self.width() <= tol
    }
}

/// GJK distance of the pair at offset `d` (normalised), closing the bracket to `tol`
/// (normalised; widened to the rounding of the bounds at large offsets) within `budget`
/// iterations; [`GjkEnd::Beyond`] as soon as the lower bound exceeds `cutoff`.
/// On [`GjkEnd::Inside`] the tetrahedron's support vertices (their `w` hold `d`
/// strictly inside: a start for EPA) are written to `tet`. (An out-parameter, not a field of
/// the variant: the 320 bytes in every `GjkEnd` cost the distance query about 5 %.)
pub(crate) fn distance<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
    budget: u32,
    polyhedral: bool,
    cutoff: Option<Real>,
    tet: Option<&mut [Vertex; 4]>,
) -> GjkEnd {
    // Rounding of `n·d − n·w` (|w| ≤ 2 in these units).
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let tol = tol.max(floor);
    let strict =
        |c: &Cert| c.lower > floor && c.width() <= tol.min(REL_STRICT * c.upper).max(0.5 * floor);
    let mut cert = Cert {
        lower: Real::NEG_INFINITY,
        normal: Vec3::zeros(),
        upper: Real::INFINITY,
        a: Vec3::zeros(),
        b: Vec3::zeros(),
        d: *d,
    };
    let start = if d.norm_squared() > 0.0 {
        *d
    } else {
        Vec3::x()
    };
    let Some(first) = cert.try_normal(pair, &start) else {
        return GjkEnd::Uncertified;
    };
    let mut simplex = [Pt::default(); 4];
    let mut w = [0.0; 4];
    simplex[0] = Pt {
        c: d - first.w,
        v: first,
    };
    w[0] = 1.0;
    let mut k = 1;
    let mut v = simplex[0].c;
    cert.try_points(first.a, first.b);
    let accept = |c: &Cert| c.closed(tol, floor);
    let fresh = || Cert {
        lower: Real::NEG_INFINITY,
        normal: Vec3::zeros(),
        upper: Real::INFINITY,
        a: Vec3::zeros(),
        b: Vec3::zeros(),
        d: *d,
    };
    // The polish's own bracket (its normal and witnesses solve the optimality conditions;
    // GJK's are only as good as the root of its width), kept apart from GJK's.
    let mut own = fresh();
    let mut used = 0;
    for (handover, handover_abs) in [
        (HANDOVER, HANDOVER_ABS),
        (HANDOVER_RESCUE, 1e-3 * HANDOVER_ABS),
    ] {
        let mut handed_over = false;
        let mut done = false;
        while used < budget {
            used += 1;
            let vv = v.norm_squared();
            if !(vv > 0.0) {
                return GjkEnd::Overlap;
            }
            let Some(vtx) = cert.try_normal(pair, &v) else {
                return GjkEnd::Uncertified;
            };
            if cutoff.is_some_and(|c| cert.lower > c + floor) {
                return GjkEnd::Beyond;
            }
            if polyhedral && strict(&cert) {
                done = true;
                break;
            }
            // A curved pair's bracket pins the distance long before it pins the witnesses
            // (an error e in the distance allows √e in the points): hand over to the polish.
            if !polyhedral
                && cert.lower > 0.0
                && (cert.width() <= handover * cert.upper || cert.width() <= handover_abs)
            {
                handed_over = true;
                break;
            }
            let c = d - vtx.w;
            // The new point adds nothing beyond v's plane (to rounding): GJK has stalled.
            if vv - v.dot(&c) <= 1e-14 * vv {
                break;
            }
            // The new point goes in slot k, past the simplex: the simplex itself changes only
            // once the step is known to make progress.
            simplex[k] = Pt { c, v: vtx };
            let Some((mask, wk)) = nearest(&simplex, k + 1) else {
                let end = inside(&simplex);
                if let (GjkEnd::Inside { .. }, Some(t)) = (end, tet) {
                    *t = simplex.map(|p| p.v);
                }
                return end;
            };
            if !(masked_point(&simplex, k + 1, mask, &wk).norm_squared() < vv) {
                // No progress (rounding): keep the previous simplex.
                break;
            }
            k = keep(&mut simplex, &mut w, k + 1, mask, &wk);
            let (nv, a, b) = combine(&simplex[..k], &w[..k]);
            v = nv;
            cert.try_points(a, b);
        }
        if done {
            break;
        }
        let upper = cert.upper;
        extra_normals(pair, &simplex[..k], &v, &mut cert);
        // Witnesses projected onto a flat face (accurate) that close the bracket: done.
        if cert.upper < upper && strict(&cert) {
            break;
        }
        let mut trial = fresh();
        polish(
            pair,
            &simplex[..k],
            &w[..k],
            cert.normal,
            cert.upper,
            (tol, floor),
            &mut trial,
        );
        if accept(&trial) {
            own = trial;
            break;
        }
        own.merge(&trial);
        // The polish failed on pieces identified at a loose bracket: refine and retry once.
        if !handed_over {
            break;
        }
    }
    let mut route = Route::Gjk;
    if accept(&own) {
        cert = own;
        route = Route::Polish;
    } else if own.lower > cert.lower || own.upper < cert.upper {
        route = Route::Polish;
        cert.merge(&own);
    }
    if accept(&cert) {
        return GjkEnd::Separated(Separation {
            distance: cert.upper,
            normal: cert.normal,
            a: cert.a,
            b: cert.b,
            route,
        });
    }
    if cert.lower <= floor && cert.upper <= tol {
        return GjkEnd::Overlap;
    }
    GjkEnd::Uncertified
}

/// The certificate of a candidate answer found elsewhere (a closed form): the lower bound at
/// `n`, the upper bound from `a ∈ K₁`, `b ∈ K₂` (relative to their origins); the answer when
/// the bracket closes to `tol` (as in [`distance`]).
pub(crate) fn certify_candidate<S: SupportMap>(
    pair: &Pair<'_, S>,
    d: &Vec3,
    tol: Real,
    n: &Vec3,
    a: Vec3,
    b: Vec3,
) -> Option<Separation> {
    let floor = 8.0 * Real::EPSILON * (d.norm() + 2.0);
    let mut cert = Cert {
        lower: Real::NEG_INFINITY,
        normal: Vec3::zeros(),
        upper: Real::INFINITY,
        a: Vec3::zeros(),
        b: Vec3::zeros(),
        d: *d,
    };
    cert.try_normal(pair, n)?;
    cert.try_points(a, b);
    cert.closed(tol.max(floor), floor).then_some(Separation {
        distance: cert.upper,
        normal: cert.normal,
        a: cert.a,
        b: cert.b,
        route: Route::ClosedForm,
    })
}

/// The tetrahedron `s` holds the origin: [`GjkEnd::Inside`] with the witnesses of the
/// origin's barycentric combination when every weight is clearly positive (the origin is not
/// on a face to rounding), else [`GjkEnd::Overlap`].
fn inside(s: &[Pt; 4]) -> GjkEnd {
    let vol = |p: &Vec3, q: &Vec3, r: &Vec3, o: &Vec3| (q - p).cross(&(r - p)).dot(&(o - p));
    let z = Vec3::zeros();
    let total = vol(&s[0].c, &s[1].c, &s[2].c, &s[3].c);
    let lam = [
        vol(&z, &s[1].c, &s[2].c, &s[3].c) / total,
        vol(&s[0].c, &z, &s[2].c, &s[3].c) / total,
        vol(&s[0].c, &s[1].c, &z, &s[3].c) / total,
        vol(&s[0].c, &s[1].c, &s[2].c, &z) / total,
    ];
    if !lam.iter().all(|l| *l > 1e-9) {
        return GjkEnd::Overlap;
    }
    let sum: Real = lam.iter().sum();
    let a = s
        .iter()
        .zip(lam)
        .fold(Vec3::zeros(), |acc, (p, l)| acc + p.v.a * (l / sum));
    GjkEnd::Inside { a }
}

/// `Σ wᵢ cᵢ` and the witnesses `Σ wᵢ aᵢ`, `Σ wᵢ bᵢ`.
fn combine(pts: &[Pt], w: &[Real]) -> (Vec3, Vec3, Vec3) {
    let (mut v, mut a, mut b) = (Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
    for (p, wi) in pts.iter().zip(w) {
        v += p.c * *wi;
        a += p.v.a * *wi;
        b += p.v.b * *wi;
    }
    (v, a, b)
}

/// Candidate normals beyond GJK's own: a triangle simplex's plane normal (accurate where the
/// closest point is tiny and its direction mostly rounding) and flat faces of either shape
/// near the best normal so far.
fn extra_normals<S: SupportMap>(pair: &Pair<'_, S>, pts: &[Pt], v: &Vec3, cert: &mut Cert) {
    if pts.len() == 3 {
        let n = (pts[1].c - pts[0].c).cross(&(pts[2].c - pts[0].c));
        let s = n.dot(v);
        let s = if s != 0.0 { s } else { n.dot(&cert.normal) };
        if s != 0.0 {
            cert.try_normal(pair, &(n * s.signum()));
        }
    }
    let best = cert.normal;
    for shape in 0..2 {
        let (posed, sign) = pair.side(shape);
        let m = posed.rot.tr_mul(&best) * sign;
        let Some(f) = posed.shape.flat_face(&m, FACE_COS) else {
            continue;
        };
        let n = posed.rot * f * sign;
        let Some(v) = cert.try_normal(pair, &n) else {
            continue;
        };
        // Witnesses on the face: a point of the other shape (its support point, or GJK's
        // best witness) projected onto the face's plane, where it lies inside the face.
        let n = n / n.norm();
        let others = if shape == 0 {
            [v.b, cert.b]
        } else {
            [v.a, cert.a]
        };
        for q in others {
            let (a, b) = if shape == 0 {
                // n·a = h₁(n) = n·v.a.
                let mu = n.dot(&(cert.d + q)) - n.dot(&v.a);
                (cert.d + q - n * mu, q)
            } else {
                // n·b = −h₂(−n) = n·v.b.
                let mu = n.dot(&v.b) - n.dot(&q) + n.dot(&cert.d);
                (q, q - cert.d + n * mu)
            };
            let own = if shape == 0 { a } else { b };
            let g = posed.shape_gauge(&own);
            if !(g <= 1.0 + SNAP_SLACK) {
                continue;
            }
            let (a, b) = match (g > 1.0, shape) {
                (false, _) => (a, b),
                (true, 0) => (a / g, b),
                (true, _) => (a, b / g),
            };
            cert.try_points(a, b);
        }
    }
}
