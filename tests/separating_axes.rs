//! The separating-axis penetration of overlapping boxes and small hulls (`crate::solver::sat`,
//! `DistancePath::SeparatingAxes`) against EPA on the same geometry: a box given with eleven
//! redundant planes more (17 rows, past the separating-axis limit of 16 facets) is the same set,
//! answered by GJK and EPA. Random attitudes and offsets, face-parallel pairs at random offsets
//! (the same attitude, or tilted by 1e-9 to 1e-3), and padded hulls (rounded boxes, by the
//! identity sd = sd(hulls) − R₁ − R₂ checked against EPA on the hulls).

mod common;

use common::random::Rng;
use dcol::{signed_distance, DistancePath, Options, Pose, Shape, SolveStatus};

const AXES: [[f64; 3]; 6] = [
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [-1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 0.0, -1.0],
];

/// The box of half extents `h`: as dcol's box, and as a polytope of 17 rows (the six faces and
/// eleven planes that touch nothing) that the separating axes leave to EPA.
fn boxes(h: [f64; 3], rng: &mut Rng) -> (Shape, Shape) {
    let mut a: Vec<[f64; 3]> = AXES.to_vec();
    let mut b: Vec<f64> = (0..6).map(|i| h[i % 3]).collect();
    let reach = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
    for _ in 0..11 {
        a.push(rng.unit::<3>());
        b.push(reach * rng.range(1.01, 1.5));
    }
    (
        Shape::cuboid(h[0], h[1], h[2]).unwrap(),
        Shape::polytope(&a, &b).unwrap(),
    )
}

fn corners(h: [f64; 3]) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { h[k] } else { -h[k] }))
        .collect()
}

/// Whether `p` (world) lies on the box of half extents `h` at `pose`, within `tol`.
fn on_box(p: &dcol::Vec3, h: [f64; 3], pose: &Pose, tol: f64) -> bool {
    let u = pose.rotation().transpose() * (p - pose.position());
    let out = (0..3)
        .map(|k| u[k].abs() - h[k])
        .fold(f64::NEG_INFINITY, f64::max);
    out.abs() <= tol
}

#[test]
fn boxes_agree_with_epa_on_the_same_geometry() {
    let mut rng = Rng::new(2024);
    let o = Options::default();
    let (mut sat, mut cases) = (0, 0);
    let mut worst: f64 = 0.0;
    for i in 0..6000 {
        let h1 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let h2 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let (b1, r1) = boxes(h1, &mut rng);
        let (b2, r2) = boxes(h2, &mut rng);
        let q1 = rng.quat();
        // Every third case face-parallel: the same attitude, or tilted by up to 1e-3.
        let q2 = match i % 3 {
            0 => rng.quat(),
            1 => q1,
            _ => {
                let t = 10f64.powf(rng.range(-9.0, -3.0));
                let e = rng.unit::<3>();
                let dq = [1.0, t * e[0], t * e[1], t * e[2]];
                // q1 ⊗ dq
                [
                    q1[0] * dq[0] - q1[1] * dq[1] - q1[2] * dq[2] - q1[3] * dq[3],
                    q1[0] * dq[1] + q1[1] * dq[0] + q1[2] * dq[3] - q1[3] * dq[2],
                    q1[0] * dq[2] - q1[1] * dq[3] + q1[2] * dq[0] + q1[3] * dq[1],
                    q1[0] * dq[3] + q1[1] * dq[2] - q1[2] * dq[1] + q1[3] * dq[0],
                ]
            }
        };
        let p1 = Pose::new([0.0; 3], q1).unwrap();
        let dir = rng.unit::<3>();
        let len = rng.range(0.05, 1.0) * (h1.iter().sum::<f64>() + h2.iter().sum::<f64>()) / 3.0;
        let p2 = Pose::new(dir.map(|c| c * len), q2).unwrap();
        let a = signed_distance(&b1, &p1, &b2, &p2, &o).unwrap();
        let b = signed_distance(&r1, &p1, &r2, &p2, &o).unwrap();
        assert_ne!(b.path, DistancePath::SeparatingAxes);
        if a.path != DistancePath::SeparatingAxes {
            continue;
        }
        assert_eq!(a.status, SolveStatus::Converged);
        let ell = b1.bounding_radius().max(b2.bounding_radius());
        assert!(b.status.is_converged(), "case {i}: EPA open");
        let e = (a.distance - b.distance).abs();
        worst = worst.max(e / ell);
        assert!(
            e <= 1e-9 * ell,
            "case {i}: {} vs EPA {}",
            a.distance,
            b.distance
        );
        // The witnesses: on their boxes, and the identity.
        assert!(
            on_box(&a.closest1, h1, &p1, 1e-10 * ell),
            "case {i}: witness 1 off the box"
        );
        assert!(
            on_box(&a.closest2, h2, &p2, 1e-10 * ell),
            "case {i}: witness 2 off the box"
        );
        let id = a.closest2 - a.closest1 - a.normal * a.distance;
        assert!(id.norm() <= 1e-12 * ell, "case {i}: identity {}", id.norm());
        assert!((a.normal.norm() - 1.0).abs() < 1e-14);
        sat += 1;
        cases += 1;
    }
    println!(
        "{sat} overlapping box pairs by the separating axes, worst depth difference {worst:e}·ℓ"
    );
    assert!(cases > 3000, "only {cases} cases took the separating axes");
}

