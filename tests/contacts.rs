//! Contact manifolds (`contact_manifold`, `dcol_contacts`): analytic box, cylinder and sphere
//! contacts, and a property test over random pairs (every point's two surface points lie on
//! the shapes' surfaces, the normal is the signed distance's).

use dcol::ffi::{dcol_contact, dcol_contacts, dcol_pose, dcol_shape_free, dcol_shape_new_box};
use dcol::ffi::{dcol_shape_new_sphere, dcol_status};
use dcol::math::rotation_from_quaternion;
use dcol::{contact_manifold, signed_distance, Contact, Manifold, Options, Pose, Shape, Vec3};

fn pose(p: [f64; 3], q: [f64; 4]) -> Pose {
    Pose::new(p, q).unwrap()
}

const ID: [f64; 4] = [1.0, 0.0, 0.0, 0.0];

/// Rotation taking body x to world z (about y by -90 degrees).
fn x_to_z() -> [f64; 4] {
    let h = std::f64::consts::FRAC_PI_4;
    [h.cos(), 0.0, -h.sin(), 0.0]
}

fn opts() -> Options {
    Options {
        tolerance: 1e-10,
        ..Options::default()
    }
}

fn has_point(cs: &[Contact], p: [f64; 3], tol: f64) -> bool {
    cs.iter().any(|c| (c.position - Vec3::from(p)).norm() < tol)
}

/// The manifold (margin 0, at most `cap` points) of `shape` at `at` against `ground` at the
/// origin.
fn on_ground(ground: &Shape, shape: &Shape, at: &Pose, cap: usize) -> Manifold {
    contact_manifold(ground, &pose([0.0; 3], ID), shape, at, 0.0, cap, &opts()).unwrap()
}

#[test]
fn box_on_box_face_to_face() {
    let ground = Shape::cuboid(1.0, 1.0, 0.5).unwrap();
    let cube = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
    let m = on_ground(&ground, &cube, &pose([0.0, 0.0, 0.99], ID), 8);
    assert_eq!(m.len(), 4, "{:?}", m.contacts());
    for c in m.contacts() {
        assert!((c.depth - 0.01).abs() < 1e-12);
        assert!((c.normal - Vec3::z()).norm() < 1e-12);
        assert!((c.position.z - 0.495).abs() < 1e-12);
    }
    for (x, y) in [(0.5, 0.5), (-0.5, 0.5), (0.5, -0.5), (-0.5, -0.5)] {
        assert!(has_point(m.contacts(), [x, y, 0.495], 1e-12));
    }
    // Separated within the margin: negative depths.
    let m = contact_manifold(
        &ground,
        &pose([0.0; 3], ID),
        &cube,
        &pose([0.0, 0.0, 1.02], ID),
        0.05,
        8,
        &opts(),
    )
    .unwrap();
    assert_eq!(m.len(), 4);
    assert!(m.contacts().iter().all(|c| (c.depth + 0.02).abs() < 1e-12));
    // Beyond the margin: nothing.
    let m = contact_manifold(
        &ground,
        &pose([0.0; 3], ID),
        &cube,
        &pose([0.0, 0.0, 1.1], ID),
        0.05,
        8,
        &opts(),
    )
    .unwrap();
    assert!(m.is_empty());
}

#[test]
fn offset_rotated_box_is_clipped() {
    let ground = Shape::cuboid(1.0, 1.0, 0.5).unwrap();
    let cube = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
    let a = std::f64::consts::FRAC_PI_8;
    let m = on_ground(
        &ground,
        &cube,
        &pose([0.9, 0.0, 0.99], [a.cos(), 0.0, 0.0, a.sin()]),
        8,
    );
    // The cube's footprint is a diamond of half-diagonal r = 0.5·√2 about (0.9, 0), cut by
    // the ground's edge x = 1.
    let r = 0.5 * 2f64.sqrt();
    let z = 0.495;
    let expect = [
        [0.9 - r, 0.0, z],
        [0.9, r, z],
        [0.9, -r, z],
        [1.0, r - 0.1, z],
        [1.0, -(r - 0.1), z],
    ];
    assert_eq!(m.len(), 5, "{:?}", m.contacts());
    for p in expect {
        assert!(has_point(m.contacts(), p, 1e-12), "missing {p:?}");
    }
    // Reduced to 4: the deepest (all equal) and the widest spread.
    let m4 = on_ground(
        &ground,
        &cube,
        &pose([0.9, 0.0, 0.99], [a.cos(), 0.0, 0.0, a.sin()]),
        4,
    );
    assert_eq!(m4.len(), 4);
}

