//! The C ABI called from Rust: it must give bit-for-bit the results of the Rust API on shared
//! reference cases, map every error to its status, and be callable from many threads at once on
//! shared shapes. (The C side of the contract is tested by `c_tests/` under ctest.)

mod common;

use common::*;
use dcol::ffi::*;
use dcol::{distance, gradient, jacobian, proximity, Error, Options};
use serde_json::Value;
use std::ptr;

fn nums(v: &Value) -> Vec<f64> {
    match v {
        Value::Array(a) => a.iter().flat_map(nums).collect(),
        other => vec![other.as_f64().expect("number")],
    }
}

/// A C-side shape built through the C constructors from a reference record.
struct CShape(*mut dcol_shape);

// SAFETY: `dcol_shape` is immutable once built and documented as shareable between threads.
unsafe impl Send for CShape {}
// SAFETY: as above.
unsafe impl Sync for CShape {}

impl CShape {
    fn ptr(&self) -> *const dcol_shape {
        self.0
    }
}

impl Drop for CShape {
    fn drop(&mut self) {
        // SAFETY: built by a constructor below, freed exactly once.
        unsafe { dcol_shape_free(self.0) }
    }
}

fn c_shape(v: &Value) -> CShape {
    let mut out = ptr::null_mut();
    let g = |k: &str| v[k].as_f64().expect("number");
    // SAFETY: every array passed holds the number of doubles the constructor reads.
    let st = unsafe {
        match v["kind"].as_str().unwrap() {
            "sphere" => dcol_shape_new_sphere(g("R"), &mut out),
            "ellipsoid" => dcol_shape_new_ellipsoid(nums(&v["P"]).as_ptr(), &mut out),
            "polytope" => {
                let (a, b) = (nums(&v["A"]), nums(&v["b"]));
                dcol_shape_new_polytope(a.as_ptr(), b.as_ptr(), b.len(), &mut out)
            }
            "capsule" => dcol_shape_new_capsule(g("R"), g("L"), &mut out),
            "cylinder" => dcol_shape_new_cylinder(g("R"), g("L"), &mut out),
            "cone" => dcol_shape_new_cone(g("H"), g("beta"), &mut out),
            "padded_polygon" => {
                let (c, d) = (nums(&v["C"]), nums(&v["d"]));
                dcol_shape_new_polygon(c.as_ptr(), d.as_ptr(), d.len(), g("R"), &mut out)
            }
            other => panic!("unknown kind {other}"),
        }
    };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert!(!out.is_null());
    CShape(out)
}

fn c_pose(v: &Value) -> dcol_pose {
    let (r, q) = (nums(&v["r"]), nums(&v["q"]));
    dcol_pose {
        position: [r[0], r[1], r[2]],
        quaternion: [q[0], q[1], q[2], q[3]],
    }
}

fn status_of(r: &Result<impl Sized, Error>, converged: impl Fn() -> bool) -> dcol_status {
    match r {
        Err(Error::InvalidShape(_)) => dcol_status::DCOL_ERROR_INVALID_SHAPE,
        Err(Error::InvalidPose(_)) => dcol_status::DCOL_ERROR_INVALID_POSE,
        Err(Error::InvalidOptions(_)) => dcol_status::DCOL_ERROR_INVALID_OPTIONS,
        Err(Error::Internal(_)) => dcol_status::DCOL_ERROR_INTERNAL,
        Ok(_) if converged() => dcol_status::DCOL_OK,
        Ok(_) => dcol_status::DCOL_ERROR_NOT_CONVERGED,
    }
}

fn v(x: &dcol::Vec3) -> [f64; 3] {
    [x.x, x.y, x.z]
}

