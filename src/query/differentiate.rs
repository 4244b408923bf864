//! The derivative queries: the gradient of α*, the Jacobian of (x*, α*), both with contact-point
//! Jacobians, and their forms over modified Rodrigues parameters. Each is one proximity solve
//! ([`super::proximity`]) asking for more outputs; the computation is in `derivatives/`.

use super::context::{Options, Proximity, Want};
use super::proximity::{plain_derivatives, query};
use super::warm::Cache;
use crate::error::Error;
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;

/// ∂α*/∂(r₁, q₁, r₂, q₂): 14 numbers, `q` as given (through the normalisation). By default
/// from the geometric solution by the envelope theorem where the contact points are unique
/// (`Proximity::derivatives` is then `Exact`), else the interior-point path's (`Smoothed`);
/// with `Options::smoothing`, the central path's. Costs little beyond [`super::proximity()`].
///
/// ```
/// use dcol::{gradient, Options, Pose, Shape};
/// let a = Shape::sphere(1.0).unwrap();
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([4.0, 0.0, 0.0]).unwrap();
/// let (prox, g) = gradient(&a, &pa, &a, &pb, &Options::default()).unwrap();
/// // α = ‖r₂ − r₁‖/2, so ∂α/∂r₂ = (1/2, 0, 0) and ∂α/∂r₁ = −(1/2, 0, 0).
/// assert!((prox.alpha - 2.0).abs() < 1e-9);
/// assert!((g[7] - 0.5).abs() < 1e-8 && (g[0] + 0.5).abs() < 1e-8);
/// ```
#[inline]
pub fn gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [Real; 14]), Error> {
    gradient_warm(shape1, pose1, shape2, pose2, options, None)
}

/// [`gradient`] starting from what `warm` kept of the pair's last answer (and keeping this one).
#[inline]
pub(crate) fn gradient_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    warm: Option<&mut Cache>,
) -> Result<(Proximity, [Real; 14]), Error> {
    let mut g = [0.0; 14];
    if let Some(p) = plain_derivatives(shape1, pose1, shape2, pose2, options, &mut g, None, warm) {
        return Ok((p, g));
    }
    let f = query(shape1, pose1, shape2, pose2, options, Want::Gradient)?;
    Ok((f.prox, f.gradient))
}

/// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂): 4×14, rows (x₁, x₂, x₃, α), by the implicit function theorem:
/// by default on the contact features of the geometric solution where x* is unique, else on
/// the interior-point solver's KKT conditions (barrier-smoothed where x* is not unique;
/// `Proximity::derivatives` says which).
#[inline]
pub fn jacobian(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Proximity, [[Real; 14]; 4]), Error> {
    jacobian_warm(shape1, pose1, shape2, pose2, options, None)
}

/// [`jacobian`] starting from what `warm` kept of the pair's last answer (and keeping this one).
#[inline]
pub(crate) fn jacobian_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    warm: Option<&mut Cache>,
) -> Result<(Proximity, [[Real; 14]; 4]), Error> {
    let (mut j, mut g) = ([[0.0; 14]; 4], [0.0; 14]);
    if let Some(p) = plain_derivatives(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        &mut g,
        Some(&mut j),
        warm,
    ) {
        return Ok((p, j));
    }
    let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
    Ok((f.prox, f.jacobian))
}

/// Everything differentiable about a proximity query, in one solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Derivatives {
    /// The proximity result.
    pub proximity: Proximity,
    /// ∂α*/∂(r₁, q₁, r₂, q₂).
    pub dalpha: [Real; 14],
    /// ∂(x*, α*)/∂(r₁, q₁, r₂, q₂), rows (x₁, x₂, x₃, α).
    pub jacobian: [[Real; 14]; 4],
    /// ∂p₁/∂(r₁, q₁, r₂, q₂) (3×14) for `p₁ = r₁ + (x* − r₁)/α*`; zero when α* = 0.
    pub dcontact1: [[Real; 14]; 3],
    /// ∂p₂/∂(r₁, q₁, r₂, q₂) (3×14); zero when α* = 0.
    pub dcontact2: [[Real; 14]; 3],
}

