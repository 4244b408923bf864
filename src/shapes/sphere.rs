//! Sphere: `‖b‖ ≤ R`. Scaled: the second-order cone `[αR; u]`.

use super::support::{ball_normal, PieceEval, Round, SupportMap};
use super::{positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::Error;
use crate::math::{Real, Vec3};

/// A ball of radius `R` about the body origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    radius: Real,
}

impl Sphere {
    /// Validates `radius` (positive, finite).
    pub fn new(radius: Real) -> Result<Sphere, Error> {
        positive_finite("radius", radius)?;
        Ok(Sphere { radius })
    }

    /// The radius `R`.
    pub fn radius(&self) -> Real {
        self.radius
    }

    /// `∂h(m)/∂R = ‖m‖` (the parameter: `R`).
    pub(crate) fn support_gradient(&self, m: &Vec3, out: &mut [Real]) {
        out[0] = m.norm();
    }

    /// The rows' derivatives at `p` (`shapes/parameters.rs`): the cone's `αR·inv_scale`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        out[0] += inv_scale * p(0).a;
    }
}

impl SupportMap for Sphere {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        (Round::Ball(self.radius).point(m), 0)
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        (id == 0).then(|| Round::Ball(self.radius).eval(&Vec3::zeros(), m))?
    }
    fn flat_face(&self, _m: &Vec3, _cos_min: Real) -> Option<Vec3> {
        None
    }
    fn gauge(&self, p: &Vec3) -> Real {
        p.norm() / self.radius
    }
    fn normal_at(&self, _id: u32, p: &Vec3) -> Option<Vec3> {
        ball_normal(&Vec3::zeros(), p)
    }
    fn piece_count(&self) -> u32 {
        1
    }
}

impl ConicShape for Sphere {
    fn lp_count(&self) -> usize {
        0
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        sink.soc(&[
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 3]),
            BodyRow::new([1.0, 0.0, 0.0], 0.0, [0.0; 3]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0; 3]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 3]),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership() {
        let s = Sphere::new(2.0).unwrap();
        assert!(member(&s, [1.9, 0.0, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&s, [1.5, 1.5, 0.0], 1.0, [0.0; 2]));
        assert!(member(&s, [1.5, 1.5, 0.0], 1.1, [0.0; 2]));
        assert!(Sphere::new(0.0).is_err());
        assert!(Sphere::new(f64::NAN).is_err());
    }
}
