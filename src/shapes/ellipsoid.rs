//! Ellipsoid: `bᵀ P b ≤ 1` with `P = UᵀU` (Cholesky). Scaled: the cone `[α; U u]`.

use super::support::{PieceEval, Round, SupportMap};
use super::{BodyRow, ConicShape, RowPoint, RowSink};
use crate::error::{Error, ErrorDetail};
use crate::math::{Mat3, Real, Vec3};

/// An ellipsoid centred at the body origin.
#[derive(Clone, Debug, PartialEq)]
pub struct Ellipsoid {
    p: Mat3,
    /// Upper-triangular `U` with `P = UᵀU`.
    u: Mat3,
    /// `P⁻¹`: the support function is `√(mᵀP⁻¹m)`.
    p_inv: Mat3,
    eig_min: Real,
    eig_max: Real,
    /// Principal directions (columns, body frame), longest semi-axis first.
    axes: Mat3,
    /// Semi-axes, descending.
    semi: Vec3,
}

impl Ellipsoid {
    /// Validates `P` (rows): finite, symmetric to 1e-12 relative, positive definite.
    pub fn new(p: [[Real; 3]; 3]) -> Result<Ellipsoid, Error> {
        let mut scale: Real = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                let v = p[i][j];
                if !v.is_finite() {
                    return Err(Error::InvalidShape(ErrorDetail::at(
                        "P",
                        3 * i + j,
                        v,
                        "must be finite",
                    )));
                }
                scale = scale.max(v.abs());
            }
        }
        for i in 0..3 {
            for j in (i + 1)..3 {
                if (p[i][j] - p[j][i]).abs() > 1e-12 * scale {
                    return Err(Error::InvalidShape(ErrorDetail::at(
                        "P",
                        3 * i + j,
                        p[i][j],
                        "must be symmetric (differs from its transpose entry)",
                    )));
                }
            }
        }
        let m = Mat3::from_fn(|i, j| 0.5 * (p[i][j] + p[j][i]));
        let eig = m.symmetric_eigenvalues();
        let eig_min = eig.min();
        let eig_max = eig.max();
        if !(eig_min > 0.0) || !eig_max.is_finite() || eig_min <= eig_max * 1e-300 {
            return Err(Error::InvalidShape(ErrorDetail::new(
                "P",
                eig_min,
                "must be positive definite (smallest eigenvalue shown)",
            )));
        }
        let chol = match m.cholesky() {
            Some(c) => c,
            None => {
                return Err(Error::InvalidShape(ErrorDetail::new(
                    "P",
                    eig_min,
                    "must be positive definite (Cholesky factorisation failed)",
                )))
            }
        };
        let u = chol.l().transpose();
        let p_inv = chol.inverse();
        let p_inv = (p_inv + p_inv.transpose()) * 0.5;
        // Principal axes, longest first (smallest eigenvalue first).
        let (vectors, values) = principal(&m);
        let mut order = [0usize, 1, 2];
        order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
        let axes = Mat3::from_columns(&order.map(|i| vectors.column(i).into_owned()));
        let semi = Vec3::from(order.map(|i| 1.0 / values[i].sqrt()));
        Ok(Ellipsoid {
            p: m,
            u,
            p_inv,
            eig_min,
            eig_max,
            axes,
            semi,
        })
    }

    /// The principal directions (columns, body frame) and semi-axes, longest first.
    pub(crate) fn principal(&self) -> Option<(&Mat3, &Vec3)> {
        // The closed forms built on the axes need them to rounding: only for semi-axes finite,
        // positive and within 1e4 of each other (a fuzzed ellipsoid of condition 1e17 came out
        // with a NaN axis and a panic in `f64::clamp` downstream).
        let e = &self.semi;
        let usable = e.iter().all(|v| v.is_finite() && *v > 0.0) && e.x <= 1e4 * e.z;
        usable.then_some((&self.axes, &self.semi))
    }

    /// `P⁻¹` (body frame), when the ellipsoid is well enough conditioned for the closed forms
    /// (as [`Ellipsoid::principal`]).
    pub(crate) fn inverse(&self) -> Option<&Mat3> {
        self.principal().map(|_| &self.p_inv)
    }

    /// `U` with `P = UᵀU` (upper triangular: `b ↦ Ub` maps the ellipsoid onto the unit
    /// ball), when the ellipsoid is well conditioned (as [`Ellipsoid::principal`]).
    pub(crate) fn cholesky(&self) -> Option<&Mat3> {
        self.principal().map(|_| &self.u)
    }

    /// The (symmetrised) matrix `P`.
    pub fn matrix(&self) -> &Mat3 {
        &self.p
    }

    /// `∂h(m)/∂P` (nine entries, row-major) of `h(m) = √(mᵀP⁻¹m)`: with `g = P⁻¹m`,
    /// `dh = −gᵀ dP g/(2h)`. The matrix is symmetric, so this is also the derivative with
    /// respect to each entry as given, through the constructor's symmetrisation `(P + Pᵀ)/2`.
    pub(crate) fn support_gradient(&self, m: &Vec3, out: &mut [Real]) {
        let g = self.p_inv * m;
        let h = m.dot(&g).max(0.0).sqrt();
        if !(h > 0.0) {
            out[..9].fill(0.0);
            return;
        }
        let k = -0.5 / h;
        for i in 0..3 {
            for j in 0..3 {
                out[3 * i + j] = k * g[i] * g[j];
            }
        }
    }

    /// The rows' derivatives at `p`: the cone `[α; ℓ U u]` with `P = UᵀU` and `ℓ = 1/inv_scale`.
    /// Any `dU` with `dUᵀU + UᵀdU = dP` gives the same derivatives of the solution (two such
    /// choices differ by an infinitesimal rotation of the cone's coordinates, under which the
    /// program, its central path and its optimum are unchanged); `dU = ½U⁻ᵀdP` is the simplest:
    /// `Σ_r ∂s_r/∂P_ij = ½ℓ (U⁻¹W)_ij` with `W`'s row `r` the point of row `r + 1`, then
    /// symmetrised (the entries as given enter through `(P + Pᵀ)/2`).
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        let Some(u_inv) = self.u.try_inverse() else {
            return;
        };
        let w = Mat3::from_rows(&[p(1).u.transpose(), p(2).u.transpose(), p(3).u.transpose()]);
        let g = u_inv * w * (0.5 / inv_scale);
        for i in 0..3 {
            for j in 0..3 {
                out[3 * i + j] += 0.5 * (g[(i, j)] + g[(j, i)]);
            }
        }
    }

    /// `∂ρ/∂P` of the bounding radius `ρ = λ_min^(−1/2)`: the support function's derivative
    /// along the longest semi-axis (`ρ` is the largest `h(m)` over unit `m`).
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) {
        let axis = self.axes.column(0).into_owned();
        self.support_gradient(&axis, out);
    }

    pub(crate) fn bounding_radius(&self) -> Real {
        1.0 / self.eig_min.sqrt()
    }

    pub(crate) fn inscribed_radius(&self) -> Real {
        1.0 / self.eig_max.sqrt()
    }
}

