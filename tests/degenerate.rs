//! Degenerate optima: parallel faces and a segment or flat cap lying on a face, where x* is not
//! unique and the final Newton polish is refused (its system is singular along the optimal
//! face). α* must still be accurate far beyond the solver tolerance: the solver takes one more
//! interior-point iteration in that case. Exact values from symmetry: for shapes symmetric under
//! the reflections of the axes, with the offset Δ along axis k, α* = |Δ_k| / (h₁(e_k) + h₂(e_k))
//! (the support values along that axis); for aligned boxes, α* = max_k |Δ_k| / (a_k + b_k).

use dcol::{proximity, Options, Pose, Shape};

fn at(r: [f64; 3]) -> Pose {
    Pose::from_position(r).unwrap()
}

fn check(what: &str, s1: &Shape, r1: [f64; 3], s2: &Shape, r2: [f64; 3], exact: f64) {
    for (a, pa, b, pb) in [(s1, r1, s2, r2), (s2, r2, s1, r1)] {
        let p = proximity(a, &at(pa), b, &at(pb), &Options::default()).unwrap();
        assert!(p.status.is_converged(), "{what}: {:?}", p.status);
        let err = (p.alpha - exact).abs() / exact.max(1.0);
        assert!(
            err <= 1e-12,
            "{what}: alpha {} vs exact {exact} (relative error {err:e}, {} iterations)",
            p.alpha,
            p.iterations
        );
    }
}

#[test]
fn parallel_box_faces() {
    let a = Shape::cuboid(1.0, 0.8, 0.6).unwrap();
    let b = Shape::cuboid(0.5, 0.7, 0.4).unwrap();
    for (d, k) in [
        ([3.0f64, 0.2, 0.1], 0usize),
        ([0.1, -2.5, 0.3], 1),
        ([0.05, 0.1, 0.7], 2),
        ([1.2, 0.1, 0.0], 0),
        ([-0.6, 0.05, -0.02], 0),
    ] {
        let sums = [1.5, 1.5, 1.0];
        let exact = d[k].abs() / sums[k];
        check(&format!("boxes at {d:?}"), &a, [0.0; 3], &b, d, exact);
    }
}

#[test]
fn segment_and_cap_on_a_face() {
    let slab = Shape::cuboid(2.0, 2.0, 0.3).unwrap();
    // A capsule (axis x) lying flat above the slab: line contact.
    let capsule = Shape::capsule(0.2, 1.0).unwrap();
    for dz in [0.4, 0.5, 1.3, 4.0] {
        check(
            &format!("capsule above slab, dz = {dz}"),
            &slab,
            [0.0; 3],
            &capsule,
            [0.0, 0.0, dz],
            dz / (0.3 + 0.2),
        );
    }
    // A cylinder (axis x) with its flat cap against the slab's x face: face contact.
    let post = Shape::cuboid(0.3, 2.0, 2.0).unwrap();
    let cylinder = Shape::cylinder(0.25, 0.8).unwrap();
    for dx in [0.5, 0.7, 2.0] {
        check(
            &format!("cylinder cap on a face, dx = {dx}"),
            &post,
            [0.0; 3],
            &cylinder,
            [dx, 0.0, 0.0],
            dx / (0.3 + 0.4),
        );
    }
}

/// `ref-stress-198` of ../shared/reference (category `parallel`): a rotated box whose face is
/// parallel to a cylinder's flat cap. The plain interior-point answer was 8.7e-11 off (1.1e-10
/// after an unrelated change of rounding); with the extra iteration it is within 1e-12. The
/// reference value is Clarabel's at 1e-12, polished (the reference README puts it within about
/// 1e-13 relative).
#[test]
fn rotated_box_face_on_cylinder_cap() {
    let h = [0.8388286294009029, 0.2834795243105931, 0.6929509234862241];
    let a = Shape::cuboid(h[0], h[1], h[2]).unwrap();
    let b = Shape::cylinder(0.9985876329328135, 1.6836421427101158).unwrap();
    let pa = Pose::new(
        [-1.3017082437329197, 0.5226323503235335, -0.8886983112709208],
        [
            0.7875376453116705,
            0.5882518228777555,
            -0.18352854789686102,
            -0.00784360917033952,
        ],
    )
    .unwrap();
    let pb = Pose::new(
        [
            -2.105246718633756,
            -2.7004068451741063,
            -0.14925688441166707,
        ],
        [
            0.5821406843224542,
            0.5570115631718444,
            0.5041415901226849,
            0.31095272833344595,
        ],
    )
    .unwrap();
    let exact = 2.211774159923271;
    for (s1, p1, s2, p2) in [(&a, &pa, &b, &pb), (&b, &pb, &a, &pa)] {
        let p = proximity(s1, p1, s2, p2, &Options::default()).unwrap();
        assert!(p.status.is_converged());
        let err = (p.alpha - exact).abs() / exact;
        assert!(err <= 1e-11, "alpha {} vs {exact} (error {err:e})", p.alpha);
    }
}

