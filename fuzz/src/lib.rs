//! Fuzz targets for dcol, shared by the libFuzzer binaries (`fuzz_targets/`, run with
//! `cargo fuzz`) and the coverage-less stable driver (`examples/random_driver.rs`).
//!
//! Inputs are decoded by hand from the raw bytes ([`Bytes`]): each number is either one of a
//! table of special values (NaN, ±inf, ±0, subnormals, 1e±300, f64::MAX, π/2 and its
//! neighbours, ...), raw IEEE bits, or a "plausible" value (a few digits times 10^-6..10^6), so
//! that both the validation paths and the solver are reached.
//!
//! Invariants checked (a violation panics, which the fuzzer records as a crash):
//! - no panic inside dcol (Rust API and C ABI);
//! - any non-finite or non-positive size (or a half angle outside (0, π/2), an empty, oversized
//!   or mismatched facet list) is rejected, and every rejection is `Error::InvalidShape`;
//!   well-scaled spheres, capsules, cylinders, cones and boxes are accepted; an accepted shape
//!   has finite positive radii; the C constructors agree with the Rust ones;
//! - `Pose::new` accepts exactly the finite, non-zero quaternions with finite positions;
//!   rejections are `Error::InvalidPose`;
//! - queries with invalid options return `Error::InvalidOptions`; with valid options they return
//!   `Ok` except `Error::InvalidPose` when `r₂ − r₁` overflows; never `Error::Internal`;
//! - within the representable regime (radii in [1e-100, 1e100], positions and offsets within
//!   1e100 of the sizes, see `queries`), every `Ok` result has finite fields, converged or not
//!   (a non-converged status carries the finite last iterate); α* ≥ 0 (for tolerances ≤ 1e-2)
//!   and d* ≥ 0; gradients and Jacobians are always finite (a quaternion too small for them
//!   gives `InvalidPose`);
//! - everywhere: `gradient` reports the same α* as `proximity` (bit for bit); the C ABI returns
//!   the status that matches the Rust result and the same α* (and signed distance, contact
//!   count, distance and early-exit status);
//! - `signed_distance`, `signed_distance_gradient` and `contact_manifold` answer finite numbers
//!   always (an answer beyond the largest double is `InvalidPose` naming the position), and fail
//!   only with the documented errors, never `Internal`;
//! - every C query ([`capi`]: proximity and its derivatives, the MRP forms, distance, signed
//!   distance, contacts, the early exits, the batch on two threads, a scene of the two bodies)
//!   writes only finite numbers on `DCOL_OK` and `DCOL_ERROR_NOT_CONVERGED` and nothing on any
//!   other status (outputs pre-filled with a sentinel), and never returns `DCOL_ERROR_INTERNAL`.
//!
//! The bugs these targets found are regression tests in tests/fuzz_regressions.rs and
//! tests/stress.rs. While one is open its invariant is suppressed here (narrowly, documented at
//! the place, with an ignored regression test) so that the fuzzer keeps exploring and the CI
//! smoke run stays meaningful. None is open now.

mod capi;

use dcol::ffi::{self, dcol_status};
use dcol::{
    alpha_below, contact_manifold, distance, distance_gradient, gradient, intersect, jacobian,
    proximity, signed_distance, signed_distance_gradient, Error, Options, Pose, Shape, SolveStatus,
};
use std::f64::consts::FRAC_PI_2;

/// `distance` rejects origins more than this many bounding radii apart with InvalidPose
/// (`MAX_OFFSET_RATIO` in src/query/distance.rs).
const DISTANCE_MAX_OFFSET_RATIO: f64 = 1e100;

/// Iteration limits above this are clamped so that one input cannot run for minutes.
pub const MAX_ITERATIONS_CAP: u32 = 500;

/// The most facets a fuzzed polytope or polygon gets (a polygon's construction is O(m³));
/// MAX_POLYGON_EDGES + 1 is also produced (cheap rows): a polygon must reject it, a polytope
/// (up to MAX_FACETS rows) accept it.
const FUZZ_FACETS: usize = 40;

/// The most points of a fuzzed hull (its construction is O(n log n)); 300 cheap points (a
/// spiral on a sphere) are also produced.
const FUZZ_HULL_POINTS: usize = 40;

const SPECIAL: [f64; 28] = [
    f64::NAN,
    -f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    0.0,
    -0.0,
    5e-324,
    -5e-324,
    f64::MIN_POSITIVE,
    1e-300,
    1e-150,
    1e-16,
    f64::EPSILON,
    1.0,
    -1.0,
    0.5,
    1.0 + f64::EPSILON,
    FRAC_PI_2,
    f64::from_bits(FRAC_PI_2.to_bits() - 1), // the double below π/2
    f64::from_bits(FRAC_PI_2.to_bits() + 1), // the double above π/2
    1e16,
    1e150,
    1e300,
    f64::MAX,
    -f64::MAX,
    1e-8,
    1e8,
    3.0,
];

/// A cursor over the fuzzer's bytes; reads past the end give zeros.
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(data: &'a [u8]) -> Bytes<'a> {
        Bytes { data, pos: 0 }
    }

    pub fn u8(&mut self) -> u8 {
        let v = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        v
    }

    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    pub fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }

    pub fn u64(&mut self) -> u64 {
        (self.u32() as u64) | ((self.u32() as u64) << 32)
    }

    /// Any double: special, raw bits, or plausible (see the module doc).
    pub fn f64(&mut self) -> f64 {
        match self.u8() % 8 {
            0 => SPECIAL[self.u8() as usize % SPECIAL.len()],
            1 => f64::from_bits(self.u64()),
            _ => self.plausible(),
        }
    }

    /// A "plausible" double: ±(a 16-bit mantissa) × 10^e with e in -6..=6.
    pub fn plausible(&mut self) -> f64 {
        let m = self.u16() as f64 / 65535.0 * 2.0 - 1.0;
        let e = (self.u8() % 13) as i32 - 6;
        m * 10f64.powi(e)
    }

    /// A size: usually a positive plausible value, sometimes any double.
    pub fn size(&mut self) -> f64 {
        if self.u8().is_multiple_of(8) {
            self.f64()
        } else {
            let v = self.plausible().abs();
            if v == 0.0 {
                1.0
            } else {
                v
            }
        }
    }
}

