//! The C ABI (`include/dcol.h`), the only place in the crate with `unsafe` code.
//!
//! One module per C type, in the style of rustls-ffi: [`status`] (`dcol_status`), [`info`] (its text, the
//! last error message, the version), [`shape`] (`dcol_shape` and its constructors), [`pose`] (`dcol_pose`),
//! [`options`] (`dcol_options`), [`cache`] (`dcol_cache`), [`proximity`] (`dcol_proximity_result`, `dcol_proximity`,
//! `dcol_gradient`, `dcol_jacobian` and their `_cached` forms), [`distance`] (`dcol_distance_result`, `dcol_distance`,
//! `dcol_distance_gradient`), [`contact`] (`dcol_contact`, `dcol_contacts`), [`early_exit`] (`dcol_alpha_below`, `dcol_intersect`),
//! [`derivatives`] (`dcol_derivatives_result`, `dcol_derivatives`, `dcol_gradient_mrp`,
//! `dcol_jacobian_mrp`), [`shape_gradient`] (`dcol_shape_parameter_count`,
//! `dcol_shape_parameters`, `dcol_shape_gradient`, `dcol_distance_shape_gradient`,
//! `dcol_signed_distance_shape_gradient`), [`batch`] (`dcol_proximity_batch`) and [`scene`] (`dcol_scene`,
//! `dcol_scene_pair`, `dcol_scene_stats` and the scene functions).
//! [`boundary`] holds the single panic boundary that wraps every exported body, the pointer
//! helpers and the per-thread error message.
//!
//! Rules every exported function keeps:
//! - every pointer argument is checked for NULL (`DCOL_ERROR_NULL_POINTER`);
//! - inputs are copied out of caller memory before they are validated and used;
//! - outputs are written only on success (and on `DCOL_ERROR_NOT_CONVERGED`, which carries the
//!   last iterate), except the constructors' `*out`, which is set to NULL on error;
//! - a panic never crosses the boundary: it becomes `DCOL_ERROR_INTERNAL`;
//! - a failure sets this thread's last error message, a sentence naming the argument and value;
//! - no query allocates on the heap (the message buffer is a fixed per-thread array).
//!
//! The header is generated from this module tree by cbindgen (see `build.rs`), so the doc
//! comments below are what C users read: they are kept in plain ASCII.

#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]
#![allow(non_camel_case_types)]

// Declared in the order of the header: cbindgen keeps source order. The blank lines stop
// rustfmt from sorting them.
pub mod status;

pub mod info;

pub mod shape;

pub mod pose;

pub mod options;

pub mod cache;

pub mod proximity;

pub mod distance;

pub mod contact;

pub mod early_exit;

pub mod derivatives;

pub mod shape_gradient;

pub mod batch;

pub mod scene;

pub mod boundary;

pub(crate) mod finite;

pub use batch::{dcol_proximity_batch, DCOL_BATCH_MAX_THREADS};
pub use contact::{dcol_contact, dcol_contacts, DCOL_MAX_CONTACTS};
pub use derivatives::{
    dcol_derivatives, dcol_derivatives_result, dcol_gradient_mrp, dcol_jacobian_mrp,
};
pub use distance::{
    dcol_distance, dcol_distance_gradient, dcol_distance_result, dcol_signed_distance,
    dcol_signed_distance_gradient, dcol_signed_distance_result,
};
pub use early_exit::{dcol_alpha_below, dcol_intersect};
pub use info::{dcol_last_error_message, dcol_status_string, dcol_version};
pub use options::{dcol_options, dcol_options_default};
pub use pose::dcol_pose;
pub use proximity::{
    dcol_gradient, dcol_jacobian, dcol_proximity, dcol_proximity_result, DCOL_DERIVATIVES_EXACT,
    DCOL_DERIVATIVES_NONE, DCOL_DERIVATIVES_SMOOTHED, DCOL_DERIVATIVES_SUBGRADIENT,
    DCOL_SOLVER_CLOSED_FORM, DCOL_SOLVER_INTERIOR_POINT, DCOL_SOLVER_POLISH, DCOL_SOLVER_RAY_CAST,
};
pub use scene::{
    dcol_scene, dcol_scene_add, dcol_scene_free, dcol_scene_new, dcol_scene_pair,
    dcol_scene_pairs_within, dcol_scene_set_pose, dcol_scene_size, dcol_scene_stats,
};
pub use shape::{
    dcol_shape, dcol_shape_free, dcol_shape_new_box, dcol_shape_new_capsule, dcol_shape_new_cone,
    dcol_shape_new_cylinder, dcol_shape_new_ellipsoid, dcol_shape_new_halfspace,
    dcol_shape_new_polygon, dcol_shape_new_polytope, dcol_shape_new_sphere,
};
pub use shape_gradient::{
    dcol_distance_shape_gradient, dcol_shape_gradient, dcol_shape_parameter_count,
    dcol_shape_parameters, dcol_signed_distance_shape_gradient,
};
pub use status::dcol_status;
