//! Shape gradients on chosen configurations: closed forms, the places where the derivative is
//! not unique or not exact (flat against flat, a corner of four planes, a hull's square facet,
//! coincident origins) and what is reported there, the parameters' order and round trip, and
//! bad buffers. The random sweeps are in `tests/shape_gradient.rs`.

mod common;

use common::random::{Kind, Rng, KINDS};
use dcol::{
    gradient, proximity, shape_gradient, signed_distance_shape_gradient, DerivativeKind, Error,
    Method, Options, Pose, Shape,
};

fn at(x: f64, y: f64, z: f64) -> Pose {
    Pose::from_position([x, y, z]).unwrap()
}

/// ∂α*/∂θ of both shapes and the kind.
fn grads(
    s1: &Shape,
    p1: &Pose,
    s2: &Shape,
    p2: &Pose,
    opts: &Options,
) -> (f64, Vec<f64>, Vec<f64>, DerivativeKind) {
    let (mut g1, mut g2) = (
        vec![0.0; s1.parameter_count()],
        vec![0.0; s2.parameter_count()],
    );
    let p = shape_gradient(s1, p1, s2, p2, opts, Some(&mut g1), Some(&mut g2)).unwrap();
    assert!(p.status.is_converged());
    (p.alpha, g1, g2, p.derivatives)
}

/// The central difference of α* along `v` of shape 1's parameters (shape 2 fixed).
fn fd1(s1: &Shape, p1: &Pose, s2: &Shape, p2: &Pose, v: &[f64], h: f64) -> f64 {
    let theta = s1.parameters();
    let alpha = |t: f64| {
        let p: Vec<f64> = theta.iter().zip(v).map(|(a, b)| a + t * b).collect();
        let s = s1.with_parameters(&p).unwrap();
        let o = Options {
            tolerance: 1e-12,
            ..Options::default()
        };
        proximity(&s, p1, s2, p2, &o).unwrap().alpha
    };
    (alpha(h) - alpha(-h)) / (2.0 * h)
}

