//! Proximity: the smallest uniform scaling α* at which two shapes touch, the touching point x*,
//! and the contact points on each unscaled shape.
//!
//! The cone program is solved in a normalised frame: origin at `r₁`, lengths divided by
//! `ℓ = max(ρ₁, ρ₂)` (the larger bounding radius), and the offset `r₂ − r₁` stretched to length
//! `κ = (ρ₁ + ρ₂)/ℓ`. Because α* and `x* − r₁` are homogeneous of degree one in `r₂ − r₁`, the
//! answer is rescaled exactly, so α* keeps its full relative precision even when the origins
//! nearly coincide, and the normalised α' is ≥ 1 with a feasible start known in closed form
//! from the inscribed radii. A half-space (unbounded) stands in with its depth for `ρ` (α' may
//! then be below 1); it reaches this program only under `Method::InteriorPoint` or smoothing
//! (otherwise its pairs are closed forms, `super::halfspace`).

use super::assemble::{add_shape, dispatch, Placement, Task};
use super::context::{Context, Frame, Full, Options, Proximity, ShapeSink, Want};
use super::derivatives;
use super::geometric;
use super::warm::{Cache, Kind};
use crate::error::{Error, ErrorDetail};
use crate::math::{robust_norm, Pose, Real, Vec3};
use crate::shapes::{ConicShape, Shape, ShapeKind};
use crate::solver::{DerivativeKind, LpRow, Method, Problem, SolveStatus, Solver, Threshold};

struct ProximityTask<'q, 'r, 's> {
    ctx: Context<'q>,
    want: Want,
    /// Stop as soon as α* is proven above this (world) value, or below it when the flag is set.
    threshold: Option<(Real, bool)>,
    /// The central-path point at this barrier parameter instead of the optimum
    /// ([`Options::smoothing`]).
    central: Option<Real>,
    /// Where the derivatives with respect to the shapes' parameters go, when asked for.
    shape: Option<&'r mut ShapeSink<'s>>,
}

impl Task for ProximityTask<'_, '_, '_> {
    type Output = Full;

    fn run<const N: usize>(self, rows: &mut [LpRow<N>]) -> Full {
        let ctx = &self.ctx;
        let frame = &ctx.frame;
        let inv = ctx.inv_scale;
        let mut problem = Problem::<N>::new(rows);
        problem.c[3] = 1.0;
        let next = add_shape(&mut problem, ctx.shape1, ctx.place1, inv, 0);
        add_shape(&mut problem, ctx.shape2, ctx.place2, inv, next);
        // Feasible start: the point dividing the offset in the ratio of the inscribed radii
        // lies in both inscribed balls once α' ≥ κ/(ι₁' + ι₂').
        let i1 = ctx.shape1.inscribed_radius() * inv;
        let i2 = ctx.shape2.inscribed_radius() * inv;
        let alpha_in = frame.kappa / (i1 + i2);
        let mut z0 = [0.0; N];
        let xi = frame.delta * (i1 / (i1 + i2));
        z0[0] = xi.x;
        z0[1] = xi.y;
        z0[2] = xi.z;
        z0[3] = start_alpha_factor() * alpha_in;
        let mu0 = 10.0 * (z0[3] - 1.0).max(0.1) / (problem.lp.len() + problem.n_soc) as Real;
        // Threshold in solver units; ‖z*‖₁ ≤ N α' bounds the dual-residual term (every
        // component of z* is at most α' in magnitude in these coordinates).
        let threshold = self.threshold.map(|(t, stop_below)| Threshold {
            value: t / frame.alpha_factor(),
            z_bound_abs: 0.0,
            z_bound_rel: N as Real,
            stop_below,
        });
        let outcome = match self.central {
            Some(mu) => problem.solve_central(&z0, mu0, ctx.options, mu),
            None => problem.solve_until(&z0, mu0, ctx.options, threshold),
        };
        // Next to an active-set change the polished point is refined on its active set (rare;
        // see `derivatives::refine_solution`), and the answer is taken there.
        let refined = if outcome.decided.is_none() && self.central.is_none() {
            derivatives::refine_solution(ctx, &problem, &outcome)
        } else {
            derivatives::Refined::NONE
        };
        let z = refined.z().unwrap_or(&outcome.z);
        let r1 = *ctx.pose1.position();
        let r2 = *ctx.pose2.position();
        let answer = |z: &[Real; N], status| {
            let alpha_n = z[3];
            let xi = Vec3::new(z[0], z[1], z[2]);
            Proximity {
                alpha: alpha_n * frame.alpha_factor(),
                point: r1 + xi * frame.point_factor(),
                contact1: r1 + xi * (frame.ell / alpha_n),
                contact2: r2 + (xi - frame.delta) * (frame.ell / alpha_n),
                iterations: outcome.iterations,
                status,
                solver: Solver::InteriorPoint,
                derivatives: DerivativeKind::None,
            }
        };
        let mut prox = answer(z, outcome.status);
        let finite = |p: &Proximity| {
            p.alpha.is_finite()
                && [p.point, p.contact1, p.contact2]
                    .iter()
                    .all(|v| v.iter().all(|x| x.is_finite()))
        };
        if !outcome.status.is_converged() && outcome.decided.is_none() && !finite(&prox) {
            // The last iterate of a failed solve is not representable (it broke down, or its
            // α' overflows in the rescaling): the feasible start stands in for it, a point of
            // both scaled shapes at an α above α*, and the status says the solve failed.
            prox = answer(&z0, SolveStatus::NumericalFailure);
        }
        let mut full = Full {
            prox,
            gradient: [0.0; 14],
            jacobian: [[0.0; 14]; 4],
            decided: outcome.decided,
        };
        if outcome.decided.is_some() {
            return full;
        }
        if self.want >= Want::Gradient {
            let central = self.central.is_some();
            derivatives::compute(
                ctx, &problem, &outcome, &refined, self.want, central, &mut full,
            );
        }
        // Only with a representable answer (else the query fails or reports a numerical failure,
        // and the buffers are left alone).
        let representable =
            full.gradient.iter().all(|v| v.is_finite()) && full.prox.is_representable();
        if let Some(sink) = self.shape.filter(|_| representable) {
            let unique =
                derivatives::shape_gradient(ctx, &problem, &outcome, &refined, self.central, sink);
            // Not differentiable in a shape's parameters even where the pose derivatives are
            // (or are smoothed): a hull's coplanar or repeated corners.
            if !unique {
                full.prox.derivatives = DerivativeKind::Subgradient;
            }
        }
        full
    }
}

