//! A shape's parameters (the numbers given to its constructor, in the order given) and the
//! derivatives that the shape-gradient queries (`crate::query::shape_gradient`) are built from:
//!
//! - [`Shape::support_gradient`]: `∂h(m)/∂θ` of the support function at a body direction `m`
//!   and the support point `x` the query identified (the envelope theorem on
//!   `α* = max n·d/(h₁(n) + h₂(−n))` turns it into `∂α*/∂θ`);
//! - [`Shape::row_gradient`]: `Σ_j ∂s_j/∂θ` over the shape's conic rows
//!   `s = f_u·u + f_α α + f_w·w` (`super::ConicShape::rows`), each row at its own point
//!   ([`RowPoint`]): the interior-point path's multipliers and adjoint make the derivatives
//!   of its answer from these (`crate::query::derivatives::shape`);
//! - [`Shape::radius_gradient`]: `∂ρ/∂θ` of the bounding radius (the smoothed answer depends on
//!   it through the program's normalisation).
//!
//! The per-kind closed forms are next to each kind (`sphere.rs`, …, `polytope/gradient.rs`); a
//! box is a polytope to the solvers, so its half extents are handled here.

use super::{Geometry, RowPoint, Shape};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

impl Shape {
    /// How many numbers [`Shape::parameters`] gives: sphere 1 (radius); ellipsoid 9 (`P`,
    /// row-major); polytope `4m` (`A` row-major, then `b`); box 3 (half extents); capsule and
    /// cylinder 2 (radius, length); cone 2 (height, half angle); padded polygon `3m + 1` (`C`
    /// row-major, `d`, radius); half-space 1 (depth); convex hull `3n + 1` (the points
    /// row-major, then the radius).
    pub fn parameter_count(&self) -> usize {
        if self.cuboid.is_some() {
            return 3;
        }
        match &self.geometry {
            Geometry::Sphere(_) | Geometry::Halfspace(_) => 1,
            Geometry::Ellipsoid(_) => 9,
            Geometry::Polytope(p) => p.parameter_count(),
            Geometry::Capsule(_) | Geometry::Cylinder(_) | Geometry::Cone(_) => 2,
            Geometry::Polygon(p) => p.parameter_count(),
            Geometry::Hull(h) => h.parameter_count(),
        }
    }

    /// The numbers given to the constructor, in the order given (see
    /// [`Shape::parameter_count`]). An ellipsoid's `P` is its symmetrised `(P + Pᵀ)/2`.
    ///
    /// ```
    /// use dcol::Shape;
    /// let s = Shape::cuboid(0.5, 1.0, 2.0).unwrap();
    /// assert_eq!(s.parameters(), vec![0.5, 1.0, 2.0]);
    /// let c = Shape::cone(1.0, 0.3).unwrap();
    /// assert_eq!(c.parameters(), vec![1.0, 0.3]);
    /// ```
    pub fn parameters(&self) -> Vec<Real> {
        let mut out = vec![0.0; self.parameter_count()];
        self.write_parameters(&mut out);
        out
    }

    /// Writes [`Shape::parameters`] into `out[..parameter_count]` (`out` at least that long).
    pub(crate) fn write_parameters(&self, out: &mut [Real]) {
        if let Some(h) = self.cuboid {
            out[..3].copy_from_slice(&h);
            return;
        }
        match &self.geometry {
            Geometry::Sphere(s) => out[0] = s.radius(),
            Geometry::Ellipsoid(e) => {
                let p = e.matrix();
                for i in 0..3 {
                    for j in 0..3 {
                        out[3 * i + j] = p[(i, j)];
                    }
                }
            }
            Geometry::Polytope(p) => p.write_parameters(out),
            Geometry::Capsule(c) => out[..2].copy_from_slice(&[c.radius(), c.length()]),
            Geometry::Cylinder(c) => out[..2].copy_from_slice(&[c.radius(), c.length()]),
            Geometry::Cone(c) => out[..2].copy_from_slice(&[c.height(), c.half_angle()]),
            Geometry::Polygon(p) => p.write_parameters(out),
            Geometry::Halfspace(h) => out[0] = h.depth(),
            Geometry::Hull(h) => h.write_parameters(out),
        }
    }

