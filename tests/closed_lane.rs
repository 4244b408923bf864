//! The C ABI's closed-form lane (`dcol_proximity` and `dcol_distance` on the pairs answered in
//! closed form, straight from the poses' numbers): every answer must be the full query's, bit
//! for bit (the Rust API's, which does not take the lane), on random poses with quaternions of
//! any length (1e-3 to 1e3, and 1e-160, which the lane leaves to the checked constructor),
//! separated, near and overlapping, under NULL, default and other valid options; sphere–sphere
//! must match the analytic α* = ‖r₂ − r₁‖/(R₁ + R₂) and d* = ‖r₂ − r₁‖ − R₁ − R₂; and every
//! check the C ABI promises must still hold where the lane would otherwise answer (NULL
//! pointers, non-finite or zero poses, invalid options, another method), with nothing written.

mod common;

use common::xorshift::Rng;
use dcol::ffi::cache::dcol_cache;
use dcol::ffi::proximity::dcol_proximity_cached;
use dcol::ffi::*;
use dcol::{distance, proximity, Options, Pose, Shape};
use std::ptr;

/// The attitudes this file draws: uniform directions, lengths from 1e-3 to 1e3.
impl Rng {
    fn raw_quaternion(&mut self) -> [f64; 4] {
        let len = 10f64.powf(self.range(-3.0, 3.0));
        let v: [f64; 4] = std::array::from_fn(|_| self.range(-1.0, 1.0));
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / n * len)
    }
}

/// A shape built through the C constructors and the same shape through the Rust API.
struct Both {
    c: *mut dcol_shape,
    rust: Shape,
    name: &'static str,
}

impl Drop for Both {
    fn drop(&mut self) {
        // SAFETY: built by a C constructor below, freed exactly once.
        unsafe { dcol_shape_free(self.c) }
    }
}

fn shapes() -> Vec<Both> {
    let mut out = Vec::new();
    let mut add = |name, st: dcol_status, c: *mut dcol_shape, rust: Shape| {
        assert_eq!(st, dcol_status::DCOL_OK, "{name}");
        out.push(Both { c, rust, name });
    };
    let mut c = ptr::null_mut();
    // SAFETY: `c` is a valid out-pointer for each constructor.
    unsafe {
        let st = dcol_shape_new_sphere(0.5, &mut c);
        add("sphere", st, c, Shape::sphere(0.5).unwrap());
        let st = dcol_shape_new_sphere(0.2, &mut c);
        add("small sphere", st, c, Shape::sphere(0.2).unwrap());
        let st = dcol_shape_new_capsule(0.3, 0.8, &mut c);
        add("capsule", st, c, Shape::capsule(0.3, 0.8).unwrap());
        let st = dcol_shape_new_box(0.6, 0.4, 0.3, &mut c);
        add("box", st, c, Shape::cuboid(0.6, 0.4, 0.3).unwrap());
        let st = dcol_shape_new_cylinder(0.4, 0.9, &mut c);
        add("cylinder", st, c, Shape::cylinder(0.4, 0.9).unwrap());
        let st = dcol_shape_new_cone(0.9, 0.5, &mut c);
        add("cone", st, c, Shape::cone(0.9, 0.5).unwrap());
        let p = [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 4.0]];
        let st = dcol_shape_new_ellipsoid(p.as_flattened().as_ptr(), &mut c);
        add("ellipsoid", st, c, Shape::ellipsoid(p).unwrap());
        let a = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [-0.3, -0.3, -1.0],
        ];
        let b = [0.5, 0.4, 0.6, 0.3, 0.5, 0.4];
        let st = dcol_shape_new_polytope(a.as_flattened().as_ptr(), b.as_ptr(), 6, &mut c);
        add("polytope", st, c, Shape::polytope(&a, &b).unwrap());
    }
    out
}

fn same3(a: &[f64; 3], b: &dcol::Vec3) -> bool {
    a[0] == b.x && a[1] == b.y && a[2] == b.z
}

