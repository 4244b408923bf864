//! # dcol
//!
//! Fast, differentiable collision detection between convex primitives, after DCOL (Tracy,
//! Howell, Manchester 2022): two shapes are scaled uniformly about their origins and the
//! smallest scale α* at which they touch is found by a small second-order cone program, solved
//! by an interior-point method written for these tiny problems (stack memory, fixed sizes).
//! α* > 1 means separated, α* < 1 interpenetrating.
//!
//! Geometry follows `CONVENTIONS.md`: quaternions `[w, x, y, z]` world-from-body, row-major
//! matrices, metres.
//!
//! ```
//! use dcol::{proximity, Options, Pose, Shape};
//! let boxed = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
//! let ball = Shape::sphere(0.5).unwrap();
//! let p1 = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
//! let p2 = Pose::from_position([2.0, 0.0, 0.0]).unwrap();
//! let prox = proximity(&boxed, &p1, &ball, &p2, &Options::default()).unwrap();
//! assert!((prox.alpha - 2.0).abs() < 1e-8);
//! ```

#![warn(missing_docs)]
#![deny(unsafe_code)]
// Numerical kernels index several fixed-size arrays in lockstep; index loops say that best.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is used on purpose: it is true when x is NaN, so NaN fails every such check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod batch;
pub mod error;
#[allow(unsafe_code)]
pub mod ffi;
pub mod math;
pub mod query;
pub mod scene;
pub mod shapes;
pub mod solver;

pub use error::{Error, ErrorDetail};
pub use math::{Pose, Real, Vec3};
pub use query::{
    alpha_below, alpha_bounds, contact_manifold, contact_manifold_cached, derivatives,
    derivatives_cached, distance, distance_cached, distance_gradient, distance_gradient_cached,
    distance_shape_gradient, distance_within, gradient, gradient_cached, gradient_mrp, intersect,
    intersect_cached, jacobian, jacobian_cached, jacobian_mrp, proximity, proximity_cached,
    shape_gradient, signed_distance, signed_distance_cached, signed_distance_gradient,
    signed_distance_shape_gradient, Cache, Contact, DecidedBy, Decision, Derivatives, Distance,
    DistancePath, Manifold, Options, Proximity, SignedDistance,
};
pub use shapes::{Shape, ShapeKind};
pub use solver::{DerivativeKind, Method, SolveStatus, Solver};

/// The README's Rust examples, compiled and run as doctests so they cannot rot.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