/// A shape request: what a constructor is called with.
#[derive(Clone, Debug)]
pub enum ShapeInput {
    Sphere(f64),
    Ellipsoid([[f64; 3]; 3]),
    Polytope(Vec<[f64; 3]>, Vec<f64>),
    Cuboid([f64; 3]),
    Capsule(f64, f64),
    Cylinder(f64, f64),
    Cone(f64, f64),
    Polygon(Vec<[f64; 2]>, Vec<f64>, f64),
    Halfspace(f64),
    /// Points (n × 3) and a radius.
    Hull(Vec<[f64; 3]>, f64),
}

fn facet_count(b: &mut Bytes) -> usize {
    match b.u8() % 16 {
        0 => 0,
        1 => 1 + b.u8() as usize % 3,
        2 => dcol::shapes::MAX_POLYGON_EDGES + 1,
        _ => 3 + b.u8() as usize % (FUZZ_FACETS - 2),
    }
}

impl ShapeInput {
    pub fn decode(b: &mut Bytes) -> ShapeInput {
        // The top eight byte values (1 in 32) ask for a half-space, the eight below 232 a
        // convex hull; the rest keep their kinds.
        let k = b.u8();
        if k >= 248 {
            return ShapeInput::Halfspace(b.size());
        }
        if (224..232).contains(&k) {
            return ShapeInput::decode_hull(b);
        }
        match k % 8 {
            0 => ShapeInput::Sphere(b.size()),
            #[allow(clippy::needless_range_loop)]
            1 => {
                // Either arbitrary entries or a symmetric matrix from arbitrary entries.
                let mut p = [[0.0; 3]; 3];
                let symmetric = !b.u8().is_multiple_of(4);
                for i in 0..3 {
                    for j in 0..3 {
                        if symmetric && j < i {
                            p[i][j] = p[j][i];
                        } else if i == j {
                            p[i][j] = b.size();
                        } else {
                            p[i][j] = b.f64() * 0.1;
                        }
                    }
                }
                ShapeInput::Ellipsoid(p)
            }
            2 => {
                let m = facet_count(b);
                // The MAX_FACETS + 1 request uses cheap rows (repeated box rows); the others
                // are arbitrary.
                let cheap = m > FUZZ_FACETS;
                let mut a = Vec::with_capacity(m);
                let mut rhs = Vec::with_capacity(m);
                for k in 0..m {
                    if cheap {
                        let mut row = [0.0; 3];
                        row[k % 3] = if k % 2 == 0 { 1.0 } else { -1.0 };
                        a.push(row);
                        rhs.push(1.0);
                    } else {
                        a.push([b.f64(), b.f64(), b.f64()]);
                        rhs.push(b.size());
                    }
                }
                match b.u8() % 16 {
                    0 => {
                        rhs.pop();
                    }
                    1 => rhs.push(1.0),
                    _ => {}
                }
                ShapeInput::Polytope(a, rhs)
            }
            3 => ShapeInput::Cuboid([b.size(), b.size(), b.size()]),
            4 => ShapeInput::Capsule(b.size(), b.size()),
            5 => ShapeInput::Cylinder(b.size(), b.size()),
            6 => {
                let h = b.size();
                let beta = match b.u8() % 4 {
                    0 => b.f64(),
                    _ => (b.u16() as f64 / 65536.0) * FRAC_PI_2,
                };
                ShapeInput::Cone(h, beta)
            }
            _ => {
                let m = facet_count(b);
                let cheap = m > FUZZ_FACETS;
                let mut c = Vec::with_capacity(m);
                let mut d = Vec::with_capacity(m);
                for k in 0..m {
                    if cheap {
                        let t = k as f64 * 2.0 * std::f64::consts::PI / 4.0;
                        c.push([t.cos(), t.sin()]);
                        d.push(1.0);
                    } else {
                        c.push([b.f64(), b.f64()]);
                        d.push(b.size());
                    }
                }
                if b.u8().is_multiple_of(16) {
                    d.pop();
                }
                ShapeInput::Polygon(c, d, b.size())
            }
        }
    }

    /// A hull: mostly a cloud of points about the origin at one scale (which usually
    /// surrounds it), sometimes arbitrary numbers, fewer than four points, or 300 points; a
    /// radius of 0, a size, or any double.
    fn decode_hull(b: &mut Bytes) -> ShapeInput {
        let n = match b.u8() % 16 {
            0 => b.u8() as usize % 4,
            1 => 300,
            _ => 4 + b.u8() as usize % (FUZZ_HULL_POINTS - 3),
        };
        let scale = b.size();
        let arbitrary = b.u8().is_multiple_of(4);
        let points = (0..n)
            .map(|i| {
                if n > FUZZ_HULL_POINTS {
                    // A spiral on the sphere of radius `scale`.
                    let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
                    let r = (1.0 - z * z).sqrt();
                    let t = 2.399963 * i as f64;
                    [scale * r * t.cos(), scale * r * t.sin(), scale * z]
                } else if arbitrary {
                    [b.f64(), b.f64(), b.f64()]
                } else {
                    [0; 3].map(|_| scale * (b.u16() as f64 / 32767.5 - 1.0))
                }
            })
            .collect();
        let radius = match b.u8() % 4 {
            0 => 0.0,
            1 => b.f64(),
            _ => b.size() * 0.1,
        };
        ShapeInput::Hull(points, radius)
    }