/// α' of the feasible start, relative to the inscribed-ball bound `κ/(ι₁' + ι₂')`.
const START_ALPHA_FACTOR: Real = 1.2;

#[cfg(test)]
thread_local! {
    /// Replaces [`START_ALPHA_FACTOR`] (this thread only), to test that the answer does not
    /// depend on the starting point.
    static TEST_START_ALPHA_FACTOR: std::cell::Cell<Real> =
        const { std::cell::Cell::new(START_ALPHA_FACTOR) };
}

#[inline]
fn start_alpha_factor() -> Real {
    #[cfg(test)]
    {
        TEST_START_ALPHA_FACTOR.with(|c| c.get())
    }
    #[cfg(not(test))]
    {
        START_ALPHA_FACTOR
    }
}

/// Solves the proximity problem and computes what `want` asks for. Never allocates when both
/// shapes have ≤ 32 orthant rows in total (otherwise a per-thread buffer, allocated once).
#[inline]
pub(crate) fn query(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
) -> Result<Full, Error> {
    query_until(shape1, pose1, shape2, pose2, options, want, None)
}

/// [`query`] that may stop early once α* is proven above `threshold.0` (or below it, when
/// `threshold.1`).
#[inline]
pub(crate) fn query_until(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
    threshold: Option<(Real, bool)>,
) -> Result<Full, Error> {
    query_full(
        shape1, pose1, shape2, pose2, options, want, threshold, None, None,
    )
}

/// [`query_until`] starting from what `warm` kept of the pair's last answer (and keeping this
/// one): the same answers.
#[allow(clippy::too_many_arguments)]
pub(crate) fn query_until_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
    threshold: Option<(Real, bool)>,
    warm: &mut Cache,
) -> Result<Full, Error> {
    query_full(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        want,
        threshold,
        None,
        Some(warm),
    )
}

