//! The full (unreduced) adjoint of the features' system, kept for the tests: the reduced
//! solve ([`super::Reduced`]) must give the same sensitivities.

use super::super::dense::{lu_factor_in_place, lu_solve_transposed4};
use super::super::features::Feature;
use super::Sensitivity;
use super::{assemble, Side, DIM};
use crate::math::{Mat3, Real, Vec3};

thread_local! {
    /// Makes [`super::sensitivity`] answer by the full system (this thread only).
    pub(crate) static DENSE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// The largest entry of the weighted Hessian `Σ λ_k H_k` (normalised) of the last reduced
    /// system formed: how much the rounding of the solves is amplified (a cylinder's or cone's
    /// rim seen nearly along its axis has a curvature ρ/‖m_yz‖).
    pub(crate) static LARGEST_HESSIAN: std::cell::Cell<Real> = const { std::cell::Cell::new(0.0) };
}

/// The outputs' sensitivities by the full system: factorised at `z`, then one transposed solve
/// with four right-hand sides (what [`super::sensitivity`] did before the reduced system);
/// `None` where the full system is singular.
pub(super) fn adjoint(
    sides: &[Side; 2],
    r: &Vec3,
    z: &[Real; DIM],
    axes: &[[Vec3; 4]; 2],
    round: [bool; 2],
) -> Option<Sensitivity> {
    let dim = 4 + sides[0].feature.unknowns() + sides[1].feature.unknowns();
    let mut lu = [[0.0; DIM]; DIM];
    assemble(sides, r, z, &mut lu);
    let ipiv = lu_factor_in_place(&mut lu, dim)?;
    let (lu, ipiv) = (&lu, &ipiv);
    let n = Vec3::new(z[0], z[1], z[2]);
    let mu = z[3];
    // Right-hand sides: e_μ and the rows of ∂a/∂z (a from shape 1's feature).
    let mut y = [[0.0; 4]; DIM];
    y[3][0] = 1.0;
    let s0 = &sides[0];
    let c = s0.col;
    let mut a = Vec3::zeros();
    match s0.feature {
        Feature::Pieces { count, .. } => {
            for k in 0..count {
                let (p, l) = (&s0.pieces[k], z[c + k]);
                a += p.grad * l;
                for i in 0..3 {
                    y[c + k][1 + i] = p.grad[i];
                    for j in 0..3 {
                        y[j][1 + i] += l * p.hess[(i, j)];
                    }
                }
            }
        }
        Feature::Disc { .. } => {
            let l = z[c];
            a = s0.pieces[0].grad * l;
            for i in 0..3 {
                y[c][1 + i] = s0.pieces[0].grad[i];
                y[c + 1][1 + i] = l * s0.tangents[0][i];
                y[c + 2][1 + i] = l * s0.tangents[1][i];
            }
        }
    }
    lu_solve_transposed4(lu, ipiv, dim, &mut y);
    // d(output) = −Yᵀ ∂F/∂p (+ the explicit change of a).
    let apply = |df: &[Real; DIM]| {
        let mut out = [0.0; 4];
        for (row, d) in y[..dim].iter().zip(&df[..dim]) {
            for o in 0..4 {
                out[o] -= row[o] * d;
            }
        }
        out
    };
    let mut dmu_dr = Vec3::zeros();
    let mut da_dr = Mat3::zeros();
    for j in 0..3 {
        let mut df = [0.0; DIM];
        df[j] = -mu;
        df[3] = n[j];
        let o = apply(&df);
        dmu_dr[j] = o[0];
        for i in 0..3 {
            da_dr[(i, j)] = o[1 + i];
        }
    }
    let mut dmu_dtheta = [0.0; 8];
    let mut da_dtheta = [Vec3::zeros(); 8];
    for (i, side) in sides.iter().enumerate() {
        if round[i] {
            continue;
        }
        for k in 0..4 {
            let w = axes[i][k];
            let wn = w.cross(&n);
            let mut df = [0.0; DIM];
            let mut explicit = Vec3::zeros();
            let c = side.col;
            match side.feature {
                Feature::Pieces { count, .. } => {
                    for q in 0..count {
                        let p = &side.pieces[q];
                        let dg = w.cross(&p.grad) - p.hess * wn;
                        explicit += dg * z[c + q];
                        if q > 0 {
                            df[c + q] = -(p.grad - side.pieces[0].grad).dot(&wn);
                        }
                    }
                }
                Feature::Disc { .. } => {
                    explicit = w.cross(&side.pieces[0].grad) * z[c];
                    df[c + 1] = -side.axes[0].dot(&wn);
                    df[c + 2] = -side.axes[1].dot(&wn);
                }
            }
            df[..3].copy_from_slice(explicit.as_slice());
            let o = apply(&df);
            dmu_dtheta[4 * i + k] = o[0];
            let own = if i == 0 { explicit } else { Vec3::zeros() };
            da_dtheta[4 * i + k] = Vec3::new(o[1], o[2], o[3]) + own;
        }
    }
    Some(Sensitivity {
        dmu_dr,
        da_dr,
        dmu_dtheta,
        da_dtheta,
        mu,
        a,
    })
}