#[test]
fn closed_forms() {
    let o = Options::default();
    // Two spheres: α* = ‖d‖/(R₁ + R₂).
    let (a, b) = (Shape::sphere(0.7).unwrap(), Shape::sphere(0.4).unwrap());
    let (alpha, g1, g2, k) = grads(&a, &at(0.0, 0.0, 0.0), &b, &at(1.0, 2.0, 2.0), &o);
    assert_eq!(k, DerivativeKind::Exact);
    let want = -alpha / 1.1;
    assert!((alpha - 3.0 / 1.1).abs() < 1e-12);
    assert!((g1[0] - want).abs() < 1e-12 && (g2[0] - want).abs() < 1e-12);
    // A sphere against a box's face: α* = d/(R + h_x); h_y and h_z do not matter.
    let bx = Shape::cuboid(0.5, 0.8, 0.3).unwrap();
    let (alpha, g1, g2, _) = grads(&a, &at(0.0, 0.0, 0.0), &bx, &at(2.4, 0.1, -0.05), &o);
    let want = -alpha / 1.2;
    assert!((g1[0] - want).abs() < 1e-12 && (g2[0] - want).abs() < 1e-12);
    assert!(g2[1].abs() < 1e-14 && g2[2].abs() < 1e-14);
    // An axis-aligned ellipsoid (semi-axes a, b, c) and a sphere along x: α* = d/(a + R), and
    // a = P₀₀^(−1/2), so ∂α*/∂P₀₀ = α*/(a + R)·a³/2; the other entries do not move h along x.
    let (sa, sb, sc) = (0.9, 0.5, 0.3);
    let e = Shape::ellipsoid([
        [1.0 / (sa * sa), 0.0, 0.0],
        [0.0, 1.0 / (sb * sb), 0.0],
        [0.0, 0.0, 1.0 / (sc * sc)],
    ])
    .unwrap();
    let (alpha, g1, g2, _) = grads(&e, &at(0.0, 0.0, 0.0), &b, &at(3.0, 0.0, 0.0), &o);
    assert!((alpha - 3.0 / 1.3).abs() < 1e-12);
    assert!(
        (g1[0] - alpha / 1.3 * sa * sa * sa / 2.0).abs() < 1e-10,
        "{g1:?}"
    );
    assert!(g1[1..].iter().all(|v| v.abs() < 1e-12), "{g1:?}");
    assert!((g2[0] + alpha / 1.3).abs() < 1e-12);
    // A capsule along x and a sphere: α* = d/(L/2 + R + R₂).
    let c = Shape::capsule(0.2, 1.0).unwrap();
    let (alpha, g1, _, _) = grads(&c, &at(0.0, 0.0, 0.0), &b, &at(3.0, 0.0, 0.0), &o);
    assert!((g1[0] + alpha / 1.1).abs() < 1e-12 && (g1[1] + 0.5 * alpha / 1.1).abs() < 1e-12);
    // A half-space (top at depth c above its origin) and a sphere above it: α* = g/(c + R).
    let floor = Shape::halfspace(0.5).unwrap();
    let (alpha, g1, g2, k) = grads(&floor, &at(0.0, 0.0, -0.5), &b, &at(0.3, 0.0, 2.0), &o);
    assert_eq!(k, DerivativeKind::Exact);
    assert!((alpha - 2.5 / 0.9).abs() < 1e-12);
    assert!((g1[0] + alpha / 0.9).abs() < 1e-12 && (g2[0] + alpha / 0.9).abs() < 1e-12);
    // The signed distance of the sphere above the floor: 2.5 − c − R.
    let (mut h1, mut h2) = ([0.0], [0.0]);
    let sd = signed_distance_shape_gradient(
        &floor,
        &at(0.0, 0.0, -0.5),
        &b,
        &at(0.3, 0.0, 2.0),
        &o,
        Some(&mut h1),
        Some(&mut h2),
    )
    .unwrap();
    assert!((sd.distance - 1.6).abs() < 1e-12);
    assert!((h1[0] + 1.0).abs() < 1e-12 && (h2[0] + 1.0).abs() < 1e-12);
    // A cone's apex pointing at a sphere (apex at −3H/4 on body x): α* = d/(3H/4 + R), and the
    // half angle does not matter there.
    let cone = Shape::cone(1.2, 0.4).unwrap();
    let (alpha, g1, _, _) = grads(&cone, &at(0.0, 0.0, 0.0), &b, &at(-3.0, 0.0, 0.0), &o);
    assert!((alpha - 3.0 / 1.3).abs() < 1e-12);
    assert!(
        (g1[0] + 0.75 * alpha / 1.3).abs() < 1e-12 && g1[1].abs() < 1e-12,
        "{g1:?}"
    );
}

/// A box resting face-down on a larger one: x* is not unique, the interior-point path answers
/// (`Smoothed`), and the derivatives with respect to the offsets of the two touching faces
/// (the half extents along z) exist and are those of α* = d_z/(h_z₁ + h_z₂).
#[test]
fn flat_against_flat() {
    let (big, small) = (
        Shape::cuboid(1.0, 1.0, 0.4).unwrap(),
        Shape::cuboid(0.3, 0.2, 0.25).unwrap(),
    );
    let (p1, p2) = (at(0.0, 0.0, 0.0), at(0.2, -0.1, 1.3));
    let (alpha, g1, g2, k) = grads(&big, &p1, &small, &p2, &Options::default());
    assert_eq!(k, DerivativeKind::Smoothed);
    assert!((alpha - 1.3 / 0.65).abs() < 1e-9);
    let want = -alpha / 0.65;
    assert!(
        (g1[2] - want).abs() < 1e-7 && (g2[2] - want).abs() < 1e-7,
        "{g1:?} {g2:?}"
    );
    for v in [g1[0], g1[1], g2[0], g2[1]] {
        assert!(v.abs() < 1e-7, "{g1:?} {g2:?}");
    }
    // The same pair given as a polytope: the derivatives with respect to A are those of
    // tilting the touching face, which has no derivative (a kink); b's is the face's offset.
    let a: Vec<[f64; 3]> = vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, 0.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, -1.0],
    ];
    let poly = Shape::polytope(&a, &[1.0, 1.0, 0.4, 1.0, 1.0, 0.4]).unwrap();
    let (_, g1, _, k) = grads(&poly, &p1, &small, &p2, &Options::default());
    assert_eq!(k, DerivativeKind::Smoothed);
    assert!((g1[18 + 2] - want).abs() < 1e-7, "{g1:?}");
}