impl SupportMap for Ellipsoid {
    #[inline]
    fn support(&self, m: &Vec3) -> (Vec3, u32) {
        (Round::Quadric(&self.p_inv).point(m), 0)
    }
    #[inline]
    fn piece(&self, id: u32, m: &Vec3) -> Option<PieceEval> {
        (id == 0).then(|| Round::Quadric(&self.p_inv).eval(&Vec3::zeros(), m))?
    }
    fn flat_face(&self, _m: &Vec3, _cos_min: Real) -> Option<Vec3> {
        None
    }
    fn gauge(&self, p: &Vec3) -> Real {
        p.dot(&(self.p * p)).max(0.0).sqrt()
    }
    fn normal_at(&self, _id: u32, p: &Vec3) -> Option<Vec3> {
        (self.p * p).try_normalize(0.0)
    }
    fn piece_count(&self) -> u32 {
        1
    }
}

impl ConicShape for Ellipsoid {
    fn lp_count(&self) -> usize {
        0
    }
    fn slack_count(&self) -> usize {
        0
    }
    fn rows(&self, inv_scale: Real, sink: &mut impl RowSink) {
        // ‖U u_world‖ ≤ α with u_world = u / inv_scale.
        let k = 1.0 / inv_scale;
        let u = &self.u;
        let r = |i: usize| [u[(i, 0)] * k, u[(i, 1)] * k, u[(i, 2)] * k];
        sink.soc(&[
            BodyRow::new([0.0; 3], 1.0, [0.0; 3]),
            BodyRow::new(r(0), 0.0, [0.0; 3]),
            BodyRow::new(r(1), 0.0, [0.0; 3]),
            BodyRow::new(r(2), 0.0, [0.0; 3]),
        ]);
    }
}