impl Default for Derivatives {
    /// Every number zero (room for the answer to be written over).
    fn default() -> Self {
        Self::ZERO
    }
}

impl Derivatives {
    /// Every number zero.
    const ZERO: Derivatives = Derivatives {
        proximity: Proximity::ZERO,
        dalpha: [0.0; 14],
        jacobian: [[0.0; 14]; 4],
        dcontact1: [[0.0; 14]; 3],
        dcontact2: [[0.0; 14]; 3],
    };
}

/// The Jacobian of (x*, α*) and, by the chain rule, of both contact points:
/// `∂pᵢ = ∂rᵢ + (∂x* − ∂rᵢ)/α* − (x* − rᵢ) ∂α*/α*²`.
#[inline]
pub fn derivatives(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Derivatives, Error> {
    derivatives_warm(shape1, pose1, shape2, pose2, options, None)
}

/// [`derivatives`] starting from what `warm` kept of the pair's last answer (and keeping this one).
#[inline]
pub(crate) fn derivatives_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    warm: Option<&mut Cache>,
) -> Result<Derivatives, Error> {
    let mut d = Derivatives::ZERO;
    derivatives_into(shape1, pose1, shape2, pose2, options, warm, &mut d)?;
    Ok(d)
}

/// [`derivatives_warm`] written into `out` in place (the C boundary's body: the answer's
/// ~1.3 kB is not moved through returns). `out` holds garbage when an error is returned.
#[inline]
pub(crate) fn derivatives_into(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    warm: Option<&mut Cache>,
    out: &mut Derivatives,
) -> Result<(), Error> {
    // The geometric answer where it has exact derivatives (no full query's room), else the
    // full query.
    out.proximity = match plain_derivatives(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        &mut out.dalpha,
        Some(&mut out.jacobian),
        warm,
    ) {
        Some(p) => p,
        None => {
            let f = query(shape1, pose1, shape2, pose2, options, Want::Jacobian)?;
            out.jacobian = f.jacobian;
            out.dalpha = f.gradient;
            f.prox
        }
    };
    let (alpha, point) = (out.proximity.alpha, out.proximity.point);
    if alpha > 0.0 {
        let j = &out.jacobian;
        let inv = 1.0 / alpha;
        let u = alpha_row_over_square(j, inv);
        contact_jacobian(j, &u, &point, inv, pose1.position(), 0, &mut out.dcontact1);
        contact_jacobian(j, &u, &point, inv, pose2.position(), 1, &mut out.dcontact2);
    } else {
        out.dcontact1 = [[0.0; 14]; 3];
        out.dcontact2 = [[0.0; 14]; 3];
    }
    Ok(())
}

/// `u = ∂α*·(1/α*)·(1/α*)`, per column, from the Jacobian's α row (`inv = 1/α*`): the part of
/// [`contact_jacobian`]'s second term shared by both contact points and all three rows.
#[inline]
fn alpha_row_over_square(j: &[[Real; 14]; 4], inv: Real) -> [Real; 14] {
    j[3].map(|v| v * inv * inv)
}

/// `∂pᵢ = ∂rᵢ + (∂x* − ∂rᵢ)/α* − (x* − rᵢ) ∂α*/α*²` for contact point `i` (α* > 0, `rᵢ` its
/// shape's position, `inv = 1/α*`, `u` [`alpha_row_over_square`]), from the Jacobian's rows,
/// into `out`. Off the three entries where `∂rᵢ` is 1 the formula's operations are
/// `J·(1/α*) − (x* − rᵢ)·u` (its zero terms dropped), a loop without a branch; the three are
/// written after it. `u` formed once saves two of the four products per entry (~100
/// instructions a call; the numbers move by rounding: the second term was
/// `((x* − rᵢ)·J_α·(1/α*))·(1/α*)`).
#[inline]
fn contact_jacobian(
    j: &[[Real; 14]; 4],
    u: &[Real; 14],
    point: &Vec3,
    inv: Real,
    r: &Vec3,
    i: usize,
    out: &mut [[Real; 14]; 3],
) {
    let rel = point - r;
    for (row, o) in out.iter_mut().enumerate() {
        let s = rel[row];
        for col in 0..14 {
            o[col] = j[row][col] * inv - s * u[col];
        }
        let col = 7 * i + row;
        o[col] = 1.0 + (j[row][col] - 1.0) * inv - s * u[col];
    }
}

