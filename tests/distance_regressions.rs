//! Regressions found by the FCL/libccd comparison suite (c_tests/compare): witness points must
//! lie on (or, for overlap, inside) their shapes whatever the status, the normal must stay
//! accurate when the gap is tiny, and an aligned cylinder–cone distance must converge.

use dcol::{distance, proximity, Options, Pose, Shape};

/// Scaled membership: the smallest α with the point in the scaled shape, via proximity with a
/// tiny sphere at the point (α ≤ 1 + ε means inside, up to the sphere's radius).
fn inside(shape: &Shape, pose: &Pose, p: dcol::Vec3, tol: f64) -> bool {
    let probe = Shape::sphere(1e-9).unwrap();
    let at = Pose::from_position([p.x, p.y, p.z]).unwrap();
    let a = proximity(shape, pose, &probe, &at, &Options::default()).unwrap();
    // The shape scaled by α reaches the point (minus the probe radius, negligible).
    a.alpha <= 1.0 + tol
}

#[test]
fn overlap_witness_is_a_common_point() {
    let s = Shape::sphere(0.4075).unwrap();
    let c = Shape::cone(1.7494, 0.9372).unwrap();
    let p1 = Pose::new([0.0; 3], [-0.7224, -0.3945, 0.5096, 0.2506]).unwrap();
    let p2 = Pose::new([0.8306, -0.4231, 0.039], [0.4865, 0.4454, 0.4736, 0.5837]).unwrap();
    assert!(
        proximity(&s, &p1, &c, &p2, &Options::default())
            .unwrap()
            .alpha
            < 1.0
    );
    let d = distance(&s, &p1, &c, &p2, &Options::default()).unwrap();
    assert!(d.status.is_converged());
    assert_eq!(d.distance, 0.0);
    assert!(inside(&s, &p1, d.closest1, 1e-6), "{:?}", d.closest1);
    assert!(inside(&c, &p2, d.closest2, 1e-6), "{:?}", d.closest2);
}

#[test]
fn tiny_gap_witnesses_stay_on_the_shapes() {
    let a = Shape::cylinder(0.520_121_509_168_517_2, 0.541_252_458_743_199_7).unwrap();
    let b = Shape::cylinder(0.530_124_029_557_616_4, 0.956_905_813_056_616_2).unwrap();
    let p1 = Pose::new(
        [
            0.813_928_505_609_331_9,
            -2.085_628_842_708_339_4,
            -0.794_320_481_316_691_3,
        ],
        [0.0, 0.0, 1.0, 0.0],
    )
    .unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    let p2 = Pose::new(
        [
            0.013_177_365_152_046_594,
            -1.693_160_961_125_893_5,
            -0.898_157_821_013_389_8,
        ],
        [0.0, h, 0.0, h],
    )
    .unwrap();
    let d = distance(&a, &p1, &b, &p2, &Options::default()).unwrap();
    assert!(d.status.is_converged());
    assert!((d.distance - 8.815e-7).abs() < 1e-9, "{}", d.distance);
    assert!(inside(&a, &p1, d.closest1, 1e-6), "{:?}", d.closest1);
    assert!(inside(&b, &p2, d.closest2, 1e-6), "{:?}", d.closest2);
}

#[test]
fn normal_is_accurate_at_tiny_gaps() {
    let b = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
    let p1 = Pose::from_position([0.0; 3]).unwrap();
    for gap in [1e-6, 1e-7, 1e-8] {
        let p2 = Pose::from_position([1.0 + gap, 0.3, 0.2]).unwrap();
        let d = distance(&b, &p1, &b, &p2, &Options::default()).unwrap();
        assert!(d.status.is_converged());
        assert!(
            (d.distance - gap).abs() < 1e-10,
            "gap {gap}: {}",
            d.distance
        );
        let angle = (d.normal.x.clamp(-1.0, 1.0)).acos();
        assert!(
            angle < 1e-6,
            "gap {gap}: normal {:?} ({angle:e} rad off)",
            d.normal
        );
    }
}

/// Fixed bug: the cylinder's axis (world z) is parallel to the cone's base disc, whose rim
/// passes 2e-5 from the cylinder's nearest generator, so the distance varies only weakly
/// along z. Near the optimum the normal equations' largest diagonal grew like 1/μ and the
/// Cholesky pivot floor (then 1e-14 times the largest diagonal) replaced that direction's
/// genuine O(1e-4) pivot; the direction then violated the dual equation, the dual residual
/// stalled at 2e-8 (limit 3e-9) and the iterates were pushed onto the cone boundary until the
/// NT scaling failed (NumericalFailure after 18 iterations).
#[test]
fn aligned_cylinder_cone_distance_converges() {
    let cyl = Shape::cylinder(0.30269, 0.8502).unwrap();
    let cone = Shape::cone(0.65542, 0.78584).unwrap();
    let p1 = Pose::new([0.0; 3], [0.5, -0.5, 0.5, 0.5]).unwrap();
    let p2 = Pose::new([0.46681, 0.65602, 0.30257], [0.0, 0.0, 1.0, 0.0]).unwrap();
    // Closed form: the nearest point of the cone is the lowest point of its base rim, at
    // x = 0.46681 − H/4 and y = 0.65602 − H tan β; the cylinder's surface is at radius R.
    let rim_y = 0.65602 - 0.65542 * 0.78584f64.tan();
    let exact = (0.46681f64 - 0.65542 / 4.0).hypot(rim_y) - 0.30269;
    for (a, pa, b, pb) in [(&cyl, &p1, &cone, &p2), (&cone, &p2, &cyl, &p1)] {
        let d = distance(a, pa, b, pb, &Options::default()).unwrap();
        assert!(
            d.status.is_converged(),
            "{:?} after {}",
            d.status,
            d.iterations
        );
        assert!(
            (d.distance - exact).abs() < 1e-9,
            "{} vs {exact}",
            d.distance
        );
    }
}
