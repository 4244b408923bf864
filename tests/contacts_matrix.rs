//! `dcol_contacts_matrix`: contact manifolds with the attitudes given as rotation matrices.
//! Against `dcol_contacts` and `dcol_contacts_cached` with quaternions: bit for bit when the
//! matrix is the one dcol computes from the quaternion (every kind of pair, a half-space
//! included, touching, overlapping and apart, 1 to 16 points), and to rounding for a matrix
//! computed by another formula (Rodrigues' from an axis and angle); a warm-started sequence the
//! same as `dcol_contacts_cached`'s; bad matrices and NULL pointers rejected with nothing
//! written.

mod common;

use common::random::{random_poses, Scaled};
use dcol::ffi::cache::dcol_cache;
use dcol::ffi::contact::dcol_contacts_cached;
use dcol::ffi::shape::dcol_shape_new_convex_hull;
use dcol::ffi::*;
use dcol::Pose;

/// A shape made by a C constructor, freed on drop.
struct CShape(*mut dcol_shape);

impl Drop for CShape {
    fn drop(&mut self) {
        // SAFETY: made by a constructor below, freed once.
        unsafe { dcol_shape_free(self.0) }
    }
}

impl std::fmt::Debug for CShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // SAFETY: live (freed only on drop).
        write!(f, "{:?}", unsafe { (*self.0).shape() })
    }
}

/// A random shape of kind `k` (sphere, box, capsule, cylinder, cone, ellipsoid, hull of 12
/// points, padded hull) of size about `z`, by the C constructors.
fn c_shape(rng: &mut Scaled, k: usize, z: f64) -> CShape {
    let mut out = std::ptr::null_mut();
    let mut u = || z * rng.range(0.3, 1.0);
    // SAFETY: valid arguments and out pointer.
    let st = unsafe {
        match k {
            0 => dcol_shape_new_sphere(u(), &mut out),
            1 => dcol_shape_new_box(u(), u(), u(), &mut out),
            2 => dcol_shape_new_capsule(u(), 2.0 * u(), &mut out),
            3 => dcol_shape_new_cylinder(u(), 2.0 * u(), &mut out),
            4 => dcol_shape_new_cone(2.0 * u(), 0.6, &mut out),
            5 => {
                let (a, b, c) = (u(), u(), u());
                let p = [
                    1.0 / (a * a),
                    0.0,
                    0.0,
                    0.0,
                    1.0 / (b * b),
                    0.0,
                    0.0,
                    0.0,
                    1.0 / (c * c),
                ];
                dcol_shape_new_ellipsoid(p.as_ptr(), &mut out)
            }
            6 | 7 => {
                let pts: Vec<f64> = (0..36)
                    .map(|i| {
                        let t = i / 3;
                        let ang = t as f64 * 2.399963;
                        let zc = 1.0 - 2.0 * (t as f64 + 0.5) / 12.0;
                        let r = (1.0 - zc * zc).sqrt();
                        z * [r * ang.cos(), r * ang.sin(), zc][i % 3] * (0.7 + 0.3 * (t % 2) as f64)
                    })
                    .collect();
                let pad = if k == 7 { 0.1 * u() } else { 0.0 };
                dcol_shape_new_convex_hull(pts.as_ptr(), 12, pad, &mut out)
            }
            _ => dcol_shape_new_halfspace(u(), &mut out),
        }
    };
    assert_eq!(st, dcol_status::DCOL_OK);
    CShape(out)
}

fn quat_pose(p: &Pose) -> dcol_pose {
    let r = p.position();
    dcol_pose {
        position: [r.x, r.y, r.z],
        quaternion: p.quaternion(),
    }
}

/// The pose's matrix as dcol computes it from its quaternion.
fn matrix_pose(p: &Pose) -> dcol_pose_matrix {
    let (r, m) = (p.position(), p.rotation());
    let mut rotation = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            rotation[3 * i + j] = m[(i, j)];
        }
    }
    dcol_pose_matrix {
        position: [r.x, r.y, r.z],
        rotation,
    }
}

/// The rotation of `q` (any length) by Rodrigues' formula from its axis and angle: the same
/// rotation as dcol's matrix of `q`, with other roundings.
fn rodrigues(p: &Pose) -> dcol_pose_matrix {
    let q = p.quaternion();
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let v = [q[1] / n, q[2] / n, q[3] / n];
    let s = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let angle = 2.0 * s.atan2(q[0] / n);
    let k = if s > 0.0 {
        v.map(|x| x / s)
    } else {
        [1.0, 0.0, 0.0]
    };
    let (sn, cs) = angle.sin_cos();
    let mut m = matrix_pose(p);
    for i in 0..3 {
        for j in 0..3 {
            let id = if i == j { 1.0 } else { 0.0 };
            let kx = match (i, j) {
                (0, 1) => -k[2],
                (0, 2) => k[1],
                (1, 0) => k[2],
                (1, 2) => -k[0],
                (2, 0) => -k[1],
                (2, 1) => k[0],
                _ => 0.0,
            };
            m.rotation[3 * i + j] = cs * id + sn * kx + (1.0 - cs) * k[i] * k[j];
        }
    }
    m
}

