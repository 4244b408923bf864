//! Nothing non-finite crosses the C boundary: at positions near the largest double, with offsets
//! from touching to 1e308, every query of the C ABI either answers with finite numbers
//! (`DCOL_OK`, or `DCOL_ERROR_NOT_CONVERGED` with its last iterate) or returns an error status
//! and leaves its outputs untouched (checked with a sentinel). A pose that is NaN or infinite
//! (an exploding simulation) is an error for `dcol_contacts`, never a crash or a contact.

use dcol::ffi::*;
use std::ptr;

const SENTINEL: f64 = 7.25;

struct CShape(*mut dcol_shape);

impl Drop for CShape {
    fn drop(&mut self) {
        // SAFETY: built by a constructor below, freed exactly once.
        unsafe { dcol_shape_free(self.0) }
    }
}

/// One shape of each kind (the half-space too), through the C constructors.
fn shapes() -> Vec<CShape> {
    let mut out = Vec::new();
    let mut add = |st: dcol_status, s: *mut dcol_shape| {
        assert_eq!(st, dcol_status::DCOL_OK);
        out.push(CShape(s));
    };
    let mut s = ptr::null_mut();
    // SAFETY: every array passed holds the doubles the constructor reads; `s` is writable.
    unsafe {
        add(dcol_shape_new_sphere(0.5, &mut s), s);
        let p = [4.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0];
        add(dcol_shape_new_ellipsoid(p.as_ptr(), &mut s), s);
        add(dcol_shape_new_box(0.5, 0.3, 0.2, &mut s), s);
        let a = [
            1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0, -1.0, -1.0, -1.0, -1.0,
        ];
        add(
            dcol_shape_new_polytope(a.as_ptr(), [1.0; 5].as_ptr(), 5, &mut s),
            s,
        );
        add(dcol_shape_new_capsule(0.3, 1.0, &mut s), s);
        add(dcol_shape_new_cylinder(0.3, 1.0, &mut s), s);
        add(dcol_shape_new_cone(1.0, 0.5, &mut s), s);
        let c = [1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, -1.0];
        add(
            dcol_shape_new_polygon(c.as_ptr(), [0.5; 4].as_ptr(), 4, 0.1, &mut s),
            s,
        );
        add(dcol_shape_new_halfspace(0.5, &mut s), s);
    }
    out
}

fn pose(r: [f64; 3], q: [f64; 4]) -> dcol_pose {
    dcol_pose {
        position: r,
        quaternion: q,
    }
}

/// Checks one call's written doubles: finite on `DCOL_OK` and `DCOL_ERROR_NOT_CONVERGED`, the
/// sentinel everywhere on any other status. Returns a description of a violation.
fn verdict(name: &str, st: dcol_status, out: &[f64]) -> Option<String> {
    let ok = matches!(
        st,
        dcol_status::DCOL_OK | dcol_status::DCOL_ERROR_NOT_CONVERGED
    );
    if ok && !out.iter().all(|v| v.is_finite()) {
        return Some(format!("{name}: {st:?} with a non-finite output"));
    }
    if !ok && !out.iter().all(|v| *v == SENTINEL) {
        return Some(format!("{name}: {st:?} but outputs written"));
    }
    None
}

fn prox_numbers(r: &dcol_proximity_result) -> Vec<f64> {
    let mut v = vec![r.alpha];
    v.extend(r.point);
    v.extend(r.contact1);
    v.extend(r.contact2);
    v
}

fn sentinel_prox() -> dcol_proximity_result {
    dcol_proximity_result {
        alpha: SENTINEL,
        point: [SENTINEL; 3],
        contact1: [SENTINEL; 3],
        contact2: [SENTINEL; 3],
        ..Default::default()
    }
}

