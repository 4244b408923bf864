//! Questions that need less than a full solve: "is α* below t?" (and its special case, "do the
//! shapes intersect?"), answered from closed-form bounds when they decide, and otherwise by an
//! interior-point solve that stops as soon as certified bounds on α* decide.
//!
//! - Bounds before any solve: with bounding radii ρᵢ and inscribed radii ιᵢ,
//!   `‖r₁ − r₂‖/(ρ₁ + ρ₂) ≤ α* ≤ ‖r₁ − r₂‖/(ι₁ + ι₂)` (equal for two spheres: the closed form).
//! - During the solve: the primal iterate is feasible from the start, so its objective is an
//!   upper bound; the dual objective corrected by the dual residual is a lower bound.

use super::context::{Options, Want};
use super::geometric::{self, Outcome};
use super::proximity::query_until;
use super::warm::Cache;
use crate::error::{Error, ErrorDetail};
use crate::math::{robust_norm, Pose, Real, Vec3};
use crate::shapes::{Shape, ShapeKind, SupportMap};
use crate::solver::decision::{boxes_below, sphere_below, Solid};
use crate::solver::{Method, SolveStatus};

/// What decided a threshold question.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecidedBy {
    /// The bounding/inscribed-sphere bracket, with no solve.
    Bounds,
    /// Certified primal or dual bounds part-way through the solve.
    EarlyExit,
    /// A complete solve (α* within the tolerance of the threshold).
    FullSolve,
    /// The pair's warm-start cache ([`crate::intersect_cached`]): the separating normal it kept
    /// still separates the shapes, proven by two support calls.
    Cache,
}

/// The answer to "is α* below the threshold?".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decision {
    /// True when α* < threshold.
    pub below: bool,
    /// How it was decided.
    pub decided_by: DecidedBy,
    /// Interior-point iterations used (0 when the bounds decided).
    pub iterations: u32,
    /// The solve's status: `Converged` whenever the answer is certain.
    pub status: SolveStatus,
}

/// A threshold on α* must be positive and finite.
pub(crate) fn check_threshold(threshold: Real) -> Result<(), Error> {
    if !threshold.is_finite() || threshold <= 0.0 {
        return Err(Error::InvalidOptions(ErrorDetail::new(
            "threshold",
            threshold,
            "must be positive and finite",
        )));
    }
    Ok(())
}

/// The closed-form bracket `[‖Δr‖/(ρ₁ + ρ₂), ‖Δr‖/(ι₁ + ι₂)]` on α*. With a half-space
/// (`ρ = ∞`, `ι = depth`) the lower bound is 0.
pub fn alpha_bounds(shape1: &Shape, pose1: &Pose, shape2: &Shape, pose2: &Pose) -> (Real, Real) {
    let d = robust_norm(&(pose2.position() - pose1.position()));
    (
        d / (shape1.bounding_radius() + shape2.bounding_radius()),
        d / (shape1.inscribed_radius() + shape2.inscribed_radius()),
    )
}

