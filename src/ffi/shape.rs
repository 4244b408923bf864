//! `dcol_shape`: the opaque shape handle, its constructors and `dcol_shape_free`.

use super::boundary::{catch, check_out, read_array, run, Failure};
use super::status::dcol_status;
use crate::error::{Error, ErrorDetail};
use crate::shapes::{Shape, MAX_FACETS, MAX_HULL_POINTS, MAX_POLYGON_EDGES};

/// An opaque, validated convex shape (body frame). Built by one of the dcol_shape_new_*
/// functions, released with dcol_shape_free. Immutable once built, so one shape may be used by
/// any number of threads at once and in any number of queries (also as both shapes of one).
pub struct dcol_shape {
    inner: Shape,
}

impl dcol_shape {
    /// The Rust shape behind the handle.
    pub fn shape(&self) -> &Shape {
        &self.inner
    }
}

/// Borrows the shape behind `ptr` after checking it for NULL.
///
/// # Safety
/// `ptr` must be NULL or a live pointer returned by a `dcol_shape_new_*` function, not freed
/// for the lifetime `'a`.
pub(crate) unsafe fn shape_ref<'a>(
    ptr: *const dcol_shape,
    name: &'static str,
) -> Result<&'a Shape, Failure> {
    if ptr.is_null() {
        return Err(Failure::Null(name));
    }
    // SAFETY: non-NULL; the caller guarantees it came from `Box::into_raw` in `finish` and is
    // still live. Shapes are immutable, so a shared reference is sound across threads.
    Ok(unsafe { &(*ptr).inner })
}

/// Runs a constructor body: checks `out`, builds, and stores the new handle or NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
unsafe fn construct(
    func: &'static str,
    out: *mut *mut dcol_shape,
    build: impl FnOnce() -> Result<Shape, Failure>,
) -> dcol_status {
    run(func, || {
        check_out(out, "out")?;
        let (handle, outcome) = match build() {
            Ok(shape) => (Box::into_raw(Box::new(dcol_shape { inner: shape })), Ok(())),
            Err(e) => (std::ptr::null_mut(), Err(e)),
        };
        // SAFETY: `out` is non-NULL (checked above) and valid for writes (caller's contract).
        unsafe { out.write(handle) };
        outcome
    })
}

/// A sphere of the given radius (> 0, finite).
///
/// On success *out receives a new shape owned by the caller (free it with dcol_shape_free);
/// on error *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_sphere(
    radius: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::sphere(radius).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_sphere", out, build) }
}

/// An ellipsoid { x : x^T P x <= 1 } (body frame): P is 3x3, row-major (9 doubles), symmetric positive
/// definite. On error *out is set to NULL.
///
/// # Safety
/// `P` must be NULL or point to 9 readable doubles; `out` must be NULL or valid for writing
/// one pointer.
#[no_mangle]
#[allow(non_snake_case)]
pub unsafe extern "C" fn dcol_shape_new_ellipsoid(
    P: *const f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || {
        // SAFETY: `P` is NULL-checked by `read_array` and points to 9 doubles.
        let p: [f64; 9] = unsafe { read_array(P, "P") }?;
        let rows = [[p[0], p[1], p[2]], [p[3], p[4], p[5]], [p[6], p[7], p[8]]];
        Shape::ellipsoid(rows).map_err(Failure::api)
    };
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_ellipsoid", out, build) }
}

/// Rejects a count above its maximum before any caller memory is read.
fn check_count(
    name: &'static str,
    m: usize,
    max: usize,
    rule: &'static str,
) -> Result<(), Failure> {
    if m > max {
        return Err(Failure::api(Error::InvalidShape(ErrorDetail::new(
            name, m as f64, rule,
        ))));
    }
    Ok(())
}

/// Copies `m` rows of `D` doubles from `ptr` into `dst`.
///
/// # Safety
/// `ptr` must point to `m * D` readable doubles; `m <= dst.len()`.
unsafe fn copy_rows<const D: usize>(ptr: *const f64, m: usize, dst: &mut [[f64; D]]) {
    for (i, row) in dst[..m].iter_mut().enumerate() {
        // SAFETY: `i < m`, and the caller guarantees `m * D` readable doubles at `ptr`;
        // `[f64; D]` has the alignment of `f64`.
        *row = unsafe { ptr.cast::<[f64; D]>().add(i).read() };
    }
}

/// Copies `m` doubles from `ptr` into `dst`.
///
/// # Safety
/// `ptr` must point to `m` readable doubles; `m <= dst.len()`.
unsafe fn copy_vec(ptr: *const f64, m: usize, dst: &mut [f64]) {
    for (i, v) in dst[..m].iter_mut().enumerate() {
        // SAFETY: `i < m` and the caller guarantees `m` readable doubles at `ptr`.
        *v = unsafe { ptr.add(i).read() };
    }
}