/// The eigenvectors (columns) and eigenvalues of a symmetric 3×3 matrix to rounding: nalgebra's
/// `symmetric_eigen`, then cyclic Jacobi rotations on `VᵀMV` until its off-diagonal entries are
/// below rounding of its diagonal. nalgebra's vectors alone left off-diagonal entries of 9e-9
/// on a matrix with well separated eigenvalues (an ellipsoid of the signed distance test), and
/// the depth of a sphere's centre in that ellipsoid came out 7e-10 too deep.
fn principal(m: &Mat3) -> (Mat3, [Real; 3]) {
    let se = m.symmetric_eigen();
    let mut v = se.eigenvectors;
    let mut b = v.transpose() * m * v;
    for _sweep in 0..8 {
        let scale = b[(0, 0)].abs() + b[(1, 1)].abs() + b[(2, 2)].abs();
        let off = b[(0, 1)].abs() + b[(0, 2)].abs() + b[(1, 2)].abs();
        if !(off > Real::EPSILON * 1e-2 * scale) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            let apq = b[(p, q)];
            if apq == 0.0 {
                continue;
            }
            // The rotation that zeroes b[p][q] (Golub and Van Loan, Algorithm 8.5.1).
            let tau = (b[(q, q)] - b[(p, p)]) / (2.0 * apq);
            let t = tau.signum() / (tau.abs() + (1.0 + tau * tau).sqrt());
            let c = 1.0 / (1.0 + t * t).sqrt();
            let s = t * c;
            let mut j = Mat3::identity();
            j[(p, p)] = c;
            j[(q, q)] = c;
            j[(p, q)] = s;
            j[(q, p)] = -s;
            b = j.transpose() * b * j;
            v *= j;
        }
    }
    (v, [b[(0, 0)], b[(1, 1)], b[(2, 2)]])
}

#[cfg(test)]
mod tests {
    use super::super::test_util::member;
    use super::*;

    #[test]
    fn membership_and_validation() {
        let e = Ellipsoid::new([[1.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 0.25]]).unwrap();
        assert!(member(&e, [0.99, 0.0, 0.0], 1.0, [0.0; 2]));
        assert!(!member(&e, [0.0, 0.51, 0.0], 1.0, [0.0; 2]));
        assert!(member(&e, [0.0, 0.0, 1.99], 1.0, [0.0; 2]));
        assert_eq!(e.bounding_radius(), 2.0);
        assert_eq!(e.inscribed_radius(), 0.5);
        assert!(Ellipsoid::new([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]]).is_err());
        assert!(Ellipsoid::new([[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]).is_err());
        assert!(Ellipsoid::new([[1.0, 0.0, 0.0], [0.0, f64::NAN, 0.0], [0.0, 0.0, 1.0]]).is_err());
    }

    #[test]
    fn principal_axes_diagonalise_p_to_rounding() {
        // The matrix on which nalgebra's vectors alone left an off-diagonal entry of 9e-9.
        let p = [
            [0.9160219655306415, 0.08549930004177712, 0.02265910076609414],
            [
                0.08549930004177712,
                1.0449348650399084,
                -0.011250653590834337,
            ],
            [
                0.02265910076609414,
                -0.011250653590834337,
                1.0853157811512821,
            ],
        ];
        let mut cases = vec![p, [[4.0, 1.0, 0.0], [1.0, 4.0, 0.0], [0.0, 0.0, 4.0]]];
        cases.push([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        for p in cases {
            let e = Ellipsoid::new(p).unwrap();
            let (axes, semi) = e.principal().unwrap();
            let m = Mat3::from_fn(|i, j| p[i][j]);
            let b = axes.transpose() * m * axes;
            let orth = (axes.transpose() * axes - Mat3::identity()).abs().max();
            assert!(orth < 1e-15, "{orth:e}");
            for i in 0..3 {
                let want = 1.0 / (semi[i] * semi[i]);
                assert!((b[(i, i)] - want).abs() < 1e-15 * want, "{b}");
                for j in 0..3 {
                    if i != j {
                        assert!(b[(i, j)].abs() < 1e-15, "off-diagonal {:e}", b[(i, j)]);
                    }
                }
            }
            assert!(semi[0] >= semi[1] && semi[1] >= semi[2]);
        }
    }
}
