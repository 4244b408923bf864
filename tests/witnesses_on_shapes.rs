//! The signed distance's witness points lie on their shapes, face to face.
//!
//! Two shapes with parallel flat faces (a box's or polytope's facet, a padded polygon's top or
//! bottom, a cylinder's cap, a cone's base) overlap face to face at random depths and random
//! offsets along the faces; a flat face also meets a sphere, an ellipsoid and a capsule. For
//! every pose, against the shapes written out independently (`common::oracle`): each witness
//! lies on its shape's support plane at the normal and not outside its shape (within 1e-9·ℓ),
//! and `closest2 − closest1 = distance·normal` (within 1e-9·ℓ). Before the fix, EPA took the
//! witnesses from the closest of the coplanar triangles that split K's facet, which need not
//! hold `d`'s projection: two boxes of one attitude face to face got witnesses on the right
//! support planes but outside both boxes (21 of 20 000 random offsets, up to 0.09 of the size).

mod common;

use common::oracle::{polygon_vertices, polytope_vertices, Oracle, Posed};
use common::random::Rng;
use dcol::{signed_distance, Options, Pose, Shape, SignedDistance, SolveStatus, Vec3};
use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Box,
    /// A box given as a polytope (six rows, or the rows turned by a random rotation).
    BoxLike,
    Polytope,
    Polygon,
    Cylinder,
    Cone,
    Sphere,
    Ellipsoid,
    Capsule,
}

const FLAT: [Kind; 6] = [
    Kind::Box,
    Kind::BoxLike,
    Kind::Polytope,
    Kind::Polygon,
    Kind::Cylinder,
    Kind::Cone,
];
const CURVED: [Kind; 3] = [Kind::Sphere, Kind::Ellipsoid, Kind::Capsule];

/// A flat face in the body frame: outward unit normal, a point of it (its centre), and the
/// radius of a disc about that point inside the face.
struct Face {
    normal: Vec3,
    centre: Vec3,
    radius: f64,
}

fn polytope(a: Vec<Vec3>, b: Vec<f64>) -> (Shape, Oracle) {
    let rows: Vec<[f64; 3]> = a.iter().map(|r| [r.x, r.y, r.z]).collect();
    let v = polytope_vertices(&a, &b);
    (
        Shape::polytope(&rows, &b).unwrap(),
        Oracle::Polytope(a, b, v),
    )
}

fn box_rows(h: [f64; 3]) -> (Vec<Vec3>, Vec<f64>) {
    let a = (0..6)
        .map(|i| {
            let mut r = Vec3::zeros();
            r[i % 3] = if i < 3 { 1.0 } else { -1.0 };
            r
        })
        .collect();
    (a, (0..6).map(|i| h[i % 3]).collect())
}

