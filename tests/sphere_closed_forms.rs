//! Spheres and capsules touching or overlapping another shape take the closed forms at once
//! (`signed_distance` without the distance query's try): thousands of random poses (exact
//! touching, boxes tilted by 1e-9 to 1e-3 rad, deep overlaps, both orders) checked against
//! the analytic answer (a sphere against a box, two spheres, a sphere against a capsule) and
//! against the general path: moving the sphere out along the normal by the depth plus a gap
//! must leave the distance query (GJK on the support maps) exactly that gap, with the same
//! normal and the same witness on the other shape. Contact manifolds of these pairs are one
//! point, the witnesses' midpoint at depth −sd, and the C function writes the same numbers.

use dcol::ffi::{dcol_contact, dcol_contacts, dcol_pose, dcol_shape, dcol_shape_free};
use dcol::ffi::{dcol_shape_new_box, dcol_shape_new_sphere, dcol_status};
use dcol::{contact_manifold, distance, signed_distance, DistancePath, Options, Pose, Shape, Vec3};

mod common;

use common::xorshift::Rng;

/// The attitudes this file draws, on the shared generator.
impl Rng {
    /// A random attitude: identity, a tilt of 1e-9 to 1e-3 rad, or any.
    fn quaternion(&mut self) -> [f64; 4] {
        let axis = self.unit();
        let angle = match (self.next() * 3.0) as u32 {
            0 => 0.0,
            1 => 10f64.powf(self.range(-9.0, -3.0)),
            _ => self.range(0.0, std::f64::consts::PI),
        };
        let (s, c) = (0.5 * angle).sin_cos();
        [c, s * axis.x, s * axis.y, s * axis.z]
    }
}

fn opts() -> Options {
    Options {
        tolerance: 1e-12,
        ..Options::default()
    }
}

/// The signed distance of a box (half extents `h`, at `pb`) and a ball (centre `c`, radius
/// `rho`), the box first: distance, unit normal from the box to the ball, witness on the box;
/// `None` where the normal is not unique (the centre on a face with a tie inside).
fn box_ball(h: &Vec3, pb: &Pose, c: &Vec3, rho: f64) -> Option<(f64, Vec3, Vec3)> {
    let rot = pb.rotation();
    let x = rot.transpose() * (c - pb.position());
    let q = Vec3::from_fn(|i, _| x[i].clamp(-h[i], h[i]));
    let gap = x - q;
    let len = gap.norm();
    if len > 1e-7 {
        return Some((len - rho, rot * (gap / len), pb.position() + rot * q));
    }
    if len > 0.0 {
        return None; // the normal carries rounding of relative size ε/len
    }
    let mut gaps: Vec<(f64, usize)> = (0..3).map(|i| (h[i] - x[i].abs(), i)).collect();
    gaps.sort_by(|a, b| a.0.total_cmp(&b.0));
    if gaps[1].0 - gaps[0].0 < 1e-9 {
        return None;
    }
    let (depth, k) = gaps[0];
    let mut u = Vec3::zeros();
    u[k] = if x[k] < 0.0 { -1.0 } else { 1.0 };
    let mut on = x;
    on[k] = u[k] * h[k];
    Some((-(depth + rho), rot * u, pb.position() + rot * on))
}

/// Asserts `a` and `b` within `tol`.
fn close(what: &str, a: f64, b: f64, tol: f64) {
    assert!(
        (a - b).abs() <= tol,
        "{what}: {a} against {b} (tolerance {tol})"
    );
}

