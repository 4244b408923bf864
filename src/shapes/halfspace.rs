//! Half-space: `{ u : u_z ≤ depth }` in body coordinates, `depth > 0` finite. The outward normal
//! is `+e_z` (body) and the boundary plane lies `depth` above the body origin, so the origin is
//! strictly inside, as for every primitive. Scaled by `α` about its origin it is
//! `{ u_z ≤ α·depth }`: one nonnegative-orthant row `α·depth − u_z ≥ 0` and no cone.
//!
//! The set is unbounded: its support function is `+∞` in every direction but `+e_z`, so the
//! general solvers (which work on support maps and bounded sets) never see a half-space. Every
//! query with one half-space is answered in closed form by `crate::query::halfspace`, through
//! one support call of the other shape in the direction `−n` (the half-space's outward normal
//! in that shape's body frame).

use super::support::{PieceEval, Round, SupportMap};
use super::{positive_finite, BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::{Error, ErrorDetail};
use crate::math::{Real, Vec3};

/// The half-space `{ u : u_z ≤ depth }` (body frame).
#[derive(Clone, Debug, PartialEq)]
pub struct Halfspace {
    depth: Real,
}

impl Halfspace {
    /// Validates `depth` (positive, finite, not subnormal).
    pub fn new(depth: Real) -> Result<Halfspace, Error> {
        positive_finite("depth", depth)?;
        if depth < Real::MIN_POSITIVE {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "depth",
                depth,
                "underflows (not a normal positive number)",
            )));
        }
        Ok(Halfspace { depth })
    }

    /// The distance `depth` from the body origin up to the boundary plane.
    pub fn depth(&self) -> Real {
        self.depth
    }

    /// `∂h(m)/∂depth = m_z` (the support function is `depth·m_z` along `+e_z`, the only
    /// direction in which it is finite).
    pub(crate) fn support_gradient(&self, m: &Vec3, out: &mut [Real]) {
        out[0] = m.z;
    }

    /// The row's derivative at `p`: `α·depth·inv_scale − u_z`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        out[0] += inv_scale * p(4).a;
    }

    /// The boundary point on the body z axis.
    #[inline]
    fn top(&self) -> Vec3 {
        Vec3::new(0.0, 0.0, self.depth)
    }
}

/// The body-frame outward normal.
const NORMAL: Vec3 = Vec3::new(0.0, 0.0, 1.0);

impl SupportMap for Halfspace {
    /// `(0, 0, depth)` for `m` along `+e_z`; in every other direction the support function is
    /// `+∞`, and the point returned has infinite coordinates along `m`'s components (the
    /// queries never ask: they answer half-space pairs in closed form). Kept out of line, so
    /// that the shapes' support dispatch stays small enough to inline in the solvers' loops
    /// (inlined, it made box–box proximity 40 % slower).
    #[cold]
    #[inline(never)]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        let inf = |v: Real| {
            if v > 0.0 {
                Real::INFINITY
            } else if v < 0.0 {
                Real::NEG_INFINITY
            } else {
                0.0
            }
        };
        let z = if m.z < 0.0 {
            Real::NEG_INFINITY
        } else {
            self.depth
        };
        (Vec3::new(inf(m.x), inf(m.y), z), 0)
    }
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        // Finite (and differentiable) only along +e_z, where it is the plane's point.
        (id == 0 && m.x == 0.0 && m.y == 0.0 && m.z > 0.0)
            .then(|| Round::Flat.eval(&self.top(), m))?
    }
    fn flat_face(&self, m: &Vec3, cos_min: Real) -> Option<Vec3> {
        let n = m.norm();
        (n > 0.0 && m.z >= cos_min * n).then_some(NORMAL)
    }
    fn gauge(&self, p: &Vec3) -> Real {
        (p.z / self.depth).max(0.0)
    }
    fn piece_count(&self) -> u32 {
        1
    }
}

impl ConicShape for Halfspace {
    fn lp_count(&self) -> usize {
        1
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn soc_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        sink.lp(BodyRow::new(
            [0.0, 0.0, -1.0],
            self.depth * inv_scale,
            [0.0; 3],
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership_and_support() {
        let h = Halfspace::new(0.5).unwrap();
        assert!(member(&h, [100.0, -3.0, 0.49], 1.0, [0.0; 2]));
        assert!(!member(&h, [0.0, 0.0, 0.51], 1.0, [0.0; 2]));
        assert!(member(&h, [0.0, 0.0, 0.99], 2.0, [0.0; 2]));
        assert!(member(&h, [5.0, 0.0, -1.0], 0.0, [0.0; 2]));
        assert_eq!(
            h.support(&Vec3::new(0.0, 0.0, 2.0)).0,
            Vec3::new(0.0, 0.0, 0.5)
        );
        assert!(h.support(&Vec3::new(0.1, 0.0, 1.0)).0.x.is_infinite());
        assert!(h.piece(0, &Vec3::new(0.0, 0.0, 1.0)).is_some());
        assert!(h.piece(0, &Vec3::new(0.1, 0.0, 1.0)).is_none());
        assert_eq!(h.gauge(&Vec3::new(3.0, 1.0, 1.0)), 2.0);
        assert_eq!(h.gauge(&Vec3::new(3.0, 1.0, -1.0)), 0.0);
        assert_eq!(h.flat_face(&Vec3::new(0.0, 0.1, 1.0), 0.9), Some(NORMAL));
        assert_eq!(h.flat_face(&Vec3::new(0.0, 1.0, 0.1), 0.9), None);
        for bad in [0.0, -1.0, Real::NAN, Real::INFINITY, 1e-310] {
            assert!(Halfspace::new(bad).is_err(), "{bad}");
        }
    }
}
