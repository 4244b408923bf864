//! Proximity on support maps: closed forms where the pair has one, else a ray cast (MPR) that
//! identifies the contact features and a Newton polish on them, each certified; `None` sends the
//! query to the interior-point solver.
//!
//! The frame is the interior-point path's: origin at `r₁`, lengths divided by `ℓ = max(ρ₁, ρ₂)`;
//! the ray is the unit vector `r = (r₂ − r₁)/‖r₂ − r₁‖`, and α* = α'·‖r₂ − r₁‖/ℓ with α' the
//! gauge of the normalised Minkowski difference at `r` (α* is homogeneous of degree one in the
//! offset, so no precision is lost at tiny or huge offsets).

use super::proximity::{Options, Proximity};
use crate::math::{Pose, Real, Vec3};
use crate::shapes::Shape;
use crate::solver::polish::{newton, snap_to_face};
use crate::solver::raycast::{cast, CastEnd, Pair, Posed};
use crate::solver::{SolveStatus, Solver};

/// Portal refinements before the polish takes over.
const CAST_BUDGET: u32 = 40;
/// Relative bracket at which a curved pair's cast hands over to the polish.
const HANDOVER: Real = 1e-5;
/// Portal refinements allowed after a failed polish, before the interior-point fallback.
const CAST_RESCUE: u32 = 200;
/// The certified bracket is closed to this fraction of the requested tolerance. The
/// interior-point solver's tolerance bounds its duality measure, and its polish lands about
/// three orders of magnitude below it; a bracket is the error bound itself, so it is closed as
/// far below to give the same accuracy for the same setting.
const MARGIN: Real = 1e-3;

/// The geometric answer in the normalised frame.
struct Answer {
    alpha: Real,
    /// Points of shape 1 and 2, relative to their origins (normalised units).
    a: Vec3,
    b: Vec3,
    solver: Solver,
}

/// Proximity by the geometric solvers, or `None` when they cannot certify the answer to the
/// requested tolerance (the caller then runs the interior-point solver). `dist = ‖r₂ − r₁‖ > 0`.
pub(crate) fn proximity(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    dist: Real,
) -> Option<Proximity> {
    let r1 = *pose1.position();
    let r2 = *pose2.position();
    let ray = (r2 - r1) / dist;
    let ell = shape1.bounding_radius().max(shape2.bounding_radius());
    let inv = 1.0 / ell;
    let iota = (shape1.inscribed_radius() + shape2.inscribed_radius()) * inv;
    let pair = Pair {
        one: Posed {
            shape: shape1,
            rot: pose1.rotation(),
            inv_scale: inv,
        },
        two: Posed {
            shape: shape2,
            rot: pose2.rotation(),
            inv_scale: inv,
        },
    };
    let ans = solve(&pair, &ray, iota, options.tolerance)?;
    // α* = α'·dist/ℓ; the touching point x* = r₁ + α*·ℓ·a; contact points r₁ + ℓa, r₂ + ℓb.
    let alpha = ans.alpha * (dist * inv);
    let contact1 = r1 + ans.a * ell;
    let contact2 = r2 + ans.b * ell;
    let point = r1 + ans.a * (alpha * ell);
    let finite = alpha.is_finite()
        && point.iter().all(|v| v.is_finite())
        && contact1.iter().all(|v| v.is_finite())
        && contact2.iter().all(|v| v.is_finite());
    finite.then_some(Proximity {
        alpha,
        point,
        contact1,
        contact2,
        iterations: 0,
        status: SolveStatus::Converged,
        solver: ans.solver,
    })
}

fn solve(pair: &Pair<'_, Shape>, ray: &Vec3, iota: Real, tolerance: Real) -> Option<Answer> {
    let tol = tolerance * MARGIN;
    let c = cast(pair, ray, tol.max(HANDOVER), CAST_BUDGET);
    // A portal in a flat face of K gives the exit point exactly; elsewhere a closed bracket
    // pins α' but not the point (the portal's vertices spread across a curved patch), so the
    // polish runs unless the requested tolerance is looser than the hand-over.
    if c.end == CastEnd::Flat || (tol >= HANDOVER && c.end == CastEnd::Closed) {
        let (a, b) = c.points();
        return Some(Answer {
            alpha: c.alpha_hi,
            a,
            b,
            solver: Solver::RayCast,
        });
    }
    if c.end == CastEnd::Degenerate {
        return None;
    }
    let polished =
        snap_to_face(pair, ray, &c.normal, iota, tol).or_else(|| newton(pair, ray, &c, iota, tol));
    if let Some(p) = polished {
        return Some(Answer {
            alpha: p.alpha_lo,
            a: p.a,
            b: p.b,
            solver: Solver::Polish,
        });
    }
    // The polish could not certify: refine the portal further.
    let c = cast(pair, ray, tol, CAST_RESCUE);
    (c.alpha_hi - c.alpha_lo <= tol * c.alpha_lo).then(|| {
        let (a, b) = c.points();
        Answer {
            alpha: c.alpha_hi,
            a,
            b,
            solver: Solver::RayCast,
        }
    })
}
