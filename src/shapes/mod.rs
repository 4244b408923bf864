//! The eight convex primitives (plus the box, a polytope), one file each: seven bounded ones and
//! the half-space, whose queries are closed forms (`crate::query::halfspace`).
//!
//! Every shape is built once by a validating constructor that precomputes what queries need
//! (Cholesky factors, tan β, bounding and inscribed radii) and is immutable afterwards, so it
//! can be shared between threads. A shape contributes its *scaled* conic constraints to a
//! problem through `ConicShape::rows`: in body coordinates `u = Qᵀ(x − r)`, each constraint
//! row is `s = f_u·u + f_α α + f_w·w` with `w` the shape's own slack variables, and the rows
//! form at most one second-order cone plus nonnegative-orthant rows.

mod capsule;
mod climb;
mod cone;
mod cylinder;
mod ellipsoid;
mod halfspace;
mod hull;
mod parameters;
mod polygon;
mod polytope;
mod quickhull;
mod sphere;
mod support;

pub use capsule::Capsule;
pub use cone::Cone;
pub use cylinder::Cylinder;
pub use ellipsoid::Ellipsoid;
pub use halfspace::Halfspace;
pub use hull::ConvexHull;
pub use polygon::Polygon;
pub use polytope::Polytope;
pub use sphere::Sphere;
pub(crate) use support::{turned, PieceEval, Reduced, SupportMap, ROUND_EPS};

use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// The most facets a polytope may have (a bound on memory; construction is O(m log m)).
pub const MAX_FACETS: usize = 1 << 20;

/// The most edges a padded polygon may have (construction is O(m³) in the edge count).
pub const MAX_POLYGON_EDGES: usize = 256;

/// The most points a convex hull may be given.
pub const MAX_HULL_POINTS: usize = 1 << 22;

/// The most facets a polytope may have for the shortcuts that scan every facet (a sphere deep
/// inside, a capsule lying on a facet, a facet against a cylinder or cone).
pub(crate) const SCAN_FACETS: usize = 64;

/// The largest ratio of bounding to inscribed radius a shape may have.
pub const MAX_ASPECT_RATIO: Real = 1e12;

/// One scaled constraint row in body coordinates: `s = f_u·u + f_α α + f_w·w`, lengths
/// already divided by the problem's length scale.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct BodyRow {
    pub fu: [Real; 3],
    pub fa: Real,
    pub fw: [Real; 3],
}

impl BodyRow {
    pub(crate) const fn new(fu: [Real; 3], fa: Real, fw: [Real; 3]) -> Self {
        BodyRow { fu, fa, fw }
    }
}

/// A point `(u, α, w)` of a shape's row space (body coordinates and slacks, lengths times the
/// problem's `inv_scale`, as the rows see them), at which the rows' derivatives with respect to
/// the shape's parameters are evaluated: `∂s/∂θ = ∂f_u/∂θ·u + ∂f_α/∂θ α + ∂f_w/∂θ·w`
/// (`shapes/parameters.rs`). Rows are numbered as a shape writes them: the cone's components
/// 0..4, then orthant row k as `4 + k`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RowPoint {
    pub u: Vec3,
    pub a: Real,
    pub w: Vec3,
}

/// Receives the rows a shape contributes.
pub(crate) trait RowSink {
    /// One nonnegative-orthant row `s ≥ 0`.
    fn lp(&mut self, row: BodyRow);
    /// One second-order cone `s₀ ≥ ‖s₁..‖`, dimension 3 or 4.
    fn soc(&mut self, rows: &[BodyRow]);
}

/// What every primitive provides to the conic problem builder.
pub(crate) trait ConicShape {
    /// Number of nonnegative-orthant rows.
    fn lp_count(&self) -> usize;
    /// Number of slack variables (0, 1 or 2).
    fn slack_count(&self) -> usize;
    /// Number of second-order cones (0 or 1; written before the orthant rows).
    fn soc_count(&self) -> usize {
        1
    }
    /// Writes the constraint rows with lengths multiplied by `inv_scale`.
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink);
}

