//! The distance of a padded polygon against a polytope, a box, another padded polygon, a
//! sphere, a capsule or a padded hull by GJK on the plane polygon (its core) less the radii
//! (`src/query/separated.rs`, `cored`):
//!
//! - random separated pairs of those kinds against the interior-point distance
//!   (`Method::InteriorPoint`, an independent solver), each answer also certified by the
//!   library-independent support functions of `common::oracle`: the slab gap at the returned
//!   normal within 1e-12·ℓ of the distance, both witnesses on their shapes (excess ≤ 1e-12·ℓ)
//!   and `‖closest2 − closest1‖` equal to the distance;
//! - closed forms, including the flat differences of cores (two polygons in parallel planes,
//!   a sphere or a capsule in the polygon's plane, two coplanar polygons) and tiny gaps.

mod common;

use common::oracle::{lower, polygon_vertices, polytope_vertices, Oracle, Posed};
use dcol::{distance, DistancePath, Method, Options, Pose, Shape, Vec3};

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
        [0; 4].map(|_| self.uniform(-1.0, 1.0))
    }
    fn unit(&mut self) -> Vec3 {
        loop {
            let v = Vec3::new(
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
                self.uniform(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }
}

/// A random padded polygon (3 to 8 edges round the origin) and its oracle.
fn polygon(rng: &mut Rng) -> (Shape, Oracle) {
    let m = 3 + (rng.next() * 6.0) as usize;
    let a0 = rng.uniform(0.0, std::f64::consts::TAU);
    let c: Vec<[f64; 2]> = (0..m)
        .map(|i| {
            let a = if i < 3 {
                a0 + std::f64::consts::TAU * i as f64 / 3.0 + rng.uniform(-0.3, 0.3)
            } else {
                rng.uniform(0.0, std::f64::consts::TAU)
            };
            [a.cos(), a.sin()]
        })
        .collect();
    let d: Vec<f64> = (0..m).map(|_| rng.uniform(0.3, 1.0)).collect();
    let radius = rng.uniform(0.02, 0.4);
    let shape = Shape::polygon(&c, &d, radius).unwrap();
    (shape, Oracle::Polygon(polygon_vertices(&c, &d), radius))
}

/// A random shape of kind `k` (0 polytope, 1 box, 2 polygon, 3 sphere, 4 capsule, 5 padded
/// hull) and its oracle.
fn partner(rng: &mut Rng, k: usize) -> (Shape, Oracle) {
    match k {
        0 => {
            let normals: Vec<[f64; 3]> = (0..12).map(|_| rng.unit().into()).collect();
            let offsets: Vec<f64> = (0..12).map(|_| rng.uniform(0.3, 1.0)).collect();
            match Shape::polytope(&normals, &offsets) {
                Ok(s) => {
                    let a: Vec<Vec3> = normals.iter().map(|n| Vec3::from(*n)).collect();
                    let v = polytope_vertices(&a, &offsets);
                    (s, Oracle::Polytope(a, offsets, v))
                }
                // Unbounded (normals in a half-space): a box instead.
                Err(_) => partner(rng, 1),
            }
        }
        1 => {
            let h = [0; 3].map(|_| rng.uniform(0.1, 1.0));
            let a: Vec<Vec3> = (0..6)
                .map(|i| {
                    let mut n = Vec3::zeros();
                    n[i / 2] = if i % 2 == 0 { 1.0 } else { -1.0 };
                    n
                })
                .collect();
            let b: Vec<f64> = (0..6).map(|i| h[i / 2]).collect();
            let v = polytope_vertices(&a, &b);
            (
                Shape::cuboid(h[0], h[1], h[2]).unwrap(),
                Oracle::Polytope(a, b, v),
            )
        }
        2 => polygon(rng),
        3 => {
            let r = rng.uniform(0.05, 1.0);
            (Shape::sphere(r).unwrap(), Oracle::Sphere(r))
        }
        4 => {
            let (r, l) = (rng.uniform(0.05, 0.6), rng.uniform(0.1, 2.0));
            (Shape::capsule(r, l).unwrap(), Oracle::Capsule(r, l))
        }
        _ => {
            // Six points about the axes (the origin strictly inside) and six anywhere.
            let mut pts: Vec<Vec3> = (0..6)
                .map(|i| {
                    let mut p = rng.unit() * 0.1;
                    p[i / 2] += if i % 2 == 0 { 1.0 } else { -1.0 } * rng.uniform(0.3, 1.0);
                    p
                })
                .collect();
            pts.extend((0..6).map(|_| rng.unit() * rng.uniform(0.3, 1.0)));
            let r = rng.uniform(0.01, 0.3);
            let raw: Vec<[f64; 3]> = pts.iter().map(|p| [p.x, p.y, p.z]).collect();
            (Shape::convex_hull(&raw, r).unwrap(), Oracle::hull(pts, r))
        }
    }
}

fn ipm() -> Options {
    Options {
        method: Method::InteriorPoint,
        ..Options::default()
    }
}

/// The library-independent certificate of a separated answer: the oracle's slab gap at the
/// answer's normal (a lower bound on the distance) and the witnesses' distance (an upper
/// bound, with both witnesses on their shapes) within `tol` of the distance.
fn certificate(
    d: &dcol::Distance,
    o1: &Oracle,
    p1: &Pose,
    o2: &Oracle,
    p2: &Pose,
    tol: f64,
) -> Result<(), String> {
    let (s1, s2) = (Posed::new(o1, p1), Posed::new(o2, p2));
    let gap = lower(&s1, &s2, &d.normal);
    let span = (d.closest2 - d.closest1).norm();
    let (e1, e2) = (s1.excess(&d.closest1), s2.excess(&d.closest2));
    if !(gap <= d.distance + tol && gap >= d.distance - tol) {
        return Err(format!("slab gap {gap} vs distance {}", d.distance));
    }
    let off = (span - d.distance).abs();
    if off.is_nan() || off > tol {
        return Err(format!("witnesses {span} apart, distance {}", d.distance));
    }
    if !(e1 <= tol && e2 <= tol) {
        return Err(format!("witnesses outside their shapes by {e1:e}, {e2:e}"));
    }
    Ok(())
}

#[test]
fn polygon_pairs_match_interior_point_and_oracle() {
    let names = ["polytope", "box", "polygon", "sphere", "capsule", "hull"];
    let mut rng = Rng(0x0901_7600_C0E5);
    let opts = Options::default();
    let mut failures = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let (mut total, mut gjk, mut worst_ipm, mut worst_cert) = (0, 0, 0.0f64, 0.0f64);
        for i in 0..250 {
            let (sp, op) = polygon(&mut rng);
            let (sq, oq) = partner(&mut rng, k);
            // Either order.
            let ((s1, o1), (s2, o2)) = if i % 2 == 0 {
                ((&sp, &op), (&sq, &oq))
            } else {
                ((&sq, &oq), (&sp, &op))
            };
            let ell = s1.bounding_radius().max(s2.bounding_radius());
            let reach = s1.bounding_radius() + s2.bounding_radius();
            let r1 = [0; 3].map(|_| rng.uniform(-2.0, 2.0));
            let off = rng.unit() * (reach * rng.uniform(0.2, 1.5));
            let p1 = Pose::new(r1, rng.quaternion()).unwrap();
            let p2 = Pose::new(
                [r1[0] + off.x, r1[1] + off.y, r1[2] + off.z],
                rng.quaternion(),
            )
            .unwrap();
            let reference = distance(s1, &p1, s2, &p2, &ipm()).unwrap();
            let d = distance(s1, &p1, s2, &p2, &opts).unwrap();
            if !(reference.status.is_converged() && reference.distance > 1e-6 * ell) {
                // Touching or overlapping by the interior point: never a gap here.
                if reference.status.is_converged()
                    && reference.distance == 0.0
                    && d.distance > 1e-7 * ell
                {
                    failures.push(format!("{name} {i}: gap {} on an overlap", d.distance));
                }
                continue;
            }
            total += 1;
            if matches!(d.path, DistancePath::Gjk | DistancePath::GjkPolish) {
                gjk += 1;
            }
            // The interior-point distance is accurate to about its tolerance (1e-8 relative).
            let err = (d.distance - reference.distance).abs() / ell;
            worst_ipm = worst_ipm.max(err);
            if err > 1e-7 {
                failures.push(format!(
                    "{name} {i}: {} vs interior point {} ({:?})",
                    d.distance, reference.distance, d.path
                ));
            }
            match certificate(&d, o1, &p1, o2, &p2, 1e-12 * ell) {
                Ok(()) => {}
                Err(e) => failures.push(format!("{name} {i}: {e} ({:?})", d.path)),
            }
            let gap = lower(&Posed::new(o1, &p1), &Posed::new(o2, &p2), &d.normal);
            worst_cert = worst_cert.max((gap - d.distance).abs() / ell);
        }
        println!(
            "polygon-{name}: {total} separated, {gjk} by GJK; max |d - d_ipm|/ℓ {worst_ipm:e}, \
             max |slab gap - d|/ℓ {worst_cert:e}"
        );
        assert!(total >= 100, "polygon-{name}: only {total} separated poses");
        // Every separated pose of these kinds is answered by GJK on the cores.
        assert_eq!(gjk, total, "polygon-{name}: some fell back");
    }
    for f in failures.iter().take(20) {
        println!("FAIL {f}");
    }
    assert!(failures.is_empty(), "{} checks failed", failures.len());
}

/// A pose from a position and a rotation about z by `t`.
fn about_z(r: [f64; 3], t: f64) -> Pose {
    Pose::new(r, [(t / 2.0).cos(), 0.0, 0.0, (t / 2.0).sin()]).unwrap()
}

/// The unit square `|x|, |y| ≤ a` padded by `radius`.
fn square(a: f64, radius: f64) -> Shape {
    Shape::polygon(
        &[[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]],
        &[a; 4],
        radius,
    )
    .unwrap()
}

#[test]
fn polygon_closed_forms() {
    let opts = Options::default();
    let mut rng = Rng(0xC105_EDF0);
    let mut checked = 0;
    let check = |what: &str, d: dcol::Distance, truth: f64, n: Option<Vec3>| {
        assert!(
            (d.distance - truth).abs() <= 1e-12 * (1.0 + truth),
            "{what}: {} vs {truth} ({:?})",
            d.distance,
            d.path
        );
        assert!(
            matches!(d.path, DistancePath::Gjk | DistancePath::GjkPolish),
            "{what}: answered by {:?}",
            d.path
        );
        if let Some(n) = n {
            assert!(
                (d.normal - n).norm() <= 1e-9,
                "{what}: normal {:?}",
                d.normal
            );
        }
        assert!(((d.closest2 - d.closest1).norm() - truth).abs() <= 1e-12 * (1.0 + truth));
    };
    for _ in 0..200 {
        let (a, r1) = (rng.uniform(0.3, 1.0), rng.uniform(0.01, 0.3));
        let sq = square(a, r1);
        let gap = 10f64.powf(rng.uniform(-9.0, 0.0));
        let t = rng.uniform(0.0, std::f64::consts::TAU);
        let p0 = about_z([0.0, 0.0, 0.0], rng.uniform(0.0, 1.0));
        let shift = [rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2)];
        // A box above the square, faces parallel: z gap less the radius.
        let h = rng.uniform(0.1, 0.8);
        let bx = Shape::cuboid(0.5, 0.4, h).unwrap();
        let pb = about_z([shift[0], shift[1], r1 + h + gap], t);
        let d = distance(&sq, &p0, &bx, &pb, &opts).unwrap();
        check("box over square", d, gap, Some(Vec3::z()));
        // Two squares in parallel planes (a flat difference of cores).
        let r2 = rng.uniform(0.01, 0.3);
        let sq2 = square(rng.uniform(0.3, 1.0), r2);
        let p2 = about_z([shift[0], shift[1], r1 + r2 + gap], t);
        let d = distance(&sq, &p0, &sq2, &p2, &opts).unwrap();
        check("parallel squares", d, gap, Some(Vec3::z()));
        // Two coplanar squares side by side along the rotated x axis of the first (its edge
        // x = a), the second unrotated relative to it: edge to edge in the plane.
        let t0 = rng.uniform(0.0, 1.0);
        let p0 = about_z([0.0, 0.0, 0.0], t0);
        let a2 = rng.uniform(0.3, 1.0);
        let sq2 = square(a2, r2);
        let along = a + r1 + r2 + a2 + gap;
        let (c, s) = (t0.cos(), t0.sin());
        let side = rng.uniform(-0.2, 0.2);
        let p2 = about_z([along * c - side * s, along * s + side * c, 0.0], t0);
        let d = distance(&sq, &p0, &sq2, &p2, &opts).unwrap();
        check("coplanar squares", d, gap, Some(Vec3::new(c, s, 0.0)));
        // A sphere in the square's plane beyond its edge, and above its interior.
        let rs = rng.uniform(0.05, 1.0);
        let ps = Pose::from_position([
            (a + r1 + rs + gap) * c - side * s,
            (a + r1 + rs + gap) * s + side * c,
            0.0,
        ])
        .unwrap();
        let sph = Shape::sphere(rs).unwrap();
        let d = distance(&sq, &p0, &sph, &ps, &opts).unwrap();
        check("sphere in the plane", d, gap, Some(Vec3::new(c, s, 0.0)));
        let ps = Pose::from_position([0.1, -0.1, -(r1 + rs + gap)]).unwrap();
        let d = distance(&sq, &p0, &sph, &ps, &opts).unwrap();
        check("sphere below", d, gap, Some(-Vec3::z()));
        // A capsule lying in the plane parallel to the edge (a segment in the polygon's
        // plane), either order.
        let (rc, lc) = (rng.uniform(0.05, 0.5), rng.uniform(0.1, 0.6));
        let cap = Shape::capsule(rc, lc).unwrap();
        // The capsule's axis (body x) along the edge direction (−s, c): turned by t0 + 90°.
        let pc = about_z(
            [
                (a + r1 + rc + gap) * c - side * s,
                (a + r1 + rc + gap) * s + side * c,
                0.0,
            ],
            t0 + std::f64::consts::FRAC_PI_2,
        );
        let d = distance(&cap, &pc, &sq, &p0, &opts).unwrap();
        check("capsule in the plane", d, gap, Some(-Vec3::new(c, s, 0.0)));
        checked += 1;
    }
    assert_eq!(checked, 200);
}
