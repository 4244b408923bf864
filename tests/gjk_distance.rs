//! The exact distance of separated shapes by GJK (with its polish and certificate):
//!
//! - every separated reference case within 1e-10·ℓ of the oracle, witnesses within 1e-8·ℓ
//!   where unique, and the touching/overlapping ones still 0 (through the fallback);
//! - random separated pairs of all 7×7 kinds against the interior-point distance
//!   (`Method::InteriorPoint`);
//! - tiny gaps (1e-12..1e-8 of ℓ) reported positive and correct: sphere–sphere and a box–box
//!   face gap, whose distances are known in closed form.

mod common;

use common::random::{random_poses, random_shape, random_shapes, Scaled};
use common::*;
use dcol::{distance, distance_gradient, DistancePath, Method, Options, Pose, Shape, Vec3};
use std::collections::BTreeMap;

fn ipm() -> Options {
    Options {
        method: Method::InteriorPoint,
        ..Options::default()
    }
}

#[test]
fn gjk_matches_reference_to_1e10() {
    let sets = reference_sets();
    if sets.is_empty() {
        return;
    }
    let opts = Options::default();
    let mut paths: BTreeMap<String, usize> = BTreeMap::new();
    let (mut worst_d, mut worst_w) = (0.0f64, 0.0f64);
    let mut failures = Vec::new();
    let mut separated = 0;
    for set in &sets {
        for file in all_files(&set.dir) {
            for case in load(&file) {
                let id = case["id"].as_str().unwrap().to_string();
                let ell = length_scale(&case);
                let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
                let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
                let d = distance(&s1, &p1, &s2, &p2, &opts).unwrap();
                let d_ref = f(&case["distance"]);
                *paths.entry(format!("{:?}", d.path)).or_default() += 1;
                if d_ref == 0.0 {
                    // Touching or overlapping: 0 with one common point, from the fallback or
                    // from GJK's certified overlap (the origin inside a tetrahedron of support
                    // points), never a gap.
                    let ok_path = matches!(d.path, DistancePath::InteriorPoint | DistancePath::Gjk);
                    if d.distance != 0.0 || d.closest1 != d.closest2 || !ok_path {
                        failures.push(format!(
                            "{id}: touching/overlap answered {} by {:?}",
                            d.distance, d.path
                        ));
                    }
                    continue;
                }
                separated += 1;
                let err = (d.distance - d_ref).abs() / ell;
                worst_d = worst_d.max(err);
                if err > 1e-10 {
                    failures.push(format!(
                        "{id}: distance {} vs {d_ref} (err {err:e} ℓ, {:?})",
                        d.distance, d.path
                    ));
                }
                if d.path == DistancePath::InteriorPoint {
                    failures.push(format!("{id}: separated case fell back"));
                }
                let nn = d.normal.norm();
                if (nn - 1.0).abs() > 1e-12 {
                    failures.push(format!("{id}: normal not unit ({nn})"));
                }
                if case["closest_unique"].as_bool() == Some(true) {
                    let ew = dist3(&v3(&case["closest1"]), &d.closest1)
                        .max(dist3(&v3(&case["closest2"]), &d.closest2))
                        / ell;
                    worst_w = worst_w.max(ew);
                    if ew > 1e-8 {
                        failures.push(format!("{id}: witness off by {ew:e} ℓ ({:?})", d.path));
                    }
                }
            }
        }
    }
    println!("separated cases {separated}; paths {paths:?}");
    println!("max |Δd|/ℓ {worst_d:e}, max |Δw|/ℓ {worst_w:e}");
    for f in failures.iter().take(30) {
        println!("FAIL {f}");
    }
    assert!(failures.is_empty(), "{} checks failed", failures.len());
    assert!(separated > 0);
}

/// SplitMix64.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn quaternion(&mut self) -> [f64; 4] {
        [
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
            self.uniform(-1.0, 1.0),
        ]
    }
}

