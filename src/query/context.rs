//! What every query shares, one floor below the queries: the options, the proximity and
//! distance results, the normalisation between world and solver coordinates ([`Frame`]), what
//! a query asks for ([`Want`]) and gets ([`Full`]), and the inputs of one solve ([`Context`]).

use super::assemble::Placement;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;
use crate::solver::{DerivativeKind, Settings, SolveStatus, Solver};

/// Query options: the solver's stopping tolerance and iteration limit.
pub type Options = Settings;

/// The result of a proximity query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Proximity {
    /// α*: > 1 separated, < 1 interpenetrating, 0 only when the origins coincide (or, against
    /// a half-space, when the other shape's origin lies in it).
    pub alpha: Real,
    /// x*, an optimal intersection point of the scaled shapes (world).
    pub point: Vec3,
    /// `p₁ = r₁ + (x* − r₁)/α*`, on the boundary of shape 1 (world). When α* = 0 this is `r₁`.
    pub contact1: Vec3,
    /// `p₂ = r₂ + (x* − r₂)/α*`, on the boundary of shape 2 (world). When α* = 0 this is `r₂`.
    pub contact2: Vec3,
    /// Interior-point iterations used (0 when another solver answered: see `solver`).
    pub iterations: u32,
    /// How the solve ended; anything but `Converged` means the fields hold the last iterate.
    pub status: SolveStatus,
    /// Which solver answered.
    pub solver: Solver,
    /// What kind of derivatives the query returned with it (`None` for a plain proximity
    /// query).
    pub derivatives: DerivativeKind,
}

impl Proximity {
    /// Every number zero (room to be written over).
    pub(crate) const ZERO: Proximity = Proximity {
        alpha: 0.0,
        point: Vec3::new(0.0, 0.0, 0.0),
        contact1: Vec3::new(0.0, 0.0, 0.0),
        contact2: Vec3::new(0.0, 0.0, 0.0),
        iterations: 0,
        status: SolveStatus::Converged,
        solver: Solver::InteriorPoint,
        derivatives: DerivativeKind::None,
    };

    /// Whether α*, x* and the contact points are all finite (a double holds the answer).
    pub(crate) fn is_representable(&self) -> bool {
        let points = self.point.iter().chain(self.contact1.iter());
        let points = points.chain(self.contact2.iter());
        self.alpha.is_finite() && points.into_iter().all(|v| v.is_finite())
    }
}

/// The result of a distance query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distance {
    /// Exact distance of the unscaled shapes; 0 when they touch or overlap.
    pub distance: Real,
    /// Witness point on shape 1 (world).
    pub closest1: Vec3,
    /// Witness point on shape 2 (world).
    pub closest2: Vec3,
    /// Unit normal from shape 1 to shape 2 (zero when the distance is 0).
    pub normal: Vec3,
    /// Interior-point iterations used.
    pub iterations: u32,
    /// How the solve ended; anything but `Converged` means the fields hold the last iterate.
    pub status: SolveStatus,
    /// Which solver answered.
    pub path: DistancePath,
}

/// Which solver answered a distance query.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum DistancePath {
    /// The interior-point distance program (touching, overlapping or uncertified pairs, or
    /// [`crate::Method::InteriorPoint`]).
    #[default]
    InteriorPoint,
    /// GJK on the support maps closed its certified bracket on its own, or an overlap was
    /// certified (the origin strictly inside a tetrahedron of support points, or two spheres'
    /// or capsules' segments no farther apart than their radii), with a common point returned
    /// as both witnesses.
    Gjk,
    /// Newton's method on the contact pieces closed the bracket: after GJK identified them, or
    /// from the offset's direction on its own (an ellipsoid, or a cone with a sphere, cone or
    /// cylinder).
    GjkPolish,
    /// The closest points of two segments (sphere and capsule pairs), certified as GJK's; and
    /// every query with a half-space (one support call of the other shape, exact).
    ClosedForm,
    /// Signed distance of an overlapping pair: EPA's polytope closed the bracket on its own.
    Epa,
    /// Signed distance of an overlapping pair: the Newton polish gave the normal, EPA's
    /// polytope the certificate.
    EpaPolish,
    /// Signed distance of an overlapping sphere or capsule pair: the closest points of their
    /// segments.
    Segments,
    /// Signed distance of two overlapping polytopes of few facets (boxes, small hulls; padded
    /// hulls whose hulls overlap): the separating-axis theorem, exact over the finite set of
    /// candidate normals (`crate::solver::sat`).
    SeparatingAxes,
}