/// [`query_until`] that also writes the derivatives of α* with respect to the shapes'
/// parameters into `sink` (with `want` at least [`Want::Gradient`]): by the envelope theorem
/// on the geometric answer's normal and contact points where those are unique, else from the
/// interior-point path's multipliers (or its central path's adjoint, with smoothing). A kind
/// of derivative that was `Exact` becomes `Subgradient` where a shape's derivative is not
/// unique (`crate::shapes::Shape::support_gradient`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn query_full(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
    threshold: Option<(Real, bool)>,
    sink: Option<&mut ShapeSink<'_>>,
    warm: Option<&mut Cache>,
) -> Result<Full, Error> {
    options.validate()?;
    // A half-space against anything: closed forms (two half-spaces: an error), or the cone
    // program when the options ask for the interior-point method or smoothing.
    let halfspace = super::halfspace::split(shape1, pose1, shape2, pose2)?;
    if let Some(pair) = &halfspace {
        if !pair.by_interior_point(options, threshold) {
            let mut full = pair.proximity(want)?;
            // Only a representable answer has shape derivatives (the buffers stay untouched).
            if let Some(sink) = sink.filter(|_| full.prox.is_representable()) {
                // ∂α*/∂r₂ is ñ = n*/h_K(n*) (zero where α* ≡ 0).
                let g = &full.gradient;
                let n = Vec3::new(g[7], g[8], g[9]);
                let p = &full.prox;
                let unique = geometric::support_gradients(
                    &n,
                    [&p.contact1, &p.contact2],
                    [shape1, shape2],
                    [pose1, pose2],
                    -p.alpha,
                    sink,
                );
                if !unique && p.derivatives == DerivativeKind::Exact {
                    full.prox.derivatives = DerivativeKind::Subgradient;
                }
            }
            return Ok(full);
        }
    }
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let offset = r2 - r1;
    let dist = robust_norm(&offset);
    if dist == 0.0 {
        let prox = Proximity {
            alpha: 0.0,
            point: r1,
            contact1: r1,
            contact2: r2,
            iterations: 0,
            status: SolveStatus::Converged,
            solver: Solver::ClosedForm,
            derivatives: DerivativeKind::None,
        };
        let mut full = Full {
            prox,
            gradient: [0.0; 14],
            jacobian: [[0.0; 14]; 4],
            decided: None,
        };
        if want >= Want::Gradient {
            derivatives::coincident(&mut full);
        }
        if let Some(sink) = sink {
            sink.zero([shape1, shape2]);
        }
        return Ok(full);
    }
    if !dist.is_finite() {
        return Err(Error::InvalidPose(ErrorDetail::new(
            "position",
            dist,
            "the distance between the two origins overflows a double",
        )));
    }
    // The geometric solvers answer α*, x*, the gradient and, where x* is unique and its
    // features' system regular, the Jacobian; elsewhere the interior-point solve answers
    // everything (its α* agrees with theirs to the solvers' rounding).
    // A smoothed answer is the interior-point method's; decisions against a threshold ignore
    // the smoothing.
    let smoothed = options.smoothing > 0.0 && threshold.is_none();
    if options.method == Method::Auto && !smoothed && halfspace.is_none() {
        match geometric::proximity(shape1, pose1, shape2, pose2, options, dist, threshold, warm) {
            geometric::Outcome::Answer(mut prox, dalpha_dd) => {
                let g = if want >= Want::Gradient {
                    geometric::gradient(&prox, &dalpha_dd, [shape1, shape2], pose1, pose2)
                } else {
                    [0.0; 14]
                };
                // As on the interior-point path: a gradient that overflows (a quaternion so
                // small that derivatives with respect to it, ~1/|q|, are not representable) is
                // an error or a numerical failure with zeros, never a different solve.
                let finite = g.iter().all(|v| v.is_finite());
                derivatives::check_representable(finite, pose1, pose2)?;
                if !finite {
                    let prox = Proximity {
                        status: SolveStatus::NumericalFailure,
                        ..prox
                    };
                    return Ok(Full {
                        prox,
                        gradient: [0.0; 14],
                        jacobian: [[0.0; 14]; 4],
                        decided: None,
                    });
                }
                let mut jacobian = [[0.0; 14]; 4];
                if want >= Want::Gradient {
                    // Flat against flat the exact derivatives do not exist: the interior-point
                    // path's smoothed ones answer (for the Jacobian, `geometric::jacobian` finds
                    // that itself).
                    let (shapes, poses) = ([shape1, shape2], [pose1, pose2]);
                    let exact = match want {
                        Want::Jacobian => {
                            let ell = shape1.bounding_radius().max(shape2.bounding_radius());
                            geometric::jacobian(&prox, &dalpha_dd, &g, shapes, poses)
                                .filter(|j| derivatives::consistent(j, &g, ell))
                                .map(|j| jacobian = j)
                                .is_some()
                        }
                        _ => geometric::unique_contact(&prox, &dalpha_dd, shapes, poses),
                    };
                    if !exact {
                        let fallback = (want == Want::Gradient).then_some((g, dalpha_dd));
                        return derivatives_by_ipm(
                            prox, fallback, shape1, pose1, shape2, pose2, options, want, sink,
                        );
                    }
                    prox.derivatives = DerivativeKind::Exact;
                    if let Some(sink) = sink.filter(|_| prox.is_representable()) {
                        let unique = geometric::support_gradients(
                            &dalpha_dd,
                            [&prox.contact1, &prox.contact2],
                            shapes,
                            poses,
                            -prox.alpha,
                            sink,
                        );
                        if !unique {
                            prox.derivatives = DerivativeKind::Subgradient;
                        }
                    }
                }
                return Ok(Full {
                    prox,
                    gradient: g,
                    jacobian,
                    decided: None,
                });
            }
            geometric::Outcome::Decided { below, alpha, .. } => {
                // Only the decision is used; the bound that made it stands in for α*.
                let prox = Proximity {
                    alpha,
                    point: r1,
                    contact1: r1,
                    contact2: r2,
                    iterations: 0,
                    status: SolveStatus::Converged,
                    solver: Solver::RayCast,
                    derivatives: DerivativeKind::None,
                };
                return Ok(Full {
                    prox,
                    gradient: [0.0; 14],
                    jacobian: [[0.0; 14]; 4],
                    decided: Some(below),
                });
            }
            geometric::Outcome::Fallback => {}
        }
    }
    query_ipm_until(shape1, pose1, shape2, pose2, options, want, threshold, sink)
}

