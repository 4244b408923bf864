//! The reduced KKT system: the dense normal matrix `H = Gᵀ W⁻² G` of order `N` and its
//! square-root-free Cholesky factorisation `H = L D Lᵀ`, on the stack.

use crate::math::Real;

/// Rounding level of a Cholesky pivot, relative to the diagonal entry it is measured against.
const PIVOT_FLOOR: Real = 1e-14;

/// What a small Cholesky pivot is measured against (see [`Normal::factor`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PivotFloor {
    /// `1e-14 · max_i H_ii`: every pivot of a nearly singular matrix is regularised.
    Largest,
    /// `1e-14 · H_jj` (its own diagonal entry): only pivots at the rounding level of their own
    /// Schur complement are raised.
    Own,
}

/// A symmetric positive definite matrix of order `N` and its factor `L D Lᵀ` (`L` unit lower
/// triangular, `D` diagonal: a Cholesky factorisation without square roots, which would sit on
/// the critical path of every iteration).
#[derive(Clone, Copy, Debug)]
pub struct Normal<const N: usize> {
    /// Lower triangle holds H before `factor` and the strictly lower part of L after.
    a: [[Real; N]; N],
    /// `1/D[i]` after `factor`, so that solves multiply instead of dividing.
    inv_diag: [Real; N],
    /// See [`Normal::has_weak_pivot`].
    weak: bool,
}

impl<const N: usize> Normal<N> {
    /// A zero matrix.
    pub fn zeros() -> Self {
        Normal {
            a: [[0.0; N]; N],
            inv_diag: [0.0; N],
            weak: false,
        }
    }

    /// `H += k g gᵀ` (lower triangle).
    #[inline]
    pub fn add_rank1(&mut self, k: Real, g: &[Real; N]) {
        let n = N;
        for i in 0..n {
            let kg = k * g[i];
            // Rows of larger problems are sparse (another shape's slack columns); skipping
            // their zeros pays, while for four dense columns the test costs more than it saves.
            if N > 4 && kg == 0.0 {
                continue;
            }
            let row = &mut self.a[i];
            for j in 0..=i {
                row[j] += kg * g[j];
            }
        }
    }

    /// `H += k M` for a symmetric `M` stored fully.
    pub fn add_scaled(&mut self, k: Real, m: &[[Real; N]; N]) {
        let n = N;
        for i in 0..n {
            for j in 0..=i {
                self.a[i][j] += k * m[i][j];
            }
        }
    }

    /// `L D Lᵀ` factorisation in place. A pivot `D[j]` not above the floor is raised to it: a
    /// static regularisation that keeps the direction a descent direction. With
    /// [`PivotFloor::Largest`] the floor is `1e-14 · max_i H_ii`; with [`PivotFloor::Own`] it
    /// is `1e-14 · H_jj`, and [`Normal::has_weak_pivot`] then tells whether a pivot was kept
    /// that the `Largest` floor would have raised. Near convergence an active constraint's
    /// weight `λ/s` grows like `1/μ`, so the `Largest` floor soon swamps the O(1) pivot of a
    /// weakly curved direction (the tangent plane of a distance); the `Own` floor keeps it,
    /// but a pivot of a direction that is singular at the solution (a parallel contact) is
    /// then left at the rounding level, so a direction solved with it must be checked. Returns
    /// false when the matrix has non-finite entries or no positive diagonal at all.
    pub fn factor(&mut self, floor: PivotFloor) -> bool {
        let n = N;
        let mut dmax: Real = 0.0;
        for i in 0..n {
            let d = self.a[i][i];
            if !d.is_finite() {
                return false;
            }
            dmax = dmax.max(d);
        }
        if dmax <= 0.0 {
            return false;
        }
        let largest = PIVOT_FLOOR * dmax;
        self.weak = false;
        // D (only `1/D` is kept for the solves).
        let mut diag = [0.0; N];
        for j in 0..n {
            // Column j's diagonal is still the original entry here (step k writes column k).
            let own = self.a[j][j];
            let floor = match floor {
                PivotFloor::Own if own > 0.0 => PIVOT_FLOOR * own,
                _ => largest,
            };
            // w_k = L[j][k] D[k]; D[j] = H_jj − Σ L[j][k] w_k.
            let mut w = [0.0; N];
            let mut d = own;
            for k in 0..j {
                w[k] = self.a[j][k] * diag[k];
                d -= self.a[j][k] * w[k];
            }
            if !(d > floor) {
                d = floor;
            }
            self.weak |= d <= largest;
            diag[j] = d;
            let inv = 1.0 / d;
            self.inv_diag[j] = inv;
            for i in (j + 1)..n {
                let mut v = self.a[i][j];
                for k in 0..j {
                    v -= self.a[i][k] * w[k];
                }
                self.a[i][j] = v * inv;
            }
        }
        true
    }