/// Which primitive a [`Shape`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShapeKind {
    /// A ball of radius `R`.
    Sphere,
    /// `bᵀ P b ≤ 1`.
    Ellipsoid,
    /// `A b ≤ b` (boxes included).
    Polytope,
    /// Points within `R` of a segment of length `L` along `e_x`.
    Capsule,
    /// Radius `R`, length `L`, axis `e_x`.
    Cylinder,
    /// Height `H`, half angle `β`, axis `e_x`, origin at the centroid.
    Cone,
    /// Points within `R` of the plane polygon `C y ≤ d` in the body x-y plane.
    Polygon,
    /// The half-space `u_z ≤ depth` (outward normal `+e_z`, boundary plane `depth` above the
    /// origin): unbounded, answered in closed form against every other kind.
    Halfspace,
    /// The convex hull of points, padded by a radius `R ≥ 0`.
    ConvexHull,
}

#[derive(Clone, Debug, PartialEq)]
enum Geometry {
    Sphere(Sphere),
    Ellipsoid(Ellipsoid),
    Polytope(Polytope),
    Capsule(Capsule),
    Cylinder(Cylinder),
    Cone(Cone),
    Polygon(Polygon),
    Halfspace(Halfspace),
    Hull(ConvexHull),
}

/// A validated convex primitive, ready for queries. Immutable and `Send + Sync`.
///
/// ```
/// use dcol::shapes::{Shape, ShapeKind};
/// let s = Shape::capsule(0.5, 2.0).unwrap();
/// assert_eq!(s.kind(), ShapeKind::Capsule);
/// assert_eq!(s.bounding_radius(), 1.5);
/// assert!(Shape::sphere(-1.0).is_err());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    geometry: Geometry,
    bounding_radius: Real,
    inscribed_radius: Real,
    /// The half extents a box was built from (`Shape::cuboid`): its parameters.
    cuboid: Option<[Real; 3]>,
}

