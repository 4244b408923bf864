//! The closed forms of capsule–capsule proximity and of the sphere–box and sphere–cylinder
//! distance against independent truths on thousands of random poses:
//! - capsule–capsule α*: bisection on the sign of `dist(S₁(α), S₂(α)) − α(R₁ + R₂)`, the
//!   scaled segments' distance by a ternary search along segment 1 of the exact point–segment
//!   distance (convex in the parameter); attitudes random, nearly parallel (1e-9 to 1e-3 rad)
//!   and exactly parallel or antiparallel. The contact points must lie on the capsules' surfaces.
//! - sphere–box and sphere–cylinder distance (separated): the centre's closest point of the solid
//!   written out in the solid's frame (a clamp; the axial clamp and the radial shortening),
//!   both orders, at the default tolerance and at 1e-12.
//! - sphere–sphere distance (separated, gaps 1e-6 to 3): the centres' distance less the radii.

use dcol::{distance, proximity, DistancePath, Options, Pose, Shape, Vec3};

mod common;

use common::xorshift::Rng;

/// The attitudes this file draws, on the shared generator.
impl Rng {
    fn quaternion(&mut self) -> [f64; 4] {
        let axis = self.unit();
        let angle = self.range(0.0, std::f64::consts::PI);
        let (s, c) = (0.5 * angle).sin_cos();
        [c, s * axis.x, s * axis.y, s * axis.z]
    }
}

/// The quaternion product `a b`.
fn qmul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// Distance from `p` to the segment `c + t a`, `|t| ≤ h` (`a` unit).
fn point_segment(p: &Vec3, c: &Vec3, a: &Vec3, h: f64) -> f64 {
    let t = (p - c).dot(a).clamp(-h, h);
    (p - c - a * t).norm()
}

