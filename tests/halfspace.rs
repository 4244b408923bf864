//! The half-space primitive: every query against the seven other kinds, both argument orders,
//! checked against independent truth: the analytic formulas on simple poses, the general
//! solvers on a large box standing in for the half-space (same origin, same top plane, so the
//! same α*), and central finite differences for every derivative.

#![allow(clippy::needless_range_loop)] // Jacobians are indexed by row and column in lockstep.

mod common;

use common::random::{Rng, KINDS};
use dcol::math::rotation_from_quaternion;
use dcol::{
    alpha_below, contact_manifold, derivatives, distance, distance_gradient, distance_within,
    gradient, gradient_mrp, intersect, jacobian, jacobian_mrp, proximity, signed_distance,
    signed_distance_gradient, DerivativeKind, Error, Method, Options, Pose, Shape, ShapeKind,
    Solver, Vec3,
};

/// The half-space `{u_z ≤ depth}` as a box: the same top plane and origin, sides and bottom
/// `big` away.
fn big_box(depth: f64, big: f64) -> Shape {
    let a = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    Shape::polytope(&a, &[big, big, depth, big, big, big]).unwrap()
}

fn normal_of(p: &Pose) -> Vec3 {
    p.rotation().column(2).into_owned()
}

/// A random half-space pose and a pose of B with `g = n·(r_B − r_H)` given, offset sideways
/// by up to 1.
fn place(rng: &mut Rng, g: f64) -> (Pose, Pose) {
    let ph = Pose::new(
        [
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        ],
        rng.quat(),
    )
    .unwrap();
    let n = normal_of(&ph);
    let t = Vec3::from(rng.unit::<3>());
    let side = (t - n * n.dot(&t)) * rng.range(0.0, 1.0);
    let rb = ph.position() + n * g + side;
    let pb = Pose::new([rb.x, rb.y, rb.z], rng.quat()).unwrap();
    (ph, pb)
}

/// `h_B(−n)` by brute force over the big-box signed distance: `sd_box = g − c − h`.
fn support_value(b: &Shape, pb: &Pose, ph: &Pose, depth: f64) -> f64 {
    let boxed = big_box(depth, 60.0);
    let sd = signed_distance(&boxed, ph, b, pb, &Options::default()).unwrap();
    let g = normal_of(ph).dot(&(pb.position() - ph.position()));
    g - depth - sd.distance
}

#[test]
fn construction_rejects_bad_depth() {
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, -0.0] {
        assert!(
            matches!(Shape::halfspace(bad), Err(Error::InvalidShape(_))),
            "{bad}"
        );
    }
    let h = Shape::halfspace(0.25).unwrap();
    assert_eq!(h.kind(), ShapeKind::Halfspace);
    assert_eq!(h.bounding_radius(), f64::INFINITY);
    assert_eq!(h.inscribed_radius(), 0.25);
}

#[test]
fn sphere_on_floor_analytic() {
    // Floor top z = 0 (depth 2), ball radius 0.5 at height z.
    let floor = Shape::halfspace(2.0).unwrap();
    let under = Pose::new([0.3, -0.2, -2.0], [1.0, 0.0, 0.0, 0.0]).unwrap();
    let ball = Shape::sphere(0.5).unwrap();
    let o = Options::default();
    for z in [1.7, 0.5, 0.2, -1.0, -2.5, -3.0] {
        let pb = Pose::from_position([1.0, 2.0, z]).unwrap();
        let alpha = if z > -2.0 { (z + 2.0) / 2.5 } else { 0.0 };
        for swap in [false, true] {
            let (s1, p1, s2, p2) = if swap {
                (&ball, &pb, &floor, &under)
            } else {
                (&floor, &under, &ball, &pb)
            };
            let p = proximity(s1, p1, s2, p2, &o).unwrap();
            assert!((p.alpha - alpha).abs() < 1e-15, "z {z}: {}", p.alpha);
            assert_eq!(p.solver, Solver::ClosedForm);
            let x = Vec3::new(1.0, 2.0, z - alpha * 0.5);
            assert!((p.point - x).norm() < 1e-15);
            let sd = signed_distance(s1, p1, s2, p2, &o).unwrap();
            assert!((sd.distance - (z - 0.5)).abs() < 1e-15);
            let up = if swap { -1.0 } else { 1.0 };
            assert_eq!(sd.normal, Vec3::new(0.0, 0.0, up));
            assert!(((sd.closest2 - sd.closest1) - sd.normal * sd.distance).norm() < 1e-15);
            let d = distance(s1, p1, s2, p2, &o).unwrap();
            assert!((d.distance - (z - 0.5).max(0.0)).abs() < 1e-15);
            let below = intersect(s1, p1, s2, p2, &o).unwrap().below;
            assert_eq!(below, z < 0.5 && z != 0.5, "z {z}");
            let within = distance_within(s1, p1, s2, p2, 1.0, &o).unwrap();
            assert_eq!(within.is_some(), z - 0.5 <= 1.0);
        }
    }
}

