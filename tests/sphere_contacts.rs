//! The contact manifold of a sphere pair takes the signed distance's closed form directly
//! (`src/query/contact_sphere.rs`): its manifold must be the general path's to the last bit.
//! Random sphere pairs against every kind the closed forms cover (spheres, capsules, boxes,
//! cylinders, cones, ellipsoids, hulls; hulls at scales 1e-30 to 1e30 only) and two they do not (a non-box polytope and a hull with
//! the centre outside, which the general solvers answer), both orders, random attitudes, from
//! deep overlap to apart by three margins, margins 0 and 0.05, capacities 0, 1 and 4, scenes
//! scaled by 1e-120 to 1e120:
//! - Rust's manifold: its signed distance and normal are `signed_distance`'s bit for bit, and
//!   with the signed distance within the margin its one point is the witnesses' midpoint at depth
//!   −sd (bit for bit); an error exactly where `signed_distance` errs.
//! - The C function: the same status, count and points as Rust's manifold, bit for bit. (Its
//!   status with other methods and iteration limits is the fuzz driver's check.)
//!
//! The closed forms' agreement with analytic answers is `sphere_closed_forms.rs`'s.

use dcol::ffi::{dcol_contact, dcol_contacts, dcol_pose, dcol_shape, dcol_shape_free, dcol_status};
use dcol::ffi::{
    dcol_shape_new_box, dcol_shape_new_capsule, dcol_shape_new_cone, dcol_shape_new_cylinder,
    dcol_shape_new_ellipsoid, dcol_shape_new_sphere,
};
use dcol::{contact_manifold, signed_distance, Options, Pose, Shape, Vec3};

mod common;

use common::xorshift::Rng;

/// A solid of the test, as Rust and C make it (unit size; `scale` multiplies every length).
#[derive(Clone, Copy)]
enum Kind {
    Sphere(f64),
    Capsule(f64, f64),
    Box(f64, f64, f64),
    Cylinder(f64, f64),
    Cone(f64, f64),
    Ellipsoid(f64, f64, f64),
    Hull,
    Octahedron,
}

impl Kind {
    fn rust(self, s: f64) -> Shape {
        match self {
            Kind::Sphere(r) => Shape::sphere(r * s),
            Kind::Capsule(r, l) => Shape::capsule(r * s, l * s),
            Kind::Box(a, b, c) => Shape::cuboid(a * s, b * s, c * s),
            Kind::Cylinder(r, l) => Shape::cylinder(r * s, l * s),
            Kind::Cone(h, a) => Shape::cone(h * s, a),
            Kind::Ellipsoid(a, b, c) => Shape::ellipsoid(diag(a * s, b * s, c * s)),
            Kind::Hull => Shape::convex_hull(&hull_points(s), 0.0),
            Kind::Octahedron => Shape::convex_hull(
                &[
                    [s, 0.0, 0.0],
                    [-s, 0.0, 0.0],
                    [0.0, 0.7 * s, 0.0],
                    [0.0, -0.7 * s, 0.0],
                    [0.0, 0.0, 0.5 * s],
                    [0.0, 0.0, -0.5 * s],
                ],
                0.0,
            ),
        }
        .unwrap()
    }

    /// The C shape (`None` for the hulls, checked through Rust only).
    fn c(self, s: f64) -> Option<*mut dcol_shape> {
        let mut out: *mut dcol_shape = std::ptr::null_mut();
        // SAFETY: valid out-pointer and matrix.
        let st = unsafe {
            match self {
                Kind::Sphere(r) => dcol_shape_new_sphere(r * s, &mut out),
                Kind::Capsule(r, l) => dcol_shape_new_capsule(r * s, l * s, &mut out),
                Kind::Box(a, b, c) => dcol_shape_new_box(a * s, b * s, c * s, &mut out),
                Kind::Cylinder(r, l) => dcol_shape_new_cylinder(r * s, l * s, &mut out),
                Kind::Cone(h, a) => dcol_shape_new_cone(h * s, a, &mut out),
                Kind::Ellipsoid(a, b, c) => {
                    let p = diag(a * s, b * s, c * s);
                    let flat: Vec<f64> = p.iter().flatten().copied().collect();
                    dcol_shape_new_ellipsoid(flat.as_ptr(), &mut out)
                }
                Kind::Hull | Kind::Octahedron => return None,
            }
        };
        assert_eq!(st, dcol_status::DCOL_OK);
        Some(out)
    }
}

/// The matrix `P` of the ellipsoid with semi-axes `a, b, c` along the body axes.
fn diag(a: f64, b: f64, c: f64) -> [[f64; 3]; 3] {
    [
        [1.0 / (a * a), 0.0, 0.0],
        [0.0, 1.0 / (b * b), 0.0],
        [0.0, 0.0, 1.0 / (c * c)],
    ]
}

/// Twelve points of an irregular hull about its origin.
fn hull_points(s: f64) -> Vec<[f64; 3]> {
    let mut rng = Rng(0x9e37_79b9);
    (0..12)
        .map(|_| {
            let u = rng.unit();
            let r = rng.range(0.3, 0.5) * s;
            [u.x * r, u.y * r, u.z * r]
        })
        .collect()
}

fn quaternion(rng: &mut Rng) -> [f64; 4] {
    let axis = rng.unit();
    let angle = match (rng.next() * 4.0) as u32 {
        0 => 0.0,
        1 => 10f64.powf(rng.range(-9.0, -3.0)),
        2 => std::f64::consts::FRAC_PI_2,
        _ => rng.range(0.0, std::f64::consts::PI),
    };
    let (s, c) = (0.5 * angle).sin_cos();
    [c, s * axis.x, s * axis.y, s * axis.z]
}

