//! The solvers. Today one: [`ipm`](self#the-interior-point-method), a primal-dual
//! interior-point method for the small cone programs of DCOL. The solvers know shapes only
//! through the rows of a cone program; they know nothing of queries or of the C ABI.
//!
//! # The interior-point method
//!
//! `ipm/`: the iteration loop (`ipm/mod.rs`), one iteration's directions (`ipm/step.rs`), the
//! final Newton polish (`ipm/polish.rs`), the second-order cone algebra ([`cones`]), the
//! normal equations and small dense factorisations ([`kkt`]) and the stopping settings
//! ([`Settings`]).

mod ipm;
mod status;

pub use ipm::{cones, kkt};
pub use ipm::{
    LpRow, Outcome, Problem, Settings, SocBlock, Threshold, DEFAULT_MAX_ITERATIONS,
    DEFAULT_TOLERANCE, MAX_SOC, MAX_VARS,
};
pub use status::SolveStatus;