#[test]
fn rounded_boxes_are_their_hulls_less_the_radii() {
    let mut rng = Rng::new(99);
    let o = Options::default();
    let mut sat = 0;
    for i in 0..3000 {
        let h1 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let h2 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let (pad1, pad2) = (rng.range(0.0, 0.2), rng.range(0.0, 0.2));
        let s1 = Shape::convex_hull(&corners(h1), pad1).unwrap();
        let s2 = Shape::convex_hull(&corners(h2), pad2).unwrap();
        let (_, r1) = boxes(h1, &mut rng);
        let (_, r2) = boxes(h2, &mut rng);
        let p1 = Pose::new([0.0; 3], rng.quat()).unwrap();
        let dir = rng.unit::<3>();
        let len = rng.range(0.05, 1.0) * (h1.iter().sum::<f64>() + h2.iter().sum::<f64>()) / 3.0;
        let p2 = Pose::new(dir.map(|c| c * len), rng.quat()).unwrap();
        let a = signed_distance(&s1, &p1, &s2, &p2, &o).unwrap();
        if a.path != DistancePath::SeparatingAxes {
            continue;
        }
        let b = signed_distance(&r1, &p1, &r2, &p2, &o).unwrap();
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        assert!(b.status.is_converged() && b.distance < 0.0, "case {i}");
        let want = b.distance - pad1 - pad2;
        assert!(
            (a.distance - want).abs() <= 1e-9 * ell,
            "case {i}: {} vs {want}",
            a.distance
        );
        let id = a.closest2 - a.closest1 - a.normal * a.distance;
        assert!(id.norm() <= 1e-12 * ell);
        // Each witness is its hull's witness moved out by the radius: on the rounded box.
        let core1 = a.closest1 - a.normal * pad1;
        assert!(on_box(&core1, h1, &p1, 1e-10 * ell), "case {i}");
        sat += 1;
    }
    println!("{sat} overlapping rounded-box pairs by the separating axes");
    assert!(sat > 1000);
}

/// The closed-form manifold of two boxes (`query::contact_boxes`) against the general path's on
/// the same boxes given with redundant planes: the same normal, the same points and depths (as
/// sets), on overlapping, touching and nearly touching pairs, with and without a margin.
#[test]
fn box_manifolds_agree_with_the_general_path() {
    use dcol::contact_manifold;
    let mut rng = Rng::new(7);
    let o = Options::default();
    let (mut compared, mut points) = (0, 0);
    for i in 0..4000 {
        let h1 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let h2 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let (b1, r1) = boxes(h1, &mut rng);
        let (b2, r2) = boxes(h2, &mut rng);
        let q1 = rng.quat();
        let q2 = if i % 2 == 0 { q1 } else { rng.quat() };
        let p1 = Pose::new([0.0; 3], q1).unwrap();
        let dir = rng.unit::<3>();
        let len = rng.range(0.3, 1.3) * (h1.iter().sum::<f64>() + h2.iter().sum::<f64>()) / 3.0;
        let p2 = Pose::new(dir.map(|c| c * len), q2).unwrap();
        let margin = if i % 3 == 0 { 0.0 } else { rng.range(0.0, 0.1) };
        let a = contact_manifold(&b1, &p1, &b2, &p2, margin, 16, &o).unwrap();
        let b = contact_manifold(&r1, &p1, &r2, &p2, margin, 16, &o).unwrap();
        let ell = b1.bounding_radius().max(b2.bounding_radius());
        assert!(
            (a.signed_distance - b.signed_distance).abs() <= 1e-9 * ell,
            "case {i}: {} vs {}",
            a.signed_distance,
            b.signed_distance
        );
        if a.is_empty() && b.is_empty() {
            continue;
        }
        assert!((a.normal - b.normal).norm() <= 1e-6, "case {i}: normals");
        // Every point of each is one of the other's (up to rounding).
        let near = |x: &dcol::Contact, ys: &[dcol::Contact]| {
            ys.iter().any(|y| {
                (x.position - y.position).norm() <= 1e-8 * ell
                    && (x.depth - y.depth).abs() <= 1e-9 * ell
            })
        };
        assert_eq!(
            a.len(),
            b.len(),
            "case {i}: {:?} vs {:?}",
            a.contacts(),
            b.contacts()
        );
        assert!(
            a.contacts().iter().all(|x| near(x, b.contacts())),
            "case {i}"
        );
        assert!(
            b.contacts().iter().all(|x| near(x, a.contacts())),
            "case {i}"
        );
        compared += 1;
        points += a.len();
    }
    println!("{compared} box manifolds ({points} points) equal to the general path's");
    assert!(compared > 1500);
}

