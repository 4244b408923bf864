//! Shapes with their padding taken off, for GJK: a sphere is its centre and a capsule its
//! segment, padded by their radius; every other shape is itself. For the signed distance
//! ([`Cores::with_polygons`]) a padded polygon is its plane polygon, padded by its radius, too.
//!
//! The distance of two padded shapes is the distance of their cores minus the two radii
//! (where that is positive), with witness points moved by the radii along the normal: what
//! Coal and FCL do for spheres and capsules. GJK then meets no curvature from the padding: a
//! sphere or capsule against a polytope ends exactly, in a few iterations, as two polytopes do.

use crate::math::{robust_norm, Real, Vec3};
use crate::shapes::{turned, PieceEval, Reduced, Shape, ShapeKind, SupportMap};
use crate::solver::raycast::Pair;

/// A shape for GJK: whole, or the core of a padded one.
#[derive(Clone, Copy)]
pub(crate) enum Core<'a> {
    /// Any shape, as it is.
    Whole(&'a Shape),
    /// The segment `[−h, h]·e_x` (a point when `h = 0`) of a capsule or sphere.
    Segment(Real),
    /// The plane polygon of a padded polygon (its vertices, body frame, `z = 0`), with the
    /// shape for its gauge.
    Flat(&'a Shape, &'a [Vec3]),
    /// An ellipsoid shrunk by `r`, no more than its least radius of curvature: the inner
    /// parallel body `E ⊖ B_r`, whose support point is the ellipsoid's less `r` along the unit
    /// direction, so that `E = (E ⊖ B_r) ⊕ B_r` exactly (a ball of radius `r` rolls freely
    /// inside `E`; Blaschke's rolling theorem).
    Shrunk(&'a Shape, Real),
}

impl<'a> Core<'a> {
    /// The core of `shape` and the radius taken off (0 for a shape used whole).
    pub(crate) fn of(shape: &'a Shape) -> (Core<'a>, Real) {
        if let Some((core, radius)) = shape.padded_core() {
            return (Core::Whole(core), radius);
        }
        match shape.rounded_segment() {
            Some((half, radius)) => (Core::Segment(half), radius),
            None => (Core::Whole(shape), 0.0),
        }
    }

    /// [`Core::of`], and a padded polygon's plane polygon with its radius.
    pub(crate) fn with_polygon(shape: &'a Shape) -> (Core<'a>, Real) {
        if shape.solver_kind() == ShapeKind::Polygon {
            if let Some((vertices, radius)) = shape.flat_vertices() {
                return (Core::Flat(shape, vertices), radius);
            }
        }
        Core::of(shape)
    }

    /// [`Core::with_polygon`], and an ellipsoid shrunk by [`ROLLING`] of its least radius of
    /// curvature `c²/a` (semi-axes `a ≥ b ≥ c`) with that radius.
    pub(crate) fn rolling(shape: &'a Shape) -> (Core<'a>, Real) {
        if let Some((_, semi)) = shape.ellipsoid_principal() {
            let r = ROLLING * semi.z * (semi.z / semi.x);
            if r > 0.0 && r.is_finite() {
                return (Core::Shrunk(shape, r), r);
            }
        }
        Core::with_polygon(shape)
    }

    /// Whether GJK on this core ends exactly (no curvature): a polytope, polygon, segment or
    /// point.
    pub(crate) fn polyhedral(&self) -> bool {
        match self {
            Core::Whole(s) => s.is_polytope(),
            Core::Segment(_) | Core::Flat(..) => true,
            Core::Shrunk(..) => false,
        }
    }
}

/// The cores of a posed pair and the radii taken off (normalised units), when at least one
/// shape is padded.
pub(crate) struct Cores<'a> {
    cores: [Core<'a>; 2],
    /// The radii of shape 1 and shape 2 (0 for a shape used whole).
    pub radii: [Real; 2],
}

impl<'a> Cores<'a> {
    /// The cores of `pair`'s shapes; `None` when neither is a sphere or capsule.
    pub(crate) fn of(pair: &Pair<'a, Shape>) -> Option<Self> {
        Self::from(pair, Core::of)
    }

    /// The cores of `pair`'s shapes with padded polygons as their plane polygons
    /// ([`Core::with_polygon`]); `None` when no shape is padded. Two polygons in parallel
    /// planes, or a polygon against a point or a segment parallel to its plane, have a flat
    /// difference of cores: EPA on it finds no tetrahedron, and the caller uses the shapes.
    pub(crate) fn with_polygons(pair: &Pair<'a, Shape>) -> Option<Self> {
        Self::from(pair, Core::with_polygon)
    }

    /// The cores of [`Cores::with_polygons`] with ellipsoids shrunk too ([`Core::rolling`]);
    /// `None` when no shape is padded or an ellipsoid.
    pub(crate) fn rolling(pair: &Pair<'a, Shape>) -> Option<Self> {
        Self::from(pair, Core::rolling)
    }

    fn from(pair: &Pair<'a, Shape>, core: fn(&'a Shape) -> (Core<'a>, Real)) -> Option<Self> {
        let (c1, p1) = core(pair.one.shape);
        let (c2, p2) = core(pair.two.shape);
        let inv = pair.one.inv_scale;
        (p1 + p2 > 0.0).then_some(Cores {
            cores: [c1, c2],
            radii: [p1 * inv, p2 * inv],
        })
    }

    /// The cores posed as `pair`'s shapes are.
    pub(crate) fn posed<'b>(&'b self, pair: &Pair<'b, Shape>) -> Pair<'b, Core<'a>> {
        Pair::new(
            [&self.cores[0], &self.cores[1]],
            [pair.one.rot, pair.two.rot],
            pair.one.inv_scale,
        )
    }

    /// Whether an ellipsoid is taken shrunk ([`Core::rolling`]).
    pub(crate) fn shrunk(&self) -> bool {
        self.cores.iter().any(|c| matches!(c, Core::Shrunk(..)))
    }

    /// Whether a padded polygon is taken as its plane polygon.
    pub(crate) fn flat(&self) -> bool {
        self.cores.iter().any(|c| matches!(c, Core::Flat(..)))
    }

    /// Whether GJK and EPA on the cores end exactly.
    pub(crate) fn polyhedral(&self) -> bool {
        self.cores.iter().all(Core::polyhedral)
    }

    /// The sum of the radii.
    pub(crate) fn pad(&self) -> Real {
        self.radii[0] + self.radii[1]
    }

    /// The shapes' witnesses from the cores' (relative to each origin) at the unit normal `n`
    /// from shape 1 to shape 2: moved by the radii along it.
    pub(crate) fn padded(&self, n: &Vec3, a: Vec3, b: Vec3) -> (Vec3, Vec3) {
        (a + n * self.radii[0], b - n * self.radii[1])
    }
}