    pub fn build(&self) -> Result<Shape, Error> {
        match self {
            ShapeInput::Hull(p, r) => Shape::convex_hull(p, *r),
            ShapeInput::Sphere(r) => Shape::sphere(*r),
            ShapeInput::Ellipsoid(p) => Shape::ellipsoid(*p),
            ShapeInput::Polytope(a, b) => Shape::polytope(a, b),
            ShapeInput::Cuboid(h) => Shape::cuboid(h[0], h[1], h[2]),
            ShapeInput::Capsule(r, l) => Shape::capsule(*r, *l),
            ShapeInput::Cylinder(r, l) => Shape::cylinder(*r, *l),
            ShapeInput::Cone(h, beta) => Shape::cone(*h, *beta),
            ShapeInput::Polygon(c, d, r) => Shape::polygon(c, d, *r),
            ShapeInput::Halfspace(d) => Shape::halfspace(*d),
        }
    }

    /// The same constructor through the C ABI; `None` where the C signature cannot express
    /// the input (row and right-hand-side counts that differ).
    pub fn build_ffi(&self) -> Option<ffi::dcol_status> {
        let mut out: *mut ffi::dcol_shape = std::ptr::null_mut();
        // SAFETY: every pointer passed is valid for the length given, `out` is a valid
        // location, and the shape is freed right after.
        let st = unsafe {
            match self {
                ShapeInput::Sphere(r) => ffi::dcol_shape_new_sphere(*r, &mut out),
                ShapeInput::Ellipsoid(p) => {
                    let flat: Vec<f64> = p.iter().flatten().copied().collect();
                    ffi::dcol_shape_new_ellipsoid(flat.as_ptr(), &mut out)
                }
                ShapeInput::Polytope(a, b) => {
                    if a.len() != b.len() {
                        return None;
                    }
                    let flat: Vec<f64> = a.iter().flatten().copied().collect();
                    ffi::dcol_shape_new_polytope(flat.as_ptr(), b.as_ptr(), a.len(), &mut out)
                }
                ShapeInput::Cuboid(h) => ffi::dcol_shape_new_box(h[0], h[1], h[2], &mut out),
                ShapeInput::Capsule(r, l) => ffi::dcol_shape_new_capsule(*r, *l, &mut out),
                ShapeInput::Cylinder(r, l) => ffi::dcol_shape_new_cylinder(*r, *l, &mut out),
                ShapeInput::Cone(h, beta) => ffi::dcol_shape_new_cone(*h, *beta, &mut out),
                ShapeInput::Polygon(c, d, r) => {
                    if c.len() != d.len() {
                        return None;
                    }
                    let flat: Vec<f64> = c.iter().flatten().copied().collect();
                    ffi::dcol_shape_new_polygon(flat.as_ptr(), d.as_ptr(), c.len(), *r, &mut out)
                }
                ShapeInput::Halfspace(d) => ffi::dcol_shape_new_halfspace(*d, &mut out),
                ShapeInput::Hull(p, r) => {
                    let flat: Vec<f64> = p.iter().flatten().copied().collect();
                    ffi::shape::dcol_shape_new_convex_hull(flat.as_ptr(), p.len(), *r, &mut out)
                }
            }
        };
        assert_eq!(
            st == ffi::dcol_status::DCOL_OK,
            !out.is_null(),
            "[ffi-out] C constructor: status {st:?} but out = {out:?}"
        );
        // SAFETY: `out` is NULL or a shape made by the constructor above, freed once.
        unsafe { ffi::dcol_shape_free(out) };
        Some(st)
    }

    /// `Some(true)` when the shape must be accepted: a kind whose validity rule is a closed
    /// form (sphere, capsule, cylinder, cone) with every size in [1e-100, 1e100], sizes within
    /// a factor 1e6 of each other and a half angle at least 1e-6 from 0 and π/2. (The library
    /// may reject more extreme shapes — it rejects aspect ratios above 1e12 and degenerate
    /// radii — but with `InvalidShape` only, which `check_constructor` checks.)
    fn must_accept(&self) -> bool {
        let comfy = |v: f64| (1e-100..=1e100).contains(&v);
        let ratio = |a: f64, b: f64| a.max(b) / a.min(b) <= 1e6;
        match self {
            ShapeInput::Sphere(r) | ShapeInput::Halfspace(r) => comfy(*r),
            ShapeInput::Capsule(r, l) | ShapeInput::Cylinder(r, l) => {
                comfy(*r) && comfy(*l) && ratio(*r, *l)
            }
            ShapeInput::Cone(h, beta) => comfy(*h) && *beta >= 1e-6 && *beta <= FRAC_PI_2 - 1e-6,
            ShapeInput::Cuboid(h) => {
                h.iter().all(|v| comfy(*v))
                    && ratio(h[0], h[1])
                    && ratio(h[1], h[2])
                    && ratio(h[0], h[2])
            }
            _ => false,
        }
    }

