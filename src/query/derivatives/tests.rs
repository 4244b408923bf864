//! Unit tests of the derivative internals.

use crate::{jacobian, Options, Pose, Shape};

/// The reduced system (one unknown per cone on its boundary) and the full one (four
/// multiplier components and the linearised complementarity) are two derivations of the
/// same Jacobian: they must agree wherever both apply. Fixed-seed random poses over pairs
/// of every kind with a cone block (sphere, ellipsoid, capsule, cylinder, cone, polygon)
/// and with facets.
#[test]
fn reduced_and_full_active_set_systems_agree() {
    let shapes = [
        Shape::sphere(0.7).unwrap(),
        Shape::ellipsoid([[1.0, 0.2, 0.0], [0.2, 2.0, 0.1], [0.0, 0.1, 0.5]]).unwrap(),
        Shape::capsule(0.3, 1.2).unwrap(),
        Shape::cylinder(0.4, 0.9).unwrap(),
        Shape::cone(1.1, 0.5).unwrap(),
        Shape::polygon(
            &[[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]],
            &[0.6; 4],
            0.1,
        )
        .unwrap(),
        Shape::cuboid(0.5, 0.4, 0.3).unwrap(),
    ];
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let (mut compared, mut worst) = (0, 0.0f64);
    for a in &shapes {
        for b in &shapes {
            for _ in 0..20 {
                let mut pose = || {
                    let r = [2.0 * next(), 2.0 * next(), 2.0 * next()];
                    let q = [next(), next(), next(), next()];
                    Pose::new(r, q).unwrap()
                };
                let (pa, pb) = (pose(), pose());
                let opts = Options::default();
                let (p, reduced) = jacobian(a, &pa, b, &pb, &opts).unwrap();
                super::jacobian::FULL_SYSTEM_ONLY.with(|f| f.set(true));
                let (_, full) = jacobian(a, &pa, b, &pb, &opts).unwrap();
                super::jacobian::FULL_SYSTEM_ONLY.with(|f| f.set(false));
                if !p.status.is_converged() || p.alpha == 0.0 {
                    continue;
                }
                let scale = full.iter().flatten().fold(1.0f64, |m, v| m.max(v.abs()));
                for (rr, fr) in reduced.iter().zip(full.iter()) {
                    for (x, y) in rr.iter().zip(fr.iter()) {
                        worst = worst.max((x - y).abs() / scale);
                    }
                }
                compared += 1;
            }
        }
    }
    assert!(compared > 900, "only {compared} converged cases");
    assert!(
        worst <= 1e-8,
        "reduced and full Jacobians differ by {worst:e}"
    );
}

/// The closed-form generators against `(∂Q/∂q_k) Qᵀ` from the entry-wise derivatives of
/// the rotation matrix (`math::rotation_derivatives`), over quaternions of norms 1e-100 to
/// 1e100.
#[test]
fn rotation_generators_match_matrix_derivatives() {
    let mut worst = 0.0f64;
    for (i, scale) in [1e-100, 1e-3, 1.0, 7.5, 1e100].into_iter().enumerate() {
        for j in 0..20 {
            let t = (i * 20 + j) as f64;
            let q = [
                (t * 0.37).sin(),
                (t * 1.1).cos(),
                (t * 0.73).sin() - 0.2,
                (t * 2.3).cos(),
            ]
            .map(|x| x * scale);
            let pose = Pose::new([0.0; 3], q).unwrap();
            let d = crate::math::rotation_derivatives(q);
            let rt = pose.rotation().transpose();
            let m = super::rotation_generators(&pose);
            for k in 0..4 {
                let want = d[k] * rt * scale;
                let got = m[k] * scale;
                worst = worst.max((want - got).abs().max());
            }
        }
    }
    assert!(worst <= 1e-14, "generators differ by {worst:e} (times |q|)");
}

/// `rotation_dots` (the gradient's four dots, the axes not formed) against the formed axes
/// dotted with the same vector, over quaternions of norms 1e-300 to 1e300 (both sides of the
/// unscaled range), relative to `max|ω_i|·max|t_i|`.
#[test]
fn rotation_dots_are_the_axes_dotted() {
    let mut worst = 0.0f64;
    for (i, scale) in [1e-300, 1e-160, 1e-3, 1.0, 7.5, 1e160, 1e300]
        .into_iter()
        .enumerate()
    {
        for j in 0..50 {
            let t = (i * 50 + j) as f64;
            let q = [
                (t * 0.37).sin(),
                (t * 1.1).cos(),
                (t * 0.73).sin() - 0.2,
                (t * 2.3).cos(),
            ]
            .map(|x| x * scale);
            let pose = Pose::new([0.0; 3], q).unwrap();
            let v = crate::Vec3::new((t * 0.9).cos(), (t * 0.4).sin() * 3.0, -0.5);
            let dots = super::rotation_dots(&pose, &v);
            for (k, w) in super::rotation_axes(&pose).iter().enumerate() {
                // Largest components (a norm's squares underflow at 1e300).
                let bound = w.amax() * v.amax();
                assert!(
                    bound.is_finite() && bound > 0.0,
                    "scale {scale:e}: {bound:e}"
                );
                worst = worst.max((dots[k] - w.dot(&v)).abs() / bound);
            }
        }
    }
    // Each side is a three-term dot of rounded factors: |error| <= ~4u·Σ|ω_i t_i| <= 12u·bound
    // (u = 1.1e-16) per side.
    assert!(worst <= 2.7e-15, "dots differ by {worst:e} relative");
}