fn shape(kind: Kind, rng: &mut Rng) -> (Shape, Oracle) {
    match kind {
        Kind::Box => {
            let h = [
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
            ];
            let (a, b) = box_rows(h);
            let v = polytope_vertices(&a, &b);
            (
                Shape::cuboid(h[0], h[1], h[2]).unwrap(),
                Oracle::Polytope(a, b, v),
            )
        }
        Kind::BoxLike => {
            let h = [
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
                rng.range(0.2, 1.0),
            ];
            let (mut a, b) = box_rows(h);
            if rng.next_u64() % 2 == 0 {
                let m = dcol::math::rotation_from_quaternion(rng.quat());
                a = a.iter().map(|r| m * r).collect();
            }
            polytope(a, b)
        }
        Kind::Polytope => {
            let phi = (1.0 + 5f64.sqrt()) / 2.0;
            let mut a = Vec::with_capacity(12);
            for s1 in [1.0, -1.0] {
                for s2 in [1.0, -1.0] {
                    for v in [
                        [0.0, s1, s2 * phi],
                        [s1, s2 * phi, 0.0],
                        [s2 * phi, 0.0, s1],
                    ] {
                        a.push(Vec3::from(v.map(|c| c + rng.range(-0.15, 0.15))));
                    }
                }
            }
            let b = (0..12).map(|_| rng.range(0.5, 1.2)).collect();
            polytope(a, b)
        }
        Kind::Polygon => {
            let m = 3 + (rng.next_u64() % 5) as usize;
            let off = rng.range(0.0, std::f64::consts::TAU);
            let c: Vec<[f64; 2]> = (0..m)
                .map(|i| {
                    let t =
                        off + std::f64::consts::TAU * (i as f64 + rng.range(-0.2, 0.2)) / m as f64;
                    [t.cos(), t.sin()]
                })
                .collect();
            let d: Vec<f64> = (0..m).map(|_| rng.range(0.3, 0.9)).collect();
            let r = rng.range(0.05, 0.3);
            let w = polygon_vertices(&c, &d);
            (Shape::polygon(&c, &d, r).unwrap(), Oracle::Polygon(w, r))
        }
        Kind::Cylinder => {
            let (r, l) = (rng.range(0.2, 0.7), rng.range(0.3, 1.5));
            (Shape::cylinder(r, l).unwrap(), Oracle::Cylinder(r, l))
        }
        Kind::Cone => {
            let (h, b) = (rng.range(0.5, 1.8), rng.range(0.25, 1.1));
            (Shape::cone(h, b).unwrap(), Oracle::Cone(h, b))
        }
        Kind::Sphere => {
            let r = rng.range(0.3, 1.2);
            (Shape::sphere(r).unwrap(), Oracle::Sphere(r))
        }
        Kind::Ellipsoid => {
            let m = dcol::math::rotation_from_quaternion(rng.quat());
            let d = Vec3::new(
                rng.range(0.3, 1.2),
                rng.range(0.3, 1.2),
                rng.range(0.3, 1.2),
            );
            let mut p = m * Matrix3::from_diagonal(&d.map(|v| 1.0 / (v * v))) * m.transpose();
            p = (p + p.transpose()) * 0.5;
            let q = m * Matrix3::from_diagonal(&d.component_mul(&d)) * m.transpose();
            let rows = [0, 1, 2].map(|i| [0, 1, 2].map(|j| p[(i, j)]));
            (Shape::ellipsoid(rows).unwrap(), Oracle::Ellipsoid(p, q))
        }
        Kind::Capsule => {
            let (r, l) = (rng.range(0.2, 0.7), rng.range(0.3, 1.5));
            (Shape::capsule(r, l).unwrap(), Oracle::Capsule(r, l))
        }
    }
}

/// A random flat face of a flat kind.
fn face(oracle: &Oracle, rng: &mut Rng) -> Face {
    match oracle {
        Oracle::Polytope(a, b, v) => {
            // A facet (a row whose plane holds three vertices or more; a perturbed
            // dodecahedron's row may bound nothing).
            let (i, on) = loop {
                let i = (rng.next_u64() % a.len() as u64) as usize;
                let on: Vec<&Vec3> = v
                    .iter()
                    .filter(|p| (a[i].dot(p) - b[i]).abs() <= 1e-9 * b[i])
                    .collect();
                if on.len() >= 3 {
                    break (i, on);
                }
            };
            let centre = on.iter().copied().sum::<Vec3>() / on.len() as f64;
            // The largest disc about the centroid inside the facet, roughly: half the least
            // distance to a vertex.
            let radius = on
                .iter()
                .map(|p| (*p - centre).norm())
                .fold(f64::INFINITY, f64::min)
                * 0.5;
            Face {
                normal: a[i].normalize(),
                centre,
                radius,
            }
        }
        Oracle::Polygon(w, r) => {
            let sign = if rng.next_u64() % 2 == 0 { 1.0 } else { -1.0 };
            let n = w.len() as f64;
            let c = [
                w.iter().map(|p| p[0]).sum::<f64>() / n,
                w.iter().map(|p| p[1]).sum::<f64>() / n,
            ];
            let radius = w
                .iter()
                .map(|p| (p[0] - c[0]).hypot(p[1] - c[1]))
                .fold(f64::INFINITY, f64::min)
                * 0.5;
            Face {
                normal: Vec3::z() * sign,
                centre: Vec3::new(c[0], c[1], r * sign),
                radius,
            }
        }
        Oracle::Cylinder(r, l) => {
            let sign = if rng.next_u64() % 2 == 0 { 1.0 } else { -1.0 };
            Face {
                normal: Vec3::x() * sign,
                centre: Vec3::x() * (0.5 * l * sign),
                radius: *r,
            }
        }
        Oracle::Cone(h, b) => Face {
            normal: Vec3::x(),
            centre: Vec3::x() * (0.25 * h),
            radius: h * b.tan(),
        },
        _ => unreachable!("not a flat kind"),
    }
}

/// A rotation taking the unit `from` to the unit `to`.
fn align(from: &Vec3, to: &Vec3) -> Rotation3<f64> {
    Rotation3::rotation_between(from, to).unwrap_or_else(|| {
        // Opposite: half a turn about any axis orthogonal to `from`.
        let o = if from.x.abs() < 0.6 {
            Vec3::x()
        } else {
            Vec3::y()
        };
        let axis = Unit::new_normalize(from.cross(&o));
        Rotation3::from_axis_angle(&axis, std::f64::consts::PI)
    })
}