#[test]
fn sphere_box_matches_the_analytic_answer() {
    let mut rng = Rng(0x5eed_0001);
    let mut checked = 0;
    for case in 0..6000 {
        let h = Vec3::new(
            rng.range(0.1, 2.0),
            rng.range(0.1, 2.0),
            rng.range(0.1, 2.0),
        );
        let bx = Shape::cuboid(h.x, h.y, h.z).unwrap();
        let rho = rng.range(0.05, 1.0);
        let ball = Shape::sphere(rho).unwrap();
        let pb = Pose::new(
            [
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
                rng.range(-3.0, 3.0),
            ],
            rng.quaternion(),
        )
        .unwrap();
        // Centres: on a face at exactly the radius (touching), near the surface, deep inside.
        let body = match case % 4 {
            0 => {
                let k = case / 4 % 3;
                let mut b = Vec3::new(
                    rng.range(-h.x, h.x),
                    rng.range(-h.y, h.y),
                    rng.range(-h.z, h.z),
                );
                b[k] = h[k] + rho;
                b
            }
            1 => Vec3::from_fn(|i, _| rng.range(-h[i] - rho, h[i] + rho)),
            2 => Vec3::from_fn(|i, _| rng.range(-0.9, 0.9) * h[i]),
            _ => {
                let q = Vec3::from_fn(|i, _| rng.range(-h[i], h[i]));
                q + rng.unit() * rng.range(0.0, rho)
            }
        };
        let c = pb.position() + pb.rotation() * body;
        let pc = Pose::new([c.x, c.y, c.z], rng.quaternion()).unwrap();
        let c = *pc.position();
        let Some((sd, n, on_box)) = box_ball(&h, &pb, &c, rho) else {
            continue;
        };
        let scale = h.norm() + rho + c.norm();
        let tol = 1e-12 * scale;
        let a = signed_distance(&bx, &pb, &ball, &pc, &opts()).unwrap();
        close("sd", a.distance, sd, tol);
        if sd.abs() > 1e-9 || case % 4 != 0 {
            assert!(
                (a.normal - n).norm() <= 1e-9,
                "case {case}: normal {} vs {n}",
                a.normal
            );
        }
        assert!(
            (a.closest1 - on_box).norm() <= 1e-9 * scale,
            "case {case}: box witness"
        );
        close("ball witness", (a.closest2 - c).norm(), rho, tol);
        // Shape 2 first: the same with the normal turned.
        let b = signed_distance(&ball, &pc, &bx, &pb, &opts()).unwrap();
        close("sd, sphere first", b.distance, sd, tol);
        assert!((b.closest2 - on_box).norm() <= 1e-9 * scale);
        // The manifold: one point midway between the witnesses, at depth −sd.
        let m = contact_manifold(&bx, &pb, &ball, &pc, 0.0, 4, &opts()).unwrap();
        if sd <= 0.0 {
            assert_eq!(m.len(), 1, "case {case}");
            let p = m.contacts()[0];
            close("depth", p.depth, -sd, tol);
            let mid = on_box + (c - n * rho - on_box) * 0.5;
            assert!((p.position - mid).norm() <= 1e-9 * scale, "case {case}");
            checked += 1;
        }
    }
    assert!(checked > 3000, "{checked} overlapping cases");
}

/// The distance from `x` to the segment `c ± half · axis`.
fn to_segment(x: &Vec3, c: &Vec3, axis: &Vec3, half: f64) -> f64 {
    let t = (x - c).dot(axis).clamp(-half, half);
    (x - (c + axis * t)).norm()
}