fn kinds() -> Vec<(&'static str, Shape)> {
    let hexagon: Vec<[f64; 2]> = (0..6)
        .map(|i| {
            let t = i as f64 * std::f64::consts::PI / 3.0;
            [t.cos(), t.sin()]
        })
        .collect();
    let normals = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
        [0.577, 0.577, 0.577],
        [-0.577, 0.577, -0.577],
    ];
    vec![
        ("sphere", Shape::sphere(0.7).unwrap()),
        (
            "ellipsoid",
            Shape::ellipsoid([[2.0, 0.3, 0.0], [0.3, 1.0, 0.1], [0.0, 0.1, 4.0]]).unwrap(),
        ),
        (
            "polytope",
            Shape::polytope(&normals, &[0.5, 0.6, 0.4, 0.7, 0.3, 0.5, 0.6, 0.55]).unwrap(),
        ),
        ("capsule", Shape::capsule(0.3, 1.2).unwrap()),
        ("cylinder", Shape::cylinder(0.4, 1.0).unwrap()),
        ("cone", Shape::cone(1.5, 0.5).unwrap()),
        (
            "polygon",
            Shape::polygon(&hexagon, &[0.6, 0.7, 0.8, 0.6, 0.7, 0.8], 0.1).unwrap(),
        ),
    ]
}

#[test]
fn random_separated_pairs_match_interior_point() {
    let shapes = kinds();
    let mut rng = Rng(0x0005_EED0_F61C);
    let opts = Options::default();
    let mut worst = 0.0f64;
    let mut fell_back = 0;
    let mut total = 0;
    let mut failures = Vec::new();
    for (n1, s1) in &shapes {
        for (n2, s2) in &shapes {
            let ell = s1.bounding_radius().max(s2.bounding_radius());
            let reach = s1.bounding_radius() + s2.bounding_radius();
            for k in 0..40 {
                let dir = Vec3::new(
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                )
                .normalize();
                let r1 = [
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                ];
                let off = dir * (reach * rng.uniform(0.3, 1.5));
                let p1 = Pose::new(r1, rng.quaternion()).unwrap();
                let p2 = Pose::new(
                    [r1[0] + off.x, r1[1] + off.y, r1[2] + off.z],
                    rng.quaternion(),
                )
                .unwrap();
                let reference = distance(s1, &p1, s2, &p2, &ipm()).unwrap();
                if !(reference.status.is_converged() && reference.distance > 1e-6 * ell) {
                    continue;
                }
                total += 1;
                let d = distance(s1, &p1, s2, &p2, &opts).unwrap();
                if d.path == DistancePath::InteriorPoint {
                    fell_back += 1;
                }
                let err = (d.distance - reference.distance).abs() / ell;
                worst = worst.max(err);
                // The interior-point distance is accurate to about its tolerance; GJK's
                // answer is certified to 1e-12·ℓ, so it may only be lower (or equal).
                if err > 1e-8 {
                    failures.push(format!(
                        "{n1}-{n2} #{k}: {} vs ipm {} ({:?})",
                        d.distance, reference.distance, d.path
                    ));
                }
                let (dg, g) = distance_gradient(s1, &p1, s2, &p2, &opts).unwrap();
                let (_, gi) = distance_gradient(s1, &p1, s2, &p2, &ipm()).unwrap();
                assert_eq!(dg.distance, d.distance);
                for c in 0..14 {
                    let scale = if c % 7 < 3 { 1.0 } else { 1.0 / ell };
                    if ((g[c] - gi[c]) * scale).abs() > 1e-5 {
                        failures.push(format!(
                            "{n1}-{n2} #{k}: gradient column {c}: {} vs ipm {} ({:?})",
                            g[c], gi[c], d.path
                        ));
                    }
                }
            }
        }
    }
    println!("{total} separated pairs, {fell_back} fell back, max |Δd|/ℓ vs ipm {worst:e}");
    for f in failures.iter().take(30) {
        println!("FAIL {f}");
    }
    assert!(failures.is_empty(), "{} checks failed", failures.len());
    assert!(total > 1000);
    assert!(
        fell_back * 100 <= total,
        "{fell_back} of {total} separated pairs fell back"
    );
}