/// Every query on every kind, both orders, separated / touching / overlapping / origin inside,
/// against the general solvers on the large box.
#[test]
fn every_kind_matches_the_big_box() {
    let o = Options::default();
    let mut rng = Rng::new(11);
    let mut worst = [0.0f64; 4];
    for kind in KINDS {
        for trial in 0..12 {
            let b = kind.random(&mut rng);
            let depth = rng.range(0.2, 2.0);
            let (rho, iota) = (b.bounding_radius(), b.inscribed_radius());
            let case = trial % 4;
            let g = match case {
                0 => depth + rng.range(1.2, 2.0) * rho,  // separated
                1 => depth + rho,                        // moved to touching below
                2 => depth + rng.range(0.1, 0.9) * iota, // overlapping, origin outside
                _ => -rng.range(0.05, 1.0) * rho,        // origin inside
            };
            let (ph, mut pb) = place(&mut rng, g);
            let n = normal_of(&ph);
            if case == 1 {
                let h = support_value(&b, &pb, &ph, depth);
                let r = pb.position() - n * (g - depth - h);
                pb = Pose::new([r.x, r.y, r.z], pb.quaternion()).unwrap();
            }
            let h = Shape::halfspace(depth).unwrap();
            let boxed = big_box(depth, 60.0);
            for swap in [false, true] {
                let (s1, p1, s2, p2) = if swap {
                    (&b, &pb, &h, &ph)
                } else {
                    (&h, &ph, &b, &pb)
                };
                let (t1, t2) = if swap { (&b, &boxed) } else { (&boxed, &b) };
                let label = format!("{} case {case} swap {swap}", kind.name());
                let p = proximity(s1, p1, s2, p2, &o).unwrap();
                let q = proximity(t1, p1, t2, p2, &o).unwrap();
                assert!(p.status.is_converged() && q.status.is_converged());
                if case == 3 {
                    // B's origin inside: α* = 0 (the scaled half-space keeps its recession
                    // cone), the box's α* is small but positive (it shrinks to a point).
                    assert!(q.alpha < 0.1, "{label}: box {}", q.alpha);
                } else {
                    let ea = (p.alpha - q.alpha).abs() / q.alpha.max(1.0);
                    worst[0] = worst[0].max(ea);
                    assert!(ea < 1e-9, "{label}: α {} vs box {}", p.alpha, q.alpha);
                }
                match case {
                    0 => assert!(p.alpha > 1.0, "{label}"),
                    1 => assert!((p.alpha - 1.0).abs() < 1e-9, "{label}: {}", p.alpha),
                    2 => assert!(p.alpha > 0.0 && p.alpha < 1.0, "{label}"),
                    _ => assert_eq!(p.alpha, 0.0, "{label}"),
                }
                if case != 3 {
                    // x* in both scaled sets, on the scaled plane.
                    let plane = n.dot(&(p.point - ph.position())) - p.alpha * depth;
                    assert!(plane.abs() < 1e-12 * (1.0 + p.point.norm()), "{label}");
                    let ex = (p.point - q.point).norm() / rho;
                    worst[1] = worst[1].max(ex);
                    assert!(ex < 1e-6, "{label}: x* off by {ex:e}");
                }
                let sd = signed_distance(s1, p1, s2, p2, &o).unwrap();
                let sq = signed_distance(t1, p1, t2, p2, &o).unwrap();
                let es = (sd.distance - sq.distance).abs() / rho;
                worst[2] = worst[2].max(es);
                assert!(
                    es < 1e-9,
                    "{label}: sd {} vs box {}",
                    sd.distance,
                    sq.distance
                );
                assert!((sd.normal - sq.normal).norm() < 1e-6, "{label}");
                let up = if swap { -n } else { n };
                assert!((sd.normal - up).norm() < 1e-15, "{label}");
                assert!(
                    ((sd.closest2 - sd.closest1) - sd.normal * sd.distance).norm() < 1e-12,
                    "{label}"
                );
                if case != 1 {
                    assert!((sd.closest1 - sq.closest1).norm() < 1e-6 * rho, "{label}");
                    assert!((sd.closest2 - sq.closest2).norm() < 1e-6 * rho, "{label}");
                }
                let d = distance(s1, p1, s2, p2, &o).unwrap();
                let dq = distance(t1, p1, t2, p2, &o).unwrap();
                assert!((d.distance - dq.distance).abs() < 1e-8 * rho, "{label}");
                assert_eq!(d.distance, sd.distance.max(0.0), "{label}");
                let dec = intersect(s1, p1, s2, p2, &o).unwrap();
                if case != 1 {
                    assert_eq!(dec.below, p.alpha < 1.0, "{label}");
                    assert_eq!(dec.below, q.alpha < 1.0, "{label}");
                }
                // The interior-point method on the cone program (the half-space's orthant
                // row): the same α*, x* and derivatives; B's origin inside: the closed form.
                let ipm = Options {
                    method: Method::InteriorPoint,
                    ..o
                };
                let (pi, gi) = gradient(s1, p1, s2, p2, &ipm).unwrap();
                let (_, gc) = gradient(s1, p1, s2, p2, &o).unwrap();
                assert!(pi.status.is_converged(), "{label}");
                if case == 3 {
                    assert_eq!(pi.solver, Solver::ClosedForm, "{label}");
                    assert_eq!(pi.alpha, 0.0);
                } else {
                    assert_eq!(pi.solver, Solver::InteriorPoint, "{label}");
                    let ea = (pi.alpha - p.alpha).abs() / p.alpha.max(1.0);
                    worst[3] = worst[3].max(ea);
                    assert!(ea < 1e-9, "{label}: IPM α {} vs {}", pi.alpha, p.alpha);
                    assert!((pi.point - p.point).norm() < 1e-7 * rho, "{label}");
                    if pi.derivatives == DerivativeKind::Exact {
                        for c in 0..14 {
                            assert!(close(gi[c], gc[c], 1e-6), "{label} IPM grad col {c}");
                        }
                    }
                }
            }
        }
    }
    println!(
        "worst: α {:e}, x* {:e}, sd {:e}, IPM α {:e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

/// Central differences of a function of the 14 pose numbers (r₁, q₁, r₂, q₂ as given).
fn central<const K: usize>(
    p1: &Pose,
    p2: &Pose,
    f: impl Fn(&Pose, &Pose) -> [f64; K],
) -> [[f64; 14]; K] {
    let mut x = [0.0; 14];
    for (k, p) in [p1, p2].iter().enumerate() {
        for j in 0..3 {
            x[7 * k + j] = p.position()[j];
        }
        x[7 * k + 3..7 * k + 7].copy_from_slice(&p.quaternion());
    }
    let poses = |x: &[f64; 14]| {
        let mk = |o: usize| {
            Pose::new(
                [x[o], x[o + 1], x[o + 2]],
                [x[o + 3], x[o + 4], x[o + 5], x[o + 6]],
            )
            .unwrap()
        };
        (mk(0), mk(7))
    };
    let mut out = [[0.0; 14]; K];
    let step = 1e-6;
    for c in 0..14 {
        let (mut xp, mut xm) = (x, x);
        xp[c] += step;
        xm[c] -= step;
        let (a, b) = poses(&xp);
        let fp = f(&a, &b);
        let (a, b) = poses(&xm);
        let fm = f(&a, &b);
        for r in 0..K {
            out[r][c] = (fp[r] - fm[r]) / (2.0 * step);
        }
    }
    out
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn derivatives_match_central_differences() {
    let o = Options::default();
    let mut rng = Rng::new(5);
    for kind in KINDS {
        for trial in 0..6 {
            let b = kind.random(&mut rng);
            let depth = rng.range(0.2, 2.0);
            let h = Shape::halfspace(depth).unwrap();
            let rho = b.bounding_radius();
            let g = if trial % 2 == 0 {
                depth + 1.5 * rho
            } else {
                depth + 0.5 * b.inscribed_radius()
            };
            let (ph, pb) = place(&mut rng, g);
            for swap in [false, true] {
                let (s1, p1, s2, p2) = if swap {
                    (&b, &pb, &h, &ph)
                } else {
                    (&h, &ph, &b, &pb)
                };
                let label = format!("{} trial {trial} swap {swap}", kind.name());
                let (prox, grad) = gradient(s1, p1, s2, p2, &o).unwrap();
                assert_eq!(prox.derivatives, DerivativeKind::Exact, "{label}");
                let (_, jac) = jacobian(s1, p1, s2, p2, &o).unwrap();
                let fd = central(p1, p2, |a, c| {
                    let p = proximity(s1, a, s2, c, &o).unwrap();
                    [p.point.x, p.point.y, p.point.z, p.alpha]
                });
                for c in 0..14 {
                    assert!(close(grad[c], fd[3][c], 1e-6), "{label} dα col {c}");
                    assert_eq!(grad[c], jac[3][c]);
                    for r in 0..3 {
                        assert!(
                            close(jac[r][c], fd[r][c], 1e-5),
                            "{label} dx{r} col {c}: {} vs {}",
                            jac[r][c],
                            fd[r][c]
                        );
                    }
                }
                // Contact-point Jacobians by the chain rule agree with their differences.
                let d = derivatives(s1, p1, s2, p2, &o).unwrap();
                let fdc = central(p1, p2, |a, c| {
                    let p = proximity(s1, a, s2, c, &o).unwrap();
                    [p.contact1.x, p.contact1.y, p.contact1.z]
                });
                for c in 0..14 {
                    for r in 0..3 {
                        assert!(close(d.dcontact1[r][c], fdc[r][c], 1e-5), "{label} dp1");
                    }
                }
                // Signed distance and distance gradients.
                let (_, gs) = signed_distance_gradient(s1, p1, s2, p2, &o).unwrap();
                let fds = central(p1, p2, |a, c| {
                    [signed_distance(s1, a, s2, c, &o).unwrap().distance]
                });
                for c in 0..14 {
                    assert!(close(gs[c], fds[0][c], 1e-6), "{label} dsd col {c}");
                }
                let (dd, gd) = distance_gradient(s1, p1, s2, p2, &o).unwrap();
                if dd.distance > 0.0 {
                    for c in 0..14 {
                        assert!(close(gd[c], fds[0][c], 1e-6), "{label} dd col {c}");
                    }
                } else {
                    assert_eq!(gd, [0.0; 14]);
                }
            }
        }
    }
}

#[test]
fn mrp_forms_agree_with_quaternion_forms() {
    let o = Options::default();
    let h = Shape::halfspace(0.7).unwrap();
    let b = Shape::cone(1.2, 0.5).unwrap();
    let (m1, m2) = ([0.1, -0.2, 0.3], [-0.4, 0.1, 0.2]);
    let (r1, r2) = ([0.0, 0.0, -0.7], [0.2, 0.1, 1.4]);
    let (p, g) = gradient_mrp(&h, r1, m1, &b, r2, m2, &o).unwrap();
    let (_, j) = jacobian_mrp(&h, r1, m1, &b, r2, m2, &o).unwrap();
    let step = 1e-6;
    for c in 0..12 {
        let eval = |s: f64| {
            let (mut a, mut bb, mut c1, mut c2) = (r1, m1, r2, m2);
            match c {
                0..=2 => a[c] += s,
                3..=5 => bb[c - 3] += s,
                6..=8 => c1[c - 6] += s,
                _ => c2[c - 9] += s,
            }
            let pa = Pose::from_mrp(a, bb).unwrap();
            let pb = Pose::from_mrp(c1, c2).unwrap();
            proximity(&h, &pa, &b, &pb, &o).unwrap().alpha
        };
        let fd = (eval(step) - eval(-step)) / (2.0 * step);
        assert!(close(g[c], fd, 1e-6), "col {c}: {} vs {fd}", g[c]);
        assert_eq!(g[c], j[3][c]);
    }
    assert!(p.alpha > 1.0);
}

#[test]
fn origin_inside_and_flat_contacts_report_their_derivative_kind() {
    let o = Options::default();
    let h = Shape::halfspace(1.0).unwrap();
    let under = Pose::from_position([0.0, 0.0, -1.0]).unwrap();
    let b = Shape::cuboid(0.5, 0.4, 0.3).unwrap();
    // Origin below the plane: α* ≡ 0 nearby, x* = r_B.
    let sunk = Pose::from_position([0.2, 0.1, -1.5]).unwrap();
    let (p, j) = jacobian(&h, &under, &b, &sunk, &o).unwrap();
    assert_eq!(p.alpha, 0.0);
    assert_eq!(p.point, *sunk.position());
    assert_eq!(p.derivatives, DerivativeKind::Exact);
    for r in 0..4 {
        for c in 0..14 {
            let want = if r < 3 && c == 7 + r { 1.0 } else { 0.0 };
            assert_eq!(j[r][c], want);
        }
    }
    // A box lying flat: its bottom face is the contact, x* its centre, α* is not
    // differentiable in the box's attitude (a subgradient); the position columns are exact.
    let flat = Pose::from_position([0.2, 0.1, 0.5]).unwrap();
    let (p, g) = gradient(&h, &under, &b, &flat, &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Subgradient);
    assert!((p.alpha - 1.5 / 1.3).abs() < 1e-15);
    let x = Vec3::new(0.2, 0.1, 0.5 - p.alpha * 0.3);
    assert!((p.point - x).norm() < 1e-15);
    let expect = [0.0, 0.0, -1.0 / 1.3];
    for k in 0..3 {
        assert!((g[k] - expect[k]).abs() < 1e-15);
        assert!((g[7 + k] + expect[k]).abs() < 1e-15);
    }
    // Tilting the box either way raises α* (a corner comes down): the subgradient at the
    // face's centre is zero in the tilt directions.
    for c in 10..14 {
        assert!(g[c].abs() < 1e-15, "col {c}: {}", g[c]);
    }
    // Cylinder standing on its cap: the disc is the contact.
    let cyl = Shape::cylinder(0.3, 1.0).unwrap();
    let h2 = std::f64::consts::FRAC_PI_4;
    let stand = Pose::new([0.0, 0.0, 0.4], [h2.cos(), 0.0, -h2.sin(), 0.0]).unwrap();
    let (p, _) = gradient(&h, &under, &cyl, &stand, &o).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Subgradient);
    assert!((p.point - Vec3::new(0.0, 0.0, 0.4 - p.alpha * 0.5)).norm() < 1e-12);
}

#[test]
fn two_halfspaces_are_an_error_everywhere() {
    let o = Options::default();
    let h = Shape::halfspace(1.0).unwrap();
    let a = Pose::from_position([0.0, 0.0, 0.0]).unwrap();
    let b = Pose::from_position([0.0, 0.0, 3.0]).unwrap();
    let bad = |r: Result<(), Error>| {
        let e = r.unwrap_err();
        assert!(matches!(e, Error::InvalidShape(_)), "{e:?}");
        assert!(e.to_string().contains("two half-spaces"), "{e}");
    };
    bad(proximity(&h, &a, &h, &b, &o).map(|_| ()));
    bad(gradient(&h, &a, &h, &b, &o).map(|_| ()));
    bad(jacobian(&h, &a, &h, &b, &o).map(|_| ()));
    bad(derivatives(&h, &a, &h, &b, &o).map(|_| ()));
    bad(distance(&h, &a, &h, &b, &o).map(|_| ()));
    bad(distance_gradient(&h, &a, &h, &b, &o).map(|_| ()));
    bad(distance_within(&h, &a, &h, &b, 1.0, &o).map(|_| ()));
    bad(signed_distance(&h, &a, &h, &b, &o).map(|_| ()));
    bad(signed_distance_gradient(&h, &a, &h, &b, &o).map(|_| ()));
    bad(contact_manifold(&h, &a, &h, &b, 0.0, 4, &o).map(|_| ()));
    bad(alpha_below(&h, &a, &h, &b, 10.0, &o).map(|_| ()));
    bad(intersect(&h, &a, &h, &b, &o).map(|_| ()));
    bad(gradient_mrp(&h, [0.0; 3], [0.0; 3], &h, [1.0; 3], [0.0; 3], &o).map(|_| ()));
    bad(jacobian_mrp(&h, [0.0; 3], [0.0; 3], &h, [1.0; 3], [0.0; 3], &o).map(|_| ()));
    let pairs = [dcol::batch::Pair {
        shape1: &h,
        pose1: &a,
        shape2: &h,
        pose2: &b,
    }];
    let mut out = [Ok(
        proximity(&h, &a, &Shape::sphere(1.0).unwrap(), &b, &o).unwrap()
    )];
    dcol::batch::proximity_batch(&pairs, &o, 1, &mut out).unwrap();
    bad(out[0].map(|_| ()));
}

/// A rotation about world z by `yaw` times one taking body `from` to world `-z` (face down).
fn resting(yaw: f64, tilt: [f64; 4]) -> [f64; 4] {
    let z = [(0.5 * yaw).cos(), 0.0, 0.0, (0.5 * yaw).sin()];
    let (a, b) = (z, tilt);
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

#[test]
fn contacts_of_shapes_resting_on_a_floor() {
    let o = Options::default();
    let floor = Shape::halfspace(0.5).unwrap();
    let sink = 0.01;
    let h2 = std::f64::consts::FRAC_PI_4;
    let id = [1.0, 0.0, 0.0, 0.0];
    let x_down = [h2.cos(), 0.0, h2.sin(), 0.0]; // body +x to world −z
    let x_flat = id; // body x horizontal
                     // (shape, attitude before yaw, height of the origin above the surface when touching,
                     //  expected points with cap 8)
    let cases: Vec<(&str, Shape, [f64; 4], f64, usize)> = vec![
        ("box", Shape::cuboid(0.4, 0.3, 0.2).unwrap(), id, 0.2, 4),
        (
            "cylinder standing",
            Shape::cylinder(0.3, 1.0).unwrap(),
            x_down,
            0.5,
            8,
        ),
        (
            "cylinder lying",
            Shape::cylinder(0.3, 1.0).unwrap(),
            x_flat,
            0.3,
            2,
        ),
        (
            "cone on its base",
            Shape::cone(1.0, 0.4).unwrap(),
            x_down,
            0.25,
            8,
        ),
        (
            "capsule lying",
            Shape::capsule(0.2, 1.0).unwrap(),
            x_flat,
            0.2,
            2,
        ),
        ("sphere", Shape::sphere(0.35).unwrap(), id, 0.35, 1),
    ];
    // Floors: level, and tilted (the whole scene rotated about an axis in the plane).
    for floor_q in [id, [0.9, 0.3, -0.2, 0.1]] {
        let fq_unit = {
            let n = floor_q.iter().map(|v| v * v).sum::<f64>().sqrt();
            floor_q.map(|v| v / n)
        };
        let rot = rotation_from_quaternion(fq_unit);
        let base = Vec3::new(0.3, -0.2, 0.1);
        let pf = {
            let r = base - rot * Vec3::new(0.0, 0.0, 0.5);
            Pose::new([r.x, r.y, r.z], floor_q).unwrap()
        };
        let n = rot * Vec3::z();
        for (name, shape, q, height, expect) in &cases {
            for yaw in [0.0, 0.7, 2.0] {
                let local = resting(yaw, *q);
                let qb = {
                    // world attitude: the floor's rotation times the local one
                    let (a, b) = (fq_unit, local);
                    [
                        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
                        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
                        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
                        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
                    ]
                };
                let r = base + rot * Vec3::new(0.1, 0.2, height - sink);
                let pb = Pose::new([r.x, r.y, r.z], qb).unwrap();
                for swap in [false, true] {
                    let label = format!("{name} yaw {yaw} swap {swap} floor {floor_q:?}");
                    let m = if swap {
                        contact_manifold(shape, &pb, &floor, &pf, 0.0, 8, &o).unwrap()
                    } else {
                        contact_manifold(&floor, &pf, shape, &pb, 0.0, 8, &o).unwrap()
                    };
                    let up = if swap { -n } else { n };
                    assert!((m.normal - up).norm() < 1e-12, "{label}");
                    assert!((m.signed_distance + sink).abs() < 1e-12, "{label}");
                    assert_eq!(m.len(), *expect, "{label}: {:?}", m.contacts());
                    let deepest = m.contacts().iter().map(|c| c.depth).fold(-1.0, f64::max);
                    assert!((deepest - sink).abs() < 1e-12, "{label}");
                    for c in m.contacts() {
                        assert!((c.depth - sink).abs() < 1e-12, "{label}: {c:?}");
                        // Midway between the surfaces: sink/2 below the plane.
                        let height = n.dot(&(c.position - base));
                        assert!((height + 0.5 * sink).abs() < 1e-12, "{label}");
                        assert_eq!(c.normal, m.normal);
                    }
                    // Four points from a box (the corners) and the 8 of a disc spread out.
                    if *expect >= 4 {
                        let m4 = contact_manifold(&floor, &pf, shape, &pb, 0.0, 4, &o).unwrap();
                        assert_eq!(m4.len(), 4, "{label}");
                    }
                }
            }
        }
    }
    // A tilted box on an edge: the two corners of the edge at margin 0, four with a margin.
    let b = Shape::cuboid(0.4, 0.3, 0.2).unwrap();
    let t = 0.2f64;
    let q = [(0.5 * t).cos(), (0.5 * t).sin(), 0.0, 0.0];
    let low = 0.3 * t.sin() + 0.2 * t.cos();
    let pb = Pose::new([0.0, 0.0, low - sink], q).unwrap();
    let pf = Pose::from_position([0.0, 0.0, -0.5]).unwrap();
    let m = contact_manifold(&floor, &pf, &b, &pb, 0.0, 4, &o).unwrap();
    assert_eq!(m.len(), 2);
    let m = contact_manifold(&floor, &pf, &b, &pb, 0.5, 4, &o).unwrap();
    assert_eq!(m.len(), 4);
    // Far above: none.
    let high = Pose::from_position([0.0, 0.0, 3.0]).unwrap();
    assert!(contact_manifold(&floor, &pf, &b, &high, 0.0, 4, &o)
        .unwrap()
        .is_empty());
}

#[test]
fn scene_reports_bodies_on_the_floor_and_skips_two_floors() {
    use dcol::scene::Scene;
    let o = Options::default();
    let mut scene = Scene::new();
    let floor = scene.add(
        Shape::halfspace(1.0).unwrap(),
        Pose::from_position([0.0, 0.0, -1.0]).unwrap(),
    );
    let wall = scene.add(
        Shape::halfspace(1.0).unwrap(),
        Pose::new([-100.0, 0.0, 0.0], [0.5f64.sqrt(), 0.0, 0.5f64.sqrt(), 0.0]).unwrap(),
    );
    let ball = Shape::sphere(0.5).unwrap();
    let resting = scene.add(
        ball.clone(),
        Pose::from_position([40.0, 0.0, 0.49]).unwrap(),
    );
    let flying = scene.add(ball, Pose::from_position([-40.0, 0.0, 3.0]).unwrap());
    let mut out = Vec::new();
    let stats = scene.pairs_within(1.0, &o, &mut out).unwrap();
    assert_eq!(stats.pairs_total, 6);
    let pairs: Vec<(usize, usize)> = out.iter().map(|p| (p.body1, p.body2)).collect();
    assert_eq!(pairs, vec![(floor, resting)]);
    assert!((out[0].proximity.alpha - 1.49 / 1.5).abs() < 1e-15);
    let _ = (wall, flying);
}

/// `Options::smoothing` on a box lying flat (where the exact derivatives do not exist): the
/// central path's smoothed derivatives from the cone program, close to the closed form's α*,
/// and the smoothed gradient matches central differences of the smoothed α*.
#[test]
fn smoothing_gives_the_central_path_derivatives() {
    let h = Shape::halfspace(1.0).unwrap();
    let under = Pose::from_position([0.0, 0.0, -1.0]).unwrap();
    let b = Shape::cuboid(0.5, 0.4, 0.3).unwrap();
    let flat = Pose::new([0.2, 0.1, 0.5], [1.0, 0.01, -0.02, 0.0]).unwrap();
    let o = Options {
        smoothing: 1e-4,
        ..Options::default()
    };
    let (p, g) = gradient(&h, &under, &b, &flat, &o).unwrap();
    let exact = proximity(&h, &under, &b, &flat, &Options::default()).unwrap();
    assert_eq!(p.derivatives, DerivativeKind::Smoothed);
    assert_eq!(p.solver, Solver::InteriorPoint);
    assert!(
        (p.alpha - exact.alpha).abs() < 1e-2,
        "{} vs {}",
        p.alpha,
        exact.alpha
    );
    let fd = central(&under, &flat, |a, c| {
        [proximity(&h, a, &b, c, &o).unwrap().alpha]
    });
    for c in 0..14 {
        assert!(
            close(g[c], fd[0][c], 1e-5),
            "col {c}: {} vs {}",
            g[c],
            fd[0][c]
        );
    }
}