/// Every query of the C ABI on one pair of posed shapes; the violations found.
fn every_query(
    s1: *const dcol_shape,
    p1: &dcol_pose,
    s2: *const dcol_shape,
    p2: &dcol_pose,
) -> Vec<String> {
    let bad = std::cell::RefCell::new(Vec::new());
    let check = |name: &str, st: dcol_status, out: Vec<f64>| {
        if let Some(v) = verdict(name, st, &out) {
            bad.borrow_mut().push(v);
        }
    };
    let o = ptr::null();
    // SAFETY: every output points to writable memory of the size the function writes, the
    // shapes are live and the poses valid.
    unsafe {
        let mut r = sentinel_prox();
        let st = dcol_proximity(s1, p1, s2, p2, o, &mut r);
        check("dcol_proximity", st, prox_numbers(&r));
        let (mut r, mut g) = (sentinel_prox(), [SENTINEL; 14]);
        let st = dcol_gradient(s1, p1, s2, p2, o, &mut r, g.as_mut_ptr());
        check("dcol_gradient", st, [prox_numbers(&r), g.to_vec()].concat());
        let (mut r, mut j) = (sentinel_prox(), [SENTINEL; 56]);
        let st = dcol_jacobian(s1, p1, s2, p2, o, &mut r, j.as_mut_ptr());
        check("dcol_jacobian", st, [prox_numbers(&r), j.to_vec()].concat());
        let mut d = dcol_derivatives_result {
            proximity: sentinel_prox(),
            gradient: [SENTINEL; 14],
            jacobian: [[SENTINEL; 14]; 4],
            contact_jacobian1: [[SENTINEL; 14]; 3],
            contact_jacobian2: [[SENTINEL; 14]; 3],
        };
        let st = dcol_derivatives(s1, p1, s2, p2, o, &mut d);
        let mut all = prox_numbers(&d.proximity);
        all.extend(d.gradient);
        all.extend(d.jacobian.iter().flatten());
        all.extend(d.contact_jacobian1.iter().flatten());
        all.extend(d.contact_jacobian2.iter().flatten());
        check("dcol_derivatives", st, all);
        let mut d = dcol_distance_result {
            distance: SENTINEL,
            closest1: [SENTINEL; 3],
            closest2: [SENTINEL; 3],
            normal: [SENTINEL; 3],
            ..Default::default()
        };
        let dist = |d: &dcol_distance_result| {
            [
                vec![d.distance],
                d.closest1.to_vec(),
                d.closest2.to_vec(),
                d.normal.to_vec(),
            ]
            .concat()
        };
        let mut g = [SENTINEL; 14];
        let mut dg = d;
        let st = dcol_distance(s1, p1, s2, p2, o, &mut d);
        check("dcol_distance", st, dist(&d));
        let st = dcol_distance_gradient(s1, p1, s2, p2, o, &mut dg, g.as_mut_ptr());
        check(
            "dcol_distance_gradient",
            st,
            [dist(&dg), g.to_vec()].concat(),
        );
        let mut sd = dcol_signed_distance_result {
            distance: SENTINEL,
            normal: [SENTINEL; 3],
            closest1: [SENTINEL; 3],
            closest2: [SENTINEL; 3],
            ..Default::default()
        };
        let sdn = |d: &dcol_signed_distance_result| {
            [
                vec![d.distance],
                d.normal.to_vec(),
                d.closest1.to_vec(),
                d.closest2.to_vec(),
            ]
            .concat()
        };
        let mut sdg = sd;
        let mut g = [SENTINEL; 14];
        let st = dcol_signed_distance(s1, p1, s2, p2, o, &mut sd);
        check("dcol_signed_distance", st, sdn(&sd));
        let st = dcol_signed_distance_gradient(s1, p1, s2, p2, o, &mut sdg, g.as_mut_ptr());
        check(
            "dcol_signed_distance_gradient",
            st,
            [sdn(&sdg), g.to_vec()].concat(),
        );
        let blank = dcol_contact {
            position: [SENTINEL; 3],
            normal: [SENTINEL; 3],
            depth: SENTINEL,
        };
        let mut cs = [blank; DCOL_MAX_CONTACTS];
        let mut count = 99usize;
        let st = dcol_contacts(
            s1,
            p1,
            s2,
            p2,
            0.1,
            o,
            cs.as_mut_ptr(),
            cs.len(),
            &mut count,
        );
        let n = if st == dcol_status::DCOL_OK || st == dcol_status::DCOL_ERROR_NOT_CONVERGED {
            count.min(cs.len())
        } else {
            if count != 99 {
                bad.borrow_mut()
                    .push(format!("dcol_contacts: {st:?} but *count written"));
            }
            cs.len()
        };
        let nums: Vec<f64> = cs[..n]
            .iter()
            .flat_map(|c| c.position.into_iter().chain(c.normal).chain([c.depth]))
            .collect();
        check("dcol_contacts", st, nums);
        let mut below = 7i32;
        let st = dcol_intersect(s1, p1, s2, p2, o, &mut below);
        let ok = matches!(
            st,
            dcol_status::DCOL_OK | dcol_status::DCOL_ERROR_NOT_CONVERGED
        );
        if ok != (below != 7) || (ok && !(below == 0 || below == 1)) {
            bad.borrow_mut()
                .push(format!("dcol_intersect: {st:?}, *intersecting = {below}"));
        }
        let (mut r, mut st1) = (sentinel_prox(), dcol_status::DCOL_ERROR_INTERNAL);
        let st = dcol_proximity_batch(&s1, p1, &s2, p2, 1, o, 1, &mut r, &mut st1);
        assert_eq!(st, dcol_status::DCOL_OK);
        check("dcol_proximity_batch", st1, prox_numbers(&r));
    }
    bad.into_inner()
}