#[test]
fn cylinder_on_its_cap_gives_points_on_the_circle() {
    let ground = Shape::cuboid(1.0, 1.0, 0.5).unwrap();
    let cyl = Shape::cylinder(0.3, 1.0).unwrap();
    let m = on_ground(&ground, &cyl, &pose([0.1, 0.2, 0.99], x_to_z()), 16);
    assert_eq!(m.len(), 12);
    for c in m.contacts() {
        let d = (c.position.x - 0.1).hypot(c.position.y - 0.2);
        assert!((d - 0.3).abs() < 1e-12, "{d}");
        assert!((c.position.z - 0.495).abs() < 1e-12);
        assert!((c.depth - 0.01).abs() < 1e-12);
    }
    let m4 = on_ground(&ground, &cyl, &pose([0.1, 0.2, 0.99], x_to_z()), 4);
    assert_eq!(m4.len(), 4);
}

#[test]
fn cylinder_on_its_side_gives_two_points() {
    let ground = Shape::cuboid(1.0, 1.0, 0.5).unwrap();
    let cyl = Shape::cylinder(0.3, 1.0).unwrap();
    let m = on_ground(&ground, &cyl, &pose([0.0, 0.0, 0.79], ID), 4);
    assert_eq!(m.len(), 2, "{:?}", m.contacts());
    assert!(has_point(m.contacts(), [0.5, 0.0, 0.495], 1e-9));
    assert!(has_point(m.contacts(), [-0.5, 0.0, 0.495], 1e-9));
    // Hanging over the edge: clipped at x = 1.
    let m = on_ground(&ground, &cyl, &pose([0.8, 0.0, 0.79], ID), 4);
    assert_eq!(m.len(), 2);
    assert!(has_point(m.contacts(), [0.3, 0.0, 0.495], 1e-9));
    assert!(has_point(m.contacts(), [1.0, 0.0, 0.495], 1e-9));
}

#[test]
fn sphere_on_box_gives_one_point() {
    let ground = Shape::cuboid(1.0, 1.0, 0.5).unwrap();
    let ball = Shape::sphere(0.3).unwrap();
    let m = on_ground(&ground, &ball, &pose([0.2, 0.0, 0.79], ID), 4);
    assert_eq!(m.len(), 1);
    let c = m.contacts()[0];
    assert!((c.depth - 0.01).abs() < 1e-9);
    assert!((c.position - Vec3::new(0.2, 0.0, 0.495)).norm() < 1e-9);
}

#[test]
fn invalid_margin_is_rejected() {
    let s = Shape::sphere(1.0).unwrap();
    let p = pose([0.0; 3], ID);
    assert!(contact_manifold(&s, &p, &s, &p, f64::NAN, 4, &opts()).is_err());
    assert!(contact_manifold(&s, &p, &s, &p, -1.0, 4, &opts()).is_err());
}

// ---- the property test -----------------------------------------------------------------

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn quat(&mut self) -> [f64; 4] {
        loop {
            let q = [0; 4].map(|_| self.range(-1.0, 1.0));
            let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
            if n > 0.1 && n <= 1.0 {
                return q.map(|v| v / n);
            }
        }
    }
}

/// Test shapes with an independent distance-to-surface function (body frame).
#[derive(Clone, Copy, Debug)]
enum Kind {
    Box(f64, f64, f64),
    Sphere(f64),
    Cylinder(f64, f64),
    Capsule(f64, f64),
    Cone(f64, f64),
}

impl Kind {
    fn shape(self) -> Shape {
        match self {
            Kind::Box(a, b, c) => Shape::cuboid(a, b, c),
            Kind::Sphere(r) => Shape::sphere(r),
            Kind::Cylinder(r, l) => Shape::cylinder(r, l),
            Kind::Capsule(r, l) => Shape::capsule(r, l),
            Kind::Cone(h, b) => Shape::cone(h, b),
        }
        .unwrap()
    }

