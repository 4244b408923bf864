//! Every query of the C ABI on one fuzzed case, with its outputs pre-filled by a sentinel:
//! on `DCOL_OK` (and `DCOL_ERROR_NOT_CONVERGED`, which carries the last iterate) every number
//! written must be finite; on any other status nothing may be written. The statuses are
//! returned for the caller to compare with the Rust API.

use dcol::ffi::{self, dcol_status};
use std::ptr;

/// What the outputs are filled with before a call (finite, and not a plausible answer).
const SENTINEL: f64 = -7.0e-77;

/// One case: two C shapes, their poses (and MRP forms, when the fuzzer gave them), options,
/// the contact margin, the `alpha_below` and scene thresholds.
pub struct Case<'a> {
    pub shape1: *const ffi::dcol_shape,
    pub shape2: *const ffi::dcol_shape,
    pub pose1: ffi::dcol_pose,
    pub pose2: ffi::dcol_pose,
    /// `(position1, mrp1, position2, mrp2)`.
    pub mrp: Option<([f64; 3], [f64; 3], [f64; 3], [f64; 3])>,
    pub options: ffi::dcol_options,
    pub margin: f64,
    pub threshold: f64,
    /// The case, for the messages.
    pub what: &'a str,
}

/// The statuses and answers of the C queries the caller compares with the Rust API (the
/// others are checked here: no `DCOL_ERROR_INTERNAL`, finite numbers or nothing written, the
/// batch's results equal to `dcol_proximity`'s).
#[derive(Clone, Copy, Debug)]
pub struct Statuses {
    pub proximity: dcol_status,
    pub distance: dcol_status,
    pub signed_distance: dcol_status,
    pub contacts: dcol_status,
    pub intersect: dcol_status,
    pub alpha_below: dcol_status,
    /// α*, the signed distance and the number of contacts.
    pub alpha: f64,
    pub signed: f64,
    pub contact_count: usize,
}

fn answered(st: dcol_status) -> bool {
    matches!(
        st,
        dcol_status::DCOL_OK | dcol_status::DCOL_ERROR_NOT_CONVERGED
    )
}

/// The invariant for one call's written doubles.
fn check(name: &str, what: &str, st: dcol_status, out: &[f64]) {
    assert!(
        st != dcol_status::DCOL_ERROR_INTERNAL,
        "[capi-internal {name}] {what}: DCOL_ERROR_INTERNAL"
    );
    if answered(st) {
        assert!(
            out.iter().all(|v| v.is_finite()),
            "[capi-nonfinite {name}] {what}: {st:?} with a non-finite output {out:?}"
        );
    } else {
        assert!(
            out.iter().all(|v| v.to_bits() == SENTINEL.to_bits()),
            "[capi-written-on-error {name}] {what}: {st:?} but outputs written {out:?}"
        );
    }
}

fn blank_proximity() -> ffi::dcol_proximity_result {
    ffi::dcol_proximity_result {
        alpha: SENTINEL,
        point: [SENTINEL; 3],
        contact1: [SENTINEL; 3],
        contact2: [SENTINEL; 3],
        ..Default::default()
    }
}

fn proximity_numbers(r: &ffi::dcol_proximity_result) -> Vec<f64> {
    let mut v = vec![r.alpha];
    v.extend(r.point);
    v.extend(r.contact1);
    v.extend(r.contact2);
    v
}

/// Derivative arrays written only with finite entries: on `DCOL_ERROR_NOT_CONVERGED` they may
/// be left as they were. `out` holds them; the sentinel check then applies to the result only.
fn derivative_check(name: &str, what: &str, st: dcol_status, result: &[f64], arrays: &[f64]) {
    check(name, what, st, result);
    let untouched = arrays.iter().all(|v| v.to_bits() == SENTINEL.to_bits());
    match st {
        dcol_status::DCOL_OK => check(name, what, st, arrays),
        dcol_status::DCOL_ERROR_NOT_CONVERGED if !untouched => check(name, what, st, arrays),
        dcol_status::DCOL_ERROR_NOT_CONVERGED => {}
        _ => check(name, what, st, arrays),
    }
}