/// The derivatives from the interior-point path where the geometric solution has none (x* not
/// unique), with the geometric answer itself (α*, x*, contacts, solver) kept, so that every
/// query reports the same proximity. If the interior-point solve does not converge, the
/// geometric `gradient` is returned when there is one (labelled a subgradient: the envelope
/// formula at the geometric contact point, one element of the generalised gradient), else the
/// interior-point result whole.
#[allow(clippy::too_many_arguments)]
fn derivatives_by_ipm(
    geometric: Proximity,
    gradient: Option<([Real; 14], Vec3)>,
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
    mut sink: Option<&mut ShapeSink<'_>>,
) -> Result<Full, Error> {
    let mut full = query_ipm_until(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        want,
        None,
        sink.as_deref_mut(),
    )?;
    if full.prox.status.is_converged() {
        full.prox = Proximity {
            derivatives: full.prox.derivatives,
            ..geometric
        };
    } else if let Some((g, dalpha_dd)) = gradient {
        full = Full {
            prox: Proximity {
                derivatives: DerivativeKind::Subgradient,
                ..geometric
            },
            gradient: g,
            jacobian: [[0.0; 14]; 4],
            decided: None,
        };
        if let Some(sink) = sink.filter(|_| full.prox.is_representable()) {
            // The envelope formula at the geometric contact points, as for the gradient.
            geometric::support_gradients(
                &dalpha_dd,
                [&full.prox.contact1, &full.prox.contact2],
                [shape1, shape2],
                [pose1, pose2],
                -full.prox.alpha,
                sink,
            );
        }
    }
    Ok(full)
}

/// The interior-point path of [`query_until`]: `r₂ ≠ r₁`, both finite.
#[allow(clippy::too_many_arguments)]
fn query_ipm_until(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    want: Want,
    threshold: Option<(Real, bool)>,
    sink: Option<&mut ShapeSink<'_>>,
) -> Result<Full, Error> {
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let offset = r2 - r1;
    let dist = robust_norm(&offset);
    // A half-space's frame radius is its depth (its bounding radius is infinite).
    let frame_radius = |s: &Shape| s.halfspace_depth().unwrap_or(s.bounding_radius());
    let (rho1, rho2) = (frame_radius(shape1), frame_radius(shape2));
    let ell = rho1.max(rho2);
    let inv = 1.0 / ell;
    let kappa = (rho1 + rho2) * inv;
    let frame = Frame {
        ell,
        dist,
        kappa,
        delta: offset / dist * kappa,
    };
    let k1 = shape1.slack_count();
    let k2 = shape2.slack_count();
    let ctx = Context {
        shape1,
        shape2,
        pose1,
        pose2,
        options,
        frame,
        place1: Placement {
            rotation: *pose1.rotation(),
            center: Vec3::zeros(),
            point_col: 0,
            alpha_col: Some(3),
            slack_col: 4,
            slacks: k1,
        },
        place2: Placement {
            rotation: *pose2.rotation(),
            center: frame.delta,
            point_col: 0,
            alpha_col: Some(3),
            slack_col: 4 + k1,
            slacks: k2,
        },
        inv_scale: inv,
    };
    let m = shape1.lp_count() + shape2.lp_count();
    let mut full = dispatch(
        4 + k1 + k2,
        m,
        ProximityTask {
            ctx,
            want,
            threshold,
            central: (options.smoothing > 0.0 && threshold.is_none()).then_some(options.smoothing),
            shape: sink,
        },
    )
    .ok_or(Error::Internal("proximity: variable count out of range"))?;
    if want >= Want::Gradient {
        // (The Jacobian is all zeros unless it was asked for.)
        let finite = full.gradient.iter().all(|v| v.is_finite())
            && (want < Want::Jacobian || full.jacobian.iter().flatten().all(|v| v.is_finite()));
        derivatives::check_representable(finite, pose1, pose2)?;
        if !finite {
            // No NaN or infinity leaves a query: derivatives that could not be computed are
            // reported as a numerical failure, with zeros in their place.
            full.prox.status = crate::solver::SolveStatus::NumericalFailure;
            full.gradient = [0.0; 14];
            full.jacobian = [[0.0; 14]; 4];
        }
    }
    Ok(full)
}