    /// |distance| from body point p to the surface.
    fn surface_distance(self, p: Vec3) -> f64 {
        let bx = |q: [f64; 2], h: [f64; 2]| {
            let d = [q[0].abs() - h[0], q[1].abs() - h[1]];
            let out = d[0].max(0.0).hypot(d[1].max(0.0));
            (out + d[0].max(d[1]).min(0.0)).abs()
        };
        match self {
            Kind::Box(a, b, c) => {
                let d = Vec3::new(p.x.abs() - a, p.y.abs() - b, p.z.abs() - c);
                let out = d.map(|v| v.max(0.0)).norm();
                (out + d.x.max(d.y).max(d.z).min(0.0)).abs()
            }
            Kind::Sphere(r) => (p.norm() - r).abs(),
            Kind::Cylinder(r, l) => bx([p.x, p.y.hypot(p.z)], [0.5 * l, r]),
            Kind::Capsule(r, l) => {
                let x = p.x.clamp(-0.5 * l, 0.5 * l);
                ((p - Vec3::new(x, 0.0, 0.0)).norm() - r).abs()
            }
            Kind::Cone(h, beta) => {
                // Distance to the triangle's edges in the (x, ρ) half plane.
                let q = [p.x, p.y.hypot(p.z)];
                let apex = [-0.75 * h, 0.0];
                let rim = [0.25 * h, h * beta.tan()];
                let axis = [0.25 * h, 0.0];
                let seg = |a: [f64; 2], b: [f64; 2]| {
                    let d = [b[0] - a[0], b[1] - a[1]];
                    let w = [q[0] - a[0], q[1] - a[1]];
                    let t =
                        ((w[0] * d[0] + w[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
                    (w[0] - t * d[0]).hypot(w[1] - t * d[1])
                };
                seg(apex, rim).min(seg(rim, axis))
            }
        }
    }
}

#[test]
fn property_points_lie_on_both_surfaces() {
    let mut rng = Rng(7);
    let kinds = [
        Kind::Box(0.5, 0.3, 0.2),
        Kind::Box(1.0, 1.0, 0.25),
        Kind::Sphere(0.4),
        Kind::Cylinder(0.3, 1.0),
        Kind::Capsule(0.25, 0.8),
        Kind::Cone(1.0, 0.5),
    ];
    let opts = opts();
    let (mut total, mut multi, mut unconverged) = (0, 0, 0);
    for trial in 0..3000 {
        let k1 = kinds[trial % kinds.len()];
        let k2 = kinds[(trial / kinds.len()) % kinds.len()];
        let (s1, s2) = (k1.shape(), k2.shape());
        // Aligned poses half of the time so faces meet faces.
        let (q1, q2) = if trial % 2 == 0 {
            (rng.quat(), rng.quat())
        } else {
            let q = rng.quat();
            (q, if trial % 4 == 1 { q } else { x_to_z() })
        };
        let dir = Vec3::new(rng.range(-0.3, 0.3), rng.range(-0.3, 0.3), 1.0).normalize();
        let reach = s1.bounding_radius() + s2.bounding_radius();
        let r2 = dir * rng.range(0.2, 1.0) * reach;
        let p1 = pose([0.0; 3], q1);
        let p2 = pose([r2.x, r2.y, r2.z], q2);
        let margin = 0.02;
        let m = contact_manifold(&s1, &p1, &s2, &p2, margin, 8, &opts).unwrap();
        let sd = signed_distance(&s1, &p1, &s2, &p2, &opts).unwrap();
        assert!((m.normal - sd.normal).norm() < 1e-15);
        assert_eq!(m.signed_distance, sd.distance);
        if sd.distance > margin {
            assert!(m.is_empty());
            continue;
        }
        assert!(!m.is_empty());
        assert_eq!(m.status, sd.status);
        if !sd.status.is_converged() {
            // The witness points of an uncertified answer are not on the surfaces.
            unconverged += 1;
            continue;
        }
        total += 1;
        multi += usize::from(m.len() > 1);
        // The deepest point is in the manifold: its depth is minus the signed distance.
        let deepest = m
            .contacts()
            .iter()
            .fold(f64::NEG_INFINITY, |d, c| d.max(c.depth));
        let ell0 = s1.bounding_radius().max(s2.bounding_radius());
        assert!(
            (deepest + sd.distance).abs() <= 1e-9 * ell0,
            "trial {trial}: {k1:?} {k2:?}: deepest {deepest} vs {}",
            -sd.distance
        );
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        let (rot1, rot2) = (rotation_from_quaternion(q1), rotation_from_quaternion(q2));
        for c in m.contacts() {
            assert!((c.normal - sd.normal).norm() < 1e-15);
            assert!(c.depth >= -margin - 1e-9 * ell);
            assert!(
                c.depth <= -sd.distance + 1e-9 * ell,
                "{} > {}",
                c.depth,
                -sd.distance
            );
            let a = c.position + c.normal * (0.5 * c.depth);
            let b = c.position - c.normal * (0.5 * c.depth);
            let d1 = k1.surface_distance(rot1.transpose() * a);
            let d2 = k2.surface_distance(rot2.transpose() * (b - r2));
            assert!(
                d1 < 1e-9 * ell && d2 < 1e-9 * ell,
                "trial {trial}: {k1:?} {k2:?}: {d1:e} {d2:e} ({} points, sd {}, {:?} {:?})",
                m.len(),
                sd.distance,
                sd.status,
                sd.path
            );
        }
    }
    eprintln!("{total} manifolds, {multi} with several points, {unconverged} unconverged skipped");
    assert!(total > 500 && multi > 100 && unconverged < total / 20);
}

#[test]
fn c_function_writes_contacts_and_checks_pointers() {
    let mut ground = std::ptr::null_mut();
    let mut ball = std::ptr::null_mut();
    // SAFETY: valid out pointers.
    unsafe {
        assert_eq!(
            dcol_shape_new_box(1.0, 1.0, 0.5, &mut ground),
            dcol_status::DCOL_OK
        );
        assert_eq!(dcol_shape_new_sphere(0.3, &mut ball), dcol_status::DCOL_OK);
    }
    let p1 = dcol_pose {
        position: [0.0; 3],
        quaternion: ID,
    };
    let p2 = dcol_pose {
        position: [0.0, 0.0, 0.79],
        quaternion: ID,
    };
    let mut cs = [dcol_contact::default(); 4];
    let mut n = 99usize;
    // SAFETY: live shapes, valid pointers, capacity matches the buffer.
    let st = unsafe {
        dcol_contacts(
            ground,
            &p1,
            ball,
            &p2,
            0.0,
            std::ptr::null(),
            cs.as_mut_ptr(),
            4,
            &mut n,
        )
    };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert_eq!(n, 1);
    assert!((cs[0].depth - 0.01).abs() < 1e-9);
    assert!((cs[0].position[2] - 0.495).abs() < 1e-9);
    // NULL count: error, nothing written.
    let mut cs2 = [dcol_contact::default(); 4];
    // SAFETY: as above; count NULL is checked.
    let st = unsafe {
        dcol_contacts(
            ground,
            &p1,
            ball,
            &p2,
            0.0,
            std::ptr::null(),
            cs2.as_mut_ptr(),
            4,
            std::ptr::null_mut(),
        )
    };
    assert_eq!(st, dcol_status::DCOL_ERROR_NULL_POINTER);
    assert_eq!(cs2[0], dcol_contact::default());
    // Bad margin: error, count untouched.
    let mut n = 99usize;
    // SAFETY: as above.
    let st = unsafe {
        dcol_contacts(
            ground,
            &p1,
            ball,
            &p2,
            f64::NAN,
            std::ptr::null(),
            cs2.as_mut_ptr(),
            4,
            &mut n,
        )
    };
    assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_OPTIONS);
    assert_eq!(n, 99);
    // Capacity 0 with NULL contacts: count 0.
    // SAFETY: as above; no contact is written when capacity is 0.
    let st = unsafe {
        dcol_contacts(
            ground,
            &p1,
            ball,
            &p2,
            0.0,
            std::ptr::null(),
            std::ptr::null_mut(),
            0,
            &mut n,
        )
    };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert_eq!(n, 0);
    // SAFETY: live shapes, freed once.
    unsafe {
        dcol_shape_free(ground);
        dcol_shape_free(ball);
    }
}