impl Shape {
    /// Checks the derived radii every query relies on: finite, not subnormal, and an aspect
    /// ratio (bounding over inscribed radius) the normalised problem can represent.
    fn wrap(
        geometry: Geometry,
        bounding_radius: Real,
        inscribed_radius: Real,
    ) -> Result<Shape, Error> {
        if !(bounding_radius.is_finite() && bounding_radius >= Real::MIN_POSITIVE) {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "size",
                bounding_radius,
                "gives a bounding radius that is not a finite normal number",
            )));
        }
        if !(inscribed_radius >= Real::MIN_POSITIVE) {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "size",
                inscribed_radius,
                "gives an inscribed radius that underflows (not a normal positive number)",
            )));
        }
        let ratio = bounding_radius / inscribed_radius;
        if !(ratio <= MAX_ASPECT_RATIO) {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "size",
                ratio,
                "gives an aspect ratio (bounding over inscribed radius) above 1e12",
            )));
        }
        Ok(Shape {
            geometry,
            bounding_radius,
            inscribed_radius,
            cuboid: None,
        })
    }

    /// A sphere of radius `radius > 0`.
    pub fn sphere(radius: Real) -> Result<Shape, Error> {
        let s = Sphere::new(radius)?;
        Shape::wrap(Geometry::Sphere(s), radius, radius)
    }

    /// An ellipsoid `bᵀ P b ≤ 1`, `P` symmetric positive definite (rows of `p`).
    pub fn ellipsoid(p: [[Real; 3]; 3]) -> Result<Shape, Error> {
        let e = Ellipsoid::new(p)?;
        let (rho, iota) = (e.bounding_radius(), e.inscribed_radius());
        Shape::wrap(Geometry::Ellipsoid(e), rho, iota)
    }

    /// A bounded polytope `A b ≤ b` with `m = a.len()` facets, every `b_i > 0`.
    pub fn polytope(a: &[[Real; 3]], b: &[Real]) -> Result<Shape, Error> {
        let p = Polytope::new(a, b)?;
        let (rho, iota) = (p.bounding_radius(), p.inscribed_radius());
        Shape::wrap(Geometry::Polytope(p), rho, iota)
    }

    /// A polytope already built (the core of a hull).
    pub(crate) fn polytope_shape(p: Polytope) -> Result<Shape, Error> {
        let (rho, iota) = (p.bounding_radius(), p.inscribed_radius());
        Shape::wrap(Geometry::Polytope(p), rho, iota)
    }

    /// The convex hull of `points` (body frame), padded by a ball of `radius ≥ 0`: the points
    /// within `radius` of the hull. Duplicate, interior and coplanar points are allowed; the
    /// points must be finite, include four affinely independent ones, and surround the origin
    /// strictly (the error says by how much to shift them otherwise).
    ///
    /// ```
    /// use dcol::{proximity, Options, Pose, Shape, ShapeKind};
    /// let corners: Vec<[f64; 3]> = (0..8)
    ///     .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { 0.5 } else { -0.5 }))
    ///     .collect();
    /// let rounded = Shape::convex_hull(&corners, 0.1).unwrap(); // a rounded unit box
    /// assert_eq!(rounded.kind(), ShapeKind::ConvexHull);
    /// let ball = Shape::sphere(0.4).unwrap();
    /// let p1 = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
    /// let p2 = Pose::from_position([2.0, 0.0, 0.0]).unwrap();
    /// let p = proximity(&rounded, &p1, &ball, &p2, &Options::default()).unwrap();
    /// assert!((p.alpha - 2.0).abs() < 1e-12); // 2 / (0.6 + 0.4)
    /// let off: Vec<[f64; 3]> = corners.iter().map(|c| [c[0] + 1.0, c[1], c[2]]).collect();
    /// assert!(Shape::convex_hull(&off, 0.0).is_err()); // the origin is on a facet
    /// ```
    pub fn convex_hull(points: &[[Real; 3]], radius: Real) -> Result<Shape, Error> {
        if points.len() > MAX_HULL_POINTS {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "n",
                points.len() as Real,
                "exceeds the maximum of 4194304 points",
            )));
        }
        let h = ConvexHull::new(points, radius)?;
        let (rho, iota) = (h.bounding_radius(), h.inscribed_radius());
        Shape::wrap(Geometry::Hull(h), rho, iota)
    }

    /// A box with half-extents `(hx, hy, hz)`: the polytope with rows `±e_i`.
    pub fn cuboid(hx: Real, hy: Real, hz: Real) -> Result<Shape, Error> {
        positive_finite("half_x", hx)?;
        positive_finite("half_y", hy)?;
        positive_finite("half_z", hz)?;
        let a = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, -1.0],
        ];
        let mut s = Shape::polytope(&a, &[hx, hy, hz, hx, hy, hz])?;
        s.cuboid = Some([hx, hy, hz]);
        Ok(s)
    }

    /// A capsule: points within `radius` of the segment `±length/2 · e_x`.
    pub fn capsule(radius: Real, length: Real) -> Result<Shape, Error> {
        let c = Capsule::new(radius, length)?;
        Shape::wrap(Geometry::Capsule(c), radius + 0.5 * length, radius)
    }

    /// A cylinder of `radius` and `length` along `e_x`, centred at the origin.
    pub fn cylinder(radius: Real, length: Real) -> Result<Shape, Error> {
        let c = Cylinder::new(radius, length)?;
        let rho = radius.hypot(0.5 * length);
        Shape::wrap(Geometry::Cylinder(c), rho, radius.min(0.5 * length))
    }

    /// A cone of `height` and `half_angle` β ∈ (0, π/2), apex at `-3H/4 e_x`, base at `+H/4 e_x`.
    pub fn cone(height: Real, half_angle: Real) -> Result<Shape, Error> {
        let c = Cone::new(height, half_angle)?;
        let (rho, iota) = (c.bounding_radius(), c.inscribed_radius());
        Shape::wrap(Geometry::Cone(c), rho, iota)
    }

    /// A padded polygon: points within `radius` of `{ (y, 0) : C y ≤ d }` (rows of `c`).
    pub fn polygon(c: &[[Real; 2]], d: &[Real], radius: Real) -> Result<Shape, Error> {
        let p = Polygon::new(c, d, radius)?;
        let (rho, iota) = (p.bounding_radius(), p.inscribed_radius());
        Shape::wrap(Geometry::Polygon(p), rho, iota)
    }

    /// The half-space `{ u : u_z ≤ depth }` in body coordinates, `depth > 0` finite: outward
    /// normal `+e_z` (body), boundary plane `depth` above the body origin (which is strictly
    /// inside, as for every shape). A floor whose top surface is `z = 0` is
    /// `Shape::halfspace(d)` at position `(0, 0, −d)` with the identity attitude, for any `d`.
    ///
    /// Scaled by `α` about its origin it is `{ u_z ≤ α·depth }`, so α* against a half-space
    /// depends on `depth` (the distance, signed distance and contacts do not). Its
    /// [`Shape::bounding_radius`] is `+∞` and its [`Shape::inscribed_radius`] is `depth`. A
    /// query between two half-spaces is an [`Error::InvalidShape`].
    ///
    /// ```
    /// use dcol::{proximity, signed_distance, Options, Pose, Shape, ShapeKind};
    /// let floor = Shape::halfspace(1.0).unwrap();
    /// assert_eq!(floor.kind(), ShapeKind::Halfspace);
    /// let under = Pose::from_position([0.0, 0.0, -1.0]).unwrap(); // top surface at z = 0
    /// let ball = Shape::sphere(0.5).unwrap();
    /// let above = Pose::from_position([0.0, 0.0, 1.5]).unwrap();
    /// let sd = signed_distance(&floor, &under, &ball, &above, &Options::default()).unwrap();
    /// assert!((sd.distance - 1.0).abs() < 1e-15);
    /// // α* = n·(r_B − r_H)/(depth + h_B(−n)) = 2.5/(1 + 0.5)
    /// let p = proximity(&floor, &under, &ball, &above, &Options::default()).unwrap();
    /// assert!((p.alpha - 2.5 / 1.5).abs() < 1e-15);
    /// assert!(Shape::halfspace(0.0).is_err());
    /// ```
    pub fn halfspace(depth: Real) -> Result<Shape, Error> {
        let h = Halfspace::new(depth)?;
        Ok(Shape {
            geometry: Geometry::Halfspace(h),
            bounding_radius: Real::INFINITY,
            inscribed_radius: depth,
            cuboid: None,
        })
    }

    /// The half-space's `depth` when this is one.
    pub(crate) fn halfspace_depth(&self) -> Option<Real> {
        match &self.geometry {
            Geometry::Halfspace(h) => Some(h.depth()),
            _ => None,
        }
    }

    /// `(half-length, radius)` when the shape is a segment along body x padded by a radius: a
    /// capsule, or a sphere (length zero). The closed forms take those pairs.
    pub(crate) fn rounded_segment(&self) -> Option<(Real, Real)> {
        match &self.geometry {
            Geometry::Sphere(s) => Some((0.0, s.radius())),
            Geometry::Capsule(c) => Some((0.5 * c.length(), c.radius())),
            _ => None,
        }
    }

    /// The vertices of a polytope (padding 0) or of a padded polygon's plane polygon (padding
    /// `R`), body frame: what the contact manifold builds flat faces from.
    pub(crate) fn flat_vertices(&self) -> Option<(&[Vec3], Real)> {
        match &self.geometry {
            Geometry::Polytope(p) => Some((p.vertices(), 0.0)),
            Geometry::Hull(h) => Some((h.corners(), h.radius())),
            Geometry::Polygon(p) => Some((p.vertices(), p.radius())),
            _ => None,
        }
    }

    /// The corners (indices into [`Shape::flat_vertices`]) of a hull's facet of outward unit
    /// normal `normal` (as [`SupportMap::flat_face`] gives it), counter-clockwise seen from
    /// outside, without the padding.
    pub(crate) fn facet_corners(&self, normal: &Vec3) -> Option<&[u32]> {
        match &self.geometry {
            Geometry::Polytope(p) => p.facet_corners(normal),
            Geometry::Hull(h) => h.poly().facet_corners(normal),
            _ => None,
        }
    }

    /// Half extents when the shape is a box centred at its origin and aligned with its axes
    /// (a polytope with the rows `±e_i` and equal opposite offsets): the sphere–box closed form.
    pub(crate) fn centred_box(&self) -> Option<Vec3> {
        self.as_polytope()?.half_extents()
    }

    /// The pieces tied with piece `id` for the support in direction `m` (values within `tol`
    /// of its, the best): the sum of their support points and their count, when the shape finds
    /// them on its vertex graph (polytopes and hulls of many vertices); `None` otherwise (scan
    /// the pieces).
    pub(crate) fn support_ties(&self, id: u32, m: &Vec3, tol: Real) -> Option<(Vec3, usize)> {
        let (poly, radius) = match &self.geometry {
            Geometry::Polytope(p) => (p, 0.0),
            Geometry::Hull(h) => (h.poly(), h.radius()),
            _ => return None,
        };
        let (sum, count) = poly.tied(id as usize, m, tol)?;
        let ball = support::Round::Ball(radius).point(m);
        Some((sum + ball * count as Real, count))
    }

    /// The polytope this shape is, when it is one (a polytope, a box, an unpadded hull).
    pub(crate) fn as_polytope(&self) -> Option<&Polytope> {
        match &self.geometry {
            Geometry::Polytope(p) => Some(p),
            Geometry::Hull(h) if h.radius() == 0.0 => Some(h.poly()),
            _ => None,
        }
    }

    /// Whether the shape is a polytope (a polytope, a box, an unpadded hull): flat facets and
    /// corners only.
    pub(crate) fn is_polytope(&self) -> bool {
        self.as_polytope().is_some()
    }

    /// A padded hull's core (the unpadded hull, as a polytope shape) and its radius.
    pub(crate) fn padded_core(&self) -> Option<(&Shape, Real)> {
        match &self.geometry {
            Geometry::Hull(h) if h.radius() > 0.0 => Some((h.core(), h.radius())),
            _ => None,
        }
    }

    /// The points and radius of a convex hull, as given.
    pub fn hull_points(&self) -> Option<(&[[Real; 3]], Real)> {
        match &self.geometry {
            Geometry::Hull(h) => Some((h.points(), h.radius())),
            _ => None,
        }
    }

    /// An ellipsoid's principal directions (columns, body frame) and semi-axes, longest first.
    pub(crate) fn ellipsoid_principal(&self) -> Option<(&crate::math::Mat3, &Vec3)> {
        match &self.geometry {
            Geometry::Ellipsoid(e) => e.principal(),
            _ => None,
        }
    }

    /// An ellipsoid's `P⁻¹` (body frame), when it is well conditioned (semi-axes within 1e4).
    pub(crate) fn ellipsoid_inverse(&self) -> Option<&crate::math::Mat3> {
        match &self.geometry {
            Geometry::Ellipsoid(e) => e.inverse(),
            _ => None,
        }
    }

    /// An ellipsoid's `U` with `P = UᵀU`, when it is well conditioned (semi-axes within 1e4).
    pub(crate) fn ellipsoid_cholesky(&self) -> Option<&crate::math::Mat3> {
        match &self.geometry {
            Geometry::Ellipsoid(e) => e.cholesky(),
            _ => None,
        }
    }

    /// A polytope's facets: outward unit normals and offsets (`n_i·u ≤ o_i`, body frame).
    ///
    /// Only for polytopes of at most [`SCAN_FACETS`] facets: the shortcuts that ask scan every
    /// facet, which costs more than the general solvers beyond that.
    pub(crate) fn facets(&self) -> Option<(&[Vec3], &[Real])> {
        let f = self.as_polytope()?.facets();
        (f.0.len() <= SCAN_FACETS).then_some(f)
    }

    /// `(radius, half-length)` of a cylinder: the sphere–cylinder distance in closed form.
    pub(crate) fn cylinder_dims(&self) -> Option<(Real, Real)> {
        match &self.geometry {
            Geometry::Cylinder(c) => Some((c.radius(), 0.5 * c.length())),
            _ => None,
        }
    }

    /// The meridian section of a cylinder or a cone (a solid of revolution about body x): its
    /// vertices `(axial, radial)`, counter-clockwise, in `[..n]` (the section is symmetric in
    /// the radial coordinate). The sphere–cylinder and sphere–cone α* in closed form.
    pub(crate) fn revolution_section(&self) -> Option<([(Real, Real); 4], usize)> {
        match &self.geometry {
            Geometry::Cylinder(c) => {
                let (r, h) = (c.radius(), 0.5 * c.length());
                Some(([(-h, -r), (h, -r), (h, r), (-h, r)], 4))
            }
            Geometry::Cone(c) => {
                let h = c.height();
                let r = h * c.half_angle().tan();
                Some((
                    [(-0.75 * h, 0.0), (0.25 * h, -r), (0.25 * h, r), (0.0, 0.0)],
                    3,
                ))
            }
            _ => None,
        }
    }

    /// The kind the solvers dispatch on: [`Shape::kind`], except that an unpadded hull is a
    /// polytope to them.
    #[inline]
    pub(crate) fn solver_kind(&self) -> ShapeKind {
        match &self.geometry {
            Geometry::Hull(h) if h.radius() == 0.0 => ShapeKind::Polytope,
            _ => self.kind(),
        }
    }

    /// Which primitive this is (a box reports [`ShapeKind::Polytope`]).
    pub fn kind(&self) -> ShapeKind {
        match &self.geometry {
            Geometry::Sphere(_) => ShapeKind::Sphere,
            Geometry::Ellipsoid(_) => ShapeKind::Ellipsoid,
            Geometry::Polytope(_) => ShapeKind::Polytope,
            Geometry::Capsule(_) => ShapeKind::Capsule,
            Geometry::Cylinder(_) => ShapeKind::Cylinder,
            Geometry::Cone(_) => ShapeKind::Cone,
            Geometry::Polygon(_) => ShapeKind::Polygon,
            Geometry::Halfspace(_) => ShapeKind::Halfspace,
            Geometry::Hull(_) => ShapeKind::ConvexHull,
        }
    }

    /// Radius of the smallest origin-centred ball containing the shape (unscaled); `+∞` for a
    /// half-space, which no ball contains (queries with one take their length scale from the
    /// other shape).
    pub fn bounding_radius(&self) -> Real {
        self.bounding_radius
    }

    /// Radius of an origin-centred ball contained in the shape (the largest one, except for
    /// the padded polygon, where it is the padding radius `R`; for a half-space, `depth`).
    pub fn inscribed_radius(&self) -> Real {
        self.inscribed_radius
    }
}