/// The apex of a square pyramid (four planes through one corner) against a sphere above it:
/// the multipliers of the four planes are not unique, and one element of the generalised
/// gradient is returned (`Subgradient`): nonnegative multipliers, so α* falls as any offset
/// grows, and the derivative along every direction that keeps the corner simple is right.
#[test]
fn corner_of_four_planes() {
    let s = 0.5f64.sqrt();
    let a = vec![
        [s, 0.0, s],
        [-s, 0.0, s],
        [0.0, s, s],
        [0.0, -s, s],
        [0.0, 0.0, -1.0],
    ];
    let b = vec![s, s, s, s, 0.5];
    let pyramid = Shape::polytope(&a, &b).unwrap();
    let ball = Shape::sphere(0.3).unwrap();
    let (p1, p2) = (at(0.0, 0.0, 0.0), at(0.0, 0.0, 2.6));
    let (alpha, g1, _, k) = grads(&pyramid, &p1, &ball, &p2, &Options::default());
    assert_eq!(k, DerivativeKind::Subgradient);
    assert!((alpha - 2.6 / 1.3).abs() < 1e-12);
    // ∂α*/∂b_i = −α* λ_i ≤ 0 for the side planes, and the apex height (1) moves with all
    // four offsets together: Σ ∂α*/∂b_i over the sides is ∂α*/∂(apex height)·∂height/∂b = −α*/1.3·√2.
    let side: f64 = g1[15..19].iter().sum();
    assert!(g1[15..19].iter().all(|v| *v <= 1e-12), "{g1:?}");
    assert!((side + alpha / 1.3 * 2f64.sqrt()).abs() < 1e-9, "{side}");
    // Along the direction that grows all four side offsets together, the finite difference.
    let mut v = vec![0.0; 20];
    v[15..19].fill(1.0);
    let fd = fd1(&pyramid, &p1, &ball, &p2, &v, 1e-6);
    assert!((side - fd).abs() < 1e-7, "{side} {fd}");
}

/// A sphere against the middle of a square facet of a box given as the hull of its eight
/// corners: the facet's four corners have no unique weights (moving one folds the facet one
/// way or the other), so `Subgradient`; moving the whole facet, or the radius, is
/// differentiable and agrees with finite differences.
#[test]
fn hull_with_a_square_facet() {
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { 0.5 } else { -0.5 }))
        .collect();
    let hull = Shape::convex_hull(&corners, 0.1).unwrap();
    let ball = Shape::sphere(0.3).unwrap();
    let (p1, p2) = (at(0.0, 0.0, 0.0), at(2.0, 0.05, -0.1));
    let (alpha, g1, _, k) = grads(&hull, &p1, &ball, &p2, &Options::default());
    assert_eq!(k, DerivativeKind::Subgradient);
    assert!((alpha - 2.0 / 0.9).abs() < 1e-12);
    // The +x facet (corners with x = 0.5) moved along x, and the radius.
    let mut v = vec![0.0; 25];
    for (i, c) in corners.iter().enumerate() {
        if c[0] > 0.0 {
            v[3 * i] = 1.0;
        }
    }
    let mine: f64 = g1.iter().zip(&v).map(|(a, b)| a * b).sum();
    assert!((mine + alpha / 0.9).abs() < 1e-10, "{mine}");
    assert!((mine - fd1(&hull, &p1, &ball, &p2, &v, 1e-6)).abs() < 1e-7);
    assert!((g1[24] + alpha / 0.9).abs() < 1e-10);
    // Corners off the facet carry nothing.
    for (i, c) in corners.iter().enumerate() {
        if c[0] < 0.0 {
            assert!(g1[3 * i..3 * i + 3].iter().all(|v| *v == 0.0), "{g1:?}");
        }
    }
}