    /// A shape of the same kind built from `params` (as [`Shape::parameters`] gives them): what
    /// the constructor makes of those numbers, with its validation. `params` must have
    /// [`Shape::parameter_count`] entries.
    ///
    /// ```
    /// use dcol::Shape;
    /// let s = Shape::capsule(0.5, 2.0).unwrap();
    /// let t = s.with_parameters(&[0.25, 1.0]).unwrap();
    /// assert_eq!(t.parameters(), vec![0.25, 1.0]);
    /// assert!(s.with_parameters(&[0.25]).is_err());
    /// ```
    pub fn with_parameters(&self, params: &[Real]) -> Result<Shape, Error> {
        let count = self.parameter_count();
        if params.len() != count {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "parameters",
                params.len() as Real,
                "must have as many entries as the shape has parameters",
            )));
        }
        let p = params;
        if self.cuboid.is_some() {
            return Shape::cuboid(p[0], p[1], p[2]);
        }
        match &self.geometry {
            Geometry::Sphere(_) => Shape::sphere(p[0]),
            Geometry::Ellipsoid(_) => {
                Shape::ellipsoid([[p[0], p[1], p[2]], [p[3], p[4], p[5]], [p[6], p[7], p[8]]])
            }
            Geometry::Polytope(_) => {
                let m = count / 4;
                let a: Vec<[Real; 3]> = (0..m)
                    .map(|i| [p[3 * i], p[3 * i + 1], p[3 * i + 2]])
                    .collect();
                Shape::polytope(&a, &p[3 * m..])
            }
            Geometry::Capsule(_) => Shape::capsule(p[0], p[1]),
            Geometry::Cylinder(_) => Shape::cylinder(p[0], p[1]),
            Geometry::Cone(_) => Shape::cone(p[0], p[1]),
            Geometry::Polygon(_) => {
                let m = (count - 1) / 3;
                let c: Vec<[Real; 2]> = (0..m).map(|i| [p[2 * i], p[2 * i + 1]]).collect();
                Shape::polygon(&c, &p[2 * m..3 * m], p[3 * m])
            }
            Geometry::Halfspace(_) => Shape::halfspace(p[0]),
            Geometry::Hull(_) => {
                let n = (count - 1) / 3;
                let pts: Vec<[Real; 3]> = (0..n)
                    .map(|i| [p[3 * i], p[3 * i + 1], p[3 * i + 2]])
                    .collect();
                Shape::convex_hull(&pts, p[3 * n])
            }
        }
    }

    /// `∂h(m)/∂θ` of the support function at the body direction `m`, at the support point `x`
    /// (body frame) the query found, into `out[..parameter_count]` (overwritten). False when
    /// the derivative is not unique there and one element of the generalised gradient was
    /// written (a corner where more than three facets meet, a hull's facet of more than three
    /// corners, a hull corner given twice).
    pub(crate) fn support_gradient(&self, m: &Vec3, x: &Vec3, out: &mut [Real]) -> bool {
        if self.cuboid.is_some() {
            for k in 0..3 {
                out[k] = m[k].abs();
            }
            return true;
        }
        match &self.geometry {
            Geometry::Sphere(s) => s.support_gradient(m, out),
            Geometry::Ellipsoid(e) => e.support_gradient(m, out),
            Geometry::Polytope(p) => return p.support_gradient(m, x, out),
            Geometry::Capsule(c) => c.support_gradient(m, out),
            Geometry::Cylinder(c) => c.support_gradient(m, out),
            Geometry::Cone(c) => c.support_gradient(m, x, out),
            Geometry::Polygon(p) => return p.support_gradient(m, x, out),
            Geometry::Halfspace(h) => h.support_gradient(m, out),
            Geometry::Hull(h) => return h.support_gradient(m, x, out),
        }
        true
    }

    /// Whether [`Shape::support_gradient`] needs the support point (not only the direction):
    /// for the kinds whose support point at a direction may be a whole feature.
    #[inline]
    pub(crate) fn support_point_matters(&self) -> bool {
        self.cuboid.is_none()
            && matches!(
                self.geometry,
                Geometry::Polytope(_)
                    | Geometry::Cone(_)
                    | Geometry::Polygon(_)
                    | Geometry::Hull(_)
            )
    }

    /// Adds `Σ_j ∂s_j/∂θ` over the shape's rows (as `ConicShape::rows` writes them with
    /// `inv_scale`), row `j` evaluated at `p(j)` (the cone's components 0..4, orthant row `k` as
    /// `4 + k`), to `out[..parameter_count]`. `at` is the solution point in the same
    /// coordinates (a hull picks the triangle of a facet of many corners by it); `central` says
    /// that the points are the central path's (`−λ_j` times `at` otherwise). False when the
    /// derivative is not unique (a hull's facet of more than three corners, or a corner given
    /// twice, carries weight).
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        at: &RowPoint,
        central: bool,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) -> bool {
        let out = &mut out[..self.parameter_count()];
        if self.cuboid.is_some() {
            // Rows +x, +y, +z, −x, −y, −z with offsets (h_x, h_y, h_z, h_x, h_y, h_z).
            for k in 0..3 {
                out[k] += inv_scale * (p(4 + k).a + p(7 + k).a);
            }
            return true;
        }
        match &self.geometry {
            Geometry::Sphere(s) => s.row_gradient(inv_scale, p, out),
            Geometry::Ellipsoid(e) => e.row_gradient(inv_scale, p, out),
            Geometry::Polytope(q) => q.row_gradient(inv_scale, p, out),
            Geometry::Capsule(c) => c.row_gradient(inv_scale, p, out),
            Geometry::Cylinder(c) => c.row_gradient(inv_scale, p, out),
            Geometry::Cone(c) => c.row_gradient(inv_scale, p, out),
            Geometry::Polygon(q) => q.row_gradient(inv_scale, p, out),
            Geometry::Halfspace(h) => h.row_gradient(inv_scale, p, out),
            Geometry::Hull(h) => {
                // The solution's core point, body frame, world lengths.
                let y = if h.radius() > 0.0 { at.w } else { at.u };
                let scale = if at.a > 0.0 {
                    at.a * inv_scale
                } else {
                    inv_scale
                };
                return h.row_gradient(inv_scale, &(y / scale), central, p, out);
            }
        }
        true
    }

    /// `∂ρ/∂θ` of the radius the interior-point program is normalised by (the bounding radius;
    /// a half-space's depth) into `out[..parameter_count]` (overwritten). The bounding radius
    /// is the largest `h(m)` over unit `m`, so this is the support function's derivative at
    /// the farthest point. False where that is not unique (ties between farthest points of
    /// different derivatives are not looked for: they are exceptional).
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) -> bool {
        let out = &mut out[..self.parameter_count()];
        out.fill(0.0);
        if let Some(h) = self.cuboid {
            let rho = Vec3::from(h).norm();
            for k in 0..3 {
                out[k] = h[k] / rho;
            }
            return true;
        }
        match &self.geometry {
            Geometry::Sphere(_) | Geometry::Halfspace(_) => out[0] = 1.0,
            Geometry::Ellipsoid(e) => e.radius_gradient(out),
            Geometry::Polytope(p) => return p.radius_gradient(out),
            Geometry::Capsule(c) => c.radius_gradient(out),
            Geometry::Cylinder(c) => c.radius_gradient(out),
            Geometry::Cone(c) => c.radius_gradient(out),
            Geometry::Polygon(p) => return p.radius_gradient(out),
            Geometry::Hull(h) => return h.radius_gradient(out),
        }
        true
    }

    /// The kinds' length dimensions, for the scale identity (scaling every length by `s`
    /// leaves α* unchanged): the exponent of each parameter under that scaling (1 for a
    /// length, 0 for a dimensionless number, −2 for the entries of an ellipsoid's `P`).
    pub fn parameter_dimensions(&self) -> Vec<Real> {
        let count = self.parameter_count();
        if self.cuboid.is_some() {
            return vec![1.0; 3];
        }
        match &self.geometry {
            Geometry::Ellipsoid(_) => vec![-2.0; 9],
            Geometry::Polytope(_) => {
                let m = count / 4;
                (0..count)
                    .map(|i| if i < 3 * m { 0.0 } else { 1.0 })
                    .collect()
            }
            Geometry::Cone(_) => vec![1.0, 0.0],
            Geometry::Polygon(_) => {
                let m = (count - 1) / 3;
                (0..count)
                    .map(|i| if i < 2 * m { 0.0 } else { 1.0 })
                    .collect()
            }
            _ => vec![1.0; count],
        }
    }
}