/// Distance between the segments `cᵢ + s aᵢ`, `|s| ≤ hᵢ`: a ternary search along segment 1.
fn segment_segment(c1: &Vec3, a1: &Vec3, h1: f64, c2: &Vec3, a2: &Vec3, h2: f64) -> f64 {
    let f = |s: f64| point_segment(&(c1 + a1 * s), c2, a2, h2);
    let (mut lo, mut hi) = (-h1, h1);
    for _ in 0..120 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if f(m1) <= f(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    f(0.5 * (lo + hi)).min(f(-h1)).min(f(h1))
}

struct Capsule {
    radius: f64,
    half: f64,
    pose: Pose,
}

impl Capsule {
    fn axis(&self) -> Vec3 {
        self.pose.rotation().column(0).into_owned()
    }
}

/// α* of two capsules by bisection on the sign of the scaled shapes' gap.
fn capsules_alpha(one: &Capsule, two: &Capsule) -> f64 {
    let gap = |alpha: f64| {
        segment_segment(
            one.pose.position(),
            &one.axis(),
            alpha * one.half,
            two.pose.position(),
            &two.axis(),
            alpha * two.half,
        ) - alpha * (one.radius + two.radius)
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    while gap(hi) > 0.0 {
        lo = hi;
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if gap(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[test]
fn capsule_capsule_alpha_matches_bisection() {
    let mut rng = Rng(0x5EED_CAB5_0001);
    let opts = Options {
        tolerance: 1e-12,
        ..Options::default()
    };
    let mut worst: f64 = 0.0;
    for case in 0..4000 {
        let q1 = rng.quaternion();
        // A third random, a third nearly parallel, a sixth exactly (anti)parallel, the rest
        // crossed at right angles.
        let q2 = match case % 6 {
            0 | 1 => rng.quaternion(),
            2 | 3 => {
                let axis = rng.unit();
                let angle = 10f64.powf(rng.range(-9.0, -3.0));
                let (s, c) = (0.5 * angle).sin_cos();
                qmul([c, s * axis.x, s * axis.y, s * axis.z], q1)
            }
            4 => {
                let flip = if rng.next() < 0.5 {
                    [1.0, 0.0, 0.0, 0.0]
                } else {
                    [0.0, 0.0, 1.0, 0.0]
                };
                qmul(q1, flip)
            }
            _ => qmul(q1, [0.5f64.sqrt(), 0.0, 0.0, 0.5f64.sqrt()]),
        };
        let r1 = Vec3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let dist = 10f64.powf(rng.range(-2.0, 0.7));
        let r2 = r1 + rng.unit() * dist;
        let one = Capsule {
            radius: rng.range(0.02, 0.5),
            half: rng.range(0.05, 1.0),
            pose: Pose::new(r1.into(), q1).unwrap(),
        };
        let two = Capsule {
            radius: rng.range(0.02, 0.5),
            half: rng.range(0.05, 1.0),
            pose: Pose::new(r2.into(), q2).unwrap(),
        };
        let s1 = Shape::capsule(one.radius, 2.0 * one.half).unwrap();
        let s2 = Shape::capsule(two.radius, 2.0 * two.half).unwrap();
        let p = proximity(&s1, &one.pose, &s2, &two.pose, &opts).unwrap();
        let truth = capsules_alpha(&one, &two);
        let err = (p.alpha - truth).abs() / truth;
        worst = worst.max(err);
        assert!(
            err <= 1e-10,
            "case {case}: alpha {} against bisection {truth} (relative {err:.2e})",
            p.alpha
        );
        // The contact points on the capsules' surfaces (scale: the larger bounding radius).
        let scale = (one.radius + one.half).max(two.radius + two.half);
        for (c, cap) in [(&p.contact1, &one), (&p.contact2, &two)] {
            let on = point_segment(c, cap.pose.position(), &cap.axis(), cap.half) - cap.radius;
            assert!(
                on.abs() <= 1e-9 * scale,
                "case {case}: contact {on:.2e} off its capsule"
            );
        }
    }
    eprintln!("capsule-capsule: worst relative alpha error {worst:.2e} over 4000 poses");
}

/// The closest point of a box (`half`) or a cylinder (`Err((radius, half_length))` along x) to
/// `x`, in its body frame.
fn closest(solid: &Result<Vec3, (f64, f64)>, x: &Vec3) -> Vec3 {
    match solid {
        Ok(h) => Vec3::new(
            x.x.clamp(-h.x, h.x),
            x.y.clamp(-h.y, h.y),
            x.z.clamp(-h.z, h.z),
        ),
        Err((radius, half)) => {
            let r = x.y.hypot(x.z);
            let k = if r > *radius { radius / r } else { 1.0 };
            Vec3::new(x.x.clamp(-*half, *half), x.y * k, x.z * k)
        }
    }
}

#[test]
fn sphere_box_and_cylinder_distance_match_closest_point() {
    let mut rng = Rng(0x5EED_5B0C_0002);
    let mut checked = 0;
    for case in 0..6000 {
        let solid = if case % 2 == 0 {
            Ok(Vec3::new(
                rng.range(0.05, 1.0),
                rng.range(0.05, 1.0),
                rng.range(0.05, 1.0),
            ))
        } else {
            Err((rng.range(0.05, 1.0), rng.range(0.05, 1.0)))
        };
        let shape = match &solid {
            Ok(h) => Shape::cuboid(h.x, h.y, h.z).unwrap(),
            Err((radius, half)) => Shape::cylinder(*radius, 2.0 * half).unwrap(),
        };
        let rho = rng.range(0.02, 0.8);
        let ball = Shape::sphere(rho).unwrap();
        let ps = Pose::new(
            [
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            ],
            rng.quaternion(),
        )
        .unwrap();
        // The centre outside the solid by more than the radius: 1e-6 to 3 beyond it.
        let x = Vec3::new(
            rng.range(-2.5, 2.5),
            rng.range(-2.5, 2.5),
            rng.range(-2.5, 2.5),
        );
        let q = closest(&solid, &x);
        let gap = (x - q).norm() - rho;
        if gap.is_nan() || gap <= 1e-6 {
            continue;
        }
        let rot = ps.rotation();
        let centre = ps.position() + rot * x;
        let pb = Pose::new(centre.into(), rng.quaternion()).unwrap();
        let witness = ps.position() + rot * q;
        let normal = rot * (x - q).normalize();
        for tolerance in [Options::default().tolerance, 1e-12] {
            let opts = Options {
                tolerance,
                ..Options::default()
            };
            for solid_first in [true, false] {
                let d = if solid_first {
                    distance(&shape, &ps, &ball, &pb, &opts).unwrap()
                } else {
                    distance(&ball, &pb, &shape, &ps, &opts).unwrap()
                };
                let (on_solid, on_ball, n) = if solid_first {
                    (d.closest1, d.closest2, d.normal)
                } else {
                    (d.closest2, d.closest1, -d.normal)
                };
                let tag =
                    format!("case {case}, tolerance {tolerance:e}, solid first {solid_first}");
                assert_eq!(d.path, DistancePath::ClosedForm, "{tag}");
                assert!(
                    (d.distance - gap).abs() <= 1e-12 * gap.max(1.0),
                    "{tag}: {} against {gap}",
                    d.distance
                );
                assert!(
                    (on_solid - witness).norm() <= 1e-12,
                    "{tag}: witness on the solid"
                );
                assert!(
                    (on_ball - (centre - normal * rho)).norm() <= 1e-12,
                    "{tag}: witness on the ball"
                );
                assert!((n - normal).norm() <= 1e-9 / gap.min(1.0), "{tag}: normal");
            }
        }
        checked += 1;
    }
    assert!(checked > 4000, "only {checked} separated poses");
}

#[test]
fn sphere_sphere_distance_matches_centres() {
    let mut rng = Rng(0x5EED_5555_0003);
    for case in 0..4000 {
        let (r1, r2) = (rng.range(0.01, 1.0), rng.range(0.01, 1.0));
        let c1 = Vec3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        let gap = 10f64.powf(rng.range(-6.0, 0.5));
        let u = rng.unit();
        let c2 = c1 + u * (r1 + r2 + gap);
        let p1 = Pose::new(c1.into(), rng.quaternion()).unwrap();
        let p2 = Pose::new(c2.into(), rng.quaternion()).unwrap();
        let (s1, s2) = (Shape::sphere(r1).unwrap(), Shape::sphere(r2).unwrap());
        let d = distance(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
        // The truth from the centres as placed (c2 − c1 rounded, not u).
        let w = c2 - c1;
        let truth = w.norm() - r1 - r2;
        let n = w / w.norm();
        assert_eq!(d.path, DistancePath::ClosedForm, "case {case}");
        assert!(
            (d.distance - truth).abs() <= 1e-14 * truth.max(1.0),
            "case {case}: {} against {truth}",
            d.distance
        );
        assert!((d.normal - n).norm() <= 1e-14, "case {case}: normal");
        assert!(
            (d.closest1 - (c1 + n * r1)).norm() <= 1e-14,
            "case {case}: witness 1"
        );
        assert!(
            (d.closest2 - (c2 - n * r2)).norm() <= 1e-14,
            "case {case}: witness 2"
        );
    }
}
