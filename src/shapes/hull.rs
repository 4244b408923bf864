//! Convex hull of points, padded by a ball of radius `R ≥ 0`: points within `R` of the hull of
//! the given points (`R = 0`: the hull itself; `R > 0`: what Bullet's collision margin makes of
//! a hull, and a rounded box). The hull is built once (`super::quickhull`) as a polytope, its
//! *core*; a query sees the core's corners, each padded by the ball. Scaled, with the slack
//! `y ∈ R³` (the core point): the cone `[αR; u − y]` and the rows `α o_i − n_i·y ≥ 0`; with
//! `R = 0`, the core's rows on `u` itself.

use super::quickhull::{self, HullError};
use super::support::{ball_normal, PieceEval, Round, SupportMap};
use super::{BodyRow, ConicShape, Polytope, RowSink, Shape};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// The convex hull of a set of points, padded by a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexHull {
    /// The hull as a polytope (a [`Shape`] so that the queries can take it as the core).
    core: Box<Shape>,
    radius: Real,
    /// The points as given.
    points: Vec<[Real; 3]>,
}

impl ConvexHull {
    /// Validates `points` (finite, at least four affinely independent, the origin strictly
    /// inside their hull) and `radius` (finite, ≥ 0), and builds the hull.
    pub fn new(points: &[[Real; 3]], radius: Real) -> Result<ConvexHull, Error> {
        if !(radius.is_finite() && radius >= 0.0) {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "radius",
                radius,
                "must be finite and non-negative",
            )));
        }
        if points.len() < 4 {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "n",
                points.len() as Real,
                "must be at least 4 (a hull needs four affinely independent points)",
            )));
        }
        let pts: Vec<Vec3> = points.iter().map(|p| Vec3::from(*p)).collect();
        let why = |e: HullError| {
            Error::InvalidShape(match e {
                HullError::NonFinite(i, v) => ErrorDetail::at("points", i, v, "must be finite"),
                HullError::Coincident(n) => ErrorDetail::new(
                    "n",
                    n as Real,
                    "points all coincide (a hull needs four affinely independent points)",
                ),
                HullError::Collinear => ErrorDetail::new(
                    "n",
                    points.len() as Real,
                    "points all lie on one line (a hull needs four affinely independent points)",
                ),
                HullError::Coplanar => ErrorDetail::new(
                    "n",
                    points.len() as Real,
                    "points all lie in one plane (a hull needs four affinely independent \
                     points; a flat shape is a padded polygon)",
                ),
                HullError::Failed(d) => ErrorDetail::new(
                    "points",
                    d,
                    "could not be hulled within rounding (a point was left this far outside)",
                ),
            })
        };
        let mesh = quickhull::hull(&pts).map_err(why)?;
        let tol = quickhull::tolerance(&pts);
        let centroid = mesh.vertices.iter().sum::<Vec3>() / mesh.vertices.len() as Real;
        let poly = Polytope::from_mesh(mesh, tol).map_err(|least| {
            Error::InvalidShape(ErrorDetail::with_point(
                "points",
                least,
                "must surround the origin strictly (the value is the nearest facet's signed \
                 distance from it): shift them by minus the centroid of their hull's corners",
                [centroid.x, centroid.y, centroid.z],
            ))
        })?;
        let core = Shape::polytope_shape(poly)?;
        Ok(ConvexHull {
            core: Box::new(core),
            radius,
            points: points.to_vec(),
        })
    }

    /// The points as given (row-major, body frame).
    pub fn points(&self) -> &[[Real; 3]] {
        &self.points
    }

    /// The padding radius `R` (0: the hull itself).
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The hull's corners (a subset of the points; body frame).
    pub fn corners(&self) -> &[Vec3] {
        self.poly().vertices()
    }

    /// The hull as a polytope shape (unpadded).
    pub(crate) fn core(&self) -> &Shape {
        &self.core
    }

    pub(crate) fn poly(&self) -> &Polytope {
        self.core
            .as_polytope()
            .expect("a hull's core is a polytope by construction")
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        self.core.bounding_radius() + self.radius
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        self.core.inscribed_radius() + self.radius
    }
}

impl SupportMap for ConvexHull {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let (p, k) = self.poly().support(m);
        if self.radius > 0.0 {
            (p + Round::Ball(self.radius).point(m), k)
        } else {
            (p, k)
        }
    }
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        let v = self.corners().get(id as usize)?;
        if self.radius > 0.0 {
            Round::Ball(self.radius).eval(v, m)
        } else {
            Round::Flat.eval(v, m)
        }
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        // The padded facets keep the core's normals.
        self.poly().flat_face(m, cos_min)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        // The core grown by the factor 1 + R/ρ (ρ its bounding radius) lies in the padded hull:
        // each of its points is within R of the core point it was scaled from.
        let rho = self.core.bounding_radius();
        self.poly().gauge(p) / (1.0 + self.radius / rho)
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        if self.radius > 0.0 {
            ball_normal(self.corners().get(id as usize)?, p)
        } else {
            None
        }
    }
    fn piece_count(&self) -> u32 {
        self.corners().len() as u32
    }
}

