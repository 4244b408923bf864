//! The signed distance of padded polygons through their plane polygons (`src/query/cores.rs`):
//! the poses where the difference of the cores is flat (parallel or coplanar polygons, a
//! sphere's centre or a capsule's segment in a polygon's plane), where EPA on the cores finds
//! no tetrahedron and the shapes themselves answer, checked against closed forms; and the
//! witness identity and separated answers equal to `distance` on generic poses.

use dcol::{distance, signed_distance, Options, Pose, Shape, SolveStatus};

/// A square of half-side `h` in the body x-y plane, padded by `r`.
fn square(h: f64, r: f64) -> Shape {
    let c = [[1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]];
    Shape::polygon(&c, &[h; 4], r).unwrap()
}

fn at(p: [f64; 3]) -> Pose {
    Pose::from_position(p).unwrap()
}

fn check(s1: &Shape, p1: &Pose, s2: &Shape, p2: &Pose, expect: f64, normal: [f64; 3]) {
    let o = Options::default();
    let sd = signed_distance(s1, p1, s2, p2, &o).unwrap();
    assert_eq!(sd.status, SolveStatus::Converged, "{sd:?}");
    assert!((sd.distance - expect).abs() <= 1e-10, "{sd:?} vs {expect}");
    let n = sd.normal;
    assert!(
        (n.x - normal[0]).abs() + (n.y - normal[1]).abs() + (n.z - normal[2]).abs() <= 1e-8,
        "{sd:?}"
    );
    let w = (sd.closest2 - sd.closest1 - sd.normal * sd.distance).norm();
    assert!(w <= 1e-9, "witness identity off by {w}: {sd:?}");
}

#[test]
fn flat_differences_of_cores() {
    let a = square(0.5, 0.1);
    let b = square(0.4, 0.08);
    // Parallel planes 0.05 apart, the squares overlapping: out along z by 0.18 − 0.05.
    check(
        &a,
        &at([0.0; 3]),
        &b,
        &at([0.1, 0.05, 0.05]),
        -0.13,
        [0.0, 0.0, 1.0],
    );
    check(
        &b,
        &at([0.0; 3]),
        &a,
        &at([0.1, 0.05, -0.05]),
        -0.13,
        [0.0, 0.0, -1.0],
    );
    // Coplanar squares: out along ±z by 0.18.
    let sd = signed_distance(
        &a,
        &at([0.0; 3]),
        &b,
        &at([0.1, 0.05, 0.0]),
        &Options::default(),
    )
    .unwrap();
    assert_eq!(sd.status, SolveStatus::Converged);
    assert!((sd.distance + 0.18).abs() <= 1e-10, "{sd:?}");
    assert!((sd.normal.z.abs() - 1.0).abs() <= 1e-8, "{sd:?}");
    // A sphere's centre in the plane, inside the square: out along ±z by 0.3 + 0.1.
    let s = Shape::sphere(0.3).unwrap();
    let sd = signed_distance(
        &a,
        &at([0.0; 3]),
        &s,
        &at([0.1, -0.2, 0.0]),
        &Options::default(),
    )
    .unwrap();
    assert_eq!(sd.status, SolveStatus::Converged);
    assert!((sd.distance + 0.4).abs() <= 1e-10, "{sd:?}");
    assert!((sd.normal.z.abs() - 1.0).abs() <= 1e-8, "{sd:?}");
    // A capsule (axis along x) lying in the plane 0.02 above it.
    let c = Shape::capsule(0.05, 0.4).unwrap();
    check(
        &a,
        &at([0.0; 3]),
        &c,
        &at([0.05, 0.1, 0.02]),
        -0.13,
        [0.0, 0.0, 1.0],
    );
}

#[test]
fn generic_poses_through_the_cores() {
    let a = square(0.5, 0.1);
    let b = square(0.4, 0.08);
    let o = Options::default();
    let q = [0.9, 0.3, -0.2, 0.25];
    let n = q.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
    let q = q.map(|v| v / n);
    let mut seen_overlap = 0;
    for k in 0..40 {
        let t = k as f64 / 40.0;
        let p2 = Pose::new([0.9 * t - 0.2, 0.3 * t, 0.4 - 0.5 * t], q).unwrap();
        let sd = signed_distance(&a, &at([0.0; 3]), &b, &p2, &o).unwrap();
        assert_eq!(sd.status, SolveStatus::Converged, "{sd:?}");
        let w = (sd.closest2 - sd.closest1 - sd.normal * sd.distance).norm();
        assert!(w <= 1e-9, "witness identity off by {w}: {sd:?}");
        if sd.distance > 0.0 {
            let d = distance(&a, &at([0.0; 3]), &b, &p2, &o).unwrap();
            assert_eq!(d.distance, sd.distance);
        } else {
            seen_overlap += 1;
        }
    }
    assert!(seen_overlap > 5);
}