/// Every pair, both orders, random poses at separations from overlapping to far apart: the C
/// answers are the Rust API's exactly, under NULL, default and a tighter tolerance.
#[test]
fn c_answers_are_the_full_querys() {
    let shapes = shapes();
    let mut rng = Rng(0x5eed_c105_ed1a_9e01);
    let mut tight = dcol_options_default();
    tight.tolerance = 1e-10;
    let mut checked = 0;
    for one in &shapes {
        for two in &shapes {
            for i in 0..200 {
                let scale = [0.3, 0.9, 1.1, 2.0, 6.0][i % 5];
                let dir = rng.unit();
                let q1 = if i % 17 == 0 {
                    // Squared norm below the smallest normal double: the checked constructor.
                    [1e-160, 0.0, 1e-160, 0.0]
                } else {
                    rng.raw_quaternion()
                };
                let c1 = dcol_pose {
                    position: [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.25],
                    quaternion: q1,
                };
                let off = dir * scale * rng.range(0.5, 1.5);
                let c2 = dcol_pose {
                    position: [
                        c1.position[0] + off.x,
                        c1.position[1] + off.y,
                        c1.position[2] + off.z,
                    ],
                    quaternion: rng.raw_quaternion(),
                };
                let p1 = Pose::new(c1.position, c1.quaternion).unwrap();
                let p2 = Pose::new(c2.position, c2.quaternion).unwrap();
                for (opts, rust_opts) in [
                    (ptr::null(), Options::default()),
                    (&tight as *const dcol_options, {
                        Options {
                            tolerance: 1e-10,
                            ..Options::default()
                        }
                    }),
                ] {
                    let what = format!("{} {} case {i}", one.name, two.name);
                    let want = proximity(&one.rust, &p1, &two.rust, &p2, &rust_opts).unwrap();
                    let mut got = dcol_proximity_result::default();
                    // SAFETY: live shapes, valid poses, options and result.
                    let st = unsafe { dcol_proximity(one.c, &c1, two.c, &c2, opts, &mut got) };
                    assert_eq!(st, dcol_status::DCOL_OK, "{what}");
                    assert_eq!(got.alpha, want.alpha, "{what}");
                    assert!(same3(&got.point, &want.point), "{what}");
                    assert!(same3(&got.contact1, &want.contact1), "{what}");
                    assert!(same3(&got.contact2, &want.contact2), "{what}");
                    assert_eq!(got.iterations, want.iterations, "{what}");
                    // The solver and derivative codes: the full path's (its result as the C
                    // boundary converts it).
                    let full = dcol_proximity_result::from(&want);
                    assert_eq!(
                        (got.solver, got.derivatives),
                        (full.solver, full.derivatives),
                        "{what}"
                    );
                    // The cached call: the same answer, bit for bit, from a cache of any bits,
                    // which the lane leaves as it was (a closed form keeps nothing).
                    let mut junk = dcol_cache::default();
                    // SAFETY: `dcol_cache` is plain old data; any bits are a valid cache.
                    unsafe {
                        let bytes = &mut junk as *mut dcol_cache as *mut u8;
                        for k in 0..std::mem::size_of::<dcol_cache>() {
                            *bytes.add(k) = (rng.range(0.0, 256.0) as u8) ^ (k as u8);
                        }
                    }
                    let bytes = |c: &dcol_cache| {
                        // SAFETY: a live cache read as its bytes.
                        unsafe {
                            std::slice::from_raw_parts(
                                c as *const dcol_cache as *const u8,
                                std::mem::size_of::<dcol_cache>(),
                            )
                        }
                        .to_vec()
                    };
                    let before = bytes(&junk);
                    let mut cached = dcol_proximity_result::default();
                    // SAFETY: as above; a live cache.
                    let st = unsafe {
                        dcol_proximity_cached(one.c, &c1, two.c, &c2, opts, &mut junk, &mut cached)
                    };
                    assert_eq!(st, dcol_status::DCOL_OK, "{what}");
                    assert_eq!(cached.alpha.to_bits(), got.alpha.to_bits(), "{what}");
                    assert_eq!(cached.point, got.point, "{what}");
                    assert_eq!(
                        (cached.solver, cached.derivatives),
                        (got.solver, got.derivatives)
                    );
                    if one.name.contains("sphere") && two.name.contains("sphere") {
                        assert_eq!(before, bytes(&junk), "{what}: the lane left the cache");
                    }
                    let want_d = distance(&one.rust, &p1, &two.rust, &p2, &rust_opts).unwrap();
                    let mut got_d = dcol_distance_result::default();
                    // SAFETY: as above.
                    let st = unsafe { dcol_distance(one.c, &c1, two.c, &c2, opts, &mut got_d) };
                    assert_eq!(st, dcol_status::DCOL_OK, "{what}");
                    assert_eq!(got_d.distance, want_d.distance, "{what}");
                    assert!(same3(&got_d.closest1, &want_d.closest1), "{what}");
                    assert!(same3(&got_d.closest2, &want_d.closest2), "{what}");
                    assert_eq!(got_d.iterations, want_d.iterations, "{what}");
                    assert!(same3(&got_d.normal, &want_d.normal), "{what}");
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 8 * 8 * 200 * 2);
}

/// Sphere–sphere against its analytic answers (independent of every solver).
#[test]
fn sphere_pairs_match_the_analytic_answers() {
    let mut rng = Rng(0x0a11_7a1c_5ec0_0001);
    let (r1, r2) = (0.5, 0.2);
    let mut a = ptr::null_mut();
    let mut b = ptr::null_mut();
    // SAFETY: valid out-pointers.
    unsafe {
        assert_eq!(dcol_shape_new_sphere(r1, &mut a), dcol_status::DCOL_OK);
        assert_eq!(dcol_shape_new_sphere(r2, &mut b), dcol_status::DCOL_OK);
    }
    for _ in 0..2000 {
        let len = 10f64.powf(rng.range(-0.5, 1.0));
        let off = rng.unit() * len;
        let c1 = dcol_pose {
            position: [
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ],
            quaternion: rng.raw_quaternion(),
        };
        let c2 = dcol_pose {
            position: [
                c1.position[0] + off.x,
                c1.position[1] + off.y,
                c1.position[2] + off.z,
            ],
            quaternion: rng.raw_quaternion(),
        };
        let gap = (0..3)
            .map(|k| (c2.position[k] - c1.position[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let mut p = dcol_proximity_result::default();
        // SAFETY: live shapes, valid poses and result.
        let st = unsafe { dcol_proximity(a, &c1, b, &c2, ptr::null(), &mut p) };
        assert_eq!(st, dcol_status::DCOL_OK);
        let alpha = gap / (r1 + r2);
        assert!(
            (p.alpha - alpha).abs() <= 1e-14 * alpha,
            "{} {alpha}",
            p.alpha
        );
        assert_eq!(p.solver, DCOL_SOLVER_CLOSED_FORM);
        // p₁ = r₁ + R₁ (r₂ − r₁)/‖r₂ − r₁‖.
        for k in 0..3 {
            let want = c1.position[k] + r1 * (c2.position[k] - c1.position[k]) / gap;
            assert!(
                (p.contact1[k] - want).abs() <= 1e-14 * (1.0 + gap),
                "contact1"
            );
        }
        if gap > r1 + r2 {
            let mut d = dcol_distance_result::default();
            // SAFETY: as above.
            let st = unsafe { dcol_distance(a, &c1, b, &c2, ptr::null(), &mut d) };
            assert_eq!(st, dcol_status::DCOL_OK);
            let want = gap - r1 - r2;
            assert!(
                (d.distance - want).abs() <= 1e-14 * (1.0 + gap),
                "{} {want}",
                d.distance
            );
        }
    }
    // SAFETY: built above, freed once.
    unsafe {
        dcol_shape_free(a);
        dcol_shape_free(b);
    }
}

/// What the lane must leave to the full query's checks: each bad input gets its status and
/// nothing is written; another method or smoothing gets that method's answer.
#[test]
fn the_c_abi_checks_still_hold() {
    let mut a = ptr::null_mut();
    let mut b = ptr::null_mut();
    // SAFETY: valid out-pointers.
    unsafe {
        assert_eq!(dcol_shape_new_sphere(0.5, &mut a), dcol_status::DCOL_OK);
        assert_eq!(
            dcol_shape_new_capsule(0.3, 0.8, &mut b),
            dcol_status::DCOL_OK
        );
    }
    let good1 = dcol_pose {
        position: [0.0, 0.0, 0.0],
        quaternion: [1.0, 0.0, 0.0, 0.0],
    };
    let good2 = dcol_pose {
        position: [2.0, 0.5, 0.0],
        quaternion: [0.3, 0.1, -0.2, 0.9],
    };
    let sentinel = dcol_proximity_result {
        alpha: -7.0,
        ..Default::default()
    };
    let sentinel_d = dcol_distance_result {
        distance: -7.0,
        ..Default::default()
    };
    let run = |s1: *const dcol_shape,
               p1: &dcol_pose,
               s2: *const dcol_shape,
               p2: &dcol_pose,
               o: *const dcol_options| {
        let (mut r, mut d) = (sentinel, sentinel_d);
        // SAFETY: shapes NULL or live, poses and results valid.
        let st = unsafe { dcol_proximity(s1, p1, s2, p2, o, &mut r) };
        // SAFETY: as above.
        let st_d = unsafe { dcol_distance(s1, p1, s2, p2, o, &mut d) };
        (st, r, st_d, d)
    };
    let expect_error = |case: &str,
                        out: (
        dcol_status,
        dcol_proximity_result,
        dcol_status,
        dcol_distance_result,
    ),
                        status| {
        assert_eq!(out.0, status, "{case}: proximity");
        assert_eq!(out.1, sentinel, "{case}: proximity wrote a result");
        assert_eq!(out.2, status, "{case}: distance");
        assert_eq!(out.3, sentinel_d, "{case}: distance wrote a result");
    };
    use dcol_status::*;
    let nan = dcol_pose {
        position: [2.0, f64::NAN, 0.0],
        ..good2
    };
    expect_error(
        "NaN position",
        run(a, &good1, b, &nan, ptr::null()),
        DCOL_ERROR_INVALID_POSE,
    );
    let inf_q = dcol_pose {
        quaternion: [f64::INFINITY, 0.0, 0.0, 0.0],
        ..good2
    };
    expect_error(
        "infinite quaternion",
        run(a, &good1, b, &inf_q, ptr::null()),
        DCOL_ERROR_INVALID_POSE,
    );
    let zero_q = dcol_pose {
        quaternion: [0.0; 4],
        ..good1
    };
    expect_error(
        "zero quaternion",
        run(a, &zero_q, b, &good2, ptr::null()),
        DCOL_ERROR_INVALID_POSE,
    );
    expect_error(
        "NULL shape",
        run(ptr::null(), &good1, b, &good2, ptr::null()),
        DCOL_ERROR_NULL_POINTER,
    );
    for (field, bad) in [
        (
            "tolerance 0",
            dcol_options {
                tolerance: 0.0,
                ..dcol_options_default()
            },
        ),
        (
            "tolerance NaN",
            dcol_options {
                tolerance: f64::NAN,
                ..dcol_options_default()
            },
        ),
        (
            "no iterations",
            dcol_options {
                max_iterations: 0,
                ..dcol_options_default()
            },
        ),
        (
            "method 7",
            dcol_options {
                method: 7,
                ..dcol_options_default()
            },
        ),
        (
            "smoothing -1",
            dcol_options {
                smoothing: -1.0,
                ..dcol_options_default()
            },
        ),
    ] {
        expect_error(
            field,
            run(a, &good1, b, &good2, &bad),
            DCOL_ERROR_INVALID_OPTIONS,
        );
    }
    // NULL poses and results.
    let mut r = sentinel;
    // SAFETY: NULL pose and result pointers are what is tested; the rest valid.
    unsafe {
        assert_eq!(
            dcol_proximity(a, ptr::null(), b, &good2, ptr::null(), &mut r),
            DCOL_ERROR_NULL_POINTER
        );
        assert_eq!(
            dcol_proximity(a, &good1, b, ptr::null(), ptr::null(), &mut r),
            DCOL_ERROR_NULL_POINTER
        );
        assert_eq!(
            dcol_proximity(a, &good1, b, &good2, ptr::null(), ptr::null_mut()),
            DCOL_ERROR_NULL_POINTER
        );
        let mut d = sentinel_d;
        assert_eq!(
            dcol_distance(a, &good1, b, &good2, ptr::null(), ptr::null_mut()),
            DCOL_ERROR_NULL_POINTER
        );
        assert_eq!(
            dcol_distance(a, ptr::null(), b, &good2, ptr::null(), &mut d),
            DCOL_ERROR_NULL_POINTER
        );
        assert_eq!(d, sentinel_d);
    }
    assert_eq!(r, sentinel);
    // The interior-point method when asked for: its answer, not the closed form's.
    let ipm = dcol_options {
        method: 1, // DCOL_METHOD_INTERIOR_POINT
        ..dcol_options_default()
    };
    let (st, r, st_d, _) = run(a, &good1, b, &good2, &ipm);
    assert_eq!((st, st_d), (DCOL_OK, DCOL_OK));
    assert_eq!(r.solver, DCOL_SOLVER_INTERIOR_POINT);
    assert!(r.iterations > 0);
    let (st, r, _, _) = run(a, &good1, b, &good2, ptr::null());
    assert_eq!(st, DCOL_OK);
    assert_eq!(r.solver, DCOL_SOLVER_CLOSED_FORM);
    // Smoothing asks for the central path's point (above the exact α*).
    let smooth = dcol_options {
        smoothing: 1e-3,
        ..dcol_options_default()
    };
    let (st, s, _, _) = run(a, &good1, b, &good2, &smooth);
    assert_eq!(st, DCOL_OK);
    assert_eq!(s.solver, DCOL_SOLVER_INTERIOR_POINT);
    assert!(s.alpha > r.alpha);
    // Coincident origins: α* = 0 (not the lane's), the distance overlap.
    let (st, z, st_d, d) = run(a, &good1, b, &good1, ptr::null());
    assert_eq!((st, st_d), (DCOL_OK, DCOL_OK));
    assert_eq!(z.alpha, 0.0);
    assert_eq!(d.distance, 0.0);
    // SAFETY: built above, freed once.
    unsafe {
        dcol_shape_free(a);
        dcol_shape_free(b);
    }
}