/// The C function's contacts of two boxes apart by less than the margin (their closed form: a
/// clipped face as far from the facet as the facet's axis separates them) against Rust's
/// manifold (the distance query and the general features): the same points, depths and normal
/// to rounding.
#[test]
fn apart_boxes_within_the_margin_from_c_agree_with_rust() {
    use dcol::contact_manifold;
    use dcol::ffi::*;
    let mut rng = Rng::new(41);
    let o = Options::default();
    let mut compared = 0;
    for i in 0..3000 {
        let h1 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let h2 = [0; 3].map(|_| rng.range(0.1, 1.0));
        let q1 = rng.quat();
        // Face to face and aligned, as boxes in a stack or a wall, or tilted a little.
        let q2 = if i % 2 == 0 {
            q1
        } else {
            let e = rng.unit::<3>();
            let t = rng.range(0.0, 0.05);
            [
                q1[0] - t * (e[0] * q1[1] + e[1] * q1[2] + e[2] * q1[3]),
                q1[1] + t * e[0],
                q1[2] + t * e[1],
                q1[3] + t * e[2],
            ]
        };
        let p1 = Pose::new([0.0; 3], q1).unwrap();
        let axis = (i / 2) % 3;
        let gap = rng.range(0.0, 0.05);
        let side = dcol::math::rotation_from_quaternion(q1)
            .column(axis)
            .into_owned();
        let lateral = rng.unit::<3>().map(|c| c * rng.range(0.0, 0.3));
        let along = h1[axis] + h2[axis] + gap;
        let r2 =
            side * along + dcol::Vec3::from(lateral) - side * side.dot(&dcol::Vec3::from(lateral));
        let p2 = Pose::new([r2.x, r2.y, r2.z], q2).unwrap();
        let margin = 0.06;
        let (b1, b2) = (
            Shape::cuboid(h1[0], h1[1], h1[2]).unwrap(),
            Shape::cuboid(h2[0], h2[1], h2[2]).unwrap(),
        );
        let rust = contact_manifold(&b1, &p1, &b2, &p2, margin, 16, &o).unwrap();
        let (mut c1, mut c2) = (std::ptr::null_mut(), std::ptr::null_mut());
        let cp = |p: &Pose| dcol_pose {
            position: [p.position().x, p.position().y, p.position().z],
            quaternion: p.quaternion(),
        };
        let mut out = [dcol_contact {
            position: [0.0; 3],
            normal: [0.0; 3],
            depth: 0.0,
        }; 16];
        let mut count = 0usize;
        // SAFETY: valid arguments: shapes made here, poses on the stack, 16 contacts of room.
        unsafe {
            assert_eq!(
                dcol_shape_new_box(h1[0], h1[1], h1[2], &mut c1),
                dcol_status::DCOL_OK
            );
            assert_eq!(
                dcol_shape_new_box(h2[0], h2[1], h2[2], &mut c2),
                dcol_status::DCOL_OK
            );
            let st = dcol_contacts(
                c1,
                &cp(&p1),
                c2,
                &cp(&p2),
                margin,
                std::ptr::null(),
                out.as_mut_ptr(),
                16,
                &mut count,
            );
            assert_eq!(st, dcol_status::DCOL_OK);
            dcol_shape_free(c1);
            dcol_shape_free(c2);
        }
        let ell = b1.bounding_radius().max(b2.bounding_radius());
        assert_eq!(
            count,
            rust.len(),
            "case {i}: {:?} vs {:?}",
            &out[..count],
            rust.contacts()
        );
        for c in &out[..count] {
            let n = dcol::Vec3::from(c.normal);
            assert!((n - rust.normal).norm() <= 1e-9, "case {i}: normal");
            assert!(
                rust.contacts()
                    .iter()
                    .any(
                        |r| (r.position - dcol::Vec3::from(c.position)).norm() <= 1e-9 * ell
                            && (r.depth - c.depth).abs() <= 1e-9 * ell
                    ),
                "case {i}: {c:?} not in {:?}",
                rust.contacts()
            );
        }
        compared += usize::from(count > 0);
    }
    println!("{compared} apart box pairs within the margin: the C function's contacts are Rust's");
    assert!(compared > 1000);
}