#[test]
fn c_abi_matches_rust_api_on_reference_cases() {
    let Some(dir) = own_dir() else { return }; // None only with DCOL_ALLOW_SKIP=1
    let opts = Options::default();
    let mut checked = 0;
    for file in all_files(&dir) {
        for case in load(&file).iter().take(2) {
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            let (c1, c2) = (c_shape(&case["shape1"]), c_shape(&case["shape2"]));
            let (q1, q2) = (c_pose(&case["pose1"]), c_pose(&case["pose2"]));
            let id = case["id"].as_str().unwrap();

            let rust = proximity(&s1, &p1, &s2, &p2, &opts);
            let mut res = dcol_proximity_result::default();
            // SAFETY: all pointers are valid locals or live shapes.
            let st = unsafe { dcol_proximity(c1.0, &q1, c2.0, &q2, ptr::null(), &mut res) };
            let conv = || rust.as_ref().unwrap().status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            let p = rust.unwrap();
            assert_eq!(res.alpha.to_bits(), p.alpha.to_bits(), "{id}");
            assert_eq!(res.point, v(&p.point), "{id}");
            assert_eq!(res.contact1, v(&p.contact1), "{id}");
            assert_eq!(res.contact2, v(&p.contact2), "{id}");
            assert_eq!(res.iterations, p.iterations, "{id}");

            let rust = gradient(&s1, &p1, &s2, &p2, &opts);
            let mut g = [f64::NAN; 14];
            // SAFETY: as above; `g` holds 14 doubles.
            let st = unsafe {
                dcol_gradient(c1.0, &q1, c2.0, &q2, ptr::null(), &mut res, g.as_mut_ptr())
            };
            let conv = || rust.as_ref().unwrap().0.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            if let Ok((_, rg)) = rust {
                assert_eq!(g.map(f64::to_bits), rg.map(f64::to_bits), "{id}");
            } else {
                assert!(g.iter().all(|x| x.is_nan()), "{id}: written on error");
            }

            let rust = jacobian(&s1, &p1, &s2, &p2, &opts);
            let mut j = [f64::NAN; 56];
            // SAFETY: as above; `j` holds 56 doubles.
            let st = unsafe {
                dcol_jacobian(c1.0, &q1, c2.0, &q2, ptr::null(), &mut res, j.as_mut_ptr())
            };
            let conv = || rust.as_ref().unwrap().0.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            if let Ok((_, rj)) = rust {
                let flat: Vec<u64> = rj.iter().flatten().map(|x| x.to_bits()).collect();
                assert_eq!(j.map(f64::to_bits).to_vec(), flat, "{id}");
            } else {
                assert!(j.iter().all(|x| x.is_nan()), "{id}: written on error");
            }

            let rust = distance(&s1, &p1, &s2, &p2, &opts);
            let mut d = dcol_distance_result {
                distance: f64::NAN,
                ..Default::default()
            };
            // SAFETY: as above.
            let st = unsafe { dcol_distance(c1.0, &q1, c2.0, &q2, ptr::null(), &mut d) };
            let conv = || rust.as_ref().unwrap().status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            if let Ok(rd) = rust {
                assert_eq!(d.distance.to_bits(), rd.distance.to_bits(), "{id}");
                assert_eq!(d.closest1, v(&rd.closest1), "{id}");
                assert_eq!(d.closest2, v(&rd.closest2), "{id}");
                assert_eq!(d.normal, v(&rd.normal), "{id}");
            } else {
                assert!(d.distance.is_nan(), "{id}: written on error");
            }
            checked += 1;
        }
    }
    assert!(checked >= 100, "only {checked} cases checked");
}

#[test]
fn many_threads_share_shapes() {
    let mut a = ptr::null_mut();
    let mut b = ptr::null_mut();
    let half = [
        1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0,
    ];
    let rhs = [0.5, 0.4, 0.3, 0.6, 0.7];
    // SAFETY: valid out pointers and arrays of the sizes read (5 facets: 15 + 5 doubles).
    unsafe {
        assert_eq!(
            dcol_shape_new_capsule(0.3, 1.0, &mut a),
            dcol_status::DCOL_OK
        );
        assert_eq!(
            dcol_shape_new_polytope(half.as_ptr(), rhs.as_ptr(), 5, &mut b),
            dcol_status::DCOL_ERROR_INVALID_SHAPE, // unbounded in -z: rejected
        );
        let full = [
            1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0,
            -1.0,
        ];
        let rhs = [0.5, 0.4, 0.3, 0.6, 0.7, 0.8];
        assert_eq!(
            dcol_shape_new_polytope(full.as_ptr(), rhs.as_ptr(), 6, &mut b),
            dcol_status::DCOL_OK
        );
    }
    let (a, b) = (CShape(a), CShape(b));
    let pose_at = |i: usize| dcol_pose {
        position: [1.5 + 0.01 * i as f64, 0.2, -0.1],
        quaternion: [1.0, 0.1 * i as f64, 0.2, 0.3],
    };
    let origin = dcol_pose {
        position: [0.0; 3],
        quaternion: [1.0, 0.0, 0.0, 0.0],
    };
    let run = |i: usize| {
        let mut r = dcol_proximity_result::default();
        // SAFETY: live shared shapes and valid locals.
        let st =
            unsafe { dcol_proximity(a.ptr(), &origin, b.ptr(), &pose_at(i), ptr::null(), &mut r) };
        assert_eq!(st, dcol_status::DCOL_OK);
        r
    };
    let serial: Vec<_> = (0..64).map(run).collect();
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| {
                for (i, expect) in serial.iter().enumerate() {
                    assert_eq!(run(i), *expect);
                }
            });
        }
    });
}

