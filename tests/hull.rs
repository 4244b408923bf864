//! Convex hulls of points (`Shape::convex_hull`), padded or not, and polytopes of many planes:
//! against the box they equal, against analytic answers, and against the interior-point solver
//! (an independent path through the conic rows) on random pairs with every other kind.

mod common;

use common::random::{Kind, Rng, KINDS};
use dcol::{distance, proximity, signed_distance, Method, Options, Pose, Shape, ShapeKind};

fn corners(h: [f64; 3]) -> Vec<[f64; 3]> {
    (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { h[k] } else { -h[k] }))
        .collect()
}

fn random_pose(rng: &mut Rng, spread: f64) -> Pose {
    let r = [0; 3].map(|_| rng.range(-spread, spread));
    Pose::new(r, rng.quat()).unwrap()
}

/// A random hull: `n` points, some on a sphere, some inside, some repeated, some on a plane
/// through the top, with the origin inside.
fn random_hull(rng: &mut Rng, n: usize, radius: f64) -> Shape {
    let axes = [
        rng.range(0.3, 1.2),
        rng.range(0.3, 1.2),
        rng.range(0.3, 1.2),
    ];
    let mut pts: Vec<[f64; 3]> = Vec::with_capacity(n);
    while pts.len() < n {
        let u = rng.unit::<3>();
        let p = [0, 1, 2].map(|k| u[k] * axes[k]);
        match rng.next_u64() % 8 {
            0 => pts.push(p.map(|c| c * rng.range(0.0, 0.9))), // inside
            1 if !pts.is_empty() => pts.push(pts[rng.next_u64() as usize % pts.len()]), // again
            2 => pts.push([p[0], p[1], 0.8 * axes[2]]),        // on the plane z = 0.8c
            _ => pts.push(p),
        }
    }
    // Centred on the points' mean, which is strictly inside the hull of points in general
    // position.
    let mean = [0, 1, 2].map(|k| pts.iter().map(|p| p[k]).sum::<f64>() / n as f64);
    for p in pts.iter_mut() {
        *p = [0, 1, 2].map(|k| p[k] - mean[k]);
    }
    Shape::convex_hull(&pts, radius).expect("a random hull")
}

