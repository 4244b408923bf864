//! Exact Euclidean distance between the unscaled shapes. Under `Method::Auto` separated pairs
//! are answered first by GJK on the support maps with a certificate (`super::separated`,
//! `crate::solver::gjk`); touching, overlapping and uncertified pairs (and every pair under
//! `Method::InteriorPoint`) by its own small cone program solved by the same interior-point
//! method:
//!
//! `minimise t  over y₁, y₂, t (and the shapes' slacks)  s.t.  ‖y₁ − y₂‖ ≤ t,  yᵢ ∈ Sᵢ(1)`.
//!
//! Coordinates are normalised as for proximity (origin at `r₁`, lengths over `ℓ`), and each
//! point is a variable in its own shape's body axes, `yᵢ = cᵢ + Qᵢuᵢ`: the shape's rows keep
//! their body-frame coefficients and the rotations appear only in the distance cone
//! `(t, Q₁u₁ − Q₂u₂ − c₂)`. With the points in world axes, a thin shape's large coefficients
//! (a polytope 1e-3 thin has rows like `(n_x, n_y, 1000 n_z)`) were rotated into all three
//! columns of its point, and near the optimum the active rows' weights `λ/s ~ 1/μ` times those
//! coefficients left the normal equations too ill-conditioned to resolve the distance's
//! tangent directions (their pivots fell to the rounding level), so the dual residual grew
//! instead of converging. The start is strictly feasible: each `uᵢ = 0` (its shape's origin,
//! strictly inside), `t` above their distance. Overlapping or touching shapes drive `t*` to zero; a `t*` within the solver
//! tolerance of zero is reported as exactly 0 with both witness points at the midpoint of the
//! solver's `y₁*, y₂*` (a point in both shapes to that tolerance) and a zero normal.
//!
//! The gradient of `d*` for separated shapes comes from the Lagrangian exactly as for α*:
//! `∂d/∂rᵢ = vᵢ` and `∂d/∂q_k = −ℓ eᵢᵀ M_k vᵢ` with `vᵢ = Σ λ̄ a` over shape i's rows (`a`
//! the row's normal in world axes, `Qᵢ` times its body-frame coefficients) and
//! `eᵢ = Qᵢuᵢ* = (yᵢ* − rᵢ)/ℓ`.

use super::assemble::{add_shape, dispatch, Placement, Task};
use super::context::{Distance, DistancePath, Options};
use super::derivatives::{rotation_generators, row_ranges};
use super::dispatch::Stage;
use super::separated::Settled;
use super::warm::Cache;
use crate::error::{Error, ErrorDetail};
use crate::math::{robust_norm, Mat3, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape};
use crate::solver::{LpRow, Method, Problem, SolveStatus, Threshold};

/// The largest distance between the origins, relative to the larger bounding radius, that the
/// distance program accepts (its squared terms must stay finite).
pub const MAX_OFFSET_RATIO: Real = 1e100;

struct DistanceTask<'q> {
    shape1: &'q Shape,
    shape2: &'q Shape,
    pose1: &'q Pose,
    pose2: &'q Pose,
    options: &'q Options,
    ell: Real,
    place1: Placement,
    place2: Placement,
    /// Origin of shape 2 in solver coordinates, `(r₂ − r₁)/ℓ`.
    center2: Vec3,
    gradient: bool,
    /// Stop as soon as the distance is proven above this (world units).
    cutoff: Option<Real>,
}