/// Is α* below `threshold` (> 0, finite)? Answers from the bounds when they decide, otherwise
/// stops the solve as soon as certified bounds do. Identical to `proximity(..).alpha <
/// threshold` outside a band of the solver tolerance around the threshold.
///
/// ```
/// use dcol::{alpha_below, Options, Pose, Shape};
/// let a = Shape::cuboid(1.0, 1.0, 1.0).unwrap();
/// let p1 = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
/// let p2 = Pose::from_position([2.5, 0.0, 0.0]).unwrap();
/// let d = alpha_below(&a, &p1, &a, &p2, 1.0, &Options::default()).unwrap();
/// assert!(!d.below); // α* = 1.25: separated
/// ```
pub fn alpha_below(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    threshold: Real,
    options: &Options,
) -> Result<Decision, Error> {
    check_threshold(threshold)?;
    options.validate()?;
    super::halfspace::check(shape1, shape2)?;
    let (lo, hi) = alpha_bounds(shape1, pose1, shape2, pose2);
    if hi < threshold || lo > threshold {
        return Ok(Decision {
            below: hi < threshold,
            decided_by: DecidedBy::Bounds,
            iterations: 0,
            status: SolveStatus::Converged,
        });
    }
    // The geometric path's decision straight, as the full query would take it (without its
    // derivatives' room, zeroed and copied: about a tenth of a closed form's time); the
    // coincident origins, half-spaces and every fallback go through the full query.
    let bounded = shape1.solver_kind() != ShapeKind::Halfspace
        && shape2.solver_kind() != ShapeKind::Halfspace;
    if options.method == Method::Auto && bounded {
        if let Some(below) = closed_decision(shape1, pose1, shape2, pose2, threshold) {
            return Ok(Decision {
                below,
                decided_by: DecidedBy::EarlyExit,
                iterations: 0,
                status: SolveStatus::Converged,
            });
        }
        let dist = robust_norm(&(pose2.position() - pose1.position()));
        if dist > 0.0 && dist.is_finite() {
            let stop = Some((threshold, true));
            match geometric::proximity(shape1, pose1, shape2, pose2, options, dist, stop, None) {
                Outcome::Decided { below, .. } => {
                    return Ok(Decision {
                        below,
                        decided_by: DecidedBy::EarlyExit,
                        iterations: 0,
                        status: SolveStatus::Converged,
                    })
                }
                Outcome::Answer(prox, _) => {
                    return Ok(Decision {
                        below: prox.alpha < threshold,
                        decided_by: DecidedBy::FullSolve,
                        iterations: prox.iterations,
                        status: prox.status,
                    })
                }
                Outcome::Fallback => {}
            }
        }
    }
    let f = query_until(
        shape1,
        pose1,
        shape2,
        pose2,
        options,
        Want::Proximity,
        Some((threshold, true)),
    )?;
    Ok(match f.decided {
        Some(below) => Decision {
            below,
            decided_by: DecidedBy::EarlyExit,
            iterations: f.prox.iterations,
            status: SolveStatus::Converged,
        },
        None => Decision {
            below: f.prox.alpha < threshold,
            decided_by: DecidedBy::FullSolve,
            iterations: f.prox.iterations,
            status: f.prox.status,
        },
    })
}

/// The decision of a sphere against a box, a capsule or a cylinder (either order), or of two
/// boxes, without α* (`crate::solver::decision`); `None` for other pairs or where the
/// decision is left open (a number on the way not finite, nearly parallel box edges).
#[inline]
fn closed_decision(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    threshold: Real,
) -> Option<bool> {
    let (ball, centre, solid, pose) = match (shape1.solver_kind(), shape2.solver_kind()) {
        (ShapeKind::Sphere, ShapeKind::Sphere) => return None,
        (ShapeKind::Sphere, _) => (shape1, pose1, shape2, pose2),
        (_, ShapeKind::Sphere) => (shape2, pose2, shape1, pose1),
        _ => {
            let (ea, eb) = (shape1.centred_box()?, shape2.centred_box()?);
            let c = pose1.rotation().tr_mul(pose2.rotation());
            let d = pose1
                .rotation()
                .tr_mul(&(pose2.position() - pose1.position()));
            return boxes_below(&ea, &eb, &c, &d, threshold);
        }
    };
    let rho = ball.rounded_segment()?.1;
    let kind = if let Some(half) = solid.centred_box() {
        Solid::Box(half)
    } else if let Some((half, radius)) = solid.rounded_segment() {
        Solid::Segment { half, radius }
    } else if let Some((radius, half)) = solid.cylinder_dims() {
        Solid::Cylinder { radius, half }
    } else {
        return None;
    };
    let p = pose
        .rotation()
        .tr_mul(&(centre.position() - pose.position()));
    sphere_below(&p, threshold, rho, kind)
}

/// Do the shapes intersect (α* < 1)? [`alpha_below`] with threshold 1.
pub fn intersect(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
) -> Result<Decision, Error> {
    alpha_below(shape1, pose1, shape2, pose2, 1.0, options)
}

