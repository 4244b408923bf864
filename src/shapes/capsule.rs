//! Capsule: points within `R` of the segment `±L/2 e_x`. Scaled, with the slack γ (position
//! along the axis): the cone `[αR; u − γ e_x]` and the rows `αL/2 ∓ γ ≥ 0`.

use super::support::{ball_normal, two_ends_set, PieceEval, Round, SupportMap, ROUND_EPS};
use super::{positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::Error;
use crate::math::{Real, Vec3};

/// A capsule of radius `R` and segment length `L` along the body x axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Capsule {
    radius: Real,
    length: Real,
}

impl Capsule {
    /// Validates `radius` and `length` (positive, finite).
    pub fn new(radius: Real, length: Real) -> Result<Capsule, Error> {
        positive_finite("radius", radius)?;
        positive_finite("length", length)?;
        Ok(Capsule { radius, length })
    }

    /// The radius `R`.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// The segment length `L`.
    pub fn length(&self) -> Real {
        self.length
    }

    /// `∂h(m)/∂(R, L) = (‖m‖, |m_x|/2)`: `h(m) = (L/2)|m_x| + R‖m‖` is linear in both.
    pub(crate) fn support_gradient(&self, m: &Vec3, out: &mut [Real]) {
        out[0] = m.norm();
        out[1] = 0.5 * m.x.abs();
    }

    /// The rows' derivatives at `p`: the cone's `αR·inv_scale`, the rows `α(L/2)·inv_scale ∓ γ`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        out[0] += inv_scale * p(0).a;
        out[1] += 0.5 * inv_scale * (p(4).a + p(5).a);
    }

    /// `∂ρ/∂(R, L)` of the bounding radius `ρ = R + L/2`.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) {
        out[0] = 1.0;
        out[1] = 0.5;
    }
}

impl Capsule {
    /// Piece 0 is the ball around `+L/2 e_x`, piece 1 the one around `−L/2 e_x`.
    #[inline]
    fn end(&self, id: u32) -> Vec3 {
        let half = 0.5 * self.length;
        Vec3::new(if id == 0 { half } else { -half }, 0.0, 0.0)
    }
}

impl SupportMap for Capsule {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let id = u32::from(m.x < 0.0);
        (self.end(id) + Round::Ball(self.radius).point(m), id)
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        (id < 2).then(|| Round::Ball(self.radius).eval(&self.end(id), m))?
    }
    fn flat_face(&self, _m: &Vec3, _cos_min: Real) -> Option<Vec3> {
        None
    }
    fn gauge(&self, p: &Vec3) -> Real {
        // The inscribed cylinder of radius R between the end centres.
        (p.x.abs() / (0.5 * self.length)).max(p.y.hypot(p.z) / self.radius)
    }
    fn normal_at(&self, id: u32, p: &Vec3) -> Option<Vec3> {
        ball_normal(&self.end(id), p)
    }
    fn piece_count(&self) -> u32 {
        2
    }
    fn support_set(&self, m: &Vec3, tie: Real, point: Real) -> Option<(usize, Vec3)> {
        // The ends' balls are differentiable wherever `m ≠ 0` (as `piece` requires).
        (m.norm() > ROUND_EPS).then(|| two_ends_set(self.length, m, tie, point))
    }
}

impl ConicShape for Capsule {
    fn lp_count(&self) -> usize {
        2
    }
    fn slack_count(&self) -> usize {
        1
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        let half = 0.5 * self.length * inv_scale;
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([1.0, 0.0, 0.0], 0.0, [-1.0, 0.0, 0.0]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0; 3]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 3]),
        ]);
        sink.lp(BodyRow::new([0.0; 3], half, [-1.0, 0.0, 0.0]));
        sink.lp(BodyRow::new([0.0; 3], half, [1.0, 0.0, 0.0]));
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership() {
        let c = Capsule::new(0.5, 2.0).unwrap();
        assert!(member(&c, [1.4, 0.0, 0.0], 1.0, [1.0, 0.0, 0.0]));
        assert!(member(&c, [0.3, 0.45, 0.0], 1.0, [0.3, 0.0]));
        assert!(!member(&c, [0.3, 0.55, 0.0], 1.0, [0.3, 0.0]));
        assert!(!member(&c, [0.0, 0.0, 0.0], 1.0, [1.1, 0.0]));
        assert!(Capsule::new(1.0, -1.0).is_err());
    }
}
