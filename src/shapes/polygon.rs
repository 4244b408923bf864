//! Padded polygon: points within `R` of the plane polygon `{ (y, 0) : C y ≤ d }`. Scaled, with
//! the slack `y ∈ R²`: the cone `[αR; u − (y, 0)]` and the rows `α d_i − c_i·y ≥ 0`.

use super::support::{
    argmax_dot, ball_normal, multipliers, nearest_normal, Active, PieceEval, Round, SupportMap,
};
use super::{check_halfspaces, positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// A polygon in the body x-y plane, padded by a radius.
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    c: Vec<[Real; 2]>,
    d: Vec<Real>,
    radius: Real,
    polygon_radius: Real,
    /// The polygon's vertices `(y, 0)`, deduplicated.
    vertices: Vec<Vec3>,
}

impl Polygon {
    /// Validates `C` (m×2, rows non-zero, finite), `d` (positive, finite), boundedness, and
    /// `radius` (positive, finite).
    pub fn new(c: &[[Real; 2]], d: &[Real], radius: Real) -> Result<Polygon, Error> {
        check_halfspaces("C", "d", c, d, super::MAX_POLYGON_EDGES)?;
        positive_finite("radius", radius)?;
        let m = c.len();
        let norms: Vec<Real> = c.iter().map(|r| r[0].hypot(r[1])).collect();
        let n: Vec<[Real; 2]> = c
            .iter()
            .zip(&norms)
            .map(|(r, k)| [r[0] / k, r[1] / k])
            .collect();
        let off: Vec<Real> = d.iter().zip(&norms).map(|(v, k)| v / k).collect();
        let unbounded = || {
            Error::InvalidShape(ErrorDetail::new(
                "C",
                m as Real,
                "rows must describe a bounded polygon (found a direction e with C e ≤ 0)",
            ))
        };
        // Bounded ⇔ no e ≠ 0 with n_i·e ≤ 0 ∀i; an extreme ray lies along some facet line.
        let cross = |a: &[Real; 2], b: &[Real; 2]| a[0] * b[1] - a[1] * b[0];
        let rank2 = (0..m).any(|i| (0..m).any(|j| cross(&n[i], &n[j]).abs() > 1e-12));
        if !rank2 {
            return Err(unbounded());
        }
        for ni in &n {
            let e = [-ni[1], ni[0]];
            for sign in [1.0, -1.0] {
                if n.iter()
                    .all(|nk| sign * (nk[0] * e[0] + nk[1] * e[1]) <= 1e-12)
                {
                    return Err(unbounded());
                }
            }
        }
        // The largest vertex norm (not its square, which underflows for polygons below ~1e-154).
        let mut polygon_radius: Real = 0.0;
        let min_off = off.iter().cloned().fold(Real::INFINITY, Real::min);
        let mut vertices: Vec<Vec3> = Vec::new();
        for i in 0..m {
            for j in (i + 1)..m {
                let det = cross(&n[i], &n[j]);
                if det.abs() < 1e-12 {
                    continue;
                }
                let v = [
                    (off[i] * n[j][1] - off[j] * n[i][1]) / det,
                    (n[i][0] * off[j] - n[j][0] * off[i]) / det,
                ];
                let vn = v[0].hypot(v[1]);
                if n.iter()
                    .zip(&off)
                    .all(|(nl, ol)| nl[0] * v[0] + nl[1] * v[1] <= ol + 1e-9 * ol.max(vn))
                {
                    polygon_radius = polygon_radius.max(vn);
                    super::polytope::add_vertex(&mut vertices, Vec3::new(v[0], v[1], 0.0), min_off);
                }
            }
        }
        if !(polygon_radius.is_finite() && polygon_radius > 0.0) {
            return Err(unbounded());
        }
        Ok(Polygon {
            c: c.to_vec(),
            d: d.to_vec(),
            radius,
            polygon_radius,
            vertices,
        })
    }

    /// The edge normals `C` (rows, as given).
    pub fn c(&self) -> &[[Real; 2]] {
        &self.c
    }

    /// The offsets `d`.
    pub fn d(&self) -> &[Real] {
        &self.d
    }