/// A convex hull, a padded polygon and a 40-plane polytope from 1e-300 to 1e300 in size (their constructors once
/// rejected them below ~1e-150 as degenerate: products of coordinates underflowed): accepted,
/// with the same bounding and inscribed radii (scaled), and α* against a sphere and a box of the same scale equal to the unit
/// size's within 1e-12 relative (the scaled problem is the same problem).
#[test]
fn tiny_and_huge_hulls_and_polygons_answer_as_at_unit_size() {
    let hull_at = |s: f64| {
        let pts: Vec<[f64; 3]> = (0..30)
            .map(|k| {
                let (t, u) = (k as f64 * 0.7, k as f64 * 1.3);
                [
                    t.cos() * u.sin() * s,
                    t.sin() * u.sin() * 0.8 * s,
                    u.cos() * 0.6 * s,
                ]
            })
            .collect();
        Shape::convex_hull(&pts, 0.0)
    };
    let polygon_at = |s: f64| {
        let c = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.5, -1.0]];
        let d = [0.4 * s, 0.3 * s, 0.5 * s, 0.35 * s];
        Shape::polygon(&c, &d, 0.08 * s)
    };
    // 40 planes: built as the polar hull of a_i / b_i (1e300 apart for the tiniest).
    let planes_at = |s: f64| {
        let a: Vec<[f64; 3]> = (0..40)
            .map(|k| {
                let (t, u) = (k as f64 * 0.7, k as f64 * 1.3 + 0.2);
                [t.cos() * u.sin(), t.sin() * u.sin(), u.cos()]
            })
            .collect();
        let b: Vec<f64> = (0..40).map(|k| (0.5 + 0.01 * k as f64) * s).collect();
        Shape::polytope(&a, &b)
    };
    let alpha = |a: &Shape, b: &Shape, s: f64| {
        let q = Pose::new([0.9 * s, -0.4 * s, 0.3 * s], [0.9, 0.1, -0.3, 0.2]).unwrap();
        let p = proximity(a, &at([0.0; 3]), b, &q, &Options::default()).unwrap();
        assert!(p.status.is_converged(), "{:?} at {s:e}", p.status);
        p.alpha
    };
    let unit = |s: f64| {
        let ball = Shape::sphere(0.3 * s).unwrap();
        let cube = Shape::cuboid(0.2 * s, 0.3 * s, 0.25 * s).unwrap();
        let (h, g, p) = (
            hull_at(s).unwrap(),
            polygon_at(s).unwrap(),
            planes_at(s).unwrap(),
        );
        (
            [
                h.bounding_radius() / s,
                h.inscribed_radius() / s,
                g.bounding_radius() / s,
                p.bounding_radius() / s,
            ],
            [
                alpha(&h, &ball, s),
                alpha(&h, &cube, s),
                alpha(&g, &ball, s),
                alpha(&g, &cube, s),
                alpha(&h, &g, s),
                alpha(&p, &ball, s),
                alpha(&p, &h, s),
            ],
        )
    };
    let (n1, a1) = unit(1.0);
    for s in [
        1e-300,
        1e-170,
        1e-120,
        2f64.powi(-101),
        1e-30,
        1e30,
        2f64.powi(101),
        1e120,
        1e170,
        1e300,
    ] {
        let (n, a) = unit(s);
        for (x, y) in n.iter().zip(&n1) {
            assert!(
                (x - y).abs() <= 1e-14 * y,
                "radius {x} at {s:e}, {y} at unit size"
            );
        }
        for (x, y) in a.iter().zip(&a1) {
            assert!(
                (x - y).abs() <= 1e-12 * y,
                "alpha {x} at {s:e}, {y} at unit size"
            );
        }
    }
    // Near the largest double the hull and the polygon still answer (the hull's tolerance and
    // centroid once overflowed: "must surround the origin", centroid inf). A polytope given by
    // 40 planes there is not supported (`huge_polytope_from_planes_is_accepted`, ignored).
    let s = 8e307;
    let ball = Shape::sphere(0.3 * s).unwrap();
    let (h, g) = (hull_at(s).unwrap(), polygon_at(s).unwrap());
    for (x, y) in [(alpha(&h, &ball, s), a1[0]), (alpha(&g, &ball, s), a1[2])] {
        assert!(
            (x - y).abs() <= 1e-12 * y,
            "alpha {x} at {s:e}, {y} at unit size"
        );
    }
}

/// Open defect (docs/failure-modes.md): a polytope given by 40 planes with offsets near the
/// largest double is rejected as unbounded (the vertex construction's products overflow).
#[test]
#[ignore = "open defect: polytopes with plane offsets near 1e308 (docs/failure-modes.md)"]
fn huge_polytope_from_planes_is_accepted() {
    let a: Vec<[f64; 3]> = (0..40)
        .map(|k| {
            let (t, u) = (k as f64 * 0.7, k as f64 * 1.3 + 0.2);
            [t.cos() * u.sin(), t.sin() * u.sin(), u.cos()]
        })
        .collect();
    let b: Vec<f64> = (0..40).map(|k| (0.5 + 0.01 * k as f64) * 8e307).collect();
    let p = Shape::polytope(&a, &b).unwrap();
    assert!((p.bounding_radius() / 8e307 - 0.8771716136936852).abs() < 1e-12);
}

/// A sphere far smaller than the box it touches (radius down to 1e-8 against a unit cube):
/// the closed form's ball-exit root once formed its discriminant as a difference of two
/// products of the cube's size that cancel down to ρ² (α* up to 1.2e-8 off); it now takes the
/// cross term from Lagrange's identity (`closed_form::vertex_root`).
#[test]
fn tiny_sphere_on_a_cube_face() {
    let cube = Shape::cuboid(1.0, 1.0, 1.0).unwrap();
    for rho in [1e-6, 1e-7, 1e-8] {
        let ball = Shape::sphere(rho).unwrap();
        for (x, y) in [(0.13, -0.41), (0.37, 0.29), (-0.22, 0.05), (0.61, -0.17)] {
            // Face contact: the scaled cube's face z = α meets the scaled ball, 2 − α = αρ.
            check(
                "tiny sphere",
                &cube,
                [0.0; 3],
                &ball,
                [x, y, 2.0],
                2.0 / (1.0 + rho),
            );
        }
    }
}