/// A warm answer decides only this far (relative) from the threshold: 16 times the solver
/// tolerance (at least 1e-12). Nearer it the cold answer is the one given, so that a cached
/// decision is the cold one even where the cold path's own α* (certified to the tolerance, a
/// fraction of this band) could fall on either side.
fn band(options: &Options) -> Real {
    (16.0 * options.tolerance).max(1e-12)
}

/// The lower bound on α* that the unit normal `n` (from shape 1 to shape 2) gives:
/// `n·(r₂ − r₁)/(h₁(n) + h₂(−n))` with the support functions about the shapes' origins (scaled
/// by anything below it, the shapes lie on either side of a plane of normal `n`). Zero or NaN
/// when it bounds nothing.
fn alpha_along(shapes: [&Shape; 2], poses: [&Pose; 2], n: &Vec3) -> Real {
    let h = |i: usize, m: Vec3| {
        let rot = poses[i].rotation();
        let (p, _) = shapes[i].support(&rot.tr_mul(&m));
        m.dot(&(rot * p))
    };
    let den = h(0, *n) + h(1, -n);
    let num = n.dot(&(poses[1].position() - poses[0].position()));
    if den > 0.0 && den.is_finite() {
        num / den
    } else {
        0.0
    }
}

/// [`intersect`] with the pair's warm-start cache (`crate::intersect_cached`): the cold path's
/// bounds, then the kept separating normal's bound, then the geometric path with the cache
/// (between polytopes its kept facet of K), then the cold path; the cache keeps a separating
/// normal of shapes found apart. The same decision as [`intersect`].
pub(crate) fn intersect_warm(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<Decision, Error> {
    options.validate()?;
    super::halfspace::check(shape1, shape2)?;
    let bounded = shape1.solver_kind() != ShapeKind::Halfspace
        && shape2.solver_kind() != ShapeKind::Halfspace;
    if !(options.method == Method::Auto && bounded) {
        // The interior-point method asked for, or a half-space: the cold answer, nothing kept.
        return intersect(shape1, pose1, shape2, pose2, options);
    }
    let (shapes, poses) = ([shape1, shape2], [pose1, pose2]);
    let quick = |below: bool, decided_by: DecidedBy| Decision {
        below,
        decided_by,
        iterations: 0,
        status: SolveStatus::Converged,
    };
    let dist = robust_norm(&(pose2.position() - pose1.position()));
    let (lo, hi) = alpha_bounds(shape1, pose1, shape2, pose2);
    if hi < 1.0 || lo > 1.0 {
        // The cold path's own first answer, as cheap as any: the cache is left as it is (its
        // writes cost 1.7 times a bounds answer between spheres, for no later gain).
        return Ok(quick(hi < 1.0, DecidedBy::Bounds));
    }
    let margin = band(options);
    if let Some(n) = cache.separating() {
        let apart = alpha_along(shapes, poses, &n) > 1.0 + margin;
        cache.separating_tried(apart);
        if apart {
            return Ok(quick(false, DecidedBy::Cache));
        }
    }
    if dist > 0.0 && dist.is_finite() {
        let stop = Some((1.0, true));
        match geometric::proximity(
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            dist,
            stop,
            Some(cache),
        ) {
            Outcome::Decided { below, normal, .. } => {
                cache.keep_separating((!below).then_some(&normal));
                return Ok(quick(below, DecidedBy::EarlyExit));
            }
            Outcome::Answer(prox, dalpha_dd) => {
                let below = prox.alpha < 1.0;
                cache.keep_separating((!below).then_some(&dalpha_dd));
                if (prox.alpha - 1.0).abs() <= margin {
                    // Within the band the cold path's own answer (the cache's facet is as
                    // certain, but may land on the other side of a threshold both brackets
                    // contain).
                    return intersect(shape1, pose1, shape2, pose2, options);
                }
                return Ok(Decision {
                    below,
                    decided_by: DecidedBy::FullSolve,
                    iterations: prox.iterations,
                    status: prox.status,
                });
            }
            Outcome::Fallback => {}
        }
    }
    cache.keep_separating(None);
    intersect(shape1, pose1, shape2, pose2, options)
}
