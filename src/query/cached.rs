//! The queries with a per-pair warm-start [`Cache`] (`super::warm`): the same answers as the
//! plain queries, certified the same way, starting from the pair's last answer where the poses
//! moved little since.

use super::context::{Distance, Options, Proximity};
use super::differentiate::{derivatives_warm, gradient_warm, jacobian_warm, Derivatives};
use super::distance::distance_query_warm;
use super::early_exit::{intersect_warm, Decision};
use super::proximity::proximity_warm;
pub use super::warm::Cache;
use crate::error::Error;
use crate::math::{Pose, Real};
use crate::shapes::Shape;

/// [`crate::proximity`] with a warm start: keep one [`Cache`] per pair and pass it to every
/// query on that pair. The answer is certified exactly as a cold one (and agrees with it to
/// the solver's tolerance); the cache then holds this answer.
///
/// ```
/// use dcol::{proximity, proximity_cached, Cache, Options, Pose, Shape};
/// let (a, b) = (Shape::cuboid(0.5, 0.4, 0.3).unwrap(), Shape::cylinder(0.3, 0.8).unwrap());
/// let mut cache = Cache::new();
/// for k in 0..100 {
///     let t = k as f64 * 1e-3;
///     let pa = Pose::new([0.0, 0.0, 0.0], [1.0, 0.1 * t, 0.0, 0.0]).unwrap();
///     let pb = Pose::new([1.5 - t, 0.2, 0.1], [1.0, 0.0, 0.2, t]).unwrap();
///     let warm = proximity_cached(&a, &pa, &b, &pb, &Options::default(), &mut cache).unwrap();
///     let cold = proximity(&a, &pa, &b, &pb, &Options::default()).unwrap();
///     assert!((warm.alpha - cold.alpha).abs() <= 1e-12 * cold.alpha);
/// }
/// ```
#[inline]
pub fn proximity_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<Proximity, Error> {
    proximity_warm(shape1, pose1, shape2, pose2, options, Some(cache))
}

/// [`crate::gradient`] with a warm start (see [`proximity_cached`]).
#[inline]
pub fn gradient_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<(Proximity, [Real; 14]), Error> {
    gradient_warm(shape1, pose1, shape2, pose2, options, Some(cache))
}

/// [`crate::jacobian`] with a warm start (see [`proximity_cached`]).
#[inline]
pub fn jacobian_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<(Proximity, [[Real; 14]; 4]), Error> {
    jacobian_warm(shape1, pose1, shape2, pose2, options, Some(cache))
}

/// [`crate::derivatives`] with a warm start (see [`proximity_cached`]).
#[inline]
pub fn derivatives_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<Derivatives, Error> {
    derivatives_warm(shape1, pose1, shape2, pose2, options, Some(cache))
}

/// [`crate::distance`] with a warm start: between two polytopes, the closest features of the
/// pair's last answer, re-solved in closed form and certified as GJK's answer is (the same
/// distance to the tolerance); other pairs, and poses where the features changed, answer
/// cold. Keep one [`Cache`] per pair.
pub fn distance_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<Distance, Error> {
    distance_query_warm(shape1, pose1, shape2, pose2, options, false, cache).map(|(d, _)| d)
}

/// [`crate::distance_gradient`] with a warm start (see [`distance_cached`]).
pub fn distance_gradient_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<(Distance, [Real; 14]), Error> {
    distance_query_warm(shape1, pose1, shape2, pose2, options, true, cache)
}

/// [`crate::intersect`] with a warm start: keep one [`Cache`] per pair and pass it to every
/// query on that pair. A separating normal the cache kept that still separates the shapes (two
/// support calls) answers "apart" at once ([`crate::DecidedBy::Cache`]); between polytopes the
/// kept facet of K, re-solved in closed form and certified ([`proximity_cached`]), gives α*;
/// otherwise the cold query answers, and the cache keeps what it found (the separating normal
/// of shapes apart). The decision is always the cold one's: within 16 times the solver
/// tolerance of touching, where the cold path's own α* could fall on either side, the cold
/// query answers. `decided_by` and `iterations` say how this call decided.
///
/// ```
/// use dcol::{intersect, intersect_cached, Cache, Options, Pose, Shape};
/// let (a, b) = (Shape::cuboid(0.5, 0.4, 0.3).unwrap(), Shape::cylinder(0.3, 0.8).unwrap());
/// let mut cache = Cache::new();
/// for k in 0..100 {
///     let t = k as f64 * 1e-2;
///     let pa = Pose::new([0.0, 0.0, 0.0], [1.0, 0.1 * t, 0.0, 0.0]).unwrap();
///     let pb = Pose::new([1.5 - t, 0.2, 0.1], [1.0, 0.0, 0.2, t]).unwrap();
///     let warm = intersect_cached(&a, &pa, &b, &pb, &Options::default(), &mut cache).unwrap();
///     let cold = intersect(&a, &pa, &b, &pb, &Options::default()).unwrap();
///     assert_eq!(warm.below, cold.below);
/// }
/// ```
pub fn intersect_cached(
    shape1: &Shape,
    pose1: &Pose,
    shape2: &Shape,
    pose2: &Pose,
    options: &Options,
    cache: &mut Cache,
) -> Result<Decision, Error> {
    intersect_warm(shape1, pose1, shape2, pose2, options, cache)
}