/// Runs every C query on `case`.
pub fn every_query(case: &Case) -> Statuses {
    let (s1, s2, what) = (case.shape1, case.shape2, case.what);
    let (p1, p2, o) = (&case.pose1, &case.pose2, &case.options as *const _);
    // SAFETY (for every call below): the shapes are live, the poses and options are valid
    // structs, and each output points to writable memory of the size the function writes.
    let mut r = blank_proximity();
    let proximity = unsafe { ffi::dcol_proximity(s1, p1, s2, p2, o, &mut r) };
    check("dcol_proximity", what, proximity, &proximity_numbers(&r));
    let alpha = r.alpha;

    let (mut r, mut g) = (blank_proximity(), [SENTINEL; 14]);
    let gradient = unsafe { ffi::dcol_gradient(s1, p1, s2, p2, o, &mut r, g.as_mut_ptr()) };
    derivative_check("dcol_gradient", what, gradient, &proximity_numbers(&r), &g);

    let (mut r, mut j) = (blank_proximity(), [SENTINEL; 56]);
    let jacobian = unsafe { ffi::dcol_jacobian(s1, p1, s2, p2, o, &mut r, j.as_mut_ptr()) };
    derivative_check("dcol_jacobian", what, jacobian, &proximity_numbers(&r), &j);

    let mut d = ffi::dcol_derivatives_result {
        proximity: blank_proximity(),
        gradient: [SENTINEL; 14],
        jacobian: [[SENTINEL; 14]; 4],
        contact_jacobian1: [[SENTINEL; 14]; 3],
        contact_jacobian2: [[SENTINEL; 14]; 3],
    };
    let derivatives = unsafe { ffi::dcol_derivatives(s1, p1, s2, p2, o, &mut d) };
    let arrays: Vec<f64> = d
        .gradient
        .iter()
        .chain(d.jacobian.iter().flatten())
        .chain(d.contact_jacobian1.iter().flatten())
        .chain(d.contact_jacobian2.iter().flatten())
        .copied()
        .collect();
    derivative_check(
        "dcol_derivatives",
        what,
        derivatives,
        &proximity_numbers(&d.proximity),
        &arrays,
    );

    if let Some((r1, m1, r2, m2)) = case.mrp {
        let (mut r, mut g) = (blank_proximity(), [SENTINEL; 12]);
        let st = unsafe {
            ffi::dcol_gradient_mrp(
                s1,
                r1.as_ptr(),
                m1.as_ptr(),
                s2,
                r2.as_ptr(),
                m2.as_ptr(),
                o,
                &mut r,
                g.as_mut_ptr(),
            )
        };
        derivative_check("dcol_gradient_mrp", what, st, &proximity_numbers(&r), &g);
        let (mut r, mut j) = (blank_proximity(), [SENTINEL; 48]);
        let st = unsafe {
            ffi::dcol_jacobian_mrp(
                s1,
                r1.as_ptr(),
                m1.as_ptr(),
                s2,
                r2.as_ptr(),
                m2.as_ptr(),
                o,
                &mut r,
                j.as_mut_ptr(),
            )
        };
        derivative_check("dcol_jacobian_mrp", what, st, &proximity_numbers(&r), &j);
    }

    let blank_distance = ffi::dcol_distance_result {
        distance: SENTINEL,
        closest1: [SENTINEL; 3],
        closest2: [SENTINEL; 3],
        normal: [SENTINEL; 3],
        ..Default::default()
    };
    let dn = |d: &ffi::dcol_distance_result| {
        let mut v = vec![d.distance];
        v.extend(d.closest1);
        v.extend(d.closest2);
        v.extend(d.normal);
        v
    };
    let mut d = blank_distance;
    let distance = unsafe { ffi::dcol_distance(s1, p1, s2, p2, o, &mut d) };
    check("dcol_distance", what, distance, &dn(&d));
    let (mut d, mut g) = (blank_distance, [SENTINEL; 14]);
    let distance_gradient =
        unsafe { ffi::dcol_distance_gradient(s1, p1, s2, p2, o, &mut d, g.as_mut_ptr()) };
    derivative_check(
        "dcol_distance_gradient",
        what,
        distance_gradient,
        &dn(&d),
        &g,
    );

    let blank_signed = ffi::dcol_signed_distance_result {
        distance: SENTINEL,
        normal: [SENTINEL; 3],
        closest1: [SENTINEL; 3],
        closest2: [SENTINEL; 3],
        ..Default::default()
    };
    let sn = |d: &ffi::dcol_signed_distance_result| {
        let mut v = vec![d.distance];
        v.extend(d.normal);
        v.extend(d.closest1);
        v.extend(d.closest2);
        v
    };
    let mut d = blank_signed;
    let signed_distance = unsafe { ffi::dcol_signed_distance(s1, p1, s2, p2, o, &mut d) };
    check("dcol_signed_distance", what, signed_distance, &sn(&d));
    let signed = d.distance;
    let (mut d, mut g) = (blank_signed, [SENTINEL; 14]);
    let signed_distance_gradient =
        unsafe { ffi::dcol_signed_distance_gradient(s1, p1, s2, p2, o, &mut d, g.as_mut_ptr()) };
    derivative_check(
        "dcol_signed_distance_gradient",
        what,
        signed_distance_gradient,
        &sn(&d),
        &g,
    );

    let blank_contact = ffi::dcol_contact {
        position: [SENTINEL; 3],
        normal: [SENTINEL; 3],
        depth: SENTINEL,
    };
    let mut cs = [blank_contact; ffi::DCOL_MAX_CONTACTS];
    let mut count = usize::MAX;
    let contacts = unsafe {
        ffi::dcol_contacts(
            s1,
            p1,
            s2,
            p2,
            case.margin,
            o,
            cs.as_mut_ptr(),
            cs.len(),
            &mut count,
        )
    };
    let written = if answered(contacts) {
        assert!(
            count <= cs.len(),
            "[capi-contacts-count] {what}: *count = {count}"
        );
        count
    } else {
        assert_eq!(
            count,
            usize::MAX,
            "[capi-written-on-error dcol_contacts] {what}: {contacts:?} but *count written"
        );
        cs.len()
    };
    let nums: Vec<f64> = cs[..written]
        .iter()
        .flat_map(|c| c.position.into_iter().chain(c.normal).chain([c.depth]))
        .collect();
    check("dcol_contacts", what, contacts, &nums);
    if answered(contacts) {
        // The slots after the count are untouched.
        let rest: Vec<f64> = cs[written..]
            .iter()
            .flat_map(|c| c.position.into_iter().chain(c.normal).chain([c.depth]))
            .collect();
        assert!(
            rest.iter().all(|v| v.to_bits() == SENTINEL.to_bits()),
            "[capi-contacts-beyond-count] {what}"
        );
    }

    let flag = |name: &str, st: dcol_status, v: i32| {
        assert!(
            st != dcol_status::DCOL_ERROR_INTERNAL,
            "[capi-internal {name}] {what}: DCOL_ERROR_INTERNAL"
        );
        if answered(st) {
            assert!(v == 0 || v == 1, "[capi-flag {name}] {what}: {st:?}, {v}");
        } else {
            assert_eq!(v, 7, "[capi-written-on-error {name}] {what}: {st:?}, {v}");
        }
    };
    let mut v = 7i32;
    let intersect = unsafe { ffi::dcol_intersect(s1, p1, s2, p2, o, &mut v) };
    flag("dcol_intersect", intersect, v);
    let mut v = 7i32;
    let alpha_below = unsafe { ffi::dcol_alpha_below(s1, p1, s2, p2, case.threshold, o, &mut v) };
    flag("dcol_alpha_below", alpha_below, v);

    // The batch: the pair twice, on two threads; each result is dcol_proximity's, bit for bit.
    let shapes1 = [s1, s1];
    let shapes2 = [s2, s2];
    let (poses1, poses2) = ([*p1, *p1], [*p2, *p2]);
    let mut results = [blank_proximity(), blank_proximity()];
    let mut statuses = [dcol_status::DCOL_ERROR_INTERNAL; 2];
    let call = unsafe {
        ffi::dcol_proximity_batch(
            shapes1.as_ptr(),
            poses1.as_ptr(),
            shapes2.as_ptr(),
            poses2.as_ptr(),
            2,
            o,
            2,
            results.as_mut_ptr(),
            statuses.as_mut_ptr(),
        )
    };
    if call == dcol_status::DCOL_OK {
        for (st, r) in statuses.iter().zip(&results) {
            check("dcol_proximity_batch", what, *st, &proximity_numbers(r));
            assert_eq!(
                *st, proximity,
                "[capi-batch-status] {what}: batch {st:?}, dcol_proximity {proximity:?}"
            );
            if answered(*st) {
                assert_eq!(
                    r.alpha.to_bits(),
                    alpha.to_bits(),
                    "[capi-batch-alpha] {what}"
                );
            }
        }
    } else {
        // Only the options can fail the whole call here; nothing is written then.
        assert_eq!(
            call,
            dcol_status::DCOL_ERROR_INVALID_OPTIONS,
            "[capi-batch-call] {what}"
        );
        for r in &results {
            check("dcol_proximity_batch", what, call, &proximity_numbers(r));
        }
    }

    scene_pairs(case);
    Statuses {
        proximity,
        distance,
        signed_distance,
        contacts,
        intersect,
        alpha_below,
        alpha,
        signed,
        contact_count: if answered(contacts) { count } else { 0 },
    }
}

