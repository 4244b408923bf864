//! Cone: height `H`, half angle β, apex at `−3H/4 e_x`, base disc of radius `H tan β` at
//! `+H/4 e_x`. Scaled: the cone `[tan β (u_x + α 3H/4); u_y; u_z]` and the row `αH/4 − u_x ≥ 0`.

use super::support::{nearest_normal, PieceEval, Reduced, Round, SupportMap};
use super::{positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// A solid right circular cone with its origin at the centroid.
#[derive(Clone, Debug, PartialEq)]
pub struct Cone {
    height: Real,
    half_angle: Real,
    tan_beta: Real,
}

impl Cone {
    /// Validates `height` (positive, finite) and `half_angle` ∈ (0, π/2).
    pub fn new(height: Real, half_angle: Real) -> Result<Cone, Error> {
        positive_finite("height", height)?;
        if !half_angle.is_finite() || half_angle <= 0.0 || half_angle >= std::f64::consts::FRAC_PI_2
        {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "half_angle",
                half_angle,
                "must lie in the open interval (0, pi/2) radians",
            )));
        }
        let tan_beta = half_angle.tan();
        if !tan_beta.is_finite() || tan_beta <= 0.0 {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "half_angle",
                half_angle,
                "has no finite positive tangent",
            )));
        }
        Ok(Cone {
            height,
            half_angle,
            tan_beta,
        })
    }

    /// The height `H`.
    pub fn height(&self) -> Real {
        self.height
    }

    /// The half angle β in radians.
    pub fn half_angle(&self) -> Real {
        self.half_angle
    }

    /// `∂h(m)/∂(H, β)` at the support point `c` (body frame). `h` is homogeneous of degree one
    /// in `H`, so `∂h/∂H = h(m)/H`. A change of β turns every generator about the apex: the
    /// point a fraction `t = (c_x + 3H/4)/H` of the way from the apex to the rim moves out by
    /// `t H sec²β` radially, so `∂h/∂β = t H sec²β ‖m_yz‖` (0 at the apex, the rim's
    /// `H sec²β ‖m_yz‖` on it, and 0 on the base disc, where `m_yz = 0`). Exact wherever the
    /// contact point is known, the side's generators included.
    pub(crate) fn support_gradient(&self, m: &Vec3, c: &Vec3, out: &mut [Real]) {
        let h = self.height;
        let radial = m.y.hypot(m.z);
        let value = (-0.75 * h * m.x).max(0.25 * h * m.x + h * self.tan_beta * radial);
        let t = ((c.x + 0.75 * h) / h).clamp(0.0, 1.0);
        let sec2 = 1.0 + self.tan_beta * self.tan_beta;
        out[0] = value / h;
        out[1] = t * h * sec2 * radial;
    }

    /// The rows' derivatives at `p`: the cone `tan β (u_x + α(3H/4)·inv_scale)` and the row
    /// `α(H/4)·inv_scale − u_x`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        let (p0, p4) = (p(0), p(4));
        let t = self.tan_beta;
        out[0] += inv_scale * (0.75 * t * p0.a + 0.25 * p4.a);
        out[1] += (1.0 + t * t) * (p0.u.x + 0.75 * self.height * inv_scale * p0.a);
    }

    /// `∂ρ/∂(H, β)` of the bounding radius: the apex's distance `3H/4`, or the rim's
    /// `√(H²/16 + H² tan²β)`, whichever is larger.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) {
        let h = self.height;
        let rim = Vec3::new(0.25 * h, h * self.tan_beta, 0.0);
        let rho = rim.norm();
        if 0.75 * h >= rho {
            out[0] = 0.75;
            out[1] = 0.0;
        } else {
            self.support_gradient(&(rim / rho), &rim, out);
        }
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        let h = self.height;
        (0.75 * h).max((0.25 * h).hypot(h * self.tan_beta))
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        let h = self.height;
        (0.25 * h).min(0.75 * h * self.half_angle.sin())
    }
}

impl Cone {
    /// Piece 0 is the apex `−3H/4 e_x`, piece 1 the base rim (radius `H tan β` at `+H/4 e_x`).
    #[inline]
    fn apex_and_rim(&self) -> (Vec3, Vec3, Real) {
        let h = self.height;
        (
            Vec3::new(-0.75 * h, 0.0, 0.0),
            Vec3::new(0.25 * h, 0.0, 0.0),
            h * self.tan_beta,
        )
    }
}

/// The base's outward normal.
const BASE_NORMAL: [Vec3; 1] = [Vec3::new(1.0, 0.0, 0.0)];

impl SupportMap for Cone {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let (apex, base, rho) = self.apex_and_rim();
        let rim = base + Round::Circle(rho).point(m);
        if apex.dot(m) > rim.dot(m) {
            (apex, 0)
        } else {
            (rim, 1)
        }
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        let (apex, base, rho) = self.apex_and_rim();
        match id {
            0 => Round::Flat.eval(&apex, m),
            1 => Round::Circle(rho).eval(&base, m),
            _ => None,
        }
    }
    #[inline]
    fn piece_reduced(&self, id: u32, m: &Vec3, b: &[Vec3; 2]) -> Option<Reduced> {
        let (apex, base, rho) = self.apex_and_rim();
        match id {
            0 => Round::Flat.eval_reduced(&apex, m, b),
            1 => Round::Circle(rho).eval_reduced(&base, m, b),
            _ => None,
        }
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        nearest_normal(&BASE_NORMAL, m, cos_min)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        // p ∈ tB ⇔ p_x ≤ tH/4 and ‖p_yz‖ ≤ tan β (p_x + t·3H/4).
        let h = self.height;
        let base = p.x / (0.25 * h);
        let side = (p.y.hypot(p.z) / self.tan_beta - p.x) / (0.75 * h);
        base.max(side).max(0.0)
    }
    fn piece_count(&self) -> u32 {
        2
    }
    fn disc(&self, m: &Vec3, cos_min: Real) -> Option<(Vec3, Real)> {
        self.flat_face(m, cos_min)?;
        let (_, base, rho) = self.apex_and_rim();
        Some((base, rho))
    }
}

impl ConicShape for Cone {
    fn lp_count(&self) -> usize {
        1
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        let h = self.height * inv_scale;
        let t = self.tan_beta;
        sink.soc(&[
            BodyRow::new([t, 0.0, 0.0], t * 0.75 * h, [0.0; 3]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0; 3]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 3]),
        ]);
        sink.lp(BodyRow::new([-1.0, 0.0, 0.0], 0.25 * h, [0.0; 3]));
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership_and_radii() {
        let beta = 0.5_f64;
        let c = Cone::new(2.0, beta).unwrap();
        // apex and base rim
        assert!(member(&c, [-1.5 + 1e-9, 0.0, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&c, [-1.51, 0.0, 0.0], 1.0, [0.0; 2]));
        let rim = 2.0 * beta.tan();
        assert!(member(&c, [0.5, rim * 0.999, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&c, [0.5, rim * 1.001, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&c, [0.51, 0.0, 0.0], 1.0, [0.0; 2]));
        assert!((c.bounding_radius() - 1.5f64.max(0.5f64.hypot(rim))).abs() < 1e-15);
        assert!(Cone::new(1.0, 0.0).is_err());
        assert!(Cone::new(1.0, std::f64::consts::FRAC_PI_2).is_err());
    }
}