#[test]
fn last_error_is_per_thread() {
    let mut out = ptr::null_mut();
    // SAFETY: valid out pointer.
    let st = unsafe { dcol_shape_new_sphere(f64::NAN, &mut out) };
    assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_SHAPE);
    let msg = |p: *const std::os::raw::c_char| {
        // SAFETY: the library returns NUL-terminated strings that outlive this call.
        unsafe { std::ffi::CStr::from_ptr(p) }
            .to_string_lossy()
            .into_owned()
    };
    let here = msg(dcol_last_error_message());
    assert!(here.contains("`radius` = NaN"), "{here}");
    let there = std::thread::spawn(move || msg(dcol_last_error_message()))
        .join()
        .unwrap();
    assert_eq!(there, "");
}

/// Modified Rodrigues parameters of the rotation of `q` (the short way round).
fn mrp_of(q: [f64; 4]) -> [f64; 3] {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let s = if q[0] < 0.0 { -1.0 / n } else { 1.0 / n };
    let w = q[0] * s;
    [
        q[1] * s / (1.0 + w),
        q[2] * s / (1.0 + w),
        q[3] * s / (1.0 + w),
    ]
}

fn bits<const N: usize>(a: &[f64; N]) -> [u64; N] {
    a.map(f64::to_bits)
}

fn same_prox(c: &dcol_proximity_result, p: &dcol::Proximity) -> bool {
    c.alpha.to_bits() == p.alpha.to_bits()
        && bits(&c.point) == bits(&v(&p.point))
        && bits(&c.contact1) == bits(&v(&p.contact1))
        && bits(&c.contact2) == bits(&v(&p.contact2))
        && c.iterations == p.iterations
}