/// The result of a signed-distance query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// The signed distance: the Euclidean distance when separated, minus the penetration
    /// depth (the minimum translation distance) when overlapping, 0 when touching.
    pub distance: Real,
    /// Unit normal from shape 1 to shape 2: moving shape 2 by `−distance·normal` (the depth
    /// along the normal, when overlapping) makes the shapes touch.
    pub normal: Vec3,
    /// Witness point on shape 1 (world): its support point at `normal`.
    pub closest1: Vec3,
    /// Witness point on shape 2 (world): its support point at `−normal`;
    /// `closest2 − closest1 = distance·normal`.
    pub closest2: Vec3,
    /// Iterations of the solver that answered: EPA's support calls for overlapping pairs,
    /// the interior-point iterations of a distance fallback, 0 for GJK.
    pub iterations: u32,
    /// `Converged` when the certified bracket closed; otherwise the best answer found.
    pub status: SolveStatus,
    /// Which solver answered.
    pub path: DistancePath,
}

/// The normalisation between world and solver coordinates.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    /// Length scale ℓ (world units).
    pub ell: Real,
    /// ‖r₂ − r₁‖ (world units).
    pub dist: Real,
    /// Normalised offset length κ.
    pub kappa: Real,
    /// Normalised offset Δ' = κ (r₂ − r₁)/‖r₂ − r₁‖.
    pub delta: Vec3,
}

impl Frame {
    /// α = α' · dist/(κ ℓ).
    pub fn alpha_factor(&self) -> Real {
        self.dist / (self.kappa * self.ell)
    }
    /// x − r₁ = ξ' · dist/κ.
    pub fn point_factor(&self) -> Real {
        self.dist / self.kappa
    }
}

/// Which outputs a query needs (each includes the ones before it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Want {
    Proximity,
    Gradient,
    Jacobian,
}

/// Everything a proximity query can produce; fields beyond what was asked for are zero.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Full {
    pub prox: Proximity,
    pub gradient: [Real; 14],
    pub jacobian: [[Real; 14]; 4],
    /// With a threshold: whether α* was proven below (true) or above (false) it early.
    pub decided: Option<bool>,
}

/// Where a shape-gradient query writes `∂(α*, d*, sd)/∂θᵢ` for each shape's parameters
/// (`None`: not wanted; otherwise at least `parameter_count` entries).
pub(crate) struct ShapeSink<'s> {
    pub d: [Option<&'s mut [Real]>; 2],
    /// Whether the buffers were written (a query that fails writes nothing; one that ends
    /// without derivatives leaves them for the caller to zero).
    pub written: bool,
    /// False when a derivative came out not finite (its buffer then holds zeros).
    pub finite: bool,
}

impl<'s> ShapeSink<'s> {
    /// The buffers, not written yet.
    pub fn new(d: [Option<&'s mut [Real]>; 2]) -> Self {
        ShapeSink {
            d,
            written: false,
            finite: true,
        }
    }

    /// Multiplies the first `count` entries of buffer `i` by `factor`; zeros in their place
    /// (and `finite` false) when any comes out not finite.
    pub fn scale(&mut self, i: usize, count: usize, factor: Real) {
        if let Some(d) = self.d[i].as_deref_mut() {
            let d = &mut d[..count];
            let mut finite = true;
            for v in d.iter_mut() {
                *v *= factor;
                finite &= v.is_finite();
            }
            if !finite {
                d.fill(0.0);
                self.finite = false;
            }
        }
    }

    /// Zeros in every buffer (`shapes` give their lengths).
    pub fn zero(&mut self, shapes: [&Shape; 2]) {
        for (d, s) in self.d.iter_mut().zip(shapes) {
            if let Some(d) = d.as_deref_mut() {
                d[..s.parameter_count()].fill(0.0);
            }
        }
        self.written = true;
    }
}

/// The inputs of one proximity solve, in solver coordinates.
#[derive(Clone, Copy)]
pub(crate) struct Context<'q> {
    pub shape1: &'q Shape,
    pub shape2: &'q Shape,
    pub pose1: &'q Pose,
    pub pose2: &'q Pose,
    pub options: &'q Options,
    pub frame: Frame,
    pub place1: Placement,
    pub place2: Placement,
    pub inv_scale: Real,
}