/// Half extents of the pyramid's cubes and the small tilts of a settling stack: exactly
/// aligned, and turned by 1e-9 to 1e-2 rad about a random axis.
const TILTS: [f64; 6] = [0.0, 1e-9, 1e-7, 1e-6, 1e-4, 1e-2];

/// The quaternion of a turn by `angle` about the unit `axis`.
fn turn(axis: [f64; 3], angle: f64) -> [f64; 4] {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, axis[0] * s, axis[1] * s, axis[2] * s]
}

/// The least of the 15 separating axes of two boxes (brute force in world axes): whether an
/// edge pair gives it (strictly below every facet's, by more than rounding).
fn edge_axis_wins(h1: [f64; 3], p1: &Pose, h2: [f64; 3], p2: &Pose) -> bool {
    let (r1, r2) = (p1.rotation(), p2.rotation());
    let d = p2.position() - p1.position();
    let f = |n: dcol::Vec3| {
        let h = |r: &dcol::math::Mat3, e: [f64; 3]| {
            (0..3)
                .map(|k| e[k] * r.column(k).dot(&n).abs())
                .sum::<f64>()
        };
        h(r1, h1) + h(r2, h2) - d.dot(&n).abs()
    };
    let faces = (0..3)
        .flat_map(|k| [r1.column(k).into_owned(), r2.column(k).into_owned()])
        .map(f)
        .fold(f64::INFINITY, f64::min);
    let mut edges = f64::INFINITY;
    for i in 0..3 {
        for j in 0..3 {
            let c = r1.column(i).cross(&r2.column(j));
            if c.norm() > 1e-6 {
                edges = edges.min(f(c / c.norm()));
            }
        }
    }
    edges < faces - 1e-12
}

/// A box of half extents `h` given as a polytope whose origin is `delta` below its centre
/// (not a centred box: the separating axes of general polytopes, then the general contact
/// features), and the pose that puts it where the centred box at `pose` is.
fn offset_box(h: [f64; 3], delta: f64, pose: &Pose) -> (Shape, Pose) {
    let b = [h[0], h[1], h[2] + delta, h[0], h[1], h[2] - delta];
    let shape = Shape::polytope(&AXES, &b).unwrap();
    let r = pose.position() - pose.rotation().column(2) * delta;
    (
        shape,
        Pose::new([r.x, r.y, r.z], pose.quaternion()).unwrap(),
    )
}