impl Task for DistanceTask<'_> {
    type Output = (Distance, [Real; 14], bool);

    fn run<const N: usize>(self, rows: &mut [LpRow<N>]) -> Self::Output {
        let inv = 1.0 / self.ell;
        let t_col = 6;
        let mut problem = Problem::<N>::new(rows);
        problem.c[t_col] = 1.0;
        let next = add_shape(&mut problem, self.shape1, self.place1, inv, 0);
        add_shape(&mut problem, self.shape2, self.place2, inv, next);
        // ‖y₁ − y₂‖ ≤ t as the last cone, with yᵢ = cᵢ + Qᵢuᵢ:
        // s = (t, Q₁u₁ − Q₂u₂ − c₂) = h − G z.
        let (q1, q2) = (self.pose1.rotation(), self.pose2.rotation());
        let c2 = self.center2;
        let k = problem.n_soc;
        let cone = &mut problem.soc[k];
        cone.g = [[0.0; N]; 4];
        cone.h = [0.0; 4];
        cone.g[0][t_col] = -1.0;
        for j in 0..3 {
            cone.h[1 + j] = -c2[j];
            for col in 0..3 {
                cone.g[1 + j][col] = -q1[(j, col)];
                cone.g[1 + j][3 + col] = q2[(j, col)];
            }
        }
        problem.n_soc += 1;
        // Each uᵢ at its shape's origin (strictly inside), t above their distance.
        let mut z0 = [0.0; N];
        z0[t_col] = 1.1 * c2.norm() + 0.5;
        let mu0 = z0[t_col] / (problem.lp.len() + problem.n_soc) as Real;
        // ‖z*‖₁ ≤ 3(ρ₁' + ρ₂') + t* + slacks (‖uᵢ‖ ≤ ρᵢ', each slack at most its shape's
        // radius).
        let cutoff = self.cutoff.map(|d| {
            let r1 = self.shape1.bounding_radius() * inv;
            let r2 = self.shape2.bounding_radius() * inv;
            Threshold {
                value: d * inv,
                z_bound_abs: 5.0 * (r1 + r2),
                z_bound_rel: 1.0,
                stop_below: false,
            }
        });
        let outcome = problem.solve_until(&z0, mu0, self.options, cutoff);
        if outcome.decided == Some(false) {
            let nothing = Distance {
                distance: Real::INFINITY,
                closest1: Vec3::zeros(),
                closest2: Vec3::zeros(),
                normal: Vec3::zeros(),
                iterations: outcome.iterations,
                status: SolveStatus::Converged,
                path: DistancePath::InteriorPoint,
            };
            return (nothing, [0.0; 14], true);
        }
        let z = &outcome.z;
        let r1 = *self.pose1.position();
        // Offsets from each origin (solver units, world axes) and the points themselves.
        let e1 = q1 * Vec3::new(z[0], z[1], z[2]);
        let e2 = q2 * Vec3::new(z[3], z[4], z[5]);
        let y1 = e1;
        let y2 = c2 + e2;
        let t = z[t_col].max(0.0);
        let mut result = Distance {
            distance: t * self.ell,
            closest1: r1 + e1 * self.ell,
            closest2: self.pose2.position() + e2 * self.ell,
            normal: Vec3::zeros(),
            iterations: outcome.iterations,
            status: outcome.status,
            path: DistancePath::InteriorPoint,
        };
        let mut grad = [0.0; 14];
        let touching = t <= 10.0 * self.options.tolerance;
        if touching {
            let mid = r1 + (y1 + y2) * (0.5 * self.ell);
            result.distance = 0.0;
            result.closest1 = mid;
            result.closest2 = mid;
            return (result, grad, false);
        }
        // The normal from the distance cone's multiplier (polished): at the optimum λ₁ =
        // −λ₀ (y₁ − y₂)/‖y₁ − y₂‖, which stays accurate when the gap is tiny and y₂ − y₁ is
        // mostly rounding; the witness difference is the fallback.
        let lam = problem.soc[k].lam_polished;
        let from_dual = Vec3::new(lam[1], lam[2], lam[3]);
        let nd = from_dual.norm();
        if lam[0] > 0.0 && nd > 0.0 && nd.is_finite() {
            result.normal = from_dual / nd;
        } else {
            let diff = y2 - y1;
            let n2 = diff.norm();
            if n2 > 0.0 {
                result.normal = diff / n2;
            }
        }
        if self.gradient {
            let ranges = row_ranges(self.shape1, self.shape2);
            let gens = [
                rotation_generators(self.pose1),
                rotation_generators(self.pose2),
            ];
            let places = [&self.place1, &self.place2];
            let rotations = [q1, q2];
            let es = [e1, e2];
            for (i, r) in ranges.iter().enumerate() {
                let pc = places[i].point_col;
                // A row's normal in world axes: the body-frame row rotated by Qᵢ.
                let qi = rotations[i];
                let a = |g: &[Real; N]| qi * Vec3::new(-g[pc], -g[pc + 1], -g[pc + 2]);
                let mut v = Vec3::zeros();
                for row in &problem.lp[r.lp.clone()] {
                    v += a(&row.g) * row.lam_polished;
                }
                if let Some(kk) = r.soc {
                    let b = &problem.soc[kk];
                    for (gr, l) in b.g.iter().zip(b.lam_polished.iter()) {
                        v += a(gr) * *l;
                    }
                }
                let e = es[i];
                for j in 0..3 {
                    grad[7 * i + j] = v[j];
                }
                for kq in 0..4 {
                    grad[7 * i + 3 + kq] = -self.ell * e.dot(&(gens[i][kq] * v));
                }
            }
        }
        (result, grad, false)
    }
}

pub(crate) fn distance_query(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    gradient: bool,
) -> Result<(Distance, [Real; 14]), Error> {
    distance_query_until(shape1, pose1, shape2, pose2, options, gradient, None, None)
        .map(|(d, g, _)| (d, g))
}