impl ConicShape for ConvexHull {
    fn lp_count(&self) -> usize {
        self.poly().lp_count()
    }
    fn slack_count(&self) -> usize {
        if self.radius > 0.0 {
            3
        } else {
            0
        }
    }
    fn soc_count(&self) -> usize {
        usize::from(self.radius > 0.0)
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        if self.radius == 0.0 {
            return self.poly().rows(inv_scale, sink);
        }
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([1.0, 0.0, 0.0], 0.0, [-1.0, 0.0, 0.0]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0, -1.0, 0.0]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0, 0.0, -1.0]),
        ]);
        let (normals, offsets) = self.poly().facets();
        for (n, o) in normals.iter().zip(offsets) {
            sink.lp(BodyRow::new([0.0; 3], o * inv_scale, [-n.x, -n.y, -n.z]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    fn cube(h: Real) -> Vec<[Real; 3]> {
        let mut p = Vec::new();
        for i in 0..8 {
            p.push([0, 1, 2].map(|k| if i >> k & 1 == 1 { h } else { -h }));
        }
        p
    }

    #[test]
    fn a_padded_cube_is_a_rounded_box() {
        let h = ConvexHull::new(&cube(1.0), 0.25).unwrap();
        assert_eq!(h.corners().len(), 8);
        assert_eq!(h.bounding_radius(), 3f64.sqrt() + 0.25);
        assert_eq!(h.inscribed_radius(), 1.25);
        // Support: the corner plus the ball.
        let (s, _) = h.support(&Vec3::new(1.0, 1.0, 1.0));
        assert!((s - Vec3::repeat(1.0 + 0.25 / 3f64.sqrt())).norm() < 1e-15);
        let (s, _) = h.support(&Vec3::new(0.0, 0.0, -2.0));
        assert!((s.z + 1.25).abs() < 1e-15);
        // The conic rows: a point within R of the cube, with its core point as the slack.
        assert!(member(&h, [1.2, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]));
        assert!(member(&h, [1.1, 1.1, 0.0], 1.0, [1.0, 1.0, 0.0]));
        assert!(!member(&h, [1.2, 1.2, 0.0], 1.0, [1.0, 1.0, 0.0]));
        assert!(!member(&h, [1.3, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]));
        // The gauge is an upper bound: p/g lies in the shape.
        for p in [
            Vec3::new(1.24, 0.0, 0.0),
            Vec3::new(1.1, 1.1, 1.1),
            Vec3::new(0.3, -2.0, 0.1),
        ] {
            let g = h.gauge(&p);
            let q = p / g;
            let core = q.map(|v| v.clamp(-1.0, 1.0));
            assert!((q - core).norm() <= 0.25 + 1e-12, "{p:?}");
        }
    }

    #[test]
    fn an_unpadded_hull_is_its_polytope() {
        let h = ConvexHull::new(&cube(0.5), 0.0).unwrap();
        assert_eq!(h.slack_count(), 0);
        assert_eq!(h.lp_count(), 6);
        assert!(member(&h, [0.5, -0.5, 0.4], 1.0, [0.0; 0]));
        assert!(!member(&h, [0.51, 0.0, 0.0], 1.0, [0.0; 0]));
        assert_eq!(h.gauge(&Vec3::new(1.0, 0.25, 0.0)), 2.0);
        assert_eq!(h.core().centred_box(), Some(Vec3::repeat(0.5)));
    }

    #[test]
    fn bad_points_say_why() {
        let msg = |r: Result<ConvexHull, Error>| r.unwrap_err().to_string();
        assert!(msg(ConvexHull::new(&cube(1.0), -0.1)).contains("radius"));
        assert!(msg(ConvexHull::new(&cube(1.0)[..3], 0.0)).contains("at least 4"));
        let mut nan = cube(1.0);
        nan[2][1] = Real::NAN;
        assert!(msg(ConvexHull::new(&nan, 0.0)).contains("points[7]"));
        let flat: Vec<[Real; 3]> = cube(1.0).into_iter().map(|p| [p[0], p[1], 0.0]).collect();
        assert!(msg(ConvexHull::new(&flat, 0.1)).contains("one plane"));
        let shifted: Vec<[Real; 3]> = cube(1.0)
            .into_iter()
            .map(|p| [p[0] + 3.0, p[1], p[2]])
            .collect();
        let m = msg(ConvexHull::new(&shifted, 0.0));
        assert!(
            m.contains("surround the origin") && m.contains("(3, 0, 0)"),
            "{m}"
        );
        // The origin on a facet is not strictly inside.
        let touching: Vec<[Real; 3]> = cube(1.0)
            .into_iter()
            .map(|p| [p[0] + 1.0, p[1], p[2]])
            .collect();
        assert!(msg(ConvexHull::new(&touching, 0.0)).contains("surround the origin"));
    }
}
