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
use crate::error::{Error, ErrorDetail};
use crate::math::{robust_norm, Pose, Real};
use crate::shapes::{Shape, ShapeKind};
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