/// [`distance_query`] starting from what `warm` kept of the pair's last distance (and keeping
/// this one).
pub(crate) fn distance_query_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    gradient: bool,
    warm: &mut Cache,
) -> Result<(Distance, [Real; 14]), Error> {
    distance_query_until(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        gradient,
        None,
        Some(warm),
    )
    .map(|(d, g, _)| (d, g))
}

/// [`distance_query`], stopping once the distance is proven above `cutoff`; the flag says so.
#[allow(clippy::too_many_arguments)]
fn distance_query_until(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    gradient: bool,
    cutoff: Option<Real>,
    mut warm: Option<&mut Cache>,
) -> Result<(Distance, [Real; 14], bool), Error> {
    options.validate()?;
    if let Some(pair) = super::halfspace::split(shape1, pose1, shape2, pose2)? {
        return pair.distance([shape1, shape2], gradient, cutoff);
    }
    let r1 = *pose1.position();
    let offset = pose2.position() - r1;
    let len = robust_norm(&offset);
    if !len.is_finite() {
        return Err(Error::InvalidPose(ErrorDetail::new(
            "position",
            Real::INFINITY,
            "the distance between the two origins overflows a double",
        )));
    }
    // Overlap certified without a solve: if the inscribed balls overlap, the point dividing
    // the offset in the ratio of the inscribed radii lies in both shapes.
    let (i1, i2) = (shape1.inscribed_radius(), shape2.inscribed_radius());
    if len < i1 + i2 {
        let w = r1 + offset * (i1 / (i1 + i2));
        return Ok((overlap(w, 0), [0.0; 14], false));
    }
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    let ratio = len / ell;
    if !(ratio <= MAX_OFFSET_RATIO) {
        return Err(Error::InvalidPose(ErrorDetail::new(
            "position",
            ratio,
            "puts the shapes more than 1e100 times their size apart, beyond what the distance \
             program can represent in double precision",
        )));
    }
    // Separated pairs: GJK with its certificate first (the gap however small, never 0);
    // before it, the closest features the pair's cache kept, where they still certify.
    let stages = super::dispatch::route(shape1, shape2).distance;
    if let Some(cache) = warm
        .as_deref_mut()
        .filter(|_| options.method == Method::Auto && stages.has(Stage::Warm))
    {
        if let Some(d) =
            cache.warm_distance([shape1, shape2], [pose1, pose2], ell, options.tolerance)
        {
            let g = if gradient {
                super::separated::witness_gradient(
                    &d.normal,
                    &d.closest1,
                    &d.closest2,
                    [shape1, shape2],
                    [pose1, pose2],
                )
            } else {
                [0.0; 14]
            };
            if g.iter().all(|v| v.is_finite()) {
                return Ok((d, g, false));
            }
        }
    }
    if options.method == Method::Auto {
        let sep = super::separated::separated(
            shape1,
            pose1,
            shape2,
            pose2,
            options.tolerance,
            ell,
            gradient,
            cutoff,
            None,
        );
        match sep {
            Settled::Apart(d, g, beyond) => {
                if let Some(cache) = warm {
                    let kept = (!beyond).then_some(&d);
                    cache.keep_distance([shape1, shape2], [pose1, pose2], ell, kept);
                }
                // As on the interior-point path: a gradient that overflows (a quaternion so
                // small that derivatives with respect to it are not representable) is an error,
                // or a numerical failure with zeros, never a non-finite number.
                let finite = g.iter().all(|v| v.is_finite());
                super::derivatives::check_representable(finite, pose1, pose2)?;
                if !finite {
                    let d = Distance {
                        status: SolveStatus::NumericalFailure,
                        ..d
                    };
                    return Ok((d, [0.0; 14], beyond));
                }
                return Ok((d, g, beyond));
            }
            Settled::Overlapping(w) => {
                let d = Distance {
                    path: DistancePath::Gjk,
                    ..overlap(w, 0)
                };
                return Ok((d, [0.0; 14], false));
            }
            Settled::Unsettled => {}
        }
        // Not certified separated: most such pairs overlap, which the geometric proximity
        // certifies in a microsecond (α* < 1 puts x* inside both shapes; the margin covers its
        // bracket, at most 1e-3 of the tolerance wide), where the distance program takes ten.
        let prox = super::proximity(shape1, pose1, shape2, pose2, options)?;
        if prox.status.is_converged() && prox.alpha * (1.0 + options.tolerance) < 1.0 {
            return Ok((overlap(prox.point, prox.iterations), [0.0; 14], false));
        }
    }
    let k1 = shape1.slack_count();
    let k2 = shape2.slack_count();
    let task = DistanceTask {
        shape1,
        shape2,
        pose1,
        pose2,
        options,
        ell,
        place1: Placement {
            rotation: Mat3::identity(),
            center: Vec3::zeros(),
            point_col: 0,
            alpha_col: None,
            slack_col: 7,
            slacks: k1,
        },
        place2: Placement {
            rotation: Mat3::identity(),
            center: Vec3::zeros(),
            point_col: 3,
            alpha_col: None,
            slack_col: 7 + k1,
            slacks: k2,
        },
        center2: offset / ell,
        gradient,
        cutoff,
    };
    let m = shape1.lp_count() + shape2.lp_count();
    let out = dispatch(7 + k1 + k2, m, task)
        .ok_or(Error::Internal("distance: variable count out of range"))?;
    super::derivatives::check_representable(out.1.iter().all(|v| v.is_finite()), pose1, pose2)?;
    if out.0.status.is_converged() || out.2 {
        return Ok(out);
    }
    // The distance program is degenerate at overlap (its optimum sits at the cone's apex); when
    // it did not converge, proximity certifies overlap: α* < 1 puts x* inside both shapes.
    let prox = super::proximity(shape1, pose1, shape2, pose2, options)?;
    if prox.status.is_converged() && prox.alpha < 1.0 {
        return Ok((
            overlap(prox.point, out.0.iterations + prox.iterations),
            [0.0; 14],
            false,
        ));
    }
    Ok(out)
}