const GAPS: [f64; 5] = [1e-12, 1e-11, 1e-10, 1e-9, 1e-8];

#[test]
fn tiny_gaps_sphere_sphere() {
    let (ra, rb) = (0.7, 1.3);
    let (a, b) = (Shape::sphere(ra).unwrap(), Shape::sphere(rb).unwrap());
    let ell: f64 = 1.3;
    let mut rng = Rng(42);
    for g in GAPS {
        for _ in 0..20 {
            let dir = Vec3::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .normalize();
            let r1 = Vec3::new(0.3, -0.2, 0.1);
            let r2 = r1 + dir * (ra + rb + g * ell);
            let p1 = Pose::new(r1.into(), rng.quaternion()).unwrap();
            let p2 = Pose::new(r2.into(), rng.quaternion()).unwrap();
            // The exact distance of the poses as stored.
            let exact = (p2.position() - p1.position()).norm() - (ra + rb);
            let d = distance(&a, &p1, &b, &p2, &Options::default()).unwrap();
            assert!(d.distance > 0.0, "gap {g}: {d:?}");
            assert!(
                (d.distance - exact).abs() <= 1e-15 * ell + 1e-3 * exact,
                "gap {g}ℓ: {} vs {exact} ({:?})",
                d.distance,
                d.path
            );
            assert!(
                (d.normal - dir).norm() < 1e-9,
                "gap {g}: normal {:?} vs {dir:?}: {d:?}",
                d.normal
            );
        }
    }
}

#[test]
fn tiny_gaps_box_face() {
    let (h1, h2) = ([0.5, 0.8, 0.3], [0.4, 0.3, 0.6]);
    let b1 = Shape::cuboid(h1[0], h1[1], h1[2]).unwrap();
    let b2 = Shape::cuboid(h2[0], h2[1], h2[2]).unwrap();
    let ell = b1.bounding_radius().max(b2.bounding_radius());
    let mut rng = Rng(7);
    for g in GAPS {
        for k in 0..20 {
            // Axis-aligned: the gap along x is exact in floating point; a shared rotation
            // keeps the faces parallel (the gap then carries the rotation's rounding).
            let rotated = k % 2 == 1;
            let q = if rotated {
                rng.quaternion()
            } else {
                [1.0, 0.0, 0.0, 0.0]
            };
            let p1 = Pose::new([0.1, 0.2, 0.3], q).unwrap();
            let lateral = Vec3::new(
                h1[0] + h2[0] + g * ell,
                rng.uniform(-0.3, 0.3),
                rng.uniform(-0.2, 0.2),
            );
            let world = p1.rotation() * lateral;
            let p2 = Pose::new((p1.position() + world).into(), q).unwrap();
            let along = p1.rotation().tr_mul(&(p2.position() - p1.position()));
            let exact = along.x - h1[0] - h2[0];
            let d = distance(&b1, &p1, &b2, &p2, &Options::default()).unwrap();
            assert!(d.distance > 0.0, "gap {g} (rotated {rotated}): {d:?}");
            let slack = if rotated { 4e-16 * 8.0 } else { 1e-16 };
            assert!(
                (d.distance - exact).abs() <= slack * ell + 1e-3 * exact,
                "gap {g}ℓ (rotated {rotated}): {} vs {exact} ({:?})",
                d.distance,
                d.path
            );
            let axis = p1.rotation().column(0).into_owned();
            assert!((d.normal - axis).norm() < 1e-9, "normal {:?}", d.normal);
        }
    }
}