type Answer = (dcol_status, usize, [dcol_contact; 16]);

/// dcol_contacts (cache NULL) or dcol_contacts_cached.
fn by_quaternion(
    s: [&CShape; 2],
    p: [&Pose; 2],
    margin: f64,
    cap: usize,
    cache: *mut dcol_cache,
) -> Answer {
    let (q1, q2) = (quat_pose(p[0]), quat_pose(p[1]));
    let mut cs = [dcol_contact::default(); 16];
    let mut n = 99usize;
    let (a, b) = (s[0].0.cast_const(), s[1].0.cast_const());
    let out = cs.as_mut_ptr();
    let none = std::ptr::null();
    // SAFETY: live shapes, valid poses, a buffer of 16 >= cap, a valid cache or NULL.
    let st = unsafe {
        if cache.is_null() {
            dcol_contacts(a, &q1, b, &q2, margin, none, out, cap, &mut n)
        } else {
            dcol_contacts_cached(a, &q1, b, &q2, margin, none, cache, out, cap, &mut n)
        }
    };
    (st, n, cs)
}

fn by_matrix(
    s: [&CShape; 2],
    m: [&dcol_pose_matrix; 2],
    margin: f64,
    cap: usize,
    cache: *mut dcol_cache,
) -> Answer {
    let mut cs = [dcol_contact::default(); 16];
    let mut n = 99usize;
    let (a, b) = (s[0].0.cast_const(), s[1].0.cast_const());
    let none = std::ptr::null();
    // SAFETY: live shapes, valid poses, a buffer of 16 >= cap, a valid cache or NULL.
    let st = unsafe {
        dcol_contacts_matrix(
            a,
            m[0],
            b,
            m[1],
            margin,
            none,
            cache,
            cs.as_mut_ptr(),
            cap,
            &mut n,
        )
    };
    (st, n, cs)
}

/// Random pairs of every kind (the 64 ordered pairs of eight kinds, and each kind against a
/// half-space in both orders), apart, touching and overlapping.
fn cases(count: usize) -> Vec<(CShape, CShape, Pose, Pose, f64, usize)> {
    let mut rng = Scaled(41);
    let mut out = vec![];
    for i in 0..count {
        let (k1, k2) = match i % 5 {
            0 => (8, i % 8),
            1 => (i % 8, 8),
            _ => ((i / 8) % 8, i % 8),
        };
        let s1 = c_shape(&mut rng, k1, 1.0);
        let s2 = c_shape(&mut rng, k2, 1.0);
        let len = rng.range(0.1, 2.5);
        let (p1, p2) = random_poses(&mut rng, 1.0, len);
        let margin = if i % 3 == 0 { 0.0 } else { rng.range(0.0, 0.2) };
        out.push((s1, s2, p1, p2, margin, 1 + i % 16));
    }
    out
}

#[test]
fn matrices_give_dcol_contacts_bit_for_bit() {
    let (mut points, mut apart) = (0, 0);
    for (s1, s2, p1, p2, margin, cap) in cases(3000) {
        let null = std::ptr::null_mut();
        let want = by_quaternion([&s1, &s2], [&p1, &p2], margin, cap, null);
        let (m1, m2) = (matrix_pose(&p1), matrix_pose(&p2));
        let got = by_matrix([&s1, &s2], [&m1, &m2], margin, cap, null);
        assert_eq!(got.0, want.0);
        assert_eq!(got.1, want.1);
        assert_eq!(got.2, want.2, "{s1:?} {p1:?} {s2:?} {p2:?}");
        points += got.1;
        apart += usize::from(got.1 == 0);
    }
    // Not a vacuous comparison: most pairs have points, some none.
    assert!(
        points > 3000 && apart > 100 && apart < 2000,
        "{points} {apart}"
    );
}

#[test]
fn another_matrix_of_the_same_rotation_gives_the_same_contacts_to_rounding() {
    let mut compared = 0;
    for (s1, s2, p1, p2, margin, cap) in cases(3000) {
        let null = std::ptr::null_mut();
        let want = by_quaternion([&s1, &s2], [&p1, &p2], margin, cap, null);
        let (m1, m2) = (rodrigues(&p1), rodrigues(&p2));
        let got = by_matrix([&s1, &s2], [&m1, &m2], margin, cap, null);
        assert_eq!(got.0, want.0);
        // A point within rounding of the margin, or a tie between features, may come or go:
        // compare the manifolds that agree in size, by their deepest point and normal.
        if got.1 != want.1 || got.1 == 0 {
            continue;
        }
        let deepest = |a: &Answer| a.2[..a.1].iter().map(|c| c.depth).fold(f64::MIN, f64::max);
        assert!(
            (deepest(&got) - deepest(&want)).abs() < 1e-12,
            "{s1:?} {s2:?}"
        );
        for k in 0..3 {
            assert!((got.2[0].normal[k] - want.2[0].normal[k]).abs() < 1e-9);
        }
        compared += 1;
    }
    assert!(compared > 1500, "{compared}");
}