    /// After [`Normal::factor`] with [`PivotFloor::Own`]: whether a pivot at or below
    /// `1e-14 · max_i H_ii` was kept (the factor then differs from the `Largest` one).
    pub fn has_weak_pivot(&self) -> bool {
        self.weak
    }

    /// Solves `H x = b` in place with the factor from [`Normal::factor`].
    pub fn solve(&self, b: &mut [Real; N]) {
        let n = N;
        for i in 0..n {
            let mut v = b[i];
            for k in 0..i {
                v -= self.a[i][k] * b[k];
            }
            b[i] = v;
        }
        for i in 0..n {
            b[i] *= self.inv_diag[i];
        }
        for i in (0..n).rev() {
            let mut v = b[i];
            for k in (i + 1)..n {
                v -= self.a[k][i] * b[k];
            }
            b[i] = v;
        }
    }
}

/// An LU factorisation with partial pivoting of a dense `N×N` matrix.
#[derive(Clone, Copy, Debug)]
pub struct Lu<const N: usize> {
    a: [[Real; N]; N],
    perm: [usize; N],
}

impl<const N: usize> Lu<N> {
    /// Factors `m`; `None` when a pivot is zero or not finite.
    pub fn factor(mut m: [[Real; N]; N]) -> Option<Self> {
        let mut perm = [0usize; N];
        for (i, p) in perm.iter_mut().enumerate() {
            *p = i;
        }
        for k in 0..N {
            let mut p = k;
            for i in (k + 1)..N {
                if m[i][k].abs() > m[p][k].abs() {
                    p = i;
                }
            }
            let piv = m[p][k];
            if !(piv.abs() > 0.0) || !piv.is_finite() {
                return None;
            }
            m.swap(k, p);
            perm.swap(k, p);
            for i in (k + 1)..N {
                let f = m[i][k] / piv;
                m[i][k] = f;
                if f == 0.0 {
                    continue;
                }
                for j in (k + 1)..N {
                    m[i][j] -= f * m[k][j];
                }
            }
        }
        Some(Lu { a: m, perm })
    }

    /// Solves `m x = b`.
    pub fn solve(&self, b: &[Real; N]) -> [Real; N] {
        let mut x = [0.0; N];
        for i in 0..N {
            x[i] = b[self.perm[i]];
        }
        for i in 0..N {
            for k in 0..i {
                x[i] -= self.a[i][k] * x[k];
            }
        }
        for i in (0..N).rev() {
            for k in (i + 1)..N {
                x[i] -= self.a[i][k] * x[k];
            }
            x[i] /= self.a[i][i];
        }
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_spd_system() {
        let mut h = Normal::<3>::zeros();
        let rows = [
            [2.0, 1.0, 0.0],
            [1.0, 3.0, 1.0],
            [0.0, 1.0, 4.0],
            [1.0, 1.0, 1.0],
        ];
        for r in rows {
            h.add_rank1(1.0, &r);
        }
        let mut full = [[0.0; 3]; 3];
        for r in rows {
            for i in 0..3 {
                for j in 0..3 {
                    full[i][j] += r[i] * r[j];
                }
            }
        }
        assert!(h.factor(PivotFloor::Own));
        let x = [1.0, -2.0, 0.5];
        let mut b = [0.0; 3];
        for i in 0..3 {
            b[i] = (0..3).map(|j| full[i][j] * x[j]).sum();
        }
        h.solve(&mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-13);
        }
    }

    #[test]
    fn lu_solves_nonsymmetric_system() {
        let a = [[0.0, 2.0, 1.0], [1.0, -1.0, 0.0], [3.0, 0.5, 4.0]];
        let m = a;
        let x = [1.0, 2.0, -3.0];
        let mut b = [0.0; 3];
        for i in 0..3 {
            b[i] = (0..3).map(|j| a[i][j] * x[j]).sum();
        }
        let got = Lu::factor(m).unwrap().solve(&b);
        for i in 0..3 {
            assert!((got[i] - x[i]).abs() < 1e-14);
        }
    }
}