/// A sphere's quaternion columns are exactly zero (its set ignores its attitude), and every
/// other column equals the generic computation for the same ball written as an ellipsoid
/// (`P = I/R²`), whose quaternion columns come out at rounding level.
#[test]
fn sphere_attitude_columns_are_exactly_zero() {
    let r = 0.6;
    let ball = Shape::sphere(r).unwrap();
    let same = Shape::ellipsoid([
        [1.0 / (r * r), 0.0, 0.0],
        [0.0, 1.0 / (r * r), 0.0],
        [0.0, 0.0, 1.0 / (r * r)],
    ])
    .unwrap();
    let others = [
        Shape::cuboid(0.5, 0.4, 0.3).unwrap(),
        Shape::cone(1.1, 0.5).unwrap(),
        Shape::capsule(0.3, 1.2).unwrap(),
        Shape::sphere(0.4).unwrap(),
    ];
    let pa = Pose::new([0.1, -0.2, 0.3], [0.9, 0.1, -0.3, 0.2]).unwrap();
    let pb = Pose::new([1.4, 0.5, -0.6], [0.4, -0.5, 0.2, 0.7]).unwrap();
    let opts = Options::default();
    for other in &others {
        let (_, j) = jacobian(&ball, &pa, other, &pb, &opts).unwrap();
        let (_, g) = crate::gradient(&ball, &pa, other, &pb, &opts).unwrap();
        let (_, je) = jacobian(&same, &pa, other, &pb, &opts).unwrap();
        for c in 3..7 {
            assert_eq!(g[c], 0.0);
            for row in &j {
                assert_eq!(row[c], 0.0);
            }
            for row in &je {
                assert!(row[c].abs() <= 1e-9, "ellipsoid q column {c}: {}", row[c]);
            }
        }
        for (jr, er) in j.iter().zip(je.iter()) {
            for c in (0..3).chain(7..14) {
                assert!(
                    (jr[c] - er[c]).abs() <= 1e-8 * (1.0 + er[c].abs()),
                    "column {c}: sphere {} vs ellipsoid {}",
                    jr[c],
                    er[c]
                );
            }
        }
    }
}

/// The padded whole-matrix factorisation of the smallest storage gives what the general
/// one gives for the same system in larger storage (orders below and at the storage size,
/// pivoting exercised by a small leading entry), and both report a singular system.
#[test]
fn padded_small_system_matches_general_factorisation() {
    use super::jacobian::xalpha_rows;
    use super::TINY_ACTIVE;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for order in 4..=TINY_ACTIVE {
        for trial in 0..20 {
            let mut small = [[0.0; TINY_ACTIVE]; TINY_ACTIVE];
            let mut large = [[0.0; 12]; 12];
            for i in 0..order {
                for j in 0..order {
                    let v = next() * if trial % 2 == 0 { 1e-3 } else { 1e3 };
                    small[i][j] = v;
                    large[i][j] = v;
                }
            }
            small[0][0] *= 1e-6;
            large[0][0] *= 1e-6;
            let ys = xalpha_rows(&mut small, order).expect("regular");
            let yl = xalpha_rows(&mut large, order).expect("regular");
            for q in 0..order {
                for r in 0..4 {
                    let (a, b) = (ys[q][r], yl[q][r]);
                    assert!(
                        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                        "order {order} trial {trial} Y[{q}][{r}]: {a} vs {b}"
                    );
                }
            }
            for y in &ys[order..] {
                assert_eq!(*y, [0.0; 4]);
            }
            // A repeated row makes both singular.
            let mut small_singular = [[0.0; TINY_ACTIVE]; TINY_ACTIVE];
            let mut large_singular = [[0.0; 12]; 12];
            for i in 0..order {
                for j in 0..order {
                    let v = next();
                    small_singular[i][j] = v;
                    large_singular[i][j] = v;
                }
            }
            for j in 0..order {
                small_singular[order - 1][j] = small_singular[0][j];
                large_singular[order - 1][j] = large_singular[0][j];
            }
            assert!(xalpha_rows(&mut small_singular, order).is_none());
            assert!(xalpha_rows(&mut large_singular, order).is_none());
        }
    }
}
