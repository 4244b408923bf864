//! The solvers. The geometric ones know shapes only through their support maps
//! (`crate::shapes::SupportMap`): `direct` (Newton's method on the support function itself,
//! tried first on every pair with a curved shape), `raycast` (the certified ray cast of α* on
//! the Minkowski difference), `polish` (Newton on the contact features the cast identified,
//! certified again), `closed_form` (sphere and capsule pairs), `segment_solid` (a capsule
//! against a box, cylinder or cone), `ellipsoid_point` (a sphere and an ellipsoid),
//! `ellipsoid_pair` (two ellipsoids), `ellipsoid_rod` (an ellipsoid and a capsule or cylinder) and
//! `gjk` (the exact distance of separated shapes, certified, with its own Newton polish). The
//! interior-point method (`ipm/`, below) knows shapes only through the rows of a cone program.
//! None of them knows queries or the C ABI.
//!
//! # The interior-point method
//!
//! `ipm/`: the iteration loop (`ipm/mod.rs`), one iteration's directions (`ipm/step.rs`), the
//! final Newton polish (`ipm/polish.rs`), the second-order cone algebra ([`cones`]), the
//! normal equations and small dense factorisations ([`kkt`]) and the stopping settings
//! ([`Settings`]).

pub(crate) mod closed_form;
pub(crate) mod decision;
pub(crate) mod dense;
pub(crate) mod direct;
pub(crate) mod ellipsoid_pair;
pub(crate) mod ellipsoid_point;
pub(crate) mod ellipsoid_rod;
pub(crate) mod features;
pub(crate) mod gjk;
mod ipm;
pub(crate) mod polish;
pub(crate) mod raycast;
pub(crate) mod sat;
pub(crate) mod segment_solid;
pub(crate) mod sensitivity;
mod status;

pub use ipm::{cones, kkt};
pub use ipm::{
    LpRow, Outcome, Problem, Settings, SocBlock, Threshold, DEFAULT_MAX_ITERATIONS,
    DEFAULT_TOLERANCE, MAX_SOC, MAX_VARS,
};
pub use status::{DerivativeKind, Method, SolveStatus, Solver};