/// The extensions (early exit, distance gradient, derivatives, MRP, batch, scene) give the
/// Rust API's answers bit for bit on the reference cases.
#[test]
fn c_extensions_match_rust_api_on_reference_cases() {
    use dcol::batch::{proximity_batch, Pair};
    use dcol::scene::Scene;
    use dcol::{alpha_below, derivatives, distance_gradient, gradient_mrp, jacobian_mrp};

    let Some(dir) = own_dir() else { return }; // None only with DCOL_ALLOW_SKIP=1
    let opts = Options::default();
    let (mut rs, mut rp, mut cs, mut cp) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for file in all_files(&dir) {
        for case in load(&file).iter().take(2) {
            let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
            let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
            let (c1, c2) = (c_shape(&case["shape1"]), c_shape(&case["shape2"]));
            let (q1, q2) = (c_pose(&case["pose1"]), c_pose(&case["pose2"]));
            let id = case["id"].as_str().unwrap();
            let alpha = proximity(&s1, &p1, &s2, &p2, &opts).unwrap().alpha;

            for t in [1.0, 0.9 * alpha, 1.1 * alpha, alpha] {
                if t <= 0.0 {
                    continue;
                }
                let rust = alpha_below(&s1, &p1, &s2, &p2, t, &opts);
                let mut below = -1;
                // SAFETY: live shapes and valid locals.
                let st = unsafe {
                    dcol_alpha_below(c1.ptr(), &q1, c2.ptr(), &q2, t, ptr::null(), &mut below)
                };
                let conv = || rust.as_ref().unwrap().status.is_converged();
                assert_eq!(st, status_of(&rust, conv), "{id} t {t}");
                assert_eq!(below, i32::from(rust.unwrap().below), "{id} t {t}");
                if t == 1.0 {
                    let mut inter = -1;
                    // SAFETY: as above.
                    let st = unsafe {
                        dcol_intersect(c1.ptr(), &q1, c2.ptr(), &q2, ptr::null(), &mut inter)
                    };
                    assert_eq!(st, dcol_status::DCOL_OK, "{id}");
                    assert_eq!(inter, below, "{id}");
                }
            }

            let rust = distance_gradient(&s1, &p1, &s2, &p2, &opts);
            let mut d = dcol_distance_result::default();
            let mut g = [f64::NAN; 14];
            // SAFETY: as above; `g` holds 14 doubles.
            let st = unsafe {
                dcol_distance_gradient(
                    c1.ptr(),
                    &q1,
                    c2.ptr(),
                    &q2,
                    ptr::null(),
                    &mut d,
                    g.as_mut_ptr(),
                )
            };
            let conv = || rust.as_ref().unwrap().0.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            let (rd, rg) = rust.unwrap();
            assert_eq!(d.distance.to_bits(), rd.distance.to_bits(), "{id}");
            assert_eq!(bits(&d.closest1), bits(&v(&rd.closest1)), "{id}");
            assert_eq!(bits(&d.closest2), bits(&v(&rd.closest2)), "{id}");
            assert_eq!(bits(&g), bits(&rg), "{id}");

            let rust = derivatives(&s1, &p1, &s2, &p2, &opts);
            let mut dr = dcol_derivatives_result::default();
            // SAFETY: as above.
            let st =
                unsafe { dcol_derivatives(c1.ptr(), &q1, c2.ptr(), &q2, ptr::null(), &mut dr) };
            let conv = || rust.as_ref().unwrap().proximity.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            let rd = rust.unwrap();
            assert!(same_prox(&dr.proximity, &rd.proximity), "{id}");
            assert_eq!(bits(&dr.gradient), bits(&rd.dalpha), "{id}");
            for r in 0..4 {
                assert_eq!(bits(&dr.jacobian[r]), bits(&rd.jacobian[r]), "{id}");
            }
            for r in 0..3 {
                assert_eq!(
                    bits(&dr.contact_jacobian1[r]),
                    bits(&rd.dcontact1[r]),
                    "{id}"
                );
                assert_eq!(
                    bits(&dr.contact_jacobian2[r]),
                    bits(&rd.dcontact2[r]),
                    "{id}"
                );
            }

            let (m1, m2) = (mrp_of(q1.quaternion), mrp_of(q2.quaternion));
            let (r1, r2) = (q1.position, q2.position);
            let rust = gradient_mrp(&s1, r1, m1, &s2, r2, m2, &opts);
            let mut res = dcol_proximity_result::default();
            let mut gm = [f64::NAN; 12];
            // SAFETY: live shapes, 3-double arrays, valid outputs (`gm` holds 12 doubles).
            let st = unsafe {
                dcol_gradient_mrp(
                    c1.ptr(),
                    r1.as_ptr(),
                    m1.as_ptr(),
                    c2.ptr(),
                    r2.as_ptr(),
                    m2.as_ptr(),
                    ptr::null(),
                    &mut res,
                    gm.as_mut_ptr(),
                )
            };
            let conv = || rust.as_ref().unwrap().0.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            let (rprox, rg) = rust.unwrap();
            assert!(same_prox(&res, &rprox), "{id}");
            assert_eq!(bits(&gm), bits(&rg), "{id}");

            let rust = jacobian_mrp(&s1, r1, m1, &s2, r2, m2, &opts);
            let mut jm = [f64::NAN; 48];
            // SAFETY: as above; `jm` holds 48 doubles.
            let st = unsafe {
                dcol_jacobian_mrp(
                    c1.ptr(),
                    r1.as_ptr(),
                    m1.as_ptr(),
                    c2.ptr(),
                    r2.as_ptr(),
                    m2.as_ptr(),
                    ptr::null(),
                    &mut res,
                    jm.as_mut_ptr(),
                )
            };
            let conv = || rust.as_ref().unwrap().0.status.is_converged();
            assert_eq!(st, status_of(&rust, conv), "{id}");
            let (rprox, rj) = rust.unwrap();
            assert!(same_prox(&res, &rprox), "{id}");
            let flat: Vec<u64> = rj.iter().flatten().map(|x| x.to_bits()).collect();
            assert_eq!(jm.map(f64::to_bits).to_vec(), flat, "{id}");

            rs.push((s1, p1, s2, p2));
            cs.push((c1, c2));
            cp.push((q1, q2));
            rp.push(id.to_string());
        }
    }
    assert!(rs.len() >= 100, "only {} cases", rs.len());

    // Batch: every case at once, against the Rust batch, on 1 and 3 threads.
    let pairs: Vec<Pair> = rs
        .iter()
        .map(|(s1, p1, s2, p2)| Pair {
            shape1: s1,
            pose1: p1,
            shape2: s2,
            pose2: p2,
        })
        .collect();
    let mut rust_out = vec![Err(Error::Internal("unset")); pairs.len()];
    proximity_batch(&pairs, &opts, 1, &mut rust_out).unwrap();
    let shapes1: Vec<*const dcol_shape> = cs.iter().map(|c| c.0.ptr()).collect();
    let shapes2: Vec<*const dcol_shape> = cs.iter().map(|c| c.1.ptr()).collect();
    let poses1: Vec<dcol_pose> = cp.iter().map(|p| p.0).collect();
    let poses2: Vec<dcol_pose> = cp.iter().map(|p| p.1).collect();
    for threads in [1, 3] {
        let n = pairs.len();
        let mut results = vec![dcol_proximity_result::default(); n];
        let mut statuses = vec![dcol_status::DCOL_ERROR_INTERNAL; n];
        // SAFETY: every array holds `n` elements; the shapes are live.
        let st = unsafe {
            dcol_proximity_batch(
                shapes1.as_ptr(),
                poses1.as_ptr(),
                shapes2.as_ptr(),
                poses2.as_ptr(),
                n,
                ptr::null(),
                threads,
                results.as_mut_ptr(),
                statuses.as_mut_ptr(),
            )
        };
        assert_eq!(st, dcol_status::DCOL_OK);
        for i in 0..n {
            let conv = || rust_out[i].as_ref().unwrap().status.is_converged();
            assert_eq!(statuses[i], status_of(&rust_out[i], conv), "{}", rp[i]);
            assert!(
                same_prox(&results[i], rust_out[i].as_ref().unwrap()),
                "{}",
                rp[i]
            );
        }
    }

    // Scene: the first shape of each case at its pose, spread out a little, against the Rust
    // scene.
    let mut rust_scene = Scene::new();
    let mut scene = ptr::null_mut();
    // SAFETY: valid out pointer.
    assert_eq!(unsafe { dcol_scene_new(&mut scene) }, dcol_status::DCOL_OK);
    for (i, ((s1, _, _, _), (c1, _))) in rs.iter().zip(&cs).enumerate() {
        let mut q = cp[i].0;
        q.position[0] += 0.05 * (i % 40) as f64;
        rust_scene.add(
            s1.clone(),
            dcol::Pose::new(q.position, q.quaternion).unwrap(),
        );
        let mut id = usize::MAX;
        // SAFETY: live scene and shape, valid locals.
        assert_eq!(
            unsafe { dcol_scene_add(scene, c1.ptr(), &q, &mut id) },
            dcol_status::DCOL_OK
        );
        assert_eq!(id, i);
    }
    let mut rust_pairs = Vec::new();
    let mut reported = 0;
    for t in [0.5, 1.0, 2.0] {
        // The C scene is asked twice (for the count, then the pairs), and a scene's pairs of
        // polytopes start from their last answer (their caches): the Rust scene is asked twice
        // too, so that both have made the same calls and answer bit for bit alike.
        rust_scene.pairs_within(t, &opts, &mut rust_pairs).unwrap();
        let rust_stats = rust_scene.pairs_within(t, &opts, &mut rust_pairs).unwrap();
        let mut count = usize::MAX;
        // SAFETY: a size query: capacity 0, `pairs` NULL.
        let st = unsafe {
            dcol_scene_pairs_within(
                scene,
                t,
                ptr::null(),
                ptr::null_mut(),
                0,
                &mut count,
                ptr::null_mut(),
            )
        };
        assert_eq!(count, rust_pairs.len());
        assert_eq!(
            st,
            if count == 0 {
                dcol_status::DCOL_OK
            } else {
                dcol_status::DCOL_ERROR_INVALID_OPTIONS
            }
        );
        let template = dcol_scene_pair {
            body1: usize::MAX,
            body2: usize::MAX,
            proximity: dcol_proximity_result::default(),
            status: dcol_status::DCOL_ERROR_INTERNAL,
        };
        let mut out = vec![template; count];
        let mut stats = dcol_scene_stats::default();
        // SAFETY: `out` holds `count` pairs.
        let st = unsafe {
            dcol_scene_pairs_within(
                scene,
                t,
                ptr::null(),
                out.as_mut_ptr(),
                count,
                &mut count,
                &mut stats,
            )
        };
        assert_eq!(st, dcol_status::DCOL_OK);
        assert_eq!(count, rust_pairs.len());
        reported += count;
        assert_eq!(stats.reported, rust_stats.reported);
        assert_eq!(stats.pairs_total, rust_stats.pairs_total);
        assert_eq!(stats.sweep_candidates, rust_stats.sweep_candidates);
        assert_eq!(stats.sphere_candidates, rust_stats.sphere_candidates);
        assert_eq!(stats.proven_by_bounds, rust_stats.proven_by_bounds);
        assert_eq!(stats.early_exits, rust_stats.early_exits);
        assert_eq!(stats.full_solves, rust_stats.full_solves);
        for (c, r) in out.iter().zip(&rust_pairs) {
            assert_eq!((c.body1, c.body2), (r.body1, r.body2));
            assert!(same_prox(&c.proximity, &r.proximity));
            assert_eq!(
                c.status == dcol_status::DCOL_OK,
                r.proximity.status.is_converged()
            );
        }
    }
    assert!(reported > 10, "only {reported} scene pairs compared");
    // SAFETY: made by dcol_scene_new, freed once.
    unsafe { dcol_scene_free(scene) };
}