fn quat(r: &Rotation3<f64>) -> [f64; 4] {
    let q = UnitQuaternion::from_rotation_matrix(r);
    [q.w, q.i, q.j, q.k]
}

/// A unit vector orthogonal to `n`, at a random angle.
fn tangent(n: &Vec3, rng: &mut Rng) -> Vec3 {
    let o = if n.x.abs() < 0.6 {
        Vec3::x()
    } else {
        Vec3::y()
    };
    let u = n.cross(&o).normalize();
    let v = n.cross(&u);
    let t = rng.range(0.0, std::f64::consts::TAU);
    u * t.cos() + v * t.sin()
}

/// The witness errors of an answer (world units): support planes, outside the shapes, and
/// the identity `closest2 − closest1 = sd·n`.
fn witness_error(sd: &SignedDistance, o1: &Posed, o2: &Posed) -> [f64; 3] {
    let n = sd.normal;
    let plane = (n.dot(&sd.closest1) - o1.h(&n))
        .abs()
        .max(((-n).dot(&sd.closest2) - o2.h(&-n)).abs());
    let outside = o1.excess(&sd.closest1).max(o2.excess(&sd.closest2));
    let identity = (sd.closest2 - sd.closest1 - n * sd.distance).norm();
    [plane, outside, identity]
}

/// Shape 1 of kind `k1` with a flat face turned to face shape 2 (kind `k2`, a flat face
/// turned against it when it has one), overlapping by a random depth at a random offset
/// along the face. Returns the poses and whether shape 2's face is parallel.
#[allow(clippy::type_complexity)]
fn face_to_face(k2: Kind, o1: &Oracle, o2: &Oracle, ell: f64, rng: &mut Rng) -> (Pose, Pose, Vec3) {
    let f1 = face(o1, rng);
    let rot1 = dcol::math::rotation_from_quaternion(rng.quat());
    let r1 = Vec3::new(
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
        rng.range(-2.0, 2.0),
    );
    let n = rot1 * f1.normal;
    let rot1 = Rotation3::from_matrix_unchecked(rot1);
    let depth = ell * 10f64.powf(rng.range(-6.0, -0.5));
    let face1 = r1 + rot1 * f1.centre;
    let (rot2, contact2) = if FLAT.contains(&k2) {
        // Shape 2's face against shape 1's, turned about the normal at random.
        let f2 = face(o2, rng);
        let spin = Rotation3::from_axis_angle(
            &Unit::new_normalize(f2.normal),
            rng.range(0.0, std::f64::consts::TAU),
        );
        let rot2 = align(&f2.normal, &-n) * spin;
        let slide = tangent(&n, rng) * rng.range(0.0, 1.0) * (f1.radius + f2.radius);
        (rot2, rot2 * f2.centre - slide)
    } else {
        // A curved shape's lowest point along the normal, over the face.
        let rot2 =
            Rotation3::from_matrix_unchecked(dcol::math::rotation_from_quaternion(rng.quat()));
        let low = {
            let m = rot2.transpose() * (-n);
            let h = o2.h(&m);
            n * (-h)
        };
        let slide = tangent(&n, rng) * rng.range(0.0, 1.0) * f1.radius;
        (rot2, low - slide)
    };
    // Shape 2's face point (or lowest point) sits `depth` below shape 1's face.
    let r2 = face1 - n * depth - contact2;
    (
        Pose::new([r1.x, r1.y, r1.z], quat(&rot1)).unwrap(),
        Pose::new([r2.x, r2.y, r2.z], quat(&rot2)).unwrap(),
        n,
    )
}

