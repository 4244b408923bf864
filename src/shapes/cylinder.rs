//! Cylinder: radius `R`, length `L`, axis `e_x`. Scaled: the cone `[αR; u_y; u_z]` and the rows
//! `αL/2 ∓ u_x ≥ 0`.

use super::support::{
    nearest_normal, two_ends_set, PieceEval, Reduced, Round, SupportMap, ROUND_EPS,
};
use super::{positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::Error;
use crate::math::{Real, Vec3};

/// A solid cylinder centred at the body origin with its axis along body x.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    radius: Real,
    length: Real,
}

impl Cylinder {
    /// Validates `radius` and `length` (positive, finite).
    pub fn new(radius: Real, length: Real) -> Result<Cylinder, Error> {
        positive_finite("radius", radius)?;
        positive_finite("length", length)?;
        Ok(Cylinder { radius, length })
    }

    /// The radius `R`.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The length `L` (flat ends at `x = ±L/2`).
    pub fn length(&self) -> Real {
        self.length
    }

    /// `∂h(m)/∂(R, L) = (‖m_yz‖, |m_x|/2)`: `h(m) = (L/2)|m_x| + R‖m_yz‖` is linear in both.
    pub(crate) fn support_gradient(&self, m: &Vec3, out: &mut [Real]) {
        out[0] = m.y.hypot(m.z);
        out[1] = 0.5 * m.x.abs();
    }

    /// The rows' derivatives at `p`: the cone's `αR·inv_scale`, the rows `α(L/2)·inv_scale ∓ u_x`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        out[0] += inv_scale * p(0).a;
        out[1] += 0.5 * inv_scale * (p(4).a + p(5).a);
    }

    /// `∂ρ/∂(R, L)` of the bounding radius `ρ = √(R² + L²/4)`.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) {
        let (r, half) = (self.radius, 0.5 * self.length);
        let rho = r.hypot(half);
        out[0] = r / rho;
        out[1] = 0.5 * half / rho;
    }
}

impl Cylinder {
    /// Piece 0 is the rim circle at `x = +L/2`, piece 1 the one at `x = −L/2`.
    #[inline]
    fn cap(&self, id: u32) -> Vec3 {
        let half = 0.5 * self.length;
        Vec3::new(if id == 0 { half } else { -half }, 0.0, 0.0)
    }
}

/// The two caps' outward normals.
const CAP_NORMALS: [Vec3; 2] = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0)];

impl SupportMap for Cylinder {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let id = u32::from(m.x < 0.0);
        (self.cap(id) + Round::Circle(self.radius).point(m), id)
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        (id < 2).then(|| Round::Circle(self.radius).eval(&self.cap(id), m))?
    }
    #[inline]
    fn piece_reduced(&self, id: u32, m: &Vec3, b: &[Vec3; 2]) -> Option<Reduced> {
        (id < 2).then(|| Round::Circle(self.radius).eval_reduced(&self.cap(id), m, b))?
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        nearest_normal(&CAP_NORMALS, m, cos_min)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        (p.x.abs() / (0.5 * self.length)).max(p.y.hypot(p.z) / self.radius)
    }
    fn piece_count(&self) -> u32 {
        2
    }
    fn support_set(&self, m: &Vec3, tie: Real, point: Real) -> Option<(usize, Vec3)> {
        // The rims are differentiable where `m` has a part across the axis (as `piece` requires).
        let across = (m.y * m.y + m.z * m.z).sqrt();
        (across > ROUND_EPS * m.norm().max(ROUND_EPS))
            .then(|| two_ends_set(self.length, m, tie, point))
    }
    fn disc(&self, m: &Vec3, cos_min: Real) -> Option<(Vec3, Real)> {
        let f = self.flat_face(m, cos_min)?;
        Some((self.cap(u32::from(f.x < 0.0)), self.radius))
    }
}

impl ConicShape for Cylinder {
    fn lp_count(&self) -> usize {
        2
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        let half = 0.5 * self.length * inv_scale;
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0; 3]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 3]),
        ]);
        sink.lp(BodyRow::new([-1.0, 0.0, 0.0], half, [0.0; 3]));
        sink.lp(BodyRow::new([1.0, 0.0, 0.0], half, [0.0; 3]));
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership() {
        let c = Cylinder::new(0.5, 2.0).unwrap();
        assert!(member(&c, [0.99, 0.3, 0.3], 1.0, [0.0; 2]));
        assert!(!member(&c, [1.01, 0.0, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&c, [0.0, 0.4, 0.4], 1.0, [0.0; 2]));
        assert!(Cylinder::new(f64::INFINITY, 1.0).is_err());
    }
}