    /// The plane polygon's vertices `(y, 0)` (deduplicated).
    pub(crate) fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }

    /// The padding radius `R`.
    pub fn radius(&self) -> Real {
        self.radius
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        self.polygon_radius + self.radius
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        self.radius
    }

    /// `3m + 1`: the rows of `C` (row-major), `d`, then `R`.
    pub(crate) fn parameter_count(&self) -> usize {
        3 * self.c.len() + 1
    }

    /// Writes `C` (row-major), `d` and `R`, as given.
    pub(crate) fn write_parameters(&self, out: &mut [Real]) {
        let m = self.c.len();
        for (i, row) in self.c.iter().enumerate() {
            out[2 * i..2 * i + 2].copy_from_slice(row);
        }
        out[2 * m..3 * m].copy_from_slice(&self.d);
        out[3 * m] = self.radius;
    }

    /// `∂h(m)/∂(C, d, R)` at the support point `x` (body frame) into `out` (overwritten). `h(m) = max { m_xy·y : C y ≤ d } + R‖m‖`: `∂h/∂R = ‖m‖`, and the plane
    /// polygon's linear program gives `∂h/∂d_i = λ_i`, `∂h/∂C_ij = −λ_i y_j` with `y` the core
    /// point `x − R m/‖m‖` and `λ` the multipliers of the edges active there (none on the flat
    /// top or bottom, where `m_xy = 0`). False where they are not unique.
    pub(crate) fn support_gradient(&self, m: &Vec3, x: &Vec3, out: &mut [Real]) -> bool {
        let count = self.c.len();
        let mn = m.norm();
        out[..3 * count].fill(0.0);
        out[3 * count] = mn;
        let mxy = Vec3::new(m.x, m.y, 0.0);
        if !(mxy.norm() > 1e-12 * mn) {
            return true;
        }
        let mut core = x - m * (self.radius / mn);
        core.z = 0.0;
        let mut act = Active::new();
        self.active_edges(&core, &mut act);
        let mut exact = true;
        if act.n == 0 {
            // Not on the polygon's boundary (it cannot be, to rounding): the support corner's.
            core = self.vertices[argmax_dot(&self.vertices, &mxy).0];
            self.active_edges(&core, &mut act);
            exact = false;
        }
        let (lam, unique) = multipliers(&act.rows[..act.n], &mxy, 2);
        for k in 0..act.n {
            let i = act.ids[k];
            let l = lam[k] / Vec3::new(self.c[i][0], self.c[i][1], 0.0).norm();
            out[2 * count + i] = l;
            out[2 * i] = -l * core.x;
            out[2 * i + 1] = -l * core.y;
        }
        exact && unique && act.all
    }

    /// The edges active at the plane point `y` (indices and unit normals `(c_i, 0)/‖c_i‖`) into
    /// `act` (emptied).
    fn active_edges(&self, y: &Vec3, act: &mut Active) {
        act.n = 0;
        act.all = true;
        let yn = y.norm();
        for (i, (c, d)) in self.c.iter().zip(&self.d).enumerate() {
            let a = Vec3::new(c[0], c[1], 0.0);
            let k = a.norm();
            if d / k - a.dot(y) / k <= 1e-8 * (d / k + yn) {
                act.push(i, a / k);
            }
        }
    }

    /// The rows' derivatives at `p` (`shapes/parameters.rs`): the cone's `αR·inv_scale`, and
    /// edge `i`'s row `α d_i·inv_scale − c_i·w` on the core point's slack `w`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        let m = self.c.len();
        out[3 * m] += inv_scale * p(0).a;
        for i in 0..m {
            let q = p(4 + i);
            out[2 * m + i] += inv_scale * q.a;
            out[2 * i] -= q.w.x;
            out[2 * i + 1] -= q.w.y;
        }
    }

    /// `∂ρ/∂(C, d, R)` of the bounding radius (the farthest polygon corner's distance plus
    /// `R`): the support function's derivative along that corner's direction.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) -> bool {
        let Some(v) = self
            .vertices
            .iter()
            .max_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()))
        else {
            return false;
        };
        let dir = v.normalize();
        self.support_gradient(&dir, &(v + dir * self.radius), out)
    }
}

/// The padded polygon's flat top and bottom.
const SIDE_NORMALS: [Vec3; 2] = [Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, -1.0)];

impl SupportMap for Polygon {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let (k, _) = argmax_dot(&self.vertices, m);
        (
            self.vertices[k] + Round::Ball(self.radius).point(m),
            k as u32,
        )
    }
    #[inline(always)]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        Round::Ball(self.radius).eval(self.vertices.get(id as usize)?, m)
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        nearest_normal(&SIDE_NORMALS, m, cos_min)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        // The inscribed prism: the polygon times [−R, R] along z.
        self.c
            .iter()
            .zip(&self.d)
            .fold(p.z.abs() / self.radius, |g: Real, (c, d)| {
                g.max((c[0] * p.x + c[1] * p.y) / d)
            })
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        ball_normal(self.vertices.get(id as usize)?, p)
    }
    fn piece_count(&self) -> u32 {
        self.vertices.len() as u32
    }
    fn ball_pieces(&self) -> Option<(&[Vec3], Real)> {
        Some((&self.vertices, self.radius))
    }
}

impl ConicShape for Polygon {
    fn lp_count(&self) -> usize {
        self.c.len()
    }
    fn slack_count(&self) -> usize {
        2
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([1.0, 0.0, 0.0], 0.0, [-1.0, 0.0, 0.0]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0, -1.0, 0.0]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 3]),
        ]);
        for (c, d) in self.c.iter().zip(&self.d) {
            sink.lp(BodyRow::new([0.0; 3], d * inv_scale, [-c[0], -c[1], 0.0]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    const SQ: [[Real; 2]; 4] = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]];

    #[test]
    fn square_radii_and_membership() {
        let p = Polygon::new(&SQ, &[1.0; 4], 0.1).unwrap();
        assert!((p.bounding_radius() - (2f64.sqrt() + 0.1)).abs() < 1e-14);
        assert!(member(&p, [1.05, 0.0, 0.05], 1.0, [1.0, 0.0, 0.0]));
        assert!(!member(&p, [0.5, 0.0, 0.11], 1.0, [0.5, 0.0]));
        assert!(!member(&p, [0.5, 0.0, 0.0], 1.0, [1.2, 0.0]));
    }

    #[test]
    fn rejects_bad_input() {
        assert!(Polygon::new(&SQ[..3], &[1.0; 3], 0.1).is_err());
        assert!(Polygon::new(&SQ, &[1.0; 4], 0.0).is_err());
        assert!(Polygon::new(&SQ, &[1.0, -1.0, 1.0, 1.0], 0.1).is_err());
        assert!(Polygon::new(&[[0.0, 0.0]], &[1.0], 0.1).is_err());
    }
}