/// The fraction of an ellipsoid's least radius of curvature taken off by [`Core::rolling`]:
/// below 1, so that the core stays strictly convex (its support function's Hessian on the
/// tangent plane, the ellipsoid's less `r`, positive definite), which the polish's Newton needs.
pub(crate) const ROLLING: Real = 0.9;

/// The end `id` (0: +h, 1: −h) of a segment.
fn end(h: Real, id: u32) -> Vec3 {
    Vec3::new(if id == 0 { h } else { -h }, 0.0, 0.0)
}

impl SupportMap for Core<'_> {
    /// A segment's (or point's) support in world axes without turning the direction and the
    /// point: `±h` times the world axis (`rot · (±h e_x)`, exactly).
    #[inline(always)]
    fn support_world(&self, rot: &crate::math::Mat3, n: &Vec3) -> (Vec3, u32) {
        match self {
            Core::Segment(h) if *h == 0.0 => (Vec3::zeros(), 0),
            Core::Segment(h) => {
                let u = rot.column(0);
                let id = u32::from(u.dot(n) < 0.0);
                let s = if id == 0 { *h } else { -*h };
                (u * s, id)
            }
            _ => turned(self, rot, n),
        }
    }
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        match self {
            Core::Whole(s) => s.support(m),
            Core::Segment(h) => {
                // A point (a sphere's core) is one piece.
                let id = u32::from(m.x < 0.0 && *h > 0.0);
                (end(*h, id), id)
            }
            Core::Flat(_, v) => {
                let (mut best, mut h) = (0, Real::NEG_INFINITY);
                for (k, p) in v.iter().enumerate() {
                    let hk = p.dot(m);
                    if hk > h {
                        (best, h) = (k, hk);
                    }
                }
                (v[best], best as u32)
            }
            // On the unit direction (a direction of length 1e-160 would lose the ellipsoid's
            // support point to underflow while `r m̂` kept its size).
            Core::Shrunk(s, r) => {
                let len = robust_norm(m);
                if len > 0.0 && len.is_finite() {
                    let u = m / len;
                    let (x, id) = s.support(&u);
                    (x - u * *r, id)
                } else {
                    s.support(m)
                }
            }
        }
    }
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        match self {
            Core::Whole(s) => s.piece(id, m),
            Core::Segment(h) => {
                let a = end(*h, id);
                (id < self.piece_count()).then(|| PieceEval {
                    value: a.dot(m),
                    grad: a,
                    hess: crate::math::Mat3::zeros(),
                })
            }
            Core::Flat(_, v) => v.get(id as usize).map(|a| PieceEval {
                value: a.dot(m),
                grad: *a,
                hess: crate::math::Mat3::zeros(),
            }),
            // `h(m) − r‖m‖`: its gradient less `r m̂`, its Hessian less `r (I − m̂m̂ᵀ)/‖m‖`.
            Core::Shrunk(s, r) => {
                let e = s.piece(id, m)?;
                let len = robust_norm(m);
                if !(len > 0.0 && len.is_finite()) {
                    return None;
                }
                let u = m / len;
                let proj = crate::math::Mat3::identity() - u * u.transpose();
                Some(PieceEval {
                    value: e.value - r * len,
                    grad: e.grad - u * *r,
                    hess: e.hess - proj * (*r / len),
                })
            }
        }
    }
    /// A whole shape's own (its rims' and rounds' reduced Hessians in closed form); the other
    /// cores' from [`SupportMap::piece`].
    #[inline]
    fn piece_reduced(&self, id: u32, m: &Vec3, b: &[Vec3; 2]) -> Option<Reduced> {
        match self {
            Core::Whole(s) => s.piece_reduced(id, m, b),
            _ => self.piece(id, m).map(|e| e.reduced(b)),
        }
    }
    #[inline]
    fn piece_point(&self, id: u32, m: &Vec3) -> Option<(Real, Vec3)> {
        match self {
            Core::Whole(s) => s.piece_point(id, m),
            _ => self.piece(id, m).map(|e| (e.value, e.grad)),
        }
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        match self {
            Core::Whole(s) => s.flat_face(m, cos_min),
            Core::Segment(_) | Core::Flat(..) | Core::Shrunk(..) => None,
        }
    }
    /// A segment or plane polygon has no interior: the gauge of a point on it is `|x|/h`, of any other point
    /// infinite (no scaling of the segment reaches it).
    fn gauge(&self, p: &Vec3) -> Real {
        match self {
            Core::Whole(s) => s.gauge(p),
            Core::Segment(h) => {
                if p.y == 0.0 && p.z == 0.0 && *h > 0.0 {
                    p.x.abs() / h
                } else if *p == Vec3::zeros() {
                    0.0
                } else {
                    Real::INFINITY
                }
            }
            // In the plane, the padded polygon's gauge is the plane polygon's.
            Core::Flat(s, _) => {
                if p.z == 0.0 {
                    s.gauge(p)
                } else {
                    Real::INFINITY
                }
            }
            // Not in closed form; the solvers ask a core's gauge only of a core with a flat
            // face (to pull a point on it inside), which a shrunk ellipsoid has not. Infinite
            // (outside) but at the origin: a test `gauge ≤ 1` never accepts a point wrongly.
            Core::Shrunk(..) => {
                if *p == Vec3::zeros() {
                    0.0
                } else {
                    Real::INFINITY
                }
            }
        }
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        match self {
            Core::Whole(s) => s.normal_at(id, p),
            Core::Segment(_) | Core::Flat(..) | Core::Shrunk(..) => None,
        }
    }
    fn piece_count(&self) -> u32 {
        match self {
            Core::Whole(s) => s.piece_count(),
            Core::Segment(h) => {
                if *h > 0.0 {
                    2
                } else {
                    1
                }
            }
            Core::Flat(_, v) => v.len() as u32,
            Core::Shrunk(s, _) => s.piece_count(),
        }
    }
    fn disc(&self, m: &Vec3, cos_min: Real) -> Option<(Vec3, Real)> {
        match self {
            Core::Whole(s) => s.disc(m, cos_min),
            Core::Segment(_) | Core::Flat(..) | Core::Shrunk(..) => None,
        }
    }
}