/// Maps 14 quaternion-parameter columns to 12 MRP-parameter columns (`J_q · ∂q/∂p` per pose).
fn to_mrp_columns(row: &[Real; 14], mrp: [[Real; 3]; 2]) -> [Real; 12] {
    let mut out = [0.0; 12];
    for i in 0..2 {
        let dq = crate::math::mrp_quaternion_jacobian(mrp[i]);
        for j in 0..3 {
            out[6 * i + j] = row[7 * i + j];
        }
        for c in 0..3 {
            out[6 * i + 3 + c] = (0..4).map(|k| row[7 * i + 3 + k] * dq[k][c]).sum();
        }
    }
    out
}

/// ∂α*/∂(r₁, p₁, r₂, p₂) for attitudes given as modified Rodrigues parameters (12 numbers).
pub fn gradient_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [Real; 12]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, g) = gradient(shape1, &pose1, shape2, &pose2, options)?;
    Ok((p, to_mrp_columns(&g, [mrp1, mrp2])))
}

/// ∂(x*, α*)/∂(r₁, p₁, r₂, p₂), 4×12, for attitudes given as modified Rodrigues parameters.
pub fn jacobian_mrp(
    shape1: &Shape,
    position1: [Real; 3],
    mrp1: [Real; 3],
    shape2: &Shape,
    position2: [Real; 3],
    mrp2: [Real; 3],
    options: &Options,
) -> Result<(Proximity, [[Real; 12]; 4]), Error> {
    let pose1 = Pose::from_mrp(position1, mrp1)?;
    let pose2 = Pose::from_mrp(position2, mrp2)?;
    let (p, j) = jacobian(shape1, &pose1, shape2, &pose2, options)?;
    let mut out = [[0.0; 12]; 4];
    for r in 0..4 {
        out[r] = to_mrp_columns(&j[r], [mrp1, mrp2]);
    }
    Ok((p, out))
}

#[cfg(test)]
mod tests {
    use super::{alpha_row_over_square, contact_jacobian};
    use crate::math::{lcg, Vec3};

    /// The branch-free contact Jacobian against the formula as written,
    /// `∂rᵢ + (∂x* − ∂rᵢ)/α* − (x* − rᵢ) ∂α*/α*²` entry by entry: the same numbers (`==`, so
    /// up to the sign of a zero) on random Jacobians, points and α*.
    #[test]
    fn contact_jacobian_is_the_formula() {
        let mut g = lcg(0xC0A7);
        for _ in 0..2_000 {
            let mut j = [[0.0; 14]; 4];
            for v in j.iter_mut().flatten() {
                *v = g() * 10f64.powf(3.0 * g());
            }
            let point = Vec3::new(g(), g(), g()) * 3.0;
            let alpha = 0.05 + 2.0 * (g() + 1.0);
            for i in 0..2 {
                let r = Vec3::new(g(), g(), g());
                let mut out = [[f64::NAN; 14]; 3];
                let inv = 1.0 / alpha;
                let u = alpha_row_over_square(&j, inv);
                contact_jacobian(&j, &u, &point, inv, &r, i, &mut out);
                let rel = point - r;
                for row in 0..3 {
                    for col in 0..14 {
                        let dr = if col == 7 * i + row { 1.0 } else { 0.0 };
                        // The formula's operations, `u` shared: bit for bit.
                        let want = dr + (j[row][col] - dr) * inv - rel[row] * u[col];
                        assert_eq!(out[row][col], want, "i {i}, ({row}, {col})");
                        // The former order of the second term's products: the same within
                        // the rounding of its four operations (a few ulps of each term).
                        let (a, b) = ((j[row][col] - dr) * inv, rel[row] * j[3][col] * inv * inv);
                        let former = dr + a - b;
                        let ulps = 8.0 * f64::EPSILON * (dr + a.abs() + b.abs());
                        assert!(
                            (out[row][col] - former).abs() <= ulps,
                            "i {i}, ({row}, {col})"
                        );
                    }
                }
            }
        }
    }
}