/// α*, x* and the contact points of two posed shapes.
///
/// ```
/// use dcol::{proximity, Options, Pose, Shape};
/// let a = Shape::sphere(1.0).unwrap();
/// let b = Shape::sphere(0.5).unwrap();
/// let pa = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let pb = Pose::from_position([3.0, 0.0, 0.0]).unwrap();
/// let p = proximity(&a, &pa, &b, &pb, &Options::default()).unwrap();
/// assert!((p.alpha - 2.0).abs() < 1e-9); // ‖r₁ − r₂‖/(R₁ + R₂)
/// assert!((p.contact1.x - 1.0).abs() < 1e-6);
/// ```
#[inline]
pub fn proximity(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Proximity, Error> {
    proximity_warm(shape1, pose1, shape2, pose2, options, None)
}

/// [`proximity`] starting from what `warm` kept of the pair's last answer (and keeping this
/// one): the same answer, certified the same way.
#[inline]
pub(crate) fn proximity_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    mut warm: Option<&mut Cache>,
) -> Result<Proximity, Error> {
    // The geometric answer straight, without the derivatives' room of the full query (its
    // zeroing and copies were about a tenth of a sphere–sphere call); anything else, and every
    // fallback, is the full query's.
    if let Some(dist) = plain_offset(shape1, pose1, shape2, pose2, options) {
        let outcome = geometric::proximity(
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            dist,
            None,
            warm.as_deref_mut(),
        );
        if let geometric::Outcome::Answer(prox, _) = outcome {
            return Ok(prox);
        }
    }
    if let Some(cache) = warm {
        cache.forget(Kind::Proximity);
    }
    query(shape1, pose1, shape2, pose2, options, Want::Proximity).map(|f| f.prox)
}

/// `‖r₂ − r₁‖` where the plain geometric path answers (default method, no smoothing, no
/// half-space, valid options, distinct and finite origins); `None` sends the caller to the
/// full query.
#[inline]
fn plain_offset(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Option<Real> {
    let plain = options.method == Method::Auto && options.smoothing == 0.0;
    let bounded = shape1.solver_kind() != ShapeKind::Halfspace
        && shape2.solver_kind() != ShapeKind::Halfspace;
    if !(plain && bounded && options.validate().is_ok()) {
        return None;
    }
    let dist = robust_norm(&(pose2.position() - pose1.position()));
    (dist > 0.0 && dist.is_finite()).then_some(dist)
}

/// The geometric answer with exact derivatives, without the full query's room (its zeroing
/// and the copies of the 4×14 Jacobian it carries were about a third of a sphere–sphere
/// gradient): the proximity answer, its gradient into `grad`, and the Jacobian into
/// `jacobian` when given (the buffers hold garbage when `None` is returned). `None` wherever
/// [`query_full`] would answer otherwise (another method, smoothing, a half-space, coincident
/// or overflowing origins, a geometric fallback, a gradient that overflows, derivatives that
/// are not exact): the caller then asks the full query, which gives the same answer.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn plain_derivatives(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    grad: &mut [Real; 14],
    jacobian: Option<&mut [[Real; 14]; 4]>,
    warm: Option<&mut Cache>,
) -> Option<Proximity> {
    let dist = plain_offset(shape1, pose1, shape2, pose2, options)?;
    let geometric::Outcome::Answer(mut prox, dalpha_dd) =
        geometric::proximity(shape1, pose1, shape2, pose2, options, dist, None, warm)
    else {
        return None;
    };
    let (shapes, poses) = ([shape1, shape2], [pose1, pose2]);
    *grad = geometric::gradient(&prox, &dalpha_dd, shapes, pose1, pose2);
    let g = &*grad;
    // One sum instead of fourteen tests: any infinity or NaN makes it non-finite (a finite
    // gradient whose sum overflows only sends the call to the full query, the same answer).
    if !g.iter().sum::<Real>().is_finite() {
        return None;
    }
    let exact = match jacobian {
        Some(out) => {
            let ell = shape1.bounding_radius().max(shape2.bounding_radius());
            // The closed forms hold the identities `consistent` checks by construction.
            match geometric::jacobian_into(&prox, &dalpha_dd, g, shapes, poses, out) {
                Some(geometric::Formed::Closed) => true,
                Some(geometric::Formed::Solved) => derivatives::consistent(out, g, ell),
                None => false,
            }
        }
        None => geometric::unique_contact(&prox, &dalpha_dd, shapes, poses),
    };
    if !exact {
        return None;
    }
    prox.derivatives = DerivativeKind::Exact;
    Some(prox)
}