/// Counts heap operations per thread, for the no-allocation checks below.
struct Counting;

thread_local! {
    static HEAP_OPS: std::cell::Cell<u64> = const { std::cell::Cell::new(0) };
}

fn heap_ops() -> u64 {
    HEAP_OPS.with(|c| c.get())
}

fn bump() {
    // `try_with`: the allocator may run while this thread's locals are being destroyed.
    let _ = HEAP_OPS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl std::alloc::GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
        bump();
        // SAFETY: forwarded from the caller.
        unsafe { std::alloc::System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
        bump();
        // SAFETY: forwarded from the caller.
        unsafe { std::alloc::System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, p: *mut u8, layout: std::alloc::Layout, size: usize) -> *mut u8 {
        bump();
        // SAFETY: forwarded from the caller.
        unsafe { std::alloc::System.realloc(p, layout, size) }
    }
    unsafe fn dealloc(&self, p: *mut u8, layout: std::alloc::Layout) {
        bump();
        // SAFETY: forwarded from the caller.
        unsafe { std::alloc::System.dealloc(p, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The new queries do not touch the heap, on success or on error: the early-exit questions,
/// the distance gradient, the derivatives, the MRP variants, a batch on the calling thread, and
/// a scene step once the scene has seen as many pairs before.
#[test]
fn c_extensions_do_not_allocate() {
    let mut shapes = [ptr::null_mut(); 3];
    // SAFETY: valid out pointers.
    unsafe {
        assert_eq!(
            dcol_shape_new_box(0.5, 0.4, 0.3, &mut shapes[0]),
            dcol_status::DCOL_OK
        );
        assert_eq!(
            dcol_shape_new_capsule(0.2, 0.8, &mut shapes[1]),
            dcol_status::DCOL_OK
        );
        assert_eq!(
            dcol_shape_new_cone(1.0, 0.5, &mut shapes[2]),
            dcol_status::DCOL_OK
        );
    }
    let shapes = shapes.map(CShape);
    let (a, b) = (shapes[0].ptr(), shapes[1].ptr());
    let p1 = dcol_pose {
        position: [0.0; 3],
        quaternion: [1.0, 0.0, 0.0, 0.0],
    };
    let p2 = dcol_pose {
        position: [0.9, 0.3, 0.1],
        quaternion: [0.9, 0.1, 0.0, 0.4],
    };
    let mut bad = p2;
    bad.position[1] = f64::NAN;
    let (r1, m1, r2, m2) = ([0.0; 3], [0.1, 0.2, 0.3], [0.9, 0.3, 0.1], [0.0, 0.1, 0.0]);
    let bad_opts = dcol_options {
        tolerance: -1.0,
        max_iterations: 10,
        method: 0,
        smoothing: 0.0,
    };
    let mut scene = ptr::null_mut();
    // SAFETY: valid out pointer; live shapes and valid poses.
    unsafe {
        assert_eq!(dcol_scene_new(&mut scene), dcol_status::DCOL_OK);
        for (i, s) in shapes.iter().enumerate() {
            let mut pose = p2;
            pose.position[0] = 0.5 * i as f64;
            let mut id = 0;
            assert_eq!(
                dcol_scene_add(scene, s.ptr(), &pose, &mut id),
                dcol_status::DCOL_OK
            );
        }
    }
    let template = dcol_scene_pair {
        body1: 0,
        body2: 0,
        proximity: dcol_proximity_result::default(),
        status: dcol_status::DCOL_OK,
    };
    let (s1s, s2s) = ([a, a, b], [b, ptr::null(), a]);
    let (p1s, p2s) = ([p1, p1, p1], [p2, p2, bad]);

    let run_all = || {
        let mut res = dcol_proximity_result::default();
        let mut dres = dcol_distance_result::default();
        let mut der = dcol_derivatives_result::default();
        let (mut g, mut gm, mut jm, mut flag) = ([0.0; 14], [0.0; 12], [0.0; 48], 0);
        let mut pairs = [template; 3];
        let mut results = [dcol_proximity_result::default(); 3];
        let mut statuses = [dcol_status::DCOL_OK; 3];
        let (mut count, mut stats) = (0, dcol_scene_stats::default());
        let o = ptr::null();
        // SAFETY: live shapes and scene, valid locals of the documented sizes.
        unsafe {
            for opts in [o, &bad_opts as *const dcol_options] {
                for pose2 in [&p2 as *const dcol_pose, &bad] {
                    dcol_alpha_below(a, &p1, b, pose2, 1.3, opts, &mut flag);
                    dcol_alpha_below(a, &p1, b, pose2, f64::NAN, opts, &mut flag);
                    dcol_intersect(a, &p1, b, pose2, opts, &mut flag);
                    dcol_distance_gradient(a, &p1, b, pose2, opts, &mut dres, g.as_mut_ptr());
                    dcol_derivatives(a, &p1, b, pose2, opts, &mut der);
                }
                let (m, pm) = (m1.as_ptr(), m2.as_ptr());
                dcol_gradient_mrp(
                    a,
                    r1.as_ptr(),
                    m,
                    b,
                    r2.as_ptr(),
                    pm,
                    opts,
                    &mut res,
                    gm.as_mut_ptr(),
                );
                dcol_jacobian_mrp(
                    a,
                    r1.as_ptr(),
                    m,
                    b,
                    r2.as_ptr(),
                    pm,
                    opts,
                    &mut res,
                    jm.as_mut_ptr(),
                );
                let st = dcol_proximity_batch(
                    s1s.as_ptr(),
                    p1s.as_ptr(),
                    s2s.as_ptr(),
                    p2s.as_ptr(),
                    3,
                    opts,
                    1,
                    results.as_mut_ptr(),
                    statuses.as_mut_ptr(),
                );
                assert_eq!(st == dcol_status::DCOL_OK, opts.is_null());
                if opts.is_null() {
                    use dcol_status::*;
                    let want = [DCOL_OK, DCOL_ERROR_NULL_POINTER, DCOL_ERROR_INVALID_POSE];
                    assert_eq!(statuses, want);
                }
                dcol_scene_set_pose(scene, 1, &p2);
                dcol_scene_set_pose(scene, 7, &p2);
                let st = dcol_scene_pairs_within(
                    scene,
                    2.0,
                    opts,
                    pairs.as_mut_ptr(),
                    3,
                    &mut count,
                    &mut stats,
                );
                assert_eq!(st == dcol_status::DCOL_OK && count > 0, opts.is_null());
                dcol_scene_pairs_within(
                    scene,
                    2.0,
                    opts,
                    pairs.as_mut_ptr(),
                    0,
                    &mut count,
                    &mut stats,
                );
            }
        }
        std::hint::black_box((
            res, dres, der, g, gm, jm, flag, pairs, results, statuses, count,
        ));
    };
    // The counter works: building a shape allocates.
    let before = heap_ops();
    drop(c_shape(&serde_json::json!({"kind": "sphere", "R": 1.0})));
    assert!(heap_ops() > before);

    run_all(); // warm-up: the scene's reusable buffers grow to their size here
    let before = heap_ops();
    run_all();
    assert_eq!(
        heap_ops() - before,
        0,
        "heap operations in the C extensions"
    );
    // SAFETY: made by dcol_scene_new, freed once.
    unsafe { dcol_scene_free(scene) };
}