#[test]
fn coincident_origins_give_zeros() {
    let (a, b) = (
        Shape::cuboid(0.5, 0.5, 0.5).unwrap(),
        Shape::cone(1.0, 0.5).unwrap(),
    );
    let p = at(1.0, 2.0, 3.0);
    let (mut g1, mut g2) = (vec![7.0; 3], vec![7.0; 2]);
    let r = shape_gradient(
        &a,
        &p,
        &b,
        &p,
        &Options::default(),
        Some(&mut g1),
        Some(&mut g2),
    )
    .unwrap();
    assert_eq!(r.alpha, 0.0);
    assert_eq!(r.derivatives, DerivativeKind::Subgradient);
    assert!(g1.iter().chain(&g2).all(|v| *v == 0.0));
}

#[test]
fn buffers_are_checked_and_only_the_parameters_written() {
    let (a, b) = (
        Shape::cuboid(0.5, 0.5, 0.5).unwrap(),
        Shape::sphere(0.5).unwrap(),
    );
    let (p1, p2) = (at(0.0, 0.0, 0.0), at(2.0, 0.0, 0.0));
    let o = Options::default();
    let mut short = [0.0; 2];
    let e = shape_gradient(&a, &p1, &b, &p2, &o, Some(&mut short), None).unwrap_err();
    assert!(matches!(e, Error::InvalidOptions(_)), "{e:?}");
    assert!(e.to_string().contains("d_shape1"), "{e}");
    // α* = 2/(0.5 + R): ∂α*/∂R = −2.
    let mut long = [9.0; 5];
    shape_gradient(&a, &p1, &b, &p2, &o, None, Some(&mut long)).unwrap();
    assert!(
        (long[0] + 2.0).abs() < 1e-12 && long[1..] == [9.0; 4],
        "{long:?}"
    );
    // Neither wanted: the proximity alone.
    let p = shape_gradient(&a, &p1, &b, &p2, &o, None, None).unwrap();
    assert!((p.alpha - 2.0).abs() < 1e-12);
}