/// A sphere (`capsule` false) or a capsule touching or overlapping `solid` from a random
/// direction; the general path's check.
fn against_general_path(solid: &Shape, name: &str, seed: u64, capsule: bool) {
    let mut rng = Rng(seed);
    let mut checked = 0;
    for case in 0..1500 {
        let rho = rng.range(0.05, 1.0);
        let half = if capsule { rng.range(0.05, 1.0) } else { 0.0 };
        let ball = if capsule {
            Shape::capsule(rho, 2.0 * half).unwrap()
        } else {
            Shape::sphere(rho).unwrap()
        };
        let q = rng.quaternion();
        let ps = Pose::new(
            [
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
            ],
            rng.quaternion(),
        )
        .unwrap();
        // The ball's centre at a random point of the solid's bounding ball, often inside.
        let reach = solid.bounding_radius() * rng.range(0.0, 1.2);
        let c = ps.position() + rng.unit() * reach;
        let pc = Pose::new([c.x, c.y, c.z], q).unwrap();
        let axis = pc.rotation() * Vec3::x();
        let sd = signed_distance(solid, &ps, &ball, &pc, &opts()).unwrap();
        // The closed forms' answers only (deep overlaps whose segment meets the solid, and
        // a sphere inside a polytope's facets' tie, go to EPA, tested elsewhere).
        let closed = matches!(sd.path, DistancePath::ClosedForm | DistancePath::Segments);
        if sd.distance > 0.0 || !closed {
            continue;
        }
        let ell = solid.bounding_radius() + rho + half;
        // Witnesses: the ball's (capsule's) on its surface, the two a multiple of the normal
        // apart.
        close(
            "ball witness",
            to_segment(&sd.closest2, &c, &axis, half),
            rho,
            1e-12 * ell,
        );
        let gap = sd.closest2 - sd.closest1 - sd.normal * sd.distance;
        assert!(
            gap.norm() <= 1e-12 * ell,
            "{name} {case}: witnesses off the normal by {} ({:?}, sd {})",
            gap.norm(),
            sd.path,
            sd.distance
        );
        // Moved out along the normal by the depth and a gap δ, the pair is δ apart, by the
        // distance query, at the same normal and witness on the solid.
        let delta = 0.1 * rho;
        let out = c + sd.normal * (delta - sd.distance);
        let po = Pose::new([out.x, out.y, out.z], q).unwrap();
        let d = distance(solid, &ps, &ball, &po, &opts()).unwrap();
        close(
            &format!("{name} {case}: distance after the move"),
            d.distance,
            delta,
            1e-9 * ell,
        );
        assert!(
            (d.normal - sd.normal).norm() <= 1e-6,
            "{name} {case}: normal"
        );
        // A sphere's witness on the solid is unique; a capsule's need not be (its segment
        // parallel to a face): then both lie on the solid's supporting plane of normal n.
        let apart = if capsule {
            sd.normal.dot(&(d.closest1 - sd.closest1)).abs()
        } else {
            (d.closest1 - sd.closest1).norm()
        };
        assert!(
            apart <= 1e-6 * ell,
            "{name} {case}: solid witness {} vs {}",
            d.closest1,
            sd.closest1
        );
        // And the other order, the normal turned.
        let r = signed_distance(&ball, &pc, solid, &ps, &opts()).unwrap();
        close("sd, sphere first", r.distance, sd.distance, 1e-12 * ell);
        assert!(
            (r.normal + sd.normal).norm() <= 1e-9,
            "{name} {case}: normal, sphere first: {} {:?} vs {} {:?} sd {} {}",
            r.normal,
            r.path,
            sd.normal,
            sd.path,
            r.distance,
            sd.distance
        );
        checked += 1;
    }
    assert!(checked > 300, "{name}: {checked} closed-form cases");
}

#[test]
fn sphere_against_solids_agrees_with_the_general_path() {
    let solids = [
        (Shape::cuboid(0.7, 0.3, 1.1).unwrap(), "box"),
        (Shape::cylinder(0.6, 1.5).unwrap(), "cylinder"),
        (Shape::cone(1.5, 0.5).unwrap(), "cone"),
        (
            Shape::ellipsoid([[1.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 0.5]]).unwrap(),
            "ellipsoid",
        ),
        (
            Shape::polytope(
                &[
                    [1.0, 1.0, 1.0],
                    [1.0, -1.0, -1.0],
                    [-1.0, 1.0, -1.0],
                    [-1.0, -1.0, 1.0],
                    [0.0, 0.0, -1.0],
                ],
                &[1.0, 1.2, 0.9, 1.1, 0.8],
            )
            .unwrap(),
            "polytope",
        ),
        (Shape::capsule(0.4, 1.2).unwrap(), "capsule"),
        (Shape::sphere(0.8).unwrap(), "sphere"),
    ];
    for (i, (s, name)) in solids.iter().enumerate() {
        against_general_path(s, name, 0xC0FFEE + i as u64, false);
    }
}