macro_rules! dispatch {
    ($self:expr, $s:ident => $e:expr) => {
        match &$self.geometry {
            Geometry::Sphere($s) => $e,
            Geometry::Ellipsoid($s) => $e,
            Geometry::Polytope($s) => $e,
            Geometry::Capsule($s) => $e,
            Geometry::Cylinder($s) => $e,
            Geometry::Cone($s) => $e,
            Geometry::Polygon($s) => $e,
            Geometry::Halfspace($s) => $e,
            Geometry::Hull($s) => $e,
        }
    };
}

impl ConicShape for Shape {
    fn lp_count(&self) -> usize {
        dispatch!(self, s => s.lp_count())
    }
    fn slack_count(&self) -> usize {
        dispatch!(self, s => s.slack_count())
    }
    fn soc_count(&self) -> usize {
        dispatch!(self, s => s.soc_count())
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        dispatch!(self, s => s.rows(inv_scale, sink))
    }
}

impl SupportMap for Shape {
    // Always inlined into the solvers' loops: left to the inliner it stopped inlining this
    // dispatch when the eighth kind came, and box–box proximity took 40 % longer.
    #[inline(always)]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        dispatch!(self, s => s.support(m))
    }
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        dispatch!(self, s => s.piece(id, m))
    }
    fn piece_point(&self, id: u32, m: &Vec3) -> Option<(Real, Vec3)> {
        dispatch!(self, s => s.piece_point(id, m))
    }
    fn piece_reduced(&self, id: u32, m: &Vec3, b: &[Vec3; 2]) -> Option<support::Reduced> {
        dispatch!(self, s => s.piece_reduced(id, m, b))
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        dispatch!(self, s => s.flat_face(m, cos_min))
    }
    fn gauge(&self, p: &Vec3) -> Real {
        dispatch!(self, s => s.gauge(p))
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        dispatch!(self, s => s.normal_at(id, p))
    }
    fn piece_count(&self) -> u32 {
        dispatch!(self, s => s.piece_count())
    }
    fn disc(&self, m: &Vec3, cos_min: Real) -> Option<(Vec3, Real)> {
        dispatch!(self, s => s.disc(m, cos_min))
    }
    fn vertex_pieces(&self) -> Option<&[Vec3]> {
        dispatch!(self, s => s.vertex_pieces())
    }
    fn ball_pieces(&self) -> Option<(&[Vec3], Real)> {
        dispatch!(self, s => s.ball_pieces())
    }
    fn support_set(&self, m: &Vec3, tie: Real, point: Real) -> Option<(usize, Vec3)> {
        dispatch!(self, s => s.support_set(m, tie, point))
    }
}

