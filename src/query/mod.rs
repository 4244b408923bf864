//! Queries between two posed shapes: proximity (α*, x*, contact points), its derivatives,
//! and the exact distance.

mod assemble;
mod proximity;

pub use proximity::{proximity, Options, Proximity};