#[test]
fn capsule_against_solids_agrees_with_the_general_path() {
    let solids = [
        (Shape::cuboid(0.7, 0.3, 1.1).unwrap(), "box"),
        (Shape::cylinder(0.6, 1.5).unwrap(), "cylinder"),
        (Shape::cone(1.5, 0.5).unwrap(), "cone"),
        (Shape::capsule(0.4, 1.2).unwrap(), "capsule"),
    ];
    for (i, (s, name)) in solids.iter().enumerate() {
        against_general_path(s, name, 0xCAFE + i as u64, true);
    }
}

#[test]
fn sphere_pairs_match_the_analytic_answer() {
    // Two spheres and a sphere on a capsule: |c₂ − c₁| − ρ₁ − ρ₂ from the segment's closest
    // point, exact touching included.
    let mut rng = Rng(0x5eed_0002);
    for case in 0..3000 {
        let (r1, r2) = (rng.range(0.1, 1.0), rng.range(0.1, 1.0));
        let half = if case % 2 == 0 {
            0.0
        } else {
            rng.range(0.1, 1.0)
        };
        let one = if half == 0.0 {
            Shape::sphere(r1).unwrap()
        } else {
            Shape::capsule(r1, 2.0 * half).unwrap()
        };
        let two = Shape::sphere(r2).unwrap();
        let p1 = Pose::new([0.0; 3], rng.quaternion()).unwrap();
        let t = rng.range(-half, half);
        let axis = p1.rotation() * Vec3::x();
        let foot = axis * t;
        // Perpendicular to the axis, at a random fraction of the radii (1: touching).
        let mut dir = rng.unit();
        dir -= axis * axis.dot(&dir);
        let dir = dir.normalize();
        let frac = if case % 5 == 0 {
            1.0
        } else {
            rng.range(0.05, 1.0)
        };
        let c = foot + dir * ((r1 + r2) * frac);
        let p2 = Pose::new([c.x, c.y, c.z], rng.quaternion()).unwrap();
        let sd = signed_distance(&one, &p1, &two, &p2, &opts()).unwrap();
        let truth = (c - foot).norm() - r1 - r2;
        close("sd", sd.distance, truth, 1e-12 * 4.0);
        assert!((sd.normal - dir).norm() <= 1e-9, "case {case}: normal");
        close("witness 1", (sd.closest1 - foot).norm(), r1, 1e-12 * 4.0);
        close("witness 2", (sd.closest2 - c).norm(), r2, 1e-12 * 4.0);
    }
}

/// The distance of two segments `c₁ ± h₁a₁`, `c₂ ± h₂a₂`, by ternary search along the first
/// (the distance to the second is convex along it).
fn segment_distance(c1: &Vec3, a1: &Vec3, h1: f64, c2: &Vec3, a2: &Vec3, h2: f64) -> f64 {
    let f = |t: f64| to_segment(&(c1 + a1 * t), c2, a2, h2);
    let (mut lo, mut hi) = (-h1, h1);
    for _ in 0..200 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if f(m1) < f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(lo).min(f(-h1)).min(f(h1))
}