/// The reported case: a padded polygon and a capsule both near x = −1e308 got a contact
/// position of −inf on `DCOL_OK` (the midpoint of the two surface points was `(a + b)/2`).
#[test]
fn contacts_near_the_largest_double_are_finite() {
    let all = shapes();
    let (polygon, capsule) = (all[7].0, all[4].0);
    let p1 = pose([-1e308, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    let p2 = pose([-1e308, 0.2, 0.3], [1.0, 0.0, 0.0, 0.0]);
    let blank = dcol_contact::default();
    let mut cs = [blank; 4];
    let mut count = 0usize;
    // SAFETY: live shapes, valid poses, 4 writable contacts and a writable count.
    let st = unsafe {
        dcol_contacts(
            polygon,
            &p1,
            capsule,
            &p2,
            0.0,
            ptr::null(),
            cs.as_mut_ptr(),
            4,
            &mut count,
        )
    };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert!(count >= 1);
    for c in &cs[..count] {
        assert!(c.position.iter().all(|v| v.is_finite()), "{c:?}");
        // The capsule (radius 0.3, 0.3 above the polygon's plane, pad 0.1) sinks 0.1 in.
        assert!(
            (c.position[0] + 1e308).abs() <= 1e292 && (c.depth - 0.1).abs() < 1e-9,
            "{c:?}"
        );
    }
}

/// Every query at positions near the largest double, offsets from touching to 1e308, all pairs
/// of kinds (the half-space included): finite answers or an error with nothing written.
#[test]
fn every_query_is_finite_or_an_error_near_the_largest_double() {
    let all = shapes();
    let xs = [
        f64::MAX,
        -f64::MAX,
        1.7e308,
        -1.7e308,
        1e308,
        -1e308,
        -8.99e307,
        1e300,
    ];
    let offsets = [
        [0.3, 0.1, 0.0],
        [1.5, 0.2, 0.1],
        [0.0, 0.0, 0.0],
        [1e300, 0.0, 0.0],
        [-1e308, 0.0, 0.0],
    ];
    let mut bad = Vec::new();
    let mut calls = 0;
    for (i, a) in all.iter().enumerate() {
        for (j, b) in all.iter().enumerate() {
            if i == 8 && j == 8 {
                continue; // Two half-spaces: an error for every query (tests/halfspace.rs).
            }
            for &x in &xs {
                for off in &offsets {
                    for axis in [0, 1] {
                        let mut r1 = [0.1, -0.2, 0.3];
                        r1[axis] = x;
                        let r2 = [0, 1, 2].map(|k| r1[k] + off[k]);
                        if !r2.iter().all(|v| v.is_finite()) {
                            continue;
                        }
                        let p1 = pose(r1, [0.9, 0.1, 0.2, 0.3]);
                        let p2 = pose(r2, [0.8, -0.3, 0.1, 0.2]);
                        calls += 1;
                        for v in every_query(a.0, &p1, b.0, &p2) {
                            bad.push(format!("kinds {i}-{j}, r1 {r1:?}, r2 {r2:?}: {v}"));
                        }
                    }
                }
            }
        }
    }
    for b in bad.iter().take(30) {
        println!("{b}");
    }
    assert!(calls > 5000);
    assert!(bad.is_empty(), "{} violations", bad.len());
}

/// A pose from an exploding simulation (a NaN or infinite position or quaternion component):
/// `dcol_contacts` returns `DCOL_ERROR_INVALID_POSE` naming it, and writes neither the contacts
/// nor the count; so does every other query (checked with `every_query`'s sentinels).
#[test]
fn contacts_reject_nan_and_infinite_poses() {
    let all = shapes();
    let good = pose([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]);
    for bad_value in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for k in 0..7 {
            let mut p = pose([0.1, 0.2, 0.3], [1.0, 0.0, 0.0, 0.0]);
            if k < 3 {
                p.position[k] = bad_value;
            } else {
                p.quaternion[k - 3] = bad_value;
            }
            for (i, a) in all.iter().enumerate() {
                for (j, b) in all.iter().enumerate() {
                    if i == 8 && j == 8 {
                        continue;
                    }
                    for (p1, p2) in [(&p, &good), (&good, &p)] {
                        let mut cs = [dcol_contact {
                            position: [SENTINEL; 3],
                            normal: [SENTINEL; 3],
                            depth: SENTINEL,
                        }; 4];
                        let mut count = 99usize;
                        // SAFETY: live shapes, valid pose structs, 4 writable contacts.
                        let st = unsafe {
                            dcol_contacts(
                                a.0,
                                p1,
                                b.0,
                                p2,
                                0.1,
                                ptr::null(),
                                cs.as_mut_ptr(),
                                4,
                                &mut count,
                            )
                        };
                        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_POSE);
                        assert_eq!(count, 99);
                        assert!(cs
                            .iter()
                            .all(|c| c.depth == SENTINEL && c.position == [SENTINEL; 3]));
                        let errs = every_query(a.0, p1, b.0, p2);
                        assert!(errs.is_empty(), "{errs:?}");
                    }
                }
            }
        }
    }
}