#[test]
fn parameters_are_the_constructors_arguments_in_order() {
    assert_eq!(Shape::sphere(0.5).unwrap().parameters(), vec![0.5]);
    assert_eq!(
        Shape::cuboid(1.0, 2.0, 3.0).unwrap().parameters(),
        vec![1.0, 2.0, 3.0]
    );
    assert_eq!(
        Shape::capsule(0.2, 1.5).unwrap().parameters(),
        vec![0.2, 1.5]
    );
    assert_eq!(
        Shape::cylinder(0.3, 1.0).unwrap().parameters(),
        vec![0.3, 1.0]
    );
    assert_eq!(Shape::cone(1.0, 0.4).unwrap().parameters(), vec![1.0, 0.4]);
    assert_eq!(Shape::halfspace(0.7).unwrap().parameters(), vec![0.7]);
    let p = [[2.0, 0.1, 0.0], [0.1, 3.0, 0.2], [0.0, 0.2, 4.0]];
    assert_eq!(
        Shape::ellipsoid(p).unwrap().parameters(),
        p.iter().flatten().copied().collect::<Vec<_>>()
    );
    let a = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [-1.0, -1.0, -1.0],
    ];
    let poly = Shape::polytope(&a, &[1.0, 2.0, 3.0, 0.5]).unwrap();
    let mut want: Vec<f64> = a.iter().flatten().copied().collect();
    want.extend([1.0, 2.0, 3.0, 0.5]);
    assert_eq!(poly.parameters(), want);
    assert_eq!(poly.parameter_count(), 16);
    let c = [[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]];
    let pg = Shape::polygon(&c, &[1.0, 1.0, 0.5], 0.1).unwrap();
    assert_eq!(
        pg.parameters(),
        vec![1.0, 0.0, 0.0, 1.0, -1.0, -1.0, 1.0, 1.0, 0.5, 0.1]
    );
    let pts: Vec<[f64; 3]> = (0..8)
        .map(|i| [0, 1, 2].map(|k| if i >> k & 1 == 1 { 0.5 } else { -0.5 }))
        .chain([[0.0, 0.0, 0.1]])
        .collect();
    let hull = Shape::convex_hull(&pts, 0.05).unwrap();
    let mut want: Vec<f64> = pts.iter().flatten().copied().collect();
    want.push(0.05);
    assert_eq!(hull.parameters(), want);
    assert_eq!(hull.parameter_count(), 28);
    // Every random kind: the same shape back from its parameters, and the dimensions' count.
    let mut rng = Rng::new(34);
    for k in KINDS {
        for _ in 0..5 {
            let s = k.random(&mut rng);
            let t = s.with_parameters(&s.parameters()).unwrap();
            assert_eq!(s, t, "{}", k.name());
            assert_eq!(s.parameter_dimensions().len(), s.parameter_count());
        }
    }
    // A box stays a box: its parameters are the half extents, not the six planes.
    let b = Shape::cuboid(1.0, 2.0, 3.0).unwrap();
    assert_eq!(
        b.with_parameters(&[2.0, 2.0, 2.0])
            .unwrap()
            .parameter_count(),
        3
    );
    assert!(b.with_parameters(&[1.0, 2.0]).is_err());
    assert!(b.with_parameters(&[1.0, -2.0, 3.0]).is_err());
}

/// Where the contact is unique, the geometric answer's envelope derivatives and the
/// interior-point path's Lagrangian ones are two independent computations of the same thing.
#[test]
fn geometric_and_interior_point_paths_agree() {
    let mut rng = Rng::new(0x34_34);
    let ipm = Options {
        method: Method::InteriorPoint,
        ..Options::default()
    };
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for k1 in KINDS {
        for k2 in KINDS {
            for _ in 0..6 {
                let (s1, s2) = (k1.random(&mut rng), k2.random(&mut rng));
                let p1 = Pose::new([0.0; 3], rng.quat()).unwrap();
                let u = rng.unit::<3>();
                let t = rng.range(0.5, 2.5);
                let p2 = Pose::new(u.map(|c| c * t), rng.quat()).unwrap();
                let (_, a1, a2, ka) = grads(&s1, &p1, &s2, &p2, &Options::default());
                let (_, b1, b2, kb) = grads(&s1, &p1, &s2, &p2, &ipm);
                if ka != DerivativeKind::Exact || kb != DerivativeKind::Exact {
                    continue;
                }
                let ell = s1.bounding_radius().max(s2.bounding_radius());
                let dims = [s1.parameter_dimensions(), s2.parameter_dimensions()];
                for (i, (a, b)) in [(&a1, &b1), (&a2, &b2)].into_iter().enumerate() {
                    for k in 0..a.len() {
                        let unit = ell.powf(dims[i][k]);
                        let err = (a[k] - b[k]).abs() * unit / (a[k].abs() * unit).max(1.0);
                        worst = worst.max(err);
                        assert!(err < 1e-6, "{}-{}: {a:?} {b:?}", k1.name(), k2.name());
                    }
                }
                compared += 1;
            }
        }
    }
    println!("geometric vs interior point: {compared} cases, worst {worst:.1e}");
    assert!(compared > 400, "{compared}");
}