pub(crate) fn positive_finite(name: &'static str, v: Real) -> Result<(), Error> {
    if !v.is_finite() {
        return Err(Error::InvalidShape(ErrorDetail::new(
            name,
            v,
            "must be finite",
        )));
    }
    if v <= 0.0 {
        return Err(Error::InvalidShape(ErrorDetail::new(
            name,
            v,
            "must be positive",
        )));
    }
    Ok(())
}

/// Validates a halfspace system `rows · y ≤ rhs` (rows of dimension `D`): non-empty, at most
/// `max`, finite, no zero row, every right-hand side positive and finite.
pub(crate) fn check_halfspaces<const D: usize>(
    rows_name: &'static str,
    rhs_name: &'static str,
    rows: &[[Real; D]],
    rhs: &[Real],
    max: usize,
) -> Result<(), Error> {
    if rows.is_empty() {
        return Err(Error::InvalidShape(ErrorDetail::new(
            "m",
            0.0,
            "must be at least 1 (no facets given)",
        )));
    }
    if rows.len() > max {
        return Err(Error::InvalidShape(ErrorDetail::new(
            "m",
            rows.len() as Real,
            if max == MAX_POLYGON_EDGES {
                "exceeds the maximum of 256 edges for a polygon"
            } else {
                "exceeds the maximum of 1048576 facets"
            },
        )));
    }
    if rows.len() != rhs.len() {
        return Err(Error::InvalidShape(ErrorDetail::new(
            rhs_name,
            rhs.len() as Real,
            "must have one entry per row",
        )));
    }
    for (i, row) in rows.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::InvalidShape(ErrorDetail::at(
                    rows_name,
                    i * D + j,
                    *v,
                    "must be finite",
                )));
            }
        }
        let n2: Real = row.iter().map(|v| v * v).sum();
        if n2 == 0.0 || !n2.is_finite() {
            return Err(Error::InvalidShape(ErrorDetail::at(
                rows_name,
                i * D,
                n2.sqrt(),
                "row must be non-zero with a finite norm",
            )));
        }
        let v = rhs[i];
        if !v.is_finite() || v <= 0.0 {
            return Err(Error::InvalidShape(ErrorDetail::at(
                rhs_name,
                i,
                v,
                "must be positive and finite (the origin must be strictly inside)",
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
pub(crate) mod test_util {
    use super::*;

    /// Collects rows for inspection in unit tests.
    #[derive(Default)]
    pub struct Collect {
        pub lp: Vec<BodyRow>,
        pub soc: Vec<Vec<BodyRow>>,
    }
    impl RowSink for Collect {
        fn lp(&mut self, row: BodyRow) {
            self.lp.push(row);
        }
        fn soc(&mut self, rows: &[BodyRow]) {
            self.soc.push(rows.to_vec());
        }
    }

    /// Evaluates whether body point `u` (with slacks `w`) at scale `alpha` satisfies all rows.
    pub fn member<const K: usize>(
        shape: &impl ConicShape,
        u: [Real; 3],
        alpha: Real,
        w: [Real; K],
    ) -> bool {
        let mut c = Collect::default();
        shape.rows(1.0, &mut c);
        let ev = |r: &BodyRow| {
            r.fu[0] * u[0]
                + r.fu[1] * u[1]
                + r.fu[2] * u[2]
                + r.fa * alpha
                + (0..K).map(|k| r.fw[k] * w[k]).sum::<Real>()
        };
        let lp_ok = c.lp.iter().all(|r| ev(r) >= -1e-12);
        let soc_ok = c.soc.iter().all(|rows| {
            let s: Vec<Real> = rows.iter().map(ev).collect();
            s[0] + 1e-12 >= s[1..].iter().map(|v| v * v).sum::<Real>().sqrt()
        });
        lp_ok && soc_ok
    }
}