/// A bounded polytope { x : A x <= b } (body frame) with m facets: `A` is m x 3 row-major (3m doubles),
/// `b` has m entries, all > 0 (the origin is strictly inside). 1 <= m <= 1048576; redundant
/// rows are allowed. Construction takes O(m log m) time (the vertices are the facets of the
/// convex hull of the points a_i / b_i). On error *out is set to NULL.
///
/// # Safety
/// `A` must be NULL or point to 3m readable doubles, `b` NULL or m readable doubles; `out`
/// must be NULL or valid for writing one pointer.
#[no_mangle]
#[allow(non_snake_case)]
pub unsafe extern "C" fn dcol_shape_new_polytope(
    A: *const f64,
    b: *const f64,
    m: usize,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || {
        if A.is_null() {
            return Err(Failure::Null("A"));
        }
        if b.is_null() {
            return Err(Failure::Null("b"));
        }
        check_count("m", m, MAX_FACETS, "exceeds the maximum of 1048576 facets")?;
        let mut a_rows = vec![[0.0; 3]; m];
        let mut b_vec = vec![0.0; m];
        // SAFETY: both non-NULL (checked above), `m` rows allocated, and `A`, `b` hold 3m
        // and m doubles (contract).
        unsafe {
            copy_rows(A, m, &mut a_rows);
            copy_vec(b, m, &mut b_vec);
        }
        Shape::polytope(&a_rows, &b_vec).map_err(Failure::api)
    };
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_polytope", out, build) }
}

/// A box with the given half-extents (each > 0, finite): the polytope with rows +-e_i.
/// On error *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_box(
    half_x: f64,
    half_y: f64,
    half_z: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::cuboid(half_x, half_y, half_z).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_box", out, build) }
}

/// A capsule: the points within `radius` of the segment from -length/2 e_x to +length/2 e_x
/// (both > 0, finite). On error *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_capsule(
    radius: f64,
    length: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::capsule(radius, length).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_capsule", out, build) }
}

/// A cylinder of `radius` and `length` (both > 0, finite), axis e_x, flat ends at
/// x = +-length/2. On error *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_cylinder(
    radius: f64,
    length: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::cylinder(radius, length).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_cylinder", out, build) }
}

/// A cone of `height` H > 0 and `half_angle` beta in (0, pi/2) radians, axis e_x: apex at
/// -3H/4 e_x, base disc of radius H tan(beta) at +H/4 e_x (the origin is the centroid).
/// On error *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_cone(
    height: f64,
    half_angle: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::cone(height, half_angle).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_cone", out, build) }
}

/// A padded polygon: the points within `radius` (> 0) of the plane polygon
/// { (y, 0) : C y <= d } in the body x-y plane. `C` is m x 2 row-major (2m doubles), `d` has
/// m entries, all > 0, and the polygon is bounded. 1 <= m <= 256. On error *out is set to NULL.
///
/// # Safety
/// `C` must be NULL or point to 2m readable doubles, `d` NULL or m readable doubles; `out`
/// must be NULL or valid for writing one pointer.
#[no_mangle]
#[allow(non_snake_case)]
pub unsafe extern "C" fn dcol_shape_new_polygon(
    C: *const f64,
    d: *const f64,
    m: usize,
    radius: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || {
        let mut c_rows = [[0.0; 2]; MAX_POLYGON_EDGES];
        let mut d_vec = [0.0; MAX_POLYGON_EDGES];
        if C.is_null() {
            return Err(Failure::Null("C"));
        }
        if d.is_null() {
            return Err(Failure::Null("d"));
        }
        check_count(
            "m",
            m,
            MAX_POLYGON_EDGES,
            "exceeds the maximum of 256 edges for a polygon",
        )?;
        // SAFETY: both non-NULL (checked above), `m <= MAX_POLYGON_EDGES`, and `C`, `d` hold 2m
        // and m doubles (contract).
        unsafe {
            copy_rows(C, m, &mut c_rows);
            copy_vec(d, m, &mut d_vec);
        }
        Shape::polygon(&c_rows[..m], &d_vec[..m], radius).map_err(Failure::api)
    };
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_polygon", out, build) }
}