/// Boxes of a pyramid or a stack settling (one on another, half over it or fully, tilted by
/// 0 to 1e-2 rad, shifted sideways by up to 1e-4 and sunk by up to 1e-3), both orders. Where
/// an edge pair is the least axis, the manifold's signed distance and normal are
/// `signed_distance`'s bit for bit (the separating axes' answer, now computed once). Every
/// manifold's points are the general path's on the same boxes given as polytopes about
/// another origin (the general polytopes' separating axes, then the faces clipped), as sets
/// (positions within 1e-8 of the size, depths 1e-12), where the tilt (1e-6 or more) keeps the
/// box edges' crossings well conditioned; every point, at every tilt, is midway between the two
/// boxes' surfaces.
#[test]
fn tilted_stacked_boxes_agree_with_the_general_path() {
    use dcol::contact_manifold;
    let mut rng = Rng::new(32);
    let o = Options::default();
    let (mut compared, mut edge_cases, mut points) = (0, 0, 0);
    for i in 0..3000 {
        let h = if i % 3 == 0 {
            [0.1; 3]
        } else {
            [0; 3].map(|_| rng.range(0.05, 0.3))
        };
        let b = Shape::cuboid(h[0], h[1], h[2]).unwrap();
        let q1 = if i % 2 == 0 {
            [1.0, 0.0, 0.0, 0.0]
        } else {
            rng.quat()
        };
        let tilt = TILTS[i % TILTS.len()];
        let q2 = {
            // q1 turned by the tilt (body frame).
            let t = turn(rng.unit::<3>(), tilt);
            [
                q1[0] * t[0] - q1[1] * t[1] - q1[2] * t[2] - q1[3] * t[3],
                q1[0] * t[1] + q1[1] * t[0] + q1[2] * t[3] - q1[3] * t[2],
                q1[0] * t[2] - q1[1] * t[3] + q1[2] * t[0] + q1[3] * t[1],
                q1[0] * t[3] + q1[1] * t[2] - q1[2] * t[1] + q1[3] * t[0],
            ]
        };
        let p1 = Pose::new([0.0; 3], q1).unwrap();
        let rot = dcol::math::rotation_from_quaternion(q1);
        // On top, half over (as the pyramid's) or fully, sideways shifts at the faces' edges.
        let sign = |rng: &mut Rng| if rng.unif() < 0.5 { -1.0 } else { 1.0 };
        let over = [0.0, h[0] + 0.005, h[0]][i % 3] * sign(&mut rng);
        let side = [0.0, 1e-9, 1e-7, 1e-4][(i / 3) % 4] * sign(&mut rng);
        let sink = rng.range(0.0, 1e-3);
        let r = rot * dcol::Vec3::new(over, side, 2.0 * h[2] - sink);
        let p2 = Pose::new([r.x, r.y, r.z], q2).unwrap();
        let ell = b.bounding_radius();
        for (pa, pb) in [(&p1, &p2), (&p2, &p1)] {
            let a = contact_manifold(&b, pa, &b, pb, 0.0, 16, &o).unwrap();
            let sd = signed_distance(&b, pa, &b, pb, &o).unwrap();
            if sd.distance < 0.0 && edge_axis_wins(h, pa, h, pb) {
                assert_eq!(a.signed_distance, sd.distance, "case {i}");
                assert_eq!(a.normal, sd.normal, "case {i}");
                edge_cases += 1;
            } else {
                // A facet's closed form, against the separating axes or (witnesses hidden by
                // rounding) EPA's certified bracket.
                assert!(
                    (a.signed_distance - sd.distance).abs() <= 1e-9 * ell,
                    "case {i}: {} vs {} ({:?}), {:?} vs {:?}",
                    a.signed_distance,
                    sd.distance,
                    sd.path,
                    a.normal,
                    sd.normal
                );
            }
            for c in a.contacts() {
                for (pose, s) in [(pa, 0.5), (pb, -0.5)] {
                    assert!(
                        on_box(&(c.position + c.normal * (s * c.depth)), h, pose, 1e-12),
                        "case {i}"
                    );
                }
            }
            points += a.len();
            if tilt < 1e-6 {
                continue;
            }
            let (ga, gpa) = offset_box(h, 0.25 * h[2], pa);
            let (gb, gpb) = offset_box(h, -0.125 * h[2], pb);
            let g = contact_manifold(&ga, &gpa, &gb, &gpb, 0.0, 16, &o).unwrap();
            assert!(
                (a.signed_distance - g.signed_distance).abs() <= 1e-12 * ell,
                "case {i}"
            );
            if a.is_empty() && g.is_empty() {
                continue;
            }
            assert!((a.normal - g.normal).norm() <= 1e-12, "case {i}: normals");
            let near = |x: &dcol::Contact, ys: &[dcol::Contact]| {
                ys.iter().any(|y| {
                    (x.position - y.position).norm() <= 1e-8 * ell
                        && (x.depth - y.depth).abs() <= 1e-12 * ell
                })
            };
            assert!(
                a.len() == g.len()
                    && a.contacts().iter().all(|x| near(x, g.contacts()))
                    && g.contacts().iter().all(|x| near(x, a.contacts())),
                "case {i}: {:?} vs {:?}",
                a.contacts(),
                g.contacts()
            );
            compared += 1;
        }
    }
    println!(
        "{points} points of stacked boxes on both surfaces; {compared} manifolds equal to the \
         general path's, {edge_cases} with an edge pair least"
    );
    assert!(compared > 2000 && edge_cases > 300);
}
