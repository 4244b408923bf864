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
    let Some(dir) = reference_dir() else { return };
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