#[test]
fn nearly_parallel_capsules_match_brute_force() {
    // Capsules side by side, the second turned from the first by 0, 1e-9 to 1e-3 rad or any
    // angle, overlapping or a little apart: `‖segments‖ − ρ₁ − ρ₂` by brute force. (The
    // segments' closest points lost the distance to cancellation below ~1e-6 rad: 7e-9 too
    // large at 1e-8.)
    let mut rng = Rng(0x5eed_0004);
    for case in 0..3000 {
        let (r1, r2) = (rng.range(0.1, 0.6), rng.range(0.1, 0.6));
        let (h1, h2) = (rng.range(0.1, 1.0), rng.range(0.1, 1.0));
        let one = Shape::capsule(r1, 2.0 * h1).unwrap();
        let two = Shape::capsule(r2, 2.0 * h2).unwrap();
        let q1 = rng.quaternion();
        let p1 = Pose::new([0.0; 3], q1).unwrap();
        let a1 = p1.rotation() * Vec3::x();
        let axis = rng.unit();
        let angle = match case % 4 {
            0 => 0.0,
            1 | 2 => 10f64.powf(rng.range(-9.0, -3.0)),
            _ => rng.range(0.0, 3.0),
        };
        let (sn, cs) = (0.5 * angle).sin_cos();
        let turn = [cs, sn * axis.x, sn * axis.y, sn * axis.z];
        // q2 = turn · q1.
        let q2 = [
            turn[0] * q1[0] - turn[1] * q1[1] - turn[2] * q1[2] - turn[3] * q1[3],
            turn[0] * q1[1] + turn[1] * q1[0] + turn[2] * q1[3] - turn[3] * q1[2],
            turn[0] * q1[2] - turn[1] * q1[3] + turn[2] * q1[0] + turn[3] * q1[1],
            turn[0] * q1[3] + turn[1] * q1[2] - turn[2] * q1[1] + turn[3] * q1[0],
        ];
        let mut side = rng.unit();
        side -= a1 * a1.dot(&side);
        let side = side.normalize();
        let c = side * ((r1 + r2) * rng.range(0.3, 1.1)) + a1 * rng.range(-h1, h1);
        let p2 = Pose::new([c.x, c.y, c.z], q2).unwrap();
        let a2 = p2.rotation() * Vec3::x();
        let truth = segment_distance(&Vec3::zeros(), &a1, h1, &c, &a2, h2) - r1 - r2;
        let sd = signed_distance(&one, &p1, &two, &p2, &opts()).unwrap();
        close(
            &format!("case {case} ({angle} rad)"),
            sd.distance,
            truth,
            1e-12 * 4.0,
        );
    }
}

#[test]
fn the_c_function_writes_the_rust_manifold() {
    let mut rng = Rng(0x5eed_0003);
    let bx = Shape::cuboid(0.5, 0.4, 0.3).unwrap();
    let ball = Shape::sphere(0.25).unwrap();
    let (mut b, mut s): (*mut dcol_shape, *mut dcol_shape) =
        (std::ptr::null_mut(), std::ptr::null_mut());
    // SAFETY: valid out-pointers.
    unsafe {
        assert_eq!(
            dcol_shape_new_box(0.5, 0.4, 0.3, &mut b),
            dcol_status::DCOL_OK
        );
        assert_eq!(dcol_shape_new_sphere(0.25, &mut s), dcol_status::DCOL_OK);
    }
    let mut written = 0;
    for _ in 0..500 {
        let q = rng.quaternion();
        let c = rng.unit() * rng.range(0.0, 0.8);
        let (pb, pc) = (
            dcol_pose {
                position: [0.0; 3],
                quaternion: q,
            },
            dcol_pose {
                position: [c.x, c.y, c.z],
                quaternion: [1.0, 0.0, 0.0, 0.0],
            },
        );
        let m = contact_manifold(
            &bx,
            &Pose::new(pb.position, pb.quaternion).unwrap(),
            &ball,
            &Pose::new(pc.position, pc.quaternion).unwrap(),
            0.0,
            4,
            &Options::default(),
        )
        .unwrap();
        let mut out = [dcol_contact::default(); 4];
        let mut n = 99usize;
        // SAFETY: live shapes (a `dcol_shape` is a `Shape`), valid poses and buffers.
        let st = unsafe {
            dcol_contacts(
                b,
                &pb,
                s,
                &pc,
                0.0,
                std::ptr::null(),
                out.as_mut_ptr(),
                4,
                &mut n,
            )
        };
        assert_eq!(st, dcol_status::DCOL_OK);
        assert_eq!(n, m.len());
        for (o, c) in out[..n].iter().zip(m.contacts()) {
            assert_eq!(o.depth, c.depth);
            assert_eq!(o.position, [c.position.x, c.position.y, c.position.z]);
            assert_eq!(o.normal, [c.normal.x, c.normal.y, c.normal.z]);
        }
        written += n;
    }
    // SAFETY: shapes made above, freed once.
    unsafe {
        dcol_shape_free(b);
        dcol_shape_free(s);
    }
    assert!(written > 100);
}