    /// True if some input number is non-finite or a size is non-positive (then the
    /// constructor must reject it).
    fn obviously_invalid(&self) -> bool {
        let bad = |v: &f64| !v.is_finite();
        let nonpos = |v: &f64| v.is_nan() || *v <= 0.0;
        match self {
            ShapeInput::Sphere(r) | ShapeInput::Halfspace(r) => nonpos(r) || bad(r),
            ShapeInput::Ellipsoid(p) => p.iter().flatten().any(bad),
            ShapeInput::Polytope(a, b) => {
                a.is_empty()
                    || a.len() > dcol::shapes::MAX_FACETS
                    || a.len() != b.len()
                    || a.iter().flatten().any(bad)
                    || b.iter().any(|v| bad(v) || nonpos(v))
            }
            ShapeInput::Cuboid(h) => h.iter().any(|v| bad(v) || nonpos(v)),
            ShapeInput::Capsule(r, l) | ShapeInput::Cylinder(r, l) => {
                [r, l].iter().any(|v| bad(v) || nonpos(v))
            }
            ShapeInput::Cone(h, beta) => bad(h) || nonpos(h) || nonpos(beta) || *beta >= FRAC_PI_2,
            ShapeInput::Hull(p, r) => {
                p.len() < 4 || p.iter().flatten().any(bad) || bad(r) || r.is_nan() || *r < 0.0
            }
            ShapeInput::Polygon(c, d, r) => {
                c.is_empty()
                    || c.len() > dcol::shapes::MAX_POLYGON_EDGES
                    || c.len() != d.len()
                    || c.iter().flatten().any(bad)
                    || d.iter().any(|v| bad(v) || nonpos(v))
                    || bad(r)
                    || nonpos(r)
            }
        }
    }
}

/// Checks a constructor's outcome against the invariants; returns the shape if accepted.
/// Either solver path: the geometric default or the interior-point solver alone.
fn fuzz_method(byte: u8) -> dcol::Method {
    if byte.is_multiple_of(2) {
        dcol::Method::Auto
    } else {
        dcol::Method::InteriorPoint
    }
}

fn check_constructor(input: &ShapeInput) -> Option<Shape> {
    let result = input.build();
    if input.must_accept() {
        assert!(
            result.is_ok(),
            "[ctor-rule] {input:?}: constructor returned {result:?}"
        );
    }
    if input.obviously_invalid() {
        assert!(result.is_err(), "[ctor-accepts-invalid] {input:?} accepted");
    }
    match &result {
        Ok(s) => {
            let (rho, iota) = (s.bounding_radius(), s.inscribed_radius());
            // Found by this target (tests/fuzz_regressions.rs, `degenerate_radii_*`, fixed):
            // accepted shapes whose radii under- or overflow gave non-finite query results.
            // A half-space's bounding radius is +∞ by definition.
            let unbounded = s.kind() == dcol::ShapeKind::Halfspace && rho == f64::INFINITY;
            assert!(
                (rho.is_finite() || unbounded) && iota.is_normal() && iota > 0.0,
                "[ctor-radii] {input:?}: radii {rho:e}, {iota:e}"
            );
            assert!(
                iota <= rho * (1.0 + 1e-12),
                "[ctor-radii-order] {input:?}: inscribed radius {iota:e} > bounding radius {rho:e}"
            );
        }
        Err(e) => assert!(
            matches!(e, Error::InvalidShape(_)),
            "[ctor-variant] {input:?}: wrong error variant {e:?}"
        ),
    }
    if let Some(st) = input.build_ffi() {
        let expect = match &result {
            Ok(_) => ffi::dcol_status::DCOL_OK,
            Err(_) => ffi::dcol_status::DCOL_ERROR_INVALID_SHAPE,
        };
        assert_eq!(
            st, expect,
            "[ffi-ctor-status] {input:?}: C status {st:?}, Rust {result:?}"
        );
    }
    result.ok()
}

/// Fuzz target 1: the shape constructors (Rust and C) with arbitrary numbers and sizes.
pub fn shapes(data: &[u8]) {
    let mut b = Bytes::new(data);
    let input = ShapeInput::decode(&mut b);
    if let Some(shape) = check_constructor(&input) {
        // An accepted shape must be usable: one query against a unit sphere.
        let ball = Shape::sphere(1.0).unwrap();
        let p1 = Pose::from_position([0.0; 3]).unwrap();
        let p2 = Pose::from_position([0.3, -2.0, 1.0]).unwrap();
        let prox = proximity(&shape, &p1, &ball, &p2, &Options::default())
            .unwrap_or_else(|e| panic!("[shape-unusable] {input:?}: proximity failed: {e}"));
        if (1e-100..=1e100).contains(&shape.inscribed_radius())
            && (1e-100..=1e100).contains(&shape.bounding_radius())
        {
            check_proximity(&prox, &format!("{input:?}"), true);
        }
    }
}

fn finite3(v: &dcol::Vec3) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn check_proximity(p: &dcol::Proximity, what: &str, sign_checked: bool) {
    assert!(
        p.alpha.is_finite() && finite3(&p.point) && finite3(&p.contact1) && finite3(&p.contact2),
        "[prox-nonfinite {:?}] {what}: non-finite proximity result {p:?}",
        p.status
    );
    if sign_checked && p.status == SolveStatus::Converged {
        assert!(
            p.alpha >= 0.0,
            "[prox-negative] {what}: α* = {} < 0",
            p.alpha
        );
    }
}

fn max_abs(q: &[f64; 4]) -> f64 {
    q.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
}

fn pose_input(b: &mut Bytes) -> ([f64; 3], [f64; 4], Option<[f64; 3]>) {
    let pos = |b: &mut Bytes| match b.u8() % 4 {
        0 => b.f64(),
        _ => b.plausible(),
    };
    let r = [pos(b), pos(b), pos(b)];
    match b.u8() % 8 {
        0 => {
            let p = [b.f64(), b.f64(), b.f64()];
            (r, [0.0; 4], Some(p))
        }
        1 => (r, [b.f64(), b.f64(), b.f64(), b.f64()], None),
        k => {
            // A plausible quaternion scaled by a power of ten (norm 1e-12 .. 1e12).
            let s = 10f64.powi((b.u8() % 25) as i32 - 12);
            let q = [b.plausible(), b.plausible(), b.plausible(), b.plausible()];
            let q = if k == 2 { q } else { q.map(|v| v * s) };
            (r, q, None)
        }
    }
}