/// A scene of the two bodies: `dcol_scene_pairs_within(threshold)`, its pair (if reported)
/// finite, nothing written on error; the body poses swapped (`dcol_scene_set_pose`) and the
/// step repeated.
fn scene_pairs(case: &Case) {
    let what = case.what;
    let mut scene = ptr::null_mut();
    // SAFETY: `scene` is a writable pointer; freed below.
    let st = unsafe { ffi::dcol_scene_new(&mut scene) };
    assert_eq!(st, dcol_status::DCOL_OK, "[capi-scene-new] {what}");
    let mut ids = [usize::MAX; 2];
    // SAFETY: a live scene, live shapes, valid poses, writable ids.
    let added = unsafe {
        [
            ffi::dcol_scene_add(scene, case.shape1, &case.pose1, &mut ids[0]),
            ffi::dcol_scene_add(scene, case.shape2, &case.pose2, &mut ids[1]),
        ]
    };
    for st in added {
        assert!(
            st == dcol_status::DCOL_OK || st == dcol_status::DCOL_ERROR_INVALID_SHAPE,
            "[capi-scene-add] {what}: {st:?}"
        );
    }
    for round in 0..2 {
        if round == 1 && added.iter().all(|st| *st == dcol_status::DCOL_OK) {
            // Swap the poses.
            // SAFETY: a live scene, valid poses.
            let moved = unsafe {
                [
                    ffi::dcol_scene_set_pose(scene, ids[0], &case.pose2),
                    ffi::dcol_scene_set_pose(scene, ids[1], &case.pose1),
                ]
            };
            assert!(
                moved.iter().all(|st| *st == dcol_status::DCOL_OK),
                "[capi-scene-set-pose] {what}: {moved:?}"
            );
        }
        let blank = ffi::dcol_scene_pair {
            body1: usize::MAX,
            body2: usize::MAX,
            proximity: blank_proximity(),
            status: dcol_status::DCOL_ERROR_INTERNAL,
        };
        let mut pairs = [blank; 1];
        let mut count = usize::MAX;
        // SAFETY: a live scene, valid options, one writable pair, a writable count; no stats.
        let st = unsafe {
            ffi::dcol_scene_pairs_within(
                scene,
                case.threshold,
                &case.options,
                pairs.as_mut_ptr(),
                1,
                &mut count,
                ptr::null_mut(),
            )
        };
        assert!(
            st != dcol_status::DCOL_ERROR_INTERNAL,
            "[capi-internal dcol_scene_pairs_within] {what}"
        );
        if st == dcol_status::DCOL_OK {
            assert!(count <= 1, "[capi-scene-count] {what}: {count}");
            if count == 1 {
                let p = &pairs[0];
                assert!(
                    answered(p.status),
                    "[capi-scene-pair-status] {what}: {:?}",
                    p.status
                );
                check(
                    "dcol_scene_pairs_within",
                    what,
                    p.status,
                    &proximity_numbers(&p.proximity),
                );
            }
        } else {
            assert_eq!(
                count,
                usize::MAX,
                "[capi-written-on-error dcol_scene_pairs_within] {what}: {st:?}"
            );
            check(
                "dcol_scene_pairs_within",
                what,
                st,
                &proximity_numbers(&pairs[0].proximity),
            );
        }
    }
    // SAFETY: made by dcol_scene_new above, freed once.
    unsafe { ffi::dcol_scene_free(scene) };
}