fn bits(v: &Vec3) -> [u64; 3] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()]
}

#[test]
fn sphere_manifolds_are_the_general_paths_to_the_last_bit() {
    let kinds = [
        Kind::Sphere(0.3),
        Kind::Capsule(0.2, 0.6),
        Kind::Box(0.4, 0.3, 0.2),
        Kind::Cylinder(0.3, 0.5),
        Kind::Cone(0.6, 0.5),
        Kind::Ellipsoid(0.5, 0.3, 0.2),
        Kind::Hull,
        Kind::Octahedron,
    ];
    let scales = [1.0, 1e-120, 1e-30, 1e30, 1e120];
    let opts = Options::default();
    let mut rng = Rng(0x5eed_0008);
    let (mut touching, mut apart_c, mut beyond) = (0usize, 0usize, 0usize);
    for (si, &scale) in scales.iter().enumerate() {
        let trials = if si == 0 { 12_000 } else { 2_000 };
        for trial in 0..trials {
            let kind = kinds[trial % kinds.len()];
            // Hulls' constructors reject sizes far below 1 (their tolerances underflow).
            if matches!(kind, Kind::Hull | Kind::Octahedron) && !(1e-60..1e60).contains(&scale) {
                continue;
            }
            let rho = rng.range(0.05, 0.5);
            let (ball, solid) = (Shape::sphere(rho * scale).unwrap(), kind.rust(scale));
            let ball_first = trial % 2 == 0;
            // Centres from inside the solid to three margins beyond touching.
            let reach = rho + solid.bounding_radius() / scale;
            let dist = reach * rng.range(0.0, 1.15);
            let c = rng.unit() * dist * scale;
            let far = if trial % 97 == 0 { 1e6 } else { 0.0 };
            let base = Vec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), far) * scale;
            let ps = Pose::new([base.x, base.y, base.z], quaternion(&mut rng)).unwrap();
            let cb = base + c;
            let pb = Pose::new([cb.x, cb.y, cb.z], quaternion(&mut rng)).unwrap();
            let margin = if trial % 3 == 0 { 0.05 * scale } else { 0.0 };
            let cap = [1usize, 4, 1, 4, 0][trial % 5];
            let ((s1, p1), (s2, p2)) = if ball_first {
                ((&ball, &pb), (&solid, &ps))
            } else {
                ((&solid, &ps), (&ball, &pb))
            };
            let sd = signed_distance(s1, p1, s2, p2, &opts);
            let m = contact_manifold(s1, p1, s2, p2, margin, cap, &opts);
            let (sd, m) = match (sd, m) {
                (Ok(sd), Ok(m)) => (sd, m),
                (Err(_), Err(_)) => continue,
                (sd, m) => panic!("trial {trial} scale {scale}: {sd:?} against {m:?}"),
            };
            assert_eq!(
                m.signed_distance.to_bits(),
                sd.distance.to_bits(),
                "trial {trial}"
            );
            assert_eq!(bits(&m.normal), bits(&sd.normal), "trial {trial}");
            if sd.distance <= margin && cap > 0 {
                assert_eq!(m.len(), 1, "trial {trial}");
                let c = &m.contacts()[0];
                let mid = sd.closest1 + (sd.closest2 - sd.closest1) * 0.5;
                assert_eq!(bits(&c.position), bits(&mid), "trial {trial}");
                assert_eq!(c.depth.to_bits(), (-sd.distance).to_bits(), "trial {trial}");
                assert_eq!(bits(&c.normal), bits(&sd.normal), "trial {trial}");
                touching += 1;
            } else {
                assert!(m.is_empty(), "trial {trial}");
                beyond += usize::from(sd.distance > margin);
            }
            // The C function: the same points, bit for bit.
            let Some(cs) = kind.c(scale) else { continue };
            let mut cb_ = std::ptr::null_mut();
            // SAFETY: valid out-pointer.
            assert_eq!(
                unsafe { dcol_shape_new_sphere(rho * scale, &mut cb_) },
                dcol_status::DCOL_OK
            );
            let cpose = |p: &Pose| dcol_pose {
                position: [p.position().x, p.position().y, p.position().z],
                quaternion: p.quaternion(),
            };
            let ((c1, q1), (c2, q2)) = if ball_first {
                ((cb_, cpose(&pb)), (cs, cpose(&ps)))
            } else {
                ((cs, cpose(&ps)), (cb_, cpose(&pb)))
            };
            let mut out = [dcol_contact::default(); 4];
            let mut n = 99usize;
            // SAFETY: live shapes, valid poses and buffers of `cap <= 4` contacts.
            let st = unsafe {
                dcol_contacts(
                    c1,
                    &q1,
                    c2,
                    &q2,
                    margin,
                    std::ptr::null(),
                    out.as_mut_ptr(),
                    cap,
                    &mut n,
                )
            };
            // SAFETY: shapes made above, freed once.
            unsafe {
                dcol_shape_free(cs);
                dcol_shape_free(cb_);
            }
            assert_eq!(st, dcol_status::DCOL_OK, "trial {trial}");
            assert_eq!(n, m.len(), "trial {trial}");
            for (o, c) in out[..n].iter().zip(m.contacts()) {
                assert_eq!(o.depth.to_bits(), c.depth.to_bits());
                assert_eq!(o.position.map(f64::to_bits), bits(&c.position));
                assert_eq!(o.normal.map(f64::to_bits), bits(&c.normal));
            }
            apart_c += usize::from(n == 0 && sd.distance > margin);
        }
    }
    // Every branch was taken many times.
    assert!(touching > 5_000, "{touching} touching");
    assert!(beyond > 1_000, "{beyond} apart");
    assert!(apart_c > 1_000, "{apart_c} apart through C");
}