fn make_pose(r: [f64; 3], q: [f64; 4], mrp: Option<[f64; 3]>) -> Option<(Pose, [f64; 4])> {
    let result = match mrp {
        Some(p) => Pose::from_mrp(r, p),
        None => Pose::new(r, q),
    };
    let finite_r = r.iter().all(|v| v.is_finite());
    let valid = match mrp {
        // from_mrp: finite p, and the quaternion it maps to must be finite and non-zero
        // (p·p can overflow for huge p); only the finite-input direction is checked exactly.
        Some(p) => {
            if !(finite_r && p.iter().all(|v| v.is_finite())) {
                Some(false)
            } else {
                None
            }
        }
        None => Some(finite_r && q.iter().all(|v| v.is_finite()) && q.iter().any(|v| *v != 0.0)),
    };
    if let Some(v) = valid {
        assert_eq!(
            result.is_ok(),
            v,
            "[pose-rule] pose r={r:?} q={q:?} mrp={mrp:?}: {result:?}"
        );
    }
    match result {
        Ok(p) => {
            let qq = p.quaternion();
            Some((p, qq))
        }
        Err(e) => {
            assert!(
                matches!(e, Error::InvalidPose(_)),
                "[pose-variant] pose r={r:?} q={q:?} mrp={mrp:?}: wrong error variant {e:?}"
            );
            None
        }
    }
}

