//! The kind of derivatives a query reports, and the smoothing option: the central-path point
//! at a user-set barrier parameter with its derivatives, checked against analytic bounds and
//! against central finite differences of the smoothed query itself.

mod common;

use common::random::{Rng, KINDS};
use dcol::ffi::*;
use dcol::{
    derivatives, gradient, jacobian, proximity, DerivativeKind, Error, Options, Pose, Shape, Solver,
};
use std::ptr;

fn at(p: [f64; 3]) -> Pose {
    Pose::from_position(p).unwrap()
}

#[test]
fn the_kind_of_derivatives_is_reported() {
    let o = Options::default();
    let cube = Shape::cuboid(1.0, 1.0, 1.0).unwrap();
    let small = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
    let ball = Shape::sphere(0.5).unwrap();
    let p0 = at([0.0, 0.0, 0.0]);
    // No derivatives asked for.
    let p = proximity(&cube, &p0, &ball, &at([3.0, 0.2, 0.1]), &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::None);
    // A sphere against a face: x* unique, exact everything, from the geometric solution.
    let (p, _) = jacobian(&cube, &p0, &ball, &at([3.0, 0.2, 0.1]), &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Exact);
    assert_ne!(p.solver, Solver::InteriorPoint);
    let (p, _) = gradient(&cube, &p0, &ball, &at([3.0, 0.2, 0.1]), &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Exact);
    // Face against face: x* is not unique, the Jacobian is the smoothed one.
    let (p, j) = jacobian(&cube, &p0, &small, &at([2.0, 0.3, 0.1]), &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Smoothed);
    assert!((p.alpha - 4.0 / 3.0).abs() < 1e-9);
    // ∂α*/∂r₂ is still the face normal's: α* = (r₂ − r₁)ₓ/1.5.
    assert!((j[3][7] - 2.0 / 3.0).abs() < 1e-6, "{:?}", j[3]);
    // The gradient alone is smoothed there too: α* has a kink under rotation (an edge touches
    // on either side), and the envelope formula's value would depend on the contact point.
    let (p, g) = gradient(&cube, &p0, &small, &at([2.0, 0.3, 0.1]), &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Smoothed);
    assert!((g[7] - 2.0 / 3.0).abs() < 1e-6, "{g:?}");
    // Coincident origins: zero, a subgradient.
    let d = derivatives(&cube, &p0, &ball, &p0, &o).unwrap();
    assert_eq!(d.proximity.derivatives, DerivativeKind::Subgradient);
    assert!(d.dalpha.iter().all(|v| *v == 0.0));
}

#[test]
fn invalid_smoothing_is_refused() {
    let ball = Shape::sphere(0.5).unwrap();
    for mu in [-1e-9, f64::NAN, f64::INFINITY] {
        let o = Options {
            smoothing: mu,
            ..Options::default()
        };
        let r = proximity(&ball, &at([0.0; 3]), &ball, &at([2.0, 0.0, 0.0]), &o);
        assert!(matches!(r, Err(Error::InvalidOptions(_))), "{mu}: {r:?}");
    }
}

/// Two boxes, face against face, the small one sliding across the big one's edge: exact α*
/// has a kink where the contact leaves the face (a corner of the small box passes the edge),
/// the smoothed one does not, and it stays above the exact one by at most ν·μ relative.
#[test]
fn smoothed_alpha_bounds_the_exact_one_and_converges_to_it() {
    let cube = Shape::cuboid(1.0, 1.0, 1.0).unwrap();
    let small = Shape::cuboid(0.5, 0.5, 0.5).unwrap();
    let nu = 12.0; // six orthant rows each
    for k in 0..40 {
        let y = -2.0 + 0.1 * k as f64;
        let p2 = Pose::new([2.2, y, 0.05], [0.995, 0.0, 0.0, 0.0998]).unwrap();
        let exact = proximity(&cube, &at([0.0; 3]), &small, &p2, &Options::default())
            .unwrap()
            .alpha;
        let mut last = f64::INFINITY;
        for mu in [1e-2, 1e-4, 1e-6, 1e-8] {
            let o = Options {
                smoothing: mu,
                ..Options::default()
            };
            let p = proximity(&cube, &at([0.0; 3]), &small, &p2, &o).unwrap();
            assert!(p.status.is_converged(), "y {y} mu {mu}: {:?}", p.status);
            assert_eq!(p.solver, Solver::InteriorPoint);
            assert!(
                p.alpha >= exact * (1.0 - 1e-12),
                "y {y} mu {mu}: {} < {exact}",
                p.alpha
            );
            assert!(
                p.alpha <= exact * (1.0 + nu * mu),
                "y {y} mu {mu}: {} vs {exact}",
                p.alpha
            );
            assert!(p.alpha < last, "y {y} mu {mu}: not decreasing");
            last = p.alpha;
        }
        assert!(
            (last - exact).abs() <= 1e-6 * exact,
            "y {y}: {last} vs {exact}"
        );
    }
}

/// `(x, α)` of the smoothed query at `theta = (r₁, q₁, r₂, q₂)`.
fn smoothed(s: &[Shape; 2], theta: &[f64; 14], o: &Options) -> [f64; 4] {
    let p1 = Pose::new(
        [theta[0], theta[1], theta[2]],
        [theta[3], theta[4], theta[5], theta[6]],
    )
    .unwrap();
    let p2 = Pose::new(
        [theta[7], theta[8], theta[9]],
        [theta[10], theta[11], theta[12], theta[13]],
    )
    .unwrap();
    let p = proximity(&s[0], &p1, &s[1], &p2, o).unwrap();
    assert!(p.status.is_converged());
    [p.point.x, p.point.y, p.point.z, p.alpha]
}