/// The convex hull of `n` points (body frame), padded by a ball of `radius`: the points within
/// `radius` (>= 0, finite; 0 is the hull itself) of the hull. `points` is n x 3 row-major (3n
/// doubles). Duplicate, interior and coplanar points are allowed. The points must be finite,
/// include four affinely independent ones (a flat set is a padded polygon), and surround the
/// origin strictly: otherwise DCOL_ERROR_INVALID_SHAPE, and the message gives the centroid of the
/// hull's corners (shift the points by minus it, and the pose by plus it turned by the
/// attitude). A collision margin, as Bullet's on its hulls, or a rounded box is `radius`.
/// 4 <= n <= 4194304; construction takes O(n log n) time (quickhull) and keeps the points
/// as given. On error *out is set to NULL.
///
/// # Safety
/// `points` must be NULL or point to 3n readable doubles; `out` must be NULL or valid for
/// writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_convex_hull(
    points: *const f64,
    n: usize,
    radius: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || {
        if n < 4 {
            return Err(Failure::api(Error::InvalidShape(ErrorDetail::new(
                "n",
                n as f64,
                "must be at least 4 (a hull needs four affinely independent points)",
            ))));
        }
        if points.is_null() {
            return Err(Failure::Null("points"));
        }
        check_count(
            "n",
            n,
            MAX_HULL_POINTS,
            "exceeds the maximum of 4194304 points",
        )?;
        let mut pts = vec![[0.0; 3]; n];
        // SAFETY: non-NULL (checked above), `n` rows allocated, and `points` holds 3n doubles
        // (contract).
        unsafe { copy_rows(points, n, &mut pts) };
        Shape::convex_hull(&pts, radius).map_err(Failure::api)
    };
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_convex_hull", out, build) }
}

/// A half-space { u : u_z <= depth } (body frame), depth > 0 and finite: outward normal +e_z
/// (body), boundary plane `depth` above the body origin. A floor whose top surface is z = 0 is
/// this shape at position (0, 0, -depth) with the identity attitude. Scaled by alpha about its
/// origin it is { u_z <= alpha*depth }, so alpha* against a half-space depends on depth
/// (distances and contacts do not). Every query between a half-space and another shape is a
/// closed form; a query between two half-spaces fails with DCOL_ERROR_INVALID_SHAPE. On error
/// *out is set to NULL.
///
/// # Safety
/// `out` must be NULL or valid for writing one pointer.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_new_halfspace(
    depth: f64,
    out: *mut *mut dcol_shape,
) -> dcol_status {
    let build = || Shape::halfspace(depth).map_err(Failure::api);
    // SAFETY: `out` is forwarded from this function's contract.
    unsafe { construct("dcol_shape_new_halfspace", out, build) }
}

/// Releases a shape made by a dcol_shape_new_* function. NULL is a no-op. The shape must not
/// be in use by another thread, and must not be used or freed again afterwards.
///
/// # Safety
/// `shape` must be NULL or a live pointer returned by a `dcol_shape_new_*` function.
#[no_mangle]
pub unsafe extern "C" fn dcol_shape_free(shape: *mut dcol_shape) {
    catch("dcol_shape_free", (), || {
        if !shape.is_null() {
            // SAFETY: the pointer came from `Box::into_raw` in `construct` and is live and
            // unshared (caller's contract), so ownership can be taken back exactly once.
            drop(unsafe { Box::from_raw(shape) });
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constructors_set_out_and_free() {
        let mut out: *mut dcol_shape = std::ptr::NonNull::dangling().as_ptr();
        // SAFETY: `out` is a valid local.
        let st = unsafe { dcol_shape_new_sphere(-1.0, &mut out) };
        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_SHAPE);
        assert!(out.is_null());
        // SAFETY: `out` is a valid local.
        let st = unsafe { dcol_shape_new_box(1.0, 2.0, 3.0, &mut out) };
        assert_eq!(st, dcol_status::DCOL_OK);
        assert!(!out.is_null());
        // SAFETY: `out` was just returned by a constructor.
        unsafe { dcol_shape_free(out) };
        // SAFETY: NULL is a no-op.
        unsafe { dcol_shape_free(std::ptr::null_mut()) };
        // SAFETY: NULL out is reported, nothing is written.
        let st = unsafe { dcol_shape_new_sphere(1.0, std::ptr::null_mut()) };
        assert_eq!(st, dcol_status::DCOL_ERROR_NULL_POINTER);
        let a = [1.0, 0.0, 0.0];
        let b = [1.0];
        let too_many = crate::shapes::MAX_FACETS + 1;
        // SAFETY: `a` has 3 doubles and `b` 1; m exceeds the maximum (MAX_FACETS) and is
        // rejected before any element is read.
        let st = unsafe { dcol_shape_new_polytope(a.as_ptr(), b.as_ptr(), too_many, &mut out) };
        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_SHAPE);
        assert!(out.is_null());
    }
}
