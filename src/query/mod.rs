//! Queries between two posed shapes: proximity (α*, x*, contact points), its derivatives,
//! and the exact distance.

mod assemble;
mod ball_jacobian;
#[cfg(test)]
mod ball_jacobian_tests;
mod cached;
mod capsule_jacobian;
#[cfg(test)]
mod capsule_jacobian_tests;
pub(crate) mod closed_lane;
mod contact;
mod contact_box_lane;
mod contact_boxes;
mod contact_halfspace;
mod contact_reduce;
mod contact_sphere;
mod context;
mod cores;
mod derivatives;
mod differentiate;
mod dispatch;
mod distance;
mod early_exit;
mod edge_jacobian;
#[cfg(test)]
mod edge_jacobian_tests;
mod ellipsoid_jacobian;
#[cfg(test)]
mod ellipsoid_jacobian_tests;
mod face_jacobian;
#[cfg(test)]
mod fast_derivatives_tests;
#[cfg(test)]
mod flat_jacobian_tests;
mod geometric;
mod halfspace;
mod polytope_jacobian;
#[cfg(test)]
mod polytope_jacobian_tests;
mod proximity;
mod segment_jacobian;
#[cfg(test)]
mod segment_jacobian_tests;
mod separated;
mod shape_gradient;
mod shortcuts;
mod signed;
mod sphere_jacobian;
#[cfg(test)]
mod sphere_jacobian_tests;
#[cfg(test)]
mod structured_solve_tests;
#[cfg(test)]
mod test_support;
mod vertex_feature;
mod warm;
mod warm_contacts;
mod warm_distance;

pub use cached::{
    derivatives_cached, distance_cached, distance_gradient_cached, gradient_cached,
    intersect_cached, jacobian_cached, proximity_cached, Cache,
};
pub(crate) use contact::manifold;
pub use contact::{contact_manifold, Contact, Manifold, MAX_CONTACTS};
pub(crate) use contact_box_lane::box_contacts;
pub(crate) use context::Want;
pub use context::{Distance, DistancePath, Options, Proximity, SignedDistance};
pub(crate) use differentiate::derivatives_into;
pub use differentiate::{derivatives, gradient, gradient_mrp, jacobian, jacobian_mrp, Derivatives};
pub use distance::{distance, distance_gradient, distance_within};
pub(crate) use early_exit::check_threshold;
pub use early_exit::{alpha_below, alpha_bounds, intersect, DecidedBy, Decision};
pub(crate) use halfspace::check as check_halfspace_pair;
pub use proximity::proximity;
pub(crate) use proximity::{query_until, query_until_warm};
pub use shape_gradient::{distance_shape_gradient, shape_gradient, signed_distance_shape_gradient};
pub(crate) use signed::not_representable;
pub use signed::{signed_distance, signed_distance_gradient};
pub(crate) use warm_contacts::manifold_cached;
pub use warm_contacts::{contact_manifold_cached, signed_distance_cached};