#[test]
fn a_warm_started_sequence_is_dcol_contacts_cached() {
    let mut rng = Scaled(5);
    let mut points = 0;
    for (s1, s2, p1, p2, margin, cap) in cases(300) {
        let (mut c1, mut c2) = (dcol_cache::default(), dcol_cache::default());
        let (mut p1, mut p2) = (p1, p2);
        for _ in 0..8 {
            let want = by_quaternion([&s1, &s2], [&p1, &p2], margin, cap, &mut c1);
            let (m1, m2) = (matrix_pose(&p1), matrix_pose(&p2));
            let got = by_matrix([&s1, &s2], [&m1, &m2], margin, cap, &mut c2);
            assert_eq!((got.0, got.1), (want.0, want.1));
            for (a, b) in got.2[..got.1].iter().zip(&want.2[..want.1]) {
                for k in 0..3 {
                    assert!((a.position[k] - b.position[k]).abs() < 1e-9);
                    assert!((a.normal[k] - b.normal[k]).abs() < 1e-9);
                }
                assert!((a.depth - b.depth).abs() < 1e-9);
            }
            points += got.1;
            // A small step, as an engine's.
            let step = |p: &Pose, rng: &mut Scaled| {
                let r = p.position();
                let q = p.quaternion();
                let d = 0.01;
                Pose::new(
                    [
                        r.x + d * rng.range(-1.0, 1.0),
                        r.y + d * rng.range(-1.0, 1.0),
                        r.z,
                    ],
                    [q[0] + d * rng.range(-1.0, 1.0), q[1], q[2], q[3]],
                )
                .unwrap()
            };
            p1 = step(&p1, &mut rng);
            p2 = step(&p2, &mut rng);
        }
    }
    assert!(points > 1000, "{points}");
}

#[test]
fn bad_matrices_and_pointers_are_rejected_with_nothing_written() {
    let (mut b, mut floor) = (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: valid out pointers.
    unsafe {
        assert_eq!(
            dcol_shape_new_box(0.5, 0.5, 0.5, &mut b),
            dcol_status::DCOL_OK
        );
        assert_eq!(
            dcol_shape_new_halfspace(1.0, &mut floor),
            dcol_status::DCOL_OK
        );
    }
    let (b, floor) = (CShape(b), CShape(floor));
    let id = dcol_pose_matrix {
        position: [0.0, 0.0, 0.0],
        rotation: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
    };
    let mut up = id;
    up.position[2] = 0.49;
    // The floor's boundary z = 0 (a half-space of depth 1 about z = -1).
    let mut down = id;
    down.position[2] = -1.0;
    // A box resting on the floor: its four lower corners, 0.01 deep.
    let (st, n, cs) = by_matrix([&floor, &b], [&down, &up], 0.0, 16, std::ptr::null_mut());
    assert_eq!((st, n), (dcol_status::DCOL_OK, 4));
    for c in &cs[..4] {
        assert!((c.depth - 0.01).abs() < 1e-15 && (c.position[2] + 0.005).abs() < 1e-15);
        assert_eq!(c.normal, [0.0, 0.0, 1.0]);
        assert!((c.position[0].abs() - 0.5).abs() < 1e-15);
    }
    let mut off = up;
    off.rotation[1] = 1e-9; // not a rotation to 1e-12
    let mut nan = up;
    nan.rotation[4] = f64::NAN;
    let mut flip = up;
    flip.rotation[8] = -1.0; // a reflection
    let mut far = up;
    far.position[0] = f64::INFINITY;
    for bad in [off, nan, flip, far] {
        let (st, n, cs) = by_matrix([&floor, &b], [&down, &bad], 0.0, 16, std::ptr::null_mut());
        assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_POSE);
        assert_eq!(n, 99);
        assert_eq!(cs[0], dcol_contact::default());
        // SAFETY: the message is a NUL-terminated string owned by this thread.
        let msg = unsafe { std::ffi::CStr::from_ptr(dcol_last_error_message()) };
        assert!(msg.to_str().unwrap().contains("pose2"), "{msg:?}");
    }
    let mut n = 99usize;
    let mut cs = [dcol_contact::default(); 4];
    // SAFETY: a NULL pose is checked.
    let st = unsafe {
        dcol_contacts_matrix(
            floor.0,
            &id,
            b.0,
            std::ptr::null(),
            0.0,
            std::ptr::null(),
            std::ptr::null_mut(),
            cs.as_mut_ptr(),
            4,
            &mut n,
        )
    };
    assert_eq!(st, dcol_status::DCOL_ERROR_NULL_POINTER);
    assert_eq!(n, 99);
}