#[test]
fn debug_case() {
    let Ok(want) = std::env::var("CASE") else {
        return;
    };
    for set in &reference_sets() {
        for file in all_files(&set.dir) {
            for case in load(&file) {
                if case["id"].as_str().unwrap() != want {
                    continue;
                }
                let (s1, s2) = (shape(&case["shape1"]), shape(&case["shape2"]));
                let (p1, p2) = (pose(&case["pose1"]), pose(&case["pose2"]));
                println!("{} {}", case["shape1"], case["shape2"]);
                let d = distance(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
                println!(
                    "ref {} {} {}",
                    case["distance"], case["closest1"], case["closest2"]
                );
                println!("got {d:?}");
            }
        }
    }
}

/// A sphere over a box face (GJK, then the face projection or the polish): gap
/// `x − h − ρ` in the box's axes.
#[test]
fn tiny_gaps_sphere_box_face() {
    let (h, rho) = ([0.5, 0.8, 0.3], 0.45);
    let bx = Shape::cuboid(h[0], h[1], h[2]).unwrap();
    let ball = Shape::sphere(rho).unwrap();
    let ell = bx.bounding_radius().max(rho);
    let mut rng = Rng(11);
    for g in GAPS {
        for k in 0..20 {
            let p1 = Pose::new([0.1, 0.2, 0.3], rng.quaternion()).unwrap();
            let local = Vec3::new(
                h[0] + rho + g * ell,
                rng.uniform(-0.5, 0.5),
                rng.uniform(-0.2, 0.2),
            );
            let p2 = Pose::new(
                (p1.position() + p1.rotation() * local).into(),
                rng.quaternion(),
            )
            .unwrap();
            let along = p1.rotation().tr_mul(&(p2.position() - p1.position()));
            let exact = along.x - h[0] - rho;
            let (a, pa, b, pb) = if k % 2 == 0 {
                (&bx, &p1, &ball, &p2)
            } else {
                (&ball, &p2, &bx, &p1)
            };
            let d = distance(a, pa, b, pb, &Options::default()).unwrap();
            assert!(d.distance > 0.0, "gap {g}: {d:?}");
            assert!(
                (d.distance - exact).abs() <= 4e-15 * ell + 1e-3 * exact,
                "gap {g}ℓ: {} vs {exact} ({:?})",
                d.distance,
                d.path
            );
        }
    }
}

/// A sphere beside a cylinder's side: gap `‖(y, z)‖ − R − ρ` in the cylinder's axes. As a
/// sphere it takes the closed form (the cylinder's point closest to the centre); as the same
/// ball written as an ellipsoid (`P = I/ρ²`) it takes GJK and the polish on the two rims and the
/// quadric.
#[test]
fn tiny_gaps_sphere_cylinder_side() {
    let (radius, length, rho) = (0.4, 1.0, 0.3);
    let cyl = Shape::cylinder(radius, length).unwrap();
    let sphere = Shape::sphere(rho).unwrap();
    let inv = 1.0 / (rho * rho);
    let quadric = Shape::ellipsoid([[inv, 0.0, 0.0], [0.0, inv, 0.0], [0.0, 0.0, inv]]).unwrap();
    let ell = cyl.bounding_radius().max(rho);
    let mut rng = Rng(13);
    let (mut polished, mut closed) = (0, 0);
    for (ball, expect) in [
        (&sphere, DistancePath::ClosedForm),
        (&quadric, DistancePath::GjkPolish),
    ] {
        for g in GAPS {
            for _ in 0..20 {
                let p1 = Pose::new([0.1, 0.2, 0.3], rng.quaternion()).unwrap();
                let phi = rng.uniform(0.0, std::f64::consts::TAU);
                let radial = radius + rho + g * ell;
                let local = Vec3::new(
                    rng.uniform(-0.3, 0.3),
                    radial * phi.cos(),
                    radial * phi.sin(),
                );
                let p2 = Pose::new(
                    (p1.position() + p1.rotation() * local).into(),
                    rng.quaternion(),
                )
                .unwrap();
                let along = p1.rotation().tr_mul(&(p2.position() - p1.position()));
                let exact = along.y.hypot(along.z) - radius - rho;
                let d = distance(&cyl, &p1, ball, &p2, &Options::default()).unwrap();
                if d.path == expect {
                    if expect == DistancePath::ClosedForm {
                        closed += 1;
                    } else {
                        polished += 1;
                    }
                }
                assert!(d.distance > 0.0, "gap {g}: {d:?}");
                assert!(
                    (d.distance - exact).abs() <= 4e-15 * ell + 1e-3 * exact,
                    "gap {g}ℓ: {} vs {exact} ({:?})",
                    d.distance,
                    d.path
                );
            }
        }
    }
    assert!(
        polished > 0 && closed > 0,
        "polished {polished}, closed form {closed}"
    );
}

/// Random pairs over the 64 ordered pairs of the eight kinds (the box included), sizes and
/// offsets spanning 1e-3..1e3, from deep overlap to well apart (`DCOL_RANDOM_PAIRS`, default
/// 20 000): the default distance agrees with the interior-point distance to 1e-8·ℓ wherever
/// the latter converges, and separated pairs rarely fall back.
/// A sweep comparing the default distance with the interior-point one: separated pairs, those
/// answered by the fallback, interior-point solves that did not converge (not compared), the
/// worst difference (over ℓ) and the pairs that differ by more than 1e-8·ℓ.
#[derive(Default)]
struct Sweep {
    separated: usize,
    fell_back: usize,
    ipm_failed: usize,
    worst: f64,
    bad: Vec<String>,
}

impl Sweep {
    fn compare(&mut self, i: usize, s1: &Shape, p1: &Pose, s2: &Shape, p2: &Pose) {
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        let g = distance(s1, p1, s2, p2, &Options::default()).unwrap();
        let q = distance(s1, p1, s2, p2, &ipm()).unwrap();
        if !q.status.is_converged() {
            self.ipm_failed += 1;
            return;
        }
        if q.distance > 1e-6 * ell {
            self.separated += 1;
            if g.path == DistancePath::InteriorPoint {
                self.fell_back += 1;
            }
        }
        let e = (g.distance - q.distance).abs() / ell;
        self.worst = self.worst.max(e);
        if e.is_nan() || e > 1e-8 {
            self.bad.push(format!(
                "#{i} {:?}-{:?}: {} vs interior point {} ({e:e} ℓ, {:?})",
                s1.kind(),
                s2.kind(),
                g.distance,
                q.distance,
                g.path
            ));
        }
    }
}

#[test]
fn random_pairs_across_scales_match_interior_point() {
    let n = std::env::var("DCOL_RANDOM_PAIRS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let mut rng = Scaled(0x5EED_0DC1);
    let mut sweep = Sweep::default();
    for i in 0..n {
        let scale = rng.log(-3.0, 3.0);
        let (s1, s2) = random_shapes(&mut rng, i, scale);
        let reach = s1.bounding_radius() + s2.bounding_radius();
        let len = reach * rng.log(-1.3, 0.7);
        let (p1, p2) = random_poses(&mut rng, scale, len);
        sweep.compare(i, &s1, &p1, &s2, &p2);
    }
    let Sweep {
        separated,
        fell_back,
        ipm_failed,
        worst,
        bad,
    } = sweep;
    println!(
        "{n} random pairs: {separated} separated, {fell_back} of them by the fallback, {} \
         disagree (max {worst:e} ℓ), {ipm_failed} interior-point solves did not converge",
        bad.len()
    );
    assert!(bad.is_empty(), "{:#?}", &bad[..bad.len().min(20)]);
    assert!(
        fell_back * 100 <= separated,
        "{fell_back} of {separated} fell back"
    );
}

/// Near contact: the offset scaled so that α* = 1 ± 10^U(−10, −6) (proximity, certified):
/// separated pairs must report a positive distance, overlapping ones 0 (`DCOL_NEAR_PAIRS`,
/// default 20 000).
#[test]
fn near_contact_sign_is_right() {
    let n = std::env::var("DCOL_NEAR_PAIRS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20_000);
    let mut rng = Scaled(0x0000_00AE_A12C);
    let mut bad = Vec::new();
    let (mut sep, mut sep_gjk, mut checked) = (0, 0, 0);
    for i in 0..n {
        let scale = rng.log(-3.0, 3.0);
        let (s1, s2) = random_shapes(&mut rng, i, scale);
        let reach = s1.bounding_radius() + s2.bounding_radius();
        let (p1, p0) = random_poses(&mut rng, scale, reach);
        let a0 = dcol::proximity(&s1, &p1, &s2, &p0, &Options::default()).unwrap();
        if !(a0.status.is_converged() && a0.alpha > 0.0) {
            continue;
        }
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        let target = 1.0 + sign * rng.log(-10.0, -6.0);
        let off = (p0.position() - p1.position()) * (target / a0.alpha);
        let p2 = Pose::new((p1.position() + off).into(), p0.quaternion()).unwrap();
        let a = dcol::proximity(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
        // Only poses whose side of 1 is certain well beyond the solver's tolerance.
        if !(a.status.is_converged() && (a.alpha - 1.0).abs() > 1e-11) {
            continue;
        }
        checked += 1;
        let d = distance(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
        if a.alpha > 1.0 {
            sep += 1;
            if d.path != DistancePath::InteriorPoint {
                sep_gjk += 1;
            }
            if d.distance <= 0.0 || d.distance.is_nan() {
                bad.push(format!(
                    "#{i} {:?}-{:?}: α* − 1 = {:e} but distance {} ({:?})",
                    s1.kind(),
                    s2.kind(),
                    a.alpha - 1.0,
                    d.distance,
                    d.path
                ));
            }
        } else if d.distance != 0.0 {
            bad.push(format!(
                "#{i} {:?}-{:?}: α* − 1 = {:e} but distance {} ({:?})",
                s1.kind(),
                s2.kind(),
                a.alpha - 1.0,
                d.distance,
                d.path
            ));
        }
    }
    println!(
        "{checked} near-contact pairs: {sep} separated ({sep_gjk} answered by GJK/closed form), \
         {} wrong",
        bad.len()
    );
    assert!(bad.is_empty(), "{:#?}", &bad[..bad.len().min(20)]);
    assert!(checked > n / 2);
}

/// `distance_within` agrees with `distance` on both sides of the cutoff (GJK stops early when
/// its lower bound passes the cutoff).
#[test]
fn distance_within_agrees() {
    let shapes = kinds();
    let mut rng = Rng(99);
    for (_, s1) in &shapes {
        for (_, s2) in &shapes {
            let reach = s1.bounding_radius() + s2.bounding_radius();
            for _ in 0..10 {
                let p1 = Pose::new([0.0; 3], rng.quaternion()).unwrap();
                let dir = Vec3::new(
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                )
                .normalize()
                    * (reach * rng.uniform(0.5, 1.5));
                let p2 = Pose::new(dir.into(), rng.quaternion()).unwrap();
                let d = distance(s1, &p1, s2, &p2, &Options::default()).unwrap();
                for cutoff in [0.5 * d.distance, 2.0 * d.distance + 1e-3] {
                    let w = dcol::distance_within(s1, &p1, s2, &p2, cutoff, &Options::default())
                        .unwrap();
                    match w {
                        Some(x) => {
                            assert!(x.distance <= cutoff);
                            assert!((x.distance - d.distance).abs() <= 1e-12 * reach);
                        }
                        None => assert!(d.distance > cutoff, "{} vs {cutoff}", d.distance),
                    }
                }
            }
        }
    }
}

/// Thin and elongated shapes (aspect ratios up to 1000: flat ellipsoids and boxes, needle
/// capsules and cylinders, flat cones, thin padded polygons) against the interior-point
/// distance (`DCOL_THIN_PAIRS`, default 5 000); prints the fallback share.
#[test]
fn thin_shapes_match_interior_point() {
    let n = std::env::var("DCOL_THIN_PAIRS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(5_000);
    let mut rng = Scaled(0x7417_0001);
    let thin = |rng: &mut Scaled, k: usize| -> Shape {
        let t = rng.log(-3.0, -1.0);
        match k % 6 {
            0 => Shape::ellipsoid([
                [1.0, 0.0, 0.0],
                [0.0, 1.0 / (0.5 * 0.5), 0.0],
                [0.0, 0.0, 1.0 / (t * t)],
            ])
            .unwrap(),
            1 => Shape::cuboid(1.0, 0.5, t).unwrap(),
            2 => Shape::capsule(t, 2.0).unwrap(),
            3 => Shape::cylinder(t, 2.0).unwrap(),
            4 => Shape::cylinder(1.0, t).unwrap(),
            _ => Shape::polygon(
                &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
                &[1.0, 0.5, 1.0, 0.5],
                t,
            )
            .unwrap(),
        }
    };
    let mut sweep = Sweep::default();
    for i in 0..n {
        let s1 = thin(&mut rng, i);
        let s2 = if i % 2 == 0 {
            thin(&mut rng, i / 6)
        } else {
            random_shape(&mut rng, i % 8, 1.0)
        };
        let reach = s1.bounding_radius() + s2.bounding_radius();
        let len = reach * rng.log(-1.0, 0.3);
        let (p1, p2) = random_poses(&mut rng, 1.0, len);
        sweep.compare(i, &s1, &p1, &s2, &p2);
    }
    let Sweep {
        separated,
        fell_back,
        worst,
        bad,
        ..
    } = sweep;
    println!(
        "{n} thin pairs: {separated} separated, {fell_back} of them by the fallback, {} \
         disagree (max {worst:e} ℓ)",
        bad.len()
    );
    assert!(bad.is_empty(), "{:#?}", &bad[..bad.len().min(20)]);
}

/// Overlapping pairs whose overlap GJK certifies (the origin strictly inside a tetrahedron of
/// support points) report 0 with one common point: that point lies in both shapes, checked by
/// the interior-point proximity of a small sphere there against each shape (α* ≤ 1 puts the
/// sphere's centre inside the shape), and the interior-point α* of the pair is below 1.
#[test]
fn certified_overlap_gives_a_point_in_both_shapes() {
    let mut rng = Scaled(0x5EED_0DC7);
    let (mut gjk, mut checked) = (0, 0);
    let mut bad = Vec::new();
    for i in 0..4000 {
        let scale = rng.log(-2.0, 2.0);
        let (s1, s2) = random_shapes(&mut rng, i, scale);
        let reach = s1.bounding_radius() + s2.bounding_radius();
        let len = reach * rng.log(-1.3, -0.1);
        let (p1, p2) = random_poses(&mut rng, scale, len);
        let d = distance(&s1, &p1, &s2, &p2, &Options::default()).unwrap();
        if d.distance != 0.0 {
            continue;
        }
        checked += 1;
        assert_eq!(d.closest1, d.closest2, "#{i}: two witnesses for an overlap");
        if d.path != DistancePath::Gjk {
            continue;
        }
        gjk += 1;
        let alpha = dcol::proximity(&s1, &p1, &s2, &p2, &ipm()).unwrap().alpha;
        let ell = s1.bounding_radius().max(s2.bounding_radius());
        let dot = Shape::sphere(1e-9 * ell).unwrap();
        let at = Pose::from_position([d.closest1.x, d.closest1.y, d.closest1.z]).unwrap();
        for (s, p) in [(&s1, &p1), (&s2, &p2)] {
            let a = dcol::proximity(&dot, &at, s, p, &ipm()).unwrap().alpha;
            let inside = a <= 1.0 + 1e-7 && alpha < 1.0;
            if !inside {
                bad.push(format!(
                    "#{i} {:?}-{:?}: α* {alpha}, point's α {a}",
                    s1.kind(),
                    s2.kind()
                ));
            }
        }
    }
    println!("{checked} overlapping pairs, {gjk} certified by GJK");
    assert!(bad.is_empty(), "{:#?}", &bad[..bad.len().min(20)]);
    assert!(gjk >= 100, "only {gjk} of {checked} certified by GJK");
}
