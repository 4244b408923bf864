//! Cylinder: radius `R`, length `L`, axis `e_x`. Scaled: the cone `[αR; u_y; u_z]` and the rows
//! `αL/2 ∓ u_x ≥ 0`.

use super::{positive_finite, BodyRow, ConicShape, RowSink};
use crate::error::Error;
use crate::math::Real;

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
            BodyRow::new([0.0; 3], self.radius * inv_scale, [0.0; 2]),
            BodyRow::new([0.0, 1.0, 0.0], 0.0, [0.0; 2]),
            BodyRow::new([0.0, 0.0, 1.0], 0.0, [0.0; 2]),
        ]);
        sink.lp(BodyRow::new([-1.0, 0.0, 0.0], half, [0.0; 2]));
        sink.lp(BodyRow::new([1.0, 0.0, 0.0], half, [0.0; 2]));
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