/// Fuzz target 2: all queries with arbitrary (valid) shapes, arbitrary poses and options.
pub fn queries(data: &[u8]) {
    let mut b = Bytes::new(data);
    let in1 = ShapeInput::decode(&mut b);
    let in2 = ShapeInput::decode(&mut b);
    let (r1, q1, m1) = pose_input(&mut b);
    let (r2, q2, m2) = pose_input(&mut b);
    // Sometimes coincident or nearly coincident origins.
    let r2 = match b.u8() % 8 {
        0 => r1,
        1 => {
            let e = b.plausible() * 1e-9;
            [r1[0] + e, r1[1], r1[2] - e]
        }
        _ => r2,
    };
    let options = match b.u8() % 4 {
        0 => Options {
            tolerance: b.f64(),
            max_iterations: b.u32() % (MAX_ITERATIONS_CAP + 1),
            method: fuzz_method(b.u8()),
            // Any double, or a plausible barrier parameter, or none.
            smoothing: match b.u8() % 4 {
                0 => b.f64(),
                1 => 1e-3,
                _ => 0.0,
            },
        },
        1 => Options {
            tolerance: Options::default().tolerance,
            max_iterations: b.u8() as u32 % 8,
            method: fuzz_method(b.u8()),
            smoothing: 0.0,
        },
        _ => Options::default(),
    };
    let (Some(s1), Some(s2)) = (check_constructor(&in1), check_constructor(&in2)) else {
        return;
    };
    let (Some((p1, q1n)), Some((p2, q2n))) = (make_pose(r1, q1, m1), make_pose(r2, q2, m2)) else {
        return;
    };
    let what = format!("{in1:?} {p1:?} / {in2:?} {p2:?} / {options:?}");
    let options_valid = options.tolerance.is_finite()
        && options.tolerance > 0.0
        && options.max_iterations > 0
        && options.smoothing.is_finite()
        && options.smoothing >= 0.0;
    let d = [
        p2.position().x - p1.position().x,
        p2.position().y - p1.position().y,
        p2.position().z - p1.position().z,
    ];
    // ‖r₂ − r₁‖ without overflow (as the library computes it): an error is allowed only when
    // the true norm exceeds the double range.
    let dmax = d.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let dist = if dmax == 0.0 || !dmax.is_finite() {
        dmax
    } else {
        dmax * d
            .iter()
            .map(|v| (v / dmax) * (v / dmax))
            .sum::<f64>()
            .sqrt()
    };
    let offset_overflows = !dist.is_finite();
    // The regime in which every number dcol returns must be finite (converged or not):
    // shape radii in [1e-100, 1e100], positions within 1e100, α* ≤ ‖Δ‖/(ι₁ + ι₂) ≤ 1e100
    // for proximity and ‖Δ‖/ℓ ≤ 1e100 for distance (beyond it distance returns InvalidPose),
    // and a tolerance below 1e-2 for the sign of α*. Outside it (offsets of 1e300 m,
    // shapes of 1e-300 m, ...) the true results can overflow; only the absence of panics,
    // the error variants and the C/Rust agreement are checked there.
    let size_ok = |s: &Shape| {
        (1e-100..=1e100).contains(&s.inscribed_radius())
            && (s.kind() == dcol::ShapeKind::Halfspace
                || (1e-100..=1e100).contains(&s.bounding_radius()))
    };
    // Two half-spaces: every query is an InvalidShape error (once the options are valid).
    let two_halfspaces =
        s1.kind() == dcol::ShapeKind::Halfspace && s2.kind() == dcol::ShapeKind::Halfspace;
    let pos_ok = |p: &Pose| p.position().iter().all(|v| v.abs() <= 1e100);
    let regime = size_ok(&s1) && size_ok(&s2) && pos_ok(&p1) && pos_ok(&p2);
    let alpha_bound = dist / (s1.inscribed_radius() + s2.inscribed_radius());
    let ell = s1.bounding_radius().max(s2.bounding_radius());
    let prox_finite = regime && alpha_bound <= 1e100;
    let dist_finite = regime && dist / ell <= 1e100;
    // Derivatives are finite whenever the proximity result is (a quaternion too small for
    // them gives InvalidPose, checked below; derivatives that cannot be computed are zeros
    // with NumericalFailure).
    let derivatives_checked = prox_finite;
    let distance_refuses = dist / ell > DISTANCE_MAX_OFFSET_RATIO;
    let sign_checked = options.tolerance <= 1e-2;

    let check_err = |e: &Error, query: &str| {
        if !options_valid {
            assert!(
                matches!(e, Error::InvalidOptions(_)),
                "[options-variant {query}] {what}: expected InvalidOptions, got {e:?}"
            );
        } else if two_halfspaces {
            assert!(
                matches!(e, Error::InvalidShape(_)),
                "[two-halfspaces {query}] {what}: expected InvalidShape, got {e:?}"
            );
        } else {
            // Derivative queries may refuse a tiny quaternion (the derivatives scale like
            // 1/‖q‖ and overflow; the library's threshold is about 1e-150, so any quaternion
            // below 1e-100 may be refused), naming the argument `quaternion`.
            let names_quaternion = matches!(e, Error::InvalidPose(d) if d.argument == "quaternion");
            let tiny_quat =
                (query == "gradient" || query == "jacobian" || query == "distance_gradient")
                    && names_quaternion
                    && (max_abs(&q1n) < 1e-100 || max_abs(&q2n) < 1e-100);
            let allowed = offset_overflows
                || (query.starts_with("distance") && distance_refuses)
                || tiny_quat;
            assert!(
                allowed && matches!(e, Error::InvalidPose(_)),
                "[query-error {query}] {what}: unexpected error {e:?}"
            );
        }
    };

    let check = |p: &dcol::Proximity| {
        if prox_finite {
            check_proximity(p, &what, sign_checked);
        }
    };
    let prox = match proximity(&s1, &p1, &s2, &p2, &options) {
        Ok(p) => {
            assert!(
                options_valid,
                "[options-accepted] {what}: invalid options accepted"
            );
            check(&p);
            Some(p)
        }
        Err(e) => {
            check_err(&e, "proximity");
            None
        }
    };
    if two_halfspaces && options_valid {
        assert!(
            prox.is_none(),
            "[two-halfspaces] {what}: proximity answered"
        );
    }
    match gradient(&s1, &p1, &s2, &p2, &options) {
        Ok((p, g)) => {
            check(&p);
            if let Some(pr) = &prox {
                assert_eq!(
                    p.alpha.to_bits(),
                    pr.alpha.to_bits(),
                    "[gradient-alpha] {what}: gradient's α* differs from proximity's"
                );
            }
            if p.status.is_converged() && derivatives_checked {
                assert!(
                    g.iter().all(|v| v.is_finite()),
                    "[gradient-nonfinite] {what}: non-finite gradient {g:?}"
                );
            }
        }
        Err(e) => check_err(&e, "gradient"),
    }
    match jacobian(&s1, &p1, &s2, &p2, &options) {
        Ok((p, j)) => {
            check(&p);
            if p.status.is_converged() && derivatives_checked {
                assert!(
                    j.iter().flatten().all(|v| v.is_finite()),
                    "[jacobian-nonfinite] {what}: non-finite jacobian {j:?}"
                );
            }
        }
        Err(e) => check_err(&e, "jacobian"),
    }
    for with_gradient in [false, true] {
        let r = if with_gradient {
            distance_gradient(&s1, &p1, &s2, &p2, &options)
        } else {
            distance(&s1, &p1, &s2, &p2, &options).map(|d| (d, [0.0; 14]))
        };
        match r {
            Ok((dd, g)) => {
                if !dist_finite {
                    continue;
                }
                assert!(
                    dd.distance.is_finite()
                        && finite3(&dd.closest1)
                        && finite3(&dd.closest2)
                        && finite3(&dd.normal),
                    "[distance-nonfinite {:?}] {what}: non-finite distance result {dd:?}",
                    dd.status
                );
                if dd.status.is_converged() {
                    assert!(
                        dd.distance >= 0.0,
                        "[distance-negative] {what}: distance {}",
                        dd.distance
                    );
                    if derivatives_checked {
                        assert!(
                            g.iter().all(|v| v.is_finite()),
                            "[distance-gradient-nonfinite] {what}: non-finite distance gradient {g:?}"
                        );
                    }
                }
            }
            Err(e) => check_err(
                &e,
                if with_gradient {
                    "distance_gradient"
                } else {
                    "distance"
                },
            ),
        }
    }

    // The signed distance, its gradient and the contact manifold: `Ok` answers are finite
    // (always: an answer beyond the largest double is `InvalidPose` naming the position), and
    // an error is one of the documented ones, never `Internal`.
    let margin = match b.u8() % 8 {
        0 => b.f64(),
        1 | 2 => b.plausible().abs(),
        _ => 0.0,
    };
    let threshold = match b.u8() % 8 {
        0 => b.f64(),
        1 => b.plausible().abs(),
        _ => 1.0,
    };
    // Positions, offsets or sizes near the largest double: an answer may not be representable.
    let huge = {
        let far = [&p1, &p2]
            .iter()
            .flat_map(|p| p.position().iter())
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        let radius = |s: &Shape| {
            let r = s.bounding_radius();
            if r.is_finite() {
                r
            } else {
                s.inscribed_radius()
            }
        };
        !(far.max(dist).max(radius(&s1)).max(radius(&s2)) <= 1e290)
    };
    let check_sd_err = |e: &Error, query: &str| {
        let names_position = matches!(e, Error::InvalidPose(d) if d.argument == "position");
        // The contacts check the margin first.
        let bad_margin = query == "contact_manifold" && !(margin.is_finite() && margin >= 0.0);
        if !options_valid || bad_margin {
            assert!(
                matches!(e, Error::InvalidOptions(_)),
                "[options-variant {query}] {what}: margin {margin}, expected InvalidOptions, \
                 got {e:?}"
            );
        } else if two_halfspaces {
            assert!(
                matches!(e, Error::InvalidShape(_)),
                "[two-halfspaces {query}] {what}: expected InvalidShape, got {e:?}"
            );
        } else {
            let names_quaternion = matches!(e, Error::InvalidPose(d) if d.argument == "quaternion");
            let tiny_quat = query == "signed_distance_gradient"
                && names_quaternion
                && (max_abs(&q1n) < 1e-100 || max_abs(&q2n) < 1e-100);
            let allowed = offset_overflows || distance_refuses || huge || tiny_quat;
            assert!(
                allowed && (names_position || names_quaternion || offset_overflows),
                "[query-error {query}] {what}: unexpected error {e:?}"
            );
        }
    };
    let finite_sd = |d: &dcol::SignedDistance| {
        d.distance.is_finite() && finite3(&d.normal) && finite3(&d.closest1) && finite3(&d.closest2)
    };
    let sd = match signed_distance(&s1, &p1, &s2, &p2, &options) {
        Ok(d) => {
            assert!(
                finite_sd(&d),
                "[sd-nonfinite {:?}] {what}: non-finite signed distance {d:?}",
                d.status
            );
            Some(d)
        }
        Err(e) => {
            check_sd_err(&e, "signed_distance");
            None
        }
    };
    match signed_distance_gradient(&s1, &p1, &s2, &p2, &options) {
        Ok((d, g)) => {
            assert!(
                finite_sd(&d) && g.iter().all(|v| v.is_finite()),
                "[sd-gradient-nonfinite {:?}] {what}: {d:?} {g:?}",
                d.status
            );
            if let Some(sd) = &sd {
                assert_eq!(
                    d.distance.to_bits(),
                    sd.distance.to_bits(),
                    "[sd-gradient-value] {what}: the gradient's signed distance differs"
                );
            }
        }
        Err(e) => check_sd_err(&e, "signed_distance_gradient"),
    }
    let manifold = match contact_manifold(&s1, &p1, &s2, &p2, margin, 16, &options) {
        Ok(m) => {
            let finite = m.signed_distance.is_finite()
                && finite3(&m.normal)
                && m.contacts()
                    .iter()
                    .all(|c| c.depth.is_finite() && finite3(&c.position) && finite3(&c.normal));
            assert!(
                finite,
                "[contacts-nonfinite {:?}] {what}: non-finite manifold {m:?}",
                m.status
            );
            if let Some(sd) = &sd {
                assert_eq!(
                    (m.signed_distance.to_bits(), m.status),
                    (sd.distance.to_bits(), sd.status),
                    "[contacts-sd] {what}: the manifold's signed distance differs"
                );
            }
            Some(m)
        }
        Err(e) => {
            check_sd_err(&e, "contact_manifold");
            None
        }
    };
    for (query, r) in [
        ("intersect", intersect(&s1, &p1, &s2, &p2, &options)),
        (
            "alpha_below",
            alpha_below(&s1, &p1, &s2, &p2, threshold, &options),
        ),
    ] {
        if let Err(e) = r {
            let bad_threshold =
                query == "alpha_below" && !(threshold.is_finite() && threshold > 0.0);
            if options_valid && !two_halfspaces && bad_threshold {
                assert!(
                    matches!(e, Error::InvalidOptions(_)),
                    "[threshold-variant] {what}: threshold {threshold}, got {e:?}"
                );
            } else {
                assert!(
                    !matches!(e, Error::Internal(_)),
                    "[query-error {query}] {what}: {e:?}"
                );
                if !bad_threshold {
                    check_err(&e, "proximity");
                }
            }
        }
    }

    // The C ABI: every query, finite numbers or nothing written (`capi`), and the statuses and
    // answers of the Rust API.
    let (Some(f1), Some(f2)) = (ffi_shape(&in1), ffi_shape(&in2)) else {
        return;
    };
    let pose = |p: &Pose| ffi::dcol_pose {
        position: [p.position().x, p.position().y, p.position().z],
        quaternion: p.quaternion(),
    };
    let mrp = match (m1, m2) {
        (Some(a), Some(c)) => Some((r1, a, r2, c)),
        _ => None,
    };
    let case = capi::Case {
        shape1: f1,
        shape2: f2,
        pose1: pose(&p1),
        pose2: pose(&p2),
        mrp,
        options: ffi::dcol_options::from(options),
        margin,
        threshold,
        what: &what,
    };
    let c = capi::every_query(&case);
    let status_of = |e: &Error| match e {
        Error::InvalidShape(_) => dcol_status::DCOL_ERROR_INVALID_SHAPE,
        Error::InvalidPose(_) => dcol_status::DCOL_ERROR_INVALID_POSE,
        Error::InvalidOptions(_) => dcol_status::DCOL_ERROR_INVALID_OPTIONS,
        Error::Internal(_) => dcol_status::DCOL_ERROR_INTERNAL,
    };
    let answered = |status: SolveStatus| {
        if status.is_converged() {
            dcol_status::DCOL_OK
        } else {
            dcol_status::DCOL_ERROR_NOT_CONVERGED
        }
    };
    // Proximity: Rust's answer, unless it holds a number a double cannot (then the C boundary
    // says InvalidPose).
    let expect = match &prox {
        Some(p)
            if !(p.alpha.is_finite()
                && finite3(&p.point)
                && finite3(&p.contact1)
                && finite3(&p.contact2)) =>
        {
            dcol_status::DCOL_ERROR_INVALID_POSE
        }
        Some(p) => answered(p.status),
        None if !options_valid => dcol_status::DCOL_ERROR_INVALID_OPTIONS,
        None if two_halfspaces => dcol_status::DCOL_ERROR_INVALID_SHAPE,
        None => dcol_status::DCOL_ERROR_INVALID_POSE,
    };
    assert_eq!(
        c.proximity, expect,
        "[ffi-query-status {:?}] {what}: C status {:?}",
        c.proximity, c.proximity
    );
    if let Some(p) = prox
        .as_ref()
        .filter(|_| c.proximity == expect && expect != dcol_status::DCOL_ERROR_INVALID_POSE)
    {
        assert_eq!(
            c.alpha.to_bits(),
            p.alpha.to_bits(),
            "[ffi-query-alpha] {what}: C α* {} vs Rust {}",
            c.alpha,
            p.alpha
        );
    }
    // The signed distance and the contacts: the same status, value and count.
    let expect = match &sd {
        Some(d) => answered(d.status),
        None => {
            let e = signed_distance(&s1, &p1, &s2, &p2, &options).unwrap_err();
            status_of(&e)
        }
    };
    assert_eq!(
        c.signed_distance, expect,
        "[ffi-sd-status {:?}] {what}",
        c.signed_distance
    );
    if let Some(d) = &sd {
        assert_eq!(
            c.signed.to_bits(),
            d.distance.to_bits(),
            "[ffi-sd-value] {what}: C {} vs Rust {}",
            c.signed,
            d.distance
        );
    }
    let expect = match &manifold {
        Some(m) => answered(m.status),
        None => {
            let e = contact_manifold(&s1, &p1, &s2, &p2, margin, 16, &options).unwrap_err();
            // Two boxes proven apart by more than the margin along an axis: the C function
            // answers "no contact" without the exact distance, which Rust's manifold computes
            // and which may be refused (origins more than 1e100 sizes apart, or overflowing).
            let skipped = matches!(e, Error::InvalidPose(_))
                && c.contacts == dcol_status::DCOL_OK
                && c.contact_count == 0;
            if skipped {
                dcol_status::DCOL_OK
            } else {
                status_of(&e)
            }
        }
    };
    assert_eq!(
        c.contacts, expect,
        "[ffi-contacts-status {:?}] {what}",
        c.contacts
    );
    if let Some(m) = &manifold {
        assert_eq!(c.contact_count, m.len(), "[ffi-contacts-count] {what}");
    }
    // The distance: Rust's answer, unless it holds a number a double cannot.
    let expect = match distance(&s1, &p1, &s2, &p2, &options) {
        Ok(d)
            if !(d.distance.is_finite()
                && finite3(&d.closest1)
                && finite3(&d.closest2)
                && finite3(&d.normal)) =>
        {
            dcol_status::DCOL_ERROR_INVALID_POSE
        }
        Ok(d) => answered(d.status),
        Err(e) => status_of(&e),
    };
    assert_eq!(
        c.distance, expect,
        "[ffi-distance-status {:?}] {what}",
        c.distance
    );
    // The early exits: the Rust API's status.
    let early = |r: Result<dcol::Decision, Error>| match r {
        Ok(d) => answered(d.status),
        Err(e) => status_of(&e),
    };
    assert_eq!(
        c.intersect,
        early(intersect(&s1, &p1, &s2, &p2, &options)),
        "[ffi-intersect-status {:?}] {what}",
        c.intersect
    );
    assert_eq!(
        c.alpha_below,
        early(alpha_below(&s1, &p1, &s2, &p2, threshold, &options)),
        "[ffi-alpha-below-status {:?}] {what}",
        c.alpha_below
    );
    // SAFETY: made by `ffi_shape`, freed once.
    unsafe {
        ffi::dcol_shape_free(f1);
        ffi::dcol_shape_free(f2);
    }
}