/// Hulls as design variables: moving every point by δ (body frame) with the origin fixed moves
/// the scaled shape `r₁ + α(B + δ)` by `αR₁δ`, as moving `r₁` by that would: so
/// `Σ_k ∂α*/∂p_k = α* R₁ᵀ ∂α*/∂r₁`, the pose gradient.
#[test]
fn moving_every_point_is_moving_the_shape() {
    let mut rng = Rng::new(0x34_35);
    let mut checked = 0;
    for other in KINDS {
        for _ in 0..20 {
            let hull = Kind::Hull.random(&mut rng);
            let s2 = other.random(&mut rng);
            let p1 = Pose::new([0.0; 3], rng.quat()).unwrap();
            let u = rng.unit::<3>();
            let p2 = Pose::new(u.map(|c| c * rng.range(0.6, 2.0)), rng.quat()).unwrap();
            let (alpha, g1, _, k) = grads(&hull, &p1, &s2, &p2, &Options::default());
            if k != DerivativeKind::Exact {
                continue;
            }
            // Translating every point by δ (body frame) is translating the shape by R₁δ:
            // Σ_k ∂α/∂p_k = R₁ᵀ ∂α/∂r₁.
            let (_, g) = gradient(&hull, &p1, &s2, &p2, &Options::default()).unwrap();
            let r = p1.rotation();
            let dr1 = dcol::Vec3::new(g[0], g[1], g[2]);
            let body = r.transpose() * dr1 * alpha;
            let n = g1.len() / 3;
            for j in 0..3 {
                let sum: f64 = (0..n).map(|k| g1[3 * k + j]).sum();
                assert!((sum - body[j]).abs() < 1e-9, "{sum} {}", body[j]);
            }
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

/// A polytope of more than 64 planes is built through its polar hull, whose facets are the
/// irredundant rows in another order (and a few rows here are redundant): its active rows are
/// found from `A` and `b` themselves. Random directions of all 4m parameters against finite
/// differences, with a sphere and with a cone.
#[test]
fn many_planes_through_the_polar_hull() {
    let mut rng = Rng::new(0x34_36);
    let m = 90;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let a: Vec<[f64; 3]> = (0..m)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / m as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * i as f64;
            [r * t.cos(), r * t.sin(), z].map(|c| c * rng.range(0.5, 2.0))
        })
        .collect();
    let b: Vec<f64> = a
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let norm = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            // Every tenth row well outside the others: redundant.
            norm * if i % 10 == 3 {
                2.0
            } else {
                rng.range(0.8, 1.0)
            }
        })
        .collect();
    let poly = Shape::polytope(&a, &b).unwrap();
    let mut compared = 0;
    for other in [Shape::sphere(0.3).unwrap(), Shape::cone(0.8, 0.4).unwrap()] {
        for _ in 0..12 {
            let p1 = Pose::new([0.0; 3], rng.quat()).unwrap();
            let u = rng.unit::<3>();
            let p2 = Pose::new(u.map(|c| c * rng.range(1.0, 2.5)), rng.quat()).unwrap();
            let (_, g1, _, k) = grads(&poly, &p1, &other, &p2, &Options::default());
            if k != DerivativeKind::Exact {
                continue;
            }
            let v: Vec<f64> = (0..4 * m).map(|_| rng.gauss()).collect();
            let mine: f64 = g1.iter().zip(&v).map(|(g, d)| g * d).sum();
            let fd = fd1(&poly, &p1, &other, &p2, &v, 1e-7);
            assert!((mine - fd).abs() < 1e-6 * fd.abs().max(1.0), "{mine} {fd}");
            compared += 1;
        }
    }
    assert!(compared >= 20, "{compared}");
}
