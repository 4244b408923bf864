//! `dcol_contact` and `dcol_contacts`: contact manifolds for rigid-body engines.

use super::boundary::{check_out, run, Failure};
use super::cache::{cache_mut, dcol_cache};
use super::options::dcol_options;
use super::pose::dcol_pose;
use super::proximity::{check_inputs, read_inputs};
use super::shape::dcol_shape;
use super::status::dcol_status;
use crate::math::Vec3;
use crate::query::{self, Contact};

/// One contact point of a manifold.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct dcol_contact {
    /// World point midway between the two surfaces.
    pub position: [f64; 3],
    /// Unit normal from shape 1 to shape 2 (world); the same for every point of a manifold.
    pub normal: [f64; 3],
    /// Penetration depth at this point: > 0 overlapping, < 0 separated (within the margin),
    /// minus the signed distance there. The surface points are position + depth/2 * normal
    /// (shape 1) and position - depth/2 * normal (shape 2).
    pub depth: f64,
}

impl From<&Contact> for dcol_contact {
    fn from(c: &Contact) -> Self {
        dcol_contact {
            position: [c.position.x, c.position.y, c.position.z],
            normal: [c.normal.x, c.normal.y, c.normal.z],
            depth: c.depth,
        }
    }
}

/// The most contacts one call of dcol_contacts reports.
pub const DCOL_MAX_CONTACTS: usize = 16;
const _: () = assert!(DCOL_MAX_CONTACTS == query::MAX_CONTACTS);

/// The contact manifold of two posed shapes: the points where their signed distance is at most
/// `margin` (finite, >= 0), one normal (the signed distance's, from shape 1 to shape 2) for
/// all of them. Face-to-face and segment-to-face contacts give the corners of the clipped
/// overlap (a cylinder's cap or a cone's base counts as a regular 12-gon); curved contacts
/// (spheres, ellipsoids, rims) give one point. At most min(capacity, DCOL_MAX_CONTACTS) points
/// are written, chosen as the deepest and those spanning the largest area; *count is set to
/// the number written (0 when the shapes are farther apart than the margin).
///
/// `options` may be NULL (defaults); `contacts` may be NULL when `capacity` is 0. Returns
/// DCOL_OK and fills contacts[0..*count] and *count; or DCOL_ERROR_NOT_CONVERGED (the signed
/// distance did not certify its answer) and fills them from the best answer found; or an error
/// status, the last error message set, and nothing written. Allocates as dcol_signed_distance
/// (at most once per thread).
///
/// # Safety
/// `shape1`, `shape2` must be NULL or live shapes; `pose1`, `pose2`, `options` NULL or valid;
/// `contacts` NULL or valid for writing `capacity` elements; `count` NULL or valid for writing
/// one size_t.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_contacts(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    margin: f64,
    options: *const dcol_options,
    contacts: *mut dcol_contact,
    capacity: usize,
    count: *mut usize,
) -> dcol_status {
    let args = (margin, contacts, capacity, count);
    // SAFETY: forwarded from this function's contract.
    unsafe {
        contacts_in(
            "dcol_contacts",
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            None,
            args,
        )
    }
}

/// dcol_contacts with a warm start from `cache`, the pair's dcol_cache (see dcol_cache): the
/// same points; a pair the last answer's separating normal still proves apart by more than the
/// margin is answered from it (two support calls). The cache then holds this answer.
///
/// # Safety
/// As dcol_contacts; `cache` NULL or valid for reads and writes.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn dcol_contacts_cached(
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    margin: f64,
    options: *const dcol_options,
    cache: *mut dcol_cache,
    contacts: *mut dcol_contact,
    capacity: usize,
    count: *mut usize,
) -> dcol_status {
    let args = (margin, contacts, capacity, count);
    let name = "dcol_contacts_cached";
    // SAFETY: forwarded from this function's contract.
    unsafe {
        contacts_in(
            name,
            shape1,
            pose1,
            shape2,
            pose2,
            options,
            Some(cache),
            args,
        )
    }
}

/// The body of dcol_contacts and dcol_contacts_cached (`cache`: `None` for the first);
/// `args`: the margin, the contacts buffer, its capacity and the count's place.
///
/// # Safety
/// As dcol_contacts; `cache` `Some` of NULL or a pointer valid for reads and writes.
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
unsafe fn contacts_in(
    name: &'static str,
    shape1: *const dcol_shape,
    pose1: *const dcol_pose,
    shape2: *const dcol_shape,
    pose2: *const dcol_pose,
    options: *const dcol_options,
    cache: Option<*mut dcol_cache>,
    (margin, contacts, capacity, count): (f64, *mut dcol_contact, usize, *mut usize),
) -> dcol_status {
    run(name, || {
        // SAFETY: forwarded from this function's contract.
        let shapes = unsafe { check_inputs(shape1, pose1, shape2, pose2) }?;
        if capacity > 0 {
            check_out(contacts, "contacts")?;
        }
        check_out(count, "count")?;
        // SAFETY: forwarded from this function's contract.
        let warm = unsafe { cache_mut(cache) }?;
        // SAFETY: forwarded from this function's contract; pose pointers are non-NULL.
        let q = unsafe { read_inputs(shapes, pose1, pose2, options) }?;
        let mut warm = warm;
        // Two boxes: their closed form's points written straight here, where it answers
        // (`query::box_contacts`: the same points as below, the cache updated alike).
        let (s1, p1, s2, p2) = (q.shape1, &q.pose1, q.shape2, &q.pose2);
        let lane = query::box_contacts(s1, p1, s2, p2, margin, capacity, warm.as_deref_mut(), {
            |i, p: &Vec3, n: &Vec3, depth| {
                let c = dcol_contact {
                    position: [p.x, p.y, p.z],
                    normal: [n.x, n.y, n.z],
                    depth,
                };
                debug_assert!(i < capacity);
                // SAFETY: `i` < the count written below, at most `capacity`; `contacts` is
                // non-NULL when capacity > 0 (checked) and valid for writing `capacity`
                // elements (contract).
                unsafe { contacts.add(i).write(c) };
            }
        });
        if let Some(k) = lane {
            // SAFETY: `count` is non-NULL (checked) and valid for writes (contract).
            unsafe { count.write(k) };
            return Ok(());
        }
        // Only the points leave: a pair apart by more than the margin need not know by how
        // much (`exact_distance` false).
        let mut m = query::Manifold::empty();
        let (s1, p1, s2, p2, o) = (q.shape1, &q.pose1, q.shape2, &q.pose2, &q.options);
        match warm {
            Some(c) => query::manifold_cached(s1, p1, s2, p2, margin, capacity, o, &mut m, c),
            None => query::manifold(s1, p1, s2, p2, margin, capacity, o, false, &mut m),
        }
        .map_err(Failure::api)?;
        for (i, c) in m.contacts().iter().enumerate() {
            // SAFETY: `i < m.len() <= capacity`; `contacts` is non-NULL when capacity > 0
            // (checked) and valid for writing `capacity` elements (contract).
            unsafe { contacts.add(i).write(c.into()) };
        }
        // SAFETY: `count` is non-NULL (checked) and valid for writes (contract).
        unsafe { count.write(m.len()) };
        q.outcome(m.status, m.iterations)
    })
}