/// A C handle for an input the Rust constructor accepted (`None` if C cannot express it).
fn ffi_shape(input: &ShapeInput) -> Option<*mut ffi::dcol_shape> {
    match input {
        ShapeInput::Polytope(a, b) if a.len() != b.len() => return None,
        ShapeInput::Polygon(c, d, _) if c.len() != d.len() => return None,
        _ => {}
    }
    let mut out: *mut ffi::dcol_shape = std::ptr::null_mut();
    // SAFETY: as in `ShapeInput::build_ffi`; the caller frees the handle.
    let st = unsafe {
        match input {
            ShapeInput::Sphere(r) => ffi::dcol_shape_new_sphere(*r, &mut out),
            ShapeInput::Ellipsoid(p) => {
                let flat: Vec<f64> = p.iter().flatten().copied().collect();
                ffi::dcol_shape_new_ellipsoid(flat.as_ptr(), &mut out)
            }
            ShapeInput::Polytope(a, b) => {
                let flat: Vec<f64> = a.iter().flatten().copied().collect();
                ffi::dcol_shape_new_polytope(flat.as_ptr(), b.as_ptr(), a.len(), &mut out)
            }
            ShapeInput::Cuboid(h) => ffi::dcol_shape_new_box(h[0], h[1], h[2], &mut out),
            ShapeInput::Capsule(r, l) => ffi::dcol_shape_new_capsule(*r, *l, &mut out),
            ShapeInput::Cylinder(r, l) => ffi::dcol_shape_new_cylinder(*r, *l, &mut out),
            ShapeInput::Cone(h, beta) => ffi::dcol_shape_new_cone(*h, *beta, &mut out),
            ShapeInput::Polygon(c, d, r) => {
                let flat: Vec<f64> = c.iter().flatten().copied().collect();
                ffi::dcol_shape_new_polygon(flat.as_ptr(), d.as_ptr(), c.len(), *r, &mut out)
            }
            ShapeInput::Halfspace(d) => ffi::dcol_shape_new_halfspace(*d, &mut out),
            ShapeInput::Hull(p, r) => {
                let flat: Vec<f64> = p.iter().flatten().copied().collect();
                ffi::shape::dcol_shape_new_convex_hull(flat.as_ptr(), p.len(), *r, &mut out)
            }
        }
    };
    (st == ffi::dcol_status::DCOL_OK).then_some(out)
}