#[test]
fn the_hull_of_a_boxs_corners_is_the_box() {
    let mut rng = Rng::new(31);
    let opts = Options::default();
    let mut compared = 0;
    for _ in 0..40 {
        let h = [
            rng.range(0.2, 1.0),
            rng.range(0.2, 1.0),
            rng.range(0.2, 1.0),
        ];
        let boxed = Shape::cuboid(h[0], h[1], h[2]).unwrap();
        let hull = Shape::convex_hull(&corners(h), 0.0).unwrap();
        assert_eq!(hull.kind(), ShapeKind::ConvexHull);
        assert_eq!(hull.bounding_radius(), boxed.bounding_radius());
        for kind in KINDS {
            let other = kind.random(&mut rng);
            for _ in 0..10 {
                let (p1, p2) = (random_pose(&mut rng, 0.5), random_pose(&mut rng, 2.0));
                let a = proximity(&boxed, &p1, &other, &p2, &opts).unwrap();
                let b = proximity(&hull, &p1, &other, &p2, &opts).unwrap();
                assert!(
                    (a.alpha - b.alpha).abs() <= 1e-11 * a.alpha.max(1.0),
                    "{}: box {} hull {}",
                    kind.name(),
                    a.alpha,
                    b.alpha
                );
                let ell = boxed.bounding_radius().max(other.bounding_radius());
                let (da, db) = (
                    distance(&boxed, &p1, &other, &p2, &opts).unwrap(),
                    distance(&hull, &p1, &other, &p2, &opts).unwrap(),
                );
                assert!((da.distance - db.distance).abs() <= 1e-11 * ell);
                let (sa, sb) = (
                    signed_distance(&boxed, &p1, &other, &p2, &opts).unwrap(),
                    signed_distance(&hull, &p1, &other, &p2, &opts).unwrap(),
                );
                assert!(
                    (sa.distance - sb.distance).abs() <= 1e-9 * ell,
                    "{}: {} vs {}",
                    kind.name(),
                    sa.distance,
                    sb.distance
                );
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 40 * KINDS.len() * 10);
}

#[test]
fn a_rounded_box_against_a_sphere_along_an_axis_and_a_diagonal() {
    let rounded = Shape::convex_hull(&corners([0.5, 0.3, 0.2]), 0.1).unwrap();
    let ball = Shape::sphere(0.4).unwrap();
    let o = Pose::from_position([0.0; 3]).unwrap();
    let opts = Options::default();
    // Along y: the face at 0.3 + 0.1, the ball's 0.4.
    let p = proximity(
        &rounded,
        &o,
        &ball,
        &Pose::from_position([0.0, 3.2, 0.0]).unwrap(),
        &opts,
    )
    .unwrap();
    assert!((p.alpha - 3.2 / 0.8).abs() < 1e-13, "{}", p.alpha);
    // Along the corner's diagonal: the support of the rounded box in direction u is
    // h(u) = 0.5|u_x| + 0.3|u_y| + 0.2|u_z| + 0.1, and the ball's is 0.4; with the ball's centre
    // on the ray through the corner's outward normal the touching normal is that direction
    // only in the limit, so check the bracket against the support bound: α* ≥ n·d / h_K(n) for
    // every unit n, with equality at the optimum.
    let d = [2.0, 1.5, 1.0];
    let p = proximity(&rounded, &o, &ball, &Pose::from_position(d).unwrap(), &opts).unwrap();
    let mut best: f64 = 0.0;
    let mut rng = Rng::new(5);
    for _ in 0..200_000 {
        let n = rng.unit::<3>();
        let h = 0.5 * n[0].abs() + 0.3 * n[1].abs() + 0.2 * n[2].abs() + 0.1 + 0.4;
        best = best.max((n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) / h);
    }
    assert!(
        p.alpha >= best - 1e-12 && p.alpha < best * (1.0 + 1e-3),
        "{} vs {best}",
        p.alpha
    );
    // Distance along x: 3 − (0.5 + 0.1) − 0.4.
    let dist = distance(
        &rounded,
        &o,
        &ball,
        &Pose::from_position([3.0, 0.0, 0.0]).unwrap(),
        &opts,
    )
    .unwrap();
    assert!((dist.distance - 2.0).abs() < 1e-13);
}

/// Every kind against random hulls (unpadded and padded, 8 to 60 points), α* and the distance
/// of the geometric path against the interior-point solver's.
#[test]
fn hulls_agree_with_the_interior_point_solver() {
    let mut rng = Rng::new(77);
    let auto = Options::default();
    let ipm = Options {
        method: Method::InteriorPoint,
        ..Options::default()
    };
    let (mut compared, mut fallback) = (0usize, 0usize);
    let mut bad = Vec::new();
    for round in 0..250 {
        let n = 8 + (rng.next_u64() % 53) as usize;
        let radius = if round % 2 == 0 {
            0.0
        } else {
            rng.range(0.02, 0.3)
        };
        let hull = random_hull(&mut rng, n, radius);
        let mut others: Vec<Shape> = KINDS.iter().map(|k| k.random(&mut rng)).collect();
        others.push(random_hull(&mut rng, 12, 0.0));
        others.push(random_hull(&mut rng, 30, 0.1));
        for (o, other) in others.iter().enumerate() {
            for _ in 0..8 {
                let (p1, p2) = (random_pose(&mut rng, 0.5), random_pose(&mut rng, 2.5));
                let (first, second) = if rng.unif() < 0.5 {
                    ((&hull, &p1), (other, &p2))
                } else {
                    ((other, &p1), (&hull, &p2))
                };
                let a = proximity(first.0, first.1, second.0, second.1, &auto).unwrap();
                let b = proximity(first.0, first.1, second.0, second.1, &ipm).unwrap();
                compared += 1;
                fallback += usize::from(a.solver == dcol::Solver::InteriorPoint);
                if b.status.is_converged() && (a.alpha - b.alpha).abs() > 1e-9 * b.alpha.max(1.0) {
                    bad.push(format!(
                        "round {round} other {o}: {} vs ipm {}",
                        a.alpha, b.alpha
                    ));
                }
                let ell = first.0.bounding_radius().max(second.0.bounding_radius());
                let da = distance(first.0, first.1, second.0, second.1, &auto).unwrap();
                let db = distance(first.0, first.1, second.0, second.1, &ipm).unwrap();
                if db.status.is_converged() && (da.distance - db.distance).abs() > 1e-7 * ell {
                    bad.push(format!(
                        "round {round} other {o}: distance {} vs ipm {}",
                        da.distance, db.distance
                    ));
                }
            }
        }
    }
    println!("{compared} pairs, {fallback} answered by the interior-point fallback");
    assert!(compared >= 20_000);
    assert!(
        bad.is_empty(),
        "{} of {compared}: {:#?}",
        bad.len(),
        &bad[..bad.len().min(20)]
    );
    assert!(
        fallback * 100 < compared,
        "fallback answered {fallback} of {compared}"
    );
}

/// A polytope of many planes (past the enumeration's limit: its vertices come from the polar
/// hull) is the hull of its own vertices, and both agree with the interior-point solver.
#[test]
fn a_polytope_of_many_planes_is_the_hull_of_its_vertices() {
    let mut rng = Rng::new(3);
    let opts = Options::default();
    let ipm = Options {
        method: Method::InteriorPoint,
        ..Options::default()
    };
    for m in [65, 300, 2000] {
        // Tangent planes of an ellipsoid, plus redundant planes farther out.
        let axes = [1.0, 0.6, 0.4];
        let mut a = Vec::new();
        let mut b = Vec::new();
        for i in 0..m {
            let u = rng.unit::<3>();
            let n = [u[0] / axes[0], u[1] / axes[1], u[2] / axes[2]];
            let p = [u[0] * axes[0], u[1] * axes[1], u[2] * axes[2]]; // the tangent point
            let off: f64 = (0..3).map(|k| n[k] * p[k]).sum::<f64>();
            a.push(n);
            b.push(off * if i % 7 == 0 { 1.5 } else { 1.0 });
        }
        let poly = Shape::polytope(&a, &b).unwrap();
        let other = Kind::Cone.random(&mut rng);
        for _ in 0..50 {
            let (p1, p2) = (random_pose(&mut rng, 0.5), random_pose(&mut rng, 2.5));
            let x = proximity(&poly, &p1, &other, &p2, &opts).unwrap();
            let y = proximity(&poly, &p1, &other, &p2, &ipm).unwrap();
            assert!(
                (x.alpha - y.alpha).abs() <= 1e-9 * y.alpha.max(1.0),
                "{m} planes: {} vs ipm {}",
                x.alpha,
                y.alpha
            );
        }
    }
}