/// Distance 0 with `w` (a point in both shapes) as both witnesses.
pub(super) fn overlap(w: Vec3, iterations: u32) -> Distance {
    Distance {
        distance: 0.0,
        closest1: w,
        closest2: w,
        normal: Vec3::zeros(),
        iterations,
        status: SolveStatus::Converged,
        path: DistancePath::InteriorPoint,
    }
}

/// Exact distance between the unscaled shapes, witness points and the unit normal from shape 1
/// to shape 2. Touching or overlapping shapes give distance 0 (status converged).
///
/// ```
/// use dcol::{distance, Options, Pose, Shape};
/// let a = Shape::sphere(1.0).unwrap();
/// let b = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([3.0, 0.0, 0.0]).unwrap();
/// let d = distance(&a, &pa, &b, &pb, &Options::default()).unwrap();
/// assert!((d.distance - 1.5).abs() < 1e-8);
/// assert!((d.normal.x - 1.0).abs() < 1e-8);
/// ```
pub fn distance(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Distance, Error> {
    distance_query(shape1, pose1, shape2, pose2, options, false).map(|(d, _)| d)
}

/// The distance and its gradient `∂d*/∂(r₁, q₁, r₂, q₂)` (14 numbers, `q` as given). For
/// touching or overlapping shapes the distance is 0 and the gradient is returned as zero (the
/// distance is not differentiable there; α* is the smooth measure to use).
pub fn distance_gradient(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<(Distance, [Real; 14]), Error> {
    distance_query(shape1, pose1, shape2, pose2, options, true)
}

/// The distance if it is at most `cutoff`, `None` when it is proven larger ("beyond d_max I only
/// need to know that"). Decided without a solve when `‖r₂ − r₁‖ − ρ₁ − ρ₂ > cutoff` (bounding
/// spheres), otherwise as soon as a certified lower bound on the distance exceeds `cutoff`
/// (GJK's slab gap, or the interior-point dual objective corrected by the dual residual).
/// `cutoff` must be ≥ 0 and finite.
///
/// ```
/// use dcol::{distance_within, Options, Pose, Shape};
/// let s = Shape::sphere(1.0).unwrap();
/// let a = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let far = Pose::from_position([10.0, 0.0, 0.0]).unwrap();
/// assert!(distance_within(&s, &a, &s, &far, 5.0, &Options::default()).unwrap().is_none());
/// let d = distance_within(&s, &a, &s, &far, 9.0, &Options::default()).unwrap().unwrap();
/// assert!((d.distance - 8.0).abs() < 1e-8);
/// ```
pub fn distance_within(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    cutoff: Real,
    options: &Options,
) -> Result<Option<Distance>, Error> {
    if !(cutoff >= 0.0 && cutoff.is_finite()) {
        return Err(Error::InvalidOptions(ErrorDetail::new(
            "cutoff",
            cutoff,
            "must be non-negative and finite",
        )));
    }
    options.validate()?;
    let gap = robust_norm(&(pose2.position() - pose1.position()))
        - shape1.bounding_radius()
        - shape2.bounding_radius();
    if gap > cutoff {
        return Ok(None);
    }
    let (d, _, beyond) = distance_query_until(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        false,
        Some(cutoff),
        None,
    )?;
    Ok(if beyond || d.distance > cutoff {
        None
    } else {
        Some(d)
    })
}