#[test]
fn witnesses_lie_on_their_shapes_face_to_face() {
    let opts = Options::default();
    let per: usize = std::env::var("DCOL_FACE_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000);
    let mut failures = Vec::new();
    let (mut cases, mut along_face, mut worst) = (0usize, 0usize, [0.0f64; 3]);
    let mut kinds = Vec::new();
    for (i, &k1) in FLAT.iter().enumerate() {
        for &k2 in FLAT[i..].iter().chain(&CURVED) {
            kinds.push((k1, k2));
        }
    }
    for (pair, &(k1, k2)) in kinds.iter().enumerate() {
        let mut rng = Rng::new(0xFACE_0000 + pair as u64);
        for case in 0..per {
            let ((s1, o1), (s2, o2)) = (shape(k1, &mut rng), shape(k2, &mut rng));
            let ell = s1.bounding_radius().max(s2.bounding_radius());
            let (p1, p2, n) = face_to_face(k2, &o1, &o2, ell, &mut rng);
            // Either order.
            let swap = rng.next_u64() % 2 == 1;
            let sd = if swap {
                signed_distance(&s2, &p2, &s1, &p1, &opts).unwrap()
            } else {
                signed_distance(&s1, &p1, &s2, &p2, &opts).unwrap()
            };
            let (q1, q2) = (Posed::new(&o1, &p1), Posed::new(&o2, &p2));
            let e = if swap {
                witness_error(&sd, &q2, &q1)
            } else {
                witness_error(&sd, &q1, &q2)
            };
            cases += 1;
            if sd.normal.dot(&n).abs() > 1.0 - 1e-9 {
                along_face += 1;
            }
            for j in 0..3 {
                worst[j] = worst[j].max(e[j] / ell);
            }
            if sd.status != SolveStatus::Converged || e.iter().any(|v| *v > 1e-9 * ell) {
                failures.push(format!(
                    "{k1:?}-{k2:?} #{case} (swap {swap}): plane {:.1e}, outside {:.1e}, identity \
                     {:.1e} (ℓ), sd {:e}, {:?}, {:?}",
                    e[0] / ell,
                    e[1] / ell,
                    e[2] / ell,
                    sd.distance,
                    sd.path,
                    sd.status
                ));
            }
        }
    }
    println!(
        "{cases} face-to-face poses ({along_face} with the face's normal as the answer's): worst \
         witness off its support plane {:.1e} ℓ, outside its shape {:.1e} ℓ, identity {:.1e} ℓ",
        worst[0], worst[1], worst[2]
    );
    for f in failures.iter().take(30) {
        println!("{f}");
    }
    assert!(failures.is_empty(), "{} failures", failures.len());
    // The poses do test face-to-face contacts.
    assert!(along_face * 2 > cases, "{along_face} of {cases}");
}

/// The defect as reported: two boxes (and box-like polytopes) with the same attitude, overlapping
/// at random offsets along all three axes.
#[test]
fn same_attitude_boxes_have_witnesses_on_them() {
    let opts = Options::default();
    let mut rng = Rng::new(0xB0C5);
    let (mut overlapping, mut bad) = (0, Vec::new());
    for case in 0..20_000 {
        let h1 = [0; 3].map(|_| rng.range(0.2, 1.0));
        let h2 = [0; 3].map(|_| rng.range(0.2, 1.0));
        let (a1, b1) = box_rows(h1);
        let (a2, b2) = box_rows(h2);
        let o1 = Oracle::Polytope(a1.clone(), b1.clone(), polytope_vertices(&a1, &b1));
        let o2 = Oracle::Polytope(a2.clone(), b2.clone(), polytope_vertices(&a2, &b2));
        let s1 = Shape::cuboid(h1[0], h1[1], h1[2]).unwrap();
        // Every other case, shape 2 is the same box given by its planes.
        let s2 = if case % 2 == 0 {
            Shape::cuboid(h2[0], h2[1], h2[2]).unwrap()
        } else {
            let rows: Vec<[f64; 3]> = a2.iter().map(|r| [r.x, r.y, r.z]).collect();
            Shape::polytope(&rows, &b2).unwrap()
        };
        let q = rng.quat();
        let rot = dcol::math::rotation_from_quaternion(q);
        let off = rot * Vec3::from([0, 1, 2].map(|i| rng.range(-1.0, 1.0) * (h1[i] + h2[i])));
        let p1 = Pose::new([0.3, -0.2, 0.1], q).unwrap();
        let p2 = Pose::new([0.3 + off.x, -0.2 + off.y, 0.1 + off.z], q).unwrap();
        let sd = signed_distance(&s1, &p1, &s2, &p2, &opts).unwrap();
        if sd.distance >= 0.0 {
            continue;
        }
        overlapping += 1;
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        let e = witness_error(&sd, &Posed::new(&o1, &p1), &Posed::new(&o2, &p2));
        if sd.status != SolveStatus::Converged || e.iter().any(|v| *v > 1e-9 * ell) {
            bad.push(format!("#{case}: {e:?}, {:?}", sd.path));
        }
    }
    println!(
        "{overlapping} overlapping, {} with a witness off its box",
        bad.len()
    );
    assert!(overlapping > 5000);
    assert!(bad.is_empty(), "{bad:?}");
}