/// The smoothed Jacobian (and gradient) against central finite differences of the smoothed
/// query, on random configurations of every ordered pair of the eight kinds, separated, near
/// and overlapping, with the smoothing where it matters (μ = 1e-3: the answer moves by up to
/// a few percent from the exact one, and its curvature is up to ~1/μ).
#[test]
fn smoothed_derivatives_match_finite_differences() {
    const CASES: usize = 12;
    const H: f64 = 1e-6;
    let o = Options {
        smoothing: 1e-3,
        tolerance: 1e-12,
        ..Options::default()
    };
    let mut worst: (f64, String) = (0.0, String::new());
    let mut cases = 0;
    for k1 in KINDS {
        for k2 in KINDS {
            for index in 0..CASES {
                let seed = 0x5300_7000 ^ (k1 as u64) << 8 ^ (k2 as u64) << 16 ^ index as u64;
                let mut rng = Rng::new(seed);
                let s = [k1.random(&mut rng), k2.random(&mut rng)];
                let ell = s[0].bounding_radius().max(s[1].bounding_radius());
                let mut theta = [0.0; 14];
                theta[3..7].copy_from_slice(&rng.quat());
                theta[10..14].copy_from_slice(&rng.quat());
                let u = rng.unit::<3>();
                let target = [1.5, 1.0, 0.6][index % 3];
                // Place shape 2 along u at the target α (α is homogeneous in r₂ − r₁).
                theta[7..10].copy_from_slice(&u);
                let a0 = smoothed(&s, &theta, &o)[3];
                for j in 0..3 {
                    theta[7 + j] = u[j] * target / a0;
                }
                let (p1, p2) = (
                    Pose::new([0.0; 3], [theta[3], theta[4], theta[5], theta[6]]).unwrap(),
                    Pose::new(
                        [theta[7], theta[8], theta[9]],
                        [theta[10], theta[11], theta[12], theta[13]],
                    )
                    .unwrap(),
                );
                let (p, jac) = jacobian(&s[0], &p1, &s[1], &p2, &o).unwrap();
                let (_, g) = gradient(&s[0], &p1, &s[1], &p2, &o).unwrap();
                assert_eq!(p.derivatives, DerivativeKind::Smoothed);
                assert_eq!(
                    g, jac[3],
                    "{k1:?}-{k2:?}#{index}: gradient ≠ Jacobian's α row"
                );
                for c in 0..14 {
                    let h = if c % 7 < 3 { H * ell } else { H };
                    let mut tp = theta;
                    let mut tm = theta;
                    tp[c] += h;
                    tm[c] -= h;
                    let (fp, fm) = (smoothed(&s, &tp, &o), smoothed(&s, &tm, &o));
                    for r in 0..4 {
                        let fd = (fp[r] - fm[r]) / (2.0 * h);
                        // Non-dimensional: x rows over ℓ, position columns times ℓ.
                        let scale =
                            if r < 3 { 1.0 / ell } else { 1.0 } * if c % 7 < 3 { ell } else { 1.0 };
                        let (a, b) = (jac[r][c] * scale, fd * scale);
                        let err = (a - b).abs() / a.abs().max(1.0);
                        if err > worst.0 {
                            worst = (err, format!("{k1:?}-{k2:?}#{index} [{r}][{c}] {a} vs {b}"));
                        }
                    }
                }
                cases += 1;
            }
        }
    }
    println!(
        "{cases} cases, worst relative error {:e}: {}",
        worst.0, worst.1
    );
    assert!(worst.0 <= 1e-5, "{}", worst.1);
}

/// The same through the C ABI: the option, its validation, and the kind reported.
#[test]
fn the_c_abi_takes_the_smoothing_and_reports_the_kind() {
    let mut shape = ptr::null_mut();
    // SAFETY: a valid out-pointer.
    assert_eq!(
        unsafe { dcol_shape_new_sphere(0.5, &mut shape) },
        dcol_status::DCOL_OK
    );
    let pose = |x: f64| dcol_pose {
        position: [x, 0.0, 0.0],
        quaternion: [1.0, 0.0, 0.0, 0.0],
    };
    let (q1, q2) = (pose(0.0), pose(2.0));
    let mut o = dcol_options_default();
    assert_eq!(o.smoothing, 0.0);
    let mut res = dcol_proximity_result::default();
    let mut j = [0.0; 56];
    // SAFETY: valid shape, poses, options and outputs of the documented sizes.
    let st = unsafe { dcol_jacobian(shape, &q1, shape, &q2, &o, &mut res, j.as_mut_ptr()) };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert_eq!(res.derivatives, DCOL_DERIVATIVES_EXACT);
    o.smoothing = 1e-4;
    // SAFETY: as above.
    let st = unsafe { dcol_jacobian(shape, &q1, shape, &q2, &o, &mut res, j.as_mut_ptr()) };
    assert_eq!(st, dcol_status::DCOL_OK);
    assert_eq!(res.derivatives, DCOL_DERIVATIVES_SMOOTHED);
    assert!(res.alpha > 2.0 && res.alpha < 2.0 * (1.0 + 2.0 * 1e-4));
    o.smoothing = -1.0;
    // SAFETY: as above.
    let st = unsafe { dcol_jacobian(shape, &q1, shape, &q2, &o, &mut res, j.as_mut_ptr()) };
    assert_eq!(st, dcol_status::DCOL_ERROR_INVALID_OPTIONS);
    // SAFETY: built above, freed once.
    unsafe { dcol_shape_free(shape) };
}