#[cfg(test)]
mod tests {
    use super::TEST_START_ALPHA_FACTOR;
    use crate::{proximity, Options, Pose, Shape};

    /// Reference case `ref-cone-ellipsoid-010` (`../shared/reference`, values copied): a contact
    /// next to the cone's rim, where the cone's base row is weakly active (slack and multiplier
    /// both O(√μ) at the last iterate). The polished point alone depended on where the solve
    /// started (x* off by 1.5e-6·ℓ when started at 1.05× the inscribed bound instead of 1.2×);
    /// with the refinement on the active set every start gives the oracle's answer.
    #[test]
    fn answer_does_not_depend_on_the_starting_point() {
        let cone = Shape::cone(0.7708460389020768, 0.38196237303482544).unwrap();
        let ellipsoid = Shape::ellipsoid([
            [
                0.9174361468979626,
                -0.04793763438889435,
                0.0017659819775128053,
            ],
            [
                -0.04793763438889435,
                1.2104364125327358,
                -0.3372793768428028,
            ],
            [
                0.0017659819775128053,
                -0.3372793768428028,
                0.9411951215311882,
            ],
        ])
        .unwrap();
        let p1 = Pose::new(
            [-0.32440352918558135, 1.3786119087878013, 1.7778231336039605],
            [
                0.20162915161790956,
                0.12202188236894111,
                0.7980098172280561,
                0.5546500491739154,
            ],
        )
        .unwrap();
        let p2 = Pose::new(
            [0.4260713840311531, 2.3753717250567505, 1.3785067884219755],
            [
                0.9307566736168071,
                -0.03205737313432736,
                0.06115922564559505,
                0.3590597282680614,
            ],
        )
        .unwrap();
        let alpha_ref = 1.009004931098814;
        let x_ref = [-0.35419812194286243, 1.7179690456128716, 1.6387257406424003];
        let ell = cone.bounding_radius().max(ellipsoid.bounding_radius());
        /// Restores the default start when dropped, even if the solve panics.
        struct Restore;
        impl Drop for Restore {
            fn drop(&mut self) {
                TEST_START_ALPHA_FACTOR.with(|c| c.set(super::START_ALPHA_FACTOR));
            }
        }
        for factor in [1.05, 1.2, 1.5, 2.0, 4.0] {
            let _restore = Restore;
            TEST_START_ALPHA_FACTOR.with(|c| c.set(factor));
            let p = proximity(&cone, &p1, &ellipsoid, &p2, &Options::default()).unwrap();
            assert!(p.status.is_converged(), "start {factor}: {:?}", p.status);
            let ea = (p.alpha - alpha_ref).abs() / alpha_ref;
            let ex = ((p.point.x - x_ref[0]).powi(2)
                + (p.point.y - x_ref[1]).powi(2)
                + (p.point.z - x_ref[2]).powi(2))
            .sqrt()
                / ell;
            assert!(ea <= 1e-12, "start {factor}: alpha off by {ea:e}");
            assert!(ex <= 1e-9, "start {factor}: x off by {ex:e} l");
        }
    }
}
