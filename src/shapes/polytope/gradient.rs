//! A polytope's parameters `(A, b)` as given, and the derivatives of its support function and
//! of its rows with respect to them (`docs/derivatives.md`, "Derivatives with respect to the
//! shapes").
//!
//! The support function is the linear program `h(m) = max { m·x : A x ≤ b }`; at a support
//! point `x` its dual multipliers `λ ≥ 0` (`Aᵀλ = m` over the rows active at `x`) give, by the
//! envelope theorem on its Lagrangian `m·x − λᵀ(Ax − b)`, `∂h/∂b_i = λ_i` and
//! `∂h/∂A_ij = −λ_i x_j`. One active row (a facet), two (an edge) or three independent ones (a
//! simple corner) have one `λ`; more rows through one corner have many, and one of them is
//! returned (flagged).

use super::super::support::{multipliers, Active, SupportMap};
use super::super::RowPoint;
use super::{Polytope, ENUMERATE_MAX};
use crate::math::{Real, Vec3};

impl Polytope {
    /// `4m`: the rows of `A` (row-major), then `b`.
    pub(crate) fn parameter_count(&self) -> usize {
        4 * self.a.len()
    }

    /// Writes `A` (row-major) then `b`, as given.
    pub(crate) fn write_parameters(&self, out: &mut [Real]) {
        let m = self.a.len();
        for (i, row) in self.a.iter().enumerate() {
            out[3 * i..3 * i + 3].copy_from_slice(row);
        }
        out[3 * m..4 * m].copy_from_slice(&self.b);
    }

    /// `∂h(m)/∂(A, b)` at the support point `x` (body frame) into `out` (overwritten),
    /// from the multipliers of the rows active at `x` (within 1e-8 of their offsets, relative).
    /// False when they are not unique (more than three rows through a corner, or rows given
    /// twice), or when `x` is not on the boundary and the support corner stood in for it.
    pub(crate) fn support_gradient(&self, m: &Vec3, x: &Vec3, out: &mut [Real]) -> bool {
        let mut act = Active::new();
        self.active_rows(x, &mut act);
        let mut at = *x;
        let mut exact = true;
        if act.n == 0 {
            // Not on the boundary (it cannot be, to rounding): the support corner's rows.
            at = self.support(m).0;
            self.active_rows(&at, &mut act);
            exact = false;
        }
        // The multipliers of the unit normals n_i = a_i/‖a_i‖.
        let (mu, unique) = multipliers(&act.rows[..act.n], m, 3);
        let count = self.a.len();
        out[..4 * count].fill(0.0);
        for k in 0..act.n {
            let i = act.ids[k];
            let lam = mu[k] / Vec3::from(self.a[i]).norm();
            out[3 * count + i] = lam;
            for j in 0..3 {
                out[3 * i + j] = -lam * at[j];
            }
        }
        exact && unique && act.all
    }

    /// The rows active at `x` (within 1e-8 of their offsets, relative), into `act` (emptied).
    fn active_rows(&self, x: &Vec3, act: &mut Active) {
        act.n = 0;
        act.all = true;
        let xn = x.norm();
        if self.a.len() <= ENUMERATE_MAX {
            // Built from every triple of planes: the unit normals and offsets are the rows'.
            for (i, (nrm, o)) in self.normals.iter().zip(&self.offsets).enumerate() {
                if o - nrm.dot(x) <= 1e-8 * (o + xn) {
                    act.push(i, *nrm);
                }
            }
        } else {
            // Through the polar hull: its facets are the irredundant rows, in another order.
            for (i, (a, b)) in self.a.iter().zip(&self.b).enumerate() {
                let a = Vec3::from(*a);
                let k = a.norm();
                if b / k - a.dot(x) / k <= 1e-8 * (b / k + xn) {
                    act.push(i, a / k);
                }
            }
        }
    }

    /// The rows' derivatives at `p` (`shapes/parameters.rs`): row `i` is
    /// `α b_i·inv_scale − a_i·u`.
    pub(crate) fn row_gradient(
        &self,
        inv_scale: Real,
        p: impl Fn(usize) -> RowPoint,
        out: &mut [Real],
    ) {
        let m = self.a.len();
        for i in 0..m {
            let q = p(4 + i);
            out[3 * m + i] += inv_scale * q.a;
            for j in 0..3 {
                out[3 * i + j] -= q.u[j];
            }
        }
    }

    /// `∂ρ/∂(A, b)` of the bounding radius, the farthest corner's distance: the support
    /// function's derivative at that corner along its own direction.
    pub(crate) fn radius_gradient(&self, out: &mut [Real]) -> bool {
        let Some(v) = self
            .vertices
            .iter()
            .max_by(|a, b| a.norm_squared().total_cmp(&b.norm_squared()))
        else {
            return false;
        };
        self.support_gradient(&v.normalize(), v, out)
    }
}
